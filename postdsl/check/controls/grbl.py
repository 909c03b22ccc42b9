"""GRBL 1.1 control model: the LinuxCNC dialect with GRBL's restrictions.

From the GRBL 1.1 documentation (github.com/gnea/grbl, doc/markdown/commands.md,
"$G - View gcode parser state", and the wiki page "Grbl v1.1 Commands"):

- the supported modal groups are motion G0 G1 G2 G3 G38.x G80, work offsets
  G54-G59, planes G17-G19, G90/G91, G91.1, G93/G94, G20/G21, G40, G43.1/G49,
  program flow M0 M1 M2 M30, spindle M3 M4 M5, coolant M7 M8 M9: there are no
  canned cycles (G81-G89 are an error), no G43 H (the tool length is touched
  off by the operator, or set with G43.1), no feed per revolution (G95);
- ``T`` is read and reported, but ``M6`` is an "unsupported command": a tool is
  changed by hand at a program pause (``M0``) after the ``T`` word names it;
  the operator then touches off Z, so the length is the new tool's own and the
  position is unknown until the program states it again;
- ``G4 P`` is seconds; comments are ``( … )`` and ``;`` to the end of the line
  outside parentheses (grbl/protocol.c, ``protocol_main_loop``: inside ``( … )``
  every character up to ``)`` or the end of the line is thrown away, a ``(`` too --
  no nested-comment error -- and a comment left open ends with the line; ``;``
  outside parentheses ends the line); ``%`` is not supported (a "TODO" in
  protocol.c): it reaches the parser, which refuses it (not a command letter);
- M2 and M30 do not stop a streamed program (grbl/gcode.c, "[21. Program flow]"):
  they reset the modal groups to G1 G17 G90 G94 G54 M5 M9 and GRBL reads on; a move
  after them runs with the spindle stopped;
- an arc with I J K is refused ("arc radius error", error 33) when the distance
  of its end from the centre differs from that of its start by more than
  0.5 mm, or by more than 0.005 mm and 0.1 % of the radius (grbl/gcode.c).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import ClassVar

from postdsl.check.controls.base import ControlError
from postdsl.check.controls.compensation import Rules
from postdsl.check.controls.events import (
    Event,
    LengthOffsetChanged,
    Origin,
    SpindleChanged,
    Stop,
    ToolLoaded,
)
from postdsl.check.controls.iso import Block
from postdsl.check.controls.linuxcnc import LinuxCNCControl


class GrblControl(LinuxCNCControl):
    #: GRBL 1.1 has no cutter radius compensation: G41/G42 are not among its G codes
    compensation_rules: ClassVar[Rules | None] = None
    name = "grbl-1.1"
    cycles: ClassVar[dict[str, tuple[str, str]]] = {}
    quiet_g = frozenset({"40", "54", "55", "56", "57", "58", "59", "21", "90", "91", "94",
                         "17", "18", "19", "80", "49", "4"})
    quiet_m = frozenset({"1", "2", "30", "7", "8", "9"})
    letters = frozenset("GMXYZIJKRFSTPN")
    #: GRBL's "arc radius error": more than 0.005 mm AND 0.1 % of the radius apart
    radius_tolerance = 0.005
    #: ... or more than 0.5 mm apart, whatever the radius
    radius_limit = 0.5
    nested_comment_error = False
    open_comment_error = False

    def percent_line(self, origin: Origin) -> None:
        raise ControlError(origin, "'%' is not supported by GRBL 1.1 (not a command letter)")

    def end_program(self, origin: Origin) -> Iterator[Event]:
        """M2/M30: the modal groups reset (gcode.c, "[21. Program flow]"), reading goes on."""
        self.motion = "1"
        self.plane = "xy"
        self.absolute = True
        self.per_rev = False
        if self.spindle != "off":
            self.spindle = "off"
            yield SpindleChanged(origin, "off", self.speed)

    def machine_functions(self, block: Block, origin: Origin) -> Iterator[Event]:
        rest = []
        for code in block.m:
            if code == "6":
                raise ControlError(origin, "M6 is not a GRBL 1.1 command (error 20): a tool "
                                           "is changed by hand at an M0 pause")
            if code == "0":
                if self.selected is None or self.selected == self.tool:
                    yield Stop(origin, False)  # a pause, not the hand tool change's
                yield from self.pause(origin)
            else:
                rest.append(code)
        block.m = rest
        yield from super().machine_functions(block, origin)

    def pause(self, origin: Origin) -> Iterator[Event]:
        """M0: the program stops; with a new T named, the operator changes the tool."""
        if self.selected is None or self.selected == self.tool:
            return
        self.tool = self.selected
        yield ToolLoaded(origin, self.tool)
        # the operator touches the new tool off: its length is its own, the axes were jogged
        self.offset = self.tool
        yield LengthOffsetChanged(origin, self.offset)
        yield from self.lose_position(origin, (0, 1, 2))

    def arc(self, block: Block, origin: Origin) -> Iterator[Event]:
        for event in super().arc(block, origin):
            radius = event.radius  # type: ignore[union-attr]  # IsoControl.arc yields ArcMoves
            end = event.end  # type: ignore[union-attr]  # (as above)
            centre = event.centre  # type: ignore[union-attr]  # (as above)
            a, b = {"xy": (0, 1), "zx": (2, 0), "yz": (1, 2)}[self.plane]
            # an ArcMove's end and centre are known: IsoControl.arc refuses a None position
            end_radius = ((end[a] - centre[a]) ** 2 + (end[b] - centre[b]) ** 2) ** 0.5  # type: ignore[operator]
            if abs(end_radius - radius) > self.radius_limit:
                raise ControlError(origin, f"arc radius error: radius {radius:.4f} at the "
                                           f"start, {end_radius:.4f} at the end")
            yield event
