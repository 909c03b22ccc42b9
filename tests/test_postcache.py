"""The cache of checked posts (postdsl/compile/postcache.py): a post from the cache posts what a
freshly read one posts, a stale or corrupt entry is never used, a bad post is reported
as without a cache, and a warm ``postdsl post`` loads neither ruamel, jsonschema
nor the expression parser."""

from __future__ import annotations

import json
import os
import pickle
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from postdsl import api, codecache
from postdsl.cli import main
from postdsl.compile import postcache
from tests.conftest import ROOT, THESIS_EPOCH, THESIS_TIME
from tests.test_snapshots import corpus_cases


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    folder = tmp_path / "cache"
    monkeypatch.setenv(codecache.CACHE_VARIABLE, str(folder))
    return folder


def _checks(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """Record every post that is read and checked (a cache miss)."""
    calls: list[str] = []
    real = postcache.check

    def counting(source: api.PostSource) -> object:
        calls.append(source.file)
        return real(source)

    monkeypatch.setattr(postcache, "check", counting)
    return calls


def _post(machine: str | Path, cl_path: Path, options: dict[str, str] | None = None) -> str:
    return _text(api.load_post(machine, options), api.read_cl(cl_path), cl_path)


def _corpus() -> dict[str, list[Path]]:
    programs: dict[str, list[Path]] = {}
    for machine, cl_path in corpus_cases():
        programs.setdefault(machine, []).append(cl_path)
    return programs


@pytest.mark.parametrize("machine", sorted(_corpus()))
def test_a_post_from_the_cache_writes_what_a_fresh_one_writes(
        machine: str, cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Every bundled machine, every program the corpus posts it with."""
    path = ROOT / "machines" / f"{machine}.yaml"
    monkeypatch.setenv(codecache.CACHE_VARIABLE, "")
    fresh = api.load_post(path)
    monkeypatch.setenv(codecache.CACHE_VARIABLE, str(cache))
    calls = _checks(monkeypatch)
    api.load_post(path)  # read, checked and kept
    cached = api.load_post(path)
    assert calls == [str(path)]
    assert len(list(cache.glob("*.post"))) == 1
    for cl_path in _corpus()[machine]:
        commands = api.read_cl(cl_path)
        assert _text(cached, commands, cl_path) == _text(fresh, commands, cl_path), cl_path


def _text(post: api.CompiledPost, commands: list[api.CLCommand], cl_path: Path) -> str:
    try:
        lines = api.post_commands(post, commands, cl_file=cl_path.name, now=THESIS_TIME)
    except api.CLError as exc:
        return f"REFUSED: {exc}"
    return api.post_text(post, lines)


def test_each_options_value_is_applied_to_the_cached_post(
        cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    cl_path = ROOT / "examples" / "feeler_drilling.apt"
    calls = _checks(monkeypatch)
    default = _post("fanuc", cl_path)
    chosen = _post("fanuc", cl_path, {"prestage_next_tool": "true"})
    assert chosen != default
    assert _post("fanuc", cl_path) == default
    assert len(calls) == 1
    monkeypatch.setenv(codecache.CACHE_VARIABLE, "")
    assert _post("fanuc", cl_path, {"prestage_next_tool": "true"}) == chosen


def _family(folder: Path) -> Path:
    """A post that extends a base in its folder (a copy of the VMC500 post)."""
    folder.mkdir(parents=True, exist_ok=True)
    vmc500 = (ROOT / "machines" / "vmc500.yaml").read_text(encoding="utf-8")
    (folder / "base.yaml").write_text(vmc500, encoding="utf-8")
    child = folder / "child.yaml"
    child.write_text("postdsl: 1\nextends: base.yaml\nmachine: {name: Child}\n",
                     encoding="utf-8")
    return child


def test_a_changed_base_is_read_again(tmp_path: Path, cache: Path,
                                      monkeypatch: pytest.MonkeyPatch) -> None:
    child = _family(tmp_path / "posts")
    calls = _checks(monkeypatch)
    first = api.load_post(child)
    api.load_post(child)
    assert calls == [str(child)]
    base = tmp_path / "posts" / "base.yaml"
    text = base.read_text(encoding="utf-8")
    assert "rapid_rate:" in text
    base.write_text(text.replace("rapid_rate:", "rapid_rate: 1234 #", 1), encoding="utf-8")
    second = api.load_post(child)
    assert calls == [str(child), str(child)]
    assert second.machine.rapid_rate == 1234
    assert first.machine.rapid_rate != 1234
    assert api.load_post(child).machine.rapid_rate == 1234
    assert len(calls) == 2


def test_a_base_that_shadows_the_one_used_is_read(tmp_path: Path, cache: Path,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    machines = tmp_path / "machines"
    (machines / "bases").mkdir(parents=True)
    vmc500 = (ROOT / "machines" / "vmc500.yaml").read_text(encoding="utf-8")
    (machines / "family.yaml").write_text(vmc500, encoding="utf-8")
    child = tmp_path / "child.yaml"
    child.write_text("postdsl: 1\nextends: family\nmachine: {name: Child}\n",
                     encoding="utf-8")
    monkeypatch.setattr(postcache, "machines_dir", lambda: machines)
    import postdsl.lang.loader
    monkeypatch.setattr(postdsl.lang.loader, "machines_dir", lambda: machines)
    calls = _checks(monkeypatch)
    assert api.load_post(child).machine.rapid_rate != 777
    api.load_post(child)
    assert len(calls) == 1
    # machines/bases/NAME.yaml comes before machines/NAME.yaml
    shadow = vmc500.replace("rapid_rate:", "rapid_rate: 777 #", 1)
    (machines / "bases" / "family.yaml").write_text(shadow, encoding="utf-8")
    assert api.load_post(child).machine.rapid_rate == 777
    assert len(calls) == 2


def test_a_changed_post_is_read_again(tmp_path: Path, cache: Path,
                                      monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "mill.yaml"
    text = (ROOT / "machines" / "vmc500.yaml").read_text(encoding="utf-8")
    path.write_text(text, encoding="utf-8")
    calls = _checks(monkeypatch)
    rate = api.load_post(path).machine.rapid_rate
    path.write_text(text.replace("rapid_rate:", "rapid_rate: 4321 #", 1), encoding="utf-8")
    assert api.load_post(path).machine.rapid_rate == 4321 != rate
    assert len(calls) == 2


def _entry(cache: Path) -> Path:
    (entry,) = cache.glob("*.post")
    return entry


def test_a_corrupt_entry_is_read_again_and_rewritten(cache: Path,
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    cl_path = ROOT / "examples" / "vmc500_cycles.jsonl"
    fresh = _post("vmc500", cl_path)
    entry = _entry(cache)
    data = bytearray(entry.read_bytes())
    data[-100] ^= 0xFF  # a flipped bit in the payload
    entry.write_bytes(bytes(data))
    calls = _checks(monkeypatch)
    assert _post("vmc500", cl_path) == fresh
    assert len(calls) == 1
    assert _post("vmc500", cl_path) == fresh  # the rewritten entry is sound
    assert len(calls) == 1
    entry.write_bytes(entry.read_bytes()[:len(data) // 2])  # torn
    assert _post("vmc500", cl_path) == fresh
    assert len(calls) == 2


class _Shell:
    def __reduce__(self) -> tuple[object, ...]:
        return (os.system, ("echo owned > owned.txt",))


def test_an_entry_calling_a_function_is_refused(tmp_path: Path, cache: Path,
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    """A sound header over a pickle that would run a command: never loaded."""
    monkeypatch.chdir(tmp_path)
    api.load_post("vmc500")
    entry = _entry(cache)
    key = entry.stem
    codecache.write_entry(entry, postcache._MAGIC, key, pickle.dumps(([], [], _Shell())))
    calls = _checks(monkeypatch)
    assert api.load_post("vmc500").machine.name
    assert not (tmp_path / "owned.txt").exists()
    assert len(calls) == 1


def test_an_unwritable_cache_still_posts(tmp_path: Path,
                                         monkeypatch: pytest.MonkeyPatch) -> None:
    blocked = tmp_path / "file"
    blocked.write_text("not a folder", encoding="utf-8")
    monkeypatch.setenv(codecache.CACHE_VARIABLE, str(blocked / "cache"))
    cl_path = ROOT / "examples" / "vmc500_cycles.jsonl"
    first = _post("vmc500", cl_path)
    assert _post("vmc500", cl_path) == first
    assert blocked.read_text(encoding="utf-8") == "not a folder"


def _cli(*args: str) -> tuple[int, str, str]:
    result = CliRunner().invoke(main, list(args))
    return result.exit_code, result.stdout, result.stderr


BROKEN = {
    # YAML syntax, the schema, the meaning, and an option value (checked at compile)
    "syntax": ("machine: {name: X\n", ()),
    "schema": (None, ("  units: mm\n", "  units: mm\n  bogus_key: 1\n")),
    "meaning": (None, ("{param: x", "{param: xx_unknown")),
    "option": (None, ()),
}


@pytest.mark.parametrize("kind", sorted(BROKEN))
def test_a_bad_post_is_reported_alike_with_and_without_the_cache(
        kind: str, tmp_path: Path, cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    text, change = BROKEN[kind]
    source = "fanuc" if kind == "option" else "vmc500"
    if text is None:
        text = (ROOT / "machines" / f"{source}.yaml").read_text(encoding="utf-8")
        if change:
            assert change[0] in text
            text = text.replace(change[0], change[1], 1)
    path = tmp_path / "bad.yaml"
    path.write_text(text, encoding="utf-8")
    cl_path = str(ROOT / "examples" / "vmc500_cycles.jsonl")
    args = ["post", str(path), cl_path]
    if kind == "option":
        args += ["--option", "prestage_next_tool=maybe"]
    monkeypatch.setenv("SOURCE_DATE_EPOCH", str(THESIS_EPOCH))
    monkeypatch.setenv(codecache.CACHE_VARIABLE, "")
    cold = _cli(*args)
    assert cold[0] == 1 and cold[2]
    monkeypatch.setenv(codecache.CACHE_VARIABLE, str(cache))
    assert _cli(*args) == cold
    assert _cli(*args) == cold  # warm: the valid post of "option" comes from the cache
    assert bool(list(cache.glob("*.post"))) == (kind == "option")
    if kind != "syntax":  # located in the file: a cached post parses its text for it
        assert f"{path}:" in cold[2] and cold[2].split(f"{path}:")[1][:1].isdigit()


_PROBE = """
import json, sys
from postdsl.cli import main
try:
    main(sys.argv[1:])
except SystemExit as exc:
    assert not exc.code, exc.code
print(json.dumps(sorted(sys.modules)))
"""


def test_a_warm_post_command_loads_no_yaml_schema_editor_or_drawing(
        tmp_path: Path, cache: Path) -> None:
    env = {**os.environ, codecache.CACHE_VARIABLE: str(cache),
           "PYTHONPATH": str(ROOT), "SOURCE_DATE_EPOCH": str(THESIS_EPOCH)}
    args = [sys.executable, "-c", _PROBE, "post", "vmc500",
            str(ROOT / "examples" / "vmc500_cycles.jsonl"), "-o", str(tmp_path / "x.nc")]
    cold = json.loads(subprocess.run(args, env=env, capture_output=True, text=True,
                                     check=True, cwd=tmp_path).stdout)
    assert "ruamel.yaml" in cold  # the first run reads the post
    warm = json.loads(subprocess.run(args, env=env, capture_output=True, text=True,
                                     check=True, cwd=tmp_path).stdout)
    # the entry holds the checked syntax trees of the expressions: nothing is parsed
    unwanted = ("ruamel", "jsonschema", "textual", "tui", "postdsl.check.svgplot", "postdsl.review",
                "postdsl.run.trace", "postdsl.lang.post.checks", "postdsl.lang.expr.parser",
                "postdsl.lang.expr.lexer")
    assert [name for name in warm if name.split(".")[0] in unwanted or
            any(name == u or name.startswith(u + ".") for u in unwanted)] == []
    assert "postdsl.compile.postcache" in warm
    # post verifies by default: the control models and the comparison are loaded; with
    # --no-verify posting needs neither
    assert "postdsl.check.verify" in warm and "postdsl.check.controls" in warm
    unverified = json.loads(subprocess.run([*args, "--no-verify"], env=env,
                                           capture_output=True, text=True, check=True,
                                           cwd=tmp_path).stdout)
    assert not [name for name in unverified
                if name.startswith(("postdsl.check.verify", "postdsl.check.controls"))]
