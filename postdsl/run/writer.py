"""Write NC text to a file atomically, and only where a file belongs.

A half-written NC program is worse than none: a control may run what is
there.  So the program is written to a temporary file beside the target and
renamed over it only when complete; any error, and SIGTERM or SIGINT, removes
the temporary file.  The program is written as it is posted (:func:`open_atomic`
gives a buffered stream), so a program of millions of lines is never held in
memory.  A SIGKILL cannot be caught, so temporary files carry a
recognisable name (``.<target>.postdsl-<pid>-<random>.tmp``) and a later
write to the same target removes those of its own that are old.

A rename replaces whatever the path names, so the target is looked at first:
a FIFO is written into (streaming to a DNC sender that reads it), a device
node, socket or folder is never replaced, and the files being posted (the CL
program, the post) are never overwritten by their own output.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import signal
import stat
import tempfile
import threading
import time
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import BinaryIO, TextIO

__all__ = ["BUFFER", "STALE_AFTER", "UnsafeTarget", "copy_spooled", "is_temporary_of",
           "join_lines", "open_atomic", "spooled", "write_atomic"]

#: bytes buffered before a write reaches the system: large enough that a program of short
#: lines costs few system calls, small enough to be nothing beside the interpreter
BUFFER = 1 << 20

#: seconds after which a temporary file of ours is taken as left by a killed run (a write
#: takes well under a second; an hour leaves a slow network share plenty of room)
STALE_AFTER = 3600.0

_TEMPORARY = re.compile(r"\.postdsl-[0-9]+-[A-Za-z0-9_]+\.tmp")

_KINDS = ((stat.S_ISDIR, "a folder"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


class UnsafeTarget(ValueError):
    """A path the NC program must not be written to; the message says why."""

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.message = message


def join_lines(lines: Iterable[str], line_ending: str = "\n", final_newline: bool = True) -> str:
    text = line_ending.join(lines)
    if final_newline and text:
        text += line_ending
    return text


def is_temporary_of(name: str, target: str) -> bool:
    """Whether ``name`` is a temporary file :func:`write_atomic` writes ``target`` through."""
    prefix = f".{target}"
    return name.startswith(prefix) and _TEMPORARY.fullmatch(name[len(prefix):]) is not None


def write_atomic(path: str | Path, text: str,
                 keep: Iterable[tuple[str | Path | int, str]] = ()) -> None:
    """Replace ``path`` with ``text`` in one rename; never leaves a partial file.

    See :func:`open_atomic`, which this writes through.
    """
    with open_atomic(path, keep) as stream:
        stream.write(text)


@contextlib.contextmanager
def open_atomic(path: str | Path,
                keep: Iterable[tuple[str | Path | int, str]] = ()) -> Iterator[TextIO]:
    """A buffered text stream whose content replaces ``path`` when the block ends cleanly.

    Everything written goes to a temporary file beside the target, renamed over it
    only when the ``with`` block ends without an exception; an exception (a CL error
    met halfway through posting), SIGTERM or SIGINT removes the temporary file and
    leaves the target as it was.  The target is looked at before anything is
    written: a symbolic link is written through (the file it points to is replaced,
    the link stays): renaming over the link itself would leave the program beside,
    say, the machine's network share instead of on it.  ``keep`` lists (file, what it
    is) pairs the target must not be, e.g. the CL program being posted (a file given
    as an int is an open file descriptor: standard input the CL is read from).  A FIFO gets
    the whole program once it is complete (spooled to an unnamed temporary file
    meanwhile).  Raises UnsafeTarget for a target that is not a file to replace,
    OSError when the system refuses.
    """
    path = Path(os.path.realpath(path))
    try:
        status = path.stat()
    except FileNotFoundError:
        status = None
    if status is not None:
        for other, what in keep:
            if _same_file(status, other):
                raise UnsafeTarget(f"it is {what}")
        if stat.S_ISFIFO(status.st_mode):
            with spooled() as stream:
                yield stream
                stream.flush()
                _write_fifo(path, stream.buffer)
            return
        for test, kind in _KINDS:
            if test(status.st_mode):
                raise UnsafeTarget(f"it is {kind}, not a file; postdsl only replaces regular "
                                   f"files")
    directory = path.parent if str(path.parent) else Path(".")
    _remove_stale(directory, path.name)
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.postdsl-{os.getpid()}-",
                                         suffix=".tmp", dir=directory)
    try:
        with _cleaned_on_termination():
            with os.fdopen(handle, "w", encoding="utf-8", newline="",
                           buffering=BUFFER) as stream:
                yield stream
                stream.flush()
                os.fsync(stream.fileno())
            os.chmod(temporary, status.st_mode & 0o777 if status is not None else 0o644)
            os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def _same_file(status: os.stat_result, other: str | Path | int) -> bool:
    """Whether the target (of ``status``) is ``other``: a path, or an open file
    descriptor -- standard input redirected from a file has no path to compare, and
    ``post M - -o in.jsonl < in.jsonl`` would otherwise replace the CL program."""
    try:
        found = os.fstat(other) if isinstance(other, int) else os.stat(other)
    except (OSError, ValueError):
        return False
    return (found.st_dev, found.st_ino) == (status.st_dev, status.st_ino)


@contextlib.contextmanager
def spooled() -> Iterator[TextIO]:
    """An unnamed temporary text file (gone when closed, or when the process dies).

    For output that may only be handed on once it is complete (a FIFO, standard
    output), without holding it in memory meanwhile.
    """
    with tempfile.TemporaryFile("w+", encoding="utf-8", newline="",
                                buffering=BUFFER) as stream:
        yield stream


def copy_spooled(stream: TextIO, target: BinaryIO) -> None:
    """Copy a :func:`spooled` file's whole content into ``target`` (bytes, in blocks)."""
    stream.flush()
    source = stream.buffer
    source.seek(0)
    while block := source.read(BUFFER):
        target.write(block)


def _write_fifo(path: Path, spool: BinaryIO) -> None:
    """Stream the program into a FIFO, if a program reads it; never wait for one.

    The program is complete before the first byte goes in, so the reader gets all of it
    or, if it stops reading, an error here; there is no file to leave half-written.
    """
    try:
        fd = os.open(path, os.O_WRONLY | os.O_NONBLOCK)
    except OSError as exc:
        if exc.errno == errno.ENXIO:
            raise UnsafeTarget("it is a FIFO that no program is reading") from None
        raise
    try:
        os.set_blocking(fd, True)
        spool.seek(0)
        while data := spool.read(BUFFER):
            view = memoryview(data)
            while view:
                written = os.write(fd, view)
                view = view[written:]
    finally:
        os.close(fd)


def _remove_stale(directory: Path, target: str) -> None:
    """Remove temporary files a killed run left for ``target``: only ours, only old ones."""
    now = time.time()
    with contextlib.suppress(OSError):
        for entry in os.scandir(directory):
            if not is_temporary_of(entry.name, target):
                continue
            with contextlib.suppress(OSError):
                info = entry.stat(follow_symlinks=False)
                if stat.S_ISREG(info.st_mode) and now - info.st_mtime > STALE_AFTER:
                    os.unlink(entry.path)


@contextlib.contextmanager
def _cleaned_on_termination() -> Iterator[None]:
    """Turn SIGTERM into an exception while writing, so the temporary file is removed.

    Python already raises KeyboardInterrupt on SIGINT; SIGTERM's default ends the
    process on the spot.  Handlers can only be set in the main thread; elsewhere (an
    editor's worker) the caller's own handling applies.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def terminate(signum: int, frame: object) -> None:
        raise SystemExit(128 + signum)

    previous = signal.signal(signal.SIGTERM, terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous if previous is not None else signal.SIG_DFL)
