"""What the editor needs to know about a post's flags: who sets or reads one, and the
checks a new flag name, a start value and a ``set:`` expression must pass.

The checks are the post's own (:func:`postdsl.api.check_expression`, the names the
loader knows), run while the technologist types, so a dialog can say what is wrong
before anything is written; the loader checks the saved post again all the same.
"""

from __future__ import annotations

from typing import Any

from postdsl import api
from tui.model import TableRef, names_read, table_node


def _refs(post: api.Post) -> list[TableRef]:
    """Every table of the post: commands, custom cycles, structures."""
    return ([TableRef("command", str(name)) for name in post.commands]
            + [TableRef("cycle", str(name)) for name in post.custom_cycles]
            + [TableRef("structure", str(name)) for name in post.structures])


def _expr_names(expr: Any) -> set[str]:
    compiled = getattr(expr, "compiled", None)
    return set(compiled.names) if compiled is not None else set()


def flag_users(post: api.Post, name: str) -> list[str]:
    """The tables that set flag ``name`` or read it (or ``prev_name``) in a condition or
    an expression: what would break if the flag were removed."""
    read = {name, f"prev_{name}"}
    users = []
    for ref in _refs(post):
        table = table_node(post, ref)
        names = set(names_read(post, ref))
        sets = getattr(table, "sets", None) or {}
        for expr in sets.values():
            names |= _expr_names(expr)
        for expr in (getattr(table, "assume", None) or {}).values():
            names |= _expr_names(expr)
        for rule in getattr(table, "reject", None) or ():
            names |= _expr_names(rule.condition)
        if name in sets or names & read:
            users.append(ref.name)
    return users


def check_flag_name(post: api.Post, text: str) -> str | None:
    """Why ``text`` cannot name a new flag (None: it can)."""
    if not text.isidentifier():
        return "a flag name is a word: letters, digits and _, not starting with a digit"
    if text in post.flags:
        return f"there is already a flag '{text}'"
    if text in api.parameters():
        return f"'{text}' is a CL parameter; a flag must not hide it"
    if text in post.variables:
        return f"'{text}' is a variable; a flag must not hide it"
    if text in post.options:
        return f"'{text}' is an option; a flag must not hide it"
    if text.startswith("prev_") or text == "next_tool":
        return f"'{text}' is a name the engine gives (prev_…, next_…); choose another"
    return None


def check_start_value(text: str) -> str | None:
    """Why ``text`` cannot be a flag's start value: a literal, as ``flags:`` holds."""
    stripped = text.strip()
    if not stripped:
        return "give a start value: a number, true/false, none or text"
    if stripped[0] in "\"'" and (len(stripped) < 2 or stripped[-1] != stripped[0]):
        return "the text has no closing quote"
    return None


def start_value(text: str) -> Any:
    """The value a start value's text stands for (quoted text is text: ``'5'``)."""
    from tui.model import parse_value

    stripped = text.strip()
    if len(stripped) >= 2 and stripped[0] in "\"'" and stripped[-1] == stripped[0]:
        return stripped[1:-1]
    return parse_value(stripped)


def check_set_expression(post: api.Post, ref: TableRef, text: str) -> str | None:
    """Why ``text`` cannot be a ``set:`` value of the table ``ref``: the post's own
    expression check (syntax, unknown names), with a custom cycle's parameters known."""
    table = table_node(post, ref)
    extra = list(getattr(table, "parameters", None) or {})
    check = api.check_expression(text, post, extra)
    if check.error is None:
        return None
    where = f" (at column {check.column + 1})" if check.column else ""
    return f"{check.error}{where}"


def check_set_flag(post: api.Post, text: str, taken: set[str]) -> str | None:
    """Why ``text`` cannot be the flag a ``set:`` entry gives a value to."""
    name = text.strip()
    if not name:
        return "name the flag"
    if name in taken:
        return f"the table already sets '{name}': change that entry (enter)"
    if name not in post.flags:
        declared = ", ".join(post.flags) or "none yet"
        return (f"'{name}' is not a flag: declare it first in the variables editor (f3, "
                f"flags); declared: {declared}")
    return None
