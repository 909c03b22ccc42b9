"""The methods of postdsl's dataclasses come from the cache after the first run.

Each check runs in a fresh interpreter (a class is made once per process), with a cache
folder of its own.  ``compile`` is counted for the texts ``dataclasses`` hands to
``exec`` (file name ``<string>``): the whole point of :mod:`postdsl.compile.classcode`.
The command line's launcher installs it; a child installs it as the launcher does, or
(``install=False``) not at all, which is how a library user's process makes the classes.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from tests.conftest import ROOT

#: run in the child: count the method texts compiled while postdsl is imported, make a
#: few objects, and report what they do (the same with or without kept code)
_CHILD = r"""
import builtins, dataclasses, json, sys
compiled = []
real = builtins.compile
def counting(source, filename, *args, **kwargs):
    if filename == "<string>":
        compiled.append(source)
    return real(source, filename, *args, **kwargs)
builtins.compile = counting
if INSTALL:
    from postdsl.compile import classcode
    classcode.install()
import postdsl.api
from postdsl.cl.model import LinearMove, ToolChange
from postdsl.lang.post.nodes import Expr
imported = len([s for s in compiled if "__create_fn__" in s])

@dataclasses.dataclass(frozen=True)
class Local:
    '''A class of another module: never kept.'''
    a: int

move = LinearMove(line=3, x=1.5, y=None, z=-2, feed=300)
try:
    move.x = 2
    frozen = False
except dataclasses.FrozenInstanceError:
    frozen = True
expr = Expr(path=("a", 1), source="x > 1", compiled=None)
print(json.dumps({
    "compiled": imported,
    "local": len([s for s in compiled if "__create_fn__" in s]) - imported,
    "repr": [repr(move), repr(expr), repr(ToolChange(line=1, tool_number=4)), repr(Local(1))],
    "eq": [move == LinearMove(line=3, x=1.5, y=None, z=-2, feed=300),
           move == LinearMove(line=3, x=1.5, y=None, z=-2, feed=301)],
    "hash": hash(move) == hash(LinearMove(line=3, x=1.5, y=None, z=-2, feed=300)),
    "frozen": frozen,
    "fields": [f.name for f in dataclasses.fields(move)],
}))
"""


def _child(cache: str, install: bool = True) -> dict:
    env = {**os.environ, "POSTDSL_CACHE_DIR": cache}
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    code = f"INSTALL = {install}\n" + _CHILD
    done = subprocess.run([sys.executable, "-c", code], env=env, cwd=ROOT,
                          capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def test_a_second_run_compiles_no_method_of_a_postdsl_class(tmp_path: Path) -> None:
    cache = tmp_path / "cache"
    first = _child(str(cache))
    second = _child(str(cache))
    assert first["compiled"] > 100  # every class's methods, compiled and kept
    assert [path.suffix for path in cache.iterdir()].count(".classes") == 1
    assert second["compiled"] == 0
    # the other module's class goes to the builtin exec, which compiles without the
    # counted compile(): never through the cache, not even in the first run
    assert first["local"] == second["local"] == 0
    for key in ("repr", "eq", "hash", "frozen", "fields"):
        assert second[key] == first[key], key
    assert second["frozen"] and second["eq"] == [True, False] and second["hash"]


def test_kept_code_makes_the_classes_dataclasses_makes(tmp_path: Path) -> None:
    """The same objects as the standard library's ``dataclasses`` makes, untouched."""
    cache = tmp_path / "cache"
    _child(str(cache))
    kept = _child(str(cache))
    plain = _child(str(cache), install=False)
    # without the launcher's install every text goes to the builtin exec, not compile()
    assert plain["compiled"] == 0 and kept["compiled"] == 0
    for key in ("repr", "eq", "hash", "frozen", "fields"):
        assert kept[key] == plain[key], key


def test_a_damaged_entry_is_compiled_again_and_rewritten(tmp_path: Path) -> None:
    cache = tmp_path / "cache"
    _child(str(cache))
    [entry] = [path for path in cache.iterdir() if path.suffix == ".classes"]
    data = entry.read_bytes()
    entry.write_bytes(data[: len(data) // 2])  # torn
    again = _child(str(cache))
    assert again["compiled"] > 100
    assert entry.read_bytes() == data
    assert _child(str(cache))["compiled"] == 0


#: in the child: every dataclass of every postdsl module, its signature and type hints
_HINTS = r"""
import dataclasses, importlib, inspect, json, pkgutil, sys, typing
if INSTALL:
    from postdsl.compile import classcode
    classcode.install()
import postdsl
seen = {}
for info in pkgutil.walk_packages(postdsl.__path__, "postdsl."):
    if info.name.startswith(("postdsl.launcher",)):
        continue
    module = importlib.import_module(info.name)
    for name, value in vars(module).items():
        if inspect.isclass(value) and dataclasses.is_dataclass(value) \
                and value.__module__ == info.name:
            # the CL classes resolve every annotation at run time; elsewhere some name
            # types imported for the type checker only, as the standard library allows
            hints = typing.get_type_hints(value.__init__) \
                if info.name.startswith("postdsl.cl.") else {}
            seen[f"{info.name}.{name}"] = [str(inspect.signature(value)), sorted(hints)]
print(json.dumps({"classes": seen, "patched": dataclasses.__dict__.get("exec") is not None}))
"""


def _hints(cache: str, install: bool) -> dict:
    env = {**os.environ, "POSTDSL_CACHE_DIR": cache}
    done = subprocess.run([sys.executable, "-c", f"INSTALL = {install}\n" + _HINTS], env=env,
                          cwd=ROOT, capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def test_kept_methods_keep_their_types(tmp_path: Path) -> None:
    """``typing.get_type_hints`` works on every CL class's ``__init__``, and every postdsl
    dataclass's signature is the one the standard library gives (no ``'_type_x'``)."""
    cache = str(tmp_path / "cache")
    _hints(cache, install=True)             # fills the entry
    kept = _hints(cache, install=True)      # methods from the entry
    plain = _hints(cache, install=False)
    assert len(plain["classes"]) > 50
    assert sum(bool(hints) for _, hints in plain["classes"].values()) > 20
    assert kept["classes"] == plain["classes"]
    assert not any("_type_" in signature for signature, _ in kept["classes"].values())


def test_importing_postdsl_leaves_dataclasses_alone(tmp_path: Path) -> None:
    """Only the command line's process routes ``dataclasses`` through the cache."""
    assert _hints(str(tmp_path / "cache"), install=False)["patched"] is False
    assert _hints(str(tmp_path / "cache"), install=True)["patched"] is True
