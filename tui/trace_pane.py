"""Where the selected program line comes from: shown in place of the command preview
while the program has the keyboard.

The text is ``postdsl explain``'s (one wording for the command line and the editor);
the pane adds which word the program's cursor is on, and where enter will go.
"""

from __future__ import annotations

from collections.abc import Sequence

from rich.text import Text
from textual.app import ComposeResult
from textual.containers import VerticalScroll
from textual.widgets import Static

from postdsl import api
from tui.model import TableRef

_KINDS = {"commands": "command", "custom_cycles": "cycle", "structures": "structure"}


def cell_of(traced: api.TracedLine, column: int) -> tuple[TableRef, int, int | None] | None:
    """The table, block and item (None: the block's own columns) that wrote the character
    at ``column`` of a traced line.  The block number goes to the block that was numbered."""
    word = next((w for w in traced.words if w.start <= column < w.end), None)
    if word is None:
        return None
    path = word.path
    if path is None:
        path = traced.block_path
    kind = _KINDS.get(str(path[0]))
    if kind is None or len(path) < 3:
        return None
    rest = path[2:] if kind == "structure" else path[3:]
    if not rest or not isinstance(rest[0], int):
        return None
    item = rest[2] if len(rest) >= 3 and rest[1] == "items" else None
    return TableRef(kind, str(path[1])), rest[0], item


class TracePane(VerticalScroll, can_focus=False):
    """The CL record, table, block and item of each word of the program's cursor line."""

    def __init__(self, id: str | None = None) -> None:
        super().__init__(id=id)
        self.traced: api.TracedLine | None = None
        self.lines: list[str] = []
        #: the character of the line the program's word cursor is on
        self.column = 0

    def compose(self) -> ComposeResult:
        yield Static(id="trace-text")

    def show_note(self, note: str) -> None:
        self.traced = None
        self.query_one("#trace-text", Static).update(Text(note, style="dim italic"))

    def show_trace(self, traced: api.TracedLine, lines: Sequence[str], column: int = 0) -> None:
        """``lines``: the explanation of the line, as ``postdsl explain`` prints it."""
        self.traced = traced
        self.lines = list(lines)
        self.border_title = f"Where line {traced.number} comes from"
        self.choose(column)

    def choose(self, column: int) -> None:
        """Mark the word at ``column``: its line of the explanation is the one enter uses."""
        self.column = column
        traced = self.traced
        if traced is None:
            return
        chosen = next((k for k, w in enumerate(traced.words) if w.start <= column < w.end), 0)
        words = self.lines.index("words:") if "words:" in self.lines else -1
        text = Text(no_wrap=True, overflow="ellipsis")
        for index, line in enumerate(self.lines):
            if index == words + 1 + chosen and words >= 0:
                text.append("▶" + line[1:] + "\n", style="bold reverse")
                continue
            style = "bold" if line.startswith("NC line") else \
                "dim" if line.startswith("registers") else ""
            text.append(line + "\n", style=style)
        text.append("←/→ choose a word · enter: go to the cell that wrote it", style="dim italic")
        self.query_one("#trace-text", Static).update(text)
