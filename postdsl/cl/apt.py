"""The APT / ISO 4343 CL source reader (what NX, CATIA, Creo and many CAMs write).

One record a line, ``WORD/args`` separated by commas; ``$`` at the end of a
line continues the record on the next one; ``$$`` starts a comment.  The
reader accepts exactly the subset documented below and turns it into the CL
vocabulary of :mod:`postdsl.cl.model`.  Anything else -- an unknown record, a
missing value, a word in the wrong place -- is a :class:`CLError` naming the
file, the line and the record text: a CL record is never skipped silently,
because a skipped ``SPINDL`` or ``GOTO`` is a crash on the machine.

Records and their meaning (lengths are converted to mm, see ``UNITS``):

``PARTNO/text`` (or ``PARTNO text``)
    The program name.  A first word ``O<digits>`` is the program number
    (the O-number of ISO 6983 controls): ``PARTNO/O20 BRACKET OP1`` gives
    program number 20 and the name ``BRACKET OP1``; ``PARTNO/O20`` alone
    gives the name ``O20``.
    Nothing else sets the program number.
``UNITS/MM`` ``UNITS/INCHES``
    Units of the file.  Inch files are **converted to mm** (every length
    times 25.4, feeds in inch/min to mm/min), so posts always see mm; the
    record must come before the first length.
``PPRINT/text`` (or ``PPRINT text``)
    An operator comment.  ``PARTNO`` and ``PPRINT`` text is taken verbatim,
    as in APT: no ``$`` continuation and no ``$$`` comment inside it.
``LOADTL/n[,...]``
    Tool change to tool *n* (further values such as ``ADJUST,h`` are read
    and not used).
``CUTTER/d[,r,...]``
    Diameter (and corner radius) of the tool loaded by the next ``LOADTL``;
    written directly after a ``LOADTL``, it describes that tool.
``SPINDL/s,RPM,CLW|CCLW`` ``SPINDL/OFF``
    Spindle on at *s* rpm clockwise / counter-clockwise, or off (the
    keywords may come in any order: ``SPINDL/RPM,s,CLW`` as NX writes it).
    ``RPM`` is ISO 4343's default unit and may be left out (``SPINDL/1000,CLW``, as
    SolidWorks CAM writes it); another unit (``SFM``, ``SMM``) is refused, and so is a
    speed without its direction.
``COOLNT/ON|FLOOD|MIST|OFF``
    Coolant (``ON`` is flood).
``FEDRAT/f[,MMPM|IPM]``
    Feed for the following moves (per minute; without a unit in the file's
    units).  Feed moves before the first ``FEDRAT`` are an error.
``RAPID``
    The next ``GOTO`` is a rapid move.
``GOTO/x,y,z[,i,j,k]``
    Move to the point (feed unless preceded by ``RAPID``).  A tool axis
    other than +Z is an error: the reader serves 3-axis machines.
``FROM/x,y,z``
    The start point; no motion, no CL command (it only tells the reader
    where the first arc starts).
``CIRCLE/xc,yc,zc,i,j,k,r`` then ``GOTO/x,y,z``
    An arc about the centre to the point of the next ``GOTO``; the axis
    (i,j,k) must lie along X, Y or Z and gives the sense: counter-clockwise
    seen from the axis' positive side when its component is positive.  A
    ``GOTO`` with another Z than the start is a helix.
``INDIRV/i,j,k`` then ``TLON,GOFWD/(CIRCLE/xc,yc,zc,r),ON,(LINE/...)``
    CATIA's arc: it leaves the start in direction (i,j,k) about the circle
    and stops where it meets the line; ``ON,n,INTOF,(LINE/...)`` stops at the
    n-th meeting (n = 2: the arc passes the line once first, as in a full
    circle).  The circle may also be written with its axis
    (``CIRCLE/xc,yc,zc,i,j,k,r``).
``MOVARC/xc,yc,zc,i,j,k,r,ANGLE,deg``
    An arc of *deg* degrees about the centre, counter-clockwise about the
    axis (i,j,k) for a positive angle (right-hand rule); ``360`` is a full
    circle.
``DELAY/sec``
    Dwell.
``CYCLE/DRILL,d,MMPM,f,c[,DWELL,s]`` ``CYCLE/DEEP,d,INCR,q,MMPM,f,c[,DWELL,s]``
``CYCLE/BRKCHP,d,INCR,q,MMPM,f,c[,DWELL,s]`` ``CYCLE/TAP,d,MMPM,f,c[,DWELL,s][,RIGID]``
    Start a drilling cycle (``IPM`` instead of ``MMPM`` gives the feed in
    inch/min).  Every following ``GOTO`` is a hole whose point is the **top
    of the hole**: the first one becomes ``cycle_start`` plus the setup
    (``single_peck``, ``deep_drill``, ``break_chip``, ``tapping`` or
    ``rigid_tapping``), each further one a ``cycle_hole``; depth *d*,
    clearance *c* above the top, peck *q*, dwell *s*, feed *f*.  When the
    last ``SPINDL`` before ``CYCLE/TAP`` turned counter-clockwise the setup is
    ``tapping_ccw`` / ``rigid_tapping_ccw`` (a left-hand tap).  A new
    ``CYCLE`` ends the active one.
``CYCLE/OFF``
    End of the cycle (``cycle_end``, ``ended_by: cancel``); outside a cycle it
    changes nothing.  A ``CYCLE`` that follows a cycle without one ends it
    (``ended_by: next_cycle``).
``END`` ``FINI``
    End of the program (``program_end``, once).  Only ``FINI`` may follow
    ``END``, and nothing may follow ``FINI``.  A file with neither is an
    error (it may be truncated: posting it would end the program early).

``CYCLE/…,FEDTO|DEPTH,d,MMPM|IPM,f,RAPTO|CLEAR,c[,RTRCTO,r][,STEP|INCR,q][,DWELL,s]``
    The keyword form SolidWorks CAM and Creo write (any order); lengths from
    the hole's top, the GOTO point, as above; ``RTRCTO`` is the return plane
    above the top.  ``CYCLE/DEEP2`` gives ``1STPECK`` and ``SUBPECK``: the
    later pecks are the ``peck``, a different first one the ``first_peck``.
    ``CYCLE/INIT`` only announces a cycle.
``MULTAX/ON|OFF`` ``TLAXIS/i,j,k`` ``CUTCOM/…``
    Read: tool axes must be +Z; ``CUTCOM/LEFT|RIGHT|OFF`` (also ``ON,LEFT``,
    ``LEFT,XYPLAN,d``, ``LEFT,d``: d the radius register) as cutter_compensation.

Each CAM family's own records (``LOAD/TOOL``, ``TLDATA``, ``CSYS``…) and
what happens to them -- read, ignored by rule or refused -- are tables in
:mod:`postdsl.cl.apt_dialects`; ``$$`` comments are read for the evidence of
which family wrote the file.

Values are plain decimals (``10``, ``-5.``, ``.5``); keywords are read in
upper or lower case.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass

from postdsl.cl.apt_dialects import DIALECTS, Rule, dialect_of_comment, dialect_of_record
from postdsl.cl.lines import MAX_LINE
from postdsl.cl.model import (
    ArcMove,
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
    LinearMove,
    OptionalStop,
    ProgramEnd,
    ProgramStart,
    ProgramStop,
    RapidMove,
    RigidTapping,
    RigidTappingCcw,
    SinglePeck,
    SpindleOff,
    SpindleOn,
    Tapping,
    TappingCcw,
    ToolChange,
    WorkPlane,
)
from postdsl.cl.native import MoveSink
from postdsl.cl.plain import linear_move, rapid_move
from postdsl.cl.record_log import RecordLog
from postdsl.errors import CLError, Location

__all__ = ["looks_like_apt", "read_apt", "starts_apt_record"]

INCH = 25.4

#: records whose text is taken verbatim (APT: no continuation, no comment); INSERT and
#: TPRINT are SolidWorks CAM's and CATIA's
_TEXT_RECORD = re.compile(r"\s*(PARTNO|PPRINT|INSERT|TPRINT)(?=[\s/]|$)", re.IGNORECASE)
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)\Z")
#: a major word: letters, digits, ``_`` and ``-`` (NX's END-OF-PATH), words apart by one
#: blank (NX's TOOL PATH), several joined by commas (TLON,GOFWD)
_NAME = r"[A-Z][A-Z0-9_-]*(?: [A-Z][A-Z0-9_-]*)*"
_WORD = re.compile(rf"{_NAME}(?:,{_NAME})*\Z")
_O_NUMBER = re.compile(r"O(\d{1,9})(?:\s+(.*))?\Z", re.IGNORECASE)

#: major words that stand alone (no slash)
_BARE = ("RAPID", "END", "FINI", "END-OF-PATH", "STOP", "OPSTOP")
#: a record start as CL source writes it: a major word (or words) then a slash
_RECORD_START = re.compile(r"[A-Za-z][A-Za-z0-9_]*(?:[ \t]?[,A-Za-z0-9_ -]){0,40}?[ \t]*/")


def looks_like_apt(lines: list[str]) -> bool:
    """Content test for format detection: the first record looks like APT.

    ``$$`` comment lines are skipped; the first other line must be a record
    start -- ``WORD/…``, ``PARTNO``/``PPRINT`` text, or a bare ``RAPID``,
    ``END`` or ``FINI``.  No other CL format starts a line like that.
    """
    for line in lines:
        stripped = line.strip()
        if not stripped or stripped.startswith("$$"):
            continue
        return starts_apt_record(stripped)
    return bool(lines)


def starts_apt_record(line: str) -> bool:
    """One line as APT starts one: a ``$$`` comment, ``WORD/…``, PARTNO text or a bare word."""
    stripped = line.strip()
    return bool(stripped.startswith("$$") or _RECORD_START.match(stripped)
                or _TEXT_RECORD.match(stripped) or stripped.upper().rstrip("/") in _BARE)


# --- records ------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Nested:
    """A parenthesised sub-record such as ``(CIRCLE/1,2,3,4)``."""

    word: str
    args: tuple[Arg, ...]


Arg = str | _Nested


@dataclass(slots=True)
class _Record:
    word: str
    #: None for a bare word (``RAPID``); the verbatim text for PARTNO/PPRINT
    args: tuple[Arg, ...] | None
    text: str
    line: int
    literal: str | None = None
    #: every value is a plain decimal (the common record, GOTO/1,2,3): read without checks
    numeric: bool = False
    #: why the values could not be split: raised unless the record is ignored by rule
    #: (CATIA's TOOLNO leaves values out: ``TOOLNO/1, 20.0, 3.0,, 120.0``)
    error: CLError | None = None
    #: the values as numbers, when ``numeric`` (as given: not yet in mm)
    numbers: tuple[float, ...] = ()


class _Records:
    """Join continued lines, split each record into its words; ``$$`` comments become
    ``$$`` records (their text can tell which CAM system wrote the file).

    Fed one line at a time (:meth:`line`), so that the reader can take a plain
    ``GOTO/x,y,z`` line itself while no record is continued (``pending`` and
    ``comment_goes_on`` are empty and false).
    """

    __slots__ = ("comment_goes_on", "file", "first_line", "last_line", "pending", "size")

    def __init__(self, file: str) -> None:
        self.file = file
        self.pending: list[str] = []
        self.size = 0
        self.first_line = 0
        self.last_line = 0
        #: a ``$$`` comment continued with ``$``: the next lines of values belong to it
        self.comment_goes_on = False

    def line(self, raw: str, number: int) -> _Record | None:
        """The record that ``raw`` (line ``number``) completes, if any."""
        file = self.file
        pending = self.pending
        self.last_line = number
        if self.comment_goes_on and _CONTINUED_VALUES.match(raw):
            # Creo continues a $$ comment (its CSYS matrix) with a $ at its end: the next
            # lines hold only values; a line that starts a record ends the comment
            self.comment_goes_on = raw.rstrip().endswith("$")
            return None
        self.comment_goes_on = False
        if not pending and (raw[:1] in "PpIiTt" or raw[:1].isspace()):
            match = _TEXT_RECORD.match(raw)
            if match:
                word = match.group(1).upper()
                rest = raw[match.end():]
                if rest.lstrip().startswith("/"):
                    rest = rest.lstrip()[1:]
                text = raw.strip()
                return _Record(word, None, text, number, literal=_unquoted(rest.strip()))
        if not pending and "$" not in raw:  # one whole record on its line: the common case
            code = raw.strip()
            if code:
                if len(code) > MAX_LINE:
                    raise CLError(f"the record continued from line {number} is longer than "
                                  f"{MAX_LINE:,} characters: this is not a CL file, or a "
                                  f"damaged one", Location(file, number))
                return _parse_record(code, number, file)
            return None
        code, marker, comment = raw.partition("$$")
        code = code.strip()
        if marker and not code and not pending:
            comment = comment.strip()
            self.comment_goes_on = comment.endswith("$")
            return _Record("$$", None, raw.strip(), number, literal=comment)
        if not code:
            return None
        if not pending:
            self.first_line = number
        self.size += len(code)
        if self.size > MAX_LINE:
            raise CLError(f"the record continued from line {self.first_line} is longer than "
                          f"{MAX_LINE:,} characters: this is not a CL file, or a damaged one",
                          Location(file, self.first_line))
        if code.endswith("$"):
            pending.append(code[:-1].strip())
            return None
        pending.append(code)
        text = "".join(pending)
        pending.clear()
        self.size = 0
        return _parse_record(text, self.first_line, file)

    def end(self) -> None:
        """The file ends: a record still continued is cut short."""
        if self.pending:
            text = _shorten("".join(self.pending))
            raise CLError(f"{text}: the record is continued with '$' but the file ends "
                          f"(truncated?)", Location(self.file, self.first_line or self.last_line))


#: INSERT text that is a command for the control, not a description
_INSERTED_COMMAND = re.compile(r"\s*(?:(?:OP)?STOP\b|[GMTSF]\s*\d)", re.IGNORECASE)

#: a line of values only: what continues Creo's ``$$-> CSYS / …, $`` comment
_CONTINUED_VALUES = re.compile(r"\s*[-+.\d]")


def _unquoted(text: str) -> str:
    """PARTNO/'name' as Fusion's APT post writes it: the quotes are not part of the text."""
    if len(text) >= 2 and text[0] == text[-1] == "'":
        return text[1:-1]
    return text


#: the common record: one word, a slash, then only signs, digits, points, commas and blanks
#: (GOTO/1.5,-2,3.).  One character class, so linear; each value is then read by ``float``,
#: which for these characters accepts exactly the plain decimals :data:`_NUMBER` accepts
#: (no letters: no exponent, ``inf`` or ``nan``; no ``_``).
_PLAIN_RECORD = re.compile(r"([A-Za-z][A-Za-z0-9_-]*)/([-+0-9., \t]*)\Z")


#: the commonest line of all, ``GOTO/x,y,z`` (or ``GOTO / x, y, z`` as Creo writes it, or
#: with the tool axis ``0,0,1`` after it as NX does), matched on the line itself: a line the
#: reader takes by it is not made a record at all (:meth:`_Reader.run`).  The characters
#: are those of :data:`_PLAIN_RECORD`, whose values ``float`` then reads or refuses as
#: the general path does; blanks after it are what ``str.strip`` would have removed
_PLAIN_GOTO_LINE = re.compile(r"[Gg][Oo][Tt][Oo][ \t]*/([-+0-9., \t]*)\Z")

#: the dialects that read GOTO by the ISO rule: another dialect's GOTO takes the general path
_PLAIN_GOTO_DIALECTS = frozenset(name for name, dialect in DIALECTS.items()
                                 if dialect.records.get("GOTO") is DIALECTS["iso"].records["GOTO"])


def _parse_record(text: str, line: int, file: str) -> _Record:
    plain = _PLAIN_RECORD.match(text)
    if plain is not None:  # the fast path: what _split would make of it, without a loop
        body = plain.group(2)
        values = body.split(",")
        if " " in body or "\t" in body:
            values = [value.strip() for value in values]
        try:
            numbers = tuple(map(float, values))
        except ValueError:  # an empty value, "1.2.3", "+": the general path says what
            return _parse_any_record(text, line, file)
        return _Record(plain.group(1).upper(), tuple(values), text, line, None, True, None,
                       numbers)
    return _parse_any_record(text, line, file)


def _parse_any_record(text: str, line: int, file: str) -> _Record:
    def fail(problem: str) -> CLError:
        return CLError(f"{_shorten(text)}: {problem}", Location(file, line))

    depth = 0
    slash = -1
    for index, char in enumerate(text):
        if char == "(":
            depth += 1
        elif char == ")":
            depth -= 1
        elif char == "/" and depth == 0:
            slash = index
            break
    head = text if slash < 0 else text[:slash]
    # blanks around commas go, runs of blanks inside a word become one (linear: a
    # pattern like \s*,\s* retried at every blank of a long run is quadratic)
    word = ",".join(" ".join(part.split()) for part in head.split(",")).upper()
    if not _WORD.match(word):
        raise fail(f"'{_shorten(head.strip())}' is not an APT record word")
    if slash < 0 or not text[slash + 1:].strip():  # RAPID/ as SolidWorks CAM writes it
        return _Record(word, None, text, line)
    try:
        return _Record(word, _split(text[slash + 1:], fail), text, line)
    except CLError as exc:
        return _Record(word, (), text, line, error=exc)


#: sub-records in sub-records: APT nests one level, (CIRCLE/…) in TLON,GOFWD; the bound keeps
#: a hostile file from exhausting the stack
_MAX_NESTING = 8


def _split(body: str, fail: Callable[[str], CLError], nesting: int = 0) -> tuple[Arg, ...]:
    if nesting > _MAX_NESTING:
        raise fail(f"sub-records nested too deeply (more than {_MAX_NESTING} levels)")
    parts: list[str] = []
    depth = 0
    start = 0
    for index, char in enumerate(body):
        if char == "(":
            depth += 1
        elif char == ")":
            depth -= 1
            if depth < 0:
                raise fail("unbalanced parentheses")
        elif char == "," and depth == 0:
            parts.append(body[start:index])
            start = index + 1
    if depth != 0:
        raise fail("unbalanced parentheses")
    parts.append(body[start:])
    args: list[Arg] = []
    for part in parts:
        token = part.strip()
        if not token:
            raise fail("a value is missing (two commas in a row, or a comma at the end)")
        if token.startswith("("):
            if not token.endswith(")"):
                raise fail(f"'{_shorten(token)}' has text after its closing parenthesis")
            inner = token[1:-1].strip()
            word, slash, rest = inner.partition("/")
            word = word.strip().upper()
            if not slash or not _WORD.match(word):
                raise fail(f"'{_shorten(token)}' is not a sub-record like (CIRCLE/…)")
            args.append(_Nested(word, _split(rest, fail, nesting + 1)))
        else:
            args.append(token.upper() if not _NUMBER.match(token) else token)
    return tuple(args)


# --- the reader ---------------------------------------------------------------------------


@dataclass
class _Cycle:
    kind: str  # setup command name
    depth: float
    peck: float
    feed: float
    clearance: float
    dwell: float
    record: _Record
    holes: int = 0
    #: the return plane above the hole's top (RTRCTO), when the cycle gives one
    retract: float | None = None
    #: the top of the cycle's first hole
    top: float = 0.0
    #: the first peck's depth when it differs from the later pecks (CYCLE/DEEP2)
    first_peck: float | None = None


@dataclass
class _State:
    scale: float = 1.0
    units_locked: bool = False
    name: str | None = None
    number: int | None = None
    started: bool = False
    ended: bool = False
    finished: bool = False
    pos: tuple[float, float, float] | None = None
    feed: float | None = None
    rapid: _Record | None = None
    circle: tuple[_Record, tuple[float, float, float], tuple[float, float, float], float] | None \
        = None
    indirv: tuple[_Record, tuple[float, float, float]] | None = None
    cycle: _Cycle | None = None
    spindle: str = "cw"
    cutter: tuple[float, float] | None = None
    tool: ToolChange | None = None
    last_line: int = 0
    #: the last record was NX's END-OF-PATH (which ends a file without FINI)
    path_ended: bool = False
    #: where the last MOVARC ended: a GOTO there only repeats it (Fusion writes one)
    arc_end: tuple[float, float, float] | None = None
    #: a tilted plane (MSYS other than the identity) is in force
    plane: bool = False


def _plain_axis(values: list[str]) -> bool:
    """Whether the tool axis i,j,k of a GOTO's six values is plainly +Z (0,0,k with k
    finite and not tiny), which :meth:`_Reader.tool_axis` accepts without a word."""
    try:
        k = float(values[5])
        return float(values[3]) == 0 and float(values[4]) == 0 and 1e-3 <= k < math.inf
    except ValueError:
        return False


class _Taken:
    """The type of :data:`_TAKEN`."""


#: what :meth:`_Reader.plain_goto` returns for a move it handed to the sink
_TAKEN = _Taken()


class _Reader:
    def __init__(self, file: str, log: RecordLog | None = None) -> None:
        self.file = file
        #: keeps the plain moves a sink takes, for a second pass (see read_apt)
        self.log = log
        self.s = _State()
        self.record: _Record | None = None
        #: the file's dialect (apt_dialects.DIALECTS), and the record that decided it
        self.dialect = "iso"
        self.evidence = ""

    # -- helpers ---------------------------------------------------------------------

    def fail(self, problem: str, record: _Record | None = None) -> CLError:
        record = record or self.record
        assert record is not None
        return CLError(f"{_shorten(record.text)}: {problem}", Location(self.file, record.line))

    def args(self, record: _Record) -> tuple[Arg, ...]:
        if record.args is None:
            raise self.fail(f"{record.word} needs values: {record.word}/…")
        return record.args

    def number(self, arg: Arg, what: str) -> float:
        if isinstance(arg, _Nested) or not _NUMBER.match(arg):
            shown = f"({arg.word}/…)" if isinstance(arg, _Nested) else _shorten(arg)
            raise self.fail(f"{what} must be a plain decimal number, not '{shown}'")
        value = float(arg)
        if not math.isfinite(value):  # float("9" * 400) is inf, without an error
            raise self.fail(f"{what} must be a finite number, not '{_shorten(arg, 20)}'")
        return value

    def numbers(self, args: tuple[Arg, ...], names: tuple[str, ...]) -> list[float]:
        if len(args) != len(names):
            raise self.fail(f"expected {len(names)} values ({', '.join(names)}), "
                            f"got {len(args)}")
        return [self.number(arg, name) for arg, name in zip(args, names, strict=True)]

    def length(self, value: float) -> float:
        self.s.units_locked = True
        return value * self.s.scale

    def point(self, values: list[float]) -> tuple[float, float, float]:
        return (self.length(values[0]), self.length(values[1]), self.length(values[2]))

    def keyword(self, arg: Arg, choices: tuple[str, ...], what: str) -> str:
        if isinstance(arg, str) and arg in choices:
            return arg
        shown = f"({arg.word}/…)" if isinstance(arg, _Nested) else _shorten(arg)
        raise self.fail(f"{what} must be {' or '.join(choices)}, not '{shown}'")

    def here(self) -> int:
        return self.record.line if self.record else 0

    # -- driving ---------------------------------------------------------------------

    def run(self, lines: Iterable[str], sink: MoveSink | None = None) -> Iterator[CLCommand]:
        """The commands of ``lines``; with ``sink``, the plain moves go to it instead.

        A finishing program is mostly feed moves ``GOTO/x,y,z`` with nothing pending:
        while that is so (``ready``, see :meth:`plain_ready`, told again after every
        other line), such a line is read here, without a record.
        """
        s = self.s
        records = _Records(self.file)
        plain_line = _PLAIN_GOTO_LINE.match
        take = sink.linear if sink is not None else None
        log = self.log
        isfinite = math.isfinite
        ready = False
        feed = scale = 0.0
        for number, raw in enumerate(lines, start=1):
            if ready:
                plain = plain_line(raw)
                if plain is not None:
                    values = plain.group(1).split(",")
                    count = len(values)
                    if count == 3 or (count == 6 and _plain_axis(values)):
                        try:
                            x, y, z = float(values[0]), float(values[1]), float(values[2])
                        except ValueError:  # an empty value, "1.2.3": the record says what
                            pass
                        else:
                            if scale != 1.0:  # x * 1.0 is x: the product only in inches
                                x, y, z = x * scale, y * scale, z * scale
                            if isfinite(x + y + z):
                                s.pos = (x, y, z)
                                s.last_line = number
                                if take is not None:
                                    take(x, y, z, feed)
                                    if log is not None:
                                        log.keep((number, x, y, z, feed))
                                else:
                                    yield linear_move(x, y, z, feed, number)
                                continue
            record = records.line(raw, number)
            if record is not None:
                yield from self.handle(record, sink)
            ready = self.plain_ready(records)
            feed, scale = s.feed or 0.0, s.scale
        records.end()
        if self.s.path_ended and not (self.s.ended or self.s.finished):
            yield from self.start()
            yield ProgramEnd(line=self.s.last_line)
            return
        if not (self.s.ended or self.s.finished):
            raise CLError("the CL file ends without END or FINI (truncated? posting it would "
                          "end the program early)", Location(self.file, self.s.last_line or 1))

    def plain_ready(self, records: _Records) -> bool:
        """Whether the next ``GOTO/x,y,z`` line is a plain feed move: no record continued,
        nothing pending (RAPID, CIRCLE, a tool, a cycle…), a feed known, and nothing for
        :meth:`plain_goto` to set but the position and the line."""
        s = self.s
        return not records.pending and not records.comment_goes_on \
            and self.dialect in _PLAIN_GOTO_DIALECTS and s.started and s.tool is None \
            and s.cycle is None and s.circle is None and s.indirv is None \
            and s.arc_end is None and not s.ended and not s.finished and s.rapid is None \
            and s.feed is not None and not s.path_ended and s.units_locked

    def handle(self, record: _Record, sink: MoveSink | None) -> Iterator[CLCommand]:
        """The commands of one record (none for a plain move ``sink`` takes)."""
        if record.numeric and record.word == "GOTO" and len(record.numbers) == 3:
            x, y, z = record.numbers
            move = self.plain_goto(x, y, z, record.line, sink)
            if move is not None:
                if move is not _TAKEN:
                    yield move  # type: ignore[misc]  # _TAKEN is the only _Taken
                return
        self.record = record
        self.s.last_line = record.line
        if record.word == "$$":
            self.comment_evidence(record)
            return
        rule = self.rule(record)
        if self.s.finished:
            raise self.fail("record after FINI (FINI must be the last record)")
        if self.s.ended and record.word != "FINI":
            raise self.fail("record after END (only FINI may follow END)")
        if rule.action == "ignore":
            return
        self.s.path_ended = False
        if record.error is not None:
            raise record.error
        if rule.action == "refuse":
            raise self.fail(f"{record.word} is refused: {rule.why}")
        if record.word not in _SETTINGS:
            yield from self.start()
        if record.word not in ("CUTTER", "TLDATA"):
            yield from self.flush_tool()
        if record.word not in ("GOTO", "MOVARC"):
            self.s.arc_end = None
        if record.args is None and record.literal is None and record.word not in _BARE \
                and record.word != "MULTAX":  # CATIA writes a bare MULTAX for MULTAX/ON
            raise self.fail(f"{record.word} needs values: {record.word}/…")
        if record.word in _BARE and record.args is not None:
            raise self.fail(f"{record.word} takes no values")
        handler = getattr(self, rule.handler or _HANDLERS[record.word])
        yield from handler(record)

    def plain_goto(self, x: float, y: float, z: float, line: int,
                   sink: MoveSink | None) -> CLCommand | _Taken | None:
        """The common GOTO/x,y,z (values as given), a move with nothing pending: what
        :meth:`goto` makes of it, without the checks no such record needs -- handed to
        ``sink`` when there is one (then :data:`_TAKEN`).  None: take the general path."""
        s = self.s
        if self.dialect not in _PLAIN_GOTO_DIALECTS or not s.started or s.tool is not None \
                or s.cycle is not None or s.circle is not None or s.indirv is not None \
                or s.arc_end is not None or s.ended or s.finished \
                or (s.rapid is None and s.feed is None):
            return None
        scale = s.scale
        x, y, z = x * scale, y * scale, z * scale
        if not math.isfinite(x + y + z):
            return None
        s.last_line = line
        s.path_ended = False
        s.units_locked = True
        s.pos = (x, y, z)
        if s.rapid is not None:
            s.rapid = None
            if sink is not None:
                sink.rapid(x, y, z)
                if self.log is not None:
                    self.log.keep((line, x, y, z))
                return _TAKEN
            return rapid_move(x, y, z, line)
        if sink is not None:
            sink.linear(x, y, z, s.feed)
            if self.log is not None:
                self.log.keep((line, x, y, z, s.feed))
            return _TAKEN
        return linear_move(x, y, z, s.feed, line)

    def rule(self, record: _Record) -> Rule:
        """The rule of the file's dialect for this record; the record may decide the dialect."""
        word = record.word
        evidence = dialect_of_record(word)
        if evidence is not None and evidence != self.dialect:
            if self.dialect != "iso":
                raise self.fail(f"{word} is written by {DIALECTS[evidence].title}, but this "
                                f"file reads as {DIALECTS[self.dialect].title} "
                                f"({self.evidence}): a file mixing two dialects was not "
                                f"written by a CAM system")
            self.dialect = evidence
            self.evidence = f"line {record.line}: {_shorten(record.text, 40)}"
        rule = DIALECTS[self.dialect].records.get(word)
        if rule is not None:
            return rule
        # a record several families write alike (LOAD/TOOL): read before the evidence; a
        # record only one family writes means something else elsewhere (APT's INSERT
        # passes code to the control) and waits for that family's evidence
        writers = [d.records[word] for d in DIALECTS.values() if word in d.records]
        if len(writers) > 1 and len(set(writers)) == 1:
            return writers[0]
        known = ", ".join(sorted(DIALECTS[self.dialect].records))
        raise self.fail(f"unknown APT record '{word}' (this reader knows for "
                        f"{DIALECTS[self.dialect].title}: {known})")

    def comment_evidence(self, record: _Record) -> None:
        dialect = dialect_of_comment(record.literal or "")
        if dialect is not None and self.dialect == "iso":
            self.dialect = dialect
            self.evidence = f"line {record.line}: {_shorten(record.text, 40)}"

    def start(self) -> Iterator[CLCommand]:
        if not self.s.started:
            self.s.started = True
            yield ProgramStart(program_name=self.s.name or "", program_number=self.s.number,
                               units="mm", line=self.here())

    def flush_tool(self) -> Iterator[CLCommand]:
        if self.s.tool is not None:
            tool, self.s.tool = self.s.tool, None
            yield tool

    def no_pending_motion(self, what: str) -> None:
        """Modifiers that wait for a GOTO must not meet another motion."""
        s = self.s
        if s.rapid is not None:
            raise self.fail(f"{what} after RAPID: RAPID applies to the next GOTO only")
        if s.circle is not None:
            raise self.fail(f"{what} after CIRCLE (line {s.circle[0].line}): the CIRCLE "
                            f"needs its GOTO first")
        if s.indirv is not None:
            raise self.fail(f"{what} after INDIRV (line {s.indirv[0].line}): INDIRV must be "
                            f"followed by TLON,GOFWD")

    def no_cycle(self, what: str) -> None:
        if self.s.cycle is not None:
            raise self.fail(f"{what} inside CYCLE/{self.s.cycle.record.args[0]} (line "  # type: ignore[index]  # a CYCLE record has its args
                            f"{self.s.cycle.record.line}): end the cycle with CYCLE/OFF first")

    def feed_of(self, what: str) -> float:
        if self.s.feed is None:
            raise self.fail(f"{what} is a feed move but no FEDRAT was given before it")
        return self.s.feed

    def tool_axis(self, values: list[float]) -> None:
        i, j, k = values
        size = math.sqrt(i * i + j * j + k * k)
        if size < 1e-9 or abs(i / size) > 1e-6 or abs(j / size) > 1e-6 or k < 0:
            raise self.fail(f"tool axis ({i:g}, {j:g}, {k:g}) is not +Z: only 3-axis "
                            f"programs can be posted")

    # -- program ---------------------------------------------------------------------

    def partno(self, record: _Record) -> Iterator[CLCommand]:
        if self.s.started:
            raise self.fail("PARTNO must come before every other record except UNITS")
        if self.s.name is not None:
            raise self.fail("a second PARTNO")
        text = record.literal or ""
        match = _O_NUMBER.match(text)
        if match:
            self.s.number = int(match.group(1))
            text = (match.group(2) or "").strip() or text
        self.s.name = text
        return iter(())

    def units(self, record: _Record) -> Iterator[CLCommand]:
        (unit,) = self.single(record)
        unit = self.keyword(unit, ("MM", "INCHES"), "UNITS")
        if self.s.units_locked:
            raise self.fail("UNITS must come before the first length in the file")
        self.s.scale = INCH if unit == "INCHES" else 1.0
        return iter(())

    def single(self, record: _Record) -> tuple[Arg]:
        args = self.args(record)
        if len(args) != 1:
            raise self.fail(f"{record.word} takes one value, got {len(args)}")
        return (args[0],)

    def pprint(self, record: _Record) -> Iterator[CLCommand]:
        yield Comment(comment=record.literal or "", line=record.line)

    def insert(self, record: _Record) -> Iterator[CLCommand]:
        """SolidWorks CAM's INSERT: a description, or a command such as INSERT/STOP."""
        text = record.literal or ""
        if _INSERTED_COMMAND.match(text):
            raise self.fail("INSERT passes a command to the control (a stop, a G or M code): "
                            "the CL cannot carry it, and dropping it would run on where the "
                            "CAM stops or switches")
        return self.pprint(record)

    def end(self, record: _Record) -> Iterator[CLCommand]:
        self.no_pending_motion("END")
        self.no_cycle("END")
        self.s.ended = True
        yield ProgramEnd(line=record.line)

    def fini(self, record: _Record) -> Iterator[CLCommand]:
        self.no_pending_motion("FINI")
        self.no_cycle("FINI")
        self.s.finished = True
        if not self.s.ended:
            self.s.ended = True
            yield ProgramEnd(line=record.line)

    # -- tool, spindle, coolant, feed ------------------------------------------------

    def loadtl(self, record: _Record) -> Iterator[CLCommand]:
        self.no_pending_motion("LOADTL")
        self.no_cycle("LOADTL")
        args = self.args(record)
        number = self.number(args[0], "the tool number")
        if number != int(number) or number < 1:
            raise self.fail(f"the tool number must be a whole number from 1, not {args[0]}")
        diameter, radius = self.s.cutter or (0.0, 0.0)
        self.s.cutter = None
        self.s.tool = ToolChange(tool_number=int(number), tool_diameter=diameter,
                                 tool_corner_radius=radius, line=record.line)
        self.s.pos = None  # the tool change moves the machine
        return iter(())

    def cutter(self, record: _Record) -> Iterator[CLCommand]:
        args = self.args(record)
        diameter = self.number(args[0], "the cutter diameter")
        radius = self.number(args[1], "the corner radius") if len(args) > 1 else 0.0
        if diameter <= 0 or radius < 0 or 2 * radius > diameter:
            raise self.fail("the cutter needs a diameter > 0 and a corner radius from 0 to "
                            "half the diameter")
        values = (self.length(diameter), self.length(radius))
        tool = self.s.tool
        if tool is not None:  # directly after LOADTL: it describes that tool
            self.s.tool = ToolChange(tool_number=tool.tool_number, tool_diameter=values[0],
                                     tool_corner_radius=values[1], line=tool.line)
        else:
            self.s.cutter = values
        return iter(())

    def spindl(self, record: _Record) -> Iterator[CLCommand]:
        args = self.args(record)
        if args == ("OFF",):
            yield SpindleOff(line=record.line)
            return
        speed: float | None = None
        rpm = False
        direction: str | None = None
        for arg in args:
            if isinstance(arg, str) and _NUMBER.match(arg):
                if speed is not None:
                    raise self.fail("SPINDL takes one speed")
                speed = self.number(arg, "the spindle speed")
            elif arg == "RPM":
                rpm = True
            elif arg in ("CLW", "CCLW"):
                if direction is not None:
                    raise self.fail("SPINDL takes one direction (CLW or CCLW)")
                direction = "cw" if arg == "CLW" else "ccw"
            else:
                shown = f"({arg.word}/…)" if isinstance(arg, _Nested) else _shorten(arg)
                raise self.fail(f"SPINDL: '{shown}' is not supported (SPINDL/s,RPM,CLW|CCLW "
                                f"or SPINDL/OFF)")
        del rpm  # RPM is ISO 4343's default: SPINDL/1000,CLW is 1000 rpm
        if speed is None or direction is None:
            raise self.fail("SPINDL needs a speed and CLW or CCLW "
                            "(SPINDL/s[,RPM],CLW|CCLW), or OFF")
        if speed <= 0:
            raise self.fail("the spindle speed must be greater than 0")
        self.s.spindle = direction
        yield SpindleOn(spindle_speed=speed, spindle=direction, line=record.line)

    def stop(self, record: _Record) -> Iterator[CLCommand]:
        """STOP (ISO 4343: a programmed stop, M0) and OPSTOP (an optional stop, M1)."""
        self.no_pending_motion(record.word)
        self.no_cycle(record.word)
        if record.word == "STOP":
            yield ProgramStop(line=record.line)
        else:
            yield OptionalStop(line=record.line)

    def coolnt(self, record: _Record) -> Iterator[CLCommand]:
        (arg,) = self.single(record)
        kind = self.keyword(arg, ("ON", "FLOOD", "MIST", "THRU", "OFF"), "COOLNT")
        if kind == "OFF":
            yield CoolantOff(line=record.line)
        else:
            coolant = {"MIST": "mist", "THRU": "through"}.get(kind, "flood")
            yield CoolantOn(coolant=coolant, line=record.line)

    def fedrat(self, record: _Record) -> Iterator[CLCommand]:
        args = self.args(record)
        value: float | None = None
        unit: str | None = None
        for arg in args:
            if isinstance(arg, str) and _NUMBER.match(arg):
                if value is not None:
                    raise self.fail("FEDRAT takes one feed")
                value = self.number(arg, "the feed")
            elif arg in ("MMPM", "IPM"):
                if unit is not None:
                    raise self.fail("FEDRAT takes one unit")
                unit = arg
            else:
                shown = f"({arg.word}/…)" if isinstance(arg, _Nested) else _shorten(arg)
                raise self.fail(f"FEDRAT: '{shown}' is not supported (FEDRAT/f[,MMPM|IPM]; "
                                f"feeds per revolution are not)")
        if value is None or value <= 0:
            raise self.fail("FEDRAT needs a feed greater than 0")
        self.s.feed = self.feed_value(value, unit)
        return iter(())

    def feed_value(self, value: float, unit: str | None) -> float:
        self.s.units_locked = True
        if unit == "IPM":
            return value * INCH
        if unit == "MMPM":
            return value
        return value * self.s.scale

    # -- motion ----------------------------------------------------------------------

    def rapid(self, record: _Record) -> Iterator[CLCommand]:
        self.no_cycle("RAPID")
        if self.s.circle is not None or self.s.indirv is not None:
            self.no_pending_motion("RAPID")
        self.s.rapid = record
        return iter(())

    def from_(self, record: _Record) -> Iterator[CLCommand]:
        self.no_pending_motion("FROM")
        self.no_cycle("FROM")
        self.s.pos = self.located_point(record)
        return iter(())

    def located_point(self, record: _Record) -> tuple[float, float, float]:
        """x,y,z of GOTO/FROM, in mm; a tool axis i,j,k after them must be +Z."""
        args = self.args(record)
        if len(args) not in (3, 6):
            raise self.fail(f"{record.word} needs x,y,z or x,y,z,i,j,k, got {len(args)} "
                            f"values")
        if record.numeric and len(args) == 3:  # GOTO/x,y,z: plain decimals, read as such
            scale = self.s.scale
            x, y, z = record.numbers
            x, y, z = x * scale, y * scale, z * scale
            if math.isfinite(x + y + z):
                self.s.units_locked = True
                return (x, y, z)
        values = [self.number(arg, name) for arg, name in zip(args, "xyzijk", strict=False)]
        if len(values) == 6:
            self.tool_axis(values[3:])
        return self.point(values[:3])

    def gohome(self, record: _Record) -> Iterator[CLCommand]:
        """NX's GOHOME/x,y,z[,i,j,k]: the return to the home point, a rapid move."""
        self.no_cycle("GOHOME")
        self.no_pending_motion("GOHOME")
        return self.goto(record, rapid=True)

    def end_of_path(self, record: _Record) -> Iterator[CLCommand]:
        """NX ends each operation's path so; the last one ends the file (no FINI)."""
        self.no_pending_motion("END-OF-PATH")
        self.no_cycle("END-OF-PATH")
        self.s.path_ended = True
        return iter(())

    def goto(self, record: _Record, rapid: bool = False) -> Iterator[CLCommand]:
        point = self.located_point(record)
        s = self.s
        arc_end, s.arc_end = s.arc_end, None
        if arc_end is not None and s.rapid is None and s.cycle is None \
                and max(abs(a - b) for a, b in zip(arc_end, point, strict=True)) < 1e-3:
            return  # the end point of the MOVARC before it, repeated: no further motion
        if s.cycle is not None:
            yield from self.hole(point, record)
            return
        if s.indirv is not None:
            self.no_pending_motion("GOTO")
        if s.circle is not None:
            yield self.arc_to(point, record)
        elif s.rapid is not None or rapid:
            s.rapid = None
            yield RapidMove(x=point[0], y=point[1], z=point[2], line=record.line)
        else:
            yield LinearMove(x=point[0], y=point[1], z=point[2], feed=self.feed_of("GOTO"),
                             line=record.line)
        s.pos = point

    def circle(self, record: _Record) -> Iterator[CLCommand]:
        self.no_cycle("CIRCLE")
        self.no_pending_motion("CIRCLE")
        args = self.args(record)
        names = ("xc", "yc", "zc", "i", "j", "k", "r")
        if len(args) == 6:
            # SolidWorks CAM leaves the radius out: it is the start point's distance
            values = self.numbers(args, names[:6])
            centre = self.point(values[:3])
            plane, _sign = self.plane_of((values[3], values[4], values[5]), record)
            start = self.start_point("the CIRCLE")
            a, b = _PLANE_AXES[plane]
            radius = math.hypot(start[a] - centre[a], start[b] - centre[b])
            if radius <= 0:
                raise self.fail("the circle radius must be greater than 0")
            self.s.circle = (record, centre, (values[3], values[4], values[5]), radius)
            return iter(())
        if "TIMES" in args:
            raise self.fail("CIRCLE with TIMES (several full turns about the centre) is not "
                            "read: write the turns as arcs")
        if 7 < len(args) <= 11:
            # NX appends the tolerance and tool data after the radius: not geometry
            args = args[:7]
        values = self.numbers(args, names)
        centre = self.point(values[:3])
        radius = self.length(values[6])
        if radius <= 0:
            raise self.fail("the circle radius must be greater than 0")
        self.s.circle = (record, centre, (values[3], values[4], values[5]), radius)
        return iter(())

    def arc_to(self, end: tuple[float, float, float], goto: _Record) -> ArcMove:
        assert self.s.circle is not None
        record, centre, axis, radius = self.s.circle
        self.s.circle = None
        plane, sign = self.plane_of(axis, record)
        start = self.start_point("the arc")
        self.on_circle(start, centre, radius, plane, "the start point", record)
        self.on_circle(end, centre, radius, plane, "the GOTO end point", goto)
        return self.arc_move(end, centre, plane, sign > 0, goto)

    def plane_of(self, axis: tuple[float, float, float], record: _Record) -> tuple[str, float]:
        size = math.sqrt(sum(c * c for c in axis))
        if size < 1e-9:
            raise self.fail("the circle axis (i,j,k) is zero", record)
        for index, plane in ((2, "xy"), (0, "yz"), (1, "zx")):
            others = [abs(axis[i]) / size for i in range(3) if i != index]
            if max(others) < 1e-6:
                return plane, axis[index]
        raise self.fail(f"the circle axis ({axis[0]:g}, {axis[1]:g}, {axis[2]:g}) is not "
                        f"along X, Y or Z: the arc lies in no G17/G18/G19 plane", record)

    def start_point(self, what: str) -> tuple[float, float, float]:
        if self.s.pos is None:
            raise self.fail(f"{what} starts where the tool is, which is not known here "
                            f"(give a GOTO or FROM first)")
        return self.s.pos

    def on_circle(self, point: tuple[float, float, float], centre: tuple[float, float, float],
                  radius: float, plane: str, what: str, record: _Record) -> None:
        a, b = _PLANE_AXES[plane]
        distance = math.hypot(point[a] - centre[a], point[b] - centre[b])
        if abs(distance - radius) > max(1e-3, radius * 1e-4):
            raise self.fail(f"{what} is {distance:.4f} from the centre, not the radius "
                            f"{radius:.4f}", record)

    def arc_move(self, end: tuple[float, float, float], centre: tuple[float, float, float],
                 plane: str, ccw: bool, record: _Record) -> ArcMove:
        a, b = _PLANE_AXES[plane]
        given = {a, b}
        cx, cy, cz = (centre[i] if i in given else None for i in range(3))
        move = ArcMove(x=end[0], y=end[1], z=end[2], cx=cx, cy=cy, cz=cz,
                       arc_direction="ccw" if ccw else "cw", plane=plane,
                       feed=self.feed_of(record.word), line=record.line)
        self.s.pos = end
        return move

    def indirv(self, record: _Record) -> Iterator[CLCommand]:
        self.no_cycle("INDIRV")
        self.no_pending_motion("INDIRV")
        values = self.numbers(self.args(record), ("i", "j", "k"))
        if math.sqrt(sum(v * v for v in values)) < 1e-9:
            raise self.fail("the direction (i,j,k) is zero")
        self.s.indirv = (record, (values[0], values[1], values[2]))
        return iter(())

    def tlon(self, record: _Record) -> Iterator[CLCommand]:
        self.no_cycle("TLON,GOFWD")
        if self.s.rapid is not None or self.s.circle is not None:
            self.no_pending_motion("TLON,GOFWD")
        if self.s.indirv is None:
            raise self.fail("TLON,GOFWD needs an INDIRV/i,j,k (the start direction) before it")
        tangent = self.s.indirv[1]
        self.s.indirv = None
        args = self.args(record)
        shape = "TLON,GOFWD/(CIRCLE/xc,yc,zc,r),ON,[n,INTOF,](LINE/x1,y1,z1,x2,y2,z2)"
        if len(args) not in (3, 5) or not isinstance(args[0], _Nested) \
                or args[0].word != "CIRCLE" or args[1] != "ON" \
                or not isinstance(args[-1], _Nested) or args[-1].word != "LINE":
            raise self.fail(f"expected {shape}")
        count = 1
        if len(args) == 5:
            if args[3] != "INTOF":
                raise self.fail(f"expected {shape}")
            count_value = self.number(args[2], "the intersection count n")
            if count_value not in (1.0, 2.0):
                raise self.fail("the intersection count n must be 1 or 2 (an arc turns at "
                                "most once)")
            count = int(count_value)
        circle_args = args[0].args
        if len(circle_args) == 4:
            values = self.numbers(circle_args, ("xc", "yc", "zc", "r"))
            axis: tuple[float, float, float] | None = None
            radius_value = values[3]
        elif len(circle_args) == 7:
            values = self.numbers(circle_args, ("xc", "yc", "zc", "i", "j", "k", "r"))
            axis = (values[3], values[4], values[5])
            radius_value = values[6]
        else:
            raise self.fail("CIRCLE in TLON,GOFWD needs xc,yc,zc,r or xc,yc,zc,i,j,k,r")
        line_values = self.numbers(args[-1].args, ("x1", "y1", "z1", "x2", "y2", "z2"))
        centre = self.point(values[:3])
        radius = self.length(radius_value)
        if radius <= 0:
            raise self.fail("the circle radius must be greater than 0")
        start = self.start_point("the TLON,GOFWD arc")
        radial = tuple(s - c for s, c in zip(start, centre, strict=True))
        normal = _cross(radial, tangent)  # type: ignore[arg-type]  # 3-tuples: points (x, y, z)
        if axis is None:
            index = max(range(3), key=lambda i: abs(normal[i]))
            if abs(normal[index]) < 1e-9:
                raise self.fail("INDIRV points along the radius: the arc's direction is "
                                "undefined")
            axis = tuple(1.0 if i == index else 0.0 for i in range(3))  # type: ignore[assignment]  # a 3-tuple: range(3)
        assert axis is not None
        plane, _sign = self.plane_of(axis, record)
        normal_index = {"xy": 2, "yz": 0, "zx": 1}[plane]
        tangent_size = math.sqrt(sum(t * t for t in tangent))
        if abs(tangent[normal_index]) / tangent_size > 1e-3:
            raise self.fail("INDIRV does not lie in the plane of the circle")
        turn = normal[normal_index]
        if abs(turn) < 1e-9:
            raise self.fail("INDIRV points along the radius: the arc's direction is undefined")
        ccw = turn > 0
        self.on_circle(start, centre, radius, plane, "the start point", record)
        end = self.line_meeting(start, centre, radius, plane, ccw, count,
                                self.point(line_values[:3]), self.point(line_values[3:]))
        yield self.arc_move(end, centre, plane, ccw, record)

    def line_meeting(self, start: tuple[float, float, float],
                     centre: tuple[float, float, float], radius: float, plane: str, ccw: bool,
                     count: int, p1: tuple[float, float, float],
                     p2: tuple[float, float, float]) -> tuple[float, float, float]:
        """Where an arc from ``start`` meets the line p1-p2 for the ``count``-th time."""
        a, b = _PLANE_AXES[plane]
        dx, dy = p2[a] - p1[a], p2[b] - p1[b]
        fx, fy = p1[a] - centre[a], p1[b] - centre[b]
        qa = dx * dx + dy * dy
        if qa < 1e-12:
            raise self.fail("the LINE has two equal points")
        qb = 2 * (fx * dx + fy * dy)
        qc = fx * fx + fy * fy - radius * radius
        disc = qb * qb - 4 * qa * qc
        if disc < -1e-6 * max(1.0, radius * radius):
            raise self.fail("the LINE does not meet the circle")
        root = math.sqrt(max(disc, 0.0))
        start_angle = math.atan2(start[b] - centre[b], start[a] - centre[a])
        meetings: list[tuple[float, tuple[float, float, float]]] = []
        for t in {(-qb - root) / (2 * qa), (-qb + root) / (2 * qa)}:
            point = tuple(p1[i] + t * (p2[i] - p1[i]) for i in range(3))
            angle = math.atan2(point[b] - centre[b], point[a] - centre[a])
            sweep = (angle - start_angle) if ccw else (start_angle - angle)
            sweep %= 2 * math.pi
            if sweep * radius < 1e-6:
                sweep = 2 * math.pi  # at the start: met again after a full turn
            meetings.append((sweep, point))  # type: ignore[arg-type]  # a 3-tuple: range(3)
        meetings.sort(key=lambda m: m[0])
        if count > len(meetings):
            raise self.fail(f"the arc meets the LINE only {len(meetings)} time(s), not {count}")
        return meetings[count - 1][1]

    def movarc(self, record: _Record) -> Iterator[CLCommand]:
        self.no_cycle("MOVARC")
        self.no_pending_motion("MOVARC")
        args = self.args(record)
        if len(args) != 9 or args[7] != "ANGLE":
            raise self.fail("expected MOVARC/xc,yc,zc,i,j,k,r,ANGLE,deg")
        values = self.numbers(args[:7], ("xc", "yc", "zc", "i", "j", "k", "r"))
        degrees = self.number(args[8], "the angle")
        if degrees == 0 or abs(degrees) > 360:
            raise self.fail("the angle must be from -360 to 360 degrees and not 0")
        centre = self.point(values[:3])
        radius = self.length(values[6])
        plane, sign = self.plane_of((values[3], values[4], values[5]), record)
        start = self.start_point("MOVARC")
        self.on_circle(start, centre, radius, plane, "the start point", record)
        a, b = _PLANE_AXES[plane]
        ccw = (sign > 0) == (degrees > 0)
        turn = math.radians(abs(degrees)) * (1 if ccw else -1)
        u, v = start[a] - centre[a], start[b] - centre[b]
        end = list(start)
        end[a] = centre[a] + u * math.cos(turn) - v * math.sin(turn)
        end[b] = centre[b] + u * math.sin(turn) + v * math.cos(turn)
        if abs(degrees) == 360:
            end = list(start)
        yield self.arc_move((end[0], end[1], end[2]), centre, plane, ccw, record)
        self.s.arc_end = (end[0], end[1], end[2])

    def delay(self, record: _Record) -> Iterator[CLCommand]:
        (arg,) = self.single(record)
        seconds = self.number(arg, "the dwell time")
        if seconds < 0:
            raise self.fail("the dwell time must not be negative")
        yield Dwell(dwell=seconds, line=record.line)

    # -- dialect records -------------------------------------------------------------

    def load(self, record: _Record) -> Iterator[CLCommand]:
        """LOAD/TOOL,n[,ADJUST,h]: SolidWorks CAM's and NX's spelling of LOADTL/n."""
        args = self.args(record)
        if args[0] != "TOOL" or len(args) < 2:
            raise self.fail("expected LOAD/TOOL,n[,ADJUST,h]")
        rest = args[2:]
        if rest and (len(rest) != 2 or rest[0] != "ADJUST"):
            raise self.fail("expected LOAD/TOOL,n[,ADJUST,h]")
        if rest:
            adjust = self.number(rest[1], "the length offset number h")
            if adjust != self.number(args[1], "the tool number"):
                raise self.fail("LOAD/TOOL with another length offset than the tool's: the CL "
                                "carries no other offset than the tool's own")
        return self.loadtl(_Record(record.word, args[1:2], record.text, record.line))

    def transformation_refused(self, what: str) -> CLError:
        return self.fail(f"{what}: the CL has no way to carry a transformation, and posting "
                         f"without it would machine the part elsewhere")

    def trntyp(self, record: _Record) -> Iterator[CLCommand]:
        args = self.args(record)
        if args[0] != "WORLD" or len(args) != 4:
            raise self.fail("expected TRNTYP/WORLD,x,y,z")
        if any(self.number(arg, "the offset") != 0 for arg in args[1:]):
            raise self.transformation_refused("TRNTYP moves the coordinate system")
        return iter(())

    def csys(self, record: _Record) -> Iterator[CLCommand]:
        values = self.numbers(self.args(record), tuple(f"m{i}" for i in range(1, 13)))
        if any(abs(v - e) > 1e-9 for v, e in zip(values, _IDENTITY_CSYS, strict=True)):
            raise self.transformation_refused("CSYS is not the identity")
        return iter(())

    def msys(self, record: _Record) -> Iterator[CLCommand]:
        """MSYS/x,y,z,xi,xj,xk,yi,yj,yk: NX's machine coordinate system -- its origin, X and
        Y axes in the part -- which the GOTOs after it are given in.  Another than the
        identity is a tilted plane (3+2): a work_plane record; the identity again after one
        is its reset."""
        names = ("x", "y", "z", "xi", "xj", "xk", "yi", "yj", "yk")
        values = self.numbers(self.args(record), names)
        if all(abs(v - e) <= 1e-6 for v, e in zip(values, _IDENTITY_MSYS, strict=True)):
            if self.s.plane:
                self.s.plane, self.s.pos = False, None
                yield WorkPlane(work_plane="reset", line=record.line)
            return
        x_axis, y_axis = values[3:6], values[6:9]
        for name, axis in (("X", x_axis), ("Y", y_axis)):
            size = math.sqrt(sum(c * c for c in axis))
            if abs(size - 1.0) > 1e-6:
                raise self.fail(f"MSYS: the {name} axis ({', '.join(f'{c:g}' for c in axis)})"
                                f" is not a unit vector (length {size:.6f})")
        if abs(sum(a * b for a, b in zip(x_axis, y_axis, strict=True))) > 1e-6:
            raise self.fail("MSYS: the X and Y axes are not at right angles")
        xi, xj, xk = x_axis
        yi, yj, yk = y_axis
        z_axis = (xj * yk - xk * yj, xk * yi - xi * yk, xi * yj - xj * yi)
        yield from self.start()
        self.s.plane, self.s.pos = True, None
        yield WorkPlane(origin_x=self.length(values[0]), origin_y=self.length(values[1]),
                        origin_z=self.length(values[2]), x_axis_i=xi, x_axis_j=xj,
                        x_axis_k=xk, z_axis_i=z_axis[0], z_axis_j=z_axis[1],
                        z_axis_k=z_axis[2], line=record.line)

    def tldata(self, record: _Record) -> Iterator[CLCommand]:
        """TLDATA/MILL,d,r,… or TLDATA/DRILL,…,d,…: NX's tool geometry, read as CUTTER."""
        args = self.args(record)
        kinds = [arg for arg in args if isinstance(arg, str) and not _NUMBER.match(arg)]
        numbers = [arg for arg in args if isinstance(arg, str) and _NUMBER.match(arg)]
        if not kinds or kinds[0] not in ("MILL", "DRILL") or not numbers:
            raise self.fail("TLDATA describes no milling tool (TLDATA/MILL,d,r,… or "
                            "TLDATA/DRILL,…): only milling and drilling are posted")
        radius = numbers[1] if kinds == ["MILL"] and len(numbers) > 1 else "0"
        return self.cutter(_Record("CUTTER", (numbers[0], radius), record.text, record.line))

    def mode(self, record: _Record) -> Iterator[CLCommand]:
        (arg,) = self.single(record)
        if arg != "MILL":
            raise self.fail("only milling programs (MODE/MILL) can be posted")
        return iter(())

    def multax(self, record: _Record) -> Iterator[CLCommand]:
        if record.args is None:
            return iter(())
        (arg,) = self.single(record)
        self.keyword(arg, ("ON", "OFF"), "MULTAX")
        return iter(())

    def tlaxis(self, record: _Record) -> Iterator[CLCommand]:
        self.tool_axis(self.numbers(self.args(record), ("i", "j", "k")))
        return iter(())

    def cutcom(self, record: _Record) -> Iterator[CLCommand]:
        """CUTCOM/LEFT|RIGHT|OFF, also as CAM systems write it: ``CUTCOM/ON,LEFT``,
        ``CUTCOM/LEFT,XYPLAN,d``, ``CUTCOM/LEFT,d`` (d: the radius register).  ON without a
        side, or another plane, is refused: the side is never guessed."""
        self.no_pending_motion("CUTCOM")
        self.no_cycle("CUTCOM")
        side: str | None = None
        register: int | None = None
        for arg in self.args(record):
            if isinstance(arg, str) and arg in ("LEFT", "RIGHT", "OFF"):
                if side is not None:
                    raise self.fail(f"CUTCOM gives {side.upper()} and {arg}: one side only")
                side = arg.lower()
            elif isinstance(arg, str) and arg in ("ON", "XYPLAN"):
                continue
            elif isinstance(arg, str) and arg in ("ZXPLAN", "YZPLAN"):
                raise self.fail(f"cutter compensation in the {arg[:2]} plane is not read "
                                f"(XYPLAN only: the posts compensate in G17)")
            elif isinstance(arg, str) and _NUMBER.match(arg):
                value = self.number(arg, "the CUTCOM register")
                if register is not None or value != int(value) or value < 0:
                    raise self.fail("CUTCOM takes one register number, a whole number")
                register = int(value)
            else:
                shown = f"({arg.word}/…)" if isinstance(arg, _Nested) else _shorten(arg)
                raise self.fail(f"CUTCOM takes LEFT, RIGHT or OFF (with ON, XYPLAN and a "
                                f"register number), not '{shown}'")
        if side is None:
            raise self.fail("CUTCOM without LEFT, RIGHT or OFF: the side of the path is not "
                            "given")
        if side == "off" and register is not None:
            raise self.fail("CUTCOM/OFF takes no register")
        yield CutterCompensation(compensation_side=side, compensation_register=register,
                                 line=record.line)

    # -- drilling --------------------------------------------------------------------

    def cycle(self, record: _Record) -> Iterator[CLCommand]:
        self.no_pending_motion("CYCLE")
        args = self.args(record)
        kind = self.keyword(args[0], ("DRILL", "DEEP", "DEEP2", "BRKCHP", "TAP", "INIT", "OFF"),
                            "the cycle")
        if kind in ("OFF", "INIT"):
            if len(args) != 1:
                raise self.fail(f"CYCLE/{kind} takes no further values")
            if kind == "OFF":
                yield from self.end_cycle(record, "cancel")
            return  # CYCLE/INIT (SolidWorks CAM) only announces the CYCLE record after it
        yield from self.end_cycle(record, "next_cycle")
        if len(args) > 1 and isinstance(args[1], str) and not _NUMBER.match(args[1]):
            if not DIALECTS[self.dialect].keyword_cycles:
                raise self.fail(f"the keyword form of CYCLE is read for SolidWorks CAM and "
                                f"Creo files, whose lengths are measured from the hole's top; "
                                f"this file reads as {DIALECTS[self.dialect].title}, whose "
                                f"reference is not known here")
            self.s.cycle = self.keyword_cycle(kind, list(args[1:]), record)
            return
        if kind == "DEEP2":
            raise self.fail("CYCLE/DEEP2 is written with keywords (FEDTO, 1STPECK, SUBPECK, "
                            "MMPM, RAPTO, RTRCTO)")
        rest = list(args[1:])
        depth = self.take_length(rest, "the depth d")
        peck = 0.0
        if kind in ("DEEP", "BRKCHP"):
            if not rest or rest.pop(0) != "INCR":
                raise self.fail(f"expected CYCLE/{kind},d,INCR,q,MMPM,f,c[,DWELL,s]")
            peck = self.take_length(rest, "the peck q")
            if peck <= 0:
                raise self.fail("the peck q must be greater than 0")
        if not rest:
            raise self.fail("the feed unit (MMPM or IPM) is missing")
        unit = self.keyword(rest.pop(0), ("MMPM", "IPM"), "the feed unit")
        if not rest:
            raise self.fail("the feed f is missing")
        feed = self.feed_value(self.number(rest.pop(0), "the feed f"), unit)
        clearance = self.take_length(rest, "the clearance c")
        dwell = 0.0
        rigid = False
        while rest:
            option = rest.pop(0)
            if option == "DWELL":
                if not rest:
                    raise self.fail("DWELL needs its time in seconds")
                dwell = self.number(rest.pop(0), "the dwell")
            elif option == "RIGID" and kind == "TAP" and not rigid:
                rigid = True
            else:
                shown = f"({option.word}/…)" if isinstance(option, _Nested) else _shorten(option)
                raise self.fail(f"'{shown}' is not an option of CYCLE/{kind}")
        if depth <= 0 or feed <= 0 or clearance < 0 or dwell < 0:
            raise self.fail("the cycle needs a depth and feed greater than 0 and a clearance "
                            "and dwell not below 0")
        setups = {"DRILL": "single_peck", "DEEP": "deep_drill", "BRKCHP": "break_chip"}
        if kind == "TAP":
            name = "rigid_tapping" if rigid else "tapping"
            if self.s.spindle == "ccw":
                name += "_ccw"
        else:
            name = setups[kind]
        self.s.cycle = _Cycle(name, depth, peck, feed, clearance, dwell, record)

    def keyword_cycle(self, kind: str, rest: list[Arg], record: _Record) -> _Cycle:
        """The keyword form: CYCLE/DRILL,FEDTO,d,MMPM,f,RAPTO,c,RTRCTO,r[,DWELL,s]
        (SolidWorks CAM), CYCLE/DEEP,DEPTH,d,STEP,s,MMPM,f,CLEAR,c (Creo),
        CYCLE/DEEP2,FEDTO,d,1STPECK,p,SUBPECK,p,… -- every length measured from the
        hole's top, the GOTO point, as in the positional form."""
        values: dict[str, float] = {}
        unit: str | None = None
        while rest:
            word = rest.pop(0)
            if not isinstance(word, str) or word not in _CYCLE_KEYWORDS:
                shown = f"({word.word}/…)" if isinstance(word, _Nested) else _shorten(word)
                raise self.fail(f"'{shown}' is not a keyword of CYCLE/{kind} (known: "
                                f"{', '.join(sorted(_CYCLE_KEYWORDS))})")
            if not rest:
                raise self.fail(f"{word} needs its value")
            value = self.number(rest.pop(0), word)
            meaning = _CYCLE_KEYWORDS[word]
            if meaning == "feed":
                if unit is not None:
                    raise self.fail("the cycle gives its feed twice")
                unit = word
            if meaning in values:
                raise self.fail(f"the cycle gives its {meaning} twice")
            values[meaning] = value
        missing = [m for m in ("depth", "feed") if m not in values]
        if missing:
            raise self.fail(f"CYCLE/{kind} needs its {' and '.join(missing)}")
        depth = self.length(values["depth"])
        feed = self.feed_value(values["feed"], unit)
        clearance = self.length(values.get("clearance", 0.0))
        retract = self.length(values["retract"]) if "retract" in values else None
        dwell = values.get("dwell", 0.0)
        peck = 0.0
        first_peck: float | None = None
        if kind == "DEEP2":
            first, later = values.get("first peck"), values.get("later peck")
            if first is None or later is None:
                raise self.fail("CYCLE/DEEP2 needs 1STPECK and SUBPECK")
            if first <= 0:
                raise self.fail("CYCLE/DEEP2 needs a first peck (1STPECK) greater than 0")
            values["peck"] = later
            if first != later:
                first_peck = self.length(first)
        elif "first peck" in values or "later peck" in values:
            raise self.fail(f"1STPECK and SUBPECK belong to CYCLE/DEEP2, not CYCLE/{kind}")
        if kind in ("DEEP", "DEEP2", "BRKCHP"):
            if values.get("peck", 0) <= 0:
                raise self.fail(f"CYCLE/{kind} needs a peck depth greater than 0 (STEP or "
                                f"INCR)")
            peck = self.length(values["peck"])
        elif "peck" in values:
            raise self.fail(f"CYCLE/{kind} drills in one feed: it takes no peck depth")
        if depth <= 0 or feed <= 0 or clearance < 0 or dwell < 0 or \
                (retract is not None and retract < clearance):
            raise self.fail("the cycle needs a depth and feed greater than 0, a clearance and "
                            "dwell not below 0 and a retract not below the clearance")
        if kind == "TAP":
            name = "tapping_ccw" if self.s.spindle == "ccw" else "tapping"
        else:
            name = {"DRILL": "single_peck", "DEEP": "deep_drill", "DEEP2": "deep_drill",
                    "BRKCHP": "break_chip"}[kind]
        return _Cycle(name, depth, peck, feed, clearance, dwell, record, retract=retract,
                      first_peck=first_peck)

    def take_length(self, rest: list[Arg], what: str) -> float:
        if not rest:
            raise self.fail(f"{what} is missing")
        return self.length(self.number(rest.pop(0), what))

    def end_cycle(self, record: _Record, ended_by: str) -> Iterator[CLCommand]:
        cycle = self.s.cycle
        self.s.cycle = None
        if cycle is not None and cycle.holes:
            yield CycleEnd(ended_by=ended_by, line=record.line)

    def hole(self, top: tuple[float, float, float], record: _Record) -> Iterator[CLCommand]:
        cycle = self.s.cycle
        assert cycle is not None
        if self.s.rapid is not None:
            raise self.fail("RAPID inside a cycle: every GOTO of a cycle is a hole")
        x, y, z = top
        if cycle.holes and cycle.retract is not None and abs(z - cycle.top) > 1e-9:
            # the return plane is measured from each hole's top: a hole at another height
            # returns elsewhere, so it starts a cycle of its own
            yield CycleEnd(ended_by="next_cycle", line=record.line)
            cycle.holes = 0
        if cycle.holes == 0:
            cycle.top = z
            yield CycleStart(line=record.line)
            retract = None if cycle.retract is None else z + cycle.retract
            yield _SETUPS[cycle.kind](x=x, y=y, top=z, depth=cycle.depth,
                                      clearance=cycle.clearance, peck=cycle.peck,
                                      first_peck=cycle.first_peck, dwell=cycle.dwell,
                                      feed=cycle.feed, retract=retract,
                                      line=record.line)
        else:
            yield CycleHole(x=x, y=y, top=z, line=record.line)
        cycle.holes += 1
        self.s.pos = (x, y, z + (cycle.clearance if cycle.retract is None else cycle.retract))


_PLANE_AXES = {"xy": (0, 1), "zx": (2, 0), "yz": (1, 2)}

#: records that set how the file reads and write nothing: they may come before PARTNO
_SETTINGS = ("PARTNO", "UNITS", "UNIT", "MODE", "MULTAX", "TRNTYP", "CSYS", "MSYS", "TLAXIS")

#: record word -> the reader's handler (a dialect's rule may name another)
_HANDLERS = {
    "PARTNO": "partno", "UNITS": "units", "PPRINT": "pprint", "LOADTL": "loadtl",
    "CUTTER": "cutter", "SPINDL": "spindl", "COOLNT": "coolnt", "FEDRAT": "fedrat",
    "RAPID": "rapid", "GOTO": "goto", "FROM": "from_", "CIRCLE": "circle", "INDIRV": "indirv",
    "TLON,GOFWD": "tlon", "MOVARC": "movarc", "DELAY": "delay", "CYCLE": "cycle",
    "END": "end", "FINI": "fini", "MULTAX": "multax", "TLAXIS": "tlaxis", "CUTCOM": "cutcom",
    "TRNTYP": "trntyp", "CSYS": "csys", "TLDATA": "tldata", "MSYS": "msys", "MODE": "mode",
    "GOHOME": "gohome", "STOP": "stop", "OPSTOP": "stop",
}

#: the keywords of a keyword-form CYCLE, and what each gives
_CYCLE_KEYWORDS = {
    "FEDTO": "depth", "DEPTH": "depth", "MMPM": "feed", "IPM": "feed", "RAPTO": "clearance",
    "CLEAR": "clearance", "RTRCTO": "retract", "STEP": "peck", "INCR": "peck",
    "1STPECK": "first peck", "SUBPECK": "later peck", "DWELL": "dwell",
}

#: identity transformations as the dialects write them
_IDENTITY_CSYS = (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0)
_IDENTITY_MSYS = (0, 0, 0, 1, 0, 0, 0, 1, 0)

_SETUPS: dict[str, type[DrillSetup]] = {
    "single_peck": SinglePeck, "deep_drill": DeepDrill, "break_chip": BreakChip,
    "tapping": Tapping, "rigid_tapping": RigidTapping, "tapping_ccw": TappingCcw,
    "rigid_tapping_ccw": RigidTappingCcw,
}


def _cross(u: tuple[float, float, float], v: tuple[float, float, float]) \
        -> tuple[float, float, float]:
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def _shorten(text: str, limit: int = 80) -> str:
    """A record as quoted in a message: a hostile megabyte-long line is not echoed whole."""
    return text if len(text) <= limit else text[: limit - 1] + "…"


def read_apt(lines: Iterable[str], file: str = "<cl>", sink: MoveSink | None = None,
             log: RecordLog | None = None) -> Iterator[CLCommand]:
    """Stream CL commands from APT source lines; every problem is a CLError at file:line.

    With ``sink`` (a first pass's fold), the plain rapid and linear moves are handed to
    it as values instead of being made commands; every check runs all the same.  ``log``
    then keeps each of them as its fields (see :func:`postdsl.cl.readers.replay`).
    """
    return _Reader(file, log).run(lines, sink)
