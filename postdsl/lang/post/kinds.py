"""What kind of value a name or an expression of a post gives: number, text, list, bool.

Read from the post's typed model and the expressions' syntax trees, never by running
them.  Its own small module because both the meaning checks (:mod:`postdsl.lang.post.checks`)
and the compiler ask it -- the compiler at every compile, also of a post read back from
the cache, which must not load the whole of the checks.
"""

from __future__ import annotations

from typing import Any

from postdsl.cl.model import PARAMETERS
from postdsl.lang.post import nodes as n


def kind(name: str, post: n.Post) -> str:
    """"number", "text" or "list" for a parameter, variable or option; "" when only the CL
    can tell."""
    info = PARAMETERS.get(name)
    if info is not None:
        return info.kind
    if name in post.variables:
        return "text" if isinstance(post.variables[name].value, str) else "number"
    if name in post.options:
        return "text" if post.options[name].type == "string" else "number"
    return ""  # a custom cycle's parameter: the CL may give a number or text


def may_be_number(tree: Any, post: n.Post) -> bool:
    """Whether an expression may give a number (a bool is written 1/0, not a number here).

    Read from its syntax tree: a constant or a name by its kind (:func:`kind`; a flag by
    its value; a custom cycle's parameter is the CL's, whatever it is: not counted), a
    function call, arithmetic unless an operand is text (``'Q' + str(q, 'int')``
    joins texts), a unary minus; ``str(value, 'fmt')`` is text, a comparison or a test
    is a bool; a conditional may give either branch.  An index into a list is not known
    and not counted.  Used to keep every written number going through a format.
    """
    from postdsl.cl.model import PREVIOUS
    from postdsl.lang.expr import nodes as e

    def kinds(node: Any) -> set[str]:
        if isinstance(node, e.Const):
            value = node.value
            if isinstance(value, bool):
                return {"bool"}
            if isinstance(value, (int, float)):
                return {"number"}
            return {"text"} if isinstance(value, str) else {"other"}
        if isinstance(node, e.Name):
            name = node.name
            if name not in PARAMETERS and name.startswith(PREVIOUS):
                name = name[len(PREVIOUS):]
            if name in post.flags:
                value = post.flags[name].value
                return {"bool"} if isinstance(value, bool) else \
                    {"number"} if isinstance(value, (int, float)) else {"text"}
            found = kind(name, post)
            return {found} if found else {"other"}
        if isinstance(node, e.Text):
            return {"text"}
        if isinstance(node, (e.Comparison, e.Probe)):
            return {"bool"}
        if isinstance(node, e.Unary):
            return {"bool"} if node.op == "not" else {"number"}
        if isinstance(node, e.Call):
            return {"number"}
        if isinstance(node, e.Arithmetic):
            parts: set[str] = set()
            for operand in (node.first, *(right for _op, right in node.rest)):
                parts |= kinds(operand)
            # + joins two texts or adds two numbers, never one of each: a text operand
            # makes the whole a text
            return {"text"} if "text" in parts else {"number"}
        if isinstance(node, e.Conditional):
            return kinds(node.then) | kinds(node.otherwise)
        if isinstance(node, e.Logical):
            if node.op == "not":
                return {"bool"}
            union: set[str] = set()
            for operand in node.operands:
                union |= kinds(operand)
            return union
        return {"other"}

    return tree is not None and "number" in kinds(tree)
