"""The command preview (PPU's Preview): the table's blocks for sample values.

Left, the lines the selected command writes (the selected block's lines
highlighted) and which conditions fired; right, the sample values in an
editable table — change one and the preview renders again at once.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, ClassVar

from rich.text import Text
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, VerticalScroll
from textual.message import Message
from textual.widgets import DataTable, Static

from tui.model import show_value
from tui.tables import fill


class CommandPreview(VerticalScroll, can_focus=False):
    """The rendered blocks, the conditions and any reason the command cannot render."""

    def compose(self) -> ComposeResult:
        yield Static(id="preview-text")

    def show(self, lines: Sequence[tuple[str, bool]], conditions: Sequence[tuple[str, str, bool]],
             error: str | None = None, note: str | None = None) -> None:
        """``lines``: (text, highlighted); ``conditions``: (where, source, fired)."""
        text = Text(no_wrap=True, overflow="ellipsis")
        for line, highlighted in lines:
            text.append(line or " ", style="bold reverse" if highlighted else "")
            text.append("\n")
        if not lines and not error:
            text.append(note or "(writes nothing for these values)", style="dim italic")
            text.append("\n")
        if error:
            text.append(error, style="bold red")
            text.append("\n")
        for where, source, fired in conditions:
            text.append("✓ " if fired else "✗ ", style="green" if fired else "red")
            text.append(source, style="" if fired else "dim")
            text.append(f"  {where}\n", style="dim")
        text.rstrip()
        self.query_one("#preview-text", Static).update(text)


class SampleTable(DataTable[Any]):
    """The sample values of the command; enter edits one, ``r`` resets it."""

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("enter", "select_cursor", "Edit value"),
        Binding("r", "screen.reset_sample", "Reset value"),
    ]

    class EditRequested(Message):
        def __init__(self, name: str) -> None:
            super().__init__()
            self.name = name

    def __init__(self, id: str | None = None) -> None:
        super().__init__(id=id, cursor_type="row", zebra_stripes=False)
        self.names: list[str] = []

    def show(self, rows: Sequence[tuple[str, Any, bool]]) -> None:
        """``rows``: (name, value, overridden)."""
        row = self.cursor_row
        self.names = [name for name, _, _ in rows]
        styled = [("bold yellow" if overridden else "", name, value)
                  for name, value, overridden in rows]
        fill(self, [("parameter", "name"), ("value", "value")],
             [((Text(name, style=style), Text(show_value(value), style=style)), name)
              for style, name, value in styled])
        if rows:
            self.move_cursor(row=min(row, len(rows) - 1), animate=False)

    @property
    def current(self) -> str | None:
        if 0 <= self.cursor_row < len(self.names):
            return self.names[self.cursor_row]
        return None

    def on_data_table_row_selected(self, event: DataTable.RowSelected) -> None:
        event.stop()
        if self.current is not None:
            self.post_message(self.EditRequested(self.current))


class PreviewPane(Horizontal):
    """Command preview and sample values side by side."""

    def compose(self) -> ComposeResult:
        yield CommandPreview(id="command-preview")
        yield SampleTable(id="samples")
