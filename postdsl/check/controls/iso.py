"""The ISO 6983 core shared by the Fanuc and LinuxCNC models (and the base of the others).

One interpreter of the word-address language, with the rules both families
document in the same way (Fanuc 0i-MD Operator's Manual B-64484EN, chapters
"Interpolation functions", "Feed functions", "Canned cycle for drilling",
"Tool compensation functions"; LinuxCNC G-code reference, "G80-G89 canned
cycles"):

- a block runs in the order F, S, T, M6, M3/M4/M5, G4, modal G codes, G43/G49,
  then motion (RS274/NGC "order of execution"; Fanuc runs the same words alike);
- G0-G3 and the canned cycles share the motion group; G80, G0-G3 end a cycle;
- in canned-cycle mode every block with an axis word is another hole — a block
  with only Z drills again at the same X Y (Fanuc: "the cycle is repeated for
  each block with positioning data"; LinuxCNC: "the cycle runs for any block
  with axis words");
- Z and R of a cycle are absolute in G90 and stay until the cycle ends; the tool
  positions at rapid in X Y at its current level, goes at rapid to R, feeds to
  Z and leaves to R (G99) or to the level it had when the cycle began (G98, the
  higher of that level and R);
- I J K are the arc centre minus the start point; R is the radius (negative:
  the long way); an end equal to the start is a full circle;
- G95 feeds per revolution: the feed is F times the spindle speed;
- G28/G30 go at rapid through the given point to a reference point the program
  does not state; a tool change moves the axes to the change position.  Both
  leave those axes unknown until the program states them again.

Reading the text (the control's comment syntax is the fact of
:data:`postdsl.lang.control_syntax.COMMENTS`, shared with the compiler that writes comments):

- a comment in parentheses ends at the first ``)`` (RS274/NGC 3.3.4 "Comments and
  Messages": "The comment ends at the first right parenthesis found thereafter";
  Fanuc: control-out ``(`` / control-in ``)``); a ``(`` inside one is an error
  (RS274/NGC: "it is an error if a left parenthesis is found after the start of a
  comment"; rs274 says "Nested comment found"), and so is a comment left open;
- where the control has a line comment (``;`` on LinuxCNC and GRBL), it starts only
  *outside* parentheses: ``(a;b) X1`` moves, ``;a (b`` is all comment;
- a number is read by :meth:`IsoControl.number`: a word without a decimal point
  means what the control makes of it (Fanuc: the least input increment);
- **M2 and M30 end the program** (RS274/NGC "M2, M30: program end", executed last in
  the block; Fanuc "M02, M30: end of program"): the lines after them are not run, so
  a cut the CL still has after them is a difference (rs274 stops there too).

The family differences (units of P, comment syntax, which words a cycle takes,
M29 rigid tapping, ``%``) are class attributes and small methods of the subclasses.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import ClassVar

from postdsl.check.controls.base import (
    PLANE_AXES,
    ControlError,
    NCInput,
    PlainFeed,
    arc_geometry,
    centre_from_radius,
    number_key,
)
from postdsl.check.controls.compensation import FANUC, CompensatedPath, Rules
from postdsl.check.controls.events import (
    UNKNOWN,
    ArcMove,
    Dwell,
    Event,
    FeedMove,
    Hole,
    LengthOffsetChanged,
    NotFollowed,
    Origin,
    Point,
    ProgramEnded,
    Rapid,
    SpindleChanged,
    Stop,
    Tooling,
    ToolLoaded,
)
from postdsl.frames import Frame
from postdsl.kinematics import (
    Kinematics,
    is_identity,
    modulo_turn,
    tip_path_length,
    to_part,
    tool_axis,
)
from postdsl.lang.control_syntax import comment_syntax

_WORD = re.compile(r"\s*([A-Z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")
_BLOCK_NUMBER = re.compile(r"\s*N\d+")
_NUM = r"([-+]?(?:\d+\.?\d*|\.\d+))"
#: the common line a fast path reads (:meth:`IsoControl.plain_move`): a block number, G0 or
#: G1, X Y Z and F in this order, single spaces or none between them; nothing else at all
#: (no comment, no ``;`` or ``%``, no other letter, no leading space, no lower case)
_PLAIN = re.compile(rf"(?:N\d+ *)?(?:G0*([01]) *)?(?:X{_NUM} *)?(?:Y{_NUM} *)?(?:Z{_NUM} *)?"
                    rf"(?:F{_NUM} *)?\Z")

MOTIONS = {"0", "1", "2", "3"}


def _float_value(letter: str, text: str) -> float:
    """:meth:`IsoControl.number` as the core has it, without the method call."""
    return float(text)

PLANES = {"17": "xy", "18": "zx", "19": "yz"}


@dataclass
class Block:
    """The words of one line: G and M codes in order, every other letter once."""

    g: list[str] = field(default_factory=list)
    m: list[str] = field(default_factory=list)
    values: dict[str, float] = field(default_factory=dict)
    #: dialect extras (a Sinumerik cycle call, an Acramatic parameter), read by subclasses
    extra: dict[str, object] = field(default_factory=dict)


def as_rapids(events: Iterable[Event]) -> Iterator[Event]:
    """A line the post declares a rapid (``verify: {motion: rapid}``): its straight moves,
    made at the control's one speed, are what the CL's rapids are compared with."""
    for event in events:
        if isinstance(event, FeedMove):
            yield Rapid(event.origin, event.start, event.end)
        else:
            yield event


class IsoControl:
    """Replays ISO word-address NC text as events.  Subclasses set the family's rules."""

    #: the model's name as posts declare it (``machine.control``)
    name = "iso"
    #: canned cycles: G code -> (kind, words it takes besides X Y Z R F)
    cycles: ClassVar[dict[str, tuple[str, str]]] = {
        "81": ("drill", ""), "82": ("drill", "P"), "83": ("peck", "Q"),
        "73": ("chip_break", "Q"), "84": ("tap", "P"), "74": ("tap", "P"),
        # boring (RS274/NGC, Fanuc 0i-MD "Boring cycle"): G85 feeds out, G89 dwells first,
        # G86 stops the spindle at the bottom and rapids out
        "85": ("bore", ""), "86": ("bore_stop", ""), "89": ("bore", "P"),
    }
    #: G codes of no motion this family accepts (work offsets, cutter compensation off…)
    quiet_g = frozenset({"40", "54", "55", "56", "57", "58", "59", "21", "90", "91", "94", "95",
               "98", "99", "17", "18", "19", "80", "43", "49", "4"})
    #: M codes without motion and without state the verify compares (coolant, stops)
    quiet_m = frozenset({"0", "1", "7", "8", "9", "2", "30"})
    #: letters an address word may have in this family
    letters = frozenset("GMXYZIJKRFSTPQHDN")
    #: an arc end may miss its circle by this much before the control refuses it (mm)
    radius_tolerance = 0.002
    #: a rigid-tap M code (Fanuc M29), or None
    rigid_tap_m: str | None = None
    #: how a plain absolute angle moves a modulo axis (``rotary: wrap: modulo``; the ways
    #: of :func:`postdsl.kinematics.modulo_turn`): Fanuc's roll-over (parameter 1008#0
    #: ROAx = 1, #1 RABx = 0: "the direction in which the distance to the target is shorter",
    #: Fanuc 0i-MF Parameter Manual, 1008) -- the ISO family's default
    modulo_way: ClassVar[str] = "shortest"
    #: the G code that clears a G92 rotary preset (LinuxCNC G92.1), or None
    preset_reset_g: ClassVar[str | None] = None
    #: ``( … )`` is a comment (ISO); otherwise parentheses are syntax of the dialect
    parenthesis_comments = True
    #: a ``(`` inside a comment is an error (RS274/NGC); GRBL ignores it
    nested_comment_error = True
    #: a comment left open is an error; GRBL ends it at the end of the line
    open_comment_error = True
    #: M codes that end the program: the lines after them are not run
    program_end_m = frozenset({"2", "30"})
    #: the dwell time is the F word of G4 (``G4 F0.5``, seconds) and F stays the feed
    dwell_by_f = False
    #: the family's common lines may take :meth:`plain_move`, the fast path of
    #: ``postdsl post``'s verify: a subclass sets it once it has checked that a line the
    #: fast path reads means nothing else to its dialect (see :meth:`plain_move_allowed`)
    fast_path: ClassVar[bool] = False
    #: the G code that selects inch input in this family (Fanuc, RS274: G20; G21 mm),
    #: None where the model reads mm only
    inch_g: ClassVar[str | None] = None
    #: the G code that selects mm again
    metric_g: ClassVar[str] = "21"
    #: the address words that are lengths (and F, a length per minute or revolution):
    #: read in inches after the inch code, and converted to the CL's mm
    length_letters: ClassVar[frozenset[str]] = frozenset("XYZIJKRQF")

    def __init__(self) -> None:
        self.pos: list[float | None] = [None, None, None]
        self.motion: str | None = None
        self.plane = "xy"
        self.absolute = True
        self.per_rev = False
        #: the inch code is in force: lengths and feeds are read in inches
        self.inch = False
        self.retract_to_r = False
        self.f: float | None = None
        self.speed: float | None = None
        self.spindle = "off"
        self.selected: int | None = None
        self.tool: int | None = None
        self.offset: int | None = None
        self.rigid = False
        self.cycle: dict[str, float] = {}
        self.cycle_words_given: set[str] = set()
        self.initial_z: float | None = None
        syntax = comment_syntax(self.name)
        #: what starts a comment to the end of the line (``;``; outside parentheses where
        #: the control has them), or None
        self.line_comment = syntax.line_comment if syntax is not None else None
        #: comment texts that are commands to the control (LinuxCNC's ``(ABORT,…)``)
        self.active_comment = syntax.active if syntax is not None else None
        #: M2/M30 has been run: the program has ended, later lines are not read
        self.ended = False
        #: set by the verifier: :meth:`replay` yields a plain feed move as a
        #: :data:`~postdsl.check.controls.base.PlainFeed` tuple instead of a FeedMove
        self.plain_feeds = False
        #: the last Tooling made, by its values: the same object while nothing changes, so a
        #: comparison may skip a state it has already compared
        self._tooling: tuple[tuple[object, ...], Tooling] | None = None
        #: the work offset in force, as the CL numbers it (1: G54, in force at power-on)
        self.work_offset = 1
        #: the tilted working plane in force (a control that tilts one sets it)
        self.frame: Frame | None = None
        #: cutter compensation: what its register holds (machine.cutter_compensation:
        #: wear, radius 0, the path is the tool centre; control, the tool's radius), the
        #: CL's tool diameters (control), the side in force, the register, the G41/G42/G40
        #: of the block being run, and the offset path of the stretch under way
        self.compensation_mode = "wear"
        self.tool_diameters: dict[int, float] = {}
        self.comp_side: str | None = None
        self.comp_register: int | None = None
        self.comp_change: str | None = None
        self.comp_path: CompensatedPath | None = None
        #: G41/G42 or G40 given, its move in the plane still to come
        self.comp_waiting: str | None = None
        #: the machine's rotaries (:meth:`set_kinematics`); None: an XYZ machine
        self.kinematics: Kinematics | None = None
        #: the rotary angles now (deg), by axis name; 0 at the start, as the post assumes
        self.rot: dict[str, float] = {}
        #: G93: F is 1 / the block's minutes
        self.inverse_time = False
        #: G92 A...: the angle the control counts less the one the program writes (deg),
        #: by axis; :attr:`rot` is the machine's count, which the kinematics turn by
        self.preset: dict[str, float] = {}

    #: M0/M1 made Stop events, compared with the CL's program_stop/optional_stop (a
    #: dialect whose stops are read elsewhere says False: the CL's are then not compared)
    reports_stops: ClassVar[bool] = True
    #: the rules of the control's cutter compensation (None: it has none, G41/G42 unknown)
    compensation_rules: ClassVar[Rules | None] = FANUC
    #: D n is the radius of tool n (ISO tool tables); else the active tool's (an edge number)
    d_is_tool_number: ClassVar[bool] = True

    def configure_compensation(self, mode: str, tool_diameters: dict[int, float]) -> None:
        """The machine's cutter_compensation mode and the CL's tool diameters: in the
        control mode the register holds the tool's radius, in wear mode (the default) a
        wear value, taken as 0 (the path is the programmed one)."""
        self.compensation_mode = mode
        self.tool_diameters = tool_diameters

    def set_kinematics(self, kinematics: Kinematics) -> None:
        """The machine's rotary axes (``machine: rotary_axes``): the model reads their words
        and G93, and reports every move in the part's frame -- the machine's X Y Z turned
        back about the table's pivots -- so verify compares it with the CL's tool tip."""
        if not kinematics.axes:
            return
        self.kinematics = kinematics
        self.rot = {name: 0.0 for name in kinematics.names}
        self.letters = self.letters | {name.upper() for name in kinematics.names}

    def to_part(self, machine: Sequence[float | None], angles: dict[str, float]) -> Point:
        """Where the tool tip is on the part, the machine at ``machine`` and ``angles``."""
        kin = self.kinematics
        if kin is None or is_identity(kin, angles):
            return (machine[0], machine[1], machine[2])
        if machine[0] is None or machine[1] is None or machine[2] is None:
            return UNKNOWN
        return to_part(kin, (machine[0], machine[1], machine[2]), angles)

    def configure(self, calculator_input: bool = False) -> None:
        """The machine's settings that change how the control reads a program.

        ``calculator_input``: a number without a decimal point is in mm (Fanuc
        parameter 3401#0 DPI = 1).  A control that has no such setting reads every
        number as written and ignores it.
        """

    def axis_steps(self) -> tuple[float, float, float] | None:
        """The smallest move of X, Y and Z (mm) when the program sets it, else None.

        A word-address control takes any coordinate to the machine's resolution;
        a control driving motors in whole steps (hmCNC) knows each axis's step from
        the program, and verify compares within it instead.
        """
        return None

    # --- reading ------------------------------------------------------------------------------

    def replay(self, lines: Iterable[NCInput | str]) -> Iterator[Event]:
        """Events of a program, line by line (a str is a line to interpret).

        With :attr:`plain_feeds` (and :attr:`fast_path`) a str line of the common form
        (:meth:`plain_move`) is read by the fast path, and a feed move comes as a
        :data:`~postdsl.check.controls.base.PlainFeed` tuple: no Origin, NCInput or FeedMove is
        made for the lines that are most of a program (verify makes them for a message).
        """
        fast = self.plain_move if self.plain_feeds and self.fast_path else None
        run = self.run_line
        for index, item in enumerate(lines, start=1):
            if item.__class__ is str:
                if fast is not None:
                    event = fast(index, item)
                    if event is not None:
                        yield event  # type: ignore[misc]  # the fast path's plain tuple
                        continue
                line = NCInput(index, item)
            else:
                line = item  # type: ignore[assignment]  # not a str: an NCInput
            yield from run(line)

    def plain_move_allowed(self) -> bool:
        """Whether the model's state lets the fast path read a G0/G1 line: a subclass with
        state that gives such a line another meaning (a modal cycle call, a held tap) says no."""
        return True

    def plain_move(self, index: int, text: str) -> Rapid | PlainFeed | None:
        """The fast path of the common line, or None: the general reader then reads it.

        Only a line :data:`_PLAIN` matches whole -- N, G0/G1, X Y Z, F and nothing else --
        with an axis word, in G90 and G94, before the program's end, with G0 or G1 the
        motion mode already (or given, and no M29 pending), where the general reader does
        exactly this: F, then a straight move (see :meth:`straight`).  The numbers are
        read by :meth:`number`, as the general reader reads them.  Nothing is changed
        before the line is known to be one the fast path takes.
        """
        if self.kinematics is not None:
            return None  # the rotaries: every move goes through the part frame
        match = _PLAIN.match(text)
        if match is None:
            return None
        g, x, y, z, f = match.groups()
        if x is None and y is None and z is None:
            return None
        motion = self.motion
        if (motion != "1" and motion != "0") or not self.absolute or self.per_rev \
                or self.ended or self.comp_side is not None or self.comp_waiting is not None \
                or self.inch:
            return None  # another mode, or nothing more runs: the general reader says what
        if g is not None:
            if self.rigid:
                return None  # G0/G1 ends M29's rigid mode: the general reader does that
            motion = g
        if not self.plain_move_allowed():
            return None
        pos = self.pos
        start = (pos[0], pos[1], pos[2])
        if type(self).number is IsoControl.number:  # the core's reading: float
            end = (pos[0] if x is None else float(x), pos[1] if y is None else float(y),
                   pos[2] if z is None else float(z))
            value = _float_value
        else:  # the model's own reading of a number
            value = self.number
            end = (pos[0] if x is None else value("X", x),
                   pos[1] if y is None else value("Y", y),
                   pos[2] if z is None else value("Z", z))
        if motion == "1" and (None in start or None in end):
            return None  # the general reader refuses it, at its line
        feed = None if f is None else value("F", f)
        self.motion = motion
        if feed is not None:
            self.f = feed
        self.pos = [end[0], end[1], end[2]]
        if motion == "0":
            return Rapid(Origin(index, text), start, end)
        # motion 1 with a None in start or end returned None above: these are floats
        return (index, text, start, end, self.feed_rate(), self.tooling())  # type: ignore[return-value]

    def run_line(self, line: NCInput) -> Iterator[Event]:
        if self.ended:
            return  # after M2/M30 the control runs nothing more of the program
        origin = Origin(line.line, line.text)
        if line.declared == "rapid":
            yield from as_rapids(self.interpret(line, origin))
            return
        if line.declared is not None:
            moves = line.declared == "unknown"
            if moves:
                self.pos = [None, None, None]
                self.motion = None
            yield NotFollowed(origin, moves)
            return
        yield from self.interpret(line, origin)

    def interpret(self, line: NCInput, origin: Origin) -> Iterator[Event]:
        """The events of one line the model reads."""
        code = self.code_of(line.text, origin)
        if self.ended:  # the line ended the record ('%')
            yield ProgramEnded(origin)
            return
        if not code.strip():
            return
        block = self.read_block(code, origin, line.skip_words)
        yield from self.execute(block, origin)

    def code_of(self, text: str, origin: Origin) -> str:
        """The line without its block number and comments."""
        text = _BLOCK_NUMBER.sub("", text, count=1) if text.lstrip().startswith("N") else text
        line_comment = self.line_comment
        if not self.parenthesis_comments:
            if line_comment is not None and line_comment in text:
                return text.split(line_comment, 1)[0]
            return text
        if "(" not in text and (line_comment is None or line_comment not in text):
            return text
        out: list[str] = []
        depth, opened = 0, 0
        for index, char in enumerate(text):
            if depth:
                if char == ")":
                    depth = 0
                    self.passive_comment(text[opened:index], origin)
                elif char == "(" and self.nested_comment_error:
                    raise ControlError(origin, "a comment inside a comment ('(' before the "
                                               "')' that ends the first: nested comment)")
            elif char == "(":
                depth, opened = 1, index + 1
            elif char == line_comment:
                return "".join(out)  # the rest of the line is a comment
            else:
                out.append(char)
        if depth and self.open_comment_error:
            raise ControlError(origin, "a comment is not closed")
        return "".join(out)

    def passive_comment(self, comment: str, origin: Origin) -> None:
        """Refuse a comment that is a command to the control (a message, a log file, an
        abort): what it does is not motion the model can vouch for."""
        if self.active_comment is not None and self.active_comment.match(comment):
            raise ControlError(origin, f"'({comment})' is a command to the {self.name} "
                                       f"control, not a comment (messages, log files, abort "
                                       f"are not modelled)")

    def read_block(self, code: str, origin: Origin, skip: frozenset[str]) -> Block:
        block = Block()
        position = 0
        code = code.upper()
        while position < len(code):
            if code[position].isspace():
                position += 1
                continue
            position = self.read_extra(code, position, block, origin)
            if position < 0:
                raise ControlError(origin, f"cannot read '{code.strip()}'")
            if position < len(code) and not code[position].isspace():
                match = _WORD.match(code, position)
                if match is None or match.group(1) not in self.letters:
                    raise ControlError(origin, f"'{code[position:].split()[0]}' is not a word "
                                               f"the {self.name} model knows")
                letter, value = match.group(1), match.group(2)
                position = match.end()
                if f"{letter}{number_key(value)}" in skip:
                    continue
                if letter == "G":
                    block.g.append(number_key(value))
                elif letter == "M":
                    block.m.append(number_key(value))
                elif letter in block.values:
                    raise ControlError(origin, f"two {letter} words in one block")
                else:
                    block.values[letter] = self.number(letter, value)
        return block

    def number(self, letter: str, text: str) -> float:
        """The value of an address word as the control reads it (ISO: the number written).

        The one place a word's digits become a value: a family whose control reads a
        number without a decimal point otherwise (Fanuc) overrides it.
        """
        return float(text)

    def read_extra(self, code: str, position: int, block: Block, origin: Origin) -> int:
        """Read a dialect's non-address syntax at ``position``; the new position (-1: error)."""
        return position

    # --- running ------------------------------------------------------------------------------

    def tooling(self) -> Tooling:
        """The cutting state now; the same object as the last one while it has not changed."""
        # the side in wear mode (control mode: the offset path itself shows the side)
        key = (self.tool, self.offset, self.spindle, self.speed, self.work_offset, self.frame,
               self.comp_side if self.compensation_mode != "control" else None)
        cached = self._tooling
        if cached is not None and cached[0] == key:
            return cached[1]
        tooling = Tooling(*key)
        self._tooling = (key, tooling)
        return tooling

    def feed_rate(self) -> float | None:
        """The feed in mm/min: F, or F times the spindle speed in G95."""
        if self.f is None:
            return None
        if self.per_rev:
            return self.f * self.speed if self.speed is not None and self.spindle != "off" \
                else 0.0
        return self.f

    def units(self, block: Block, origin: Origin) -> None:
        """The inch code (G20) or G21 in the block, and its lengths in mm: the units apply to
        the block's own values (RS274/NGC and Fanuc read the code first).  A dwell's X
        (Fanuc G04 X, seconds) is a time, not a length."""
        inch_g = self.inch_g
        if inch_g is None:
            return
        metric_g = self.metric_g
        if inch_g in block.g:
            if metric_g in block.g:
                raise ControlError(origin, f"G{inch_g} and G{metric_g} in one block")
            self.inch = True
        elif metric_g in block.g:
            self.inch = False
        if self.inch:
            # a dwell's time: Fanuc's G04 X, Sinumerik's G4 F (seconds, not lengths)
            lengths = self.length_letters - ({"X", "F"} if "4" in block.g else set())
            if "93" in block.g or (self.inverse_time and "94" not in block.g
                                   and "95" not in block.g):
                lengths = lengths - {"F"}  # G93: F is 1 / minutes in either unit system
            for letter in lengths.intersection(block.values):
                block.values[letter] *= 25.4

    def execute(self, block: Block, origin: Origin) -> Iterator[Event]:
        self.units(block, origin)
        values = block.values
        self.cycle_words_given = set()
        if self.dwell_by_f and "4" in block.g and "F" in values:
            block.extra["dwell"] = values.pop("F")
        for code in block.g:
            if code not in self.quiet_g and code not in MOTIONS and code not in self.cycles \
                    and code not in ("28", "30") and code not in self.work_offsets \
                    and code != self.inch_g and code != self.metric_g \
                    and not self.knows_g(code) and not (
                        code in ("41", "42") and self.compensation_rules is not None) \
                    and not (code == "93" and self.kinematics is not None) \
                    and not (code in ("92", self.preset_reset_g) and self.kinematics is not None):
                raise ControlError(origin, f"G{code} is not a code the {self.name} model knows")
        if "F" in values:
            self.f = values["F"]
        if "S" in values:
            self.speed = values["S"]
            if self.spindle != "off":
                yield SpindleChanged(origin, self.spindle, self.speed)
        if "T" in values:
            self.selected = int(values["T"])
        if self.kinematics is not None:
            rotary = {name: values.pop(name.upper()) for name in self.kinematics.names
                      if name.upper() in values}
            if rotary:
                block.extra["rotary"] = rotary
            self.rotary_preset(block, origin)
        yield from self.machine_functions(block, origin)
        yield from self.modal_codes(block, origin)
        yield from self.motion_words(block, origin)
        if self.program_end_m.intersection(block.m):
            yield from self.end_program(origin)

    def rotary_preset(self, block: Block, origin: Origin) -> None:
        """``G92 A…`` sets the count of the rotary where it stands to the value written
        (LinuxCNC G-code reference, "G92 Coordinate System Offset"; Fanuc 0i-MF Operator's
        Manual, "Setting a workpiece coordinate system (G92)"): the axis does not move, the
        program's later angles are counted from there -- how a ``rezero`` post sets back a
        continuous axis after whole turns.  ``G92.1`` (LinuxCNC) clears it.  A G92 on X Y Z
        is not modelled (it would move the part's origin)."""
        if self.preset_reset_g is not None and self.preset_reset_g in block.g:
            self.preset = {}
        if "92" not in block.g:
            return
        rotary = block.extra.pop("rotary", None)
        if not rotary or any(letter in block.values for letter in "XYZ"):
            raise ControlError(origin, "G92 on X, Y or Z (or without a rotary word): not "
                                       "modelled; only G92 A/B/C, a rotary's count, is")
        for name, value in rotary.items():  # type: ignore[attr-defined]  # the dict put above
            self.preset[name] = self.rot[name] - value

    def end_program(self, origin: Origin) -> Iterator[Event]:
        """M2/M30, after everything else of its block: the program ends here."""
        if self.comp_path is not None and self.comp_path.unfinished() is not None:
            raise ControlError(origin, "the program ends with cutter compensation on: the "
                               "last compensated move is never finished (G40 first)")
        self.ended = True
        yield ProgramEnded(origin)

    def knows_g(self, code: str) -> bool:
        return False

    def machine_functions(self, block: Block, origin: Origin) -> Iterator[Event]:
        for code in block.m:
            if code == "6":
                yield from self.change_tool(origin)
            elif code in ("3", "4"):
                self.spindle = "cw" if code == "3" else "ccw"
                yield SpindleChanged(origin, self.spindle, self.speed)
            elif code == "5":
                self.spindle = "off"
                yield SpindleChanged(origin, "off", self.speed)
            elif code == self.rigid_tap_m:
                self.rigid = True
            elif code in ("0", "1") and self.reports_stops:
                yield Stop(origin, code == "1")
            elif code not in self.quiet_m:
                raise ControlError(origin, f"M{code} is not a code the {self.name} model knows; "
                                           f"declare it in the post (verify: words)")

    def change_tool(self, origin: Origin) -> Iterator[Event]:
        if self.comp_side is not None or self.comp_waiting in ("41", "42"):
            raise ControlError(origin, "a tool change with cutter compensation on (G40 first)")
        if self.selected is None:
            raise ControlError(origin, "M6 without a tool selected (no T word before it)")
        self.tool = self.selected
        yield ToolLoaded(origin, self.tool)
        yield from self.lose_position(origin, (0, 1, 2))
        yield from self.after_tool_change(origin)

    def after_tool_change(self, origin: Origin) -> Iterator[Event]:
        """ISO controls keep the length offset register until G43/G49 says otherwise."""
        return iter(())

    def lose_position(self, origin: Origin, axes: Iterable[int]) -> Iterator[Event]:
        start: Point = (self.pos[0], self.pos[1], self.pos[2])
        for axis in axes:
            self.pos[axis] = None
        yield Rapid(origin, start, (self.pos[0], self.pos[1], self.pos[2]))

    def dwell_seconds(self, block: Block, origin: Origin) -> float:
        """G4's time: P (ISO: seconds) or X."""
        if "dwell" in block.extra:
            return float(block.extra["dwell"])  # type: ignore[arg-type]  # a number, as read
        if "P" in block.values:
            return block.values["P"]
        if "X" in block.values:
            return block.values["X"]
        raise ControlError(origin, "G4 without a time")

    def modal_codes(self, block: Block, origin: Origin) -> Iterator[Event]:
        g = block.g
        if "4" in g:
            yield Dwell(origin, self.dwell_seconds(block, origin))
            block.values.pop("P", None)
            block.values.pop("X", None)
        for code in g:
            if code in PLANES:
                self.plane = PLANES[code]
            elif code in ("90", "91"):
                self.absolute = code == "90"
            elif code in ("94", "95"):
                self.per_rev = code == "95"
                self.inverse_time = False
            elif code == "93":
                self.per_rev = False
                self.inverse_time = True
            elif code in ("98", "99"):
                self.retract_to_r = code == "99"
            elif code == "49":
                self.offset = None
                yield LengthOffsetChanged(origin, None)
        number = self.work_offset_of(block, origin)
        if number is not None and number != self.work_offset:
            # the tool stays, its coordinates in the new offset are unknown (the offsets'
            # values are on the machine, not in the program)
            self.work_offset = number
            yield from self.lose_position(origin, (0, 1, 2))
        if "43" in g:
            if "H" not in block.values:
                raise ControlError(origin, "G43 without an H register")
            self.offset = int(block.values.pop("H"))
            yield LengthOffsetChanged(origin, self.offset)
        elif "H" in block.values:
            raise ControlError(origin, "an H word without G43")
        self.compensation_codes(block, origin)

    def compensation_codes(self, block: Block, origin: Origin) -> None:
        """G40/G41/G42 and D: taken here, run with the block's move (:meth:`compensate`)."""
        codes = [code for code in ("40", "41", "42") if code in block.g]
        if len(codes) > 1:
            raise ControlError(origin, "two cutter compensation codes in one block")
        register = block.values.pop("D", None)
        if not codes or self.compensation_rules is None:
            return  # a D alone: a register chosen, no effect without G41/G42
        if register is not None:
            if register != int(register) or register < 0:
                raise ControlError(origin, f"D{register:g} is not a register number")
            self.comp_register = int(register)
        code = codes[0]
        if code != "40":
            if self.comp_register is None:
                raise ControlError(origin, f"G{code} without a D register")
            if self.comp_side is not None or self.comp_waiting in ("41", "42"):
                raise ControlError(origin, f"G{code} while cutter compensation is on: a "
                                   f"change of side without G40 is beyond the model")
        elif self.comp_side is None and self.comp_waiting is None:
            return  # G40 in force already (a safe-start block)
        self.comp_waiting = code

    def comp_radius(self, origin: Origin) -> float:
        """The radius the register holds: 0 in wear mode, the tool's in control mode."""
        if self.compensation_mode != "control":
            return 0.0
        tool = self.comp_register if self.d_is_tool_number else self.tool
        diameter = self.tool_diameters.get(tool) if tool is not None else None
        if not diameter:
            raise ControlError(origin, f"cutter compensation with D{self.comp_register}: the "
                               f"CL gives no diameter for tool {tool}, whose radius the "
                               f"register holds (cutter_compensation: control)")
        return diameter / 2

    def compensate(self, events: Iterable[Event], origin: Origin) -> Iterator[Event]:
        """A block's move as the control runs it with cutter compensation: started by
        G41/G42 or ended by G40 on a straight move in the plane, offset in between."""
        waiting, side, path = self.comp_waiting, self.comp_side, self.comp_path
        if waiting is None and side is None:
            yield from events
            return
        for event in events:
            if not isinstance(event, (Rapid, FeedMove, ArcMove)) or None in event.start \
                    or None in event.end:
                if side is not None or waiting in ("41", "42"):
                    raise ControlError(origin, "cutter compensation on where the position "
                                       "is not known (a reference return, a tool change)")
                yield event
                continue
            in_plane = event.start[0] != event.end[0] or event.start[1] != event.end[1] \
                or isinstance(event, ArcMove)
            if waiting in ("41", "42") and in_plane:
                if self.plane != "xy":
                    raise ControlError(origin, "cutter compensation outside G17 (XY) is "
                                       "beyond the model")
                self.comp_side = side = "left" if waiting == "41" else "right"
                self.comp_waiting = waiting = None
                radius = self.comp_radius(origin)
                if isinstance(event, ArcMove):
                    raise ControlError(origin, f"cutter compensation starts (G4"
                                       f"{'1' if side == 'left' else '2'}) on an arc: the "
                                       f"control starts it on a straight move (G0/G1) in the "
                                       f"plane")
                self.comp_path = path = CompensatedPath(side, radius, self.compensation_rules) \
                    if radius > 0 and self.compensation_rules is not None else None
                if path is None:
                    yield event
                else:
                    yield from path.move(event)
            elif waiting == "40" and in_plane:
                if isinstance(event, ArcMove):
                    raise ControlError(origin, "cutter compensation ends (G40) on an arc: the "
                                       "control ends it on a straight move (G0/G1) in the plane")
                self.comp_side = side = None
                self.comp_waiting = waiting = None
                self.comp_path = None
                if path is None:
                    yield event
                else:
                    yield from path.cancel(event)
            elif path is not None:
                yield from path.move(event)
            else:
                yield event

    #: the work offsets of the family: G code -> the CL's number (RS274's six)
    work_offsets: ClassVar[dict[str, int]] = {str(n): n - 53 for n in range(54, 60)}

    def work_offset_of(self, block: Block, origin: Origin) -> int | None:
        """The work offset a block selects, as the CL numbers it, or None."""
        found = [self.work_offsets[code] for code in block.g if code in self.work_offsets]
        if len(found) > 1:
            raise ControlError(origin, "two work offsets in one block")
        return found[0] if found else None

    def target(self, block: Block) -> list[float | None]:
        out = list(self.pos)
        for axis, letter in enumerate("XYZ"):
            if letter in block.values:
                value = block.values[letter]
                if self.absolute:
                    out[axis] = value
                else:
                    current = self.pos[axis]
                    out[axis] = None if current is None else current + value
        return out

    def motion_words(self, block: Block, origin: Origin) -> Iterator[Event]:
        g = block.g
        axes = any(letter in block.values for letter in "XYZ")
        if "28" in g or "30" in g:
            through = self.target(block)
            start: Point = (self.pos[0], self.pos[1], self.pos[2])
            named = [i for i, letter in enumerate("XYZ") if letter in block.values]
            self.pos = through
            yield Rapid(origin, start, (through[0], through[1], through[2]))
            yield from self.lose_position(origin, named)
            for letter in "XYZ":
                block.values.pop(letter, None)
            axes = False
        for code in g:
            if code in MOTIONS or code in self.cycles:
                if code in self.cycles and self.motion not in self.cycles:
                    self.initial_z = self.pos[2]
                self.motion = code
                if code in MOTIONS:
                    self.end_cycle()
            elif code == "80":
                self.motion = None
                self.end_cycle()
        if self.motion in self.cycles:
            for letter in "RQP":
                if letter in block.values:
                    self.cycle[letter] = block.values.pop(letter)
                    self.cycle_words_given.add(letter)
            if "Z" in block.values:
                self.cycle["Z"] = block.values["Z"]
        arc_mode = self.motion in ("2", "3")
        leftover = set(block.values) - set("XYZIJKRFST" if arc_mode
                                           else "XYZFST")
        if leftover:
            word = sorted(leftover)[0]
            raise ControlError(origin, f"{word} is not a word of "
                                       f"{'G' + self.motion if self.motion else 'this block'}")
        if self.motion in ("2", "3") and any(w in block.values for w in ("I", "J", "K", "R")):
            axes = True  # a centre without an end point: a full circle (end = start)
        if block.extra.get("rotary"):
            if self.motion not in ("0", "1"):
                raise ControlError(origin, "a rotary word outside G0/G1: not modelled")
            axes = True
        if not axes:
            return
        if self.motion is None:
            raise ControlError(origin, "axis words without a motion mode (G80 is active)")
        if self.motion in self.cycles:
            if self.comp_side is not None or self.comp_waiting is not None:
                raise ControlError(origin, "a canned cycle with cutter compensation on")
            yield from self.hole(block, origin)
        elif self.motion in ("0", "1"):
            yield from self.compensate(self.straight(block, origin), origin)
        else:
            yield from self.compensate(self.arc(block, origin), origin)

    def end_cycle(self) -> None:
        self.cycle = {}
        self.rigid = False
        self.initial_z = None

    def straight(self, block: Block, origin: Origin) -> Iterator[Event]:
        if self.kinematics is not None:
            yield from self.rotary_straight(block, origin)
            return
        start: Point = (self.pos[0], self.pos[1], self.pos[2])
        end = self.target(block)
        self.pos = end
        if self.motion == "0":
            yield Rapid(origin, start, (end[0], end[1], end[2]))
        else:
            if None in start or None in end:
                raise ControlError(origin, "a feed move from or to a position the program does "
                                           "not state (after a tool change or reference return)")
            yield FeedMove(origin, start, (end[0], end[1], end[2]), self.feed_rate(),
                           self.tooling())

    def rotary_straight(self, block: Block, origin: Origin) -> Iterator[Event]:
        """A G0/G1 on a machine with rotaries: start and end in the part frame, and the
        feed along the tip's path in the part (G93: that path in 1/F minutes; G94: the
        control's feed spread over the X Y Z length, or the angle where only it moves)."""
        kin = self.kinematics
        assert kin is not None  # straight() sends only a machine with rotaries here
        machine_start = list(self.pos)
        before = dict(self.rot)
        after = dict(before)
        ways: dict[str, str] = block.extra.get("ways", {})  # type: ignore[assignment]  # a dict read_extra put there
        for name, value in block.extra.get("rotary", {}).items():  # type: ignore[attr-defined]  # the dict execute() put there
            axis = kin.axis(name)
            modulo = axis is not None and axis.continuous and kin.wrap == "modulo"
            if name in ways and not modulo:
                raise ControlError(origin, f"{name.upper()}: a direction word on an axis the "
                                           f"machine does not declare modulo (rotary: wrap)")
            if not self.absolute:
                after[name] = before[name] + value
            elif modulo:
                low = -360.0 if self.modulo_way == "signed" and name not in ways else 0.0
                if not low < value < 360.0 and value != 0.0:
                    raise ControlError(origin, f"{name.upper()}{value:g}: a modulo axis's "
                                               f"angle is 0 to under 360")
                after[name] = modulo_turn(before[name], value, ways.get(name, self.modulo_way))
            else:
                after[name] = value + self.preset.get(name, 0.0)
            if axis is not None and axis.limits is not None and not (
                    axis.limits[0] - 1e-9 <= after[name] <= axis.limits[1] + 1e-9):
                raise ControlError(origin, f"{name.upper()}{after[name]:g} is beyond the axis's "
                                           f"limits {axis.limits[0]:g} to {axis.limits[1]:g}")
        end = self.target(block)
        self.pos = end
        self.rot = after
        start = self.to_part(machine_start, before)
        finish = self.to_part(end, after)
        if self.motion == "0":
            yield Rapid(origin, start, finish)
            return
        if None in machine_start or None in end:
            raise ControlError(origin, "a feed move from or to a position the program does "
                                       "not state (after a tool change or reference return)")
        turned = any(abs(after[n] - before[n]) > 1e-12 for n in after)
        if self.inverse_time and "F" not in block.values:
            raise ControlError(origin, "G93 (inverse time): a feed move needs its own F word")
        feed = self.feed_rate()
        length = None
        if turned or self.inverse_time:
            length = tip_path_length(kin, machine_start, before, end, after)  # type: ignore[arg-type]  # no None: checked above
            if self.inverse_time:
                feed = None if self.f is None else length * self.f
            elif feed is not None:
                linear = math.dist(machine_start, end)  # type: ignore[arg-type]  # no None: checked above
                travel = linear if linear > 1e-12 else max(
                    abs(after[n] - before[n]) for n in after)
                feed = feed * length / travel if travel > 0 else feed
        yield FeedMove(origin, start, finish, feed, self.tooling(), length if turned else None,
                       tool_axis(kin, after))

    def arc(self, block: Block, origin: Origin) -> Iterator[Event]:
        if self.kinematics is not None and (self.inverse_time
                                            or not is_identity(self.kinematics, self.rot)):
            raise ControlError(origin, "an arc in G93 or with the rotaries turned: not modelled")
        start: Point = (self.pos[0], self.pos[1], self.pos[2])
        end_list = self.target(block)
        if None in start or None in end_list:
            raise ControlError(origin, "an arc from or to a position the program does not state")
        end = (float(end_list[0]), float(end_list[1]), float(end_list[2]))  # type: ignore[arg-type]  # None refused above
        clockwise = self.motion == "2"
        a, b, n = PLANE_AXES[self.plane]
        radius = self.arc_radius(block)
        if radius is not None:
            centre = centre_from_radius(origin, start, end, radius, clockwise, self.plane)
        else:
            offsets = {0: block.values.get("I"), 1: block.values.get("J"),
                       2: block.values.get("K")}
            if offsets[n] not in (None, 0.0):
                raise ControlError(origin, f"{'IJK'[n]} is not a centre word of the "
                                           f"{self.plane.upper()} plane")
            if offsets[a] is None and offsets[b] is None:
                raise ControlError(origin, "an arc without a centre (I J K) or radius")
            c = [0.0, 0.0, 0.0]
            c[a] = float(start[a]) + (offsets[a] or 0.0)  # type: ignore[arg-type]  # None refused above
            c[b] = float(start[b]) + (offsets[b] or 0.0)  # type: ignore[arg-type]  # (as above)
            c[n] = float(start[n])  # type: ignore[arg-type]  # (as above)
            centre = (c[0], c[1], c[2])
        # two of the program's last digits: 0.002 mm, or 0.0002 inch after G20 (an inch
        # digit is 2.54 times a mm one; the post rounds the end and the centre to it)
        sweep, r = arc_geometry(origin, start, end, centre, clockwise, self.plane,
                                self.radius_tolerance * (2.54 if self.inch else 1.0))
        self.pos = list(end)
        yield ArcMove(origin, start, end, centre, clockwise, self.plane, sweep, r,
                      self.feed_rate(), self.tooling())

    def arc_radius(self, block: Block) -> float | None:
        return block.values.get("R")

    def cycle_data(self, origin: Origin, letters: str) -> tuple[str, str, float, float]:
        """(G code, kind, R, Z) of the active cycle, its block's words checked against it.

        Only the words of this block count: one kept from another cycle is unused.
        """
        code = self.motion or ""
        kind, words = self.cycles[code]
        for letter in letters:
            if letter in self.cycle_words_given and letter not in words \
                    and not (letter == "Q" and self.rigid and kind == "tap"):
                raise ControlError(origin, f"{letter} is not a word of G{code}")
        if not self.absolute:
            raise ControlError(origin, "canned cycles in G91 are not modelled")
        if "R" not in self.cycle or "Z" not in self.cycle:
            raise ControlError(origin, f"G{code} needs R and Z")
        return code, kind, self.cycle["R"], self.cycle["Z"]

    def hole(self, block: Block, origin: Origin) -> Iterator[Event]:
        if self.kinematics is not None and (self.inverse_time
                                            or not is_identity(self.kinematics, self.rot)):
            raise ControlError(origin, "a drilling cycle in G93 or with the rotaries turned: "
                                       "not modelled")
        code, kind, r, bottom = self.cycle_data(origin, "PQ")
        words = self.cycles[code][1]
        if bottom > r:
            raise ControlError(origin, f"a G{code} hole with its bottom Z{bottom:g} above "
                                       f"R{r:g} (in canned-cycle mode every block with an "
                                       f"axis word is another hole)")
        z = self.pos[2]  # None after a tool change: the cycle positions from up there
        end = self.target(block)
        if end[0] is None or end[1] is None:
            raise ControlError(origin, "a hole at an X Y the program does not state")
        x, y = float(end[0]), float(end[1])
        peck = self.cycle.get("Q", 0.0) if kind in ("peck", "chip_break") or self.rigid \
            else 0.0
        if kind in ("peck", "chip_break") and peck <= 0:
            raise ControlError(origin, f"G{code} needs a peck Q greater than 0")
        direction = self.spindle
        if kind == "tap":
            direction = self.tap_direction(code, origin)
            if self.rigid:
                kind = "rigid_tap"
        initial = self.initial_z if self.initial_z is not None else z
        leave: float | None = r if self.retract_to_r else \
            None if initial is None else max(initial, r)
        start: Point = (self.pos[0], self.pos[1], z)
        yield Rapid(origin, start, (x, y, z))
        yield Rapid(origin, (x, y, z), (x, y, r))
        dwell = self.cycle_dwell(self.cycle.get("P", 0.0)) if "P" in words else 0.0
        self.pos = [x, y, leave]
        # G76's Q is modal as a peck's is: one left from an earlier cycle shifts this hole
        shift = self.cycle.get("Q", 0.0) if kind == "fine_bore" else None
        yield Hole(origin, (x, y, z), x, y, r, bottom, leave, kind, direction, dwell, peck,
                   self.feed_rate(), self.tooling(), shift=shift)

    def tap_direction(self, code: str, origin: Origin) -> str:
        """G84 taps right-hand (the spindle must turn M3), G74 left-hand (M4)."""
        wanted = "ccw" if code == "74" else "cw"
        if self.spindle != wanted:
            raise ControlError(origin, f"G{code} with the spindle "
                                       f"{'off' if self.spindle == 'off' else self.spindle}")
        return wanted

    def cycle_dwell(self, value: float) -> float:
        """A cycle's P in seconds (ISO: seconds)."""
        return value
