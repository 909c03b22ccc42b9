"""The native CL format: JSON Lines, one CL command per line.

Why JSON Lines: it streams (a reader never holds more than one line), every
language writes it, and a diff of two CL files reads line by line.  Each line
is an object whose ``cmd`` names the command and whose other keys are that
command's fields (see ``schemas/cl.schema.json``, generated from
:mod:`postdsl.cl.model`).  Blank lines and lines starting with ``#`` are
skipped, so examples can be annotated.

Records are checked here with the model's own field table rather than by
running jsonschema on every line: the checks are the same ones the schema
states (a test keeps the two in step) and this way a million-line file costs
seconds, not minutes.
"""

from __future__ import annotations

import dataclasses
import json
import json.scanner
import sys
from collections.abc import Callable, Iterable, Iterator
from typing import Any, Protocol

from postdsl.cl.model import (
    COMMANDS,
    CLCommand,
    CustomCycle,
    LinearMove,
    ProgramEnd,
    RapidMove,
    command_fields,
    field_type,
    record_builder,
)
from postdsl.cl.record_log import BATCH, RecordLog
from postdsl.errors import CLError, Location

_NUMBER = (int, float)
#: the largest whole number a float holds exactly
_EXACT = 2**53
#: the largest int CPython holds in one digit, whose comparisons it makes quickly
_SMALL = 2**30 - 1


@dataclasses.dataclass(frozen=True)
class _FieldCheck:
    """What reading a native record checks of one field, worked out once per class."""

    name: str
    kind: str  # "number", "integer", "text", "object"
    optional: bool
    choices: tuple[str, ...] | None


def _checks(cls: type[CLCommand]) -> dict[str, _FieldCheck]:
    checks = {}
    for f in command_fields(cls):
        kind, optional = field_type(f)
        checks[f.name] = _FieldCheck(f.name, kind, optional, f.metadata["choices"])
    return checks


_CHECKS = {name: _checks(cls) for name, cls in COMMANDS.items()}


def _type_error(check: _FieldCheck, value: Any) -> str | None:
    if value is None:
        return None if check.optional else f"'{check.name}' must not be null"
    if check.kind == "text":
        if not isinstance(value, str):
            return f"'{check.name}' must be text, not {json.dumps(value)}"
        if not _unicode(value):
            return _not_unicode(check.name, value)
        if check.choices and value not in check.choices:
            options = ", ".join(check.choices)
            return f"'{check.name}' must be one of {options}, not {json.dumps(value)}"
        return None
    if check.kind == "object":
        if not isinstance(value, dict):
            return f"'{check.name}' must be an object of named values"
        for key, item in value.items():
            if not _unicode(key):
                return _not_unicode(f"{check.name} key", key)
            if not isinstance(item, (str, int, float)) or isinstance(item, bool):
                return f"'{check.name}.{key}' must be a number or text"
            if isinstance(item, str) and not _unicode(item):
                return _not_unicode(f"{check.name}.{key}", item)
        return None
    if isinstance(value, bool) or not isinstance(value, _NUMBER):
        return f"'{check.name}' must be a number, not {json.dumps(value)}"
    if isinstance(value, int) and abs(value) > _EXACT:
        # beyond 2**53 a number is no longer exact as a float, and beyond about 10**308 it
        # is none at all: no machine value is that large, so it is refused, not rounded
        return f"'{check.name}' is too large a number ({len(str(abs(value)))} digits)"
    if value != value or value in (float("inf"), float("-inf")):
        return f"'{check.name}' must be a finite number"
    if check.kind == "integer" and value != int(value):
        return f"'{check.name}' must be a whole number, not {value}"
    return None


def _unicode(text: str) -> bool:
    """False for text holding a lone surrogate (JSON's ``"\\ud800"``): it cannot be written."""
    if text.isascii():
        return True
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def _not_unicode(name: str, text: str) -> str:
    bad = next(c for c in text if "\ud800" <= c <= "\udfff")
    return f"'{name}' is not valid Unicode text (a lone surrogate \\u{ord(bad):04x})"


def record_to_command(record: Any, location: Location) -> CLCommand:
    """One decoded JSON value -> a CL command, or a CLError saying what is wrong."""
    if not isinstance(record, dict):
        raise CLError("a CL record must be a JSON object like {\"cmd\": \"rapid_move\", …}",
                      location)
    name = record.get("cmd")
    if not isinstance(name, str):
        raise CLError("the record has no \"cmd\" naming its command", location)
    cls = COMMANDS.get(name)
    if cls is None:
        from difflib import get_close_matches

        hint = get_close_matches(name, COMMANDS, n=1)
        extra = f" (did you mean '{hint[0]}'?)" if hint else ""
        raise CLError(f"unknown CL command '{name}'{extra}", location)
    checks = _CHECKS[name]
    values: dict[str, Any] = {}
    for key, value in record.items():
        if key == "cmd":
            continue
        check = checks.get(key)
        if check is None:
            known = ", ".join(checks) or "none"
            raise CLError(f"{name} has no field '{key}' (its fields: {known})", location)
        problem = _type_error(check, value)
        if problem:
            raise CLError(f"{name}: {problem}", location)
        if check.kind == "integer" and value is not None:
            value = int(value)
        values[key] = value
    return cls(line=location.line or 0, **values)


class _DuplicateKey(Exception):
    """Raised from inside the JSON decoder, which offers no other way to stop it."""

    def __init__(self, key: str) -> None:
        super().__init__(key)
        self.key = key


def _unique(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """An object's fields; a field given twice is an error (json keeps the last in silence)."""
    record = dict(pairs)
    if len(record) != len(pairs):
        seen: set[str] = set()
        for key, _value in pairs:
            if key in seen:
                raise _DuplicateKey(key)
            seen.add(key)
    return record


_DECODER = json.JSONDecoder(object_pairs_hook=_unique)


#: the C scanner under ``json.loads``: one call per record, without the decoder's Python
#: wrapper; plain dicts (duplicate keys are told from the quote count, see _fast_record)
# (typeshed types the scanner's context as the scanner class; the C scanner takes a decoder)
_SCAN = json.scanner.make_scanner(json.JSONDecoder())  # type: ignore[arg-type]


@dataclasses.dataclass(frozen=True)
class _Shape:
    """What the fast path accepts of one command: numeric fields (int only where the
    field is an integer), and text fields with their choices (None: any ASCII text)."""

    cls: type[CLCommand]
    numbers: frozenset[str]
    integers: frozenset[str]
    texts: dict[str, frozenset[str] | None]
    #: makes the command from checked fields (:func:`~postdsl.cl.model.record_builder`)
    build: Callable[[dict[str, Any], int], CLCommand]


def _shape(cls: type[CLCommand]) -> _Shape:
    numbers, integers, texts = set(), set(), {}
    for f in command_fields(cls):
        kind, _optional = field_type(f)
        if kind == "number":
            numbers.add(f.name)
        elif kind == "integer":
            integers.add(f.name)
        elif kind == "text":
            choices = f.metadata["choices"]
            texts[f.name] = frozenset(choices) if choices else None
    return _Shape(cls, frozenset(numbers), frozenset(integers), texts, record_builder(cls))


_SHAPES = {name: _shape(cls) for name, cls in COMMANDS.items() if name != "custom_cycle"}


def _fast_record(text: str, number: int) -> CLCommand | None:
    """The command of a plain record, or None when it needs the full reading.

    A record qualifies when it is one flat JSON object of known fields whose values
    are finite numbers of the right kind or ASCII texts (of the field's choices): the
    common moves and feed changes.  Everything else -- and every record that is
    wrong -- goes through :func:`record_to_command`, so errors are worded in one place.
    A key given twice would be merged by the scanner, so the record's quotes are
    counted: two per key, two per text value, none escaped.
    """
    if "\\" in text:
        return None
    try:
        record, end = _SCAN(text, 0)
    except (StopIteration, ValueError, RecursionError):
        return None
    if end != len(text) or type(record) is not dict:
        return None
    name = record.pop("cmd", None)
    shape = _SHAPES.get(name) if type(name) is str else None
    if shape is None:
        return None
    quotes = 4  # "cmd" and its value
    numbers, integers, texts = shape.numbers, shape.integers, shape.texts
    for key, value in record.items():
        kind = type(value)
        if kind is float:
            if key not in numbers or value - value != 0.0:  # NaN and infinities
                return None
        elif kind is int:
            if (key not in numbers and key not in integers) or not -_EXACT <= value <= _EXACT:
                return None
        elif kind is str:
            if key not in texts or not value.isascii():
                return None
            choices = texts[key]
            if choices is not None and value not in choices:
                return None
            quotes += 2
        else:
            return None
        quotes += 2
    if text.count('"') != quotes:
        return None
    return shape.build(record, number)


class MoveSink(Protocol):
    """What takes the common moves' fields without a command object (a first pass's
    fold, see :func:`move_taker`); a field the record leaves out is None.  ``moves``
    False: it has no use for them (a fold that leaves the moves out), and a reader that
    can skip the calls does."""

    moves: bool

    def rapid(self, x: float | None, y: float | None, z: float | None) -> None: ...

    def linear(self, x: float | None, y: float | None, z: float | None,
               feed: float | None) -> None: ...

    def arc(self, x: float | None, y: float | None, z: float | None, cx: float | None,
            cy: float | None, cz: float | None, clockwise: bool, plane: str,
            feed: float | None) -> None: ...


_DIRECTIONS = ("cw", "ccw")
_PLANES = ("xy", "zx", "yz")


def plain_move(text: str, number: int) -> tuple[Any, ...] | None:
    """A plain rapid, linear or arc record's fields, or None for every other line.

    It takes a line exactly when the full reading would read it as such a move and
    gives the values the full reading puts in the command: one flat object, known
    fields, numbers finite and of at most 2**53 or null (an optional field given as
    null is one left out), texts of the field's choices; no escape, each key once
    (the quotes are counted, as :func:`_fast_record` counts them).  The fields come
    after the line number, and the tuple's length tells the move: ``(number, x, y,
    z)`` a rapid, ``(number, x, y, z, feed)`` a linear move (a
    :data:`~postdsl.cl.model.PlainMove` without its class), ``(number, x, y, z, cx,
    cy, cz, clockwise, plane, feed)`` an arc.  Every other line -- the wrong ones
    included -- is left to the full reading, so that errors are worded in one place.
    """
    if "\\" in text:
        return None
    try:
        record, end = _SCAN(text, 0)
    except (StopIteration, ValueError, RecursionError):
        return None
    if type(record) is not dict or (end != len(text) and text[end:].strip()):
        return None
    name = record.pop("cmd", None)
    quotes = 4 + 2 * len(record)  # "cmd", its value and each key
    pop = record.pop
    move: tuple[Any, ...]
    if name == "linear_move":
        move = (number, pop("x", None), pop("y", None), pop("z", None), pop("feed", None))
    elif name == "rapid_move":
        move = (number, pop("x", None), pop("y", None), pop("z", None))
    elif name == "arc_move":
        size = len(record)
        direction = pop("arc_direction", "ccw")
        plane = pop("plane", "xy")
        if direction not in _DIRECTIONS or plane not in _PLANES:  # null, or no choice
            return None
        quotes += 2 * (size - len(record))  # each text value's quotes
        x, y, z = pop("x", None), pop("y", None), pop("z", None)
        cx, cy, cz, feed = pop("cx", None), pop("cy", None), pop("cz", None), pop("feed", None)
        if not (_plain(x) and _plain(y) and _plain(z) and _plain(cx) and _plain(cy)
                and _plain(cz) and _plain(feed)):
            return None
        move = (number, x, y, z, cx, cy, cz, direction == "cw", plane, feed)
    else:
        return None
    if record or text.count('"') != quotes:  # a field of another kind, or a key twice
        return None
    if name != "arc_move":  # the straight moves' values, checked inline: most lines
        for value in move:  # the line number passes as a small int
            kind = type(value)  # (type(), not __class__: CPython makes it a quick call)
            if kind is float:
                if value - value:  # NaN and infinities
                    return None
            elif kind is int:  # a bool is not; the first bounds are one-digit ints: quick
                if not -_SMALL <= value <= _SMALL and not -_EXACT <= value <= _EXACT:
                    return None
            elif value is not None:
                return None
    return move


def _plain(value: Any) -> bool:
    """A value a move's number field may hold: None, a finite float, an int within
    2**53 (not a bool)."""
    kind = type(value)
    if kind is float:
        return not value - value
    if kind is int:
        return -_EXACT <= value <= _EXACT  # type: ignore[no-any-return]  # an int: kind is int
    return value is None


#: what :func:`read_native` lets a taker do with a line: leave it (None), consume it
#: (True), or replace it by a record to hand on
Taker = Callable[[str, int], Any]


def move_taker(sink: MoveSink, log: RecordLog | None = None) -> Taker:
    """A taker (see :func:`read_native`) that hands a plain rapid, linear or arc
    record's fields to ``sink`` (see :func:`plain_move`) and builds no command: a first
    pass that only folds the moves needs none.  ``log`` keeps each move for the second
    pass (see :func:`postdsl.cl.readers.replay`).  A sink whose ``moves`` is False is
    not called: the moves are still checked and kept."""
    folds = sink.moves
    rapid, linear, arc = sink.rapid, sink.linear, sink.arc
    batch = log.batch if log is not None else None
    write = log.write if log is not None else None

    def take(text: str, number: int) -> bool | None:
        move = plain_move(text, number)
        if move is None:
            return None
        size = len(move)
        if size == 5:
            if folds:
                linear(move[1], move[2], move[3], move[4])
        elif size == 4:
            if folds:
                rapid(move[1], move[2], move[3])
        else:
            if folds:
                arc(*move[1:])
            move = (number, text)  # read again by the second pass: arcs are few
        if batch is not None:
            batch.append(move)
            if len(batch) >= BATCH:
                write()  # type: ignore[misc]  # write is set whenever batch is
        return True

    return take


def straight_taker(text: str, number: int) -> tuple[Any, ...] | None:
    """A taker (see :func:`read_native`) that hands a plain rapid or linear move on as
    its :data:`~postdsl.cl.model.PlainMove` (a second pass that posts it needs no
    command object); every other line, arcs included, is read as usual."""
    move = plain_move(text, number)
    if move is None:
        return None
    size = len(move)
    if size == 5:
        return (LinearMove, *move)
    return (RapidMove, *move) if size == 4 else None


def read_native(lines: Iterable[str], file: str = "<cl>",
                take: Taker | None = None, log: RecordLog | None = None) -> Iterator[Any]:
    """Stream CL commands from JSON Lines text; errors name ``file:line``.

    A program is whole when its last record is ``program_end``: a file cut between
    two lines is still valid JSON Lines, and nothing else in it could tell.
    ``take(text, line)`` (see :func:`move_taker`, :func:`straight_taker`) may take a
    record before a command is made of it: it consumes it (True) or hands on what to
    yield instead (a :data:`~postdsl.cl.model.PlainMove`); every check on the order of
    the records still runs here.  ``log`` keeps each record read as a command (a
    taker keeps the ones it takes), for :func:`postdsl.cl.readers.replay`.
    """
    ended = 0
    last = 0
    for number, text in enumerate(lines, start=1):
        if ended == 0 and text[:1] == "{":
            if take is not None:
                taken = take(text, number)
                if taken is not None:
                    last = number
                    if taken is not True:
                        yield taken
                    continue
            command = _fast_record(text.rstrip(), number)
            if command is not None:
                last = number
                if isinstance(command, ProgramEnd):
                    ended = number
                if log is not None:
                    log.keep((number, text))
                yield command
                continue
        stripped = text.strip()
        if not stripped or stripped.startswith("#"):
            continue
        last = number
        if ended:
            raise CLError(f"a record after program_end (line {ended}): program_end must be "
                          f"the last record", Location(file, number))
        command = _full_record(stripped, number, file)
        if isinstance(command, ProgramEnd):
            ended = number
        if log is not None:
            log.keep((number, text))
        yield command
    if not ended:
        raise CLError("the CL file ends without a program_end record: it may be cut short "
                      "(a whole native CL program ends with {\"cmd\": \"program_end\"})",
                      Location(file, last or None))


def _full_record(stripped: str, number: int, file: str) -> CLCommand:
    """The command of one record's text (stripped), by the full reading: every error
    located and worded."""
    location = Location(file, number)
    try:
        record = _DECODER.decode(stripped)
    except _DuplicateKey as exc:
        raise CLError(f"the record gives '{exc.key}' twice", location) from None
    except json.JSONDecodeError as exc:
        raise CLError(f"not a JSON record ({exc.msg}): {_shorten(stripped)}",
                      Location(file, number, exc.colno)) from None
    except RecursionError:
        raise CLError(f"not a JSON record (nested too deeply): {_shorten(stripped)}",
                      location) from None
    except ValueError:  # an integer longer than Python converts
        raise CLError(f"not a JSON record (a number of more than "
                      f"{sys.get_int_max_str_digits()} digits): {_shorten(stripped)}",
                      location) from None
    return record_to_command(record, location)


def read_record(text: str, number: int, file: str = "<cl>") -> CLCommand:
    """The command of one record's line, read as :func:`read_native` reads it (for a
    second pass that replays the lines a first pass kept)."""
    command = _fast_record(text.rstrip(), number) if text[:1] == "{" else None
    return command if command is not None else _full_record(text.strip(), number, file)


def command_to_record(command: CLCommand) -> dict[str, Any]:
    """A CL command as a native record, omitting fields left at their default."""
    record: dict[str, Any] = {"cmd": command.name}
    for f in command_fields(type(command)):
        value = getattr(command, f.name)
        default = f.default if f.default is not dataclasses.MISSING else None
        if isinstance(command, CustomCycle) and f.name == "params":
            if value:
                record[f.name] = dict(value)
            continue
        if value != default:
            record[f.name] = value
    return record


def write_native(commands: Iterable[CLCommand]) -> Iterator[str]:
    """Native JSON Lines text for CL commands (readers of other formats use it to convert)."""
    for command in commands:
        yield json.dumps(command_to_record(command), ensure_ascii=False) + "\n"


def _shorten(text: str, limit: int = 60) -> str:
    return text if len(text) <= limit else text[: limit - 1] + "…"
