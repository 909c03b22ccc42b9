"""Pick a CL reader by name or by content, and read a file with it.

Each reader lives in its own module beside this one and turns text lines
into CL commands; this module only knows their names and how to tell their
files apart, so adding a format is one module plus one line here.  Files are
streamed (:mod:`postdsl.cl.lines`): a reader never needs the whole file, and a
hostile one (no line ends, ``/dev/zero``) stops at a located error instead of
filling the memory.
"""

from __future__ import annotations

import functools
import pickle
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import Any, Protocol

from postdsl.cl.lines import SourceLines, binary_blocks, text_blocks
from postdsl.cl.model import CLCommand, LinearMove, PlainMove, RapidMove
from postdsl.cl.native import MoveSink, move_taker, read_native, read_record, straight_taker
from postdsl.cl.record_log import RecordLog
from postdsl.errors import CLError, Location

Reader = Callable[..., Iterator[CLCommand]]

# The APT and FreeCAD readers are imported when a file needs them (their patterns and
# dialect tables are a fair part of a short native program's start-up): these stand in.


def read_apt(lines: Iterable[str], file: str = "<cl>", **options: Any) -> Iterator[CLCommand]:
    """:func:`postdsl.cl.apt.read_apt`."""
    from postdsl.cl.apt import read_apt

    return read_apt(lines, file, **options)


def read_freecad(lines: Iterable[str], file: str = "<cl>",
                 **options: Any) -> Iterator[CLCommand]:
    """:func:`postdsl.cl.freecad.read_freecad`."""
    from postdsl.cl.freecad import read_freecad

    return read_freecad(lines, file, **options)


def read_gcode(lines: Iterable[str], file: str = "<cl>", **options: Any) -> Iterator[CLCommand]:
    """:func:`postdsl.cl.gcode.read_gcode`."""
    from postdsl.cl.gcode import read_gcode

    return read_gcode(lines, file, **options)


def looks_like_gcode(lines: list[str]) -> bool:
    from postdsl.cl.gcode import looks_like_gcode

    return looks_like_gcode(lines)


def starts_block(line: str) -> bool:
    from postdsl.cl.gcode import starts_block

    return starts_block(line)


def looks_like_apt(lines: list[str]) -> bool:
    from postdsl.cl.apt import looks_like_apt

    return looks_like_apt(lines)


def looks_like_freecad(lines: list[str]) -> bool:
    from postdsl.cl.freecad import looks_like_freecad

    return looks_like_freecad(lines)


def starts_apt_record(line: str) -> bool:
    from postdsl.cl.apt import starts_apt_record

    return starts_apt_record(line)


def starts_gcode_line(line: str) -> bool:
    from postdsl.cl.freecad import starts_gcode_line

    return starts_gcode_line(line)


#: format name -> reader(lines, file name); each but native also takes ``sink=``, a
#: :class:`~postdsl.cl.native.MoveSink` for the plain moves (native takes a line taker)
READERS: dict[str, Reader] = {"native": read_native, "freecad": read_freecad,
                             "apt": read_apt, "gcode": read_gcode}

#: format name -> test on the first meaningful lines of a file
DETECTORS: dict[str, Callable[[list[str]], bool]] = {
    "native": lambda lines: all(line.lstrip().startswith("{") for line in lines),
    "freecad": looks_like_freecad,
    "apt": looks_like_apt,
    # plain RS274 G-code that the FreeCAD reader's shapes do not all fit (T1 M6, S alone)
    "gcode": looks_like_gcode,
}

#: format name -> does this one line look like that format (to name the line that fits none)
_LINE_TESTS: dict[str, Callable[[str], bool]] = {
    "native": lambda line: line.lstrip().startswith("{"),
    "freecad": starts_gcode_line,
    "apt": starts_apt_record,
    "gcode": starts_block,
}

#: lines looked at to tell the format
_SAMPLE = 200


def detect_format(lines: list[str], file: str = "<cl>") -> str:
    """The format of a CL file, judged from its first meaningful lines."""
    numbered = [(number, line) for number, line in enumerate(lines[:_SAMPLE], start=1)
                if line.strip() and not line.lstrip().startswith("#")][:20]
    if not numbered:
        raise CLError("the CL file is empty", Location(file))
    sample = [line for _, line in numbered]
    for name, test in DETECTORS.items():
        if test(sample):
            return name
    raise _undetected(numbered, file)


def _undetected(numbered: list[tuple[int, str]], file: str) -> CLError:
    """Name the first line that fits no format, or two lines that fit different ones."""
    known = ", ".join(READERS)
    hint = f"(known: {known}); name the format with --format"
    first_fit: tuple[int, str] | None = None
    for number, line in numbered:
        fits = [name for name, test in _LINE_TESTS.items() if test(line)]
        if not fits:
            return CLError(f"cannot tell the CL format: this line is neither a JSON record, an "
                           f"APT record (WORD/…) nor a G-code block: {_shorten(line.strip())} "
                           f"{hint}", Location(file, number))
        if first_fit is None:
            first_fit = (number, fits[0])
        elif first_fit[1] not in fits:
            return CLError(f"cannot tell the CL format: line {first_fit[0]} reads as "
                           f"{first_fit[1]} but this one as {fits[0]}: "
                           f"{_shorten(line.strip())} {hint}", Location(file, number))
    number = numbered[0][0]
    return CLError(f"cannot tell the CL format from the content {hint}", Location(file, number))


def read_cl(path: str | Path, fmt: str | None = None,
            feed_units: str | None = None) -> list[CLCommand]:
    """Read a whole CL file into commands; every problem is a located CLError."""
    path = Path(path)
    try:
        with path.open("rb") as stream:
            return _read(SourceLines(binary_blocks(stream), str(path)), fmt, feed_units)
    except OSError as exc:
        raise CLError(f"cannot read CL file: {exc.strerror or exc}", Location(str(path))) \
            from None


def read_cl_text(text: str, file: str = "<cl>", fmt: str | None = None,
                 feed_units: str | None = None) -> list[CLCommand]:
    """Read CL text; a leading byte order mark (as Windows editors write) is not content.

    Lines end at LF, CRLF or CR only, as editors count them: ``str.splitlines`` would
    also split at U+2028, U+0085 or a form feed, which JSON allows inside a string, and
    every later error would name the wrong line.
    """
    return _read(SourceLines(text_blocks(text), file), fmt, feed_units)


def _read(lines: SourceLines, fmt: str | None, feed_units: str | None) -> list[CLCommand]:
    return list(stream_commands(lines, fmt, feed_units))


def stream_commands(lines: SourceLines, fmt: str | None = None,
                    feed_units: str | None = None) -> Iterator[CLCommand]:
    """The commands of CL lines, read as they are needed (the format is told at once)."""
    return _reader(lines, fmt, feed_units)(lines, lines.file)


def stream_records(lines: SourceLines, fmt: str | None = None,
                   feed_units: str | None = None) -> Iterator[CLCommand | PlainMove]:
    """:func:`stream_commands` for posting: a native file's plain rapid and linear moves
    come as :data:`~postdsl.cl.model.PlainMove` (checked as the full reading checks them,
    without a command object), every other record as its command."""
    reader = _reader(lines, fmt, feed_units)
    if reader is read_native:
        return read_native(lines, lines.file, straight_taker)
    return reader(lines, lines.file)


class Folder(MoveSink, Protocol):
    """What a first pass folds the CL into: the common moves by their fields (see
    :class:`~postdsl.cl.native.MoveSink`), every other record as a command; when its
    ``moves`` is False, the moves are not handed to it at all."""

    def command(self, command: CLCommand) -> None: ...


class _NoMoves:
    """The sink of a fold that leaves the moves out: a native file's taker does not call
    it (:func:`~postdsl.cl.native.move_taker`), an APT or G-code reader's calls drop."""

    moves = False

    def rapid(self, x: Any, y: Any, z: Any) -> None:
        pass

    def linear(self, x: Any, y: Any, z: Any, feed: Any) -> None:
        pass

    def arc(self, *fields: Any) -> None:
        pass


_NO_MOVES = _NoMoves()


def fold_commands(lines: SourceLines, folder: Folder, fmt: str | None = None,
                  feed_units: str | None = None, log: RecordLog | None = None) -> None:
    """Read CL lines to their end, every check included, into ``folder``.

    The same records as :func:`stream_commands` reads, with the same errors; the
    plain moves reach the folder as fields, without a command object (half a first
    pass's time went into making them): a native file's through its taker, an APT or
    G-code file's from the reader itself, which knows the modal state they need.
    ``log`` keeps every record, in order, for a second pass that replays them
    (:func:`replay`): the plain moves as their fields, the rest as a native record's
    line or as the command itself; it is marked complete once the whole file is read.
    """
    reader = _reader(lines, fmt, feed_units)
    take = folder.command
    sink = folder if folder.moves else _NO_MOVES
    if reader is read_native:
        commands = read_native(lines, lines.file, move_taker(sink, log), log)
        for command in commands:
            take(command)
    elif log is None:
        for command in reader(lines, lines.file, sink=sink):
            take(command)
    else:
        # a reader whose records depend on the ones before (APT, G-code) cannot read one
        # line alone again: the command itself is kept
        keep, dumps = log.keep, pickle.dumps
        for command in reader(lines, lines.file, sink=sink, log=log):
            take(command)
            keep((command.line, dumps(command, pickle.HIGHEST_PROTOCOL)))
    if log is not None:
        log.complete = True


_LINEAR = (LinearMove,)
_RAPID = (RapidMove,)


def replay(log: RecordLog, file: str = "<cl>",
           done: Callable[[int], None] | None = None) -> Iterator[CLCommand | PlainMove]:
    """The records a first pass kept in ``log`` (:func:`fold_commands`), in order, as
    :func:`stream_records` would hand them on, without reading the file: a plain
    straight move as its :data:`~postdsl.cl.model.PlainMove` (kept as its fields: ``(line,
    x, y, z)`` a rapid, ``(line, x, y, z, feed)`` a linear move), every other record as
    its command -- read again from a native record's kept ``(line, text)``, or unpickled
    from ``(line, data)``: only the few records that are not straight moves.  ``done(count)``
    is told the records replayed after each batch.  ``pickle`` loads only what this
    process wrote into its own unnamed file (:mod:`postdsl.cl.record_log`).
    """
    count = 0
    loads = pickle.loads
    for batch in log.batches():
        for record in batch:
            size = len(record)
            if size == 5:
                yield _LINEAR + record
            elif size == 4:
                yield _RAPID + record
            else:
                number, kept = record
                yield loads(kept) if kept.__class__ is bytes else read_record(kept, number, file)
        if done is not None:
            count += len(batch)
            done(count)


def _reader(lines: SourceLines, fmt: str | None, feed_units: str | None) -> Reader:
    """The reader of CL lines' format (given, or told from their start)."""
    file = lines.file
    name = fmt or detect_format(lines.peek(_SAMPLE), file)
    reader = READERS.get(name)
    if reader is None:
        raise CLError(f"unknown CL format '{name}' (known: {', '.join(READERS)})",
                      Location(file))
    if feed_units is not None:
        from postdsl.cl.freecad import FEED_UNITS

        if feed_units not in FEED_UNITS:
            raise CLError(f"unknown feed unit '{feed_units}' (known: {', '.join(FEED_UNITS)})",
                          Location(file))
        if name != "freecad":
            raise CLError(f"--feed-units applies to FreeCAD G-code only: a {name} CL file "
                          f"states its own feed units", Location(file))
        reader = functools.partial(read_freecad, feed_units=feed_units)
    return reader


def _shorten(text: str, limit: int = 60) -> str:
    return text if len(text) <= limit else text[: limit - 1] + "…"
