"""hmCNC control model: the hobby router of seed 001 (its own command code, not ISO).

From the thesis (seed 001, chapter 7.1 "Struktura příkazů v kódu" and 7.1.2
"Pravidla", chapter 8 "Algoritmus pro pohyb", the Delphi listing of the code
generator):

- one command a line, a capital letter and its parameters, each parameter's
  value **before** its letter, no spaces: ``L1234X5678Y4321Z`` moves to X 1234,
  Y 5678, Z 4321 motor steps; parameters in their order, none left out;
- the program starts with ``T`` (test the machine) and ends with ``S`` (stop);
  everything after ``//`` is a comment;
- ``L`` moves Z first, then X and Y together (Bresenham); every move runs at the
  one speed set in the control: there is no rapid and no feed word;
- ``R`` / ``E`` switch the spindle relay on / off; ``V<z>V`` drives Z up to the
  top switch, sets the position there, and goes down to the height z; ``W<ms>W``
  waits; ``Q`` drives to the home position; ``P`` asks for the position;
  ``A`` sets the position to zero (refused here: the program's coordinates would
  move under it).

The machine's settings are not in its code: steps per mm of each axis, the speed
of its moves and its spindle, the tool mounted by hand.  A post for it states the
ones it wrote the program for in comment lines the machine ignores and this model
reads: ``//steps/mm 400X400Y400Z``, ``//feed 600mm/min``, ``//spindle 20000rpm``,
``//tool 1``.  A program without the first three cannot be replayed.

Where a setting is read (a comment written from CL text -- a ``comment`` or an
operation's name -- must not be taken for one): steps per mm, speed and spindle
speed only in the program's start, the comment lines after ``T`` and before the
first command other than ``P`` and ``E`` (the post writes them there, before any CL
record but the program's name is written; the first of each there counts, so a CL
comment after them is a comment even in a program without ``V``); the tool only from the start up
to the first ``R`` (the tool is mounted by hand before the spindle runs: the last
``//tool`` line before it counts).  Anywhere else such a line is a comment.  A CL
comment of that form between the tool change and the first ``R`` is the one place
the model still reads as the tool (the post writes nothing there to tell them apart).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator
from typing import ClassVar

from postdsl.check.controls.base import ControlError, NCInput
from postdsl.check.controls.compensation import Rules
from postdsl.check.controls.events import (
    Dwell,
    Event,
    FeedMove,
    LengthOffsetChanged,
    Origin,
    Point,
    Rapid,
    SpindleChanged,
    ToolLoaded,
)
from postdsl.check.controls.iso import IsoControl, as_rapids

_NUMBER = r"(-?\d+(?:\.\d+)?)"
_SETTINGS = {
    "steps": re.compile(rf"steps/mm {_NUMBER}X{_NUMBER}Y{_NUMBER}Z\Z"),
    "feed": re.compile(rf"feed {_NUMBER}mm/min\Z"),
    "spindle": re.compile(rf"spindle {_NUMBER}rpm\Z"),
    "tool": re.compile(r"tool (\d+)\b"),
}
_COMMANDS = {
    "L": re.compile(r"L(-?\d+)X(-?\d+)Y(-?\d+)Z\Z"),
    "V": re.compile(r"V(-?\d+)V\Z"),
    "W": re.compile(r"W(\d+)W\Z"),
}


class HmcncControl(IsoControl):
    #: the thesis code has no cutter compensation
    compensation_rules: ClassVar[Rules | None] = None
    name = "hmcnc"

    def __init__(self) -> None:
        super().__init__()
        self.steps: tuple[float, float, float] | None = None
        self.move_feed: float | None = None
        self.spindle_speed: float | None = None
        self.started = False
        self.stopped = False
        self.last = Origin(0)
        #: the program's start (after T, before any command but P and E): settings are read
        self.in_start = False
        #: the spindle has been switched on (R): a ``//tool`` line is a comment from now
        self.spindle_started = False
        #: the settings the start has stated (the first of each counts)
        self.stated: set[str] = set()

    def axis_steps(self) -> tuple[float, float, float] | None:
        """One motor step of each axis, once ``//steps/mm`` has been read."""
        if self.steps is None:
            return None
        return (1 / self.steps[0], 1 / self.steps[1], 1 / self.steps[2])

    def replay(self, lines: Iterable[NCInput | str]) -> Iterator[Event]:
        yield from super().replay(lines)
        if not self.stopped:
            raise ControlError(self.last, "the program does not end with S (stop)")

    def run_line(self, line: NCInput) -> Iterator[Event]:
        origin = Origin(line.line, line.text)
        self.last = origin
        if line.declared == "rapid":
            yield from as_rapids(self.interpret(line, origin))
        elif line.declared is not None:
            raise ControlError(origin, "the hmCNC model reads every line (no verify: none "
                                       "or unknown)")
        else:
            yield from self.interpret(line, origin)

    def interpret(self, line: NCInput, origin: Origin) -> Iterator[Event]:
        command, _, comment = line.text.partition("//")
        if comment and self.started:
            yield from self.setting(comment.strip(), origin)
        if not command:
            return
        if command != command.strip() or " " in command or "\t" in command:
            raise ControlError(origin, "a command with a space (the rules: no spaces)")
        if self.stopped:
            raise ControlError(origin, "a command after S (stop)")
        if not self.started:
            if command != "T":
                raise ControlError(origin, "the program must start with T (test)")
            self.started = True
            self.in_start = True
            return
        if command not in ("P", "E"):
            self.in_start = False
        yield from self.command(command, origin)

    def setting(self, text: str, origin: Origin) -> Iterator[Event]:
        for key, pattern in _SETTINGS.items():
            match = pattern.match(text)
            if match is None:
                continue
            if (key == "tool" and self.spindle_started) or (key != "tool" and (
                    not self.in_start or key in self.stated)):
                return  # a comment that looks like a setting, where none is read
            self.stated.add(key)
            values = [float(v) for v in match.groups()]
            if key == "steps":
                if any(v <= 0 for v in values):
                    raise ControlError(origin, "steps per mm must be greater than 0")
                self.steps = (values[0], values[1], values[2])
            elif key == "feed":
                self.move_feed = values[0]
            elif key == "spindle":
                self.spindle_speed = values[0]
                self.speed = values[0]
            else:
                self.tool = self.offset = int(values[0])
                yield ToolLoaded(origin, self.tool)
                yield LengthOffsetChanged(origin, self.offset)

    def command(self, command: str, origin: Origin) -> Iterator[Event]:
        letter = command[0]
        if letter in "TP":
            if command != letter:
                raise ControlError(origin, f"{letter} has no parameters")
            return
        if letter == "S" and command == "S":
            self.stopped = True
            return
        if letter in "RE" and command == letter:
            if letter == "R" and self.spindle_speed is None:
                raise ControlError(origin, "R before the program states the spindle speed "
                                           "(//spindle …rpm)")
            self.spindle = "cw" if letter == "R" else "off"
            self.spindle_started = self.spindle_started or letter == "R"
            yield SpindleChanged(origin, self.spindle, self.speed)
            return
        if letter == "Q" and command == "Q":
            yield from self.lose_position(origin, (0, 1, 2))
            return
        if letter == "A":
            raise ControlError(origin, "A sets the position to zero: the coordinates of the "
                                       "rest of the program would move")
        pattern = _COMMANDS.get(letter)
        match = pattern.match(command) if pattern else None
        if match is None:
            raise ControlError(origin, f"'{command}' is not an hmCNC command")
        values = [int(v) for v in match.groups()]
        if letter == "W":
            yield Dwell(origin, values[0] / 1000.0)
            return
        steps = self.scale(origin)
        if letter == "V":
            start: Point = (self.pos[0], self.pos[1], self.pos[2])
            top: Point = (self.pos[0], self.pos[1], None)
            self.pos[2] = values[0] / steps[2]
            yield Rapid(origin, start, top)
            yield Rapid(origin, top, (self.pos[0], self.pos[1], self.pos[2]))
            return
        target = [value / scale for value, scale in zip(values, steps, strict=True)]
        yield from self.move(target, origin)

    def scale(self, origin: Origin) -> tuple[float, float, float]:
        if self.steps is None or self.move_feed is None:
            raise ControlError(origin, "a move before the program states its steps per mm "
                                       "and speed (//steps/mm …X…Y…Z, //feed …mm/min)")
        return self.steps

    def move(self, target: list[float], origin: Origin) -> Iterator[Event]:
        """L: Z first, then X and Y together (chapter 8)."""
        start = list(self.pos)
        if start[2] != target[2]:
            # start[0], start[1] are None while the position is unknown: straight_to takes
            # that case first (None in its own start), before it reads `end`
            yield from self.straight_to([start[0], start[1], target[2]], origin)  # type: ignore[list-item]
        if (start[0], start[1]) != (target[0], target[1]):
            yield from self.straight_to(target, origin)
        if start == target:
            yield from self.straight_to(target, origin)  # a move in place: nothing

    def straight_to(self, end: list[float], origin: Origin) -> Iterator[Event]:
        start: Point = (self.pos[0], self.pos[1], self.pos[2])
        if None in start:
            self.pos = list(end)
            yield Rapid(origin, start, (end[0], end[1], end[2]))
            return
        self.pos = list(end)
        yield FeedMove(origin, start, (end[0], end[1], end[2]), self.move_feed, self.tooling())
