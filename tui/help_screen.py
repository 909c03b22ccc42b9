"""f1: every key of the editor and what the marks in the grid and the command list mean.

The keys are read from the bindings themselves, so the help cannot drift from what
the keys do.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import ClassVar

from rich.text import Text
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Vertical, VerticalScroll
from textual.screen import ModalScreen
from textual.widgets import Label, Static

#: the grid's marks (tui/model.py item_cell, tui/command_table.py)
GRID_MARKS = (
    ("?", "after a cell: the item has a condition (if); dim when it did not fire for the "
          "sample values"),
    ("~", "after a cell: written only when its value changed (mode changed)"),
    ("!", "after a cell: forced — written, and its register forgotten (mode forced)"),
    ("⇢", "the block inserts a structure (shared blocks): enter opens it"),
    ("·", "in the N column: the block is not numbered (N: numbered, ↺: numbering restarts,"
          " *: once per tool)"),
    ("␣", "a space in fixed text, prefix or suffix; {x:coord} is parameter x in format coord"),
)
#: the command list's marks (tui/commands_pane.py)
LIST_MARKS = (
    ("●", "the sample program uses the command"),
    ("✗", "the sample program uses it but the post has no table: it cannot be posted"),
    ("→", "written with another command's table (redirect)"),
    ("!", "the table has a problem"),
    ("·", "no table, and the sample program does not use it"),
)
#: what the toolpath pane draws (tui/backplot.py, tui/braille.py)
PLOT_MARKS = (
    ("⠁⠁", "dotted, grey: a rapid move (G0); in a 3+2 program also the tilted tool axis, "
           "standing on the tip at the first cut of each plane"),
    ("⠉⠉", "solid: a cutting move; an arc is drawn along its curve"),
    ("⠿", "red: a drilled, tapped or bored hole, from its R level to the bottom"),
    ("⠿⠉", "yellow, bold: the moves of the command selected in the list or the grid"),
)


def key_rows(bindings: Iterable[BindingType], display: object) -> list[tuple[str, str]]:
    """(keys, description) of bindings, as the footer writes the keys."""
    rows = []
    for binding in bindings:
        if not isinstance(binding, Binding):
            continue
        keys = " ".join(display(Binding(key, binding.action))  # type: ignore[operator]  # display: the footer's key formatter
                        for key in binding.key.split(","))
        rows.append((keys, binding.description))
    return rows


class HelpScreen(ModalScreen[None]):
    """The keys of every pane and the meaning of the marks."""

    BINDINGS: ClassVar[list[BindingType]] = [Binding("escape,f1", "close", "Close")]

    def __init__(self, sections: list[tuple[str, list[tuple[str, str]]]]) -> None:
        super().__init__()
        self.sections = sections

    def compose(self) -> ComposeResult:
        with Vertical(classes="dialog full", id="help"):
            yield Label("Keys and marks · escape closes", classes="dialog-title")
            with VerticalScroll(id="help-body"):
                yield Static(self._text(), id="help-text")

    def _text(self) -> Text:
        text = Text()
        for title, rows in self.sections:
            text.append(f"{title}\n", style="bold")
            for keys, description in rows:
                text.append(f"  {keys:<22}", style="bold cyan")
                text.append(f"{description}\n")
            text.append("\n")
        for title, marks in (("Marks in the grid", GRID_MARKS),
                             ("Marks in the command list", LIST_MARKS),
                             ("The toolpath (the sample replayed by the control model)",
                              PLOT_MARKS)):
            text.append(f"{title}\n", style="bold")
            for mark, meaning in marks:
                text.append(f"  {mark:<3}", style="bold magenta")
                text.append(f"{meaning}\n")
            text.append("\n")
        text.rstrip()
        return text

    def action_close(self) -> None:
        self.dismiss(None)
