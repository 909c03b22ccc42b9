"""HEIDENHAIN TNC 640 control model: Klartext (conversational) programs, not ISO.

From the HEIDENHAIN TNC 640 User's Manual, Klartext Programming, and its Cycle
Programming manual (the cycles: :mod:`postdsl.check.controls.heidenhain_cycles`):

- a program is ``0 BEGIN PGM NAME MM`` ... ``N END PGM NAME MM`` (or ``INCH``: below);
  every block
  has a number, 0, 1, 2 ...; a line ending in ``~`` continues the block on the
  next line (the Q parameters of a cycle), which has no number of its own;
  ``;`` starts a comment, a block ``* - text`` is a structure item;
- ``BLK FORM 0.1 Z X Y Z`` (the tool axis and the blank's MIN point) and
  ``BLK FORM 0.2 X Y Z`` (its MAX point) right after BEGIN PGM define the
  workpiece blank for the control's graphics: no motion, MAX above MIN;
- ``L`` is a straight line to the coordinates given (the others keep their
  value; ``IX`` ``IY`` ``IZ`` are incremental), with the radius compensation
  ``R0``, ``RL`` or ``RR`` (modal until R0; started and ended on an L, the offset path
  as :mod:`postdsl.check.controls.compensation` makes it with the tool's radius); ``FMAX`` (or
  ``F MAX``) is rapid traverse in its block only, ``F`` a feed that stays in
  force until the next one;
- ``CC X Y`` sets the circle centre (it stays); ``C X Y DR+`` is an arc around
  it (DR+ the mathematically positive sense, counter-clockwise; DR- clockwise;
  an end on the start is a full circle).  The two axes CC names give the
  circle's plane, also one other than the working plane: ``CC X Z`` / ``C X Z``
  in ZX (reference axis Z: DR+ turns Z towards X), ``CC Y Z`` / ``C Y Z`` in YZ
  (reference axis Y), as ISO's G18/G19 counter-clockwise arcs; ``CP IPA IZ DR``
  a helix around a ``CC X Y``: ``IPA`` the angle turned, signed as DR, ``IZ``
  (or ``Z``) the height;
- ``TOOL CALL n Z S..`` loads tool n for the tool axis Z with its length from
  the tool table, at speed S; the change leaves the axes where the changer
  left them and the spindle stopped.  ``TOOL CALL Z S..`` without a number
  only changes the speed;
- miscellaneous functions act at the start of their block (M3 M4 M8) or at its
  end (M5 M9 M30 M99 M140); ``M140 MB MAX`` takes the tool up in its axis to
  the limit of the travel; ``M99`` calls the defined cycle at the block's end
  point, as does the block ``CYCL CALL``;
- ``CYCL DEF 9.0 DWELL TIME`` / ``CYCL DEF 9.1 DWELL t`` waits t seconds at once;
- touch probe cycles (``TCH PROBE 4xx``) move the probe as they find the part:
  the post must declare their lines (``verify: {motion: unknown}``).

Tilted working plane (3+2; TNC 640 User's Manual, "Tilting the working plane",
"Defining the working plane with spatial angles: PLANE SPATIAL", "Datum shift with
TRANS DATUM"):

- ``TRANS DATUM AXIS X Y Z`` shifts the datum, ``TRANS DATUM RESET`` removes the shift;
  the model reads them untilted only (a shift in a tilted plane acts in its frame);
- ``PLANE SPATIAL SPA SPB SPC`` tilts the plane about the shifted datum: about the
  machine's fixed X by SPA, then its fixed Y by SPB, then its fixed Z by SPC (all three
  always written: ``postdsl.frames``'s ``fixed_xyz``); ``PLANE RESET`` untilts it.
  ``TURN`` turns the rotary axes at once (with ``MB MAX`` the tool first goes up in its
  axis to the travel limit, ``FMAX`` or ``F`` the positioning feed); ``STAY`` leaves
  them where they are: the model refuses a cut while the head does not stand as the
  last PLANE says (``PLANE RESET STAY`` before a ``PLANE SPATIAL ... TURN`` is the
  usual way from one plane to the next).  ``SEQ+``/``SEQ-`` and ``COORD ROT``/
  ``TABLE ROT`` choose between the machine's solutions and are read as given.
After a PLANE or TRANS DATUM the tool's coordinates in the new frame are unknown.

Inch programs (``BEGIN PGM NAME INCH``): the unit of the whole program, named again by
``END PGM``.  Coordinates (X Y Z, IX IY IZ, CC, TRANS DATUM, BLK FORM) and the cycles'
lengths (Q200-Q205, Q212, Q239 the pitch per revolution, 203's Q256, Q257) are inches;
the feed F and the cycles' feeds (Q206, Q208) are in 1/10 inch/min -- F100 is 10 inch/min
(the TNC 640 Klartext user's manual, 34059x-07, "Units" of the program, as summarised in
a Klartext syntax reference; Autodesk's generic Heidenhain post writes the feed of an
inch program times 10 for the same reason).  Angles, seconds, S (rpm) and 209's Q256 (a
factor of the pitch) are as in mm.  The model converts all of it to the CL's mm.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Iterator
from typing import ClassVar

from postdsl import frames
from postdsl.check.controls import heidenhain_cycles as cycles
from postdsl.check.controls.base import PLANE_AXES, ControlError, NCInput, arc_geometry
from postdsl.check.controls.compensation import TRANSITION_ARC, Rules
from postdsl.check.controls.events import (
    ArcMove,
    Dwell,
    Event,
    FeedMove,
    Hole,
    LengthOffsetChanged,
    NotFollowed,
    Origin,
    Point,
    Rapid,
    SpindleChanged,
    Tooling,
    ToolLoaded,
)
from postdsl.check.controls.iso import IsoControl, as_rapids

_NUM = r"[+-]?(?:\d+\.?\d*|\.\d+)"
#: an INCH program's words in mm: lengths times 25.4, F (1/10 inch/min) times 2.54
_INCH_SCALE = {"X": 25.4, "Y": 25.4, "Z": 25.4, "IX": 25.4, "IY": 25.4, "IZ": 25.4,
               "F": 2.54}
_BLOCK = re.compile(r"(\d+) +(\S.*)\Z")
_PGM = re.compile(r"(BEGIN|END) PGM (\S+) (MM|INCH)\Z")
_TOOL_CALL = re.compile(rf"TOOL CALL(?: (\d+))? ([XYZ])(?: S({_NUM}))?\Z")
_CYCL_DEF = re.compile(r"CYCL DEF (\d+(?:\.\d)?)(?: (.*))?\Z")
_DWELL = re.compile(rf"DWELL ({_NUM})\Z")
_BLK_MIN = re.compile(rf"BLK FORM 0\.1 ([XYZ]) X({_NUM}) Y({_NUM}) Z({_NUM})\Z")
_BLK_MAX = re.compile(rf"BLK FORM 0\.2 X({_NUM}) Y({_NUM}) Z({_NUM})\Z")
_Q = re.compile(rf"Q(\d+) *= *({_NUM})\Z")
_WORD = re.compile(rf"(IPA|IX|IY|IZ|X|Y|Z|F|M|S)({_NUM})\Z")
#: a rotary axis word (L A+30 B+0 C+0): refused after a PLANE ... STAY, see read_words
_ROTARY_WORD = re.compile(rf"[ABC]{_NUM}\Z")
_START_M = {3, 4, 8}
#: the plane of a circle from the axes its CC names, in the order the plane's positive
#: sense (DR+) turns: X to Y, Z to X, Y to Z
_CIRCLE_PLANES = {"XY": "xy", "XZ": "zx", "YZ": "yz"}
#: M0 program stop, M1 optional stop: both also stop the spindle and switch coolant off
#: (TNC 640 User's Manual, "Overview of miscellaneous functions"), as M1 does when the
#: operator has optional stop on -- the model takes it on, so a program that cuts on after
#: M1 without M3/M4 again is refused either way
_STOP_M = {0, 1}
_PLANE = re.compile(rf"PLANE (?:SPATIAL SPA({_NUM}) SPB({_NUM}) SPC({_NUM})|(RESET))"
                    rf"(?: (TURN|STAY))?(?: (?:MB MAX|MB ?\+?\d+(?:\.\d*)?))?"
                    rf"(?: (?:FMAX|F{_NUM}))?(?: SEQ[+-])?(?: (?:COORD|TABLE) ROT)?\Z")
_DATUM = re.compile(rf"TRANS DATUM (?:AXIS X({_NUM}) Y({_NUM}) Z({_NUM})|(RESET))\Z")
_END_M = {5, 9, 30, 2, 99, 140} | _STOP_M


class HeidenhainControl(IsoControl):
    name = "heidenhain-tnc640"
    #: C's end may miss the circle by this much before the model refuses it (mm)
    radius_tolerance = 0.002

    def __init__(self) -> None:
        super().__init__()
        self.next_number = 0
        self.program: str | None = None
        self.ended = False
        self.m30 = False
        self.lines: list[str] = []
        self.first: NCInput | None = None
        self.centre: tuple[float | None, float | None, float | None] | None = None
        self.centre_plane = "xy"
        self.defined: cycles.CycleDef | None = None
        self.dwell_due = False
        #: BLK FORM: "open" right after BEGIN PGM, "min" after 0.1, "closed" after 0.2 or
        #: any other block
        self.blank = "open"
        self.blank_min: list[float] = []
        self.last = Origin(0)
        #: TRANS DATUM's shift, the rotation the last PLANE set, the head's rotation
        self.shift: tuple[float, float, float] = (0.0, 0.0, 0.0)
        self.rotation: frames.Matrix = frames.IDENTITY
        self.head: frames.Matrix = frames.IDENTITY
        #: the program's unit (BEGIN PGM): "MM", or "INCH" (lengths x 25.4, F x 2.54)
        self.unit = "MM"

    # --- lines and blocks ------------------------------------------------------------------

    def replay(self, lines: Iterable[NCInput | str]) -> Iterator[Event]:
        yield from super().replay(lines)
        if self.lines:
            raise ControlError(self.last, "the last block ends with '~' (continued, never ended)")
        if not self.ended:
            raise ControlError(self.last, "the program does not end with END PGM")

    def run_line(self, line: NCInput) -> Iterator[Event]:
        origin = Origin(line.line, line.text)
        self.last = origin
        text = line.text.rstrip()
        if self.ended:
            raise ControlError(origin, "a line after END PGM")
        if not self.lines:
            match = _BLOCK.match(text)
            if match is None:
                raise ControlError(origin, "a block without its number")
            if int(match.group(1)) != self.next_number:
                raise ControlError(origin, f"block number {match.group(1)}, the TNC's next is "
                                           f"{self.next_number}")
            self.next_number += 1
            self.first = line
            text = match.group(2)
        elif line.declared != self.first.declared:  # type: ignore[union-attr]  # set by the program's first line
            raise ControlError(origin, "a continued block written by two tables")
        if text.endswith("~"):
            self.lines.append(text[:-1].strip())
            return
        parts = self.lines + [text.strip()]
        self.lines = []
        if line.declared == "rapid":
            yield from as_rapids(self.block(parts, origin))
        elif line.declared is not None:
            if line.declared == "unknown":
                yield from self.lose_position(origin, (0, 1, 2))
            yield NotFollowed(origin, line.declared == "unknown")
        else:
            yield from self.block(parts, origin)

    def block(self, parts: list[str], origin: Origin) -> Iterator[Event]:
        head = parts[0]
        if self.program is None:
            yield from self.begin(head, parts, origin)
            return
        if head.startswith("BLK FORM") or self.blank == "min":
            if len(parts) > 1:
                raise ControlError(origin, "BLK FORM continued on another line")
            self.blank_form(head, origin)
            return
        if self.blank == "open":
            self.blank = "closed"
        if head.startswith(";") or head.startswith("*"):
            if len(parts) > 1:
                raise ControlError(origin, "a comment continued on another line")
            return
        if head.startswith("END PGM"):
            yield from self.end(head, origin)
            return
        if self.m30:
            raise ControlError(origin, "a block after M30 other than END PGM")
        if head.startswith("CYCL DEF"):
            yield from self.cycle_def(parts, origin)
            return
        if len(parts) > 1:
            raise ControlError(origin, "only a CYCL DEF continues on Q parameter lines")
        if head.startswith("PLANE") or head.startswith("TRANS DATUM"):
            yield from self.tilt(head, origin)
        elif head.startswith("TOOL CALL"):
            yield from self.tool_call(head, origin)
        elif head.startswith("TCH PROBE"):
            raise ControlError(origin, "a touch probe cycle moves the probe where the model "
                                       "cannot follow: the post must declare it (verify: "
                                       "{motion: unknown})")
        elif head.startswith("CYCL CALL"):
            yield from self.path(["CALL"] + head.split()[2:], origin)
        else:
            yield from self.path(head.split(), origin)

    def tilt(self, head: str, origin: Origin) -> Iterator[Event]:
        """PLANE SPATIAL / PLANE RESET and TRANS DATUM: the frame the coordinates are in."""
        if head.startswith("TRANS DATUM"):
            match = _DATUM.match(head)
            if match is None:
                raise ControlError(origin, f"cannot read '{head}' (TRANS DATUM AXIS X Y Z, "
                                           f"TRANS DATUM RESET)")
            if self.rotation != frames.IDENTITY:
                raise ControlError(origin, "TRANS DATUM in a tilted plane: the model reads a "
                                           "datum shift untilted only (PLANE RESET first)")
            self.shift = (0.0, 0.0, 0.0) if match.group(4) else \
                (self.mm(match.group(1)), self.mm(match.group(2)), self.mm(match.group(3)))
        else:
            match = _PLANE.match(head)
            if match is None:
                raise ControlError(origin, f"cannot read '{head}' (PLANE SPATIAL SPA SPB SPC "
                                           f"TURN|STAY [MB MAX] [FMAX], PLANE RESET)")
            if match.group(5) is None:
                raise ControlError(origin, "PLANE without TURN or STAY: whether the rotary "
                                           "axes turn is not stated")
            self.rotation = frames.IDENTITY if match.group(4) else frames.frame_from_angles(
                self.tilted_plane_convention, (0, 0, 0),
                [float(match.group(n)) for n in (1, 2, 3)]).rotation
            if match.group(5) == "TURN":
                self.head = self.rotation
        untilted = self.rotation == frames.IDENTITY and self.shift == (0.0, 0.0, 0.0)
        self.frame = None if untilted else frames.Frame(self.shift, self.rotation)
        yield from self.lose_position(origin, (0, 1, 2))

    #: PLANE SPATIAL's SPA SPB SPC: about the fixed X, then Y, then Z
    tilted_plane_convention = "fixed_xyz"

    def oriented(self, origin: Origin) -> None:
        """A cut needs the head where the last PLANE says (not left by STAY)."""
        if self.head != self.rotation:
            raise ControlError(origin, "a cut with the rotary axes not where the last PLANE "
                                       "says (STAY): the tool axis is not the plane's")

    def begin(self, head: str, parts: list[str], origin: Origin) -> Iterator[Event]:
        match = _PGM.match(head)
        if match is None or match.group(1) != "BEGIN" or len(parts) > 1:
            raise ControlError(origin, "the program does not start with BEGIN PGM NAME MM "
                                       "(or INCH)")
        self.program = match.group(2)
        self.unit = match.group(3)
        self.inch = self.unit == "INCH"
        return iter(())

    def blank_form(self, head: str, origin: Origin) -> None:
        """BLK FORM 0.1 (tool axis, MIN point) and 0.2 (MAX point): the workpiece blank
        for the control's graphics, right after BEGIN PGM; no motion."""
        if self.blank == "min":
            match = _BLK_MAX.match(head)
            if match is None:
                raise ControlError(origin, "BLK FORM 0.1 without its BLK FORM 0.2 X.. Y.. Z.. "
                                           "(the MAX point) in the next block")
            top = [self.mm(value) for value in match.groups()]
            if any(high <= low for low, high in zip(self.blank_min, top, strict=True)):
                raise ControlError(origin, "BLK FORM 0.2: the MAX point is not above the MIN "
                                           "point in every axis")
            self.blank = "closed"
            return
        match = _BLK_MIN.match(head)
        if self.blank != "open":
            raise ControlError(origin, "BLK FORM after other blocks: the blank comes right "
                                       "after BEGIN PGM")
        if match is None:
            raise ControlError(origin, f"cannot read '{head}' (BLK FORM 0.1 Z X.. Y.. Z..: "
                                       f"the tool axis and the MIN point)")
        if match.group(1) != "Z":
            raise ControlError(origin, f"BLK FORM 0.1 {match.group(1)}: the model knows the "
                                       f"tool axis Z")
        self.blank_min = [self.mm(value) for value in match.groups()[1:]]
        self.blank = "min"

    def end(self, head: str, origin: Origin) -> Iterator[Event]:
        match = _PGM.match(head)
        if match is None or match.group(1) != "END":
            raise ControlError(origin, "END PGM without its name and unit")
        if (match.group(2), match.group(3)) != (self.program, self.unit):
            raise ControlError(origin, f"END PGM {match.group(2)} {match.group(3)} does not "
                                       f"close BEGIN PGM {self.program} {self.unit}")
        self.ended = True
        return iter(())

    def mm(self, text: str) -> float:
        """A length as written, in the CL's mm."""
        return float(text) * (25.4 if self.inch else 1.0)

    # --- tools and cycles ------------------------------------------------------------------

    def tool_call(self, head: str, origin: Origin) -> Iterator[Event]:
        match = _TOOL_CALL.match(head)
        if match is None:
            raise ControlError(origin, f"cannot read '{head}' (TOOL CALL n Z S..)")
        number, axis, speed = match.groups()
        if axis != "Z":
            raise ControlError(origin, f"tool axis {axis}: the model knows the tool axis Z")
        if speed is not None:
            if float(speed) < 0:
                raise ControlError(origin, "a negative spindle speed")
            self.speed = float(speed)
        if number is None:
            if speed is None:
                raise ControlError(origin, "TOOL CALL without a tool number or a speed")
            if self.spindle != "off":
                yield SpindleChanged(origin, self.spindle, self.speed)
            return
        if self.spindle != "off":
            self.spindle = "off"
            yield SpindleChanged(origin, "off", self.speed)
        self.tool = self.offset = int(number)
        yield ToolLoaded(origin, self.tool)
        yield LengthOffsetChanged(origin, self.offset)
        yield from self.lose_position(origin, (0, 1, 2))

    def cycle_def(self, parts: list[str], origin: Origin) -> Iterator[Event]:
        match = _CYCL_DEF.match(parts[0])
        if match is None:
            raise ControlError(origin, f"cannot read '{parts[0]}'")
        number, name = match.group(1), (match.group(2) or "").strip()
        if number in ("9.0", "9.1"):
            if len(parts) > 1:
                raise ControlError(origin, "cycle 9 has no Q parameter lines")
            yield from self.dwell(number, name, origin)
            return
        if "." in number:
            raise ControlError(origin, f"cycle {number} is not one the model knows")
        if number == "247":
            yield from self.datum_setting(name, parts[1:], origin)
            return
        q: dict[int, float] = {}
        for part in parts[1:]:
            code = part.split(";", 1)[0].strip()
            qmatch = _Q.match(code)
            if qmatch is None:
                raise ControlError(origin, f"cannot read the cycle parameter '{part}'")
            key = int(qmatch.group(1))
            if key in q:
                raise ControlError(origin, f"Q{key} twice in one cycle")
            q[key] = float(qmatch.group(2))
        if self.inch:
            q = cycles.in_mm(int(number), q)
        self.defined = cycles.define(origin, int(number), name, q)

    def datum_setting(self, name: str, lines: list[str], origin: Origin) -> Iterator[Event]:
        """CYCL DEF 247 DATUM SETTING Q339=n: preset n of the preset table is in force at
        once (TNC 640 Cycle Programming, "DATUM SETTING (Cycle 247)": DEF-active); the
        CL's work offset n.  The tool stays: its coordinates in the new datum are unknown."""
        if name != "DATUM SETTING" or len(lines) != 1:
            raise ControlError(origin, "cycle 247 is DATUM SETTING with one line, Q339")
        qmatch = _Q.match(lines[0].split(";", 1)[0].strip())
        if qmatch is None or qmatch.group(1) != "339":
            raise ControlError(origin, "cycle 247 takes Q339, the preset number")
        preset = float(qmatch.group(2))
        if preset != int(preset) or preset < 0:
            raise ControlError(origin, f"Q339={preset:g} is not a preset table row")
        if int(preset) != self.work_offset:
            self.work_offset = int(preset)
            yield from self.lose_position(origin, (0, 1, 2))

    def dwell(self, number: str, name: str, origin: Origin) -> Iterator[Event]:
        if number == "9.0":
            if name != "DWELL TIME":
                raise ControlError(origin, "cycle 9.0 is DWELL TIME")
            self.dwell_due = True
            return
        match = _DWELL.match(name)
        if not self.dwell_due or match is None:
            raise ControlError(origin, "CYCL DEF 9.1 DWELL t comes right after 9.0 DWELL TIME")
        self.dwell_due = False
        seconds = float(match.group(1))
        if seconds < 0:
            raise ControlError(origin, "a negative dwell")
        yield Dwell(origin, seconds)

    # --- paths -----------------------------------------------------------------------------

    def path(self, words: list[str], origin: Origin) -> Iterator[Event]:
        """L, C, CP, CC, CYCL CALL and blocks of M functions alone."""
        if self.dwell_due:
            raise ControlError(origin, "CYCL DEF 9.0 without its 9.1 DWELL block")
        kind = words[0] if words[0] in ("L", "C", "CP", "CC", "CALL") else None
        values, flags, m = self.read_words(words[1:] if kind else words, origin)
        if kind is None and (values or flags - {"MB MAX"}):
            raise ControlError(origin, f"cannot read '{' '.join(words)}'")
        for code in m:
            if code in _START_M:
                yield from self.machine_function(code, origin)
        if "F" in values:
            if values["F"] <= 0:
                raise ControlError(origin, f"feed F{values['F']:g}")
            self.f = values.pop("F")
        if kind in ("L", "C", "CP", "CALL") and self.head != self.rotation \
                and (kind != "L" or "FMAX" not in flags or 99 in m):
            self.oriented(origin)
        self.radius_compensation(kind, flags, origin)
        if kind == "CC":
            yield from self.circle_centre(values, flags, origin)
        elif kind == "L":
            yield from self.compensate(self.line(values, flags, origin), origin)
        elif kind == "C":
            yield from self.compensate(self.arc_to(values, flags, origin), origin)
        elif kind == "CP":
            yield from self.compensate(self.helix(values, flags, origin), origin)
        elif values:
            raise ControlError(origin, "CYCL CALL takes no coordinates")
        if kind == "CALL":
            yield from self.call(origin)
        for code in m:
            if code not in _START_M:
                yield from self.machine_function(code, origin)
        if "MB MAX" in flags:
            if 140 not in m:
                raise ControlError(origin, "MB MAX without M140")
        elif 140 in m:
            raise ControlError(origin, "M140 without MB MAX (the retraction is not modelled)")

    #: User's Manual, "Tool radius compensation": a transition arc at outside corners, the
    #: first RL/RR line ending square to the contour; the radius is the called tool's
    compensation_rules: ClassVar[Rules | None] = TRANSITION_ARC
    d_is_tool_number: ClassVar[bool] = False

    def radius_compensation(self, kind: str | None, flags: set[str], origin: Origin) -> None:
        """RL/RR/R0 of an L: compensation starts or ends on it (modal until R0); a circle
        (C, CP) may restate the compensation in force, never change it."""
        word = next((w for w in ("R0", "RL", "RR") if w in flags), None)
        if word is None:
            return
        side = {"R0": None, "RL": "left", "RR": "right"}[word]
        current = self.comp_side if self.comp_waiting is None else (
            None if self.comp_waiting == "40" else "left" if self.comp_waiting == "41"
            else "right")
        if side == current:
            return
        if kind != "L":
            raise ControlError(origin, f"{word} on a circle: radius compensation starts and "
                                       f"ends on a straight line L")
        if side is not None and current is not None:
            raise ControlError(origin, f"{word} while the other radius compensation is on: "
                                       f"beyond the model (R0 first)")
        self.comp_register = self.tool
        self.comp_waiting = "40" if side is None else "41" if side == "left" else "42"

    def read_words(self, words: list[str], origin: Origin
                   ) -> tuple[dict[str, float], set[str], list[int]]:
        values: dict[str, float] = {}
        flags: set[str] = set()
        m: list[int] = []
        index = 0
        while index < len(words):
            word = words[index]
            pair = " ".join(words[index:index + 2])
            if pair in ("F MAX", "MB MAX"):
                flags.add("FMAX" if pair == "F MAX" else pair)
                index += 2
                continue
            index += 1
            if word in ("FMAX", "R0", "RL", "RR", "DR+", "DR-"):
                if word in flags or (word.startswith("DR") and flags & {"DR+", "DR-"}) or (
                        word[0] == "R" and flags & {"R0", "RL", "RR"}):
                    raise ControlError(origin, f"{word} twice in one block (or two radius "
                                               f"compensations)")
                flags.add(word)
                continue
            if self.head != self.rotation and _ROTARY_WORD.match(word):
                raise ControlError(origin, f"'{word}': the rotary axes positioned by the "
                                           f"program after PLANE ... STAY; whether these "
                                           f"angles put the tool on the plane's axis "
                                           f"depends on the machine's kinematics, which the "
                                           f"model does not verify: write PLANE ... TURN "
                                           f"(the control turns them to the plane itself)")
            match = _WORD.match(word)
            if match is None:
                raise ControlError(origin, f"'{word}' is not a word the TNC 640 model knows")
            letter, value = match.group(1), float(match.group(2))
            if self.inch and letter in _INCH_SCALE:
                value *= _INCH_SCALE[letter]
            if letter == "M":
                if value not in _START_M | _END_M:
                    raise ControlError(origin, f"M{value:g} is not a function the model knows")
                m.append(int(value))
            elif letter in values:
                raise ControlError(origin, f"two {letter} words in one block")
            else:
                values[letter] = value
        if "FMAX" in flags and "F" in values:
            raise ControlError(origin, "FMAX and F in one block")
        return values, flags, m

    def machine_function(self, code: int, origin: Origin) -> Iterator[Event]:
        if code in (3, 4):
            self.spindle = "cw" if code == 3 else "ccw"
            yield SpindleChanged(origin, self.spindle, self.speed)
        elif code == 5 or code in _STOP_M:
            self.spindle = "off"
            yield SpindleChanged(origin, "off", self.speed)
        elif code in (2, 30):
            self.m30 = True
        elif code == 99:
            yield from self.call(origin)
        elif code == 140:
            start: Point = (self.pos[0], self.pos[1], self.pos[2])
            self.pos[2] = None
            yield Rapid(origin, start, (self.pos[0], self.pos[1], None))

    def target(self, values: dict[str, float]) -> list[float | None]:  # type: ignore[override]  # an axis off an unknown position: None
        out = list(self.pos)
        for axis, letter in enumerate("XYZ"):
            if letter in values:
                out[axis] = values[letter]
            elif "I" + letter in values:
                current = self.pos[axis]
                out[axis] = None if current is None else current + values["I" + letter]
        return out

    def only(self, values: dict[str, float], allowed: str, what: str, origin: Origin) -> None:
        extra = sorted(set(values) - set(allowed.split()))
        if extra:
            raise ControlError(origin, f"{extra[0]} is not a word of {what}")

    def circle_centre(self, values: dict[str, float], flags: set[str],
                      origin: Origin) -> Iterator[Event]:
        axes = "".join(letter for letter in "XYZ" if letter in values)
        if flags or len(values) != 2 or axes not in _CIRCLE_PLANES:
            raise ControlError(origin, "CC takes the centre's two coordinates in the circle's "
                                       "plane (X Y, X Z or Y Z)")
        self.centre = (values.get("X"), values.get("Y"), values.get("Z"))
        self.centre_plane = _CIRCLE_PLANES[axes]
        return iter(())

    def line(self, values: dict[str, float], flags: set[str], origin: Origin) -> Iterator[Event]:
        self.only(values, "X Y Z IX IY IZ", "L", origin)
        if flags & {"DR+", "DR-"}:
            raise ControlError(origin, "DR is a word of C and CP, not of L")
        if not values:
            return
        start: Point = (self.pos[0], self.pos[1], self.pos[2])
        end = self.target(values)
        self.pos = end
        if "FMAX" in flags:
            yield Rapid(origin, start, (end[0], end[1], end[2]))
            return
        if self.f is None:
            raise ControlError(origin, "a feed move before any F")
        if None in start or None in end:
            raise ControlError(origin, "a feed move from or to a position the program does not "
                                       "state (after TOOL CALL or M140 MB MAX)")
        yield FeedMove(origin, start, (end[0], end[1], end[2]), self.f, self.tooling())

    def arc_start(self, flags: set[str], origin: Origin, what: str
                  ) -> tuple[tuple[float, float, float], bool]:
        if self.centre is None:
            raise ControlError(origin, f"{what} before any CC")
        if "FMAX" in flags:
            raise ControlError(origin, f"{what} at FMAX")
        if not flags & {"DR+", "DR-"}:
            raise ControlError(origin, f"{what} without its direction DR+ or DR-")
        if self.f is None:
            raise ControlError(origin, f"{what} before any F")
        if None in self.pos:
            raise ControlError(origin, f"{what} from a position the program does not state")
        start = (float(self.pos[0]), float(self.pos[1]), float(self.pos[2]))  # type: ignore[arg-type]  # None refused above
        return start, "DR-" in flags

    def arc_to(self, values: dict[str, float], flags: set[str], origin: Origin) -> Iterator[Event]:
        plane = self.centre_plane
        allowed = {"xy": "X Y", "zx": "X Z", "yz": "Y Z"}[plane]
        self.only(values, allowed, f"C around a CC in the {plane.upper()} plane (a helix is "
                                   f"CP)", origin)
        start, clockwise = self.arc_start(flags, origin, "C")
        normal = PLANE_AXES[plane][2]
        target = self.target(values)
        end_list = [float(v) for v in target]  # type: ignore[arg-type]  # known: arc_start refused None
        end_list[normal] = start[normal]
        end = (end_list[0], end_list[1], end_list[2])
        centre_list = [float(c) if c is not None else start[axis]
                       for axis, c in enumerate(self.centre)]  # type: ignore[arg-type]  # (as above)
        centre = (centre_list[0], centre_list[1], centre_list[2])
        sweep, radius = arc_geometry(origin, start, end, centre, clockwise, plane,
                                     self.radius_tolerance)
        self.pos = list(end)
        yield ArcMove(origin, start, end, centre, clockwise, plane, sweep, radius, self.f,
                      self.tooling())

    def helix(self, values: dict[str, float], flags: set[str], origin: Origin) -> Iterator[Event]:
        self.only(values, "IPA Z IZ", "CP (IPA and the height)", origin)
        start, clockwise = self.arc_start(flags, origin, "CP")
        if self.centre_plane != "xy":
            raise ControlError(origin, "CP around a CC in the "
                                       f"{self.centre_plane.upper()} plane: the model knows "
                                       "helices around the tool axis Z (CC X Y)")
        if "IPA" not in values:
            raise ControlError(origin, "CP without IPA (the angle turned)")
        angle = values["IPA"]
        if angle == 0 or (angle < 0) != clockwise:
            raise ControlError(origin, f"IPA{angle:+g} with {'DR-' if clockwise else 'DR+'}: "
                                       f"the angle's sign is the direction's")
        cx, cy = float(self.centre[0]), float(self.centre[1])  # type: ignore[arg-type,index]  # a CC was given, checked above
        radius = math.hypot(start[0] - cx, start[1] - cy)
        if radius <= 0:
            raise ControlError(origin, "the helix has radius 0")
        a1 = math.atan2(start[1] - cy, start[0] - cx) + math.radians(angle)
        z = self.target(values)[2]
        end = (cx + radius * math.cos(a1), cy + radius * math.sin(a1), float(z))  # type: ignore[arg-type]  # known: arc_start refused None
        self.pos = list(end)
        yield ArcMove(origin, start, end, (cx, cy, start[2]), clockwise, "xy",
                      math.radians(abs(angle)), radius, self.f, self.tooling())

    def call(self, origin: Origin) -> Iterator[Event]:
        if self.defined is None:
            raise ControlError(origin, "a cycle call (M99) without a CYCL DEF")
        hole = cycles.shape(origin, self.defined)
        x, y, z = self.pos
        if x is None or y is None:
            raise ControlError(origin, "a cycle called at an X Y the program does not state")
        direction, feed = self.spindle, hole.feed
        if hole.kind == "tap" and self.spindle == "off":
            raise ControlError(origin, "cycle 206 with the spindle stopped (M3 right-hand, M4 "
                                       "left-hand)")
        if hole.kind == "rigid_tap":
            direction = "cw" if hole.pitch > 0 else "ccw"
            if not self.speed:
                raise ControlError(origin, "a rigid tap without a spindle speed")
            feed = abs(hole.pitch) * self.speed
        tooling = Tooling(self.tool, self.offset, direction, self.speed, self.work_offset,
                          self.frame) \
            if hole.kind == "rigid_tap" else self.tooling()
        yield Rapid(origin, (x, y, z), (x, y, hole.r))
        self.pos = [x, y, hole.leave]
        yield Hole(origin, (x, y, z), x, y, hole.r, hole.bottom, hole.leave, hole.kind,
                   direction, hole.dwell, hole.peck, feed, tooling,
                   shift_direction=hole.shift_direction)
