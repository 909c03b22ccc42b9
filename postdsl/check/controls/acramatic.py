"""Siemens (Cincinnati) Acramatic 2100 control model: ISO motion, the 2100's drilling cycles.

From the 2100 drilling-cycle chapter as seed 002 (chapter 3, and section 7.1,
the program the thesis ran on the machine) describes it:

- comments run from ``;`` to the end of the line; a lone ``:`` carries no word; M2 and
  M30 end the program (the thesis program ends with M2): the lines after them are not run;
  ``G4 F`` dwells F seconds;
- control parameters are set by lines ``[$CYCLE_PARAMS(2)NAME] = value``:
  ``GAGE_HT_MM`` is the clearance above R where the feed starts and where the
  tool returns to, ``G82_DWELL`` and ``G84_DWELL`` the dwell in seconds;
- ``G81``/``G82 X Y Z R`` drill, ``G83 … J K`` pecks K (J11 chip breaking, J13
  full retract; J1-J3 vary the peck and are refused), ``G84 … J`` taps with a
  floating holder, ``G84.1 … J K P`` taps rigidly pecking K; **R is the absolute
  Z of the hole's top and Z the depth below R** (positive).  The tool goes at
  rapid in X Y, then to R + GAGE_HT_MM, feeds to R - Z and returns to
  R + GAGE_HT_MM, or to the plane of a W word;
- the taps turn the way M3/M4 set the spindle; G82 with a finishing depth or a
  feed factor other than 100 % is refused (it changes the feed near the bottom);
- the thesis program, run on the machine, writes no G43: the 2100 applies the
  loaded tool's length with the tool change.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import ClassVar

from postdsl.check.controls.base import ControlError
from postdsl.check.controls.events import Event, Hole, LengthOffsetChanged, Origin, Point, Rapid
from postdsl.check.controls.iso import Block, IsoControl

_PARAMETER = re.compile(r"\s*\[\$CYCLE_PARAMS\(\d+\)([A-Z0-9_]+)\]\s*=\s*([-+]?(?:\d+\.?\d*|"
                        r"\.\d+))\s*$")
_KNOWN_PARAMETERS = {"GAGE_HT_MM", "G82_DWELL", "G82_FEED_FAC", "G82_FIN_DPTH", "G83_RELIEF",
                     "G83_RET_DIST", "G83_SHRT_RET", "G84_DWELL", "G84_CHIP_BRK"}


class AcramaticControl(IsoControl):
    name = "acramatic-2100"
    cycles: ClassVar[dict[str, tuple[str, str]]] = {
        "81": ("drill", ""), "82": ("drill", ""), "83": ("peck", "JK"), "84": ("tap", "J"),
        "84.1": ("rigid_tap", "JKP")}
    quiet_g = IsoControl.quiet_g - {"43", "49", "98", "99"}
    letters = frozenset("GMXYZIJKRFSTPWN")
    parenthesis_comments = False
    dwell_by_f = True
    #: a G0/G1 line of N G X Y Z F means the core's straight move (cycles need G8x)
    fast_path = True

    def __init__(self) -> None:
        super().__init__()
        self.parameters: dict[str, float] = {"G82_FEED_FAC": 100.0, "G82_FIN_DPTH": 0.0}

    def code_of(self, text: str, origin: Origin) -> str:
        code = super().code_of(text, origin)
        if code.strip() == ":":
            return ""
        match = _PARAMETER.match(code)
        if match is not None:
            name = match.group(1)
            if name not in _KNOWN_PARAMETERS:
                raise ControlError(origin, f"{name} is not a cycle parameter the {self.name} "
                                           f"model knows")
            self.parameters[name] = float(match.group(2))
            return ""
        return code

    def after_tool_change(self, origin: Origin) -> Iterator[Event]:
        self.offset = self.tool
        yield LengthOffsetChanged(origin, self.offset)

    def motion_words(self, block: Block, origin: Origin) -> Iterator[Event]:
        if self.motion in self.cycles or set(block.g) & set(self.cycles):
            for letter in "JKW":
                if letter in block.values:
                    self.cycle[letter] = block.values.pop(letter)
                    self.cycle_words_given.add(letter)
        yield from super().motion_words(block, origin)

    def hole(self, block: Block, origin: Origin) -> Iterator[Event]:
        code, kind, top, depth = self.cycle_data(origin, "PQJK")  # R the top, Z the depth
        if depth <= 0:
            raise ControlError(origin, f"Z{depth:g} is a depth below R and must be positive")
        gauge = self.parameters.get("GAGE_HT_MM")
        if gauge is None:
            raise ControlError(origin, "a cycle before [$CYCLE_PARAMS(2)GAGE_HT_MM] is set")
        r = top + gauge
        leave = self.cycle.get("W", r)
        z = self.pos[2]
        end = self.target(block)
        if end[0] is None or end[1] is None:
            raise ControlError(origin, "a hole from a position the program does not state")
        x, y = float(end[0]), float(end[1])
        dwell, peck = 0.0, 0.0
        if code == "82":
            if self.parameters["G82_FIN_DPTH"] != 0 or self.parameters["G82_FEED_FAC"] != 100:
                raise ControlError(origin, "G82 with a finishing depth or feed factor is not "
                                           "modelled")
            dwell = self.parameters.get("G82_DWELL", 0.0)
        elif code == "83":
            variant = self.cycle.get("J")
            if variant not in (11.0, 13.0):
                raise ControlError(origin, "G83 is modelled with J11 (chip breaking) and J13 "
                                           "(full retract) only")
            kind = "chip_break" if variant == 11.0 else "peck"
            peck = self.cycle.get("K", 0.0)
            if peck <= 0:
                raise ControlError(origin, "G83 needs a peck K greater than 0")
        elif code.startswith("84"):
            dwell = self.parameters.get("G84_DWELL", 0.0)
            peck = self.cycle.get("K", 0.0) if code == "84.1" else 0.0
            if self.spindle == "off":
                raise ControlError(origin, f"G{code} with the spindle off")
        start: Point = (self.pos[0], self.pos[1], z)
        yield Rapid(origin, start, (x, y, z))
        yield Rapid(origin, (x, y, z), (x, y, r))
        self.pos = [x, y, leave]
        yield Hole(origin, (x, y, z), x, y, r, top - depth, leave, kind, self.spindle, dwell,
                   peck, self.feed_rate(), self.tooling())
