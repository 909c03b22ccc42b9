"""The backplot: a program's toolpath drawn in braille characters, one view at a time.

The path is the NC program replayed through the control model
(``api.toolpath``), so the picture shows what the posted text makes the
machine do.  Rapids are dotted, feeds solid, holes in their own colour; the
moves of the NC lines in ``highlight`` (the selected command's) are drawn
over the rest in the highlight colour.  ``v`` switches between the XY, XZ
and YZ views.

Rasterising 200 000 segments takes a good part of a second in Python, so it
runs in a thread worker; the widget draws its last picture (or says it is
drawing) meanwhile, and each row is then drawn from the raster in
O(columns).  A highlight only rasterises the highlighted segments, over the
picture already drawn.  A screen that mounts the widget adds ``BACKPLOT_TCSS``
to its ``CSS_PATH`` for the colours and the border.
"""

from __future__ import annotations

import textwrap
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

from rich.segment import Segment as RichSegment
from rich.style import Style
from textual import work
from textual.binding import Binding, BindingType
from textual.reactive import reactive
from textual.strip import Strip
from textual.widget import Widget
from textual.worker import Worker, WorkerState, get_current_worker

from postdsl.api import Segment, Toolpath
from tui.braille import BLANK, FEED, HOLE, RAPID, Frame, Raster, Stopped, rasterise

BACKPLOT_TCSS = Path(__file__).with_name("backplot.tcss")

VIEWS = ("xy", "xz", "yz")
#: the style key of highlighted cells, above every layer of tui.braille
LIT = 99
VIEW_NAMES = {"xy": "XY top", "xz": "XZ front", "yz": "YZ side"}


@dataclass(frozen=True)
class Picture:
    """A finished raster and what it was drawn from (to drop one that is out of date)."""

    segments: Sequence[Segment]
    raster: Raster
    highlight: frozenset[int]
    overlay: Raster | None


@dataclass(frozen=True)
class Overlay:
    """The highlighted moves drawn into the frame of the picture on screen."""

    segments: Sequence[Segment]
    frame: Frame
    highlight: frozenset[int]
    raster: Raster | None


def _cancelled() -> bool:
    """Whether the worker running this has been replaced by a newer one (exclusive workers)."""
    return get_current_worker().is_cancelled


def _highlighted(segments: Sequence[Segment], frame: Frame, highlight: frozenset[int],
                 stop: Callable[[], bool] | None = None) -> Raster | None:
    if not highlight:
        return None
    return rasterise((s for s in segments if s.nc_line in highlight), frame, stop)


class Backplot(Widget, can_focus=True):
    """A toolpath in braille, scaled to the widget; ``v`` cycles the views."""

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("v,V", "next_view", "View", tooltip="Show the toolpath from the top, the "
                "front or the side"),
    ]

    COMPONENT_CLASSES: ClassVar[set[str]] = {
        "backplot--rapid", "backplot--feed", "backplot--hole", "backplot--highlight",
        "backplot--message",
    }

    #: the view drawn: "xy" from the top, "xz" from the front, "yz" from the side
    view: reactive[str] = reactive("xy")
    #: NC line numbers whose moves are drawn in the highlight colour
    highlight: reactive[frozenset[int]] = reactive(frozenset())
    #: True while a raster is being computed in the worker
    drawing: reactive[bool] = reactive(False)

    def __init__(self, *, name: str | None = None, id: str | None = None,
                 classes: str | None = None) -> None:
        super().__init__(name=name, id=id, classes=classes)
        self.segments: Sequence[Segment] = []
        self.stopped: str | None = None
        self.picture: Picture | None = None
        #: why there is no path to draw (shown instead of "no motion to draw")
        self.note = ""

    # --- what to draw ------------------------------------------------------------------------

    def show_path(self, path: Toolpath) -> None:
        """Draw a new toolpath (the previous picture stays until the new one is ready)."""
        self.segments = path.segments
        self.stopped = path.stopped
        self.note = ""
        self._title()
        self._redraw()

    def show_note(self, note: str) -> None:
        """No path to draw, and why (the post has problems, the program is being posted)."""
        self.segments = []
        self.stopped = None
        self.picture = None
        self.note = note
        self.drawing = False
        self._title()
        self.refresh()

    def highlight_table(self, table: str) -> None:
        """Highlight the moves written by one table (a command's, or a custom cycle's)."""
        self.highlight = frozenset(s.nc_line for s in self.segments if s.table == table)

    def action_next_view(self) -> None:
        self.view = VIEWS[(VIEWS.index(self.view) + 1) % len(VIEWS)]

    def on_mount(self) -> None:
        self._title()

    def watch_view(self) -> None:
        self._title()
        self._redraw()

    def watch_highlight(self, highlight: frozenset[int]) -> None:
        picture = self.picture
        if picture is None or picture.segments is not self.segments:
            return  # the picture being drawn takes the new highlight when it arrives
        self._draw_highlight(self.segments, picture.raster.frame, highlight)

    def watch_drawing(self) -> None:
        self._title()

    def on_resize(self) -> None:
        self._redraw()

    def _title(self) -> None:
        self.border_title = f"toolpath · {VIEW_NAMES[self.view]} · V: view"
        notes = []
        if self.drawing:
            notes.append("drawing…")
        if self.stopped:
            notes.append(f"the control stops: {self.stopped}")
        self.border_subtitle = " · ".join(notes)

    def _wanted_frame(self, frame: Frame) -> bool:
        size = self.size
        return (frame.view, frame.cols, frame.rows) == (self.view, size.width, size.height)

    # --- rasterising, off the UI thread --------------------------------------------------

    def _redraw(self) -> None:
        if not self.is_mounted:
            return
        self.drawing = True
        size = self.size
        self._rasterise(self.segments, self.view, size.width, size.height, self.highlight)

    # a description, so Textual does not repr() 200 000 segments to name the worker
    @work(thread=True, exclusive=True, group="backplot", exit_on_error=False,
          description="rasterising the toolpath")
    def _rasterise(self, segments: Sequence[Segment], view: str, cols: int, rows: int,
                   highlight: frozenset[int]) -> Picture | None:
        frame = Frame.fitting(segments, view, cols, rows)
        try:
            raster = rasterise(segments, frame, _cancelled)
            overlay = _highlighted(segments, frame, highlight, _cancelled)
        except Stopped:
            return None  # a newer worker draws what is wanted now
        return Picture(segments, raster, highlight, overlay)

    def _draw_highlight(self, segments: Sequence[Segment], frame: Frame,
                        highlight: frozenset[int]) -> None:
        self._rasterise_highlight(segments, frame, highlight)

    @work(thread=True, exclusive=True, group="backplot-highlight", exit_on_error=False,
          description="rasterising the highlighted moves")
    def _rasterise_highlight(self, segments: Sequence[Segment], frame: Frame,
                             highlight: frozenset[int]) -> Overlay | None:
        try:
            return Overlay(segments, frame, highlight,
                           _highlighted(segments, frame, highlight, _cancelled))
        except Stopped:
            return None

    def on_worker_state_changed(self, event: Worker.StateChanged) -> None:
        group = event.worker.group
        if group not in ("backplot", "backplot-highlight"):
            return
        event.stop()
        if event.state == WorkerState.ERROR:  # a bug: say so in the border, keep the screen
            self.drawing = False
            self.stopped = f"cannot draw ({event.worker.error})"
            self._title()
            return
        if event.state != WorkerState.SUCCESS:
            return
        result = event.worker.result
        if isinstance(result, Picture):
            if result.segments is not self.segments or not self._wanted_frame(result.raster.frame):
                return  # drawn for a path, view or size no longer shown
            self.picture = result
            self.drawing = False
            if result.highlight != self.highlight:
                self._draw_highlight(self.segments, result.raster.frame, self.highlight)
        elif isinstance(result, Overlay):
            picture = self.picture
            if picture is None or result.segments is not picture.segments or \
                    result.frame != picture.raster.frame or result.highlight != self.highlight:
                return
            self.picture = Picture(picture.segments, picture.raster, result.highlight,
                                   result.raster)
        self.refresh()

    # --- drawing rows ---------------------------------------------------------------------

    def render_line(self, y: int) -> Strip:
        width = self.size.width
        picture = self.picture
        if not self.segments or picture is None or \
                not self._wanted_frame(picture.raster.frame):
            return self._message_line(y, width)
        raster, overlay = picture.raster, picture.overlay
        styles = self._styles()
        lit = styles[LIT]
        start = y * raster.frame.cols
        bits, layers = raster.bits, raster.layers
        over = overlay.bits if overlay is not None else None
        runs: list[RichSegment] = []
        text: list[str] = []
        current: Style | None = None
        for cell in range(start, start + raster.frame.cols):
            dots = bits[cell]
            style = styles[layers[cell]]
            if over is not None and over[cell]:
                dots |= over[cell]
                style = lit
            if style is not current:
                if text:
                    runs.append(RichSegment("".join(text), current))
                text, current = [], style
            text.append(chr(BLANK + dots))
        if text:
            runs.append(RichSegment("".join(text), current))
        return Strip(runs, width)

    def _styles(self) -> dict[int, Style]:
        """The colour of each layer over the widget's own background (blank cells too)."""
        base = self.rich_style
        names = {RAPID: "backplot--rapid", FEED: "backplot--feed", HOLE: "backplot--hole",
                 LIT: "backplot--highlight"}
        styles = {layer: base + self.get_component_rich_style(name, partial=True)
                  for layer, name in names.items()}
        styles[0] = base
        return styles

    def _message_line(self, y: int, width: int) -> Strip:
        if self.note:
            lines = textwrap.wrap(self.note, max(width, 1)) or [""]
        else:
            lines = ["drawing…" if self.segments else "no motion to draw"]
        if y >= len(lines):
            return Strip.blank(width)
        style = self.get_component_rich_style("backplot--message")
        return Strip([RichSegment(lines[y][:width], style)], width).extend_cell_length(width)
