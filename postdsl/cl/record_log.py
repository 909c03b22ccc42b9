"""The records a first pass read, kept on disk so the second pass need not read the file.

Posting reads a CL program twice (see :mod:`postdsl.cl.source`): a first pass
folds it into the header's summary, the second posts it.  The first pass has
already read and checked every record; reading, decoding and checking the file
once more cost the second pass most of its time.  So a first pass keeps each
record it read, in reading order, as a small tuple of plain values (numbers,
texts, bytes, None; what a tuple holds is the readers' business, see
:func:`postdsl.cl.readers.replay`) in an anonymous temporary file, in batches
written by ``marshal``, and the second pass replays them.  The memory stays flat
(one batch at a time); the file goes when the source is closed.

What the second pass posts is then exactly what the first pass read, and what
the header describes, even if the file is rewritten in between.  Only this
process writes and reads its own unnamed file, so nothing loaded from it (by
``marshal`` here, or a kept command by ``pickle``) comes from anyone else.
"""

from __future__ import annotations

import marshal
import struct
import tempfile
from collections.abc import Iterator
from typing import Any

__all__ = ["BATCH", "RecordLog"]

#: records per batch: a batch is held in memory while it is written and read
BATCH = 4096

_SIZE = struct.Struct("<Q")


class RecordLog:
    """Records as tuples of plain values, in reading order:
    appended to :attr:`batch` (a :meth:`write` once it holds :data:`BATCH`), then
    replayed in the same order (:meth:`batches`)."""

    def __init__(self) -> None:
        self._file = tempfile.TemporaryFile(prefix="postdsl-records-")  # noqa: SIM115
        #: the records kept since the last write; a first pass's taker appends here
        self.batch: list[tuple[Any, ...]] = []
        #: the records kept in all
        self.count = 0
        #: set by the first pass once it has read the whole program without an error: only
        #: then can a second pass replay it instead of reading the file
        self.complete = False

    def keep(self, record: tuple[Any, ...]) -> None:
        """Append one record (the hot path appends to :attr:`batch` itself)."""
        self.batch.append(record)
        if len(self.batch) >= BATCH:
            self.write()

    def write(self) -> None:
        """Write the kept batch to the file."""
        if self.batch:
            data = marshal.dumps(self.batch)
            self._file.write(_SIZE.pack(len(data)))
            self._file.write(data)
            self.count += len(self.batch)
            self.batch.clear()

    def batches(self) -> Iterator[list[tuple[Any, ...]]]:
        """The kept records, batch by batch, from the first; one replay at a time."""
        self.write()
        file = self._file
        file.seek(0)
        size = _SIZE.size
        while True:
            head = file.read(size)
            if len(head) < size:
                return
            yield marshal.loads(file.read(_SIZE.unpack(head)[0]))

    def close(self) -> None:
        self._file.close()
