"""Errors that reach the user.

Every error a technologist can cause — a bad post, a bad CL file, a value
outside the machine — is one of these, carries the place it comes from and
prints as ``file:line:column: message`` like a compiler.  The CLI turns them
into exit codes; nothing else should ever escape as a traceback.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


def printable(text: str) -> str:
    """``text`` with its control characters escaped (``\\n``, ``\\x1b``).

    A file name may hold a line break or a terminal escape sequence: shown escaped, a
    message stays one line and cannot repaint the terminal it is printed on.
    """
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


@dataclass(frozen=True)
class Location:
    """Where a problem is: a file and, when known, a 1-based line and column.

    A problem of a post also keeps ``path``, the keys and indexes from the root of
    ``file``'s YAML document to the node the problem is about, as jsonschema's
    ``error.path`` does.  The check that found the problem knows it; keeping it here
    spares every reader (the editor marking a cell) from guessing the node back from
    the line and column, which a flow mapping, a block of a list or a node edited in
    memory make ambiguous.  ``None`` when the problem is about no node (a YAML syntax
    error, a file that cannot be read, a CL file); the text is ``file:line:column``
    either way.
    """

    file: str
    line: int | None = None
    column: int | None = None
    path: tuple[Any, ...] | None = None

    def __str__(self) -> str:
        parts = [printable(self.file)]
        if self.line is not None:
            parts.append(str(self.line))
            if self.column is not None:
                parts.append(str(self.column))
        return ":".join(parts)


class PostdslError(Exception):
    """Base of every error meant for the user, located when possible."""

    exit_code = 2

    def __init__(self, message: str, location: Location | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.location = location

    def __str__(self) -> str:
        if self.location is None:
            return self.message
        return f"{self.location}: {self.message}"


class PostError(PostdslError):
    """The machine post (YAML) is invalid: exit status 1."""

    exit_code = 1

    def __init__(
        self,
        message: str,
        location: Location | None = None,
        problems: list[PostError] | None = None,
    ) -> None:
        super().__init__(message, location)
        #: all problems found, when a whole file was checked (this error is the first)
        self.problems: list[PostError] = problems or [self]

    @property
    def path(self) -> tuple[Any, ...] | None:
        """The document path of the node this problem is about, in ``location.file``'s
        document (None when it is about no node)."""
        return self.location.path if self.location is not None else None

    def report(self) -> str:
        """All problems, one per line, in file order."""
        return "\n".join(str(p) for p in self.problems)


class CLError(PostdslError):
    """The CL input is malformed, unknown to the post, or outside the machine: exit status 2."""

    exit_code = 2


class VerifyError(PostdslError):
    """The NC program does not do what the CL says (``postdsl verify``): exit status 4.

    The message names the CL record, the NC line and what differs.
    """

    exit_code = 4
