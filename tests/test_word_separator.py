"""``output.word_separator``: words apart, none before the first, none for a left-out one.

Without it a post puts the space in each prefix, and a block whose first word is
left out (a modal G1) starts with a space; with it the separator goes only between
the words actually written, in the generated code and its traced flavour.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from postdsl import api
from postdsl.errors import PostError
from postdsl.run.trace import trace_lines
from tests.conftest import THESIS_TIME
from tests.test_codegen import post_both

POST = '''\
postdsl: 1
machine: {name: separated}
output:
  word_separator: "@SEPARATOR@"
  block_numbers: {default: @NUMBERED@, suffix: " "}
formats:
  coord: {decimals: 3, trailing_zeros: false, point: always}
  int: {integer: true}
commands:
  program_start:
    blocks: [{number: false, items: ["%"]}]
  program_end:
    blocks: [{items: [M30]}]
  tool_change:
    blocks: [{items: [{param: tool_number, prefix: T, format: int}, M6]}]
    reset: [x, y, z, feed]
  rapid_move:
    blocks:
      - items: [{text: G0, modal: motion, mode: changed},
                {param: x, prefix: X, format: coord, mode: changed},
                {param: y, prefix: Y, format: coord, mode: changed},
                {param: z, prefix: Z, format: coord, mode: changed}]
  linear_move:
    blocks:
      - only_with_values: true
        items: [{text: G1, modal: motion, mode: changed},
                {param: x, prefix: X, format: coord, mode: changed},
                {param: y, prefix: Y, format: coord, mode: changed},
                {param: z, prefix: Z, format: coord, mode: changed},
                {param: feed, prefix: F, format: int, mode: changed}, ""]
'''

PROGRAM = "\n".join([
    '{"cmd": "tool_change", "tool_number": 3}',
    '{"cmd": "rapid_move", "x": 1, "y": 2, "z": 5}',
    '{"cmd": "rapid_move", "z": 1}',
    '{"cmd": "linear_move", "x": 4, "feed": 300}',
    '{"cmd": "linear_move", "y": 7}',
    '{"cmd": "linear_move", "y": 7}',
    '{"cmd": "program_end"}',
]) + "\n"


def load(tmp_path: Path, separator: str = " ", numbered: str = "false") -> api.CompiledPost:
    path = tmp_path / "separated.yaml"
    text = POST.replace("@SEPARATOR@", separator).replace("@NUMBERED@", numbered)
    path.write_text(text, encoding="utf-8")
    return api.load_post(path)


def test_words_are_separated_and_no_line_starts_with_it(tmp_path: Path) -> None:
    post = load(tmp_path)
    commands = list(api.read_cl_text(PROGRAM, "p.jsonl"))
    generated, traced = post_both(post, commands)
    assert generated == traced
    lines = [line.text for line in api.post_commands(post, commands, now=THESIS_TIME)]
    # "Z1." alone: G0 is still active, so the block's first word is left out - and the
    # unchanged Y 7 writes nothing at all (only_with_values drops the bare G1)
    assert lines == ["%", "T3 M6", "G0 X1. Y2. Z5.", "Z1.", "G1 X4. F300", "Y7.", "M30"]


def test_numbered_blocks_keep_their_own_suffix(tmp_path: Path) -> None:
    post = load(tmp_path, separator=" ", numbered="true")
    commands = list(api.read_cl_text(PROGRAM, "p.jsonl"))
    generated, traced = post_both(post, commands)
    assert generated == traced
    lines = [line.text for line in api.post_commands(post, commands, now=THESIS_TIME)]
    assert lines[1:5] == ["N10 T3 M6", "N20 G0 X1. Y2. Z5.", "N30 Z1.", "N40 G1 X4. F300"]


def test_without_a_separator_the_words_touch(tmp_path: Path) -> None:
    post = load(tmp_path, separator="")
    lines = [line.text for line in api.post_commands(
        post, api.read_cl_text(PROGRAM, "p.jsonl"), now=THESIS_TIME)]
    assert lines[2:5] == ["G0X1.Y2.Z5.", "Z1.", "G1X4.F300"]


def test_the_trace_finds_each_word_between_separators(tmp_path: Path) -> None:
    post = load(tmp_path, separator=", ")
    traced = trace_lines(post, api.read_cl_text(PROGRAM, "p.jsonl"), now=THESIS_TIME)
    line = next(t for t in traced if t.line.text.startswith("G1"))
    assert line.line.text == "G1, X4., F300"
    assert [(w.text, line.line.text[w.start:w.end]) for w in line.words] == [
        ("G1", "G1"), ("X4.", "X4."), ("F300", "F300")]


def test_a_control_character_is_refused_where_it_stands(tmp_path: Path) -> None:
    with pytest.raises(PostError) as caught:
        load(tmp_path, separator="\\t")
    assert caught.value.location.line == 4
    assert "word separator" in str(caught.value) and "'\\t'" in str(caught.value)


def test_a_separator_must_be_text(tmp_path: Path) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(POST.replace('"@SEPARATOR@"', "[1]").replace(
        "@NUMBERED@", "false"), encoding="utf-8")
    with pytest.raises(PostError) as caught:
        api.load_post(path)
    assert caught.value.location.line == 4 and "word_separator" in str(caught.value)
