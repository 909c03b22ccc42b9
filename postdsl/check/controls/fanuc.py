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
  :data:`postdsl.lang.control_syntax.NUMBERS` (``postdsl check`` reads it too).
  Macro calls (G65) and macro variables (``#``) are not interpreted: a
  post declares what its macro lines do (``verify:`` of the table that writes them).

Tilted working plane indexing (3+2; Series 30i/31i-B Operator's Manual, "Tilted working
plane indexing", Euler angle method; the 0i-F Plus option of the same name):

- ``G68.2 X Y Z I J K`` defines the feature coordinate system: its origin X Y Z in the
  work offset, its orientation as Euler angles Z-X'-Z'' in degrees (turn about Z by I,
  then about the new X by J, then about the newest Z by K: ``postdsl.frames``'s
  ``euler_zxz``).  From this block on, X Y Z are programmed in that system;
- ``G53.1`` turns the rotary axes so that the tool axis is the system's Z; the model
  refuses a cut between G68.2 and G53.1 (the coordinates tilted, the tool not);
- ``G69`` cancels it: the work offset's own frame again.  A G68.2 over another is
  refused (it is multiple-command only by a parameter the model does not assume).
After each of them the tool stays where it is at coordinates of the new frame the
program has not stated: the position is unknown until it is.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import ClassVar

from postdsl import frames
from postdsl.check.controls.base import ControlError
from postdsl.check.controls.events import ArcMove, Event, FeedMove, Hole, Origin
from postdsl.check.controls.iso import Block, IsoControl
from postdsl.lang.control_syntax import number_syntax

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
        #: the plane G68.2 declared (in force for the tool axis once G53.1 is read)
        self.declared: frames.Frame | None = None
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

    def _execute(self, block: Block, origin: Origin) -> Iterator[Event]:
        if "F" in block.values and self.f_pointless and \
                ("95" in block.g or (self.per_rev and "94" not in block.g)):
            raise ControlError(origin, "an F without a decimal point in G95: its unit (0.01 "
                                       "or 0.0001 mm/rev by parameter) is not modelled; write "
                                       "F with a point")
        yield from self.tilted_plane(block, origin)
        yield from super().execute(block, origin)

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
        return code in ("30", "28", "68.2", "53.1", "69")

    #: G68.2's I J K: Euler angles Z-X'-Z''
    tilted_plane_convention: ClassVar[str] = "euler_zxz"

    def plain_move_allowed(self) -> bool:
        """Between G68.2 and G53.1 a move is refused: the general reader says so."""
        return self.declared is None or self.frame is self.declared

    def execute(self, block: Block, origin: Origin) -> Iterator[Event]:
        for event in self._execute(block, origin):
            if self.declared is not None and self.frame is not self.declared \
                    and isinstance(event, (FeedMove, ArcMove, Hole)):
                raise ControlError(origin, "a cut after G68.2 without G53.1: the coordinates "
                                           "are tilted, the tool axis is not")
            yield event

    def tilted_plane(self, block: Block, origin: Origin) -> Iterator[Event]:
        """G68.2, G53.1 and G69, before the block's other modal codes."""
        g, values = block.g, block.values
        if "69" in g:
            if "68.2" in g or "53.1" in g:
                raise ControlError(origin, "G69 with G68.2 or G53.1 in one block")
            if self.declared is not None:
                self.declared = self.frame = None
                yield from self.lose_position(origin, (0, 1, 2))
        if "68.2" in g:
            if self.declared is not None:
                raise ControlError(origin, "G68.2 while a tilted plane is in force: cancel it "
                                           "with G69 first")
            missing = [letter for letter in "IJK" if letter not in values]
            if missing:
                raise ControlError(origin, f"G68.2 without {' '.join(missing)} (the Euler "
                                           f"angles)")
            if not self.absolute:
                raise ControlError(origin, "G68.2 in G91: the model reads its origin absolute")
            # the origin in the units in force (read before the block's lengths are scaled)
            place = [values.pop(letter, 0.0) * (25.4 if self.inch else 1.0) for letter in "XYZ"]
            angles = [values.pop(letter) for letter in "IJK"]
            self.declared = frames.frame_from_angles(self.tilted_plane_convention, place,
                                                     angles)
            yield from self.lose_position(origin, (0, 1, 2))
        if "53.1" in g:
            if self.declared is None:
                raise ControlError(origin, "G53.1 without a tilted plane (G68.2)")
            self.frame = self.declared

    def dwell_seconds(self, block: Block, origin: Origin) -> float:
        if "X" in block.values:
            return block.values["X"]  # seconds; without a point in 0.001 s (as X in mm)
        if "P" in block.values:
            return block.values["P"] / 1000.0
        raise ControlError(origin, "G04 without a time (X seconds or P milliseconds)")

    def cycle_dwell(self, value: float) -> float:
        return value / 1000.0
