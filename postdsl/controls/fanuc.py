"""Fanuc 0i-M (0i-MD/0i-MF) control model: the ISO core with Fanuc's own rules.

From the Fanuc Series 0i-MD Operator's Manual (B-64484EN):

- "Dwell (G04)": ``G04 X`` in seconds, ``G04 P`` in milliseconds (no point);
  the P of G82, G84, G74 and G89 is the dwell in milliseconds too;
- "Canned cycle for drilling": the word formats G73/G83 ``X Y Z R Q F``, G82
  ``… P``, G84/G74 ``… P F``; a word the format does not list (P on G73) is not
  executed as the CAM meant, so the model refuses it;
- "Rigid tapping": ``M29 S`` before G84/G74 makes the next taps rigid until G80;
  Q on a rigid tap is the peck depth;
- the program number ``O``, the ``%`` tape marks and ``( … )`` comments carry no
  motion.  Macro calls (G65) and macro variables (``#``) are not interpreted: a
  post declares what its macro lines do (``verify:`` of the table that writes them).
"""

from __future__ import annotations

import re
from typing import ClassVar

from postdsl.controls.base import ControlError
from postdsl.controls.events import Origin
from postdsl.controls.iso import Block, IsoControl

_PROGRAM_NUMBER = re.compile(r"\s*(?:%|O\d+)\s*$")


class FanucControl(IsoControl):
    name = "fanuc-0i"
    #: G76 fine boring (X Y Z R Q P F): Q is the shift at the bottom, not a peck
    cycles: ClassVar[dict[str, tuple[str, str]]] = {**IsoControl.cycles, "76": ("bore", "PQ")}
    rigid_tap_m = "29"
    letters = IsoControl.letters | {"O"}
    #: a G0/G1 line of N G X Y Z F means the core's straight move (no ``#``, no ``O``)
    fast_path = True

    def code_of(self, text: str, origin: Origin) -> str:
        code = super().code_of(text, origin)
        if _PROGRAM_NUMBER.match(code):
            return ""
        if "#" in code:
            raise ControlError(origin, "macro variables (#) are not interpreted; declare the "
                                       "line in the post (verify: of its table)")
        return code

    def knows_g(self, code: str) -> bool:
        if code == "65":
            return False
        return code in ("30", "28")

    def dwell_seconds(self, block: Block, origin: Origin) -> float:
        if "X" in block.values:
            return block.values["X"]
        if "P" in block.values:
            return block.values["P"] / 1000.0
        raise ControlError(origin, "G04 without a time (X seconds or P milliseconds)")

    def cycle_dwell(self, value: float) -> float:
        return value / 1000.0
