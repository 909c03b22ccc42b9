"""What a CL program asks the machine to do, as the events a control model yields.

``postdsl verify`` compares these with the events of the posted program
replayed through a control model; both sides speak :mod:`postdsl.check.controls.events`.
The CL's own meaning (``postdsl/cl/model.py``): an axis a move leaves out
keeps its value; an arc's centre defaults to the start; a hole's feed starts at
``top + clearance``, reaches ``top - depth`` and leaves to ``retract``
(``top + clearance`` when omitted); the active length offset while cutting must
be the loaded tool's own, so it is expected equal to the tool number.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import Any

from postdsl import arcs, frames
from postdsl.check.controls import events as ev
from postdsl.check.controls.base import PlainFeed, arc_geometry
from postdsl.cl.holes import hole_moves
from postdsl.cl.model import (
    ArcMove,
    CLCommand,
    CustomCycle,
    CutterCompensation,
    CycleHole,
    DrillSetup,
    Dwell,
    FineBoring,
    LinearMove,
    OptionalStop,
    PlainMove,
    ProgramStop,
    RapidMove,
    SafeRetract,
    SpindleOff,
    SpindleOn,
    ToolChange,
    WorkOffset,
    WorkPlane,
    plain_command,
)
from postdsl.kinematics import Kinematics, tool_axis

#: drilling setup -> the kind of hole a control must make of it
HOLE_KINDS = {
    "single_peck": "drill", "deep_drill": "peck", "break_chip": "chip_break",
    "tapping": "tap", "tapping_ccw": "tap", "rigid_tapping": "rigid_tap",
    "rigid_tapping_ccw": "rigid_tap", "boring": "bore", "boring_spindle_stop": "bore_stop",
    "fine_boring": "fine_bore",
}


def cl_events(commands: Iterable[CLCommand | PlainMove], cl_file: str,
              declared: Callable[[CLCommand], str | None] = lambda command: None,
              expanded: Callable[[DrillSetup], bool] | None = None,
              chord_tolerance: float | None = None, *,
              plain: bool = False, stops: bool = False,
              kinematics: Kinematics | None = None) -> Iterator[ev.Event | PlainFeed]:
    """Events of a CL program, each with its CL file and line.

    ``commands`` may hold plain moves as a first pass kept them
    (:data:`~postdsl.cl.model.PlainMove`: the records the posting pass replays), read
    as their commands would be, without making one.  With ``plain`` a straight feed move
    between known points comes as a :data:`~postdsl.check.controls.base.PlainFeed` tuple, not
    a FeedMove: what the fast path of verify compares (the CL line, ``linear_move``).

    ``declared`` says what the post declared about a command's table
    (``verify: motion``): ``"none"``, ``"unknown"``, ``"rapid"`` or None (a rapid
    table's moves are compared as rapids whatever the control makes of them).  ``expanded`` says
    whether the post writes a drilling setup's holes as plain moves (``expand:
    true``, a control without canned cycles): those holes are expected as the
    moves of :func:`postdsl.cl.holes.hole_moves` (None: the post expands none).
    ``chord_tolerance``, when the
    post writes arcs as chords (``arc_move: {expand: true}``), expects each arc as
    the chords of :func:`postdsl.arcs.chords`.  With ``stops`` program and optional
    stops come as Stop events (the control model reads M0/M1).  ``kinematics`` (the
    machine's rotaries): where the CL gives angles (``a``/``b``/``c``) rather than a tool
    axis, the tool axis they set on the part, so that verify compares it with the
    machine's as it does a CAM's vector -- a wrong angle with the tip on the rotary's axis
    shows nowhere else.
    """
    if expanded is not None or chord_tolerance is not None:
        commands = _with_holes_expanded(commands, expanded or _never, chord_tolerance)
    pos: Sequence[float | None] = (None, None, None)
    tool: int | None = None
    spindle, speed = "off", None
    feed: float | None = None
    setup: DrillSetup | None = None

    made: list[Any] = [None, None]  # the last Tooling made and its values: reused while equal
    work_offset = 1
    frame: frames.Frame | None = None

    #: cutter compensation: the side in force, the side asked for ("off" to end it), and
    #: whether the move just made was in XY: the side asked for is in force after it (the
    #: move of the control's G41/G42/G40 block runs with the side before, as the model has it)
    comp: str | None = None
    comp_asked: str | None = None
    comp_turns = False

    def tooling(direction: str | None = None) -> ev.Tooling:
        key = (tool, direction or spindle, speed, work_offset, frame, comp)
        if made[0] != key:
            made[0], made[1] = key, ev.Tooling(tool, tool, key[1], speed, work_offset, frame,
                                               comp)
        return made[1]  # type: ignore[no-any-return]  # made[1] is a Tooling

    #: the tooling of a straight cut; None once the tool or the spindle changes
    cutting: ev.Tooling | None = None

    # a straight move whose table declares nothing is read from its fields (most of a CL)
    fields_read = {cls: declared(cls(line=0)) is None for cls in (RapidMove, LinearMove)}
    #: the CL's tool axis on the part once it gave one (tool_i/j/k; sticky), else None
    axis: tuple[float, float, float] | None = None
    #: the CL's angles so far (sticky), by the names of the machine's rotaries
    rotaries = kinematics.names if kinematics is not None else ()
    angles: dict[str, float] = {}
    for command in commands:
        if comp_turns:
            comp = None if comp_asked == "off" else comp_asked
            comp_asked, comp_turns, cutting = None, False, None
        cls = command.__class__
        if cls is tuple or cls is LinearMove or cls is RapidMove:
            if cls is not tuple and (command.tool_i is not None  # type: ignore[union-attr]  # a move
                                     or command.tool_j is not None  # type: ignore[union-attr]  # (as above)
                                     or command.tool_k is not None):  # type: ignore[union-attr]  # (as above)
                axis = _tool_axis(command, axis)  # type: ignore[arg-type]  # a RapidMove or LinearMove (cls, as above)
            if rotaries and kinematics is not None and cls is not tuple and any(
                    getattr(command, name) is not None for name in rotaries):
                for name in rotaries:
                    value = getattr(command, name)
                    if value is not None:
                        angles[name] = value
                axis = tool_axis(kinematics, angles)
            if cls is tuple:
                if len(command) == 6:  # type: ignore[arg-type]  # cls is tuple: a PlainMove
                    kind, line, x, y, z, given = command  # type: ignore[misc]  # (as above)
                else:
                    kind, line, x, y, z = command  # type: ignore[misc]  # (as above)
                    given = None
            else:
                # a LinearMove or RapidMove: mypy does not narrow through `cls`
                kind, line, x, y, z = (cls, command.line, command.x,  # type: ignore[union-attr]
                                       command.y, command.z)  # type: ignore[union-attr]  # (as above)
                given = command.feed if cls is LinearMove else None  # type: ignore[union-attr]  # (as above)
            if fields_read[kind]:
                start = (pos[0], pos[1], pos[2])
                pos = end = (start[0] if x is None else x, start[1] if y is None else y,
                             start[2] if z is None else z)
                if comp_asked is not None:
                    comp_turns = start[0] != end[0] or start[1] != end[1]
                if kind is RapidMove:
                    yield ev.Rapid(ev.Origin(line, "rapid_move", cl_file), start, end)
                    continue
                if given is not None:
                    feed = given
                if cutting is None:
                    cutting = tooling()
                if plain and None not in start and None not in end and axis is None:
                    yield (line, "linear_move", start, end, feed, cutting)  # type: ignore[misc]  # the plain fast path's tuple
                else:
                    yield ev.FeedMove(ev.Origin(line, "linear_move", cl_file), start, end,
                                      feed, cutting, None, axis)
                continue
            if cls is tuple:
                command = plain_command(command)  # type: ignore[arg-type]  # cls is tuple: a PlainMove
        # a plain move was made its CLCommand just above
        origin = ev.Origin(command.line, command.name, cl_file)  # type: ignore[union-attr]
        cutting = None
        start = (pos[0], pos[1], pos[2])
        motion = declared(command)  # type: ignore[arg-type]  # a CLCommand, as above
        if motion in ("none", "unknown"):
            if motion == "unknown":
                pos = [None, None, None]
            yield ev.NotFollowed(origin, motion == "unknown")
            continue
        if isinstance(command, ToolChange):
            tool = command.tool_number
            yield ev.ToolLoaded(origin, tool)
        elif isinstance(command, SpindleOn):
            spindle, speed = command.spindle, command.spindle_speed
            yield ev.SpindleChanged(origin, spindle, speed)
        elif isinstance(command, WorkOffset):  # another frame: where the tool is, unknown
            if command.work_offset_index != work_offset:
                work_offset = command.work_offset_index
                pos = [None, None, None]
                yield ev.Rapid(origin, start, (None, None, None))
        elif isinstance(command, WorkPlane):  # another frame: where the tool is, unknown
            frame = None if command.work_plane == "reset" else frames.frame_of(
                (command.origin_x, command.origin_y, command.origin_z),
                (command.x_axis_i, command.x_axis_j, command.x_axis_k),
                (command.z_axis_i, command.z_axis_j, command.z_axis_k))
            pos = [None, None, None]
            yield ev.Rapid(origin, start, (None, None, None))
        elif isinstance(command, SpindleOff):
            spindle = "off"
            yield ev.SpindleChanged(origin, spindle, speed)
        elif isinstance(command, SafeRetract):  # the CAM's "go safe": a rapid to its Z
            pos = [pos[0], pos[1], command.z if command.z is not None else pos[2]]
            yield ev.Rapid(origin, start, (pos[0], pos[1], pos[2]))
        elif isinstance(command, CutterCompensation):
            comp_asked = command.compensation_side
            if comp_asked == "off" and comp is None:
                comp_asked = None
        elif isinstance(command, (RapidMove, LinearMove, ArcMove)):
            pos = [v if v is not None else p
                   for v, p in zip((command.x, command.y, command.z), pos, strict=True)]
            end = (pos[0], pos[1], pos[2])
            if comp_asked is not None:
                comp_turns = isinstance(command, ArcMove) or start[0] != end[0] \
                    or start[1] != end[1]
            if isinstance(command, RapidMove):
                yield ev.Rapid(origin, start, end)
                continue
            feed = command.feed if command.feed is not None else feed
            if isinstance(command, LinearMove):
                yield ev.FeedMove(origin, start, end, feed, tooling(), None, axis)
                continue
            if None in start or None in end:
                yield ev.FeedMove(origin, start, end, feed, tooling())  # verify reports it
                continue
            given = (command.cx, command.cy, command.cz)
            centre = tuple(float(g if g is not None else s)  # type: ignore[arg-type]  # None in start returned above
                           for g, s in zip(given, start, strict=True))
            clockwise = command.arc_direction == "cw"
            a_end = (float(end[0]), float(end[1]), float(end[2]))  # type: ignore[arg-type]  # (as above)
            sweep, radius = arc_geometry(origin, start, a_end, centre,  # type: ignore[arg-type]  # (as above)
                                         clockwise, command.plane, radius_tolerance=1e9)
            yield ev.ArcMove(origin, start, a_end, centre, clockwise,  # type: ignore[arg-type]  # (as above)
                             command.plane, sweep, radius, feed, tooling())
        elif isinstance(command, Dwell):
            yield ev.Dwell(origin, command.dwell)
        elif stops and isinstance(command, (ProgramStop, OptionalStop)):
            yield ev.Stop(origin, isinstance(command, OptionalStop))
        elif isinstance(command, (DrillSetup, CycleHole)):
            if isinstance(command, DrillSetup):
                setup = command
                feed = command.feed if command.feed is not None else feed
            if setup is None:
                continue  # the reader refuses a hole outside a cycle
            top = setup.top if isinstance(command, DrillSetup) or command.top is None \
                else command.top
            x = command.x if command.x is not None else pos[0]
            y = command.y if command.y is not None else pos[1]
            if x is None or y is None:
                continue
            r = top + setup.clearance
            leave = setup.retract if setup.retract is not None else r
            kind = HOLE_KINDS[setup.name]
            direction = ("ccw" if setup.name.endswith("_ccw") else "cw") \
                if "tap" in kind else spindle
            yield ev.Rapid(origin, start, (x, y, start[2]))
            yield ev.Rapid(origin, (x, y, start[2]), (x, y, r))
            pos = [x, y, leave]
            yield ev.Hole(origin, (x, y, start[2]), x, y, r, top - setup.depth, leave, kind,
                          direction, setup.dwell, setup.peck, setup.feed if setup.feed is not None
                          else feed, tooling(direction if "tap" in kind else None),
                          setup.first_peck,
                          shift=setup.shift if isinstance(setup, FineBoring) else None,
                          shift_direction=setup.shift_direction
                          if isinstance(setup, FineBoring) else None)
        elif isinstance(command, CustomCycle):
            yield ev.NotFollowed(origin, True)  # a custom cycle's motion is the post's
            pos = [None, None, None]


def _tool_axis(move: RapidMove | LinearMove,
               last: tuple[float, float, float] | None) -> tuple[float, float, float]:
    """The move's tool axis (a component it leaves out keeps its value), of unit length."""
    before = last or (0.0, 0.0, 1.0)
    given = (move.tool_i, move.tool_j, move.tool_k)
    i, j, k = (b if g is None else g for g, b in zip(given, before, strict=True))
    size = math.sqrt(i * i + j * j + k * k) or 1.0
    return (i / size, j / size, k / size)


def _never(setup: DrillSetup) -> bool:
    return False


def _with_holes_expanded(commands: Iterable[CLCommand | PlainMove],
                         expanded: Callable[[DrillSetup], bool],
                         chord_tolerance: float | None) -> Iterator[CLCommand | PlainMove]:
    """The CL with the holes of expanded drilling setups replaced by their moves, and
    (with ``chord_tolerance``) its arcs by their chords."""
    pos: list[float | None] = [None, None, None]
    setup: DrillSetup | None = None
    feed: float | None = None
    for command in commands:
        if command.__class__ is tuple:  # a plain move: its position and feed
            x, y, z = command[2], command[3], command[4]
            if x is None or y is None or z is None:
                pos = [pos[0] if x is None else x, pos[1] if y is None else y,
                       pos[2] if z is None else z]
            else:
                pos = command[2:5]  # type: ignore[assignment]  # three floats, as a list reads them
            if len(command) == 6 and command[5] is not None:
                feed = command[5]
            yield command
            continue
        if isinstance(command, DrillSetup):
            setup = command
            feed = command.feed if command.feed is not None else feed
        if not isinstance(command, (DrillSetup, CycleHole)) or setup is None \
                or not expanded(setup):
            if isinstance(command, (RapidMove, LinearMove, ArcMove)):
                start = pos
                pos = [v if v is not None else p
                       for v, p in zip((command.x, command.y, command.z), pos, strict=True)]
                if isinstance(command, ArcMove) and chord_tolerance is not None \
                        and None not in start:
                    yield from _chords(command, start, pos, chord_tolerance)  # type: ignore[arg-type]  # None not in start
                    if command.feed is not None:
                        feed = command.feed
                    continue
                if not isinstance(command, RapidMove) and command.feed is not None:
                    feed = command.feed
            yield command
            continue
        top = setup.top if isinstance(command, DrillSetup) or command.top is None \
            else command.top
        x = command.x if command.x is not None else pos[0]
        y = command.y if command.y is not None else pos[1]
        if x is None or y is None:
            yield command  # the reader refuses a hole without a position
            continue
        leave = setup.retract if setup.retract is not None else top + setup.clearance
        yield from hole_moves(x=x, y=y, top=top, bottom=top - setup.depth,
                              clearance=setup.clearance, retract=leave, feed=feed,
                              peck=setup.peck, dwell=setup.dwell, cycle=setup.name,
                              start_z=pos[2], line=command.line,
                              first_peck=setup.first_peck)
        pos = [x, y, leave]


def _chords(arc: ArcMove, start: list[float], end: list[float],
            tolerance: float) -> Iterator[LinearMove]:
    centre = tuple(float(c if c is not None else s)
                   for c, s in zip((arc.cx, arc.cy, arc.cz), start, strict=True))
    for x, y, z in arcs.chords((start[0], start[1], start[2]), (end[0], end[1], end[2]),
                               centre, arc.arc_direction == "cw",  # type: ignore[arg-type]  # (as above)
                               arc.plane, tolerance):
        yield LinearMove(x=x, y=y, z=z, feed=arc.feed, line=arc.line)
