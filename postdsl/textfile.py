"""Read a user's text file (a CL program, a post) whatever editor or CAM system saved it.

Files reach postdsl from Windows CAM systems, PowerShell redirections and
text editors, so the bytes are not always plain UTF-8: a UTF-8 byte order
mark, UTF-16 or UTF-32 with a byte order mark are unambiguous and are
decoded.  Anything else must be UTF-8; when it is not (a Latin-1 file, a
binary file, UTF-16 without a byte order mark, which is full of NUL bytes)
the error names the line and column of the first bad byte, as every other
input error does, instead of Python's "can't decode byte 0xe9 in position
5123".  A UTF-8 byte order mark is kept as U+FEFF at the start of the text:
the post editor saves the text it read, and a reader that does not want the
mark strips it.
"""

from __future__ import annotations

import codecs
from pathlib import Path

__all__ = ["TextFileError", "decode_text", "read_text"]

#: byte order marks that say unambiguously how a file is encoded (UTF-32 first: its
#: little-endian mark starts with UTF-16's)
_BOMS = ((codecs.BOM_UTF32_LE, "utf-32"), (codecs.BOM_UTF32_BE, "utf-32"),
         (codecs.BOM_UTF16_LE, "utf-16"), (codecs.BOM_UTF16_BE, "utf-16"))


class TextFileError(ValueError):
    """A file that is not text postdsl can read; ``line`` and ``column`` are 1-based."""

    def __init__(self, message: str, line: int | None = None,
                 column: int | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.line = line
        self.column = column


def read_text(path: str | Path) -> str:
    """The text of a file; OSError when it cannot be opened, TextFileError when it is not text."""
    return decode_text(Path(path).read_bytes())


def decode_text(data: bytes) -> str:
    """Bytes -> text: UTF-8, or UTF-16/UTF-32 announced by a byte order mark."""
    for bom, codec in _BOMS:
        if data.startswith(bom):
            try:
                text = data.decode(codec)
            except UnicodeDecodeError as exc:
                raise TextFileError(f"the file starts with a {codec.upper()} byte order mark "
                                    f"but is not {codec.upper()} text ({exc.reason})") from None
            return _no_nul(text)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line, column = _position(data[:exc.start])
        raise TextFileError(f"not UTF-8 text (byte 0x{data[exc.start]:02x} here); save the file "
                            f"as UTF-8", line, column) from None
    return _no_nul(text)


def _no_nul(text: str) -> str:
    """No text format holds NUL: it is a binary file, or UTF-16 saved without its mark."""
    index = text.find("\x00")
    if index >= 0:
        line = text.count("\n", 0, index) + 1
        column = index - (text.rfind("\n", 0, index) + 1) + 1
        raise TextFileError("the file contains a NUL byte: it is not a text file (or is "
                            "UTF-16 without a byte order mark; save it as UTF-8)", line, column)
    return text


def _position(before: bytes) -> tuple[int, int]:
    """1-based line and column (in characters) just after ``before``, the valid UTF-8 prefix."""
    line = before.count(b"\n") + 1
    start = before.rfind(b"\n") + 1
    return line, len(before[start:].decode("utf-8", errors="replace")) + 1
