"""Sinumerik 828D control model: ISO motion words plus Siemens drilling cycles.

From the SINUMERIK 828D Programming Manual (Fundamentals; Cycles 6FC5398-…):

- comments run from ``;`` to the end of the line (``postdsl.lang.control_syntax``);
- M2 and M30 end the program: the lines after them are not run;
- ``CR=`` gives an arc by its radius (negative: more than a half circle);
  ``G4 F`` dwells in seconds;
- the tool's offset (cutting edge D1) becomes active with the tool change: there
  is no G43, so the length offset in effect is that of the loaded tool;
- ``CYCLE81(RTP, RFP, SDIS, DP, DPR)``, ``CYCLE82(…, DTB)``,
  ``CYCLE83(RTP, RFP, SDIS, DP, DPR, FDEP, FDPR, DAM, DTB, DTS, FRF, VARI)``,
  ``CYCLE84(RTP, RFP, SDIS, DP, DPR, DTB, SDAC, MPIT, PIT, POSS, SST, SST1, AXN,
  PTAB, TECHNO, VARI, DAM, VRT)`` and ``CYCLE840(RTP, RFP, SDIS, DP, DPR, DTB, SDR,
  SDAC, ENC, MPIT, PIT)``: arguments by position, an empty one takes its default.
  The cycle goes at rapid to RFP + SDIS, drills to DP (or RFP - DPR) and leaves
  the tool at RTP.  CYCLE83 pecks FDPR (VARI=1 chip removal, 0 chip breaking),
  CYCLE84 taps rigidly at SST rpm with pitch PIT (its sign is the hand), pecking
  DAM when VARI is 1 or 2;
- ``CYCLE85(RTP, RFP, SDIS, DP, DPR, DTB, FFR, RFF)`` bores in at FFR, dwells DTB and
  leaves at RFF to RFP + SDIS (boring 1); ``CYCLE89(RTP, RFP, SDIS, DP, DPR, DTB)`` does
  so at the active F (boring 5); both then leave at rapid to RTP;
- ``CYCLE86(RTP, RFP, SDIS, DP, DPR, DTB, SDIR, RPA, RPO, RPAP, POSS)`` (boring 2) bores at
  F, dwells DTB, stops the spindle oriented at POSS, moves off the wall by RPA (X) and
  RPO (Y), leaves at rapid and turns the spindle on again in SDIR (3: M3, 4: M4);
- ``MCALL CYCLE…`` makes the cycle modal: it is called after **every block with
  motion** until a bare ``MCALL`` — a Z-only block drills again.  A ``CYCLE…``
  call without MCALL drills once, where the tool is.

CYCLE840, tapping with a compensating chuck (Cycles manual, "CYCLE840"): the tap goes
in turning as the spindle does before the call (M3 or M4: it must be on); SDR is the
direction it retracts in -- 3 (M3) or 4 (M4), the reverse of the direction going in,
or 0 for the automatic reversal, which needs the spindle's encoder (ENC=0; without it
the cycle stops with alarm 61202 "no spindle direction programmed"); an SDR equal to
the direction going in would pull the tap out turning the way it cut, and is refused.
SDAC is the spindle after the cycle, 3 4 or 5 (M3 M4 M5): the model sets the spindle
so (with SDR=0 it stays as it was), so the next hole of an ``MCALL`` goes in, and the
next cut runs, with it.  PIT, when given, is signed as the thread (+ right-hand).

Swivel plane (3+2; 828D/840D sl Cycles manual, "Swivel plane - CYCLE800"):
``CYCLE800(_FR, _TC, _ST, _MODE, _X0, _Y0, _Z0, _A, _B, _C, _X1, _Y1, _Z1, _DIR, _FR_I,
_DMODE)``.  _FR the retract before swivelling (0 none, 1 machine Z, 2 Z then X Y, 4 as far
as possible in the tool direction, 5 _FR_I in the tool direction), _TC the swivel data
record, _ST 0 a new plane (additive planes are refused), _MODE the swivel mode: the model
reads 57 only, axis by axis in the order X, Y, Z (bits 7-6 00; bits 5-0 11 10 01, Z Y X
for the third, second and first axis): turn about X by _A, then the new Y by _B, then
the newest Z by _C (``postdsl.frames``'s ``rotated_xyz``).  _X0 _Y0 _Z0 is the point
turned about, _X1 _Y1 _Z1 the zero in the turned frame: the plane's origin is
X0 + R X1.  _DIR -1 or +1 turns the rotary axes (the solution on the minus or plus side),
0 leaves them: the model refuses a cut while the head does not stand as the plane says.
``CYCLE800()`` removes the swivel frame and leaves the rotary axes where they are; a
CYCLE800 with all angles 0 and _DIR turns them back.  After each the tool's coordinates
in the new frame are unknown.

What these cycles can do beyond that (degression, MPIT thread sizes, a feed
factor for the first peck) is refused rather than guessed.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from typing import ClassVar

from postdsl import frames
from postdsl.check.controls.base import ControlError
from postdsl.check.controls.compensation import TRANSITION_ARC, Rules
from postdsl.check.controls.events import (
    ArcMove,
    Event,
    FeedMove,
    Hole,
    LengthOffsetChanged,
    Origin,
    Point,
    Rapid,
    SpindleChanged,
)
from postdsl.check.controls.iso import Block, IsoControl

_CALL = re.compile(r"(MCALL\b)?\s*(CYCLE\d+)\s*\(([^)]*)\)|MCALL\b|CR\s*=\s*([-+]?(?:\d+\.?\d*|"
                   r"\.\d+))")
_SWIVEL = re.compile(r"CYCLE800\s*\(([^)]*)\)")
#: a rotary's position with its way round (828D Programming Manual Fundamentals,
#: "Absolute dimensions for rotary axes (DC, ACP, ACN)"): A=DC(…) the shortest path,
#: ACP in the positive, ACN in the negative direction -- on a modulo rotary axis
_ROTARY_WAY = re.compile(r"([ABC])\s*=\s*(DC|ACP|ACN)\s*\(\s*([-+]?(?:\d+\.?\d*|\.\d+))\s*\)")
_WAYS = {"DC": "shortest", "ACP": "positive", "ACN": "negative"}
_SWIVEL_ARGUMENTS = ("_FR", "_TC", "_ST", "_MODE", "_X0", "_Y0", "_Z0", "_A", "_B", "_C",
                     "_X1", "_Y1", "_Z1", "_DIR", "_FR_I", "_DMODE")
_ARGUMENTS = {
    "CYCLE81": ("RTP", "RFP", "SDIS", "DP", "DPR"),
    "CYCLE82": ("RTP", "RFP", "SDIS", "DP", "DPR", "DTB"),
    "CYCLE83": ("RTP", "RFP", "SDIS", "DP", "DPR", "FDEP", "FDPR", "DAM", "DTB", "DTS",
                "FRF", "VARI"),
    "CYCLE85": ("RTP", "RFP", "SDIS", "DP", "DPR", "DTB", "FFR", "RFF"),
    "CYCLE89": ("RTP", "RFP", "SDIS", "DP", "DPR", "DTB"),
    "CYCLE86": ("RTP", "RFP", "SDIS", "DP", "DPR", "DTB", "SDIR", "RPA", "RPO", "RPAP", "POSS"),
    "CYCLE84": ("RTP", "RFP", "SDIS", "DP", "DPR", "DTB", "SDAC", "MPIT", "PIT", "POSS",
                "SST", "SST1", "AXN", "PTAB", "TECHNO", "VARI", "DAM", "VRT"),
    "CYCLE840": ("RTP", "RFP", "SDIS", "DP", "DPR", "DTB", "SDR", "SDAC", "ENC", "MPIT",
                 "PIT"),
}


#: the cycles' arguments that are lengths or feeds (read in inches after G700)
_LENGTH_ARGUMENTS = frozenset({"RTP", "RFP", "SDIS", "DP", "DPR", "FDEP", "FDPR", "DAM",
                               "PIT", "RPA", "RPO", "RPAP", "FFR", "RFF"})


class SinumerikControl(IsoControl):
    #: 828D Programming Manual Fundamentals, "Tool radius compensation (G40, G41, G42,
    #: OFFN)": G450 (a transition circle at outside corners) and NORM start-up are the
    #: defaults; D is the cutting edge of the active tool, whose radius it holds
    compensation_rules: ClassVar[Rules | None] = TRANSITION_ARC
    d_is_tool_number: ClassVar[bool] = False
    name = "sinumerik-828d"
    cycles: ClassVar[dict[str, tuple[str, str]]] = {}
    # G58/G59 are programmable axial offsets on Sinumerik, not settable ones: not read
    quiet_g = (IsoControl.quiet_g - {"43", "49", "98", "99", "80", "58", "59"}) | {"500", "71"}
    #: settable zero offsets (828D Programming Manual Fundamentals, "Settable zero offset
    #: (G54 to G57, G505 to G599)"): G54-G57 are the CL's 1-4, G505-G599 its 5-99
    work_offsets: ClassVar[dict[str, int]] = {
        **{str(n): n - 53 for n in range(54, 58)}, **{str(500 + n): n for n in range(5, 100)}}
    letters = frozenset("GMXYZIJKFSTDN")
    #: G700 inch, lengths and feeds (828D Programming Manual Fundamentals, "Inch or metric
    #: dimensions with G70/G700"); G710 mm.  G70 (geometry only, feeds still mm/min) is
    #: not read: G700 keeps a program in one unit
    inch_g = "700"
    metric_g = "710"
    length_letters = frozenset({"X", "Y", "Z", "I", "J", "K", "F", "CR"})
    parenthesis_comments = False
    dwell_by_f = True
    #: a G0/G1 line of N G X Y Z F is the core's straight move, unless a MCALL is active
    fast_path = True
    #: a plain absolute angle keeps a modulo axis within its turn (MD30455 bit 2 = 0, the
    #: standard: "target position > current position: move in positive traversing
    #: direction"; SINUMERIK 840D sl Function Manual Axes and spindles, R2 "Rotary axes",
    #: "Modulo 360 degrees"); DC/ACP/ACN say the way (:data:`_ROTARY_WAY`)
    modulo_way: ClassVar[str] = "within"

    def __init__(self) -> None:
        super().__init__()
        self.modal_call: tuple[str, dict[str, float | None]] | None = None
        #: the swivel frame's rotation and the rotation the rotary axes stand at
        self.rotation: frames.Matrix = frames.IDENTITY
        self.head: frames.Matrix = frames.IDENTITY

    #: CYCLE800 mode 57's _A _B _C: axis by axis, X then Y' then Z''
    tilted_plane_convention: ClassVar[str] = "rotated_xyz"

    def plain_move_allowed(self) -> bool:
        """A block with motion calls the modal cycle (MCALL): not a plain move then; a
        cut with the head off the plane is refused by the general reader."""
        return self.modal_call is None and self.head == self.rotation

    def execute(self, block: Block, origin: Origin) -> Iterator[Event]:
        swivel = block.extra.pop("swivel", False)
        if swivel is not False:
            yield from self.swivel(swivel, origin)  # type: ignore[arg-type]  # as read_extra stores it
        for event in super().execute(block, origin):
            if self.head != self.rotation and isinstance(event, (FeedMove, ArcMove, Hole)):
                raise ControlError(origin, "a cut with the rotary axes not turned to the swivel "
                                           "plane (CYCLE800 with _DIR 0, or CYCLE800() after a "
                                           "tilted plane): the tool axis is not the plane's")
            yield event

    def swivel(self, values: dict[str, float | str] | None, origin: Origin) -> Iterator[Event]:
        """CYCLE800: the swivel frame (None: ``CYCLE800()``)."""
        if values is None:
            self.rotation, self.frame = frames.IDENTITY, None
        else:
            def number(key: str) -> float:
                value = values.get(key, 0.0)
                if isinstance(value, str):
                    raise ControlError(origin, f"CYCLE800: {key} '{value}' is not a number")
                return value
            if number("_ST") != 0:
                raise ControlError(origin, "CYCLE800: _ST other than 0 (a new plane): an "
                                           "additive plane is not modelled")
            if number("_MODE") != 57:
                raise ControlError(origin, f"CYCLE800: swivel mode {number('_MODE'):g} is not "
                                           f"modelled (57: axis by axis X, Y, Z)")
            if number("_FR") not in (0, 1, 2, 4, 5):
                raise ControlError(origin, f"CYCLE800: retract mode _FR {number('_FR'):g}")
            turn = frames.frame_from_angles(
                self.tilted_plane_convention, (0, 0, 0),
                [number(key) for key in ("_A", "_B", "_C")])
            pivot = [number(key) for key in ("_X0", "_Y0", "_Z0")]
            zero = turn.to_part([number(key) for key in ("_X1", "_Y1", "_Z1")])
            scale = 25.4 if self.inch else 1.0  # the pivot and shift in the units in force
            origin_point = ((pivot[0] + zero[0]) * scale, (pivot[1] + zero[1]) * scale,
                            (pivot[2] + zero[2]) * scale)
            self.rotation = turn.rotation
            if number("_DIR") != 0:
                self.head = self.rotation
            untilted = self.rotation == frames.IDENTITY and origin_point == (0.0, 0.0, 0.0)
            self.frame = None if untilted else frames.Frame(origin_point, self.rotation)
        yield from self.lose_position(origin, (0, 1, 2))

    def read_extra(self, code: str, position: int, block: Block, origin: Origin) -> int:
        way = _ROTARY_WAY.match(code, position)
        if way is not None:
            letter = way.group(1)
            if letter not in self.letters or letter in block.values:
                raise ControlError(origin, f"'{way.group(0)}': not an axis of this machine, "
                                           f"or given twice")
            block.values[letter] = float(way.group(3))
            block.extra.setdefault("ways", {})[letter.lower()] = _WAYS[way.group(2)]  # type: ignore[index]  # the dict set here
            return way.end()
        swivel = _SWIVEL.match(code, position)
        if swivel is not None:
            block.extra["swivel"] = self.swivel_arguments(swivel.group(1), origin)
            return swivel.end()
        match = _CALL.match(code, position)
        if match is None:
            return position
        if match.group(4) is not None:
            block.values["CR"] = float(match.group(4))
        elif match.group(2) is not None:
            name = match.group(2)
            if name not in _ARGUMENTS:
                raise ControlError(origin, f"{name} is not a cycle the {self.name} model knows")
            block.extra["call"] = (name, self.arguments(name, match.group(3), origin),
                                   match.group(1) is not None)
        else:
            block.extra["call"] = None  # a bare MCALL: the modal call ends
        return match.end()

    @staticmethod
    def swivel_arguments(text: str, origin: Origin) -> dict[str, float | str] | None:
        """CYCLE800's arguments by name (None: the bare ``CYCLE800()``)."""
        if not text.strip():
            return None
        parts = [part.strip() for part in text.split(",")]
        if len(parts) > len(_SWIVEL_ARGUMENTS):
            raise ControlError(origin, f"CYCLE800 takes at most {len(_SWIVEL_ARGUMENTS)} "
                                       f"arguments, not {len(parts)}")
        values: dict[str, float | str] = {}
        for key, part in zip(_SWIVEL_ARGUMENTS, parts, strict=False):
            if not part:
                continue
            if part.startswith('"') and part.endswith('"') and len(part) >= 2:
                values[key] = part[1:-1]
                continue
            try:
                values[key] = float(part)
            except ValueError:
                raise ControlError(origin, f"CYCLE800: {key} '{part}' is not a number") \
                    from None
        return values

    @staticmethod
    def arguments(name: str, text: str, origin: Origin) -> dict[str, float | None]:
        names = _ARGUMENTS[name]
        parts = [p.strip() for p in text.split(",")]
        if len(parts) > len(names):
            raise ControlError(origin, f"{name} takes at most {len(names)} arguments, "
                                       f"not {len(parts)}")
        values: dict[str, float | None] = dict.fromkeys(names)
        for key, part in zip(names, parts, strict=False):
            if part:
                try:
                    values[key] = float(part)
                except ValueError:
                    raise ControlError(origin, f"{name}: {key} '{part}' is not a number") \
                        from None
        return values

    def after_tool_change(self, origin: Origin) -> Iterator[Event]:
        self.offset = self.tool
        yield LengthOffsetChanged(origin, self.offset)

    def modal_codes(self, block: Block, origin: Origin) -> Iterator[Event]:
        if "4" in block.g:
            block.values.pop("P", None)
        if "D" in block.values:
            self.offset = self.tool if block.values["D"] else None
        yield from super().modal_codes(block, origin)

    def motion_words(self, block: Block, origin: Origin) -> Iterator[Event]:
        call = block.extra.get("call", False)
        cr = block.values.pop("CR", None)
        if cr is not None:
            if self.motion not in ("2", "3") and not {"2", "3"} & set(block.g):
                raise ControlError(origin, "CR= outside an arc")
            block.values["R"] = cr
        moved = any(letter in block.values for letter in "XYZ")
        yield from super().motion_words(block, origin)
        if call is None:
            self.modal_call = None
        elif call:
            # what read_extra stored: (cycle name, its arguments, MCALL's modal flag)
            name: str
            arguments: dict[str, float | None]
            modal: bool
            name, arguments, modal = call  # type: ignore[misc]  # extra values are objects
            if modal:
                self.modal_call = (name, arguments)
            else:
                yield from self.drill(name, arguments, origin)
        elif moved and self.modal_call is not None:
            yield from self.drill(*self.modal_call, origin)

    def drill(self, name: str, a: dict[str, float | None], origin: Origin) -> Iterator[Event]:
        if self.inch:  # the cycle reads its lengths and feeds in the units in force
            a = {key: value * 25.4 if value is not None and key in _LENGTH_ARGUMENTS
                 else value for key, value in a.items()}
        x, y, z = self.pos
        if x is None or y is None:
            raise ControlError(origin, f"{name} at a position the program does not state")
        rtp, rfp, sdis = a["RTP"], a["RFP"], a["SDIS"]
        if rtp is None or rfp is None:
            raise ControlError(origin, f"{name} needs RTP and RFP")
        sdis = sdis or 0.0
        if a["DP"] is not None:
            bottom = a["DP"]
        elif a["DPR"] is not None:
            bottom = rfp - abs(a["DPR"])
        else:
            raise ControlError(origin, f"{name} needs DP or DPR")
        r = rfp + sdis
        # RTP may equal RFP + SDIS: compared as written, not after the inch factor's rounding
        if bottom > r + 1e-9 or rtp < r - 1e-9:
            raise ControlError(origin, f"{name}: the depth must be below RFP + SDIS "
                                       f"({r:g}) and RTP above it")
        dwell = a.get("DTB") or 0.0
        peck = 0.0
        direction = after = self.spindle  # after: the spindle once the cycle has run
        feed = self.feed_rate()
        tooling = self.tooling()
        if name in ("CYCLE81", "CYCLE82"):
            kind = "drill"
        elif name == "CYCLE85":
            # feed in at FFR, dwell DTB, out at RFF to RFP + SDIS, then rapid to RTP
            kind = "bore"
            feed_in, feed_out = a["FFR"], a["RFF"]
            if feed_in is None or feed_in <= 0:
                raise ControlError(origin, "CYCLE85 needs its feed FFR above 0")
            if feed_out != feed_in:
                raise ControlError(origin, "CYCLE85 with a retraction feed RFF other than "
                                           "FFR is not modelled")
            feed = feed_in
        elif name == "CYCLE86":
            # boring 2: at F in, dwell DTB, oriented stop at POSS, off the wall by RPA/RPO,
            # rapid out, back, and the spindle on again in SDIR (3: M3, 4: M4)
            kind = "fine_bore"
            sdir = a["SDIR"]
            if sdir not in (3.0, 4.0) or {3.0: "cw", 4.0: "ccw"}[sdir] != self.spindle:
                raise ControlError(origin, f"CYCLE86 SDIR {sdir} is not the spindle's "
                                           f"direction ({self.spindle}): 3 for M3, 4 for M4")
            if not (a["RPA"] or a["RPO"]) or (a["RPAP"] or 0.0) != 0.0:
                raise ControlError(origin, "CYCLE86 without a retraction off the wall (RPA or "
                                           "RPO), or with one along the tool (RPAP), is not "
                                           "modelled")
        elif name == "CYCLE89":
            kind = "bore"  # at F in, dwell DTB, at F out to RFP + SDIS, then rapid to RTP
        elif name == "CYCLE83":
            vari = a["VARI"] or 0.0
            kind = "peck" if vari == 1 else "chip_break"
            if a["FDPR"] is not None:
                peck = abs(a["FDPR"])
            elif a["FDEP"] is not None:
                peck = rfp - a["FDEP"]
            if peck <= 0:
                raise ControlError(origin, "CYCLE83 needs a first depth (FDEP or FDPR)")
            if a["DAM"] not in (None, 0.0):
                raise ControlError(origin, "CYCLE83 with a degression DAM is not modelled")
            if a["FRF"] not in (None, 1.0) or a["DTS"] not in (None, 0.0):
                raise ControlError(origin, "CYCLE83 with FRF or DTS is not modelled")
        elif name == "CYCLE84":
            kind = "rigid_tap"
            pitch, speed = a["PIT"], a["SST"]
            if pitch is None or a["MPIT"] is not None or speed is None:
                raise ControlError(origin, "CYCLE84 is modelled with PIT and SST only")
            direction = "cw" if pitch > 0 else "ccw"
            feed = abs(pitch) * speed
            tooling = type(tooling)(tooling.tool, tooling.length_offset, direction, speed)
            if (a["VARI"] or 0.0) in (1.0, 2.0):
                peck = a["DAM"] or 0.0
        else:
            kind = "tap"
            if self.spindle == "off":
                raise ControlError(origin, "CYCLE840 with the spindle off")
            pitch = a["PIT"]
            if pitch is not None and (pitch > 0) != (self.spindle == "cw"):
                raise ControlError(origin, f"CYCLE840 with pitch {pitch:g} and the spindle "
                                           f"{self.spindle}")
            after = self.tap_directions(a, origin)
        start: Point = (x, y, z)
        yield Rapid(origin, start, (x, y, r))
        self.pos = [x, y, rtp]
        shift, shift_direction = _shift(a) if kind == "fine_bore" else (None, None)
        yield Hole(origin, start, x, y, r, bottom, rtp, kind, direction, dwell, peck, feed,
                   tooling, shift=shift, shift_direction=shift_direction)
        if after != self.spindle:
            self.spindle = after
            yield SpindleChanged(origin, after, self.speed)

    def tap_directions(self, a: dict[str, float | None], origin: Origin) -> str:
        """CYCLE840's SDR and SDAC checked against the spindle going in; the spindle after."""
        going_in = self.spindle
        m_code = {"cw": 3, "ccw": 4}
        sdr, sdac, enc = a["SDR"] or 0.0, a["SDAC"], a["ENC"] or 0.0
        if sdr == 0:
            if enc != 0:
                raise ControlError(origin, "CYCLE840 SDR=0 (automatic reversal) without the "
                                           "encoder (ENC=1): the cycle stops, alarm 61202 (no "
                                           "spindle direction programmed)")
            return going_in  # reversed and restored by the cycle
        if sdr not in (3, 4):
            raise ControlError(origin, f"CYCLE840 SDR={sdr:g}: the retraction turns M3 or M4 "
                                       f"(3 or 4), or 0 for the automatic reversal")
        if sdr == m_code[going_in]:
            raise ControlError(origin, f"CYCLE840 SDR={sdr:g}: the tap retracts turning "
                                       f"M{sdr:g}, as it went in ({going_in}): it must retract "
                                       f"reversed (SDR={7 - sdr:g})")
        if sdac not in (3, 4, 5):
            shown = "empty" if sdac is None else f"{sdac:g}"
            raise ControlError(origin, f"CYCLE840 SDAC {shown}: the spindle after the cycle is "
                                       f"3, 4 or 5 (M3, M4, M5)")
        return {3: "cw", 4: "ccw", 5: "off"}[int(sdac)]


def _shift(a: dict[str, float | None]) -> tuple[float, str]:
    """CYCLE86's retraction off the wall as verify compares it with the CL's shift: RPA
    along the abscissa, RPO along the ordinate, each incremental and signed (the
    module's "boring 2"); both at once is a slant no CL direction names."""
    rpa, rpo = a["RPA"] or 0.0, a["RPO"] or 0.0
    if rpo == 0.0:
        return abs(rpa), "+x" if rpa > 0 else "-x"
    if rpa == 0.0:
        return abs(rpo), "+y" if rpo > 0 else "-y"
    return math.hypot(rpa, rpo), f"({rpa:+g}, {rpo:+g})"
