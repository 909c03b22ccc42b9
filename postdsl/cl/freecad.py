"""FreeCAD Path commands -> CL records, from either textual form FreeCAD writes.

FreeCAD keeps toolpaths as *machine-neutral G-code* (``Path.Command``: a name
such as ``G1`` plus ``Letter: float`` arguments, sorted alphabetically) and
hands them to a post script.  Two texts of that stream occur in practice:

* the **dump** post's listing (seed 000, appendix 2)::

      (Path: Pocket_Shape)
      Command (Pocket_Shape) [ ]
      Command G1 [ F:3.3333 X:7 Y:-7 Z:12.5 ]

  ``(Path: label)`` starts each path object (operation or tool controller),
  ``(compound: label)`` a group of them; ``Command … [ ]`` is one command
  (older FreeCAD printed ``( … )`` instead of ``[ … ]``; both are read).  The
  dump post writes a banner of bare ``(…)`` notes about itself before its
  first record: they describe the dump, not the toolpath, so they become no
  record.  Any other bare ``(…)`` line in a dump is an error.
* **plain** G-code, one command a line: the internal path as
  ``Path.toGCode()`` writes it, or what FreeCAD's post-processors (linuxcnc,
  grbl, …) make of it::

      G1 F3.333300 X7.000000 Y-7.000000 Z12.500000        (Path.toGCode)
      N120 G1 X7.000 Y-7.000 Z12.500 F200.000             (a post)

  A line holding several command words is split at each G/M word, as
  FreeCAD's ``Path.setFromGCode`` does; a line of axis words alone repeats the
  motion in force (RS274); ``N`` words, ``%`` and ``;`` comments (posts) are read.

The form is decided once per file (the first line that only one form can
hold), and a line of the other form is an error: mixing them is a sign of a
damaged file.

**Feeds.**  The internal path's feeds are **mm/s**, a post's **mm/min**, and
nothing in a single ``F`` says which: reading one as the other cuts 60 times
too fast or too slow.  So the unit comes from evidence in the first lines
(the dump form or six decimals on every number: the internal path; a post's
banner, its ``(machine units: mm/min)`` comment, ``G21``, ``G43``, ``%``, ``;``
or ``N`` words: a post), or from the user (``feed_units``); with neither, the
first ``F`` is an error asking for it.  ``F`` on ``G0`` is the internal path's
rapid rate (often ``F:0``) and is not a feed; in a post's output it is RS274's
modal feed.  ``F`` 0 on a cutting move is an error (the tool controller has no
feed rate), and so is a cutting move before any feed.

**A whole program.**  The last line must end with a line end (a line cut
inside still reads as G-code) unless it ends the program (FreeCAD writes its
postamble ``M5 M2`` without one), and a post's output must end with ``M2`` or
``M30``, which every FreeCAD post writes.  The internal path has no end record.

**Before the first tool.**  A ``G0`` in Z alone, before any tool change and any
move in X or Y (the Job's fixture: ``G54``, ``G0 Z<clearance>``), is the CAM's
"go safe": a ``safe_retract`` record, which a post with a tool changer writes as
its own retract.  ``G61``, ``G61.1`` and ``G64 P`` (FreeCAD's preamble option
writes ``G64 P0.01``) are the path-control mode, an ``input_modes`` fact; ``G94``
and ``G91.1`` state what the CL already means.

What FreeCAD's conventions mean for the CL (FreeCAD documentation, seed 004):

* omitted ``X Y Z`` keep their value; ``I J K`` are relative to the start
  point and become the absolute centre ``cx cy cz`` (an omitted one is 0).
* ``G90``/``G91`` select absolute/incremental ``X Y Z``: both are modelled
  (incremental values are added to the current position).  Drilling cycles
  under ``G91`` are refused: their incremental R/Z rules are controller
  specific and a wrong guess drills to the wrong depth.
* ``G17``/``G18``/``G19`` select the arc plane; ``G21`` (mm) is accepted,
  ``G20`` (inch) refused.  ``G41 D``/``G42 D``/``G40``: cutter_compensation where the
  side changes (a G40 in force is no record).  ``G49``, ``G43 H``
  of the loaded tool (the post writes its own length offset; another H, or
  none loaded, is an error) and ``G54`` (the first work offset, which every
  post assumes)
  state what the CL already means and are accepted without a record; other
  work offsets and cutter compensation are refused, because the CL has no
  way to carry them and dropping them would move the part.
* ``M6 T`` -> tool_change, ``M3/M4 S`` -> spindle_on (``S`` may be omitted
  once a speed is known), ``M5`` -> spindle_off, ``M7``/``M8`` -> coolant_on
  mist/flood, ``M9`` -> coolant_off, ``G95`` (F per revolution: F times the speed in
  force is the CL's mm/min; a cutting move with no speed is refused) and ``G94``
  (per minute) -> no record, ``G4 P`` (s) -> dwell, ``M0``/``M1`` (Path's
  Stop, mandatory/optional) -> program_stop/optional_stop, ``M2``/``M30`` ->
  program_end (nothing may follow it), ``(text)`` -> comment,
  ``(Path: label)`` -> operation.

Drilling (``G81`` ``G82`` ``G83`` ``G73`` ``G84`` ``G74`` with ``X Y Z R Q P F``, ``G80``,
``G98``/``G99``): FreeCAD gives only ``R``, the plane where the feed starts
(its "RetractHeight", by default 1 mm above the hole's start depth), and
``Z``, the absolute bottom; it has no separate hole top.  The CL geometry is
therefore ``top = R``, ``clearance = 0``, ``depth = R - Z`` (so the CL bottom
is exactly ``Z``).  Where the tool leaves to follows the canned-cycle return
mode FreeCAD writes before the holes (its ``ReturnLevel`` property): ``G99``
-> ``retract = R``; ``G98`` -> the higher of ``R`` and the Z the tool was at
when the cycle started.  Without either, ``G98`` is assumed (the usual RS274
power-on state, and never lower than ``R``).  Each ``G90``/``G91``,
``G17``-``G19`` and ``G98``/``G99`` also gives an input_modes record with
the one mode its line set, where the line is, so a post may echo the words
FreeCAD's own posts echo.  ``G81`` -> single_peck,
``G82`` -> single_peck with ``dwell = P`` (s), ``G83`` -> deep_drill with
``peck = Q``, ``G73`` -> break_chip with ``peck = Q``, ``G84``/``G74`` ->
tapping/tapping_ccw.  The first hole gives
cycle_start + the setup; each further hole with the same cycle and the same
``R Z Q P F`` and return level gives cycle_hole; ``G80`` or any other command
gives cycle_end (in RS274 any other motion cancels a canned cycle too).  On a
further hole of the same cycle omitted ``R Z Q P F`` keep the cycle's values,
as canned cycles are modal (another kind of cycle must give its own).  After
a hole the tool is at the hole's X Y and the retract Z.

Every line that is not one of the above is a located :class:`CLError` naming
the file, the line and its content; nothing is skipped silently.
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from decimal import Decimal

from postdsl.cl.model import (
    ArcMove,
    Boring,
    BoringSpindleStop,
    BreakChip,
    CLCommand,
    Comment,
    CoolantOff,
    CoolantOn,
    CutterCompensation,
    CycleEnd,
    CycleHole,
    CycleStart,
    DeepDrill,
    DrillSetup,
    Dwell,
    InputModes,
    LinearMove,
    MachineRetract,
    Operation,
    OptionalStop,
    ProgramEnd,
    ProgramStart,
    ProgramStop,
    RapidMove,
    SafeRetract,
    SinglePeck,
    SpindleOff,
    SpindleOn,
    Tapping,
    TappingCcw,
    ToolChange,
    WorkOffset,
)
from postdsl.cl.native import MoveSink
from postdsl.cl.plain import linear_move, rapid_move
from postdsl.cl.record_log import RecordLog
from postdsl.errors import CLError, Location
from postdsl.kinematics import Kinematics, RotaryAxis, is_identity, to_part

__all__ = ["FEED_UNITS", "looks_like_freecad", "read_freecad", "starts_gcode_line"]

#: feed units a FreeCAD file may be in, and the factor to the CL's mm/min
FEED_UNITS: dict[str, float] = {"mm/min": 1.0, "mm/s": 60.0}

_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_DUMP_ARG = re.compile(rf"^(?P<letter>[A-Za-z]):(?P<value>{_NUMBER})$")
_PATH_RECORD = re.compile(r"^\((?P<kind>Path|compound):\s?(?P<label>.*)\)$")
_PLAIN_WORD = re.compile(rf"(?P<letter>[A-Za-z])[ \t]*(?P<value>{_NUMBER})")
_COMMAND_NAME = re.compile(r"^(?P<letter>[GM])(?P<number>\d+(?:\.\d+)?)$")
#: a block number word (FreeCAD's posts write them with OUTPUT_LINE_NUMBERS)
_BLOCK_NUMBER = re.compile(r"[Nn]\d+(?=[^\d]|$)[ \t]*")
#: what a G-code line of either form may start with (after a block number)
_SHAPE = re.compile(r"(?:Command\s|\(|;|%|[GgMm][ \t]*[\d.]|[XYZIJKFxyzijkf][ \t]*[-+\d.])")
#: every number ``Path.toGCode()`` writes has six decimals
_SIX_DECIMALS = re.compile(r"[-+]?\d+\.\d{6}$")
_ANY_NUMBER = re.compile(rf"[A-FH-LO-Za-fh-lo-z][ \t]*({_NUMBER})")

#: command -> the argument letters it accepts
_ARGUMENTS: dict[str, str] = {
    "G0": "XYZABCF",
    "G1": "XYZABCF",
    "G2": "XYZIJKF",
    "G3": "XYZIJKF",
    "G4": "P",
    "G17": "", "G18": "", "G19": "", "G21": "", "G40": "", "G43": "H", "G49": "",
    "G41": "D", "G42": "D",
    **{f"G{n}": "" for n in range(54, 60)},
    "G73": "XYZRQPF",
    "G74": "XYZRPF",
    "G80": "",
    "G81": "XYZRF",
    "G82": "XYZRPF",
    "G83": "XYZRQPF",
    "G84": "XYZRPF",
    "G85": "XYZRF", "G86": "XYZRPF", "G89": "XYZRPF",
    "G90": "", "G91": "", "G98": "", "G99": "",
    "G61": "", "G61.1": "", "G64": "PQ", "G94": "", "G95": "", "G91.1": "",
    "M0": "", "M1": "", "M2": "", "M30": "",
    "M3": "S", "M4": "S", "M5": "",
    "M6": "T", "F": "F", "S": "S", "T": "T", "G28": "Z", "G53": "Z",
    "M7": "", "M8": "", "M9": "",
}

#: commands the CL cannot carry, with the reason given to the user
_REFUSED: dict[str, str] = {
    "G20": "inch units (G20) are not supported: post the job in mm (G21)",
    "G38.2": "probing (G38.2) cannot be carried by the CL: probing is written as the post's "
             "custom cycles",
}

#: commands a FreeCAD post writes that the CL already means, read and not recorded by rule
_IMPLIED = {
    "G21": "mm: the CL is in mm",
    "G49": "tool length compensation off: the post writes its own with each tool change",
    "G94": "feed per minute: the CL's feeds are mm/min",
    "G91.1": "arc centres I J K relative to the start point, as they are read",
}

#: the work offsets RS274 names, as the CL numbers them
_WORK_OFFSETS = {f"G{n}": n - 53 for n in range(54, 60)}

#: the path-control modes (RS274/NGC G61, G61.1, G64), as input_modes says them
_PATH_MODES = {"G61": "exact_stop", "G61.1": "exact_path", "G64": "blend"}

_DRILLS: dict[str, type[DrillSetup]] = {
    "G81": SinglePeck, "G82": SinglePeck, "G83": DeepDrill, "G73": BreakChip,
    "G84": Tapping, "G74": TappingCcw,
    "G85": Boring, "G89": Boring, "G86": BoringSpindleStop}
_PLANES = {"G17": "xy", "G18": "zx", "G19": "yz"}


def looks_like_freecad(lines: list[str]) -> bool:
    """Detector: every sampled line is a FreeCAD dump record, a comment or a G-code block,
    and nothing in them says that another CAM system wrote it.

    Lines FreeCAD's posts share with every RS274 program (``%``, ``N`` words, ``;``,
    ``G21``, ``G43``) without FreeCAD's own banner or ``(machine units: …)`` note are any
    CAM's G-code: the G-code reader (:mod:`postdsl.cl.gcode`) reads them.  Lines with no
    evidence at all stay FreeCAD's, whose reader asks for the unit of F.
    """
    if not lines or not all(starts_gcode_line(line) for line in lines):
        return False
    window = [(number, line.strip()) for number, line in enumerate(lines, start=1)]
    return not _judge(window, _is_dump(window)).generic


def starts_gcode_line(line: str) -> bool:
    """One line as FreeCAD's texts start one: a dump record, a comment, ``%`` or a block."""
    text = line.strip()
    match = _BLOCK_NUMBER.match(text)
    if match:
        text = text[match.end():]
        if not text:
            return True
    return text == "%" or bool(_SHAPE.match(text))


@dataclass(slots=True)
class _Command:
    """One FreeCAD command as read from a line: its name and arguments."""

    name: str
    args: dict[str, float]
    line: int
    text: str


@dataclass
class _Cycle:
    """The open drilling cycle: what makes a further hole part of it, and its modal values."""

    key: tuple[object, ...]
    r: float
    z: float
    q: float | None
    p: float | None
    feed: float
    #: the Z the tool was at when the cycle started (G98's return level)
    initial: float | None


@dataclass
class _Evidence:
    """What the file says about who wrote it: the feed unit follows from that."""

    #: "mm/min" (a FreeCAD post's output), "mm/s" (FreeCAD's internal path) or None
    units: str | None
    #: the line and text that say so, for messages
    reason: str = ""
    line: int = 0
    #: a post's output: it ends with M2 or M30, so a file without one is cut short
    post: bool = False
    #: only what every RS274 program writes says so (no FreeCAD banner or note)
    generic: bool = False


@dataclass
class _State:
    file: str
    records: list[CLCommand] = field(default_factory=list)
    pos: list[float | None] = field(default_factory=lambda: [None, None, None])
    incremental: bool = False
    plane: str = "xy"
    return_level: str = "G98"
    #: the work offset in force (G54-G59: 1-6); 1 until the program selects another
    work_offset: int = 1
    #: the cutter compensation in force (G40: off, G41: left, G42: right)
    compensation: str = "off"
    #: whether the file wrote G98 or G99 (the fact a post may want), not the assumption
    return_given: bool = False
    speed: float | None = None
    cycle: _Cycle | None = None
    ended: bool = False
    evidence: _Evidence = field(default_factory=lambda: _Evidence(None))
    #: mm/min per unit of F; None while the file does not say (and the user did not)
    feed_factor: float | None = None
    #: the feed in force (mm/min), once one was given
    feed: float | None = None
    tool: int | None = None
    #: the motion command a block without G word repeats (RS274 modal motion)
    modal: str | None = None
    started: bool = False
    #: a feed set by a block without a move (``F500`` alone): the next cutting move
    #: carries it, since the CL's feed in force is the last move's
    feed_unsent: bool = False
    #: the tool a T word selected for the next M6 (RS274: ``T1`` then ``M6``)
    selected: int | None = None
    #: the spindle's direction while it turns ("cw"/"ccw"), None while stopped
    spindle: str | None = None
    #: G20 in force: lengths and feeds are inches, converted to mm by the block reader
    inch: bool = False
    #: the line of M2 or M30
    end_line: int = 0
    #: the rotary words in force (A, B or C: degrees), once a move gave one
    rot: dict[str, float] = field(default_factory=dict)
    #: the last move had the part turned (its tip on the part differs from X Y Z)
    turned: bool = False
    #: G95 in force (plain G-code): F is per revolution, the CL's feed is F times the
    #: speed in force, converted when a move needs it (RS274 sets F before S in a block)
    per_rev: bool = False
    #: the feed per revolution in force (mm), once G95's F was given
    per_rev_feed: float | None = None


#: lines looked at to judge who wrote a file, as format detection does
_EVIDENCE_WINDOW = 200

#: what RS274 itself says of plain G-code (the G-code reader): F is per minute (G94)
_RS274_EVIDENCE = _Evidence("mm/min", "RS274 G-code: F is per minute (G94)", 0, False)

#: reads one G-code block (stripped) into its commands in RS274's order of execution
BlockReader = Callable[["_State", str, int], list["_Command"]]


def read_freecad(lines: Iterable[str], file: str = "<cl>",
                 feed_units: str | None = None, sink: MoveSink | None = None,
                 log: RecordLog | None = None,
                 block_reader: BlockReader | None = None) -> Iterator[CLCommand]:
    """Stream CL commands from a FreeCAD dump or FreeCAD G-code; errors name file:line.

    ``feed_units`` ("mm/min" or "mm/s") is the user's word on the unit of F, needed
    when the file gives no evidence of who wrote it; evidence it contradicts is an error.
    With ``sink`` (a first pass's fold), the plain G0 and G1 moves are handed to it as
    values instead of being made commands; every check runs all the same.  ``log`` then
    keeps each of them as its fields (see :func:`postdsl.cl.readers.replay`).
    ``block_reader`` reads a whole block as plain RS274 G-code does (the G-code reader,
    :mod:`postdsl.cl.gcode`): F is then per minute by RS274's rule, not by evidence.
    """
    numbered = enumerate(lines, start=1)
    window: list[tuple[int, str]] = []  # the first lines that are not blank, stripped
    for number, raw in numbered:
        text = raw.strip()
        if text:
            window.append((number, text))
            if len(window) == _EVIDENCE_WINDOW:
                break
    dump = block_reader is None and _is_dump(window)
    state = _State(file)
    state.evidence = _judge(window, dump) if block_reader is None else _RS274_EVIDENCE
    state.feed_factor = _feed_factor(state.evidence, feed_units, file)
    yield ProgramStart()
    seen_record = False  # the dump post's banner comes before its first record
    last = 0
    records = state.records
    plain_move = (_PLAIN_DUMP_MOVE if dump else _PLAIN_MOVE).match
    # after the window, the lines as read: the commonest line, which the pattern takes
    # whole, has no blank around it; any other line is stripped first
    for number, text in itertools.chain(window, numbered):
        plain = plain_move(text)
        if plain is not None and not state.ended and len(text) < _FINITE_LINE:
            move = _plain_move(state, plain.groups(), number, sink, log)
            if move is not None:
                last = number
                seen_record = True
                state.started = True
                if move is not _TAKEN:
                    yield move  # type: ignore[misc]  # _TAKEN is the only _Taken
                continue
        text = text.strip()
        if not text:
            continue
        last = number
        if not dump and block_reader is None:
            plain = _PLAIN_LINE.match(text)
            if plain is not None and not state.ended:  # the common line, as below
                command = _plain_command(plain, text, number, file)
                if (command.name == "G1" or command.name == "G0") and state.cycle is None \
                        and command.args.keys() <= _MOVE_LETTERS:
                    _move(state, command)  # as _command's own fast path does
                else:
                    _command(state, command)
                state.started = True
                if records:
                    yield from records
                    records.clear()
                continue
        elif text.startswith("Command") and not state.ended:  # the common record, as below
            seen_record = True
            _command(state, _dump_command(text, number, file))
            state.started = True
            if records:
                yield from records
                records.clear()
            continue
        where = Location(file, number)
        if text == "%" and not dump:
            if state.started and not state.ended:
                raise CLError("'%' inside the program (it marks the start and end of the "
                              "tape)", where)
            continue
        if state.ended:
            raise CLError(f"nothing may follow the program end: {_shorten(text)}", where)
        if dump:
            record = _PATH_RECORD.match(text)
            if record:
                seen_record = True
                _close_cycle(state, number, "other")
                state.records.append(Operation(operation=record["label"].strip(), line=number))
            elif text.startswith("Command"):
                seen_record = True
                _command(state, _dump_command(text, number, file))
            elif text.startswith("(") and text.endswith(")") and not seen_record:
                pass  # the dump post's banner about itself (see the module docstring)
            elif text.startswith("(") and text.endswith(")"):
                raise CLError(f"a FreeCAD dump writes comments as 'Command (…) [ ]'; "
                              f"unexpected line: {_shorten(text)}", where)
            else:
                raise CLError(f"not a FreeCAD dump record (expected 'Command …' or "
                              f"'(Path: …)'): {_shorten(text)}", where)
        else:
            if text.startswith("Command"):
                raise CLError(f"a dump record in plain FreeCAD G-code: {_shorten(text)}", where)
            # axis words alone repeat the motion in force, or the open drilling cycle
            # at another hole (RS274; FreeCAD's --modal writes "X30.000" so)
            modal = state.modal or (str(state.cycle.key[0]) if state.cycle else None)
            commands = _plain_commands(text, number, file, modal) \
                if block_reader is None else block_reader(state, text, number)
            for command in commands:
                _command(state, command)
        if not text.startswith(("(", ";")):
            state.started = True  # comments may come before a leading '%'
        yield from state.records
        state.records.clear()
    if not getattr(lines, "final_newline", True) and not (state.ended and state.end_line == last):
        # a last line that ends the program (M2, M30) is whole: a cut M30 reads as M3,
        # and a program without its end is refused below
        raise CLError("the last line has no line end: the file may be cut inside it (a cut "
                      "'G0 X30' still reads as 'G0 X3'); a complete file ends with a line end",
                      Location(file, last))
    if state.evidence is _RS274_EVIDENCE and not state.ended:
        raise CLError("the program ends without M2 or M30 (RS274's end of program): the file "
                      "may be cut short; a complete program ends with M2 or M30",
                      Location(file, last or 1))
    if state.evidence.post and not state.ended:
        raise CLError(f"the program ends without M2 or M30, which FreeCAD's posts write at the "
                      f"end of every program ({state.evidence.reason}): the file is cut short",
                      Location(file, last or 1))
    _close_cycle(state, 0, "other")
    yield from state.records
    if not state.ended:
        yield ProgramEnd()


def _is_dump(numbered: list[tuple[int, str]]) -> bool:
    """True when the first line only one form can hold is a dump record."""
    for _, text in numbered:
        if text.startswith("Command") or _PATH_RECORD.match(text):
            return True
        if not (text.startswith("(") and text.endswith(")")):
            return False
    return False


#: comments only FreeCAD's posts write: their banner and the machine's feed unit
_POST_BANNER = re.compile(r"\((?:Exported by FreeCAD|Post Processor:)", re.IGNORECASE)
_MACHINE_UNITS = re.compile(r"\(machine[^()]*?\b(mm/min|in/min|mm/s)\)", re.IGNORECASE)
_POST_WORDS = re.compile(r"(?:^|[\s\d.])(G21|G43)(?![\d.])", re.IGNORECASE)


def _judge(window: list[tuple[int, str]], dump: bool) -> _Evidence:
    """Who wrote the file, judged from its first lines; see the module docstring."""
    if dump:
        return _Evidence("mm/s", "the FreeCAD dump form of the internal path", 0)
    for number, text in window:
        text = _BLOCK_NUMBER.sub("", text, count=1)  # a post numbering every line
        if _POST_BANNER.match(text):
            return _Evidence("mm/min", f"line {number}: {_shorten(text, 40)}", number, True)
        units = _MACHINE_UNITS.match(text)
        if units:
            unit = units.group(1).lower()
            return _Evidence(unit if unit != "in/min" else None,
                             f"line {number}: {_shorten(text, 40)}", number, True)
    for number, text in window:
        code = text.split("(", 1)[0].split(";", 1)[0]
        if text == "%" or text.startswith(";") or _BLOCK_NUMBER.match(text) \
                or _POST_WORDS.search(code):
            return _Evidence("mm/min", f"line {number}: {_shorten(text, 40)}, as FreeCAD's "
                             f"posts write", number, True, generic=True)
    numbers = [(number, value) for number, text in window if not text.startswith("(")
               for value in _ANY_NUMBER.findall(text)]
    if numbers and all(_SIX_DECIMALS.match(value) for _, value in numbers):
        return _Evidence("mm/s", "every number has six decimals, as FreeCAD's Path.toGCode() "
                         "writes the internal path", numbers[0][0])
    return _Evidence(None)


def _feed_factor(evidence: _Evidence, feed_units: str | None, file: str) -> float | None:
    if feed_units is not None:
        if evidence.units is not None and evidence.units != feed_units:
            raise CLError(f"--feed-units {feed_units} contradicts the file: its feeds are "
                          f"{evidence.units} ({evidence.reason})",
                          Location(file, evidence.line or None))
        return FEED_UNITS[feed_units]
    return FEED_UNITS[evidence.units] if evidence.units else None


# --- parsing lines ------------------------------------------------------------------------


def _normal_name(raw: str, number: int, file: str, text: str) -> str:
    match = _COMMAND_NAME.match(raw.upper())
    if match is None:
        raise CLError(f"'{raw}' is not a G or M command: {_shorten(text)}", Location(file, number))
    value = match["number"]
    if "." in value:
        whole, fraction = value.split(".")
        value = f"{int(whole)}.{fraction.rstrip('0')}".rstrip(".")
    else:
        value = str(int(value))
    return match["letter"] + value


def _number(raw: str, letter: str, number: int, file: str, text: str) -> float:
    value = float(raw)
    if not math.isfinite(value):
        raise CLError(f"{letter} is not a finite number: {_shorten(text)}", Location(file, number))
    return value


def _dump_parts(text: str) -> tuple[str, str] | None:
    """``Command NAME [ args ]`` (or older ``( args )``) -> (NAME, args), scanning once.

    A regular expression with a lazy name and optional blanks backtracks on every blank
    of a long line; this never looks at a character twice.
    """
    if not text.startswith("Command") or len(text) < 8 or not text[7].isspace():
        return None
    close = text[-1]
    opening = {"]": "[", ")": "("}.get(close)
    if opening is None:
        return None
    index = text.rfind(opening)
    if index < 8:
        return None
    args = text[index + 1:-1]
    if any(c in args for c in "[]()"):
        return None
    return text[8:index].strip(), args


#: the common dump record: ``Command G1 [ F:3.3333 X:7 Y:-7 ]`` with upper-case letters and
#: plain decimals.  Precompiled and unambiguous, so linear; anything else (comments, old
#: brackets, exponents, stray blanks) takes the general path.
_PLAIN_DUMP = re.compile(r"Command ([GM]\d+) \[((?: [A-Z]:[-+]?(?:\d+\.?\d*|\.\d+))*) \]\Z")


def _dump_command(text: str, number: int, file: str) -> _Command:
    plain = _PLAIN_DUMP.match(text)
    if plain is not None:  # the fast path: what the general reading makes of such a record
        name = plain.group(1)
        if name not in _ARGUMENTS:
            name = _normal_name(name, number, file, text)
        words = plain.group(2).split()
        args = {word[0]: float(word[2:]) for word in words}
        if len(args) == len(words) and math.isfinite(sum(args.values())):
            return _Command(name, args, number, text)
    return _dump_any_command(text, number, file)


def _dump_any_command(text: str, number: int, file: str) -> _Command:
    where = Location(file, number)
    parts = _dump_parts(text)
    if parts is None:
        raise CLError(f"malformed dump record (expected 'Command NAME [ A:1 B:2 ]'): "
                      f"{_shorten(text)}", where)
    name, args_text = parts
    if name.startswith("(") and name.endswith(")"):
        if args_text.strip():
            raise CLError(f"a comment record takes no arguments: {_shorten(text)}", where)
        return _Command("(", {}, number, name[1:-1])
    if not name:
        raise CLError(f"dump record without a command name: {_shorten(text)}", where)
    args: dict[str, float] = {}
    for token in args_text.split():
        arg = _DUMP_ARG.match(token)
        if arg is None:
            raise CLError(f"malformed argument '{token}' (expected Letter:number): "
                          f"{_shorten(text)}", where)
        letter = arg["letter"].upper()
        if letter in args:
            raise CLError(f"argument {letter} given twice: {_shorten(text)}", where)
        args[letter] = _number(arg["value"], letter, number, file, text)
    return _Command(_normal_name(name, number, file, text), args, number, text)


#: the common line: one G or M command first, then argument words (no G or M) apart by one
#: blank, in upper case, plain decimals (``G1 X7.000 Y-7.000 F200.000``).  Precompiled and
#: unambiguous, so linear; anything else takes the general word-by-word path.
_PLAIN_LINE = re.compile(r"(?:N\d+ )?([GM]\d+)((?: [A-FH-LN-Z][-+]?(?:\d+\.?\d*|\.\d+))*)\Z")


def _plain_command(plain: re.Match[str], text: str, number: int, file: str) -> _Command:
    """The one command of a line :data:`_PLAIN_LINE` matched: what the word-by-word loop of
    :func:`_plain_commands` makes of it, without the loop."""
    name = plain.group(1)
    if name not in _ARGUMENTS:  # G01, M03...: the general spelling rules
        name = _normal_name(name, number, file, text)
    words = plain.group(2).split()
    args = {word[0]: float(word[1:]) for word in words}
    if len(args) != len(words) or not math.isfinite(sum(args.values())):
        [command] = _plain_words(text, number, file, None)  # its own error, at its word
        return command
    return _Command(name, args, number, text)


def _plain_commands(text: str, number: int, file: str,
                    modal: str | None = None) -> list[_Command]:
    """The commands of one G-code line; ``modal`` is the motion a block without G repeats."""
    plain = _PLAIN_LINE.match(text)
    if plain is not None:
        return [_plain_command(plain, text, number, file)]
    return _plain_words(text, number, file, modal)


def _plain_words(text: str, number: int, file: str, modal: str | None) -> list[_Command]:
    """The word-by-word reading of a line, for every line the fast path does not take."""
    where = Location(file, number)
    block = _BLOCK_NUMBER.match(text)
    body = text[block.end():] if block else text
    offset = len(text) - len(body)
    if not body:
        return []
    if body.startswith(";"):
        return [_Command("(", {}, number, body[1:].strip())]
    if body.startswith("("):
        if not body.endswith(")") or body.count("(") != body.count(")"):
            raise CLError(f"malformed comment (a comment line is '(text)'): {_shorten(text)}",
                          where)
        return [_Command("(", {}, number, body[1:-1])]
    commands: list[_Command] = []
    position = 0
    length = len(body)
    while position < length:
        while position < length and body[position] in " \t":
            position += 1
        if position == length:
            break
        word = _PLAIN_WORD.match(body, position)
        if word is None:
            rest = body[position:].strip()
            raise CLError(f"cannot read '{_shorten(rest, 20)}' (expected words like X12.5, "
                          f"one command a line, comments on their own line): "
                          f"{_shorten(text)}", Location(file, number, offset + position + 1))
        letter = word["letter"].upper()
        if letter in "GM":
            name = _normal_name(letter + word["value"], number, file, text)
            commands.append(_Command(name, {}, number, text))
        elif not commands and modal is not None and letter in "XYZIJK":
            # RS274: a block of axis words repeats the motion in force (FreeCAD's posts
            # write such blocks when they leave out repeated commands)
            commands.append(_Command(modal, {}, number, text))
            commands[-1].args[letter] = _number(word["value"], letter, number, file, text)
        elif not commands:
            raise CLError(f"a line must start with a G or M command: {_shorten(text)}", where)
        else:
            args = commands[-1].args
            if letter in args:
                raise CLError(f"argument {letter} given twice: {_shorten(text)}", where)
            args[letter] = _number(word["value"], letter, number, file, text)
        position = word.end()
    if not commands:
        raise CLError(f"a line must start with a G or M command: {_shorten(text)}", where)
    return commands


# --- meaning ------------------------------------------------------------------------------


def _command(state: _State, command: _Command) -> None:
    """Turn one FreeCAD command into CL records appended to ``state.records``."""
    name = command.name
    if (name == "G1" or name == "G0") and state.cycle is None \
            and command.args.keys() <= _MOVE_LETTERS:
        _move(state, command)  # the common command: nothing below applies to it
        return
    where = Location(state.file, command.line)
    if name[0] == "=":  # the G-code reader's motion word alone: the mode, no move
        _close_cycle(state, command.line, "motion")
        state.modal = name[1:]
        return
    if name == "(":
        _close_cycle(state, command.line, "other")
        state.records.append(Comment(comment=command.text, line=command.line))
        return
    if name in _REFUSED:
        raise CLError(f"{_REFUSED[name]}: {_shorten(command.text)}", where)
    allowed = _ARGUMENTS.get(name)
    if allowed is None:
        raise CLError(f"unknown FreeCAD command {name}: {_shorten(command.text)}", where)
    for letter in command.args:
        if letter not in allowed:
            accepts = " ".join(allowed) or "no arguments"
            raise CLError(f"{name} takes {accepts}, not {letter}: {_shorten(command.text)}",
                          where)
    if (name in _DRILLS or name in ("G2", "G3")) and any(
            abs(math.remainder(angle, 360.0)) > 1e-9 for angle in state.rot.values()):
        raise CLError(f"{name} with the rotary at {_rotary_text(state)}: arcs and drilling "
                      f"cycles are read with the rotaries at zero only: {_shorten(command.text)}",
                      where)
    if name in _DRILLS:
        _drill(state, command)
        state.modal = None
        return
    if name not in ("G98", "G99"):  # a return level sets how the next holes leave
        _close_cycle(state, command.line, _ENDED_BY.get(name, "other"))
    if name in ("G94", "G95"):
        _feed_mode(state, command)
        return
    if name in _IMPLIED:
        return  # states what the CL already means: read, and no record by rule
    args, line = command.args, command.line
    records = state.records
    if name in ("G0", "G1", "G2", "G3"):
        state.modal = name
    if name in ("G0", "G1"):
        _move(state, command)
    elif name in ("G2", "G3"):
        _arc(state, command)
    elif name == "G4":
        if "P" not in args or args["P"] < 0:
            raise CLError(f"G4 needs a dwell time P (seconds, not negative): "
                          f"{_shorten(command.text)}", where)
        records.append(Dwell(dwell=args["P"], line=line))
    elif name in _PLANES:
        state.plane = _PLANES[name]
        records.append(InputModes(active_plane=state.plane, line=line))
    elif name in ("G90", "G91"):
        state.incremental = name == "G91"
        records.append(InputModes(distance_mode="incremental" if state.incremental
                                  else "absolute", line=line))
    elif name in ("G98", "G99"):
        state.return_level = name
        state.return_given = True
        records.append(InputModes(cycle_return=_RETURNS[name], line=line))
    elif (name == "G28" or name == "G53") and state.evidence is not _RS274_EVIDENCE:
        raise CLError(f"{name} moves in machine coordinates: read only from plain G-code "
                      f"(--format gcode), as a retract of Z alone: {_shorten(command.text)}",
                      where)
    elif name == "G28" or name == "G53":  # read by the G-code reader: Z alone, checked
        records.append(MachineRetract(machine_z=args.get("Z") if name == "G53" else None,
                                      line=line))
        state.pos[2] = None  # wherever the machine's Z is, in program coordinates
        if name == "G53":
            state.modal = "G0"
    elif name in _PATH_MODES:
        records.append(InputModes(path_mode=_PATH_MODES[name],
                                  path_tolerance=args.get("P"), line=line))
    elif name == "F":  # a feed alone on its block (RS274): the next cutting move takes it
        state.feed = _feed(state, command)
        state.feed_unsent = True
    elif name == "S":  # a speed alone: a turning spindle changes speed at once
        if args["S"] < 0:
            raise CLError(f"spindle speed must not be negative: {_shorten(command.text)}",
                          where)
        state.speed = args["S"]
        _per_rev_speed(state)
        if state.spindle is not None:
            records.append(SpindleOn(spindle_speed=state.speed, spindle=state.spindle,
                                     line=line))
    elif name == "T":  # RS274: T selects the tool the next M6 loads
        tool = args["T"]
        if tool < 0 or tool != int(tool):
            raise CLError(f"T needs a tool number (a whole number): {_shorten(command.text)}",
                          where)
        state.selected = int(tool)
    elif name in ("M3", "M4"):
        if "S" in args:
            if args["S"] < 0:
                raise CLError(f"spindle speed must not be negative: {_shorten(command.text)}",
                              where)
            state.speed = args["S"]
            _per_rev_speed(state)
        if state.speed is None:
            raise CLError(f"{name} without a spindle speed S, and none given before: "
                          f"{_shorten(command.text)}", where)
        state.spindle = "cw" if name == "M3" else "ccw"
        records.append(SpindleOn(spindle_speed=state.speed, spindle=state.spindle, line=line))
    elif name == "M5":
        state.spindle = None
        records.append(SpindleOff(line=line))
    elif name == "M6":
        tool = args.get("T", state.selected)  # type: ignore[assignment]  # None: refused next
        if tool is None or tool < 0 or tool != int(tool):
            raise CLError(f"M6 needs a tool number T (a whole number, on its block or "
                          f"selected by a T word before it): "
                          f"{_shorten(command.text)}", where)
        records.append(ToolChange(tool_number=int(tool), line=line))
        state.tool = int(tool)
    elif name == "G43":
        _length_offset(state, command)
    elif name in ("M7", "M8"):
        records.append(CoolantOn(coolant="mist" if name == "M7" else "flood", line=line))
    elif name == "M9":
        records.append(CoolantOff(line=line))
    elif name == "M0":  # Path's Stop (mandatory): a program stop
        records.append(ProgramStop(line=line))
    elif name == "M1":  # Path's Stop (optional)
        records.append(OptionalStop(line=line))
    elif name in _WORK_OFFSETS:  # G54-G59: a record where the offset changes (G54 first:
        number = _WORK_OFFSETS[name]  # the CL's own default, no record)
        if number != state.work_offset:
            state.work_offset = number
            records.append(WorkOffset(work_offset_index=number, line=line))
    elif name in _COMPENSATIONS:  # G40/G41/G42: a record where the side changes (or D)
        _compensation(state, command)
    elif name in ("M2", "M30"):
        records.append(ProgramEnd(line=line))
        state.ended = True
        state.end_line = line
    elif name == "G80":
        state.modal = None


#: G40-G42: the side of the path the tool keeps to (cutter_compensation)
_COMPENSATIONS = {"G40": "off", "G41": "left", "G42": "right"}


def _compensation(state: _State, command: _Command) -> None:
    """G41/G42 D.. and G40 as a cutter_compensation record: what the path is (tool centre
    or contour) is for the post's declared mode to say; a G40 in force, as every safe-start
    block writes it, is no record."""
    side = _COMPENSATIONS[command.name]
    register = command.args.get("D")
    if register is not None and (register != int(register) or register < 0):
        raise CLError(f"D must be a register number (a whole number): "
                      f"{_shorten(command.text)}", Location(state.file, command.line))
    if side == "off" and state.compensation == "off":
        return
    state.compensation = side
    state.records.append(CutterCompensation(
        compensation_side=side, compensation_register=None if register is None
        else int(register), line=command.line))


def _move(state: _State, command: _Command) -> None:
    """G0 or G1 (a cycle open before it is closed by then)."""
    state.modal = command.name
    args = command.args
    if state.rot or any(letter in args for letter in "ABC"):
        _rotary_move(state, command)
        return
    if state.incremental:
        target = _target(state, command)
        given = _given(command, target)
    else:  # absolute: what _target and _given make of it, in one step
        given = [args.get("X"), args.get("Y"), args.get("Z")]
        x, y, z = given
        px, py, pz = state.pos
        target = [px if x is None else x, py if y is None else y, pz if z is None else z]
    if command.name == "G0":
        if (state.evidence.post or state.evidence is _RS274_EVIDENCE) and "F" in args:
            state.feed = _feed(state, command)  # RS274: F is modal, on a rapid too
            state.feed_unsent = True
        if state.tool is None and given[0] is None and given[1] is None \
                and given[2] is not None and state.pos[0] is None and state.pos[1] is None:
            # Z alone before the first tool and before any move in X or Y: the Job's
            # "go safe" (its fixture's clearance height)
            state.records.append(SafeRetract(z=given[2], line=command.line))
        else:
            state.records.append(RapidMove(x=given[0], y=given[1], z=given[2],
                                           line=command.line))
    else:
        given_feed = args.get("F")
        if given_feed is None and state.feed is not None:
            feed = state.feed if state.feed_unsent else None  # the feed in force
            state.feed_unsent = False
        elif given_feed is not None and given_feed > 0 and state.feed_factor is not None \
                and not state.per_rev:
            feed = state.feed = given_feed * state.feed_factor  # as _feed converts it
            state.feed_unsent = False
        else:
            feed = _feed(state, command)  # its errors
        state.records.append(LinearMove(x=given[0], y=given[1], z=given[2], feed=feed,
                                        line=command.line))
    state.pos = target


#: the rotary words as the G-code's CAM meant them: ISO axes (A about X, B about Y, C about
#: Z), turning the part (a table) about the program origin, ISO 841's direction -- the X Y Z
#: written are where the machine is with the part so turned
_ROTARY_TABLES = {letter: Kinematics((RotaryAxis(letter.lower(), about, continuous=True),))
                  for letter, about in (("A", "x"), ("B", "y"), ("C", "z"))}


def _rotary_text(state: _State) -> str:
    return " ".join(f"{letter}{angle:g}" for letter, angle in sorted(state.rot.items()))


def _rotary_move(state: _State, command: _Command) -> None:
    """A G0/G1 on a machine with a rotary: the tip in the part frame, and the angle."""
    args = command.args
    where = Location(state.file, command.line)
    for letter in "ABC":
        if letter in args:
            value = args[letter]
            state.rot[letter] = state.rot.get(letter, 0.0) + value if state.incremental \
                else value
    if len(state.rot) > 1:
        raise CLError("two rotary axes (" + ", ".join(sorted(state.rot)) + ") in one program: "
                      "which carries which is not in the G-code: " + _shorten(command.text),
                      where)
    ((letter, angle),) = state.rot.items()
    target = _target(state, command)
    kin = _ROTARY_TABLES[letter]
    turned = not is_identity(kin, {letter.lower(): angle})
    if turned and None in target:
        raise CLError("a rotary move before X, Y and Z are known: the tip on the part is not "
                      "known: " + _shorten(command.text), where)
    # with the part turned (or turned back) every coordinate of the tip on the part may
    # change, a word left out included; else the words given
    tip: list[float | None]
    if turned:
        tip = list(to_part(kin, target, {letter.lower(): angle}))  # type: ignore[arg-type]  # no None when turned: checked above
    else:
        tip = target if state.turned else _given(command, target)
    state.turned = turned
    rotary = {letter.lower(): angle} if letter in args else {}
    feed = None
    if command.name == "G1":
        given_feed = args.get("F")
        if given_feed is not None:
            feed = _feed(state, command)
        elif state.feed is not None:
            feed = state.feed
        else:
            feed = _feed(state, command)  # its error
        state.feed_unsent = False
        state.records.append(LinearMove(x=tip[0], y=tip[1], z=tip[2], feed=feed,
                                        line=command.line, **rotary))
    else:
        state.records.append(RapidMove(x=tip[0], y=tip[1], z=tip[2], line=command.line,
                                       **rotary))
    state.pos = target


#: a value of a plain move: a sign, then digits and points.  ``float`` reads exactly the
#: plain decimals of these (``[-+]?(\d+\.?\d*|\.\d+)``, the general path's) and refuses the
#: rest ("1.2.3", "."), which :func:`_plain_move` leaves to the general path
_DECIMAL = r"[-+]?[\d.]+"
#: a line shorter than this holds no decimal beyond a float's range (10**308)
_FINITE_LINE = 300
#: the commonest line of all, a G0 or G1 of plain decimals in upper case, or the axis
#: words alone that repeat the modal G0 or G1: what :data:`_PLAIN_LINE` (and
#: :data:`_PLAIN_DUMP`) and the word-by-word loop read, in the orders FreeCAD and its posts
#: write (F first or last, then X Y Z; words apart by one blank or none, and the one blank
#: the linuxcnc post leaves at the end); read by :func:`_plain_move` without a command
_PLAIN_MOVE = re.compile(rf"(?:N\d+ )?(?:G0*([01]) ?)?(?:F({_DECIMAL}) ?)?(?:X({_DECIMAL}) ?)?"
                         rf"(?:Y({_DECIMAL}) ?)?(?:Z({_DECIMAL}) ?)?(?:F({_DECIMAL}) ?)?\Z")
_PLAIN_DUMP_MOVE = re.compile(rf"Command G0*([01]) \[(?: F:({_DECIMAL}))?(?: X:({_DECIMAL}))?"
                              rf"(?: Y:({_DECIMAL}))?(?: Z:({_DECIMAL}))?(?: F:({_DECIMAL}))? \]\Z")


class _Taken:
    """The type of :data:`_TAKEN`."""


#: what :func:`_plain_move` returns for a move it handed to the sink
_TAKEN = _Taken()


def _plain_move(state: _State, words: tuple[str | None, ...], line: int,
                sink: MoveSink | None, log: RecordLog | None = None) -> CLCommand | _Taken | None:
    """The G0 or G1 of a :data:`_PLAIN_MOVE` line, as :func:`_move` reads it, when nothing
    but the move itself can happen: no cycle to close, absolute coordinates, a feed that
    is known and can be converted.  It is handed to ``sink`` when there is one (then
    :data:`_TAKEN`, and kept in ``log`` when there is one); None, having changed nothing,
    for every other line, which the general path then reads (its errors included)."""
    code, feed_text, x_text, y_text, z_text, last_feed = words
    if code is None:  # axis words alone repeat the motion in force (RS274), F not first
        if feed_text is not None or (x_text is None and y_text is None and z_text is None):
            return None
        modal = state.modal
        if modal == "G1":
            code = "1"
        elif modal == "G0":
            code = "0"
        else:
            return None
    if last_feed is not None:
        if feed_text is not None:
            return None  # F twice
        feed_text = last_feed
    if state.cycle is not None or state.incremental or state.inch or state.feed_unsent \
            or state.rot or state.per_rev:
        return None
    try:
        x = float(x_text) if x_text is not None else None
        y = float(y_text) if y_text is not None else None
        z = float(z_text) if z_text is not None else None
        given = float(feed_text) if feed_text is not None else None
    except ValueError:  # "1.2.3", "-.": not a plain decimal
        return None
    pos = state.pos
    target = [pos[0] if x is None else x, pos[1] if y is None else y,
              pos[2] if z is None else z]
    if code == "0":
        if given is not None and state.evidence.post:
            return None  # RS274's modal feed: _feed reads it
        if state.tool is None and x is None and y is None and state.pos[0] is None \
                and state.pos[1] is None:
            return None  # a safe_retract, which _move makes
        state.modal = "G0"
        state.pos = target
        if sink is not None:
            sink.rapid(x, y, z)
            if log is not None:
                log.keep((line, x, y, z))
            return _TAKEN
        return rapid_move(x, y, z, line)
    feed: float | None
    if given is None:
        if state.feed is None:
            return None
        feed = None  # the feed in force
    else:
        factor = state.feed_factor
        if given <= 0 or factor is None:
            return None
        feed = state.feed = given * factor
    state.modal = "G1"
    state.pos = target
    if sink is not None:
        sink.linear(x, y, z, feed)
        if log is not None:
            log.keep((line, x, y, z, feed))
        return _TAKEN
    return linear_move(x, y, z, feed, line)


def _length_offset(state: _State, command: _Command) -> None:
    """G43 H: the post writes the loaded tool's own length offset, so H must be that tool."""
    where = Location(state.file, command.line)
    offset = command.args.get("H")
    if state.tool is None:
        raise CLError(f"G43 (tool length compensation) with no tool loaded (no M6 T before "
                      f"it): the offset would belong to no tool: {_shorten(command.text)}",
                      where)
    if offset is None or offset != state.tool:
        shown = "no H" if offset is None else f"H{_num(offset)}"
        raise CLError(f"G43 with {shown} for tool T{state.tool}: the CL carries no other length "
                      f"offset than the loaded tool's, which the post writes itself: "
                      f"{_shorten(command.text)}", where)


def _feed(state: _State, command: _Command) -> float | None:
    """F in the file's unit -> mm/min; None when omitted (the CL keeps the previous feed).

    A cutting move needs a feed: one given here, or one in force from before.
    """
    where = Location(state.file, command.line)
    if "F" not in command.args:
        if state.feed is None and command.name != "G0" and state.per_rev_feed is not None:
            raise CLError(_NO_SPEED.format(feed=_num(state.per_rev_feed),
                                           text=_shorten(command.text)), where)
        if state.feed_unsent and command.name != "G0":
            state.feed_unsent = False
            return state.feed  # set by a block without a move: this move carries it
        if state.feed is None and command.name != "G0":
            raise CLError(f"{command.name} is a cutting move but no feed F was given before "
                          f"it: {_shorten(command.text)}", where)
        return None
    feed = command.args["F"]
    if feed <= 0:
        raise CLError(f"{command.name} with feed F{_num(feed)}: a cutting move needs a "
                      f"positive feed (set the tool controller's feed rate): "
                      f"{_shorten(command.text)}", where)
    if state.per_rev:
        return _per_rev(state, command, feed)
    if state.feed_factor is None:
        raise CLError(f"F{_num(feed)}: nothing in the file tells whether its feeds are mm/min "
                      f"(G-code a FreeCAD post wrote) or mm/s (FreeCAD's internal path, as "
                      f"Path.toGCode() writes it); say which with --feed-units mm/min or "
                      f"--feed-units mm/s", where)
    state.feed = feed * state.feed_factor
    state.feed_unsent = False
    return state.feed


_NO_SPEED = ("a cutting move at F{feed} per revolution (G95) with no spindle speed S in "
             "force: the feed per minute it means is not known (give S before the move): "
             "{text}")


def _per_rev(state: _State, command: _Command, feed: float) -> float | None:
    """G95's F (mm per revolution, exact from the file) as the CL's mm/min: times the
    speed in force.  A feed alone or on a rapid waits for the speed; a cutting move
    without one is refused at its line."""
    state.per_rev_feed = feed
    if state.speed:
        state.feed = _times(feed, state.speed)
        state.feed_unsent = command.name in ("F", "G0")
        return state.feed
    state.feed = None
    if command.name in ("F", "G0"):
        return None
    raise CLError(_NO_SPEED.format(feed=_num(feed), text=_shorten(command.text)),
                  Location(state.file, command.line))


def _feed_mode(state: _State, command: _Command) -> None:
    """G95 (F per revolution) or G94 (per minute) from here on.  The F in force was in the
    other mode: dropped, as rs274 drops it, so the next cutting move gives its own.  A
    file whose feeds are mm/s (FreeCAD's internal path) has no feed per revolution."""
    per_rev = command.name == "G95"
    if per_rev == state.per_rev:
        return
    if per_rev and state.feed_factor not in (None, 1.0):
        raise CLError(f"G95 (feed per revolution) in a file whose feeds are mm/s (FreeCAD's "
                      f"internal path writes no G95): {_shorten(command.text)}",
                      Location(state.file, command.line))
    state.per_rev = per_rev
    state.per_rev_feed = None
    state.feed = None
    state.feed_unsent = False


def _per_rev_speed(state: _State) -> None:
    """A new speed in G95: the feed per minute changes with it, and the next cutting move
    carries the new one (an S block ends a canned cycle here, so no hole keeps the old)."""
    if not state.per_rev or state.per_rev_feed is None:
        return
    state.feed = _times(state.per_rev_feed, state.speed) if state.speed else None
    state.feed_unsent = state.feed is not None


def _times(feed: float, speed: float) -> float:
    """mm/rev times rpm from the decimals written (a float's repr gives back the decimal
    it was read from), rounded once: 0.1 x 1200 is 120, not 120.00000000000001."""
    return float(Decimal(repr(feed)) * Decimal(repr(speed)))


def _target(state: _State, command: _Command) -> list[float | None]:
    """The end point of a move: omitted axes keep their value; G91 adds to the position."""
    target = list(state.pos)
    for index, letter in enumerate("XYZ"):
        if letter not in command.args:
            continue
        value = command.args[letter]
        if state.incremental:
            current = state.pos[index]
            if current is None:
                raise CLError(f"incremental (G91) {letter} before the {letter} position is "
                              f"known: {_shorten(command.text)}",
                              Location(state.file, command.line))
            value += current
        target[index] = value
    return target


def _given(command: _Command, target: list[float | None]) -> list[float | None]:
    """The end point with the axes the command left out as None (the CL's "not moved")."""
    return [value if letter in command.args else None
            for letter, value in zip("XYZ", target, strict=True)]


def _moved(state: _State, target: list[float | None]) -> None:
    state.pos = list(target)


def _arc(state: _State, command: _Command) -> None:
    where = Location(state.file, command.line)
    start = state.pos
    if None in start:
        raise CLError(f"{command.name} before the tool position is known (the centre is "
                      f"relative to the start point): {_shorten(command.text)}", where)
    target = _target(state, command)
    given = _given(command, target)
    args = command.args
    in_plane = {"xy": "IJ", "zx": "KI", "yz": "JK"}[state.plane]
    # the centre on the plane's axes always (an omitted offset is 0); on the normal axis
    # only when given, since the CL then takes the start point's value anyway
    centre = [start[i] + args[letter] if letter in args else  # type: ignore[operator]  # start known: refused above
              start[i] if letter in in_plane else None
              for i, letter in enumerate("IJK")]
    state.records.append(ArcMove(
        x=given[0], y=given[1], z=given[2], cx=centre[0], cy=centre[1], cz=centre[2],
        arc_direction="cw" if command.name == "G2" else "ccw", plane=state.plane,
        feed=_feed(state, command), line=command.line))
    _moved(state, target)


def _drill(state: _State, command: _Command) -> None:
    where = Location(state.file, command.line)
    if state.incremental:
        raise CLError(f"drilling cycles in incremental mode (G91) are not supported "
                      f"(write them under G90): {_shorten(command.text)}", where)
    args = command.args
    cycle = state.cycle
    # canned-cycle values are modal while the same cycle repeats; another kind of cycle
    # must give its own (a G82 dwell must not leak into a G83)
    kept = cycle if cycle is not None and cycle.key[0] == command.name else None

    def value(letter: str, previous: float | None) -> float | None:
        return args.get(letter, previous)

    r = value("R", kept.r if kept else None)
    z = value("Z", kept.z if kept else None)
    if r is None or z is None:
        missing = " and ".join(letter for letter, v in (("R", r), ("Z", z)) if v is None)
        raise CLError(f"{command.name} needs {missing} on its first hole: "
                      f"{_shorten(command.text)}", where)
    if z >= r:
        raise CLError(f"{command.name}: the bottom Z{_num(z)} must be below R{_num(r)}: "
                      f"{_shorten(command.text)}", where)
    q = value("Q", kept.q if kept else None) if command.name in ("G83", "G73") else None
    if command.name in ("G83", "G73") and (q is None or q <= 0):
        raise CLError(f"{command.name} needs a positive peck depth Q: "
                      f"{_shorten(command.text)}", where)
    p = value("P", kept.p if kept else None) if command.name != "G81" else None
    if command.name == "G82" and p is None:
        raise CLError(f"G82 needs a dwell time P (seconds): {_shorten(command.text)}", where)
    if p is not None and p < 0:
        raise CLError(f"dwell P must not be negative: {_shorten(command.text)}", where)
    feed = _feed(state, command) if "F" in args else (kept.feed if kept else None)
    if feed is None and state.evidence is _RS274_EVIDENCE:
        feed = state.feed  # RS274: the feed in force
        state.feed_unsent = False
    if feed is None:
        raise CLError(f"{command.name} needs a feed F on its first hole: "
                      f"{_shorten(command.text)}", where)
    x = args.get("X", state.pos[0])
    y = args.get("Y", state.pos[1])
    if x is None or y is None:
        raise CLError(f"{command.name}: the hole's X and Y are not known: "
                      f"{_shorten(command.text)}", where)
    initial = cycle.initial if cycle else state.pos[2]
    # G98: back to the level the cycle started at (never below R); G99: to R
    retract = max(initial, r) if state.return_level == "G98" and initial is not None else r
    key = (command.name, r, z, q, p, feed, retract)
    if cycle is not None and cycle.key == key:
        state.records.append(CycleHole(x=x, y=y, line=command.line))
    else:
        _close_cycle(state, command.line, "next_cycle")
        state.records.append(CycleStart(line=command.line))
        setup: type[DrillSetup] = _DRILLS[command.name]
        state.records.append(setup(
            x=x, y=y, top=r, depth=r - z, clearance=0.0, retract=retract,
            peck=q if command.name in ("G83", "G73") else 0.0,  # type: ignore[arg-type]  # Q > 0
            dwell=p or 0.0, feed=feed, line=command.line,
            cycle_return=_RETURNS[state.return_level] if state.return_given else None))
        state.cycle = _Cycle(key, r, z, q, p, feed, initial)
    state.pos = [x, y, retract]


#: the words of a G0 or G1 (no others: _command's fast path)
_MOVE_LETTERS = frozenset("XYZF")

#: what a command that ends an open cycle is, as the CL's cycle_end says it
_ENDED_BY = {"G80": "cancel", "G0": "motion", "G1": "motion", "G2": "motion", "G3": "motion"}
_RETURNS = {"G98": "initial", "G99": "r_plane"}


def _close_cycle(state: _State, line: int, ended_by: str) -> None:
    if state.cycle is not None:
        state.records.append(CycleEnd(ended_by=ended_by, line=line))
        state.cycle = None


def _num(value: float) -> str:
    return f"{value:g}"


def _shorten(text: str, limit: int = 80) -> str:
    return text if len(text) <= limit else text[: limit - 1] + "…"
