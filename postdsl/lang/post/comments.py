"""Which items of a block the control reads inside a comment, found from the post's text.

A post writes a comment as literal text around a value: ``["(", {param: comment}, ")"]``,
``["; ", {param: comment}]``, ``{param: tool_name, prefix: " (", suffix: ")"}``.  The
control reads the value as comment text only while the literal before it has opened a
comment the literal after it closes (or a line comment that runs to the end of the
block).  The compiler uses this to escape the CL text written there by the control's
rule (:mod:`postdsl.lang.control_syntax`), for every post, instead of each post remembering a
``replace:`` table; ``postdsl check`` uses it to find CL text a post writes as NC code.

The scan reads the literal text of every item (fixed text, prefixes, suffixes) in block
order, whatever its ``if:``: a comment opened under a condition is taken as open.  A
value (a parameter's or an expression's) is never read as opening or closing a comment:
the escaping is what keeps it from doing so.
"""

from __future__ import annotations

from collections.abc import Iterable

from postdsl.lang.control_syntax import CommentSyntax
from postdsl.lang.post import nodes as n

#: where the scan is: in NC code, inside an inline comment, in a comment to the block's end
CODE, INLINE, TO_END = 0, 1, 2


def scan(text: str, syntax: CommentSyntax, state: int) -> int:
    """The state after the control has read the literal ``text`` from ``state``."""
    position, length = 0, len(text)
    while position < length:
        if state == TO_END:
            return state
        if state == INLINE:
            end = text.find(syntax.closes, position)
            if end < 0:
                return state
            state, position = CODE, end + len(syntax.closes)
            continue
        opens = text.find(syntax.opens, position) if syntax.closes else -1
        line = text.find(syntax.line_comment, position) if syntax.line_comment else -1
        if opens < 0 and line < 0:
            return state
        if line >= 0 and (opens < 0 or line < opens):
            return TO_END
        state, position = INLINE, opens + len(syntax.opens)
    return state


def _parts(item: n.Item) -> tuple[str, bool, str]:
    """The literal text before an item's value, whether it has a value, the text after."""
    if isinstance(item, (n.PlainText, n.TextItem)):
        return (item.prefix or "") + item.text + (item.suffix or ""), False, ""
    return item.prefix or "", True, item.suffix or ""


def in_comment(items: Iterable[n.Item], syntax: CommentSyntax | None) -> list[bool]:
    """For each item of a block: whether its value stands inside a comment.

    Fixed text items are always False (their text is the post's own, read as written).
    With no known syntax (a post naming no control) nothing is in a comment.
    """
    found: list[bool] = []
    state = CODE
    start = True  # nothing written yet: a structure block's opener counts here
    for item in items:
        before, valued, after = _parts(item)
        if syntax is None:
            found.append(False)
            continue
        if start and before.strip():
            start = False
            if before.lstrip().startswith(syntax.starts_block):
                state = TO_END
        elif start and valued:
            start = False
        state = scan(before, syntax, state)
        found.append(valued and state != CODE)
        state = scan(after, syntax, state)
    return found


__all__ = ["CODE", "INLINE", "TO_END", "in_comment", "scan"]
