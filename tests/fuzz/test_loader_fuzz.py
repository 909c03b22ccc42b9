"""The loader on mutated machine files: a located PostError or a post, quickly; never a crash.

The bundled posts are mutated as text (characters, lines and YAML syntax changed, cut
or repeated) and as data (a value anywhere in the document replaced by a hostile one:
huge or negative numbers, control characters, the wrong type, deep nesting), then
loaded.  A post that still loads also posts its machine's bundled program: that may be
refused with a located CLError, and nothing else.
"""

from __future__ import annotations

import io
import json
import time
from functools import cache
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from postdsl import api
from postdsl.errors import CLError, PostError
from postdsl.lang.loader import make_yaml
from tests.conftest import MACHINES, THESIS_TIME
from tests.fuzz import share

pytestmark = pytest.mark.fuzz

BUNDLED = sorted(p.stem for p in MACHINES.glob("*.yaml"))

#: the slowest a mutated post may load and post its program: a bundled post loads in
#: ~30 ms and posts in ~20 ms; the rest is room for a loaded CI machine, far below the
#: minutes a runaway expansion took
BUDGET = 10.0


@cache
def _text(machine: str) -> str:
    return (MACHINES / f"{machine}.yaml").read_text(encoding="utf-8")


@cache
def _program(machine: str) -> list[api.CLCommand]:
    example = api.example_program(machine)
    assert example is not None, machine
    return api.read_cl(example)


def _check(text: str, machine: str) -> None:
    """Load ``text``; post the machine's program with it when it loads."""
    started = time.perf_counter()
    try:
        post = api.load_post_text(text, "mutated.yaml")
    except PostError as exc:
        for problem in exc.problems:
            assert problem.location is not None and problem.location.file == "mutated.yaml"
            assert problem.location.line is not None, str(problem)
            assert problem.message and "Traceback" not in problem.message
        assert time.perf_counter() - started < BUDGET
        return
    try:
        lines = api.post_commands(post, _program(machine), cl_file="prog", now=THESIS_TIME)
    except CLError as exc:
        assert exc.location is not None and exc.location.file == "prog", str(exc)
    else:
        for line in lines:
            assert line.text.isprintable(), line.text  # one NC block per line, always
    assert time.perf_counter() - started < BUDGET


# --- text mutations ---------------------------------------------------------------------------

SNIPPETS = ["\t", "\r", "\x00", "\ufeff", ":", "- ", "{", "}", "[", "]", "&a ", "*a",
            "!!python/object ", "'", '"', "#", "|", ">", "? ", "%YAML 1.1\n", "---\n", "...\n",
            "\\", "1e999",
            "99999999999999999999", "-1", ".nan", "~", "<<: *a", "\u2028", "é"]


@st.composite
def mutated_text(draw: st.DrawFn) -> tuple[str, str]:
    machine = draw(st.sampled_from(BUNDLED))
    text = _text(machine)
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(["insert", "delete", "replace", "cut_line", "dup_line",
                                     "swap_lines", "truncate"]))
        at = draw(st.integers(0, max(0, len(text) - 1)))
        if kind == "insert":
            text = text[:at] + draw(st.sampled_from(SNIPPETS)) + text[at:]
        elif kind == "delete":
            text = text[:at] + text[at + draw(st.integers(1, 40)):]
        elif kind == "replace":
            text = text[:at] + draw(st.characters()) + text[at + 1:]
        elif kind == "truncate":
            text = text[:at]
        else:
            lines = text.split("\n")
            index = draw(st.integers(0, len(lines) - 1))
            if kind == "cut_line":
                del lines[index]
            elif kind == "dup_line":
                lines.insert(index, lines[index])
            else:
                other = draw(st.integers(0, len(lines) - 1))
                lines[index], lines[other] = lines[other], lines[index]
            text = "\n".join(lines)
    return machine, text


@given(case=mutated_text())
def test_text_mutations_of_the_bundled_posts(case: tuple[str, str]) -> None:
    machine, text = case
    _check(text, machine)


# --- data mutations ---------------------------------------------------------------------------

HOSTILE_VALUES = st.one_of(
    st.sampled_from([0, -1, -10**6, 10**300, 1e308, -1e-308, 2**63, True, None, "", " ",
                     "G0\rM30", "X\n", "\x00", "a" * 5000, [], {}, [[[[[]]]]],
                     {"use": "nosuch"}, {"items": []}, {"if": "1/0"}, "__import__('os')",
                     "changed(", "x" * 3000]),
    st.integers(), st.floats(), st.text(max_size=30),
    st.lists(st.integers(), max_size=3),
)


def _paths(node: Any, path: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    """Every place in a document a value can be replaced."""
    found = [path] if path else []
    if isinstance(node, dict):
        for key, value in node.items():
            found += _paths(value, path + (key,))
    elif isinstance(node, list):
        for index, value in enumerate(node):
            found += _paths(value, path + (index,))
    return found


def _plain(node: Any) -> Any:
    if isinstance(node, dict):
        return {str(key): _plain(value) for key, value in node.items()}
    if isinstance(node, list):
        return [_plain(value) for value in node]
    return node


@cache
def _document(machine: str) -> str:
    """The post as plain data, in JSON (a YAML subset that is quick to copy and write)."""
    return json.dumps(_plain(make_yaml().load(io.StringIO(_text(machine)))))


@st.composite
def mutated_data(draw: st.DrawFn) -> tuple[str, str]:
    machine = draw(st.sampled_from(BUNDLED))
    document = json.loads(_document(machine))
    paths = _paths(document)
    for _ in range(draw(st.integers(1, 3))):
        path = draw(st.sampled_from(paths))
        parent = document
        try:
            for part in path[:-1]:
                parent = parent[part]
            parent[path[-1]] = draw(HOSTILE_VALUES)
        except (KeyError, IndexError, TypeError):
            continue  # an earlier mutation replaced this branch
        if draw(st.booleans()) and isinstance(parent, dict):  # or drop the key
            parent.pop(path[-1], None)
    # one value per line, so that every problem has a line of its own to point at
    return machine, json.dumps(document, indent=1, ensure_ascii=draw(st.booleans()))


@share(0.5)
@given(case=mutated_data())
def test_data_mutations_of_the_bundled_posts(case: tuple[str, str]) -> None:
    machine, text = case
    _check(text, machine)


def test_the_bundled_posts_themselves_pass_the_check() -> None:
    """The fuzz cases start from posts that load and post: mutations make the difference."""
    for machine in BUNDLED:
        api.post_commands(api.load_post_text(_text(machine), "mutated.yaml"),
                          _program(machine), cl_file="prog", now=THESIS_TIME)
