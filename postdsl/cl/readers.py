"""Pick a CL reader by name or by content, and read a file with it.

Each reader lives in its own module beside this one and turns text lines
into CL commands; this module only knows their names and how to tell their
files apart, so adding a format is one module plus one line here.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path

from postdsl.cl.apt import looks_like_apt, read_apt
from postdsl.cl.freecad import looks_like_freecad, read_freecad
from postdsl.cl.model import CLCommand
from postdsl.cl.native import read_native
from postdsl.errors import CLError, Location
from postdsl.textfile import TextFileError, read_text

_LINE_END = re.compile(r"\r\n?|\n")

Reader = Callable[[Iterable[str], str], Iterator[CLCommand]]

#: format name -> reader(lines, file name)
READERS: dict[str, Reader] = {"native": read_native, "freecad": read_freecad,
                             "apt": read_apt}

#: format name -> test on the first meaningful lines of a file
DETECTORS: dict[str, Callable[[list[str]], bool]] = {
    "native": lambda lines: all(line.lstrip().startswith("{") for line in lines),
    "freecad": looks_like_freecad,
    "apt": looks_like_apt,
}


def detect_format(lines: list[str], file: str = "<cl>") -> str:
    """The format of a CL file, judged from its first meaningful lines."""
    sample = [line for line in lines[:200] if line.strip() and not line.lstrip().startswith("#")]
    sample = sample[:20]
    if not sample:
        raise CLError("the CL file is empty", Location(file))
    for name, test in DETECTORS.items():
        if test(sample):
            return name
    formats = ", ".join(READERS)
    raise CLError(f"cannot tell the CL format from the content (known: {formats}); "
                  f"name it with --format", Location(file, 1))


def read_cl(path: str | Path, fmt: str | None = None) -> list[CLCommand]:
    """Read a whole CL file into commands; every problem is a located CLError."""
    path = Path(path)
    try:
        text = read_text(path)
    except OSError as exc:
        raise CLError(f"cannot read CL file: {exc.strerror or exc}", Location(str(path))) \
            from None
    except TextFileError as exc:
        raise CLError(exc.message, Location(str(path), exc.line, exc.column)) from None
    return read_cl_text(text, str(path), fmt)


def read_cl_text(text: str, file: str = "<cl>", fmt: str | None = None) -> list[CLCommand]:
    """Read CL text; a leading byte order mark (as Windows editors write) is not content.

    Lines end at LF, CRLF or CR only, as editors count them: ``str.splitlines`` would
    also split at U+2028, U+0085 or a form feed, which JSON allows inside a string, and
    every later error would name the wrong line.
    """
    lines = _LINE_END.split(text.removeprefix("\ufeff"))
    if lines[-1] == "":
        lines.pop()  # the final line end ends the last line; it starts none
    name = fmt or detect_format(lines, file)
    reader = READERS.get(name)
    if reader is None:
        raise CLError(f"unknown CL format '{name}' (known: {', '.join(READERS)})",
                      Location(file))
    return list(reader(lines, file))
