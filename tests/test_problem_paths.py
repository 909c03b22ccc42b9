"""Every problem of a post keeps the document path its check found it at.

The checks know the node a problem is about; the loader locates it as
``file:line:column`` and keeps the path beside (``PostError.path``), so the editor
marks the cell from the path, never by guessing the node back from a line and a
column.  One row per kind of problem: YAML, schema (type, unknown key, missing key),
meaning checks, expressions, .nan, extends, overrides, structures, options.
"""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import Any

import pytest

from postdsl import api
from postdsl.errors import PostError
from postdsl.lang.loader import PostSource, parse_yaml

BASE = """\
postdsl: 1
machine: {name: Mill, tool_changer: false}
formats:
  c: {decimals: 3}
commands:
  program_start: {blocks: []}
  program_end: {blocks: [{items: [" M30"]}]}
  rapid_move:
    blocks:
      - items: ["G0", {param: x, prefix: " X", format: c}]
"""

RAPID = ("commands", "rapid_move", "blocks", 0)

#: (what, text added under commands: or at the top level, the path, a word of the message)
CASES: list[tuple[str, str, str, tuple[Any, ...], str]] = [
    ("schema: wrong type", "", "output: {block_numbers: {start: ten}}\n",
     ("output", "block_numbers", "start"), "expected"),
    # a block written as a block mapping: the item and its first key start at the same
    # line and column, so a walk from the position back to a node took the item
    ("schema: unknown key", "linear_move:\n  blocks:\n    - items:\n        - prefx: ' X'\n"
     "          param: x\n          format: c\n", "",
     ("commands", "linear_move", "blocks", 0, "items", 0, "prefx"), "unknown key 'prefx'"),
    ("schema: missing key", "linear_move: {blocks: [{if: x > 0}]}\n", "",
     ("commands", "linear_move", "blocks", 0), "required property"),
    ("meaning: unknown format",
     "linear_move: {blocks: [{items: [G1, {param: x, prefix: ' X', format: cc}]}]}\n", "",
     ("commands", "linear_move", "blocks", 0, "items", 1, "format"), "did you mean 'c'"),
    ("meaning: unknown parameter",
     "linear_move: {blocks: [{items: [G1, {param: xx, prefix: ' X', format: c}]}]}\n", "",
     ("commands", "linear_move", "blocks", 0, "items", 1, "param"), "xx"),
    ("meaning: a variable hiding a parameter", "", "variables: {feed: 1}\n",
     ("variables", "feed"), "hides the parameter"),
    ("expression: syntax", "linear_move: {blocks: [{if: 'x >', items: [G1]}]}\n", "",
     ("commands", "linear_move", "blocks", 0, "if"), "unexpected end of expression"),
    ("expression: unknown name", "linear_move: {blocks: [{if: 'xx > 1', items: [G1]}]}\n", "",
     ("commands", "linear_move", "blocks", 0, "if"), "xx"),
    ("finite: .nan", "", "variables: {depth_margin: .nan}\n", ("variables", "depth_margin"),
     "not a finite number"),
    ("structures: use of an unknown structure", "linear_move: {blocks: [{use: nothing}]}\n", "",
     ("commands", "linear_move", "blocks", 0, "use"), "nothing"),
    ("structures: a loop", "linear_move: {blocks: [{use: a}]}\n",
     "structures:\n  a: [{use: b}]\n  b: [{use: a}]\n", ("structures", "b", 0, "use"),
     "structure loop: a -> b -> a"),
]


def _text(commands: str, top: str) -> str:
    return BASE + textwrap.indent(commands, "  ") + top


def _problems(text: str, file: str = "post.yaml") -> list[api.PostProblem]:
    source = PostSource(file, parse_yaml(text, file), text, Path(file))
    return api.check_source(source).problems


@pytest.mark.parametrize(("what", "commands", "top", "path", "word"), CASES,
                         ids=[case[0] for case in CASES])
def test_every_kind_of_problem_carries_its_path(what: str, commands: str, top: str,
                                                path: tuple[Any, ...], word: str) -> None:
    text = _text(commands, top)
    with pytest.raises(PostError) as caught:
        api.load_post_text(text, "post.yaml")
    found = {p.path: p.message for p in caught.value.problems}
    assert path in found, f"{what}: no problem at {path}: {found}"
    assert word in found[path]
    # the editor's check gives the same paths, and the CLI's text is unchanged
    assert {p.path for p in _problems(text)} == set(found)
    for problem in caught.value.problems:
        assert problem.location is not None
        assert str(problem).startswith(f"post.yaml:{problem.location.line}:")


def test_the_path_is_the_nodes_even_where_its_position_is_a_parents() -> None:
    """A missing key is located at its parent; an edited node at the nearest one known."""
    text = _text("linear_move: {blocks: [{if: x > 0}]}\n", "")
    problem, = _problems(text)
    assert problem.path == ("commands", "linear_move", "blocks", 0)
    assert problem.location.line is not None
    assert text.splitlines()[problem.location.line - 1].startswith("  linear_move")


def test_yaml_errors_are_about_no_node() -> None:
    with pytest.raises(PostError) as caught:
        api.load_post_text(BASE + "  bad: [\n", "post.yaml")
    assert caught.value.path is None
    with pytest.raises(PostError) as caught:
        api.load_post_text("- a list\n", "post.yaml")
    assert caught.value.path == ()


def test_an_option_value_refused_when_compiling_carries_the_options_path() -> None:
    text = _text("", "options:\n  depth: {type: number, default: 1}\n")
    source = PostSource("post.yaml", parse_yaml(text, "post.yaml"), text)
    result = api.check_source(source, {"depth": "deep"})
    assert [p.path for p in result.problems] == [("options", "depth")]


def test_extends_problems_carry_the_path_in_their_own_file(tmp_path: Path) -> None:
    (tmp_path / "base.yaml").write_text(BASE, encoding="utf-8")
    missing = tmp_path / "missing.yaml"
    missing.write_text("postdsl: 1\nextends: nowhere.yaml\nmachine: {name: M}\n",
                       encoding="utf-8")
    with pytest.raises(PostError) as caught:
        api.load_post(missing)
    assert caught.value.path == ("extends",)

    child = tmp_path / "child.yaml"
    child.write_text("postdsl: 1\nextends: base.yaml\noverride:\n"
                     "  commands/rapid_move/blocks/0/items/9: G00\n", encoding="utf-8")
    with pytest.raises(PostError) as caught:
        api.load_post(child)
    assert caught.value.path == ("override", "commands/rapid_move/blocks/0/items/9")
    text = child.read_text(encoding="utf-8")
    problem, = _problems(text, str(child))
    assert problem.path == ("override", "commands/rapid_move/blocks/0/items/9")


def test_a_problem_in_a_base_has_no_path_in_the_edited_post(tmp_path: Path) -> None:
    (tmp_path / "base.yaml").write_text(
        _text("linear_move: {blocks: [{items: [G1, {param: x, format: cc}]}]}\n", ""),
        encoding="utf-8")
    child = tmp_path / "child.yaml"
    text = "postdsl: 1\nextends: base.yaml\nmachine: {name: Child}\n"
    child.write_text(text, encoding="utf-8")
    with pytest.raises(PostError) as caught:
        api.load_post(child)
    base_problem = caught.value.problems[0]
    assert base_problem.location is not None and base_problem.location.file.endswith("base.yaml")
    assert base_problem.path == ("commands", "linear_move", "blocks", 0, "items", 1, "format")
    assert [p.path for p in _problems(text, str(child))] == [()]
