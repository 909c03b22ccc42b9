"""What a control does with a program, as typed events with their NC line.

A control model (``postdsl.check.controls``) replays NC text and yields these; the
CL side (``postdsl.check.motion``) yields the same types from CL commands, so a
comparison, a backplot or a time estimate reads one vocabulary whichever side
the events come from.  Lengths are mm in program coordinates, feeds mm/min
(feed per revolution already multiplied by the spindle speed), times seconds.

An axis the program does not determine (after a reference return or a tool
change) is ``None``: the tool is somewhere the program does not say.
"""

from __future__ import annotations

from dataclasses import dataclass

from postdsl.frames import Frame

#: X, Y, Z; None where the position is not known from the program
Point = tuple[float | None, float | None, float | None]

UNKNOWN: Point = (None, None, None)


@dataclass(frozen=True, slots=True)
class Origin:
    """Where an event comes from: an NC line (1-based, with its text) or a CL record."""

    line: int
    text: str = ""
    file: str = ""

    def __str__(self) -> str:
        if self.file:
            return f"{self.file}:{self.line}"
        return f"NC line {self.line}: {self.text.strip()}"


@dataclass(frozen=True, slots=True)
class Tooling:
    """The state a cut happens in: which tool, which length offset, which spindle."""

    tool: int | None = None
    #: the length offset register in effect (H on ISO controls), None when none is active
    length_offset: int | None = None
    spindle: str = "off"  # "cw", "ccw" or "off"
    speed: float | None = None
    #: the work offset in force, as the CL numbers it (1: G54, the default)
    work_offset: int = 1
    #: the tilted working plane in force (3+2), in the part frame; None: the part frame.
    #: The positions of the cuts made in it are in its frame.
    frame: Frame | None = None


@dataclass(frozen=True, slots=True)
class Rapid:
    """A positioning move at rapid rate; ``end`` may hold None (reference point, tool change)."""

    origin: Origin
    start: Point
    end: Point


@dataclass(frozen=True, slots=True)
class FeedMove:
    """A straight cutting move."""

    origin: Origin
    start: Point
    end: Point
    feed: float | None
    tooling: Tooling
    #: the length of the tool tip's path on the part where a rotary turns during the move
    #: (not a straight line there); None: the straight line from start to end
    path: float | None = None
    #: the tool axis on the part at the end (unit X Y Z), where the side knows it: the CL
    #: where it gives one, the control model of a machine with rotaries
    axis: tuple[float, float, float] | None = None


@dataclass(frozen=True, slots=True)
class ArcMove:
    """A circular or helical cutting move; ``sweep`` is the angle turned, radians (> 0)."""

    origin: Origin
    start: Point
    end: Point
    centre: tuple[float, float, float]
    clockwise: bool
    plane: str  # "xy", "zx" or "yz"
    sweep: float
    radius: float
    feed: float | None
    tooling: Tooling


@dataclass(frozen=True, slots=True)
class Hole:
    """A drilled, tapped or bored hole, as one event.

    ``r`` is the level the feed starts at (the R plane: the hole's top plus the
    clearance), ``leave`` the level the tool is left at.  ``kind`` is one of
    ``drill`` (dwell allowed), ``peck`` (full retract), ``chip_break``, ``tap``
    (floating holder), ``rigid_tap``, ``bore``.  ``direction`` is the spindle
    direction while the tool goes in.
    """

    origin: Origin
    start: Point
    x: float
    y: float
    r: float
    bottom: float
    #: None when the tool returns to a level the program does not state (G98 after M6)
    leave: float | None
    kind: str
    direction: str
    dwell: float
    peck: float
    feed: float | None
    tooling: Tooling
    #: the depth of the first peck when it differs from the later ones (None: ``peck``);
    #: a control with a first infeed of its own (a first plunge, a degression) sets it
    first_peck: float | None = None
    #: a lower level the cycle itself ends at, when the model read a straight rapid up
    #: after it as the hole's leave (LinuxCNC's G33.1 ends where it began): the program
    #: leaves the hole to either level, and a CL retract at either is what it does
    via: float | None = None
    #: a fine bore's shift of the cutting edge off the wall at the bottom (mm), where the
    #: side knows it (None: not known -- Fanuc's G76 Q is the amount, its direction is a
    #: machine parameter); its direction ``+x -x +y -y``, or ``(dx, dy)`` for a slant
    shift: float | None = None
    shift_direction: str | None = None


@dataclass(frozen=True, slots=True)
class Dwell:
    origin: Origin
    seconds: float


@dataclass(frozen=True, slots=True)
class ToolLoaded:
    origin: Origin
    tool: int


@dataclass(frozen=True, slots=True)
class SpindleChanged:
    origin: Origin
    direction: str
    speed: float | None


@dataclass(frozen=True, slots=True)
class LengthOffsetChanged:
    origin: Origin
    register: int | None


@dataclass(frozen=True, slots=True)
class NotFollowed:
    """Lines the post declared as not to be interpreted (``verify:`` of its table).

    ``moves`` tells whether the tool may have moved: after such lines the
    position is unknown until the program states it again.
    """

    origin: Origin
    moves: bool


@dataclass(frozen=True, slots=True)
class ProgramEnded:
    """The control runs no more of the program (M2/M30, a Fanuc's end-of-record ``%``):
    the line that ends it, so a cut the CL still has is reported there."""

    origin: Origin


Event = (Rapid | FeedMove | ArcMove | Hole | Dwell | ToolLoaded | SpindleChanged
         | LengthOffsetChanged | NotFollowed | ProgramEnded)

#: the events that remove material: compared one by one
CUTS = (FeedMove, ArcMove, Hole, Dwell)
