"""LinuxCNC control model: the ISO core with LinuxCNC's rules (its G-code reference).

- comments are ``( … )`` or ``;`` to the end of the line outside parentheses (the
  G-code reference, "Comments": "Semicolon ... the rest of the line is a comment";
  rs274 reads ``(a;b)`` as one comment);
- ``%`` (G-code reference, "File Requirements"): a line of its own; the first
  non-blank line may be one, and then the program ends at the next one ("the useful
  contents of a file demarcated by percents stop after the second percent line");
  a ``%`` line in a file that did not start with one is an error (rs274: "Bad
  character '%' used"); inside a comment ``%`` is an ordinary character;
- M2 and M30 end the program (the lines after them are not run);
- ``G4 P`` and the P of G82/G86/G88/G89 are seconds;
- there is no M29: G84/G74 tap with a floating holder (``tap``); a rigid tap is
  ``G33.1`` (below).

**G33.1 Rigid Tapping** (LinuxCNC G-code reference, "G33.1 Rigid Tapping";
``G33.1 X- Y- Z- K- I- $-``): a move from the current point to the given one,
synchronised with the spindle at K (distance per revolution), the spindle reversed at
the end, the same synchronised motion back, the spindle reversed again, and the move
"ends at the original coordinate".  It is an error if every axis word is omitted or
the spindle is not turning; ``rs274`` also refuses a G33.1 without K (K is not
modal).  G33.1 is a motion mode (group 1): a block of axis words alone after it taps
again.  The model reads it as a ``rigid_tap`` hole whose R level (where the
synchronised feed starts) and leave level are the Z the tool was at, its bottom the
Z word, its feed K times the spindle speed, its direction the spindle's.  The manual
warns that X or Y other than the current ones make the tap move sideways in the
hole, so the model refuses them, and a Z at or above the tool (a tap going up), the
I return multiplier (kept out: the model states no return speed) and the ``$``
spindle selector.

The tap ends where it began, at R; a post that leaves the hole higher (the CL's
retract plane) writes a rapid straight up right after it.  The model reads such a
rapid -- the next line that moves, moving only Z upward from the tap's start, comment
lines between allowed -- as the end of the tapped hole: the hole is left at that Z, as a
G98 cycle's hole is left at its initial level, by way of the tap's start (the event's
``via``): a CL whose retract is either level is what the program does (the rapid up is
then the CL's own next move).  The hole's event is therefore yielded
when that next line is read (or at the program's end).

Its events are cross-checked against LinuxCNC's own interpreter ``rs274``
(tests/test_controls_rs274.py) on programs of the dialect the two share.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import replace
from typing import ClassVar

from postdsl.check.controls.base import ControlError, NCInput
from postdsl.check.controls.compensation import LINUXCNC, Rules
from postdsl.check.controls.events import Event, Hole, Origin, Point, Rapid
from postdsl.check.controls.iso import MOTIONS, Block, IsoControl

#: the rigid-tap motion code, as the model keys G numbers
RIGID_TAP = "33.1"


class LinuxCNCControl(IsoControl):
    name = "linuxcnc"
    #: G92.1 clears the G92 offsets (LinuxCNC G-code reference, "G92.1, G92.2")
    preset_reset_g = "92.1"
    #: a wrapped rotary ([JOINT_n] WRAPPED_ROTARY = 1, the post's rotary: wrap: modulo) goes
    #: the way its angle's sign says, to the place its size says (``unwrap_rotary``,
    #: src/emc/rs274ngc/interp_find.cc): A10 from 350 turns on +20, A-350 from 10 turns -20
    modulo_way: ClassVar[str] = "signed"
    #: G-code manual, "Cutter Compensation": an arc around every convex corner, the
    #: entry move square to itself (interp_convert.cc, convert_straight_comp1)
    compensation_rules: ClassVar[Rules | None] = LINUXCNC
    cycles: ClassVar[dict[str, tuple[str, str]]] = {
        **IsoControl.cycles, "86": ("bore_stop", "P"), "88": ("bore", "P")}
    #: a G0/G1 line of N G X Y Z F is the core's straight move (G33.1 is its own mode)
    fast_path = True
    #: G20 inch units (G-code reference, "G20, G21 Units")
    inch_g = "20"
    #: G54-G59 and G59.1-G59.3 (G-code reference, "G54-G59.3 Select Coordinate System"):
    #: the CL's work offsets 1-9
    work_offsets: ClassVar[dict[str, int]] = {
        **IsoControl.work_offsets, "59.1": 7, "59.2": 8, "59.3": 9}

    def __init__(self) -> None:
        super().__init__()
        #: the last G33.1 hole, held until the next line that moves says where it is left
        self.tapped: Hole | None = None
        #: a line of code has been read (a '%' line now ends or is an error)
        self.begun = False
        #: the program started with a '%' line: the next one ends it
        self.demarcated = False

    def replay(self, lines: Iterable[NCInput | str]) -> Iterator[Event]:
        yield from super().replay(lines)
        if self.tapped is not None:
            yield self.tapped
            self.tapped = None

    def run_line(self, line: NCInput) -> Iterator[Event]:
        events = list(super().run_line(line))
        if self.tapped is not None and events:
            hole, self.tapped = self.tapped, None
            first = events[0]
            if isinstance(first, Rapid) and first.start == hole.start \
                    and first.end[:2] == hole.start[:2] and first.end[2] is not None \
                    and first.end[2] > hole.r:
                # the rapid up out of the hole; the tap itself ended at its start
                hole = replace(hole, leave=first.end[2], via=hole.leave)
            yield hole
        for event in events:
            if isinstance(event, Hole) and event.kind == "rigid_tap" and event is events[-1]:
                self.tapped = event
            else:
                yield event

    def plain_move_allowed(self) -> bool:
        """A held G33.1 hole waits for the next line that moves: that line is read whole."""
        return self.tapped is None

    def code_of(self, text: str, origin: Origin) -> str:
        if text.strip() == "%":
            self.percent_line(origin)
            return ""
        if text.strip():
            self.begun = True  # a comment line too: rs274 takes '%' only as the first line
        return super().code_of(text, origin)

    def percent_line(self, origin: Origin) -> None:
        """A ``%`` line: the start of a demarcated file, or its end."""
        if not self.begun and not self.demarcated:
            self.demarcated = True
        elif self.demarcated:
            self.ended = True  # the useful contents stop at the second percent line
        else:
            raise ControlError(origin, "a '%' line in a program that does not start with "
                                       "one (rs274: bad character '%')")

    def knows_g(self, code: str) -> bool:
        return code == RIGID_TAP

    def motion_words(self, block: Block, origin: Origin) -> Iterator[Event]:
        """G33.1 and the blocks it stays in force for; every other motion is the core's."""
        new_motion = [code for code in block.g
                      if code in MOTIONS or code in self.cycles or code == "80"]
        if RIGID_TAP in block.g:
            if new_motion:
                raise ControlError(origin, f"G33.1 and G{new_motion[0]} in one block: two "
                                           f"motion codes")
            self.end_cycle()
            self.motion = RIGID_TAP
        elif new_motion or self.motion != RIGID_TAP:
            yield from super().motion_words(block, origin)
            return
        yield from self.rigid_tap(block, origin)

    def rigid_tap(self, block: Block, origin: Origin) -> Iterator[Event]:
        values = block.values
        if "28" in block.g or "30" in block.g:
            raise ControlError(origin, "G28/G30 while G33.1 is the motion mode is not modelled")
        leftover = set(values) - set("XYZKFST")
        if leftover:
            word = sorted(leftover)[0]
            raise ControlError(origin, f"{word} is not a word of G33.1 the model reads (X Y Z K)")
        if not any(letter in values for letter in "XYZ"):
            if RIGID_TAP in block.g or "K" in values:
                raise ControlError(origin, "G33.1 without an axis word")
            return
        pitch = values.get("K")
        if pitch is None:
            raise ControlError(origin, "G33.1 without K (the distance per spindle revolution; "
                                       "K is not modal)")
        if pitch <= 0:
            raise ControlError(origin, f"G33.1 with K{pitch:g}: the pitch must be positive")
        if self.spindle == "off" or not self.speed:
            raise ControlError(origin, "G33.1 with the spindle not turning")
        x, y, z = self.pos
        if x is None or y is None or z is None:
            raise ControlError(origin, "a G33.1 from a position the program does not state")
        end = self.target(block)
        if end[0] is None or end[1] is None or end[2] is None \
                or abs(end[0] - x) > 1e-9 or abs(end[1] - y) > 1e-9:
            raise ControlError(origin, "G33.1 to another X or Y than the tool's: the tap would "
                                       "move sideways in the hole (position over it first)")
        bottom = float(end[2])
        if bottom >= z:
            raise ControlError(origin, f"G33.1 to Z{bottom:g}, not below the tool at Z{z:g}")
        start: Point = (x, y, z)
        # the move ends where it began: the position is unchanged
        yield Hole(origin, start, x, y, z, bottom, z, "rigid_tap", self.spindle, 0.0, 0.0,
                   pitch * self.speed, self.tooling())
