"""The methods of postdsl's dataclasses come from the cache after the first run.

Each check runs in a fresh interpreter (a class is made once per process), with a cache
folder of its own.  ``compile`` is counted for the texts ``dataclasses`` hands to
``exec`` (file name ``<string>``): the whole point of :mod:`postdsl.classcode`.
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
import postdsl.api
from postdsl.cl.model import LinearMove, ToolChange
from postdsl.post.nodes import Expr
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


def _child(cache: str) -> dict:
    env = {**os.environ, "POSTDSL_CACHE_DIR": cache}
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    done = subprocess.run([sys.executable, "-c", _CHILD], env=env, cwd=ROOT,
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
    """The same objects with the cache switched off (every text compiled, nothing kept)."""
    cache = tmp_path / "cache"
    _child(str(cache))
    kept = _child(str(cache))
    plain = _child("")
    assert plain["compiled"] > 100 and kept["compiled"] == 0
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
