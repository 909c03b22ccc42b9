"""Fill a DataTable with columns sized to their content up front.

DataTable measures auto-width columns only when it next goes idle, and a
frame drawn before that keeps the old widths in its caches; giving every
column its width when it is added makes what is shown depend on the content
alone (and screenshots reproducible).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from rich.cells import cell_len
from rich.text import Text
from textual.widgets import DataTable


def width_of(cell: Any) -> int:
    if isinstance(cell, Text):
        return max((cell_len(line) for line in cell.plain.splitlines()), default=0)
    return max((cell_len(line) for line in str(cell).splitlines()), default=0)


def fill(table: DataTable[Any], columns: Sequence[tuple[str, str]],
         rows: Sequence[tuple[Sequence[Any], str]]) -> None:
    """Replace the table's columns ``(label, key)`` and rows ``(cells, key)``."""
    table.clear(columns=True)
    for index, (label, key) in enumerate(columns):
        width = max([cell_len(label)] + [width_of(cells[index]) for cells, _ in rows
                                         if index < len(cells)])
        table.add_column(label, key=key, width=width)
    for cells, key in rows:
        table.add_row(*cells, key=key)
