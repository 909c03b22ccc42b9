"""Structure parameters: names in an expression replaced by the text of other expressions.

``use: peck_words`` with ``with: {word: "'Q'"}`` inlines the structure's blocks with every
read of ``word`` replaced by ``('Q')``.  The replacement is made in the source text, so the
result is an ordinary expression: it is checked, compiled, quoted in errors and written
out by any back end exactly like one a post author typed.  Names are found in the syntax
tree, never by searching the text, so ``word`` inside a string or in ``words`` is left
alone.
"""

from __future__ import annotations

from collections.abc import Mapping

from postdsl.lang.expr import nodes
from postdsl.lang.expr.errors import ExprError


class _AnyFormat:
    """Every format name, so that ``str(x, 'f')`` parses here; the post checks it later."""

    def __contains__(self, name: object) -> bool:
        return True


def substitute(source: str, bindings: Mapping[str, str]) -> str:
    """``source`` with each name in ``bindings`` replaced by its bound text, in brackets.

    A bound text that is itself a bare name replaces the name as it is, so that it may
    also stand in ``changed()`` and ``defined()``; those probes take a parameter's name,
    so a probe of a name bound to anything else is an error.

    Raises:
        ExprError: when ``source`` does not parse, or a probe reads a name bound to a
            value that is not a parameter's name.
    """
    if not bindings:
        return source
    from postdsl.lang.expr.parser import parse  # only a structure with parameters

    tree, names = parse(source, None, _AnyFormat())
    if not names & bindings.keys():
        return source
    spans: list[tuple[int, int, str]] = []
    for node in nodes.walk(tree):
        if isinstance(node, nodes.Name) and node.name in bindings:
            text = bindings[node.name]
            spans.append((node.start, node.end, text if _is_name(text) else f"({text})"))
        elif isinstance(node, nodes.Probe) and node.name in bindings:
            text = bindings[node.name]
            if not _is_name(text):
                raise ExprError(f"{node.function}() takes a parameter's name, but "
                                f"'{node.name}' stands for {text!r}", node.start)
            start = source.index(node.name, node.start + len(node.function))
            spans.append((start, start + len(node.name), text.strip()))
    pieces: list[str] = []
    position = 0
    for start, end, text in sorted(spans):
        pieces += [source[position:start], text]
        position = end
    pieces.append(source[position:])
    return "".join(pieces)


def _is_name(text: str) -> bool:
    return text.strip().isidentifier()


