"""A progress bar for posting or verifying a large CL file, drawn on a terminal only.

Posting a program of millions of moves takes a while; without a sign of life a
user cannot tell a slow post from a hung one.  The bar counts the bytes each pass
has read of the CL file (the only measure known before posting: the number of NC
lines is not), one bar per pass ("reading" the file for the header's summary,
then "posting" or "verifying").  It is drawn on stderr, and only when stderr is
a terminal and the file is large enough to take time: pipes, CI logs and tests'
captured output never see it, and the NC program on stdout is never mixed with it.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from typing import TextIO

__all__ = ["LARGE", "ProgressBar", "terminal_progress"]

#: files smaller than this (bytes) post in about a second: no bar
LARGE = 4 << 20
#: seconds between two redraws: a redraw costs a write to the terminal
_INTERVAL = 0.1
_WIDTH = 30


class ProgressBar:
    """Draws ``label [####......]  42%  12.3/29.1 MB`` on one terminal line."""

    def __init__(self, stream: TextIO, minimum: int = LARGE) -> None:
        self.stream = stream
        self.minimum = minimum
        self._label = ""
        self._drawn = 0.0
        self._visible = False

    def update(self, label: str, done: int, total: int | None) -> None:
        """A pass has read ``done`` of ``total`` bytes (no bar for a small or unknown size)."""
        if total is None or total < self.minimum:
            return
        now = time.monotonic()
        if label == self._label and now - self._drawn < _INTERVAL and done < total:
            return
        self._label, self._drawn = label, now
        share = min(done / total, 1.0)
        filled = round(share * _WIDTH)
        self.stream.write(f"\r{label:9} [{'#' * filled}{'.' * (_WIDTH - filled)}] "
                          f"{share:4.0%}  {done / 1e6:.1f}/{total / 1e6:.1f} MB")
        self.stream.flush()
        self._visible = True

    def finish(self) -> None:
        """Clear the bar's line, so what is printed next starts on a clean line."""
        if self._visible:
            self.stream.write("\r\x1b[2K")
            self.stream.flush()
            self._visible = False


def terminal_progress(stream: TextIO | None = None,
                      ) -> tuple[Callable[[str, int, int | None], None] | None,
                                 Callable[[], None]]:
    """A progress callback for :func:`postdsl.api.write_program` when ``stream`` (stderr)
    is a terminal, else None; and a function that clears the bar."""
    stream = stream if stream is not None else sys.stderr
    if not stream.isatty():
        return None, lambda: None
    bar = ProgressBar(stream)
    return bar.update, bar.finish
