"""A CL file read in passes, so a program of millions of moves is never held in memory.

A header prints what only the whole program knows (its tools, its extents, its
machining time), so posting reads the file twice: a first pass folds it into a
:class:`~postdsl.run.program.ProgramSummary`, the second posts as it reads.  Every
reader check runs in the first pass too, so a program cut short or a bad record
is refused before a line of NC is written.  The first pass (:meth:`CLSource.fold`)
hands the plain moves (native, APT and G-code alike) to the fold as fields, without
making their command objects, which the fold does not need, and keeps every record
on disk, so the second (:meth:`CLSource.records`) posts them without
reading the file again (:mod:`postdsl.cl.record_log`).

A regular file is simply opened again for each pass.  Standard input (``-``) or a
FIFO can be read only once: the first pass copies the bytes it reads into an
unnamed-on-exit temporary file, and later passes read that copy.  The copy is
made while the first pass reads and checks the lines, so a hostile stream
(``/dev/zero``, a line without end) stops at the same located error as a file
and never fills the disk.  A regular file that changes while a pass reads it, or
between two passes that both read it, is refused: the header would describe
another program than the one posted.  (A second pass that replays what the first
kept posts exactly the program the header describes, whatever the file holds by
then.)
"""

from __future__ import annotations

import os
import stat
import sys
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from types import TracebackType
from typing import IO, BinaryIO

from postdsl.cl.lines import SourceLines, binary_blocks
from postdsl.cl.model import CLCommand, PlainMove
from postdsl.cl.readers import Folder, fold_commands, replay, stream_commands, stream_records
from postdsl.cl.record_log import RecordLog
from postdsl.errors import CLError, Location

__all__ = ["STDIN", "CLSource", "Progress"]

#: the CL path that means standard input
STDIN = "-"

#: called with the bytes read so far in a pass
Progress = Callable[[int], None]


class CLSource:
    """One CL file, readable as commands once per pass; use as a context manager.

    ``size`` is the file's length in bytes when known before reading (a regular
    file), for a progress bar.
    """

    def __init__(self, path: str | Path, fmt: str | None = None,
                 feed_units: str | None = None) -> None:
        self.path = str(path)
        self.fmt = fmt
        self.feed_units = feed_units
        self.size: int | None = None
        self._spool: IO[bytes] | None = None
        self._spooled = False
        #: the records the last fold kept, for records(); and the bytes it read
        self._log: RecordLog | None = None
        self._folded_bytes = 0
        self._identity: tuple[int, int, int, int] | None = None
        if self.path != STDIN:
            try:
                status = os.stat(self.path)
            except OSError as exc:
                raise self._unreadable(exc) from None
            if stat.S_ISREG(status.st_mode):
                self._identity = _identity(status)
                self.size = status.st_size

    def __enter__(self) -> CLSource:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.close()

    def close(self) -> None:
        """Remove the copy of a stream read once and the moves a first pass kept."""
        if self._spool is not None:
            self._spool.close()
            self._spool = None
        if self._log is not None:
            self._log.close()
            self._log = None

    def commands(self, progress: Progress | None = None) -> Iterator[CLCommand]:
        """A new pass over the file: its commands, read as they are needed.

        Every pass after the first of a stream reads the first pass's copy, so the
        first pass must have been read to its end.
        """
        stream = self._open()
        # _read yields plain moves (PlainMove tuples) beside the commands when the reader
        # takes them; the stream's consumers (postdsl.check.motion, the engine) take both
        return self._read(stream, progress)  # type: ignore[return-value]

    def records(self, progress: Progress | None = None) -> Iterator[CLCommand | PlainMove]:
        """A new pass for posting (:meth:`postdsl.run.engine.Engine.texts`): :meth:`commands`,
        with a native file's plain straight moves as :data:`~postdsl.cl.model.PlainMove`,
        without a command object.  After a :meth:`fold`, the records it kept are replayed
        and the file is not read again."""
        log = self._log
        if log is not None and log.complete:
            return self._replay(log, progress)
        return self._read(self._open(), progress, posting=True)

    def fold(self, folder: Folder, progress: Progress | None = None) -> None:
        """A new pass over the whole file into ``folder`` (a first pass's summary):
        the same reading and checks as :meth:`commands`, but the common moves reach
        the folder without a command object, and every record is kept for
        :meth:`records` (see :mod:`postdsl.cl.record_log`)."""
        if self._log is not None:
            self._log.close()
        self._log = RecordLog()
        for _ in self._read(self._open(), progress, folder):
            pass

    def _replay(self, log: RecordLog,
                progress: Progress | None) -> Iterator[CLCommand | PlainMove]:
        """The records a fold kept; ``progress`` told the bytes they took in the file."""
        if progress is None:
            return replay(log, self.name)
        total, read = log.count + len(log.batch), self._folded_bytes
        return replay(log, self.name, lambda count: progress(read * count // max(total, 1)))

    def _open(self) -> BinaryIO:
        if self._identity is not None:
            try:
                stream: BinaryIO = open(self.path, "rb")  # noqa: SIM115 (closed by _read)
            except OSError as exc:
                raise self._unreadable(exc) from None
            return stream
        if self._spooled:
            if self._spool is None:
                raise CLError("the CL input was read once and its copy is gone",
                              Location(self.path))
            return open(self._spool.name, "rb")
        self._spooled = True
        self._spool = tempfile.NamedTemporaryFile(  # noqa: SIM115 (closed by close())
            prefix="postdsl-cl-", suffix=".spool")
        if self.path == STDIN:
            source: BinaryIO = os.fdopen(os.dup(sys.stdin.fileno()), "rb")
        else:
            try:
                source = open(self.path, "rb")  # noqa: SIM115 (closed by _read)
            except OSError as exc:
                raise self._unreadable(exc) from None
        return _Tee(source, self._spool)  # type: ignore[return-value]  # a _Tee reads as a BinaryIO

    def _read(self, stream: BinaryIO, progress: Progress | None,
              folder: Folder | None = None, *,
              posting: bool = False) -> Iterator[CLCommand | PlainMove]:
        """The commands of a pass (plain moves as such when ``posting``), or none when
        ``folder`` takes them all."""
        counted: BinaryIO = _Counted(stream, progress) \
            if progress or folder is not None else stream  # type: ignore[assignment]  # a _Counted reads as a BinaryIO
        with stream:
            try:
                lines = SourceLines(binary_blocks(counted), self.name)
                if posting:
                    yield from stream_records(lines, self.fmt, self.feed_units)
                elif folder is None:
                    yield from stream_commands(lines, self.fmt, self.feed_units)
                else:
                    fold_commands(lines, folder, self.fmt, self.feed_units, self._log)
                    self._folded_bytes = counted.done  # type: ignore[attr-defined]  # a _Counted when folding
            except OSError as exc:
                raise self._unreadable(exc) from None
        if isinstance(stream, _Tee):
            stream.spool.flush()
        self._unchanged()

    @property
    def name(self) -> str:
        """The file's name in messages (``<stdin>`` for standard input)."""
        return "<stdin>" if self.path == STDIN else self.path

    def _unchanged(self) -> None:
        if self._identity is None:
            return
        try:
            now = _identity(os.stat(self.path))
        except OSError as exc:
            raise self._unreadable(exc) from None
        if now != self._identity:
            raise CLError("the CL file changed while it was being posted (it is read twice: "
                          "once for the header's tools, extents and time, once to post); "
                          "post it again once it is written", Location(self.path))

    def _unreadable(self, exc: OSError) -> CLError:
        return CLError(f"cannot read CL file: {exc.strerror or exc}", Location(self.name))


def _identity(status: os.stat_result) -> tuple[int, int, int, int]:
    return (status.st_dev, status.st_ino, status.st_size, status.st_mtime_ns)


class _Tee:
    """A byte stream read once whose bytes are also copied into ``spool``."""

    def __init__(self, source: BinaryIO, spool: IO[bytes]) -> None:
        self.source = source
        self.spool = spool

    def read(self, size: int = -1) -> bytes:
        data = self.source.read(size)
        self.spool.write(data)
        return data

    def __enter__(self) -> _Tee:
        return self

    def __exit__(self, *exc: object) -> None:
        self.source.close()


class _Counted:
    """A byte stream that reports the bytes read so far to ``progress``."""

    def __init__(self, source: BinaryIO, progress: Progress | None) -> None:
        self.source = source
        self.progress = progress
        self.done = 0

    def read(self, size: int = -1) -> bytes:
        data = self.source.read(size)
        self.done += len(data)
        if self.progress is not None:
            self.progress(self.done)
        return data
