"""A part-contour CL as the tool centre a control makes of it (cutter_compensation: control).

In the ``control`` mode the CL's path between a ``cutter_compensation`` left/right and
the next one off is the part contour: the control offsets it by the tool's radius (half
the CL tool diameter).  verify compares the NC program's replayed path with this one,
made by the same rules the control model follows
(:mod:`postdsl.check.controls.compensation`); moves outside compensation pass unchanged.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator

from postdsl.check.controls import events as ev
from postdsl.check.controls.base import ControlError, arc_geometry
from postdsl.check.controls.compensation import CompensatedPath, Move, Rules
from postdsl.cl.model import (
    ArcMove,
    CLCommand,
    CutterCompensation,
    LinearMove,
    PlainMove,
    RapidMove,
    ToolChange,
    plain_command,
)

_TOOLING = ev.Tooling(None, None)


def tool_centre(commands: Iterable[CLCommand | PlainMove], rules: Rules,
                cl_file: str) -> Iterator[CLCommand | PlainMove]:
    """``commands`` with every compensated stretch replaced by the tool centre's moves."""
    pos: list[float | None] = [None, None, None]
    diameter = 0.0
    feed: float | None = None
    waiting: str | None = None  # "left", "right" or "off": from the next move in XY
    path: CompensatedPath | None = None
    for command in commands:
        if command.__class__ is tuple:
            if waiting is None and path is None:
                x, y, z = command[2], command[3], command[4]
                pos = [pos[0] if x is None else x, pos[1] if y is None else y,
                       pos[2] if z is None else z]
                if len(command) == 6 and command[5] is not None:
                    feed = command[5]
                yield command
                continue
            command = plain_command(command)
        if isinstance(command, ToolChange):
            diameter = command.tool_diameter
        if isinstance(command, CutterCompensation):
            waiting = command.compensation_side
            if waiting == "off" and path is None:
                waiting = None
            continue  # the side is in the offset path: not compared again as a state
        if not isinstance(command, (RapidMove, LinearMove, ArcMove)):
            yield command
            continue
        move = _event(command, pos, feed, cl_file)
        pos = [command.x if command.x is not None else pos[0],
               command.y if command.y is not None else pos[1],
               command.z if command.z is not None else pos[2]]
        if not isinstance(command, RapidMove) and command.feed is not None:
            feed = command.feed
        if move is None or (waiting is None and path is None):
            yield command
            continue
        in_plane = isinstance(move, ev.ArcMove) or move.start[:2] != move.end[:2]
        if waiting in ("left", "right") and in_plane:
            if diameter <= 0:
                raise ControlError(move.origin, "cutter compensation on the part contour "
                                   "(cutter_compensation: control) with a tool of no "
                                   "diameter: the CL's tool_change gives none")
            path = CompensatedPath(waiting, diameter / 2, rules)
            waiting = None
            moves = path.move(move)
        elif waiting == "off" and in_plane and path is not None:
            moves = path.cancel(move)
            path = None
            waiting = None
        elif path is not None:
            moves = path.move(move)
        else:
            yield command
            continue
        yield from (_record(m) for m in moves)


def _event(command: RapidMove | LinearMove | ArcMove, pos: list[float | None],
           feed: float | None, cl_file: str) -> Move | None:
    start = (pos[0], pos[1], pos[2])
    end = (command.x if command.x is not None else pos[0],
           command.y if command.y is not None else pos[1],
           command.z if command.z is not None else pos[2])
    if None in start or None in end:
        return None
    origin = ev.Origin(command.line, command.name, cl_file)
    if isinstance(command, RapidMove):
        return ev.Rapid(origin, start, end)
    given = command.feed if command.feed is not None else feed
    if isinstance(command, LinearMove):
        return ev.FeedMove(origin, start, end, given, _TOOLING)
    centre = tuple(float(c if c is not None else s)  # type: ignore[arg-type]  # known
                   for c, s in zip((command.cx, command.cy, command.cz), start, strict=True))
    clockwise = command.arc_direction == "cw"
    sweep, radius = arc_geometry(origin, start, end, centre, clockwise,  # type: ignore[arg-type]  # known
                                 command.plane, radius_tolerance=1e9)
    return ev.ArcMove(origin, start, end, centre, clockwise, command.plane,  # type: ignore[arg-type]  # known
                      sweep, radius, given, _TOOLING)


def _record(move: Move) -> CLCommand:
    x, y, z = move.end
    line = move.origin.line
    if isinstance(move, ev.Rapid):
        return RapidMove(x=x, y=y, z=z, line=line)
    if isinstance(move, ev.FeedMove):
        return LinearMove(x=x, y=y, z=z, feed=move.feed, line=line)
    return ArcMove(x=x, y=y, z=z, cx=move.centre[0], cy=move.centre[1], cz=move.centre[2],
                   arc_direction="cw" if move.clockwise else "ccw", plane=move.plane,
                   feed=move.feed, line=line)
