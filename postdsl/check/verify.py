"""Does the NC program do what the CL says?  Event by event, within the machine's resolution.

Both sides are streams of :mod:`postdsl.check.controls.events`: the CL commands
(``postdsl.check.motion``) and the posted program replayed through the model of
the machine's control (``postdsl.check.controls``).  They are read in step, one
*cut* at a time — a feed move, an arc, a hole or a dwell — so a program of a
million moves is never held in memory.

Compared for every cut, within ``machine.resolution`` (mm) for lengths — or, where
the control model knows the smallest move of each axis from the program (a control
driving motors in whole steps, whose program states steps per mm), within one such
step of each axis, since a post rounds every coordinate to whole steps:

- the position the cut starts from (feed moves and arcs), its end point, an
  arc's centre, direction, plane and length (a short arc written as a full
  circle turns a whole turn more), a hole's X Y, R level (top + clearance),
  bottom, kind (drill, peck, chip break, tap, rigid tap), spindle direction
  going in, dwell, peck and first peck (a peck cycle with peck 0 is a drill), and the
  level the tool is left at: the CL's retract level, neither lower nor higher;
- the feed (mm/min, within 0.5 mm/min; feed per revolution times the
  spindle speed), the spindle direction and speed (within 0.5 rpm), the tool
  and that its own length offset is active; no cut with the spindle stopped;
- a dwell's time within 0.5 ms;
- the tilted working plane (3+2) each cut is made in: a cut's positions are in its
  plane's frame on both sides, so the planes themselves are compared -- the tool axis
  and the plane's X axis within the resolution per 100 mm, its origin within the
  resolution, all in the part frame (:func:`postdsl.frames.frame_difference`); no plane
  is the part frame.  A plane not cancelled, a plane change not written, angles in
  another convention than the control's all differ here.

Rapid moves are not matched one to one (a post may split an XYZ rapid into XY
then Z), but between two cuts: no NC rapid ends below the lowest point the
CL's tool reaches in that stretch, and no NC rapid moves sideways (in X or Y)
below the lowest level at which the CL moves sideways there — or, when the CL
does not move sideways, below the higher of the stretch's two ends.  An axis
left unknown by a reference return or a tool change counts as at the top of
its travel.

Feed moves and arcs shorter than the resolution (no axis moving more than its
step), and zero dwells, do nothing on a machine and are skipped on both sides.

Either side may hand a straight feed move on as a
:data:`~postdsl.check.controls.base.PlainFeed` tuple instead of a FeedMove (the control
models' fast path for the common NC line, the CL's plain moves): two such moves
with no rapid between them are compared in line -- the same tests, within the same
tolerances -- and anything else, or any difference, goes through the general
comparison with the events made from the tuples, so a message is the same either way.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass

from postdsl.check.controls.base import ControlError, PlainFeed, feed_event
from postdsl.check.controls.events import (
    ArcMove,
    Dwell,
    Event,
    FeedMove,
    Hole,
    NotFollowed,
    Origin,
    Point,
    Rapid,
    Tooling,
)
from postdsl.frames import frame_difference

FEED_TOLERANCE = 0.5  # mm/min
SPEED_TOLERANCE = 0.5  # rpm
DWELL_TOLERANCE = 0.0005  # s

Cut = FeedMove | ArcMove | Hole | Dwell
#: the smallest move of each axis X Y Z (mm) once the control knows it; None: not known
AxisSteps = Callable[[], Sequence[float] | None]


class _Tolerance:
    """Within how much two lengths of an axis agree: one step of the axis, else the resolution.

    Asked at each comparison, because a control learns its steps from the program
    it replays (a comment line at the top) after the comparison has started.
    """

    def __init__(self, resolution: float, axis_steps: AxisSteps | None) -> None:
        self.resolution = resolution
        self.axis_steps = axis_steps

    def steps(self) -> Sequence[float] | None:
        return self.axis_steps() if self.axis_steps is not None else None

    def of(self, axis: int) -> float:
        steps = self.steps()
        return self.resolution if steps is None else steps[axis]

    def largest(self) -> float:
        steps = self.steps()
        return self.resolution if steps is None else max(steps)


@dataclass(frozen=True)
class Divergence:
    """The first place the NC program does not do what the CL says."""

    message: str
    cl: Origin | None
    nc: Origin | None

    def __str__(self) -> str:
        where = [str(o) for o in (self.cl, self.nc) if o is not None]
        return ": ".join(where + [self.message])


@dataclass
class Verdict:
    """What a verify found: the first divergence (None: none) and what it compared."""

    divergence: Divergence | None = None
    cuts: int = 0
    holes: int = 0
    rapids: int = 0

    @property
    def ok(self) -> bool:
        return self.divergence is None


class _Stream:
    """One side's events, handed out a stretch of rapids and the cut after them at a time.

    A :data:`PlainFeed` stays a tuple (``file`` names the CL file its origin is in).
    """

    def __init__(self, events: Iterator[Event | PlainFeed], tolerance: _Tolerance,
                 file: str = "") -> None:
        self.events = events
        self.tolerance = tolerance
        self.file = file
        self._last: Origin | PlainFeed | None = None
        #: the resolution when it is the tolerance of every axis (no axis steps), else None
        self.fixed = tolerance.resolution if tolerance.axis_steps is None else None

    @property
    def last(self) -> Origin | None:
        """The origin of the last event read."""
        last = self._last
        return feed_event(last, self.file).origin if last.__class__ is tuple \
            else last  # type: ignore[return-value]  # not a tuple: an Origin

    def event(self, cut: Cut | PlainFeed) -> Cut:
        """A cut as an event (a :data:`PlainFeed` made a FeedMove)."""
        # mypy narrows neither side of `__class__ is tuple`: a tuple is a PlainFeed, else a Cut
        return feed_event(cut, self.file) if cut.__class__ is tuple else cut  # type: ignore[return-value]

    def next_cut(self, first: Event | PlainFeed | None = None
                 ) -> tuple[list[Rapid | NotFollowed], Cut | PlainFeed | None]:
        """The rapids up to the next cut, and the cut (None: the side ends); ``first``
        is an event of the side already read, to take first."""
        gap: list[Rapid | NotFollowed] = []
        dist = math.dist
        fixed = self.fixed
        events = self.events if first is None else itertools.chain((first,), self.events)
        for event in events:
            if event.__class__ is tuple:
                self._last = event
                if fixed is not None:
                    if dist(event[2], event[3]) <= fixed:
                        continue
                elif self._does_nothing(self.event(event)):
                    continue
                return gap, event
            self._last = event.origin  # type: ignore[union-attr]  # not a tuple: an event
            if isinstance(event, (Rapid, NotFollowed)):
                gap.append(event)
            elif isinstance(event, (FeedMove, ArcMove, Hole, Dwell)):
                if self._does_nothing(event):
                    continue
                return gap, event
        return gap, None

    def _does_nothing(self, event: Cut) -> bool:
        if isinstance(event, Dwell):
            return event.seconds <= DWELL_TOLERANCE
        if isinstance(event, FeedMove):
            if None in event.start or None in event.end:
                return False
            steps = self.tolerance.steps()
            if steps is not None:   # whole steps: less than one on every axis is none
                return all(abs(float(b) - float(a)) <= step + 1e-9  # type: ignore[arg-type]  # None refused above
                           for a, b, step in zip(event.start, event.end, steps, strict=True))
            return _distance(event.start, event.end) <= self.tolerance.resolution
        if isinstance(event, ArcMove):
            return _arc_length(event) <= self.tolerance.largest()
        return False


def verify_events(nc: Iterable[Event | PlainFeed], cl: Iterable[Event | PlainFeed],
                  resolution: float,
                  cl_of_nc_line: Callable[[int], Origin | None] = lambda line: None,
                  axis_steps: AxisSteps | None = None, cl_file: str = "") -> Verdict:
    """Compare the NC side's events with the CL's; the first divergence, located on both sides.

    ``cl_of_nc_line`` names the CL record that wrote an NC line, for a line the
    control model refuses (the comparison knows the CL side of every other).
    ``axis_steps``, when it returns the steps of the axes, replaces ``resolution``.
    Either side may hold :data:`PlainFeed` tuples; ``cl_file`` is the file of the CL
    side's (its events name their own).
    """
    verdict = Verdict()
    tolerance = _Tolerance(resolution, axis_steps)
    nc_side = _Stream(iter(nc), tolerance)
    cl_side = _Stream(iter(cl), tolerance, cl_file)
    compare = _Comparison(tolerance)
    nc_from: Point | None = None
    cl_from: Point | None = None
    plain = tuple
    dist = math.dist
    fixed = nc_side.fixed
    no_gap: list[Rapid | NotFollowed] = []
    held_nc: list[Rapid | NotFollowed] = []
    held_cl: list[Rapid | NotFollowed] = []
    nc_plain: Cut | PlainFeed | None
    cl_plain: Cut | PlainFeed | None
    while True:
        # the common cut in line: the next event of each side a plain feed move that
        # moves (else next_cut, from that event, reads the side as it reads any)
        try:
            for event in nc_side.events:
                if event.__class__ is plain and fixed is not None:
                    nc_side._last = event
                    if dist(event[2], event[3]) <= fixed:
                        continue
                    nc_gap, nc_plain = no_gap, event
                else:
                    nc_gap, nc_plain = nc_side.next_cut(event)
                break
            else:
                nc_gap, nc_plain = no_gap, None
        except ControlError as exc:
            verdict.divergence = Divergence(exc.message, cl_of_nc_line(exc.origin.line),
                                            exc.origin)
            return verdict
        try:
            for event in cl_side.events:
                if event.__class__ is plain and fixed is not None:
                    cl_side._last = event
                    if dist(event[2], event[3]) <= fixed:
                        continue
                    cl_gap, cl_plain = no_gap, event
                else:
                    cl_gap, cl_plain = cl_side.next_cut(event)
                break
            else:
                cl_gap, cl_plain = no_gap, None
        except ControlError as exc:  # a CL arc no control can run (radius 0)
            verdict.divergence = Divergence(exc.message, exc.origin, None)
            return verdict
        if held_nc or held_cl:
            # the rapids of a stretch a dwell interrupted (see below): one stretch
            nc_gap, cl_gap = held_nc + nc_gap, held_cl + cl_gap
            held_nc, held_cl = [], []
        if nc_plain.__class__ is plain and cl_plain.__class__ is plain and not nc_gap \
                and compare.plain_feeds(nc_plain, cl_plain):
            # two straight feed moves alike, nothing between them: no rapid to check
            verdict.cuts += 1
            nc_from, cl_from = nc_plain[3], cl_plain[3]
            continue
        nc_cut = nc_side.event(nc_plain) if nc_plain is not None else None
        cl_cut = cl_side.event(cl_plain) if cl_plain is not None else None
        if isinstance(nc_cut, Dwell) and isinstance(cl_cut, Dwell):
            # a dwell moves nothing: the rapids before it and after it, up to the next
            # cut, are one stretch (a manual tool change, a dwell for the spindle, then
            # the CL's first rapid: the rapids of the post's tool change are judged
            # against where the CL goes next, not against an unknown height)
            verdict.cuts += 1
            problem = compare.cut(nc_cut, cl_cut, verdict.cuts)
            if problem is not None:
                verdict.divergence = Divergence(problem, cl_cut.origin, nc_cut.origin)
                return verdict
            held_nc, held_cl = nc_gap, cl_gap
            continue
        verdict.rapids += sum(isinstance(e, Rapid) for e in nc_gap)
        problem = compare.gap(nc_gap, cl_gap, cl_from, cl_cut)
        if problem is not None:
            verdict.divergence = Divergence(problem, _origin(cl_cut, cl_gap, cl_side),
                                            _origin(nc_cut, nc_gap, nc_side))
            return verdict
        if nc_cut is None and cl_cut is None:
            return verdict
        if nc_cut is None or cl_cut is None:
            if nc_cut is None:
                message = f"the NC program ends, the CL still has {_describe(cl_cut)}"
            else:
                message = f"{_describe(nc_cut)} that the CL does not have"
            verdict.divergence = Divergence(message, cl_cut.origin if cl_cut else cl_side.last,
                                            nc_cut.origin if nc_cut else nc_side.last)
            return verdict
        verdict.cuts += 1
        verdict.holes += isinstance(cl_cut, Hole)
        problem = compare.cut(nc_cut, cl_cut, verdict.cuts)
        if problem is not None:
            verdict.divergence = Divergence(problem, cl_cut.origin, nc_cut.origin)
            return verdict
        nc_from, cl_from = _after(nc_cut, nc_from), _after(cl_cut, cl_from)


def _origin(cut: Cut | None, gap: list[Rapid | NotFollowed], side: _Stream) -> Origin | None:
    if cut is not None:
        return cut.origin
    return gap[-1].origin if gap else side.last


def _after(cut: Cut, before: Point | None) -> Point | None:
    if isinstance(cut, Hole):
        return (cut.x, cut.y, cut.leave)
    if isinstance(cut, Dwell):
        return before
    return cut.end


def _distance(a: Point, b: Point) -> float:
    return math.dist([float(v) for v in a], [float(v) for v in b])  # type: ignore[arg-type]  # points of moves verify compares: known


def _arc_length(arc: ArcMove) -> float:
    normal = {"xy": 2, "zx": 1, "yz": 0}[arc.plane]
    rise = float(arc.end[normal]) - float(arc.start[normal])  # type: ignore[arg-type]  # an arc verify compares: known ends
    return math.hypot(arc.radius * arc.sweep, rise)


def _fmt(value: float | None) -> str:
    return "unknown" if value is None else f"{value:.3f}"


def _point(p: Point) -> str:
    return " ".join(f"{a}{_fmt(v)}" for a, v in zip("XYZ", p, strict=True))


def _describe(cut: Cut | None) -> str:
    if isinstance(cut, FeedMove):
        return f"a feed move to {_point(cut.end)}"
    if isinstance(cut, ArcMove):
        return f"a {'cw' if cut.clockwise else 'ccw'} arc to {_point(cut.end)}"
    if isinstance(cut, Hole):
        return f"a hole at X{cut.x:.3f} Y{cut.y:.3f}"
    if isinstance(cut, Dwell):
        return f"a dwell of {cut.seconds:g} s"
    return "nothing"


class _Comparison:
    def __init__(self, tolerance: _Tolerance) -> None:
        self.tolerance = tolerance
        self.hole_number = 0
        #: the NC and CL Tooling of the last cut whose cutting state agreed (both sides
        #: reuse a Tooling while it is unchanged: the same pair needs no comparing again)
        self.agreed: tuple[Tooling | None, Tooling | None] = (None, None)
        #: each axis's tolerance when it is fixed (no axis steps)
        fixed = tolerance.resolution + 1e-9
        self.fixed = (fixed, fixed, fixed) if tolerance.axis_steps is None else None

    def plain_feeds(self, nc: PlainFeed, cl: PlainFeed) -> bool:
        """Whether two plain feed moves agree: :meth:`cut`'s tests of two FeedMoves, in line.

        False sends them through :meth:`cut`, which says what differs.
        """
        fixed = self.fixed
        if fixed is not None:
            tx, ty, tz = fixed
        else:
            steps = self.tolerance.steps()
            if steps is None:
                tx = ty = tz = self.tolerance.resolution + 1e-9
            else:
                tx, ty, tz = steps[0] + 1e-9, steps[1] + 1e-9, steps[2] + 1e-9
        a, b = nc[2], cl[2]
        if abs(a[0] - b[0]) > tx or abs(a[1] - b[1]) > ty or abs(a[2] - b[2]) > tz:
            return False
        a, b = nc[3], cl[3]
        if abs(a[0] - b[0]) > tx or abs(a[1] - b[1]) > ty or abs(a[2] - b[2]) > tz:
            return False
        feed, cl_feed = nc[4], cl[4]
        if feed is None or feed <= 0 or cl_feed is None \
                or abs(feed - cl_feed) > FEED_TOLERANCE:
            return False
        agreed = self.agreed
        return nc[5] is agreed[0] and cl[5] is agreed[1]

    def differs(self, a: float | None, b: float | None, axis: int) -> bool:
        """Whether two values of an axis (0 X, 1 Y, 2 Z) differ by more than its tolerance."""
        if a is None or b is None:
            return a is not b
        return abs(a - b) > self.tolerance.of(axis) + 1e-9

    def points(self, what: str, nc: Point, cl: Point) -> str | None:
        if any(self.differs(a, b, axis) for axis, (a, b) in enumerate(zip(nc, cl, strict=True))):
            return f"{what} {_point(nc)}, CL says {_point(cl)}"
        return None

    def cut(self, nc: Cut, cl: Cut, number: int) -> str | None:
        if type(nc) is not type(cl):
            return f"{_describe(nc)}, CL says {_describe(cl)}"
        if isinstance(nc, Dwell):
            assert isinstance(cl, Dwell)
            if abs(nc.seconds - cl.seconds) > DWELL_TOLERANCE:
                return f"dwell {nc.seconds:g} s, CL says {cl.seconds:g} s"
            return None
        if isinstance(nc, Hole):
            assert isinstance(cl, Hole)
            return self.hole(nc, cl)
        assert isinstance(nc, (FeedMove, ArcMove)) and isinstance(cl, (FeedMove, ArcMove))
        kind = "feed move" if isinstance(nc, FeedMove) else "arc"
        problem = (self.plane(kind, nc.tooling, cl.tooling)
                   or self.points(f"{kind} starts at", nc.start, cl.start)
                   or self.points(f"{kind} ends at", nc.end, cl.end))
        if problem is None and isinstance(nc, ArcMove):
            assert isinstance(cl, ArcMove)
            problem = self.arc(nc, cl)
        if problem is None and isinstance(nc, FeedMove) and nc.path is not None:
            problem = self.rotary_path(nc)
        if problem is None and isinstance(nc, FeedMove) and isinstance(cl, FeedMove) \
                and nc.axis is not None and cl.axis is not None:
            problem = self.tool_axis(nc.axis, cl.axis)
        return problem or self.cutting_state(kind, nc.feed, cl.feed, nc.tooling, cl.tooling)

    def tool_axis(self, nc: tuple[float, float, float],
                  cl: tuple[float, float, float]) -> str | None:
        """The tool's axis on the part, where both sides know it: within 0.01 degree (the
        angles are written to 0.001 degree, a CAM's vector to 6 decimals)."""
        cosine = nc[0] * cl[0] + nc[1] * cl[1] + nc[2] * cl[2]
        if cosine < math.cos(math.radians(0.01)):
            return (f"tool axis on the part ({nc[0]:.4f}, {nc[1]:.4f}, {nc[2]:.4f}), CL says "
                    f"({cl[0]:.4f}, {cl[1]:.4f}, {cl[2]:.4f})")
        return None

    def rotary_path(self, nc: FeedMove) -> str | None:
        """A cut turning a rotary goes the short way round: its tip's path on the part is no
        longer than a half turn's arc over its chord (pi/2 times the straight line; a
        rotary cut of up to 180 degrees stays within it), or the table turned the long way
        (an angle unwound wrongly, a modulo axis written as unwound)."""
        assert nc.path is not None
        chord = _distance(nc.start, nc.end)
        if nc.path > chord * math.pi / 2 + self.tolerance.largest():
            return (f"feed move's tool tip travels {nc.path:.3f} mm on the part between "
                    f"points {chord:.3f} mm apart: a rotary turned the long way round")
        return None

    def arc(self, nc: ArcMove, cl: ArcMove) -> str | None:
        if nc.plane != cl.plane:
            return f"arc in the {nc.plane.upper()} plane, CL says {cl.plane.upper()}"
        if nc.clockwise != cl.clockwise:
            sense = {True: "clockwise", False: "counter-clockwise"}
            return f"arc {sense[nc.clockwise]}, CL says {sense[cl.clockwise]}"
        problem = self.points("arc centre", nc.centre, cl.centre)
        if problem is not None:
            return problem
        # with the same centre, end and sense, sweeps differ by whole turns or by rounding
        nc_len, cl_len = _arc_length(nc), _arc_length(cl)
        if abs(nc.sweep - cl.sweep) > math.pi:
            return (f"arc of {math.degrees(nc.sweep):.3f}° ({nc_len:.3f} mm), CL says "
                    f"{math.degrees(cl.sweep):.3f}° ({cl_len:.3f} mm)")
        return None

    def hole(self, nc: Hole, cl: Hole) -> str | None:
        self.hole_number += 1
        name = f"hole {self.hole_number}"
        problem = self.plane(name, nc.tooling, cl.tooling)
        if problem is not None:
            return problem
        checks = [("X", nc.x, cl.x, 0), ("Y", nc.y, cl.y, 1), ("R level Z", nc.r, cl.r, 2),
                  ("bottom Z", nc.bottom, cl.bottom, 2), ("peck", nc.peck, cl.peck, 2)]
        for label, a, b, axis in checks:
            if self.differs(a, b, axis):
                return f"{name}: {label}{_fmt(a)}, CL says {label}{_fmt(b)}"
        # a first peck unlike the later ones: what the control plunges first must be the
        # CL's (either side without one plunges first by its peck)
        nc_first = nc.first_peck if nc.first_peck is not None else nc.peck
        cl_first = cl.first_peck if cl.first_peck is not None else cl.peck
        if self.differs(nc_first, cl_first, 2):
            return f"{name}: first peck {_fmt(nc_first)}, CL says {_fmt(cl_first)}"
        nc_kind, cl_kind = _hole_kind(nc), _hole_kind(cl)
        if nc_kind != cl_kind:
            return f"{name}: a {nc_kind.replace('_', ' ')} cycle, CL says " \
                   f"{cl_kind.replace('_', ' ')}"
        if nc.direction != cl.direction:
            return f"{name}: spindle {nc.direction} going in, CL says {cl.direction}"
        problem = self.shift(name, nc, cl)
        if problem is not None:
            return problem
        if abs(nc.dwell - cl.dwell) > DWELL_TOLERANCE:
            return f"{name}: dwell {nc.dwell:g} s, CL says {cl.dwell:g} s"
        # the level the tool leaves the hole to is the CL's retract, in either direction: a
        # program that goes higher (G98 for G99, Q204 written absolute) does not do what the
        # CL says either, and the next rapid starts from another place
        if cl.leave is not None and nc.leave is None:
            return f"{name}: the tool is left at a level the program does not state (the " \
                   f"initial level after a tool change), CL says Z{cl.leave:.3f}"
        if cl.leave is not None and self.differs(nc.leave, cl.leave, 2) and (
                nc.via is None or self.differs(nc.via, cl.leave, 2)):
            where = "below" if nc.leave < cl.leave else "above"  # type: ignore[operator]  # nc.leave None returned above
            return f"{name}: the tool is left at Z{nc.leave:.3f}, {where} the CL's retract " \
                   f"Z{cl.leave:.3f}"
        return self.cutting_state(name, nc.feed, cl.feed, nc.tooling, cl.tooling)

    def shift(self, name: str, nc: Hole, cl: Hole) -> str | None:
        """A fine bore's shift off the wall, where both sides know it: too little and the
        edge marks the finished wall on its way out, too much and the bar's back hits the
        opposite wall (a control whose shift direction is a machine parameter states
        the amount only; one whose distance is its own, the direction only)."""
        if nc.shift is not None and cl.shift is not None \
                and self.differs(nc.shift, cl.shift, 0):
            return f"{name}: a fine bore shifting {nc.shift:.3f} mm off the wall, CL says " \
                   f"{cl.shift:.3f} mm"
        if nc.shift_direction is not None and cl.shift_direction is not None \
                and nc.shift_direction != cl.shift_direction:
            return f"{name}: a fine bore shifting {nc.shift_direction}, CL says " \
                   f"{cl.shift_direction}"
        return None

    def cutting_state(self, what: str, nc_feed: float | None, cl_feed: float | None,
                      nc: Tooling, cl: Tooling) -> str | None:
        if nc.spindle == "off" or not nc.speed:
            return f"{what} with the spindle stopped"
        if nc_feed is None or nc_feed <= 0:
            return f"{what} without a feed rate (F{_fmt(nc_feed)})"
        if cl_feed is None or abs(nc_feed - cl_feed) > FEED_TOLERANCE:
            return f"{what}: feed {nc_feed:.3f} mm/min, CL says {_fmt(cl_feed)}"
        if nc.tool != cl.tool:
            return f"{what} with tool {nc.tool}, CL says tool {cl.tool}"
        if nc.length_offset != cl.length_offset:
            active = "no length offset" if nc.length_offset is None \
                else f"length offset {nc.length_offset}"
            return f"{what} with {active}, CL says tool {cl.tool}'s own"
        if nc.work_offset != cl.work_offset:
            return f"{what} in work offset {nc.work_offset}, CL says {cl.work_offset}"
        problem = self.plane(what, nc, cl)
        if problem is not None:
            return problem
        if nc.spindle != cl.spindle:
            return f"{what}: spindle {nc.spindle}, CL says {cl.spindle}"
        if cl.speed is None or abs(nc.speed - cl.speed) > SPEED_TOLERANCE:
            return f"{what}: spindle {nc.speed:g} rpm, CL says {_fmt(cl.speed)}"
        self.agreed = (nc, cl)
        return None

    def plane(self, what: str, nc: Tooling, cl: Tooling) -> str | None:
        """The tilted plane a cut is made in (3+2): its positions are in the plane's frame on
        both sides, so the frames themselves must agree -- the tool axis, the plane's X
        axis and origin in the part frame -- for the tool tip to be where the CL says."""
        if nc.frame is cl.frame or (nc is self.agreed[0] and cl is self.agreed[1]):
            return None
        problem = frame_difference(nc.frame, cl.frame, self.tolerance.resolution)
        return None if problem is None else f"{what}: {problem}"

    def gap(self, nc: list[Rapid | NotFollowed], cl: list[Rapid | NotFollowed],
            cl_from: Point | None, cl_next: Cut | None) -> str | None:
        """The rapid rule of the module docstring, for one stretch between two cuts."""
        top = math.inf
        lows: list[float] = []
        sideways: list[float] = []
        ends: list[float] = []
        if cl_from is not None:
            ends.append(_z(cl_from[2]))
        nxt = _start_of(cl_next)
        if nxt is not None:
            ends.append(_z(nxt[2]))
        for event in cl:
            if isinstance(event, Rapid):
                lows.append(_z(event.end[2]))
                if _sideways(event):
                    sideways.append(min(_z(event.start[2]), _z(event.end[2])))
        lowest = min(lows + ends, default=top)
        floor = min(sideways) if sideways else max(ends, default=top)
        z_tolerance = self.tolerance.of(2)
        for event in nc:
            if not isinstance(event, Rapid) or event.end == (None, None, None):
                continue
            z = _z(event.end[2])
            if z < lowest - z_tolerance:
                return f"a rapid down to Z{z:.3f}, below the CL's lowest point Z{lowest:.3f} " \
                       f"between these cuts"
            if _sideways(event):
                level = min(_z(event.start[2]), z)
                if level < floor - z_tolerance:
                    return f"a rapid sideways at Z{level:.3f}, below the CL's Z{floor:.3f}"
        return None


def _hole_kind(hole: Hole) -> str:
    """A hole's kind as compared: a peck or chip-break cycle with no peck (the CL's
    ``peck: 0``, "no pecking") drills to the bottom in one plunge, as a drill does."""
    if hole.kind in ("peck", "chip_break") and hole.peck == 0:
        return "drill"
    return hole.kind


def _z(value: float | None) -> float:
    return math.inf if value is None else value


def _sideways(rapid: Rapid) -> bool:
    for a, b in zip(rapid.start[:2], rapid.end[:2], strict=True):
        if a is None or b is None:
            if a is not b:
                return True
        elif abs(a - b) > 1e-9:
            return True
    return False


def _start_of(cut: Cut | None) -> Point | None:
    if isinstance(cut, (FeedMove, ArcMove)):
        return cut.start
    if isinstance(cut, Hole):
        return cut.start
    return None


def first_divergence(nc: Iterable[Event], cl: Iterable[Event], resolution: float) -> str | None:
    """The first divergence as text, None when the NC does what the CL says (for tests)."""
    verdict = verify_events(nc, cl, resolution)
    return None if verdict.divergence is None else str(verdict.divergence)


__all__ = ["Divergence", "Verdict", "first_divergence", "verify_events"]

