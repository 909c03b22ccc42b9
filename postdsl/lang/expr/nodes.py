"""Syntax tree of the expression language, shared by the parser and the compiler.

Nodes are immutable and carry their source span, so that the compiler can quote the exact
sub-expression in run-time errors, and their depth, so that the parser can bound how deep
compiling and evaluating will recurse.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True, slots=True)
class Node:
    """Base of the syntax tree: the span for quoting in errors, the depth bounding recursion."""

    #: source span, parentheses included, for quoting the sub-expression in run-time errors
    start: int
    end: int
    #: levels of operators in the sub-tree (0 for a leaf); bounded so that compiling and
    #: evaluating cannot overflow the stack
    depth: int


@dataclass(frozen=True, slots=True)
class Const(Node):
    """A literal, kept as its value so compiling needs no conversion."""

    value: Any


@dataclass(frozen=True, slots=True)
class Name(Node):
    """A parameter, variable, flag or option read by name."""

    name: str


@dataclass(frozen=True, slots=True)
class Probe(Node):
    """``changed(name)`` or ``defined(name)``: they inspect a parameter instead of reading it."""

    function: str
    name: str


@dataclass(frozen=True, slots=True)
class List(Node):
    """A list literal, for membership tests (``x in [1, 2]``)."""

    items: tuple[Node, ...]


@dataclass(frozen=True, slots=True)
class Unary(Node):
    """``-x`` or ``not x``."""

    op: str
    operand: Node


@dataclass(frozen=True, slots=True)
class Logical(Node):
    """``and`` / ``or`` over any number of operands: a flat chain keeps the tree shallow."""

    op: str
    operands: tuple[Node, ...]


@dataclass(frozen=True, slots=True)
class Arithmetic(Node):
    """A left-associative chain such as ``a - b + c``, flat so that long sums stay shallow."""

    first: Node
    rest: tuple[tuple[str, Node], ...]


@dataclass(frozen=True, slots=True)
class Comparison(Node):
    """A comparison chain such as ``0 < x <= 5``, with Python's pairwise meaning."""

    first: Node
    rest: tuple[tuple[str, Node], ...]


@dataclass(frozen=True, slots=True)
class Call(Node):
    """A call of one of the language's functions (the names
    :mod:`postdsl.lang.expr.runtime` has)."""

    function: str
    args: tuple[Node, ...]


@dataclass(frozen=True, slots=True)
class Conditional(Node):
    """``then if test else otherwise``: only the branch the test picks is evaluated."""

    then: Node
    test: Node
    otherwise: Node


@dataclass(frozen=True, slots=True)
class Index(Node):
    """``target[index]``: an item of a list (``tools[0]``) or a character of a text."""

    target: Node
    index: Node


@dataclass(frozen=True, slots=True)
class Text(Node):
    """``str(value, 'format')``: a number as the named format of the post writes it.

    The format is a literal name, checked when the post loads, so that a misspelt name is
    a load-time error and the format's renderer can be bound once, at compile time.
    """

    value: Node
    format: str


def children(node: Node) -> tuple[Node, ...]:
    """The operands of a node, in source order (none for a leaf)."""
    match node:
        case Unary(operand=operand) | Text(value=operand):
            return (operand,)
        case Logical(operands=parts) | List(items=parts) | Call(args=parts):
            return parts
        case Arithmetic(first=first, rest=rest) | Comparison(first=first, rest=rest):
            return (first, *(operand for _symbol, operand in rest))
        case Conditional(then=then, test=test, otherwise=otherwise):
            return (then, test, otherwise)
        case Index(target=target, index=index):
            return (target, index)
    return ()


def walk(node: Node) -> Iterator[Node]:
    """Every node of the tree, without recursion (trees may be 64 levels deep)."""
    stack: list[Node] = [node]
    while stack:
        current = stack.pop()
        yield current
        stack.extend(children(current))
