"""The plain straight moves a first pass read, kept on disk for the second pass.

Posting reads a CL file twice (see :mod:`postdsl.cl.source`).  Of a native
file's records, nearly all are plain rapid and linear moves, and the first pass
has already parsed and checked each of them; parsing and checking their JSON
again costs the second pass most of its time.  So the first pass writes each
plain straight move's fields -- its line number and x, y, z (and feed), as the
reader read them: ints stay ints, a field left out stays None -- into an
anonymous temporary file, in batches written by ``marshal``; the second pass
takes a recorded line's move from there instead of its text, and reads every
other line as usual.  The memory stays flat (one batch at a time); the file
holds about 30 bytes a move and goes when the source is closed.

The second pass still reads every line (for the rest of the records, their
numbers, and the checks on their order), and the source checks once it ends
that the file did not change between the two passes, so a move is never
posted from a record the file no longer holds: a change refuses the program.
``marshal`` reads only what this process wrote into its own unnamed file.
"""

from __future__ import annotations

import marshal
import struct
import tempfile
from typing import Any

from postdsl.cl.model import LinearMove, PlainMove, RapidMove

__all__ = ["MoveLog"]

#: moves per batch: a batch is held in memory while it is written and read
BATCH = 4096

_SIZE = struct.Struct("<Q")


class MoveLog:
    """Plain straight moves, by line number: appended to :attr:`batch` in pass order (a
    :meth:`write` once it holds :data:`BATCH`), then replayed in the same order
    (:meth:`replay`)."""

    def __init__(self) -> None:
        self._file = tempfile.TemporaryFile(prefix="postdsl-moves-")  # noqa: SIM115
        #: the moves kept since the last write: a PlainMove without its class,
        #: (line, x, y, z) or (line, x, y, z, feed); the first pass's taker appends here
        self.batch: list[tuple[Any, ...]] = []

    def write(self) -> None:
        """Write the kept batch to the file."""
        if self.batch:
            data = marshal.dumps(self.batch)
            self._file.write(_SIZE.pack(len(data)))
            self._file.write(data)
            self.batch.clear()

    def replay(self) -> Any:
        """A taker (see :func:`postdsl.cl.native.read_native`) for the second pass: a
        recorded line's :data:`~postdsl.cl.model.PlainMove`, None for any other line.
        Lines must be offered in order; one replay at a time."""
        self.write()
        file = self._file
        file.seek(0)
        size = _SIZE.size

        def batches() -> Any:
            while True:
                head = file.read(size)
                if len(head) < size:
                    return
                yield marshal.loads(file.read(_SIZE.unpack(head)[0]))

        chunks = batches()
        moves: list[tuple[Any, ...]] = next(chunks, [])
        index = 0
        count = len(moves)
        line = moves[0][0] if moves else 0

        def take(text: str, number: int) -> PlainMove | None:
            nonlocal moves, index, count, line
            if number != line:
                return None
            move = moves[index]
            index += 1
            if index == count:
                moves = next(chunks, [])
                index, count = 0, len(moves)
            line = moves[index][0] if count else 0
            return ((LinearMove,) if len(move) == 5 else (RapidMove,)) + move

        return take

    def close(self) -> None:
        self._file.close()
