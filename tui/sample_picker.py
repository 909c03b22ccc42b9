"""The sample picker (f6): every CL program corpus.yaml lists for the machine.

The previews show the machine through one program; a technologist checks a change
against the others too, without leaving the editor.
"""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar

from rich.text import Text
from textual import on
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Vertical
from textual.screen import ModalScreen
from textual.widgets import Label, OptionList, Static
from textual.widgets.option_list import Option

from tui.sample import shown_path


class SamplePicker(ModalScreen[Path | None]):
    """Choose the sample program; dismissed with its path (None: keep the current one)."""

    BINDINGS: ClassVar[list[BindingType]] = [Binding("escape", "cancel", "Cancel"),
                                             Binding("f6", "cancel", "Close", show=False)]

    def __init__(self, programs: list[Path], current: Path | None) -> None:
        super().__init__()
        self.programs = programs
        self.current = current

    def compose(self) -> ComposeResult:
        with Vertical(classes="dialog wide"):
            yield Label("Sample program", classes="dialog-title")
            options = []
            for index, path in enumerate(self.programs):
                label = Text("● " if path == self.current else "  ", style="green")
                label.append(shown_path(path))
                if index == 0:
                    label.append("  the machine's showcase", style="dim italic")
                options.append(Option(label, id=str(index)))
            yield OptionList(*options, id="samples-list")
            yield Static("enter: post this program in the previews · escape: keep the current",
                         classes="dialog-hint")

    def on_mount(self) -> None:
        options = self.query_one(OptionList)
        options.highlighted = self.programs.index(self.current) \
            if self.current in self.programs else 0
        options.focus()

    @on(OptionList.OptionSelected)
    def _chosen(self, event: OptionList.OptionSelected) -> None:
        event.stop()
        self.dismiss(self.programs[int(event.option.id or 0)])

    def action_cancel(self) -> None:
        self.dismiss(None)
