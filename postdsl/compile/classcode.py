"""The methods ``dataclasses`` writes for postdsl's classes, compiled once per Python.

``dataclasses`` makes each class's ``__init__``, ``__repr__``, ``__eq__``, ``__hash__``
(and a frozen class's ``__setattr__`` and ``__delattr__``) by compiling their text
with ``exec``: some 450 compilations for the 76 classes a ``postdsl post`` loads, on
every run -- a third of its start-up, more than the whole posting of a short program.
The texts depend only on the class definitions, so their code is kept, the way the
posts' generated modules are (:mod:`postdsl.codecache`): :func:`install` puts an
``exec`` into the namespace of the ``dataclasses`` module, where its name is looked up
before the builtin's.  For a class of a postdsl module it takes the code of the text
from one cache entry, compiling only a text it has not seen (the entry is rewritten
at exit when it gained any); every other class goes to the builtin ``exec`` unchanged.

The code is what ``exec`` itself compiles from the same text under the same file name
(``<string>``), so a class is the same either way; the entry is keyed like every
entry of the cache (:func:`postdsl.codecache.environment`: postdsl's code, Python's
version) and read only when trusted as they are (:func:`postdsl.codecache.read_entry`).
A Python whose ``dataclasses`` no longer looks ``exec`` up by name simply compiles as
before.
"""

from __future__ import annotations

import atexit
import builtins
import dataclasses
import marshal
from types import CodeType
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from pathlib import Path

_MAGIC = b"postdsl-classes-2\n"
#: the file name ``exec`` compiles a text under
_FILENAME = "<string>"
#: an entry holding more texts than this (old versions of classes edited since) is
#: rewritten with the texts of the run alone
_LIMIT = 4096


class _Codes:
    """The code of each method text, loaded from the entry on first use."""

    def __init__(self) -> None:
        self.entry: Path | None = None
        self.key = ""
        self.codes: dict[str, CodeType] | None = None
        #: the texts this run asked for
        self.used: set[str] = set()
        #: the entry is rewritten at exit (this run compiled a text it did not hold)
        self.saving = False

    def load(self) -> dict[str, CodeType]:
        from postdsl.codecache import cache_dir, read_marshalled, source_key

        codes: dict[str, CodeType] = {}
        folder = cache_dir()
        if folder is not None:
            self.key = source_key("dataclass methods")
            self.entry = folder / f"{self.key}.classes"
            loaded = read_marshalled(self.entry, _MAGIC, self.key)
            if isinstance(loaded, dict):
                codes = {text: code for text, code in loaded.items()
                         if type(text) is str and type(code) is CodeType}
        self.codes = codes
        return codes

    def code(self, text: str) -> CodeType:
        codes = self.codes if self.codes is not None else self.load()
        self.used.add(text)
        code = codes.get(text)
        if code is None:
            # dont_inherit: compiled as the ``dataclasses`` module's own exec compiles it, not
            # under this module's ``from __future__ import annotations`` (which would turn
            # every annotation of the methods into an unresolvable string)
            code = codes[text] = compile(text, _FILENAME, "exec", dont_inherit=True)
            if not self.saving and self.entry is not None:
                atexit.register(self.save)
                self.saving = True
        return code

    def save(self) -> None:
        from postdsl.codecache import write_entry

        codes = self.codes
        if self.entry is None or not codes:
            return
        if len(codes) > _LIMIT:
            codes = {text: codes[text] for text in self.used}
        write_entry(self.entry, _MAGIC, self.key, marshal.dumps(codes))


_CODES = _Codes()


def _exec(source: Any, globals: dict[str, Any] | None = None,
          locals: dict[str, Any] | None = None) -> None:
    """``exec`` for the ``dataclasses`` module: a method text of a postdsl class runs
    from its kept code, anything else as the builtin runs it."""
    if type(source) is str and globals is not None \
            and str(globals.get("__name__", "")).startswith("postdsl."):
        source = _CODES.code(source)
    builtins.exec(source, globals, locals)


def install() -> None:
    """Route the ``dataclasses`` module's ``exec`` through :func:`_exec` (once).

    Called by the command line's launcher (:mod:`postdsl.launcher`) alone, before it
    imports any module that defines a dataclass: a program that imports postdsl as a
    library keeps the standard library's ``dataclasses`` as it is.
    """
    dataclasses.exec = _exec  # type: ignore[attr-defined]  # the patch the docstring explains
