"""Python source for an expression, from its syntax tree, for :mod:`postdsl.compile.codegen`.

The post compiler turns a post into one generated module; a condition such as
``changed(x) and feed > 0`` is worth writing inline there rather than calling a
chain of closures.  Only the post's own syntax tree is written out: names become
string constants through ``repr``, numbers and strings through ``repr``, and every
operation keeps the semantics of :mod:`postdsl.lang.expr.compiler` - the same checked
kernels, the same :class:`~postdsl.lang.expr.runtime.Blame` and so the same error
messages.  A node kind not written inline here is the closure the expression
compiler already made for that sub-tree, bound as a module constant: correct first,
fast where it counts (names, probes, ``not``/``and``/``or``, comparisons).

The text produced reads ``values`` (the engine's parameter dict), ``changed`` and
``state`` from the enclosing function; a missing parameter raises ``KeyError`` with
its name, which the caller turns into the interpreter's "has no value" error.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

from postdsl.lang.expr import nodes
from postdsl.lang.expr.compiler import Compiler, Expression
from postdsl.lang.expr.runtime import NUMBERS, ORDERINGS, Blame, Mismatch, TextFormat

#: registers a Python object as a constant of the generated module, returns its name
Bind = Callable[[Any], str]


def emit_expression(expression: Expression, bind: Bind) -> str:
    """A Python expression computing ``expression`` in the generated module."""
    tree = expression.tree
    if tree is None:  # an expression made without its tree: parse its checked source again
        from postdsl.lang.expr.parser import parse

        tree, _names = parse(expression.source, None, expression.formats or None)
    return _Emitter(expression.source, bind, expression.formats).emit(tree)


def literal(value: Any, bind: Bind) -> str:
    """``value`` as Python source: ``repr`` for plain scalars, a bound constant otherwise."""
    if value is None or value.__class__ in (bool, int, str):
        return repr(value)
    if value.__class__ is float and math.isfinite(value):
        return repr(value)
    return bind(value)


class _Emitter:
    def __init__(self, source: str, bind: Bind,
                 formats: Mapping[str, TextFormat] | None = None) -> None:
        self._source = source
        self._bind = bind
        self._compiler = Compiler(source, formats)
        self._temps = 0

    def emit(self, node: nodes.Node) -> str:
        code = self._compiler.compile(node)
        if code.constant:  # folded at load time, exactly as the interpreter folds it
            return literal(code.value, self._bind)
        match node:
            case nodes.Name(name=name):
                return f"values[{name!r}]"
            case nodes.Probe(function="changed", name=name):
                return f"({name!r} in changed)"
            case nodes.Probe(name=name):
                return f"(values.get({name!r}) is not None)"
            case nodes.Unary(op="not", operand=operand):
                return f"(not {self.emit(operand)})"
            case nodes.Logical(op=op, operands=operands):
                return "bool(" + f" {op} ".join(self.emit(o) for o in operands) + ")"
            case nodes.Comparison(first=first, rest=((symbol, right),)) if symbol in ("==", "!="):
                return f"({self.emit(first)} {symbol} {self.emit(right)})"
            case nodes.Comparison(first=first, rest=((symbol, right),)) if symbol in ORDERINGS:
                inline = self._ordering(node, first, symbol, right)
                if inline is not None:
                    return inline
        # any other node: the expression compiler's own closure for this sub-tree
        return f"{self._bind(code.run)}(state)"

    def _ordering(self, node: nodes.Comparison, first: nodes.Node, symbol: str,
                  right: nodes.Node) -> str | None:
        """``x > 0``: with a constant number or text, only the other operand is checked."""
        right_code = self._compiler.compile(right)
        value = right_code.value
        if not right_code.constant or not isinstance(value, (*NUMBERS, str)):
            return None
        kind = "_NUMBERS" if isinstance(value, NUMBERS) else "str"
        blame = Blame(repr(symbol), self._source[first.start:right.end],
                      (_parameter(first), _parameter(right)))
        self._temps += 1
        temp = f"_o{self._temps}"
        constant = literal(value, self._bind)
        # the test runs first: it takes the operand's value, the comparison reads it
        return (f"({temp} {symbol} {constant} "
                f"if isinstance({temp} := {self.emit(first)}, {kind}) "
                f"else _blame({self._bind(blame)}, {temp}, {constant}))")


def _parameter(node: nodes.Node) -> str | None:
    return node.name if isinstance(node, nodes.Name) else None


def raise_blame(blame: Blame, left: Any, right: Any) -> Any:
    """Raise the mismatch error of an inlined ordering, worded as the interpreter does."""
    raise blame(Mismatch(), (left, right))


#: what the generated text expects in its module's namespace
NAMESPACE: dict[str, Any] = {"_NUMBERS": NUMBERS, "_blame": raise_blame}
