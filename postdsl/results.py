"""What the editor's calls of :mod:`postdsl.api` return: previews and checks.

They are defined here, not in the API module, because posting never makes one: the
API imports this module (and creates these dataclasses) only when an editor, a preview
or a check first asks.  Import them from :mod:`postdsl.api`, as every other name.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from postdsl.compile.compiler import CompiledPost
    from postdsl.compile.runtime import NCLine
    from postdsl.errors import Location


@dataclass
class PreviewResult:
    """A command's blocks for sample values, with what its conditions said."""

    command: str
    lines: list[NCLine]
    values: dict[str, Any]
    #: (path of the block or item in the post, condition source, result)
    conditions: list[tuple[tuple[Any, ...], str, bool]] = field(default_factory=list)
    error: str | None = None


@dataclass(frozen=True)
class PostProblem:
    """A problem of a post and the YAML path of the node it is about (the cell, the field).

    The path is the one the check that found the problem gave (``PostError.path``), not
    one found back from the line and column; ``()`` when the problem is about no node of
    this document (a YAML syntax error, a node of a base post it extends).
    """

    path: tuple[Any, ...]
    message: str
    location: Location


@dataclass
class CheckResult:
    """A post document checked and compiled: the post when valid, else every problem."""

    post: CompiledPost | None
    problems: list[PostProblem] = field(default_factory=list)


@dataclass(frozen=True)
class ExpressionCheck:
    """An expression checked as the loader checks it: the names it reads, or the error."""

    names: frozenset[str] = frozenset()
    error: str | None = None
    #: 0-based column of the error in the expression
    column: int = 0
