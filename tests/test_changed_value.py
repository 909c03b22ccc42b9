"""Output mode ``changed_value``: a word left out only when its value is the register's.

``changed`` compares the formatted text with what the control last received, so
-1.1834 after -1.1831 is the same ``Z-1.183`` and left out.  Some posts compare the
number itself -- FreeCAD's own posts keep the last value of each word as a float and
write ``Z-1.183`` again when the unrounded value changed -- and a post reproducing one
says so with ``mode: changed_value``.  The generated code, its traced flavour and
the text-only lane ``postdsl post`` streams plain moves through must write alike; a
register shared with ``changed`` items compares as text where either wrote it.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from postdsl import api
from postdsl.errors import PostError
from tests.conftest import DATA, MACHINES, THESIS_TIME, compiled_post
from tests.test_codegen import post_both

POST = '''\
postdsl: 1
machine: {name: raw}
output: {block_numbers: {default: false}}
formats:
  coord: {decimals: 3, trailing_zeros: true, point: always}
  int: {integer: true}
commands:
  program_start:
    blocks: [{items: ["%"]}]
  program_end:
    blocks: [{items: [M30]}]
  tool_change:
    blocks: [{items: [{param: tool_number, prefix: T, format: int}, " M6"]}]
    reset: [x, y, z, feed]
  rapid_move:
    blocks:
      - only_with_values: true
        items: [{text: G0, modal: motion},
                {param: x, prefix: " X", format: coord, mode: @MODE@},
                {param: z, prefix: " Z", format: coord, mode: @MODE@}]
  linear_move:
    blocks:
      - only_with_values: true
        items: [{text: G1, modal: motion},
                {param: x, prefix: " X", format: coord, mode: @MODE@},
                {param: z, prefix: " Z", format: coord, mode: changed},
                {param: feed, prefix: " F", format: int, mode: @MODE@, force_if: "@FORCE@"}]
'''

PROGRAM = "\n".join([
    '{"cmd": "tool_change", "tool_number": 3}',
    '{"cmd": "rapid_move", "x": 1.1831, "z": 5}',
    '{"cmd": "rapid_move", "x": 1.1834, "z": 5}',     # again: another value
    '{"cmd": "rapid_move", "x": 1.1834, "z": 5.0}',   # the same values: nothing
    '{"cmd": "linear_move", "x": 2, "z": 5.0004, "feed": 300}',   # Z: a changed item
    '{"cmd": "linear_move", "x": 2, "z": 5.0001, "feed": 300.0004}',
    '{"cmd": "program_end"}',
]) + "\n"


def load(tmp_path: Path, mode: str, force: str = "false") -> api.CompiledPost:
    path = tmp_path / "raw.yaml"
    path.write_text(POST.replace("@MODE@", mode).replace("@FORCE@", force), encoding="utf-8")
    return api.load_post(path)


def posted(post: api.CompiledPost) -> list[str]:
    commands = list(api.read_cl_text(PROGRAM, "p.jsonl"))
    generated, traced = post_both(post, commands)
    assert generated == traced
    return [line.text for line in api.post_commands(post, commands, now=THESIS_TIME)]


def test_changed_value_compares_the_number(tmp_path: Path) -> None:
    lines = posted(load(tmp_path, "changed_value"))
    # Z 5.0004 is written by a `changed` item: its text ("5.000") is in the register, so
    # the `changed_value` Z of the rapid compares text; the feed 300.0004 is another value
    assert lines == ["%", "T3 M6", "G0 X1.183 Z5.000", "G0 X1.183", "G1 X2.000 F300",
                     "G1 F300", "M30"]


def test_changed_compares_the_text(tmp_path: Path) -> None:
    lines = posted(load(tmp_path, "changed"))
    assert lines == ["%", "T3 M6", "G0 X1.183 Z5.000", "G1 X2.000 F300", "M30"]


def test_force_if_writes_a_changed_value_item_anyway(tmp_path: Path) -> None:
    lines = posted(load(tmp_path, "changed_value", force="x > 1.5"))
    assert lines[4:6] == ["G1 X2.000 F300", "G1 F300"]
    lines = posted(load(tmp_path, "changed", force="x > 1.5"))
    assert lines[3:5] == ["G1 X2.000 F300", "G1 F300"]


def test_postdsl_post_streams_the_same_text(tmp_path: Path,
                                            monkeypatch: pytest.MonkeyPatch) -> None:
    """``postdsl post`` hands plain moves to the text-only lanes on their fields."""
    post = load(tmp_path, "changed_value")
    cl = tmp_path / "p.jsonl"
    cl.write_text(PROGRAM, encoding="utf-8")
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "0")
    text = api.post_file(tmp_path / "raw.yaml", cl, verify=False)
    assert text.splitlines() == posted(post)


def test_an_unknown_mode_is_refused(tmp_path: Path) -> None:
    with pytest.raises(PostError, match="changed_raw"):
        load(tmp_path, "changed_raw")


_FREECAD = DATA / "freecad"


@pytest.mark.parametrize("parity", [True, False])
@pytest.mark.parametrize("dump", sorted([*_FREECAD.glob("*.dump.txt"),
                                         *(_FREECAD / "random").glob("*.dump.txt")]),
                         ids=lambda path: path.name.split(".")[0])
def test_the_linuxcnc_modal_sets_are_written_alike(dump: Path, parity: bool) -> None:
    """The LinuxCNC post's axis words are changed_value items: posted and traced alike on
    FreeCAD's jobs."""
    post = compiled_post(MACHINES / "linuxcnc.yaml",
                         {"modal": True, "axis_modal": True, "parity": parity})
    generated, traced = post_both(post, list(api.read_cl(dump)))
    assert generated == traced and not generated.startswith("REFUSED")
