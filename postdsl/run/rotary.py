"""The CL's part-frame moves as the machine makes them: rotary angles, machine X Y Z, G93 times.

The CL gives the tool tip in the part frame, and the rotaries where the CAM chose them
(``a``/``b``/``c``) or the tool axis (``tool_i``/``tool_j``/``tool_k``, solved here
to angles).  A post's tables write machine words, so before the engine sees a move this
pass turns it into what the machine does: the angles (unwound as the post says), X Y Z
with the tip carried round the table's pivots (unless the control does it, ``tcp``), and
for a cut that turns a rotary the inverse time of the move (``inverse_time``, 1/min) from
the length of the path the tip cuts in the part -- the rotary's arc included.

A move the machine cannot make is refused at its CL line: a tool axis the rotaries do not
reach, an angle outside the limits, any rotary on a 3-axis post.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterable, Iterator

from postdsl.cl.model import (
    ArcMove,
    CLCommand,
    CycleHole,
    DrillSetup,
    LinearMove,
    MachineRetract,
    RapidMove,
    SafeRetract,
)
from postdsl.errors import CLError, Location
from postdsl.kinematics import (
    Kinematics,
    KinematicsError,
    is_identity,
    rezero_by,
    solve,
    tip_path_length,
    to_machine,
    unwind,
)

ROTARY = ("a", "b", "c")
TOOL_AXIS = ("tool_i", "tool_j", "tool_k")


def needs_rotaries(command: CLCommand) -> bool:
    """The move names a rotary angle or a tool axis (a 3-axis post must look at it)."""
    return any(getattr(command, name, None) is not None for name in ROTARY + TOOL_AXIS)


class RotaryPass:
    """One program's moves through the machine's rotaries (state: the last tip and angles)."""

    def __init__(self, kin: Kinematics, where: Callable[[CLCommand], Location]) -> None:
        self.kin = kin
        self.where = where
        self.tip: list[float | None] = [None, None, None]
        self.machine: list[float | None] = [None, None, None]
        self.angles: dict[str, float] = {name: 0.0 for name in kin.names}
        self.vector: tuple[float, float, float] = (0.0, 0.0, 1.0)
        self.feed: float | None = None
        #: whole turns (deg) a ``rezero`` post has taken off each axis's count so far: the
        #: angle written is the machine's angle less these
        self.rezeroed: dict[str, float] = {name: 0.0 for name in kin.names}
        #: the angles as the CL gave them, counted on (a modulo post's turn is their change)
        self.cl_angles: dict[str, float] = {}

    def run(self, commands: Iterable[CLCommand]) -> Iterator[CLCommand]:
        for command in commands:
            yield self.step(command)

    def refuse(self, command: CLCommand, message: str) -> CLError:
        return CLError(f"{command.name}: {message}", self.where(command))

    def step(self, command: CLCommand) -> CLCommand:
        kind = command.__class__
        if kind is RapidMove or kind is LinearMove:
            return self.move(command)
        turned = not is_identity(self.kin, self.angles)
        if kind is ArcMove:
            if turned:
                raise self.refuse(command, "an arc with the rotaries away from zero is not "
                                  "posted: the arc's plane turns with the part (give the arc "
                                  "as lines)")
            self._take_tip(command)
            self.machine = list(self.tip)
        elif kind is SafeRetract:
            self._take_tip(command)
            self.machine = list(self.tip)
        elif kind is MachineRetract:
            self.tip[2] = self.machine[2] = None
        elif isinstance(command, (DrillSetup, CycleHole)) and turned:
            raise self.refuse(command, "a drilling cycle with the rotaries away from zero is "
                              "not posted: its holes would be drilled along the machine's Z")
        return command

    def _take_tip(self, command: CLCommand) -> None:
        for index, name in enumerate("xyz"):
            value = getattr(command, name, None)
            if value is not None:
                self.tip[index] = value

    def move(self, command: CLCommand) -> CLCommand:
        kin = self.kin
        before = dict(self.angles)
        angles = self._angles(command)
        self._take_tip(command)
        tip = self.tip
        if is_identity(kin, angles):  # whole turns: exactly the CL's tip, no rounding noise
            machine: list[float | None] = list(tip)
        else:
            if tip[0] is None or tip[1] is None or tip[2] is None:
                raise self.refuse(command, "the tool tip must be known in X, Y and Z before "
                                  "the rotaries turn away from zero")
            try:
                # to 1e-9 mm: a rotation's rounding noise is no move of the axis
                machine = [round(v, 9) + 0.0
                           for v in to_machine(kin, (tip[0], tip[1], tip[2]), angles)]
            except KinematicsError as exc:
                raise self.refuse(command, str(exc)) from None
        # a word the CL did not give and the machine does not move stays out of the move,
        # as an axis left out of a 3-axis move ("'x' in given" of the posts)
        # (with the part turned, the CL's X Y Z are the part's, not the machine's words: a
        # machine word is given where it moves)
        changes: dict[str, object] = {"tool_i": None, "tool_j": None, "tool_k": None}
        turned = not is_identity(kin, angles) or not is_identity(kin, before)
        for index, name in enumerate("xyz"):
            was, now = self.machine[index], machine[index]
            kept = (getattr(command, name) is None or turned) and (
                was == now or (was is not None and now is not None and abs(was - now) < 1e-9))
            changes[name] = None if kept else machine[index]
        solved = any(getattr(command, name) is not None for name in TOOL_AXIS)
        for name in ROTARY:
            kept = getattr(command, name) is None and not solved \
                and angles.get(name) == before.get(name)
            changes[name] = angles[name] - self.rezeroed[name] \
                if name in angles and not kept else None
        if kin.wrap == "rezero":
            changes["rezero"] = self._rezero(changes, before)
        if isinstance(command, LinearMove):
            feed = command.feed
            if feed is not None:
                self.feed = feed
            changes["inverse_time"] = self._inverse_time(command, before, angles, machine)
        self.machine = machine
        self.angles = angles
        return dataclasses.replace(command, **changes)  # type: ignore[arg-type]  # the fields of a move: floats or None

    def _modulo_cut(self, command: CLCommand, name: str, value: float) -> None:
        """A cut may turn a modulo axis less than half a turn: the angle is written 0 to 360
        and the control takes the short way round (a roll-over setting, or the word the
        post writes for the shortest path), so a longer turn of the CL would be cut the
        other way round the part.  A rapid (an index) may turn any way: it ends at the
        same place."""
        turn = value - self.cl_angles.get(name, 0.0)
        self.cl_angles[name] = value
        if isinstance(command, LinearMove) and abs(turn) >= 180.0 - 1e-9:
            raise self.refuse(command, f"{name.upper()}{value:g}: a cut turning a modulo axis "
                              f"{abs(turn):g} degrees in one move; the control turns it the "
                              f"short way round (split the move, or rotary: wrap: unwound)")

    def _rezero(self, changes: dict[str, object], before: dict[str, float]) -> float | None:
        """The count the continuous axis is set to before this move (G92 A...), where the
        move would end a full turn or more from zero; its angle then written less the turns."""
        for axis in self.kin.axes:
            written = changes.get(axis.name)
            if not axis.continuous or not isinstance(written, (int, float)):
                continue
            by = rezero_by(written)
            if by == 0.0:
                return None
            self.rezeroed[axis.name] += by
            changes[axis.name] = written - by
            return before[axis.name] - self.rezeroed[axis.name]
        return None

    def _angles(self, command: CLCommand) -> dict[str, float]:
        kin = self.kin
        angles = dict(self.angles)
        given = {name: getattr(command, name) for name in ROTARY
                 if getattr(command, name, None) is not None}
        for name, value in given.items():
            axis = kin.axis(name)
            if axis is None:
                if abs(math.remainder(value, 360.0)) > 1e-9:
                    raise self.refuse(command, f"{name.upper()}{value:g}: this machine has no "
                                      f"{name.upper()} axis (machine: rotary_axes)")
                continue
            if axis.limits is not None and not (
                    axis.limits[0] - 1e-9 <= value <= axis.limits[1] + 1e-9):
                raise self.refuse(command, f"{name.upper()}{value:g} is outside the axis's "
                                  f"limits {axis.limits[0]:g} to {axis.limits[1]:g}")
            if axis.continuous and kin.wrap == "modulo":
                self._modulo_cut(command, name, value)
                value = value % 360.0
            angles[name] = value
        vector = [getattr(command, name, None) for name in TOOL_AXIS]
        if not given and any(v is not None for v in vector):
            self.vector = (
                self.vector[0] if vector[0] is None else float(vector[0]),
                self.vector[1] if vector[1] is None else float(vector[1]),
                self.vector[2] if vector[2] is None else float(vector[2]))
            try:
                solved = solve(kin, self.vector, angles)
            except KinematicsError as exc:
                raise self.refuse(command, str(exc)) from None
            for axis in kin.axes:
                turned = unwind(axis, solved[axis.name], angles[axis.name], kin.wrap)
                # the CL's count goes on by the turn made (a later a/b/c is a turn from it)
                self.cl_angles[axis.name] = self.cl_angles.get(axis.name, 0.0) \
                    + math.remainder(turned - angles[axis.name], 360.0)
                angles[axis.name] = turned
        return angles

    def _inverse_time(self, command: CLCommand, before: dict[str, float],
                      after: dict[str, float], end: list[float | None]) -> float | None:
        """1 / the move's minutes at the CL's feed along the tip's path in the part."""
        if all(abs(after[n] - before[n]) < 1e-9 for n in after):
            return None
        if self.kin.wrap == "modulo":  # the control turns a modulo axis the short way
            after = {axis.name: before[axis.name] + math.remainder(
                after[axis.name] - before[axis.name], 360.0) if axis.continuous
                else after[axis.name] for axis in self.kin.axes}
        start = self.machine
        if None in start or None in end:
            raise self.refuse(command, "a cut turning a rotary needs the tool's X, Y and Z "
                              "known before it (for its inverse-time feed)")
        length = tip_path_length(self.kin, start, before, end, after)  # type: ignore[arg-type]  # no None: checked above
        if length < 1e-6:
            raise self.refuse(command, "a cut turning a rotary with the tool tip on its axis "
                              "has no path in the part: no inverse-time feed can be given")
        if self.feed is None:
            return None  # the engine refuses the cut without a feed, at its line
        return self.feed / length


def refuse_rotaries(commands: Iterable[CLCommand],
                    where: Callable[[CLCommand], Location]) -> Iterator[CLCommand]:
    """A 3-axis post's input: a rotary angle or a tool axis other than +Z is refused."""
    for command in commands:
        if (command.__class__ is RapidMove or command.__class__ is LinearMove) \
                and needs_rotaries(command):
            for name in ROTARY:
                value = getattr(command, name)
                if value is not None and abs(math.remainder(value, 360.0)) > 1e-9:
                    raise CLError(f"{command.name}: {name.upper()}{value:g}: this post's "
                                  f"machine has no rotary axis (machine: rotary_axes)",
                                  where(command))
            i, j, k = (getattr(command, name) for name in TOOL_AXIS)
            if any(v is not None for v in (i, j, k)) and not (
                    abs(i or 0.0) < 1e-9 and abs(j or 0.0) < 1e-9 and (k or 0.0) > 0):
                raise CLError(f"{command.name}: tool axis ({i or 0:g}, {j or 0:g}, {k or 0:g}) "
                              f"is not +Z and this post's machine has no rotary axis "
                              f"(machine: rotary_axes)", where(command))
        yield command
