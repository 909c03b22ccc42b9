"""The whole sample program, posted, with the selected command's lines highlighted.

A Line API widget: only the visible lines are rendered, so programs of many
thousand lines scroll as fast as short ones.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import ClassVar

from rich.segment import Segment
from rich.style import Style
from textual.geometry import Size
from textual.scroll_view import ScrollView
from textual.strip import Strip

#: mark of a line: 0 plain, 1 written by the selected table, 2 by the selected block
PLAIN, TABLE, BLOCK = 0, 1, 2


class ProgramView(ScrollView, can_focus=True):
    """Scrollable NC program with a line-number gutter."""

    DEFAULT_CSS = """
    ProgramView { background: $surface; }
    """

    COMPONENT_CLASSES: ClassVar[set[str]] = {"program--gutter", "program--table", "program--block",
                         "program--message"}

    def __init__(self, id: str | None = None) -> None:
        super().__init__(id=id)
        self.lines: list[str] = []
        self.marks: list[int] = []
        self.message = ""

    def show(self, lines: Sequence[str], marks: Sequence[int], message: str = "",
             scroll: bool = False) -> None:
        """New content; ``scroll`` brings the first marked line into view."""
        self.lines = list(lines)
        self.marks = list(marks) + [PLAIN] * (len(lines) - len(marks))
        self.message = message
        rows = len(self.lines) + (1 if message else 0)
        width = max((len(line) for line in self.lines), default=0) + self._gutter + 1
        self.virtual_size = Size(max(width, len(message)), rows)
        if scroll:
            # after the layout: a new virtual size is not scrollable until then
            self.call_after_refresh(self.scroll_to_mark)
        self.refresh()

    @property
    def _gutter(self) -> int:
        return len(str(len(self.lines))) + 1

    def scroll_to_mark(self) -> None:
        """Bring the first line of the selected block (or table) into view."""
        for wanted in (BLOCK, TABLE):
            if wanted in self.marks:
                first = self.marks.index(wanted)
                height = self.scrollable_content_region.height or 1
                self.scroll_to(y=max(0, first - height // 3), animate=False)
                return

    def render_line(self, y: int) -> Strip:
        scroll_x, scroll_y = self.scroll_offset
        index = y + scroll_y
        width = self.scrollable_content_region.width
        if index == len(self.lines) and self.message:
            style = self.get_component_rich_style("program--message")
            return Strip([Segment(self.message, style)]).crop_extend(
                scroll_x, scroll_x + width, None).apply_style(self.rich_style)
        if index >= len(self.lines):
            return Strip.blank(width, self.rich_style)
        mark = self.marks[index]
        gutter_style = self.get_component_rich_style("program--gutter")
        line_style = Style()
        if mark == TABLE:
            line_style = self.get_component_rich_style("program--table")
        elif mark == BLOCK:
            line_style = self.get_component_rich_style("program--block")
        text = self.lines[index]
        number = str(index + 1).rjust(self._gutter - 1) + " "
        strip = Strip([Segment(number, gutter_style), Segment(text, line_style)])
        strip = strip.crop_extend(scroll_x, scroll_x + width, line_style)
        return strip.apply_style(self.rich_style)
