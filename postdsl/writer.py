"""Write NC text to a file atomically.

A half-written NC program is worse than none: a control may run what is
there.  So the program is written to a temporary file beside the target and
renamed over it only when complete; any error removes the temporary file.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable
from pathlib import Path


def join_lines(lines: Iterable[str], line_ending: str = "\n", final_newline: bool = True) -> str:
    text = line_ending.join(lines)
    if final_newline and text:
        text += line_ending
    return text


def write_atomic(path: str | Path, text: str) -> None:
    """Replace ``path`` with ``text`` in one rename; never leaves a partial file.

    A symbolic link is written through (the file it points to is replaced, the link
    stays): renaming over the link itself would leave the program beside, say, the
    machine's network share instead of on it.
    """
    path = Path(os.path.realpath(path))
    directory = path.parent if str(path.parent) else Path(".")
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp",
                                         dir=directory)
    try:
        with os.fdopen(handle, "w", encoding="utf-8", newline="") as stream:
            stream.write(text)
            stream.flush()
            os.fsync(stream.fileno())
        if path.exists():
            os.chmod(temporary, path.stat().st_mode & 0o777)
        else:
            os.chmod(temporary, 0o644)
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
