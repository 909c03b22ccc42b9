"""Program-level values from a first pass over the CL: tools, extents, machining time.

Headers print them before the first move is posted, so they must be known
up front.  Values the CAM system gave (e.g. its own time estimate in
``program_start``) win over computed ones.

The values are folded by one :class:`SummaryFolder`, fed either command objects
(:meth:`SummaryFolder.command`, what :func:`summarize` does) or, for the moves a
reader can check without building a command (a reader's first pass, see
:func:`postdsl.cl.readers.fold_commands`), the move's fields themselves
(:meth:`SummaryFolder.rapid`, :meth:`~SummaryFolder.linear`,
:meth:`~SummaryFolder.arc`).  A command object's move is folded by those same
methods, so each rule is written once and both ways give the same summary.

The extents and the time (:data:`MOVE_VALUES`) need every move folded, the tools'
values only a few records: a first pass for a post that reads none of the former
leaves the moves out (the values it cannot know are then not given at all).

The extents are the part's: a move made inside a tilted working plane (3+2, a
``work_plane`` record) is given in the plane's coordinates, and each of its points is
turned into the part frame before it widens them, so a header (Heidenhain's BLK FORM,
a min_/max_ comment) covers the part the planes machine, not a mix of frames.  Lengths,
and so the time, are the same in every frame.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from postdsl.cl.model import (
    ArcMove,
    CLCommand,
    CycleHole,
    DrillSetup,
    Dwell,
    LinearMove,
    ProgramStart,
    RapidMove,
    SafeRetract,
    SpindleOn,
    ToolChange,
    WorkPlane,
)
from postdsl.errors import CLError, Location
from postdsl.frames import Frame, axes_problem, frame_of
from postdsl.kinematics import Kinematics
from postdsl.run.rotary import RotaryPass, needs_rotaries

if TYPE_CHECKING:
    from postdsl.cl.source import CLSource, Progress

#: the summary values only the moves give; a first pass for a post that reads none of
#: them leaves the moves out (see :func:`summarize_source`)
MOVE_VALUES = frozenset({"min_x", "max_x", "min_y", "max_y", "min_z", "max_z",
                         "machining_time"})


@dataclass
class ProgramSummary:
    """What the header needs from the whole program, gathered by the first pass."""

    tools: list[int] = field(default_factory=list)
    #: each tool's first tool change, for tool lists and headers (type, diameter…)
    tool_records: dict[int, ToolChange] = field(default_factory=dict)
    extents: dict[str, float | None] = field(default_factory=dict)
    machining_time: float = 0.0
    #: every tool change's tool, in program order (a tool may come back), for next_tool
    tool_sequence: list[int] = field(default_factory=list)
    #: per tool change: the speed of the first spindle_on after it (None: none follows)
    tool_speeds: list[float | None] = field(default_factory=list)
    #: False when the moves were left out (:data:`MOVE_VALUES` unknown, so not given)
    moves: bool = True

    def values(self) -> dict[str, Any]:
        values: dict[str, Any] = {
            "tools": list(self.tools), "tool_count": len(self.tools),
            "next_tool": self.tool_sequence[0] if self.tool_sequence else None,
            "next_spindle_speed": None}
        if self.moves:
            values.update(self.extents, machining_time=self.machining_time)
        return values


def arc_length(start: tuple[float, float, float], end: tuple[float, float, float],
               centre: tuple[float, float, float], clockwise: bool, plane: str) -> float:
    """Length of a circular or helical arc (a full circle when start and end coincide)."""
    a, b, n = {"xy": (0, 1, 2), "zx": (2, 0, 1), "yz": (1, 2, 0)}[plane]
    r = math.hypot(start[a] - centre[a], start[b] - centre[b])
    a0 = math.atan2(start[b] - centre[b], start[a] - centre[a])
    a1 = math.atan2(end[b] - centre[b], end[a] - centre[a])
    sweep = (a0 - a1) if clockwise else (a1 - a0)
    sweep %= 2 * math.pi
    if sweep < 1e-9:
        sweep = 2 * math.pi
    return math.hypot(r * sweep, end[n] - start[n])


Number = float | int


class SummaryFolder:
    """The program summary, folded one record at a time.

    The time model: rapids at ``rapid_rate``, cuts at their feed, dwells as
    given, and each hole as rapid to the clearance plane, feed down and back
    up at the cycle feed (pecking retracts are ignored: an estimate, which
    the CAM's own figure overrides).

    On a machine with rotaries (``kinematics``) a move that turns one is timed as the
    machine makes it (:class:`~postdsl.run.rotary.RotaryPass`): a cut by the path the
    tool tip cuts on the part, the rotary's arc included, at the CL's feed (the time its
    G93 F says); an index (a rapid) by the longer of its X Y Z travel at ``rapid_rate``
    and its turn at the rotaries' ``rotary: rapid_rate`` -- where the machine declares no
    such rate, the turn itself is not counted.  A move the machine cannot make gets no
    time here: the posting pass refuses it at its line.

    The position is a tuple whose axes stay None until a record names them; the
    extents of an axis are first set by the record that first gives it, so once
    every axis is known (``_known``) a linear move skips every None test.  The move
    methods take a record's fields as read, None for a field it leaves out, and
    :meth:`command` hands them a move command's fields: the rules are these.
    """

    __slots__ = (
        "_cycle",
        "_feed",
        "_frame",
        "_given_time",
        "_high_x",
        "_high_y",
        "_high_z",
        "_known",
        "_low_x",
        "_low_y",
        "_low_z",
        "_pos",
        "_rapid_rate",
        "_rotary",
        "_seconds",
        "_summary",
        "moves",
    )

    def __init__(self, rapid_rate: float, moves: bool = True,
                 kinematics: Kinematics | None = None) -> None:
        #: False: only the records the tools' values come from are folded (tool changes,
        #: spindle starts); a reader need not hand this folder the moves
        self.moves = moves
        self._rapid_rate = rapid_rate
        self._summary = ProgramSummary()
        #: the machine's rotaries as the post makes their moves (None: a 3-axis machine)
        self._rotary: RotaryPass | None = RotaryPass(
            kinematics, lambda command: Location("<summary>", command.line)) \
            if kinematics is not None and kinematics.axes else None
        self._pos: tuple[Number | None, Number | None, Number | None] = (None, None, None)
        self._known = False
        self._feed: Number | None = None
        self._given_time: float | None = None
        self._seconds = 0.0
        self._cycle: DrillSetup | None = None
        #: the tilted working plane the moves are given in (None: the part frame)
        self._frame: Frame | None = None
        # the bounds: None until the first move that gives the axis
        self._low_x: Number | None = None
        self._low_y: Number | None = None
        self._low_z: Number | None = None
        self._high_x: Number | None = None
        self._high_y: Number | None = None
        self._high_z: Number | None = None

    # --- moves, from their fields ----------------------------------------------------

    def rapid(self, x: Number | None, y: Number | None, z: Number | None) -> None:
        """A rapid_move record's end point."""
        pos = self._pos
        target = (x if x is not None else pos[0], y if y is not None else pos[1],
                  z if z is not None else pos[2])
        self._travel(target, self._rapid_rate)
        self._reach(target)

    def linear(self, x: Number | None, y: Number | None, z: Number | None,
               feed: Number | None) -> None:
        """A linear_move record's end point and feed.

        Once every axis is known, :meth:`_travel` and :meth:`_reach` are written out
        here once more, for the millions of moves of a finishing program.
        """
        if feed is None:
            feed = self._feed
        else:
            self._feed = feed
        pos = self._pos
        if not self._known or self._frame is not None:
            target = (x if x is not None else pos[0], y if y is not None else pos[1],
                      z if z is not None else pos[2])
            self._travel(target, feed)
            self._reach(target)
            return
        if x is None:
            x = pos[0]
        if y is None:
            y = pos[1]
        if z is None:
            z = pos[2]
        target = self._pos = (x, y, z)
        if feed is not None and not feed <= 0:
            self._seconds += math.dist(pos, target) / feed * 60.0  # type: ignore[arg-type]  # pos is known (not None) here
        if x < self._low_x:  # type: ignore[operator]  # x, y, z and the bounds are known
            self._low_x = x
        if x > self._high_x:  # type: ignore[operator]  # (as above)
            self._high_x = x
        if y < self._low_y:  # type: ignore[operator]  # (as above)
            self._low_y = y
        if y > self._high_y:  # type: ignore[operator]  # (as above)
            self._high_y = y
        if z < self._low_z:  # type: ignore[operator]  # (as above)
            self._low_z = z
        if z > self._high_z:  # type: ignore[operator]  # (as above)
            self._high_z = z

    def arc(self, x: Number | None, y: Number | None, z: Number | None,
            cx: Number | None, cy: Number | None, cz: Number | None, clockwise: bool,
            plane: str, feed: Number | None) -> None:
        """An arc_move record: end point, centre (an axis left out: the start's), direction,
        plane and feed."""
        pos = self._pos
        if x is None:
            x = pos[0]
        if y is None:
            y = pos[1]
        if z is None:
            z = pos[2]
        if feed is None:
            feed = self._feed
        else:
            self._feed = feed
        target = (x, y, z)
        if None not in pos and None not in target:  # else no time: an end is unknown
            centre = (cx if cx is not None else pos[0], cy if cy is not None else pos[1],
                      cz if cz is not None else pos[2])
            length = arc_length(pos, target, centre, clockwise, plane)  # type: ignore[arg-type]  # pos is known here
            if feed:
                self._seconds += length / feed * 60.0
        self._reach(target)

    def _travel(self, target: tuple[Number | None, ...], rate: Number | None) -> None:
        """Time for a straight move to ``target`` at ``rate`` (none while an end is unknown)."""
        if rate is None or rate <= 0:
            return
        pos = self._pos
        if self._known or (None not in pos and None not in target):
            self._seconds += math.dist(pos, target) / rate * 60.0  # type: ignore[arg-type]  # None not in pos and target

    def _reach(self, target: tuple[Number | None, Number | None, Number | None]) -> None:
        """The tool is at ``target``: the new position, within the extents."""
        self._pos = target
        self._known = None not in target
        self._bound_point(target)

    def _bound_point(self, point: tuple[Number | None, Number | None, Number | None]) -> None:
        """Widen the extents to a point of the current frame, in the part frame.

        In a tilted plane every axis of the part mixes the plane's three: a point with
        an axis not known yet widens nothing there.
        """
        frame = self._frame
        if frame is not None:
            if None in point:
                return
            point = frame.to_part(point)  # type: ignore[arg-type]  # None not in point
        self._bound("x", point[0])
        self._bound("y", point[1])
        self._bound("z", point[2])

    def _plane(self, command: WorkPlane) -> None:
        """A work_plane record: the moves after it are in its frame.  The tool stays where
        it is: its position is restated in the new frame (for the time of the next move
        and an axis it leaves out).  A plane the engine refuses widens nothing here."""
        frame: Frame | None = None
        if command.work_plane != "reset":
            x_axis = (command.x_axis_i, command.x_axis_j, command.x_axis_k)
            z_axis = (command.z_axis_i, command.z_axis_j, command.z_axis_k)
            if axes_problem(x_axis, z_axis) is not None:
                return  # the engine refuses the record at its line
            frame = frame_of((command.origin_x, command.origin_y, command.origin_z),
                             x_axis, z_axis)
        pos = self._pos
        if None not in pos:
            old = self._frame
            part = old.to_part(pos) if old is not None else pos  # type: ignore[arg-type]  # None not in pos
            self._pos = _in_frame(frame, part)  # type: ignore[arg-type]  # (as above)
        else:
            self._pos = (None, None, None)
            self._known = False
        self._frame = frame

    def _bound(self, axis: str, value: Number | None) -> None:
        """Widen one axis's extents to ``value`` (None: the axis is not known yet)."""
        if value is None:
            return
        low, high = f"_low_{axis}", f"_high_{axis}"
        now = getattr(self, low)
        if now is None or value < now:
            setattr(self, low, value)
        now = getattr(self, high)
        if now is None or value > now:
            setattr(self, high, value)

    # --- every record, as a command ----------------------------------------------------

    def command(self, command: CLCommand) -> None:
        """Fold one CL command."""
        kind = type(command)
        if not self.moves and not isinstance(command, (ToolChange, SpindleOn)):
            return
        if self._rotary is not None and (kind is LinearMove or kind is RapidMove):
            self._rotary_move(command)  # type: ignore[arg-type]  # kind: a move
            return
        if self._rotary is not None:  # the pass follows the tip through arcs and retracts
            with contextlib.suppress(CLError):  # the posting pass refuses it, at its line
                self._rotary.step(command)
        if kind is LinearMove:
            # `kind is` narrows nothing for mypy: the attributes are the move's
            self.linear(command.x, command.y, command.z, command.feed)  # type: ignore[attr-defined]
        elif kind is RapidMove:
            self.rapid(command.x, command.y, command.z)  # type: ignore[attr-defined]  # kind is RapidMove
        elif kind is ArcMove:
            self.arc(command.x, command.y, command.z,  # type: ignore[attr-defined]  # kind is ArcMove
                     command.cx, command.cy, command.cz,  # type: ignore[attr-defined]  # (as above)
                     command.arc_direction == "cw", command.plane,  # type: ignore[attr-defined]  # (as above)
                     command.feed)  # type: ignore[attr-defined]  # (as above)
        elif isinstance(command, ProgramStart):
            self._given_time = command.machining_time
        elif isinstance(command, ToolChange):
            summary = self._summary
            summary.tool_records.setdefault(command.tool_number, command)
            summary.tool_sequence.append(command.tool_number)
            summary.tool_speeds.append(None)
            if command.tool_number not in summary.tools:
                summary.tools.append(command.tool_number)
        elif isinstance(command, SpindleOn):
            speeds = self._summary.tool_speeds
            if speeds and speeds[-1] is None:
                speeds[-1] = command.spindle_speed
        elif isinstance(command, Dwell):
            self._seconds += command.dwell
        elif isinstance(command, SafeRetract):
            # the CAM's "go safe" before the first tool: a height the tool reaches, so the
            # highest Z of the program (a post retracting to max_z at a tool change must
            # not go down from it), though not a position: the post may write it in
            # machine coordinates
            self._bound("z", command.z)
        elif isinstance(command, (DrillSetup, CycleHole)):
            self._hole(command)
        elif isinstance(command, WorkPlane):
            self._plane(command)

    def _rotary_move(self, command: LinearMove | RapidMove) -> None:
        """A move on a machine with rotaries, timed as the machine makes it."""
        rotary = self._rotary
        assert rotary is not None  # command() sends only a machine with rotaries here
        before = dict(rotary.angles)
        turns = needs_rotaries(command)
        made: CLCommand | None = None
        try:
            made = rotary.step(command)
        except CLError:
            made = None  # the posting pass refuses it, at its line
        seconds = self._seconds
        if isinstance(command, LinearMove):
            self.linear(command.x, command.y, command.z, command.feed)
            inverse = getattr(made, "inverse_time", None) if turns else None
            if inverse:
                self._seconds = seconds + 60.0 / inverse
            return
        self.rapid(command.x, command.y, command.z)
        rate = rotary.kin.rapid_rate
        if turns and rate:
            turn = max((abs(rotary.angles[n] - before[n]) for n in before), default=0.0)
            self._seconds = max(self._seconds, seconds + turn / rate * 60.0)

    def _hole(self, command: DrillSetup | CycleHole) -> None:
        """A drilling setup (its first hole) or a further hole of the open cycle."""
        if isinstance(command, DrillSetup):
            self._cycle = command
        cycle = self._cycle
        if cycle is None:
            return
        top = cycle.top if isinstance(command, DrillSetup) or command.top is None \
            else command.top
        pos = self._pos
        x = command.x if command.x is not None else pos[0]
        y = command.y if command.y is not None else pos[1]
        retract = cycle.retract if cycle.retract is not None else top + cycle.clearance
        bottom = top - cycle.depth
        self._travel((x, y, pos[2]), self._rapid_rate)
        cut_feed = cycle.feed if cycle.feed is not None else self._feed
        if cut_feed:
            self._seconds += 2 * (top + cycle.clearance - bottom) / cut_feed * 60.0
        self._seconds += cycle.dwell
        for level in (bottom, retract, top + cycle.clearance):
            self._bound_point((x, y, level))
        self._pos = (x, y, retract)
        self._known = None not in self._pos

    def summary(self) -> ProgramSummary:
        """The summary of the records folded so far."""
        summary = self._summary
        if not self.moves:
            summary.moves = False
            return summary
        summary.extents = {"min_x": self._low_x, "max_x": self._high_x,
                           "min_y": self._low_y, "max_y": self._high_y,
                           "min_z": self._low_z, "max_z": self._high_z}
        given = self._given_time
        summary.machining_time = given if given is not None else self._seconds
        return summary


def _in_frame(frame: Frame | None, point: tuple[float, float, float]) \
        -> tuple[float, float, float]:
    """A point of the part in a plane's coordinates (the rotation's transpose)."""
    if frame is None:
        return point
    r, o = frame.rotation, frame.origin
    d = (point[0] - o[0], point[1] - o[1], point[2] - o[2])
    return (r[0][0] * d[0] + r[1][0] * d[1] + r[2][0] * d[2],
            r[0][1] * d[0] + r[1][1] * d[1] + r[2][1] * d[2],
            r[0][2] * d[0] + r[1][2] * d[1] + r[2][2] * d[2])


def summarize(commands: Iterable[CLCommand], rapid_rate: float,
              kinematics: Kinematics | None = None) -> ProgramSummary:
    """One pass over the CL: tools in order of first use, extents, estimated time (s);
    see :class:`SummaryFolder` for the time model."""
    folder = SummaryFolder(rapid_rate, kinematics=kinematics)
    fold = folder.command
    for command in commands:
        fold(command)
    return folder.summary()


def summarize_source(source: CLSource, rapid_rate: float,
                     progress: Progress | None = None, *, moves: bool = True,
                     kinematics: Kinematics | None = None) -> ProgramSummary:
    """The first pass over a CL file: every reader check, and the summary
    :func:`summarize` makes of its commands, without making the common moves' commands.

    ``moves=False`` leaves the moves out of the summary (:data:`MOVE_VALUES` are then
    not given): for a post that reads none of those values, which need every move
    folded, while the tools' values need only a few records."""
    folder = SummaryFolder(rapid_rate, moves, kinematics)
    source.fold(folder, progress)
    return folder.summary()
