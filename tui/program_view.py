"""The whole sample program, posted, with the selected command's lines highlighted.

A Line API widget: only the visible lines are rendered, and a line's mark (written
by the selected table, by its selected block) is asked for only when the line is
drawn, so a program of 200 000 lines scrolls, and follows the grid's cursor, as
fast as a short one.

It has a cursor of its own: up and down choose a line, left and right a word of
it; the screen traces the line (which cell wrote each word) and enter goes to
the cell that wrote the chosen word.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from typing import ClassVar

from rich.segment import Segment
from rich.style import Style
from textual.binding import Binding, BindingType
from textual.geometry import Size
from textual.message import Message
from textual.reactive import reactive
from textual.scroll_view import ScrollView
from textual.strip import Strip

#: mark of a line: 0 plain, 1 written by the selected table, 2 by the selected block
PLAIN, TABLE, BLOCK = 0, 1, 2

Marker = Callable[[int], int]


def _plain(_index: int) -> int:
    return PLAIN


class ProgramView(ScrollView, can_focus=True):
    """Scrollable NC program with a line-number gutter, a line cursor and a word cursor."""

    DEFAULT_CSS = """
    ProgramView { background: $surface; }
    """

    COMPONENT_CLASSES: ClassVar[set[str]] = {"program--gutter", "program--table",
                                             "program--block", "program--message",
                                             "program--cursor", "program--word"}

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("enter", "go_to_cell", "Go to cell"),
        Binding("up", "move(-1)", "Line up", show=False),
        Binding("down", "move(1)", "Line down", show=False),
        Binding("pageup", "page(-1)", "Page up", show=False),
        Binding("pagedown", "page(1)", "Page down", show=False),
        Binding("home", "move_to(0)", "First line", show=False),
        Binding("end", "move_to(-1)", "Last line", show=False),
        Binding("left", "word(-1)", "Word left", show=False),
        Binding("right", "word(1)", "Word right", show=False),
    ]

    cursor: reactive[int] = reactive(0, init=False, always_update=True)
    #: the character of the cursor's line the word cursor is on
    column: reactive[int] = reactive(0, init=False)

    class CursorMoved(Message):
        """The cursor is on line ``index`` (0-based): the screen traces it."""

        def __init__(self, index: int) -> None:
            super().__init__()
            self.index = index

    class WordChosen(Message):
        """The word cursor moved to character ``column`` of line ``index``."""

        def __init__(self, index: int, column: int) -> None:
            super().__init__()
            self.index = index
            self.column = column

    class CellWanted(Message):
        """Enter on line ``index``, character ``column``: show the cell that wrote it."""

        def __init__(self, index: int, column: int) -> None:
            super().__init__()
            self.index = index
            self.column = column

    def __init__(self, id: str | None = None) -> None:
        super().__init__(id=id)
        self.lines: list[str] = []
        self.mark: Marker = _plain
        self.message = ""
        #: (start, end) of the words of the cursor's line, once it is traced
        self.spans: list[tuple[int, int]] = []

    @property
    def marks(self) -> list[int]:
        """Every line's mark (for tests and small programs: drawing asks line by line)."""
        return [self.mark(index) for index in range(len(self.lines))]

    def show(self, lines: Sequence[str], mark: Marker = _plain, message: str = "",
             scroll_to: int | None = None) -> None:
        """New content; ``scroll_to`` brings that line into view."""
        if lines is not self.lines:
            self.lines = lines if isinstance(lines, list) else list(lines)
            self.spans = []
            width = max((len(line) for line in self.lines), default=0) + self._gutter + 1
            rows = len(self.lines) + (1 if message else 0)
            self.virtual_size = Size(max(width, len(message)), rows)
            if self.cursor >= len(self.lines):
                self.set_reactive(ProgramView.cursor, max(0, len(self.lines) - 1))
        self.mark = mark
        if message != self.message:
            self.message = message
            self.virtual_size = Size(self.virtual_size.width,
                                     len(self.lines) + (1 if message else 0))
        if scroll_to is not None:
            # after the layout: a new virtual size is not scrollable until then
            self.call_after_refresh(self._scroll_to_line, scroll_to)
        self.refresh()

    def remark(self, mark: Marker, scroll_to: int | None = None) -> None:
        """Another table or block is selected: new marks, same lines."""
        self.show(self.lines, mark, self.message, scroll_to)

    def _scroll_to_line(self, index: int) -> None:
        height = self.scrollable_content_region.height or 1
        self.scroll_to(y=max(0, index - height // 3), animate=False)

    @property
    def _gutter(self) -> int:
        return len(str(len(self.lines))) + 1

    # --- the cursor ---------------------------------------------------------------------------

    def set_words(self, index: int, spans: Sequence[tuple[int, int]]) -> None:
        """The word spans of line ``index`` (from its trace); ignored if the cursor moved on."""
        if index == self.cursor:
            self.spans = list(spans)
            self.refresh()

    def _spans(self) -> list[tuple[int, int]]:
        """The words of the cursor's line: traced ones, else runs of non-blank characters
        (so left and right work before the trace arrives)."""
        if self.spans:
            return self.spans
        text = self.lines[self.cursor] if 0 <= self.cursor < len(self.lines) else ""
        return [(m.start(), m.end()) for m in re.finditer(r"\S+", text)]

    def chosen(self) -> tuple[int, int] | None:
        """The span of the word under the word cursor."""
        spans = self._spans()
        for start, end in spans:
            if start <= self.column < end:
                return start, end
        return spans[0] if spans else None

    def watch_cursor(self, index: int) -> None:
        self.spans = []
        self.set_reactive(ProgramView.column, 0)
        height = self.scrollable_content_region.height or 1
        top = round(self.scroll_offset.y)
        if index < top:
            self.scroll_to(y=index, animate=False)
        elif index >= top + height:
            self.scroll_to(y=index - height + 1, animate=False)
        self.refresh()
        self.post_message(self.CursorMoved(index))

    def watch_column(self, column: int) -> None:
        self.refresh()
        self.post_message(self.WordChosen(self.cursor, column))

    def action_move(self, offset: int) -> None:
        if not self.lines:
            self.notify("no program: the sample could not be posted", severity="warning")
            return
        self.cursor = max(0, min(len(self.lines) - 1, self.cursor + offset))

    def action_page(self, direction: int) -> None:
        self.action_move(direction * max(1, self.scrollable_content_region.height - 1))

    def action_move_to(self, index: int) -> None:
        if self.lines:
            self.cursor = index % len(self.lines)

    def action_word(self, offset: int) -> None:
        spans = self._spans()
        current = self.chosen()
        if not spans or current is None:
            self.notify("the line has no words", severity="warning")
            return
        index = spans.index(current) + offset
        if not 0 <= index < len(spans):
            self.notify(f"that is the {'first' if offset < 0 else 'last'} word of the line")
            return
        start, end = spans[index]
        # land on the word itself, not on the space an item writes before it
        text = self.lines[self.cursor]
        self.column = next((i for i in range(start, end) if not text[i].isspace()), start)

    def action_go_to_cell(self) -> None:
        if not self.lines:
            self.notify("no program: nothing to go to", severity="warning")
            return
        self.post_message(self.CellWanted(self.cursor, self.column))

    def on_click(self, event: object) -> None:
        offset = getattr(event, "y", None)
        if isinstance(offset, int) and self.lines:
            index = offset + round(self.scroll_offset.y)
            if 0 <= index < len(self.lines):
                self.cursor = index

    # --- drawing ------------------------------------------------------------------------------

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
        mark = self.mark(index)
        gutter_style = self.get_component_rich_style("program--gutter")
        line_style = Style()
        if mark == TABLE:
            line_style = self.get_component_rich_style("program--table")
        elif mark == BLOCK:
            line_style = self.get_component_rich_style("program--block")
        text = self.lines[index]
        number = str(index + 1).rjust(self._gutter - 1)
        segments = [Segment(number, gutter_style)]
        if index == self.cursor and self.has_focus:
            segments.append(Segment("▶", self.get_component_rich_style("program--cursor")))
            segments += self._words(text, line_style)
        else:
            segments += [Segment(" ", gutter_style), Segment(text, line_style)]
        strip = Strip(segments).crop_extend(scroll_x, scroll_x + width, line_style)
        return strip.apply_style(self.rich_style)

    def _words(self, text: str, style: Style) -> list[Segment]:
        """The cursor's line with its chosen word shown."""
        chosen = self.chosen()
        if chosen is None:
            return [Segment(text, style)]
        start, end = chosen
        word = self.get_component_rich_style("program--word")
        return [Segment(text[:start], style), Segment(text[start:end], word),
                Segment(text[end:], style)]
