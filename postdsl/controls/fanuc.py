"""Fanuc 0i-M (0i-MD/0i-MF) control model: the ISO core with Fanuc's own rules.

From the Fanuc Series 0i-MD Operator's Manual (B-64484EN):

- "Dwell (G04)": ``G04 X`` in seconds, ``G04 P`` in milliseconds (no point);
  the P of G82, G84, G74 and G89 is the dwell in milliseconds too;
- "Canned cycle for drilling": the word formats G73/G83 ``X Y Z R Q F``, G82
  ``… P``, G84/G74 ``… P F``; a word the format does not list (P on G73) is not
  executed as the CAM meant, so the model refuses it;
- "Rigid tapping": ``M29 S`` before G84/G74 makes the next taps rigid until G80;
  Q on a rigid tap is the peck depth;
- the program number ``O`` and ``( … )`` comments carry no motion; a comment ends at
  the first ``)``, ``(`` inside one is refused (a comment cannot nest);
- ``%`` is the end-of-record code ("Tape format"): the tape's first ``%`` (a line of
  its own before the program) starts it, and any later ``%`` -- in a comment too --
  ends the record: the program stops before that line;
- M02 and M30 end the program ("Program end"): the lines after them are not run;
- by default (parameter 3401#0 DPI = 0) a number without a decimal point is in the
  least input increment, 0.001 mm for IS-B ("Decimal point programming": "X1000 is
  1 mm ... X1000. is 1000 mm"), for the addresses that take a point -- X Y Z I J K
  R Q, and X of G04 (0.001 s); F is mm/min either way in G94, and an F without a
  point in G95 (feed per revolution) is refused as not modelled; P, S, T, H, D, M,
  G, N and O are integers and unaffected.  A machine in calculator input (3401#0
  DPI = 1, the post's ``machine: calculator_input: true``) reads every number in mm
  and seconds.  The letters and the increment are the table
  :data:`postdsl.control_syntax.NUMBERS` (``postdsl check`` reads it too).
  Macro calls (G65) and macro variables (``#``) are not interpreted: a
  post declares what its macro lines do (``verify:`` of the table that writes them).
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import ClassVar

from postdsl.control_syntax import number_syntax
from postdsl.controls.base import ControlError
from postdsl.controls.events import Event, Origin
from postdsl.controls.iso import Block, IsoControl

_PROGRAM_NUMBER = re.compile(r"\s*(?:%|O\d+)\s*$")


class FanucControl(IsoControl):
    name = "fanuc-0i"
    #: G76 fine boring (X Y Z R Q P F): the oriented stop, then the shift Q at the bottom
    #: (its direction is parameter 5101 RD1/RD2's), not a peck
    cycles: ClassVar[dict[str, tuple[str, str]]] = {**IsoControl.cycles,
                                                    "76": ("fine_bore", "PQ")}
    rigid_tap_m = "29"
    letters = IsoControl.letters | {"O"}
    #: a G0/G1 line of N G X Y Z F means the core's straight move (no ``#``, no ``O``)
    fast_path = True
    #: G20 inch input (Operator's Manual, "Inch/metric conversion (G20, G21)")
    inch_g = "20"

    def __init__(self) -> None:
        super().__init__()
        self.begun = False
        self.configure()

    def configure(self, calculator_input: bool = False) -> None:
        syntax = number_syntax(self.name)
        #: the letters a number without a point is scaled for, and the factor
        self.increment_letters = frozenset() if calculator_input or syntax is None \
            else syntax.letters
        self.increment = 1.0 if syntax is None else syntax.increment
        self.calculator_input = calculator_input
        #: the last F was written without a decimal point (refused in G95)
        self.f_pointless = False

    def number(self, letter: str, text: str) -> float:
        if letter in self.increment_letters and "." not in text:
            # the least input increment: 0.001 mm, or 0.0001 inch in G20 (IS-B)
            return int(text) * (self.increment / 10 if self.inch else self.increment)
        if letter == "F":
            self.f_pointless = not self.calculator_input and "." not in text
        return float(text)

    def execute(self, block: Block, origin: Origin) -> Iterator[Event]:
        if "F" in block.values and self.f_pointless and \
                ("95" in block.g or (self.per_rev and "94" not in block.g)):
            raise ControlError(origin, "an F without a decimal point in G95: its unit (0.01 "
                                       "or 0.0001 mm/rev by parameter) is not modelled; write "
                                       "F with a point")
        return super().execute(block, origin)

    def code_of(self, text: str, origin: Origin) -> str:
        if "%" in text:
            if not self.begun and text.strip() == "%":
                self.begun = True  # the tape's leader: the program starts after it
                return ""
            self.ended = True  # the end-of-record code: the program stops before this line
            return ""
        if text.strip():
            self.begun = True
        code = super().code_of(text, origin)
        if _PROGRAM_NUMBER.match(code):
            return ""
        if "#" in code:
            raise ControlError(origin, "macro variables (#) are not interpreted; declare the "
                                       "line in the post (verify: of its table)")
        return code

    #: G54-G59, and G54.1 P1-P48 (Operator's Manual, "Additional workpiece coordinate
    #: systems"): the CL's work offsets 1-6 and 7-54
    work_offsets: ClassVar[dict[str, int]] = {**IsoControl.work_offsets, "54.1": 0}

    def work_offset_of(self, block: Block, origin: Origin) -> int | None:
        if "54.1" not in block.g:
            return super().work_offset_of(block, origin)
        if any(code in IsoControl.work_offsets for code in block.g):
            raise ControlError(origin, "two work offsets in one block")
        p = block.values.pop("P", None)
        if p is None or p != int(p) or not 1 <= p <= 48:
            raise ControlError(origin, "G54.1 needs P1 to P48 (the additional workpiece "
                                       "coordinate systems)")
        return 6 + int(p)

    def knows_g(self, code: str) -> bool:
        if code == "65":
            return False
        return code in ("30", "28")

    def dwell_seconds(self, block: Block, origin: Origin) -> float:
        if "X" in block.values:
            return block.values["X"]  # seconds; without a point in 0.001 s (as X in mm)
        if "P" in block.values:
            return block.values["P"] / 1000.0
        raise ControlError(origin, "G04 without a time (X seconds or P milliseconds)")

    def cycle_dwell(self, value: float) -> float:
        return value / 1000.0
