"""What a posting run is made of, shared by the engine and the code generated for a post.

The NC line a table writes, the error a condition or item raises at run time, and
the mark of a value never set.  They live below both :mod:`postdsl.compile.codegen` and
:mod:`postdsl.run.engine`: the engine runs generated code, and generated code makes these
objects, so the code generator reads them from here instead of importing the engine
back (an import circle, hidden inside a function, that the import contract forbids).
"""

from __future__ import annotations

from typing import Any, NamedTuple

from postdsl.lang.expr import ExprEvalError


class PostEvalError(ExprEvalError):
    """A condition or item of the post failed at run time; ``path`` is where it is in the post."""

    def __init__(self, message: str, path: tuple[Any, ...]) -> None:
        super().__init__(message)
        self.path = path


class NCLine(NamedTuple):
    """One written line and where it came from (for previews, reviews and editors).

    A named tuple rather than a frozen dataclass: one is made per NC line, and a tuple
    is made in a fifth of the time (the generated tables build it with ``tuple.__new__``).
    """

    text: str
    #: the CL command that caused it, and the table that wrote it (differs after a redirect)
    command: str
    table: str
    #: 1-based line of the CL command in its file (0 for implicit commands)
    cl_line: int
    #: index of the block in the compiled table
    block: int


#: a value never set (``values.get(name, MISSING)``): None is a value a parameter may have
MISSING = object()
