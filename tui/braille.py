"""Toolpath segments rasterised into Unicode braille cells: 2 × 4 dots per terminal cell.

Braille characters (U+2800–U+28FF) draw in any terminal with a Unicode
font, and a cell's dots are about square, so one scale fits both axes.
Rasterising is the expensive part (every dot of 200 000 segments); it runs
once per path, view and size, off the UI thread, and yields a
:class:`Raster` whose rows are drawn in O(columns) each.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

from postdsl.api import Segment, projector

#: bit of each dot in a braille cell, by [row 0..3][column 0..1] (Unicode's dot numbering)
DOT_BITS = ((0x01, 0x08), (0x02, 0x10), (0x04, 0x20), (0x40, 0x80))
BLANK = 0x2800

#: layers of a cell, lowest first: a cell shows the highest layer drawn into it
NONE, RAPID, FEED, HOLE = 0, 1, 2, 3
#: a tilted tool axis (3+2) is dotted as a rapid: a direction, not a move
LAYERS = {"rapid": RAPID, "feed": FEED, "hole": HOLE, "axis": RAPID}


@dataclass(frozen=True, slots=True)
class Frame:
    """Where millimetres land in dots: the view, its scale and the dot of its lowest corner."""

    view: str
    cols: int
    rows: int
    h0: float = 0.0
    v1: float = 0.0
    scale: float = 1.0
    left: float = 0.0
    top: float = 0.0

    @classmethod
    def fitting(cls, segments: Sequence[Segment], view: str, cols: int, rows: int) -> Frame:
        """The frame that shows every segment as large as the cells allow, centred."""
        project = projector(view)
        hs: list[float] = []
        vs: list[float] = []
        for segment in segments:
            for point in segment.points:
                h, v = project(point)
                hs.append(h)
                vs.append(v)
        if not hs or cols < 1 or rows < 1:
            return cls(view, max(cols, 0), max(rows, 0))
        h0, h1, v0, v1 = min(hs), max(hs), min(vs), max(vs)
        width, height = cols * 2 - 1, rows * 4 - 1
        span_h, span_v = h1 - h0, v1 - v0
        scales = [size / span for size, span in ((width, span_h), (height, span_v)) if span > 0]
        scale = min(scales) if scales else 1.0
        left = (width - span_h * scale) / 2
        top = (height - span_v * scale) / 2
        return cls(view, cols, rows, h0, v1, scale, left, top)


@dataclass
class Raster:
    """Dots and layers of every cell, row by row; ``bits`` 0 is a blank cell."""

    frame: Frame
    bits: bytearray
    layers: bytearray

    @classmethod
    def empty(cls, frame: Frame) -> Raster:
        size = frame.cols * frame.rows
        return cls(frame, bytearray(size), bytearray(size))

    def row_text(self, row: int) -> str:
        start = row * self.frame.cols
        return "".join(chr(BLANK + b) for b in self.bits[start:start + self.frame.cols])


#: segments drawn between two looks at ``stop``
CHECK_EVERY = 2048


class Stopped(Exception):
    """Rasterising was abandoned: its picture is no longer wanted."""


def rasterise(segments: Iterable[Segment], frame: Frame,
              stop: Callable[[], bool] | None = None) -> Raster:
    """Draw segments into a fresh raster: feeds and holes solid, rapids every other dot.

    A hole seen from above is a point: it is drawn as a small cross so it
    stands out from the moves around it.  ``stop`` is asked every few thousand
    segments whether the picture is still wanted (a thread cannot be killed:
    a worker whose view changed must give the processor back); when it says
    so, :class:`Stopped` is raised.
    """
    raster = Raster.empty(frame)
    cols, rows = frame.cols, frame.rows
    if cols == 0 or rows == 0:
        return raster
    bits, layers = raster.bits, raster.layers
    max_x, max_y = cols * 2 - 1, rows * 4 - 1
    project = projector(frame.view)
    h0, v1, scale, left, top = frame.h0, frame.v1, frame.scale, frame.left, frame.top
    dot_bits = DOT_BITS

    def plot(x: int, y: int, layer: int) -> None:
        if 0 <= x <= max_x and 0 <= y <= max_y:
            cell = (y >> 2) * cols + (x >> 1)
            bits[cell] |= dot_bits[y & 3][x & 1]
            if layers[cell] < layer:
                layers[cell] = layer

    # the hot loop of 200 000 segments: locals only, and a chord shorter than a dot
    # (most of a finely flattened arc) costs one comparison, not a plot
    for index, segment in enumerate(segments):
        if stop is not None and index % CHECK_EVERY == 0 and stop():
            raise Stopped
        layer = LAYERS[segment.kind]
        step = 2 if layer == RAPID else 1
        points = segment.points
        h, v = project(points[0])
        x0, y0 = left + (h - h0) * scale, top + (v1 - v) * scale
        last = (round(x0), round(y0))
        plot(last[0], last[1], layer)
        for point in points[1:]:
            h, v = project(point)
            x, y = left + (h - h0) * scale, top + (v1 - v) * scale
            dx, dy = x - x0, y - y0
            count = int(max(abs(dx), abs(dy)))
            if count == 0:
                here = (round(x), round(y))
                if here != last:
                    plot(here[0], here[1], layer)
                    last = here
            else:
                for i in range(step, count + 1, step):
                    t = i / count
                    plot(round(x0 + dx * t), round(y0 + dy * t), layer)
                last = (round(x0 + dx), round(y0 + dy))
            x0, y0 = x, y
        if layer == HOLE:
            h, v = project(points[0])
            if (h, v) == project(points[1]):  # seen end-on: a cross
                cx, cy = round(left + (h - h0) * scale), round(top + (v1 - v) * scale)
                for ddx, ddy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                    plot(cx + ddx, cy + ddy, layer)
    return raster
