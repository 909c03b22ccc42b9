"""The lines of a CL file, read as a stream with a bound on every line.

A CL file can be large (a surface finish of millions of moves) or hostile (a
megabyte without a line end, ``/dev/zero``): reading it whole would hold it all
in memory, and a line without end would never finish.  So the bytes are read
in blocks, decoded incrementally (UTF-8, or UTF-16/UTF-32 announced by a byte
order mark, as :mod:`postdsl.textfile` explains) and cut into lines at LF,
CRLF or CR -- the line ends editors count, so every error names the line an
editor shows.  A line longer than :data:`MAX_LINE` characters, a NUL byte or a
byte that is not text is a located :class:`CLError` as soon as it is met.

Whether the last line ended with a line end is remembered
(:attr:`SourceLines.final_newline`): G-code cut inside its last line still
reads as G-code (``G0 X30`` cut to ``X3``), and the line end is the only
evidence that the last block is whole.
"""

from __future__ import annotations

import codecs
import itertools
import re
from collections.abc import Iterable, Iterator
from typing import BinaryIO

from postdsl.errors import CLError, Location

__all__ = ["MAX_LINE", "SourceLines", "binary_blocks", "text_blocks"]

#: the longest line a CL file may hold, in characters: real CL lines are far shorter (an
#: APT record continued with ``$`` is bounded the same way, joined)
MAX_LINE = 1_000_000
#: bytes read at a time
_BLOCK = 1 << 16

_BOMS = ((codecs.BOM_UTF32_LE, "utf-32"), (codecs.BOM_UTF32_BE, "utf-32"),
         (codecs.BOM_UTF16_LE, "utf-16"), (codecs.BOM_UTF16_BE, "utf-16"),
         (codecs.BOM_UTF8, "utf-8-sig"))
_LINE_END = re.compile(r"\r\n|\r|\n")


class _Undecodable(Exception):
    """Bytes that are not text, with the text decoded before them."""

    def __init__(self, message: str, before: str) -> None:
        super().__init__(message)
        self.message = message
        self.before = before


def binary_blocks(stream: BinaryIO) -> Iterator[str]:
    """Decoded text of a binary stream, block by block; _Undecodable at a bad byte."""
    head = stream.read(4)
    codec = "utf-8"
    for bom, name in _BOMS:
        if head.startswith(bom):
            codec = name
            break
    decoder = codecs.getincrementaldecoder(codec)()
    data = head
    while True:
        buffered = decoder.getstate()[0]
        try:
            text = decoder.decode(data, final=not data)
        except UnicodeDecodeError as exc:
            whole = buffered + data
            before = whole[:exc.start].decode(codec, errors="replace")
            if codec == "utf-8":
                message = (f"not UTF-8 text (byte 0x{whole[exc.start]:02x} here); save the "
                           f"file as UTF-8")
            else:
                shown = codec.removesuffix("-sig").upper()
                message = (f"the file starts with a {shown} byte order mark but is not "
                           f"{shown} text ({exc.reason})")
            raise _Undecodable(message, before) from None
        if text:
            yield text
        if not data:
            return
        data = stream.read(_BLOCK)


def text_blocks(text: str) -> Iterator[str]:
    """Text already in memory (the editor's buffer), as blocks: a leading BOM is not content."""
    text = text.removeprefix("\ufeff")
    for start in range(0, len(text), _BLOCK):
        yield text[start:start + _BLOCK]


class SourceLines:
    """The lines of one CL source, streamed; iterate once (after :meth:`peek`, if used)."""

    def __init__(self, blocks: Iterable[str], file: str) -> None:
        self.file = file
        #: whether the last line ended with a line end; known once the lines are exhausted
        #: (an empty file counts as ended)
        self.final_newline = True
        self._lines = self._split(iter(blocks))
        self._peeked: list[str] = []

    def peek(self, count: int) -> list[str]:
        """Up to ``count`` first lines, which iteration then still yields."""
        while len(self._peeked) < count:
            line = next(self._lines, None)
            if line is None:
                break
            self._peeked.append(line)
        return list(self._peeked)

    def __iter__(self) -> Iterator[str]:
        # chained in C: a line reaches the reader through one generator, not two
        peeked, self._peeked = self._peeked, []
        return itertools.chain(peeked, self._lines)

    def _split(self, blocks: Iterator[str]) -> Iterator[str]:
        """Lines from blocks, each character looked at once (a long line is kept as pieces,
        never copied again per block)."""
        number = 1
        pieces: list[str] = []
        size = 0
        skip_lf = False  # a CR ended the last block: an LF starting this one is its CRLF
        ended = True
        while True:
            try:
                block = next(blocks, None)
            except _Undecodable as exc:
                lines = _LINE_END.split("".join(pieces) + exc.before)
                raise CLError(exc.message, Location(self.file, number + len(lines) - 1,
                                                    len(lines[-1]) + 1)) from None
            if block is None:
                break
            start = 0
            if skip_lf and block.startswith("\n"):
                start = 1
            skip_lf = False
            if "\r" not in block and "\x00" not in block:
                # the common case, at the speed of str.split: LF line ends only; every
                # whole line is shorter than the block, only the first can be longer
                parts = block[start:].split("\n")
                if len(parts) > 1:
                    self._check(parts[0], number, size)
                    pieces.append(parts[0])
                    yield "".join(pieces)
                    pieces, size = [], 0
                    number += 1
                    last = len(parts) - 1
                    yield from parts[1:last]
                    number += last - 1
                    piece = parts[last]
                else:
                    piece = parts[0]
                self._check(piece, number, size)
                if piece:
                    pieces.append(piece)
                    size += len(piece)
                ended = not pieces
                continue
            for match in _LINE_END.finditer(block, start):
                piece = block[start:match.start()]
                self._check(piece, number, size)
                pieces.append(piece)
                yield "".join(pieces)
                pieces, size = [], 0
                number += 1
                start = match.end()
                skip_lf = match.group() == "\r" and start == len(block)
            piece = block[start:]
            self._check(piece, number, size)
            if piece:
                pieces.append(piece)
                size += len(piece)
            ended = not pieces
        self.final_newline = ended
        if pieces:
            yield "".join(pieces)

    def _check(self, piece: str, number: int, before: int) -> None:
        """A NUL byte, or a line beyond the bound, in a piece of line ``number``."""
        index = piece.find("\x00")
        if index >= 0:
            raise CLError("the file contains a NUL byte: it is not a text file (or is UTF-16 "
                          "without a byte order mark; save it as UTF-8)",
                          Location(self.file, number, before + index + 1))
        if before + len(piece) > MAX_LINE:
            raise CLError(f"line {number} is longer than {MAX_LINE:,} characters: this is not "
                          f"a CL file, or a damaged one", Location(self.file, number))
