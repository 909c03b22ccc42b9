"""What the table editor asks while a post is edited: the post checked without
raising, the CL vocabulary, expressions and number formats checked as they are typed.

Apart from loading because these calls never post: they describe and check a post
document that may be half-written.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any

from postdsl.api.loading import Options, compile_source
from postdsl.cl.model import (
    COMMANDS,
    EVENTS,
    GROUPS,
    PARAMETERS,
    ParamInfo,
    command_fields,
    with_previous,
)
from postdsl.errors import Location, PostError
from postdsl.lang.expr import ExprError, compile_expr
from postdsl.lang.formats import NumberFormat
from postdsl.lang.loader import PostSource
from postdsl.lang.post import Post
from postdsl.lang.post.build import format_stand_ins
from postdsl.lang.post.build import known_names as document_names

if TYPE_CHECKING:
    from postdsl.results import CheckResult, ExpressionCheck


def check_source(source: PostSource, options: Options | None = None) -> CheckResult:
    """Check and compile a post document without raising: an editor re-checks after every edit.

    Each problem keeps the document path its check found it at (``PostError.path``), so
    the editor can mark the item or field a problem is about.  A problem in a base
    post (``extends:``) has no node in this document: its path is ``()``.
    """
    from postdsl.results import CheckResult, PostProblem

    try:
        return CheckResult(compile_source(source, options))
    except PostError as exc:
        return CheckResult(None, [
            PostProblem(p.path if p.path is not None and p.location is not None and
                        p.location.file == source.file else (), p.message,
                        p.location or Location(source.file))
            for p in exc.problems])


def command_groups() -> dict[str, list[str]]:
    """CL command names by group (program, tool and spindle, motion…), as editors list them."""
    groups: dict[str, list[str]] = {group: [] for group in GROUPS}
    for name, cls in COMMANDS.items():
        groups.setdefault(cls.group, []).append(name)
    return groups


def command_doc(name: str) -> str:
    """What a CL command means ('' for names outside the vocabulary, e.g. custom cycles)."""
    cls = COMMANDS.get(name) or EVENTS.get(name)
    return cls.doc if cls is not None else ""


def place_in_post(path: tuple[Any, ...]) -> str:
    """A path in a post document in an editor's words: ``deep_drill, block 2, item 3``,
    ``formats › coord › decimals``."""
    if path and path[0] in ("commands", "custom_cycles", "structures") and len(path) >= 2:
        from postdsl.run.trace import place  # tracing is the editor's, not posting's

        return place(path)
    return " › ".join(str(part) for part in path)


def commands_setting(name: str) -> list[str]:
    """The CL commands whose records carry parameter ``name`` (in vocabulary order)."""
    return [command for command, cls in COMMANDS.items()
            if any(f.name == name for f in command_fields(cls))]


def parameters() -> Mapping[str, ParamInfo]:
    """Every CL parameter a post may print or test, with its meaning (the editor's picker)."""
    return PARAMETERS


def check_expression(source: str, post: Post | Mapping[str, Any],
                     extra_names: Iterable[str] = ()) -> ExpressionCheck:
    """Validate a condition or computed value while it is typed.

    Known names are the CL parameters, the variables and options of the post (its
    model or document) and ``extra_names`` (a custom cycle's parameters), as for the
    loader.
    """
    from postdsl.results import ExpressionCheck

    if isinstance(post, Post):
        names = with_previous({*PARAMETERS, *post.variables, *post.options, *post.flags})
        formats = {name: NumberFormat() for name in post.formats}
    else:  # a document: only its names are needed, not a whole model
        names = document_names(post)
        formats = format_stand_ins(post)
    names |= with_previous(extra_names)
    if not source.strip():
        return ExpressionCheck(error="the expression is empty")
    try:
        return ExpressionCheck(compile_expr(source, names, formats).names)
    except ExprError as exc:
        return ExpressionCheck(error=exc.message, column=exc.column)


def render_number(spec: Mapping[str, Any], value: float) -> str:
    """``value`` written with a format as a post declares it (the editors' live examples).

    Raises FormatSpecError, whose ``key`` names the option at fault.
    """
    return NumberFormat.from_mapping(dict(spec)).render(value)
