"""A posted program's motion as drawable segments: what a backplot or an SVG plot draws.

The segments come from the NC program replayed through the machine's control
model (``postdsl.check.controls``), not from the CL: a picture must show what the
control would do with the text the post wrote, so a wrong word shows as a
wrong line.  Each segment is a polyline in program coordinates (mm):

- ``rapid``: a positioning move (a reference return or a tool change leaves
  an axis unknown: moves from or to an unknown position are not drawn);
- ``feed``: a cutting move; an arc is flattened to a polyline whose chords
  stay within ``tolerance`` of the true circle;
- ``hole``: a drilled, tapped or bored hole, from its R level to the bottom
  and back to the level the tool is left at (the rapids to the hole are
  rapid segments of their own);
- ``axis``: where the tool axis tilts (a 3+2 plane), a short line from the tool tip at
  the first cut made in each plane, :data:`AXIS_LENGTH` mm along the tool axis, as a
  CAM backplot draws the tool standing on the part.  On a machine with rotaries, likewise
  at the end of a cut whose tool axis on the part (``FeedMove.axis``) tilts, where it has
  turned :data:`AXIS_STEP` degrees or more from the last one drawn: a wrap shows the tool
  every so often round the part, not once per block.

The points are in the part frame: a move the control makes inside a tilted working
plane is given in the plane's coordinates (``Tooling.frame`` of a cut, the model's
frame in force for a rapid) and drawn where the plane puts it, so the cuts of a
plane appear on the part's face they machine, not flat over the origin.

Every segment keeps the NC line that made it and the CL command and table
that wrote that line, so an editor can highlight one command's moves.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass

from postdsl.check.controls.base import PLANE_AXES, ControlError
from postdsl.check.controls.events import ArcMove, Event, FeedMove, Hole, Point, Rapid
from postdsl.frames import Frame

#: largest distance (mm) between an arc and the chords that draw it
ARC_TOLERANCE = 0.01
#: an arc is never cut into more chords than this, whatever its size
MAX_ARC_CHORDS = 720
#: the length (mm) of the line drawn along a tilted tool axis
AXIS_LENGTH = 15.0
#: a rotary cut's tool axis is drawn again once it has turned this much (degrees)
AXIS_STEP = 15.0
_AXIS_STEP_COS = math.cos(math.radians(AXIS_STEP))

XYZ = tuple[float, float, float]

#: drawing views: name -> (horizontal axis, vertical axis) as indices of X Y Z,
#: or None for the isometric view (X to the upper right, Y to the upper left, Z up)
VIEWS: dict[str, tuple[int, int] | None] = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2),
                                            "iso": None}
#: the axis names along a view's horizontal and vertical directions
VIEW_AXES = {"xy": ("X", "Y"), "xz": ("X", "Z"), "yz": ("Y", "Z"), "iso": ("", "Z")}

_COS30 = math.cos(math.pi / 6)


@dataclass(frozen=True, slots=True)
class Segment:
    """One move to draw: a polyline, its kind and where it comes from."""

    kind: str  # "rapid", "feed", "hole" or "axis"
    points: tuple[XYZ, ...]
    #: the NC line (1-based) the control executed this move for
    nc_line: int
    #: the CL command that caused the line and the table that wrote it ('' when unknown)
    command: str = ""
    table: str = ""
    #: the CL command's line in its file (0 when unknown)
    cl_line: int = 0


@dataclass
class Toolpath:
    """The segments of a program, and why the replay stopped early (None: it did not)."""

    segments: list[Segment]
    stopped: str | None = None

    def bounds(self) -> tuple[XYZ, XYZ] | None:
        """(lowest X Y Z, highest X Y Z) over every drawn point; None for an empty path."""
        return bounds_of(self.segments)


@dataclass(frozen=True, slots=True)
class LineSource:
    """What wrote an NC line: the CL command, its table and its CL line."""

    command: str
    table: str
    cl_line: int


def bounds_of(segments: Iterable[Segment]) -> tuple[XYZ, XYZ] | None:
    low = [math.inf] * 3
    high = [-math.inf] * 3
    for segment in segments:
        for point in segment.points:
            for axis in range(3):
                value = point[axis]
                if value < low[axis]:
                    low[axis] = value
                if value > high[axis]:
                    high[axis] = value
    if low[0] == math.inf:
        return None
    return (low[0], low[1], low[2]), (high[0], high[1], high[2])


def _known(point: Point) -> XYZ | None:
    if point[0] is None or point[1] is None or point[2] is None:
        return None
    return (float(point[0]), float(point[1]), float(point[2]))


def flatten_arc(arc: ArcMove, tolerance: float = ARC_TOLERANCE) -> tuple[XYZ, ...]:
    """The arc as points from its start to its end, chords within ``tolerance`` of the circle.

    A helix rises linearly along the plane's normal.  The last point is the
    arc's end exactly, so consecutive moves join without a gap.
    """
    start, end = _known(arc.start), _known(arc.end)
    if start is None or end is None:
        return ()
    a, b, n = PLANE_AXES[arc.plane]
    radius = arc.radius
    step = math.pi / 2 if radius <= tolerance else 2 * math.acos(1 - tolerance / radius)
    chords = min(MAX_ARC_CHORDS, max(1, math.ceil(arc.sweep / step)))
    angle0 = math.atan2(start[b] - arc.centre[b], start[a] - arc.centre[a])
    turn = -arc.sweep if arc.clockwise else arc.sweep
    points: list[XYZ] = [start]
    for i in range(1, chords):
        t = i / chords
        angle = angle0 + turn * t
        p = [0.0, 0.0, 0.0]
        p[a] = arc.centre[a] + radius * math.cos(angle)
        p[b] = arc.centre[b] + radius * math.sin(angle)
        p[n] = start[n] + (end[n] - start[n]) * t
        points.append((p[0], p[1], p[2]))
    points.append(end)
    return tuple(points)


def segments_of(events: Iterable[Event], source: Callable[[int], LineSource | None],
                tolerance: float = ARC_TOLERANCE,
                frame_now: Callable[[], Frame | None] | None = None) -> Iterator[Segment]:
    """Drawable segments of a replayed program's events (see the module docstring).

    ``source`` names what wrote an NC line.  ``frame_now`` is the working plane the
    control has in force while it yields an event (a rapid carries no tooling to say
    it); None: every rapid is in the part frame.  Raises ControlError as the replay
    does, after yielding the segments before the refused line.
    """
    last_cut: Frame | None = None  # the plane of the last cut drawn
    drawn_axis: XYZ | None = None  # a rotary cut's tool axis last drawn
    for event in events:
        kind: str
        points: tuple[XYZ, ...]
        frame: Frame | None
        if isinstance(event, (Rapid, FeedMove)):
            start, end = _known(event.start), _known(event.end)
            if start is None or end is None or start == end:
                continue
            if isinstance(event, Rapid):
                kind, frame = "rapid", frame_now() if frame_now is not None else None
            else:
                kind, frame = "feed", event.tooling.frame
            points = (start, end)
        elif isinstance(event, ArcMove):
            points = flatten_arc(event, tolerance)
            if not points:
                continue
            kind, frame = "feed", event.tooling.frame
        elif isinstance(event, Hole):
            leave = event.leave if event.leave is not None else event.r
            points = ((event.x, event.y, event.r), (event.x, event.y, event.bottom),
                      (event.x, event.y, leave))
            kind, frame = "hole", event.tooling.frame
        else:
            continue
        if frame is not None:
            to_part = frame.to_part
            points = tuple(to_part(p) for p in points)
        origin = source(event.origin.line)
        command, table, cl_line = ("", "", 0) if origin is None else \
            (origin.command, origin.table, origin.cl_line)
        if kind != "rapid" and frame != last_cut:
            last_cut = frame
            if frame is not None and _tilted(frame):
                yield Segment("axis", axis_line(points[0], frame), event.origin.line,
                              command, table, cl_line)
        yield Segment(kind, points, event.origin.line, command, table, cl_line)
        if event.__class__ is FeedMove and event.axis is not None:
            axis = event.axis
            tilted = abs(axis[0]) > 1e-9 or abs(axis[1]) > 1e-9 or axis[2] < 1 - 1e-9
            if tilted and (drawn_axis is None or _dot(axis, drawn_axis) < _AXIS_STEP_COS):
                drawn_axis = axis
                tip = points[-1]
                yield Segment("axis", (tip, (tip[0] + axis[0] * AXIS_LENGTH,
                                             tip[1] + axis[1] * AXIS_LENGTH,
                                             tip[2] + axis[2] * AXIS_LENGTH)),
                              event.origin.line, command, table, cl_line)
            elif not tilted:
                drawn_axis = None


def _dot(u: XYZ, v: XYZ) -> float:
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def _tilted(frame: Frame) -> bool:
    """Whether a plane's tool axis leaves the part's Z (a datum shift alone does not)."""
    i, j, k = frame.tool_axis
    return abs(i) > 1e-9 or abs(j) > 1e-9 or k < 1 - 1e-9


def axis_line(tip: XYZ, frame: Frame, length: float = AXIS_LENGTH) -> tuple[XYZ, XYZ]:
    """The tool standing on ``tip`` in a tilted plane: from the tip up its tool axis."""
    i, j, k = frame.tool_axis
    return tip, (tip[0] + i * length, tip[1] + j * length, tip[2] + k * length)


def collect(events: Iterable[Event], source: Callable[[int], LineSource | None],
            tolerance: float = ARC_TOLERANCE,
            frame_now: Callable[[], Frame | None] | None = None) -> Toolpath:
    """Every segment of a replay; a line the control refuses ends the path, saying why."""
    segments: list[Segment] = []
    try:
        segments.extend(segments_of(events, source, tolerance, frame_now))
    except ControlError as exc:
        return Toolpath(segments, str(exc))
    return Toolpath(segments)


def motion_key(segments: Sequence[Segment], resolution: float) -> list[tuple[object, ...]]:
    """The motion of a path without its line numbers, rounded to ``resolution``.

    Two programs move the tool alike when their keys are equal: renumbered
    blocks, a changed comment or a split block leave the key unchanged only
    when the moves themselves are the same.
    """
    step = resolution if resolution > 0 else 0.001
    return [(s.kind, *(tuple(round(v / step) for v in p) for p in s.points)) for s in segments]


def projector(view: str) -> Callable[[XYZ], tuple[float, float]]:
    """How a view sees a point: ``xy`` from above, ``xz`` from the front, ``yz`` from the side.

    Returned as a function, so a loop over 200 000 segments does not look the
    view up per point.
    """
    axes = VIEWS[view]
    if axes is None:
        return lambda p: ((p[0] - p[1]) * _COS30, (p[0] + p[1]) * 0.5 + p[2])
    h, v = axes
    return lambda p: (p[h], p[v])
