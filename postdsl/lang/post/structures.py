"""``use:`` of structures, with ``if:`` and ``with:`` parameters, resolved into plain blocks.

A block ``{use: drill_words, if: "cycle != 'tapping'", with: {word: "'Q'"}}`` stands for
the structure's blocks, each written only when the ``if:`` holds (as well as its own
``if:``), with every read of the structure parameter ``word`` replaced by ``('Q')``.  A
structure's parameters are the names its ``use:`` sites bind with ``with:``; the checks
make sure every site binds each one the structure reads.

The replacement is made in the expression's text (:func:`postdsl.lang.expr.substitute`), so
what a table runs is an ordinary expression, checked, compiled, quoted in errors and
written out by any back end like one the author typed.  The checks (to report every
resolved expression at the ``use:`` that made it) and the compiler (to compile it) walk
structures with this one function, so what is checked is exactly what runs.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

from postdsl.lang.expr import ExprError, substitute
from postdsl.lang.post import nodes as n

PathKey = tuple[Any, ...]


class StructureLoop(Exception):
    """A structure uses itself, directly or through others: ``chain`` names them in order."""

    def __init__(self, chain: tuple[str, ...], path: PathKey) -> None:
        super().__init__("structure loop: " + " -> ".join(chain))
        self.chain = chain
        #: the ``use`` key that closes the loop
        self.path = path


@dataclass(frozen=True)
class Inlined:
    """A block as a table runs it, with what its ``use:`` sites made of it."""

    block: n.Block
    #: the ``if:`` of the enclosing ``use:`` blocks and of the block, combined, with the
    #: structure parameters replaced (None: written unconditionally)
    condition: str | None
    #: structure parameter -> the expression text it stands for, in the table's names
    bindings: Mapping[str, str] = field(default_factory=dict)
    #: the outermost ``use:`` that brought the block in (None: the table's own block)
    use_path: PathKey | None = None
    #: the structures it came through, outermost first
    via: tuple[str, ...] = ()

    def text(self, expr: n.Expr) -> str:
        """The source of one of the block's expressions as the table runs it."""
        return resolve(expr.source, self.bindings)


def combine(outer: str | None, inner: str | None) -> str | None:
    """Both conditions, as one expression text (either may be absent)."""
    if outer is None:
        return inner
    if inner is None:
        return outer
    return f"({outer}) and ({inner})"


def resolve(source: str, bindings: Mapping[str, str]) -> str:
    """``source`` with the structure parameters replaced, or as written if it is wrong
    (the checks report it where it is written)."""
    try:
        return substitute(source, bindings)
    except ExprError:
        return source


def inline(post: n.Post, blocks: tuple[n.BlockEntry, ...] | None,
           condition: str | None = None, bindings: Mapping[str, str] | None = None,
           use_path: PathKey | None = None, using: tuple[str, ...] = ()) -> Iterator[Inlined]:
    """The blocks a table's ``blocks`` stand for, structures inlined, in order.

    A structure that does not exist is skipped (the checks report it).  Each ``use:``'s
    ``if:`` and ``with:`` texts are resolved in the names of the block that holds it, so a
    nested structure's parameter may be bound to a parameter of the structure using it.

    Raises:
        StructureLoop: when a structure uses itself, directly or through others.
    """
    bound = bindings or {}
    for entry in blocks or ():
        if isinstance(entry, n.Block):
            own = resolve(entry.condition.source, bound) if entry.condition else None
            yield Inlined(entry, combine(condition, own), bound, use_path, using)
            continue
        if entry.use in using:
            raise StructureLoop(using + (entry.use,), entry.path + ("use",))
        target = post.structures.get(entry.use)
        if target is None:
            continue
        test = resolve(entry.condition.source, bound) if entry.condition else None
        inner = {name: resolve(expr.source, bound)
                 for name, expr in (entry.bindings or {}).items()}
        yield from inline(post, target.blocks, combine(condition, test), inner,
                          use_path if use_path is not None else entry.path,
                          using + (entry.use,))


def item_exprs(block: n.Block) -> Iterator[tuple[PathKey, n.Expr]]:
    """The expressions of a block's items (value, ``if:``, ``force_if:``), with their paths."""
    for item in block.items:
        for expr in (getattr(item, "expr", None), item.condition, item.force_if):
            if isinstance(expr, n.Expr):
                yield expr.path, expr


def reads(post: n.Post, name: str) -> frozenset[str]:
    """The names the structure ``name``'s own expressions read (its parameters among them)."""
    structure = post.structures.get(name)
    found: set[str] = set()
    for entry in structure.blocks if structure is not None else ():
        exprs: list[n.Expr] = []
        if isinstance(entry, n.Use):
            exprs += [entry.condition] if entry.condition else []
            exprs += list((entry.bindings or {}).values())
        else:
            exprs += [entry.condition] if entry.condition else []
            exprs += [expr for _path, expr in item_exprs(entry)]
            found |= {item.param for item in entry.items if isinstance(item, n.ParamItem)}
        for expr in exprs:
            if expr.compiled is not None:
                found |= expr.compiled.names
    return frozenset(found)
