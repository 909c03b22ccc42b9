"""The command table: one row per block, one cell per item, as in PPU's table editor.

Columns: ``#`` the block, ``N`` whether it is numbered (``·`` not, ``↺``
restarts numbering), ``if`` its condition, then the items, then an empty
``+`` column to add an item at the end.  A block that inserts a structure
shows ``⇢ name``.  Cells with a problem are red; a conditional item is dim
when its condition did not fire in the preview.
"""

from __future__ import annotations

from collections.abc import Collection
from typing import Any, ClassVar

from rich.text import Text
from textual.binding import Binding, BindingType
from textual.message import Message
from textual.widgets import DataTable

from postdsl.api import PlainText
from tui.model import BlockView, item_cell
from tui.tables import fill

#: columns before the first item
ITEM_COLUMN = 3
CELL_WIDTH = 24


def _cut(text: str, width: int) -> str:
    return text if len(text) <= width else text[:width - 1] + "…"


class CommandTable(DataTable[Any]):
    """The grid of the selected table.  Its edits (a, x, b…) are the main screen's actions:
    they act on this grid's cursor from any pane of the screen."""

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("enter", "select_cursor", "Edit"),
    ]

    class Moved(Message):
        """The cursor is on ``block`` and ``column`` (items start at ITEM_COLUMN)."""

        def __init__(self, block: int, column: int) -> None:
            super().__init__()
            self.block = block
            self.column = column

    class Activated(Message):
        """Enter or a click on a cell: edit it."""

        def __init__(self, block: int, column: int) -> None:
            super().__init__()
            self.block = block
            self.column = column

    def __init__(self, id: str | None = None) -> None:
        super().__init__(id=id, cursor_type="cell", zebra_stripes=False)
        self.fixed_columns = ITEM_COLUMN  # block number, numbering and condition stay in view
        self.blocks: list[BlockView] = []

    def show(self, blocks: list[BlockView], *, bad: Collection[tuple[Any, ...]] = (),
             fired: dict[tuple[Any, ...], bool] | None = None,
             cursor: tuple[int, int] | None = None) -> None:
        """Fill the grid.  ``bad``: (block,) or (block, item) with problems;
        ``fired``: the same keys -> did the condition fire in the preview."""
        fired = fired or {}
        self.blocks = blocks
        row, column = cursor if cursor is not None else self.cursor_coordinate
        width = max((len(b.items) if b.use is None else 1 for b in blocks), default=0)
        columns = [("#", "block"), ("N", "number"), ("if", "if")]
        columns += [(str(index + 1), f"item{index}") for index in range(width)]
        columns.append(("+", "add"))
        with self.prevent(DataTable.CellHighlighted):
            fill(self, columns, [(self._row(block, width, bad, fired), str(block.index))
                                 for block in blocks])
        if blocks:
            self.move_cursor(row=min(row, len(blocks) - 1),
                             column=min(column, ITEM_COLUMN + width), animate=False)

    def _row(self, block: BlockView, width: int, bad: Collection[tuple[Any, ...]],
             fired: dict[tuple[Any, ...], bool]) -> list[Any]:
        here = (block.index,)
        number = Text("·", style="dim") if not block.numbered else Text("N")
        if block.renumber:
            number.append("↺")
        if block.for_each:
            number.append("*")
        condition = Text(_cut(block.condition, 14), style="yellow")
        if block.condition and fired.get(here) is False:
            condition.stylize("dim")
        index_cell = Text(str(block.index + 1), style="bold red" if here in bad else "bold")
        if block.inherited:  # from the base post: an edit writes an override
            index_cell.append("↑", style="cyan")
        cells: list[Any] = [index_cell, number, condition]
        if block.use is not None:
            cells.append(Text(f"⇢ {block.use}", style="magenta"))
            cells += [""] * (width - 1)
        else:
            for index, item in enumerate(block.items):
                text = Text(_cut(item_cell(item), CELL_WIDTH))
                if isinstance(item, PlainText):
                    text.stylize("cyan")
                if fired.get(here + (index,)) is False:
                    text.stylize("dim")
                if here + (index,) in bad:
                    text.stylize("bold white on red")
                cells.append(text)
            cells += [""] * (width - len(block.items))
        cells.append("")
        if here in bad and block.use is None and not block.items:
            cells[ITEM_COLUMN] = Text("problem", style="bold white on red")
        return cells

    @property
    def position(self) -> tuple[int, int]:
        return self.cursor_coordinate.row, self.cursor_coordinate.column

    def on_data_table_cell_highlighted(self, event: DataTable.CellHighlighted) -> None:
        event.stop()
        self.post_message(self.Moved(event.coordinate.row, event.coordinate.column))

    def on_data_table_cell_selected(self, event: DataTable.CellSelected) -> None:
        event.stop()
        self.post_message(self.Activated(event.coordinate.row, event.coordinate.column))

