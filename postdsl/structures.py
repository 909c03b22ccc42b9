"""``use:`` of structures, with ``if:`` and ``with:`` parameters, resolved into plain blocks.

A block ``{use: drill_words, if: "cycle != 'tapping'", with: {word: "'Q'"}}`` stands for
the structure's blocks, each written only when the ``if:`` holds (as well as its own
``if:``), with every read of the structure parameter ``word`` replaced by ``('Q')``.  A
structure's parameters are the names its ``use:`` sites bind with ``with:``; the loader
checks that every site binds each one the structure reads.

The loader (to check every resolved expression, located at the ``use:`` that made it) and
the compiler (to compile it) walk structures with this one function, so what is checked is
exactly what runs.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

from postdsl.expr import ExprError, substitute

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

    #: the block as written in its table or structure
    block: Mapping[str, Any]
    #: where the block is written
    path: PathKey
    #: the ``if:`` of the enclosing ``use:`` blocks and of the block, combined, with the
    #: structure parameters replaced (None: written unconditionally)
    condition: str | None
    #: structure parameter -> the expression text it stands for, in the table's names
    bindings: Mapping[str, str] = field(default_factory=dict)
    #: the outermost ``use:`` block that brought the block in (None: the table's own)
    use_path: PathKey | None = None


def combine(outer: str | None, inner: str | None) -> str | None:
    """Both conditions, as one expression text (either may be absent)."""
    if outer is None:
        return inner
    if inner is None:
        return outer
    return f"({outer}) and ({inner})"


def inline(blocks: list[Any], path: PathKey, structures: Mapping[str, Any],
           condition: str | None = None, bindings: Mapping[str, str] | None = None,
           use_path: PathKey | None = None,
           using: tuple[str, ...] = ()) -> Iterator[Inlined]:
    """The blocks a table's ``blocks`` stand for, structures inlined.

    A structure that does not exist is skipped (the loader reports it).  Each structure's
    ``with:`` texts are resolved in the names of the block that uses it before they are
    passed on, so a nested structure's parameter may be bound to the parameter of the
    structure using it.  Text that does not parse is passed on as written: the loader
    reports it where it is written.

    Raises:
        StructureLoop: when a structure uses itself, directly or through others.
    """
    bound = bindings or {}
    for index, block in enumerate(blocks):
        here = path + (index,)
        if not isinstance(block, Mapping):
            continue
        if "use" not in block:
            own = block.get("if")
            own = resolve(own, bound) if isinstance(own, str) else None
            yield Inlined(block, here, combine(condition, own), bound, use_path)
            continue
        target = block["use"]
        if target in using:
            raise StructureLoop(using + (target,), here + ("use",))
        if not isinstance(structures.get(target), list):
            continue
        test = block.get("if")
        test = resolve(test, bound) if isinstance(test, str) else None
        inner = {str(name): resolve(str(text), bound)
                 for name, text in (block.get("with") or {}).items()}
        yield from inline(structures[target], ("structures", target), structures,
                          combine(condition, test), inner,
                          use_path if use_path is not None else here, using + (target,))


def resolve(source: str, bindings: Mapping[str, str]) -> str:
    """``source`` with the structure parameters replaced, or as written if it is wrong."""
    try:
        return substitute(source, bindings)
    except ExprError:
        return source


def item_sources(block: Mapping[str, Any]) -> Iterator[tuple[PathKey, str]]:
    """The expression texts of a block's items, with their place in the block."""
    for position, item in enumerate(block.get("items") or ()):
        if isinstance(item, Mapping):
            for key in ("expr", "if", "force_if"):
                if isinstance(item.get(key), str):
                    yield ("items", position, key), item[key]
