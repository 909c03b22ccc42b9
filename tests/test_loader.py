"""Post validation: every problem located as file:line:column, nothing evaluated."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from postdsl import api
from postdsl.errors import PostError
from tests.conftest import MACHINES

GOOD = """\
postdsl: 1
machine:
  name: Test
formats:
  c: {decimals: 3}
commands:
  rapid_move:
    blocks:
      - items:
          - " G0"
          - {param: x, prefix: " X", format: c, mode: changed}
          - {param: z, prefix: " Z", format: c, if: "z > 0"}
"""


def problems(text: str) -> list[str]:
    with pytest.raises(PostError) as info:
        api.load_post_text(text, "post.yaml")
    return [str(p) for p in info.value.problems]


def test_a_good_post_loads() -> None:
    assert api.load_post_text(GOOD, "post.yaml").commands["rapid_move"].blocks


def test_misspelled_parameter_is_located_with_a_hint() -> None:
    text = GOOD.replace("param: x,", "param: xx,")
    assert problems(text) == [
        "post.yaml:11:21: unknown parameter 'xx' (did you mean 'x'?)"]


def test_unknown_format_is_located() -> None:
    text = GOOD.replace("format: c, mode", "format: coord, mode")
    assert problems(text) == ["post.yaml:11:46: unknown format 'coord'"]


def test_broken_condition_is_located_at_the_bad_character() -> None:
    text = GOOD.replace('if: "z > 0"', 'if: "z > > 0"')
    [message] = problems(text)
    # the column of the second '>' inside the quoted condition
    line = text.splitlines()[11]
    assert message == f"post.yaml:12:{line.index('> >') + 3}: bad expression: unexpected '>'"


def test_schema_violation_is_located() -> None:
    text = GOOD.replace("mode: changed", "mode: sometimes")
    [message] = problems(text)
    assert message.startswith("post.yaml:11:")
    assert "sometimes" in message


def test_unknown_key_is_located_at_the_key_with_a_hint() -> None:
    text = GOOD.replace("  name: Test", "  name: Test\n  controler: Fanuc")
    assert problems(text) == [
        "post.yaml:4:3: unknown key 'controler' (did you mean 'controller'?)"]


def test_unknown_cl_command_name() -> None:
    text = GOOD.replace("  rapid_move:", "  rapid_mov:")
    assert problems(text) == [
        "post.yaml:7:3: unknown CL command 'rapid_mov' (did you mean 'rapid_move'?)"]


def test_yaml_syntax_error_is_located() -> None:
    [message] = problems(GOOD.replace("  c: {decimals: 3}", "  c: {decimals: 3"))
    assert message.startswith("post.yaml:6:")
    assert "YAML error" in message


def test_duplicate_key_is_an_error() -> None:
    [message] = problems(GOOD + "  rapid_move:\n    blocks: []\n")
    assert "YAML error" in message and "duplicate" in message


def test_all_problems_are_reported_in_file_order() -> None:
    text = GOOD.replace("param: x,", "param: xx,").replace("format: c, if", "format: d, if")
    found = problems(text)
    assert [m.split(":")[1] for m in found] == ["11", "12"]


@pytest.mark.parametrize(
    "condition",
    [
        "__import__('os')",
        "x.__class__",
        "9**9**9",
        "().__class__.__bases__",
        "open('/etc/passwd')",
        "lambda: 1",
        "[c for c in 'ab']",
        "x if x",
        "exec('1')",
        "z; x",
    ],
)
def test_hostile_conditions_are_rejected_at_load(condition: str) -> None:
    text = GOOD.replace('if: "z > 0"', f'if: "{condition}"')
    [message] = problems(text)
    assert message.startswith("post.yaml:12:")
    assert "bad expression" in message


def test_number_parameter_without_format_needs_a_default_format() -> None:
    text = GOOD.replace("{param: x, prefix: \" X\", format: c, mode: changed}",
                        "{param: x, prefix: \" X\"}")
    assert problems(text) == [
        "post.yaml:11:21: number parameter 'x' needs a format (or define a format named "
        "'default')"]
    assert api.load_post_text(text.replace("  c: {decimals: 3}",
                                           "  c: {decimals: 3}\n  default: {decimals: 2}"), "p")


def test_text_item_in_changed_mode_needs_a_register() -> None:
    text = GOOD.replace('- " G0"', '- {text: " G0", mode: changed}')
    [message] = problems(text)
    assert "needs 'modal: <register>'" in message


@pytest.mark.parametrize(
    ("snippet", "expected"),
    [
        ("  tapping_ccw: {redirect: tapping}\n", "redirect to 'tapping', which has no table"),
        ("  tapping_ccw: {redirect: rigid_tapping_ccw}\n  rigid_tapping_ccw: "
         "{redirect: tapping_ccw}\n", "redirect loop"),
        ("  linear_move: {expand: true}\n", "only drilling setups and arc_move can be expanded"),
        ("  tapping: {expand: true}\n", "tapping cannot be expanded"),
        ("  dwell: {blocks: [{use: nowhere}]}\n", "unknown structure 'nowhere'"),
        ("  dwell: {preview: {dwel: 1}, blocks: []}\n", "unknown parameter 'dwel'"),
    ],
)
def test_semantic_checks(snippet: str, expected: str) -> None:
    found = problems(GOOD + snippet)
    assert any(expected in message for message in found), found


def test_bad_format_options_name_the_key() -> None:
    text = GOOD.replace("  c: {decimals: 3}", "  c: {decimals: 3, integer: true}")
    [message] = problems(text)
    assert message.startswith("post.yaml:5:")
    assert "format 'c'" in message


def test_every_bundled_machine_is_valid() -> None:
    for path in sorted(MACHINES.glob("*.yaml")):
        assert api.load_post(path).machine.name


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "postdsl.cli", *args], capture_output=True,
                          text=True, check=False)


@pytest.mark.parametrize(
    ("old", "new", "where"),
    [
        ("param: depth, prefix: \" Z\"", "param: depht, prefix: \" Z\"",
         "unknown parameter 'depht'"),
        ("format: coord}", "format: cord}", "unknown format 'cord'"),
        ("if: \"tool_count > 1\"", "if: \"tool_count >\"", "bad expression"),
        ("mode: changed}", "mode: modal}", "'modal' is not one of"),
    ],
)
def test_check_command_rejects_a_broken_vmc500_copy(tmp_path: Path, old: str, new: str,
                                                    where: str) -> None:
    copy = tmp_path / "vmc500.yaml"
    shutil.copy(MACHINES / "vmc500.yaml", copy)
    text = copy.read_text(encoding="utf-8")
    assert old in text
    copy.write_text(text.replace(old, new, 1), encoding="utf-8")
    result = _cli("check", str(copy))
    assert result.returncode == 1
    first = result.stderr.splitlines()[0]
    file, line, column, message = first.split(":", 3)
    assert file == str(copy) and int(line) > 0 and int(column) > 0
    assert where in message
    assert "Traceback" not in result.stderr


def test_check_command_accepts_the_bundled_machine() -> None:
    result = _cli("check", "vmc500")
    assert result.returncode == 0, result.stderr


def test_unknown_machine_name_is_a_clear_error() -> None:
    result = _cli("check", "vmc5000")
    assert result.returncode == 1
    assert "unknown machine 'vmc5000'" in result.stderr


def test_reject_conditions_are_checked_at_load() -> None:
    text = GOOD + "  dwell:\n    reject: [{if: \"dwell >\", message: too long}]\n    blocks: []\n"
    [message] = problems(text)
    assert message.startswith("post.yaml:14:") and "unexpected end of expression" in message
    text = GOOD + "  dwell:\n    reject: [{if: \"dwell\"}]\n    blocks: []\n"
    [message] = problems(text)
    assert "'message' is a required property" in message


def test_nodes_added_in_memory_are_located_at_their_parent() -> None:
    from ruamel.yaml.comments import CommentedMap

    from postdsl.lang.loader import locate, parse_yaml

    data = parse_yaml(GOOD, "post.yaml")
    data["commands"]["dwell"] = CommentedMap(blocks=[])
    assert locate(data, ("commands", "dwell", "blocks")) == locate(data, ("commands",))


# --- hostile posts ---------------------------------------------------------------------------


def test_a_yaml_alias_bomb_is_refused_quickly() -> None:
    """Nine levels of ten aliases are 10**9 values: the loader must not expand them."""
    bomb = ["  v0: &v0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]"]
    bomb += [f"  v{i}: &v{i} [" + ", ".join([f"*v{i - 1}"] * 10) + "]" for i in range(1, 9)]
    text = GOOD.replace("formats:\n", "variables:\n" + "\n".join(bomb) + "\nformats:\n")
    [message] = problems(text)
    assert message == ("post.yaml:13:3: YAML aliases expand 'variables/v8' to 1,111,111,111 "
                       "values (at most 200,000 are allowed in a post)")


def test_aliases_of_a_reasonable_size_still_work() -> None:
    text = GOOD.replace("  c: {decimals: 3}", "  c: &c {decimals: 3}\n  d: *c") \
        .replace("      - items:", "      - &block\n        items:") + \
        "  linear_move:\n    blocks: [*block]\n"
    post = api.load_post_text(text, "post.yaml")
    assert len(post.commands["linear_move"].blocks) == 1


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("  name: Test", "  name: Test\n  travel: {x: [.nan, 10]}",
         "post.yaml:4:16: machine/travel/x/0: .nan is not a finite number"),
        ("  name: Test", "  name: Test\n  max_feed: .inf",
         "post.yaml:4:13: machine/max_feed: .inf is not a finite number"),
        ("formats:", "variables: {big: 1e999}\nformats:",
         "post.yaml:4:18: variables/big: .inf is not a finite number"),
        ("  name: Test", "  name: Test\n  travel: {x: [10, -10]}",
         "post.yaml:4:15: machine/travel/x: the minimum 10 is above the maximum -10"),
        ("  name: Test", "  name: Test\n  spindle: [8000, 0]",
         "post.yaml:4:12: machine/spindle: the minimum 8000 is above the maximum 0"),
    ],
)
def test_machine_numbers_must_make_sense(old: str, new: str, message: str) -> None:
    assert problems(GOOD.replace(old, new)) == [message]


def test_a_tab_gets_a_hint() -> None:
    [message] = problems(GOOD.replace("  rapid_move:", "\trapid_move:"))
    assert message.startswith("post.yaml:7:1: YAML error: found character '\\t'")
    assert message.endswith("(YAML indents with spaces, not tabs)")


@pytest.mark.slow  # ruamel's recursion to its limit: ~20 s
def test_nesting_too_deep_for_yaml_is_a_clear_error() -> None:
    [message] = problems(GOOD + "x: " + "[" * 5000 + "]" * 5000 + "\n")
    # the deepest bracket: line 13, after "x: " and 4,999 brackets
    assert message == "post.yaml:13:5003: YAML error: the document is nested too deeply"


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("  name: Test", "  name: !custom Test",
         "post.yaml:3:9: machine/name: expected text, not a value tagged '!custom'"),
        ("  name: Test", "  name: [a, b]",
         "post.yaml:3:9: machine/name: expected text, not a list"),
        ("  name: Test", "  name: 2001-12-14",
         "post.yaml:3:9: machine/name: expected text, not the date 2001-12-14"),
        ("  c: {decimals: 3}", "  c: {decimals: " + "[1, " * 20 + "1" + "]" * 20 + "}",
         "post.yaml:5:17: formats/c/decimals: expected a whole number, not a list"),
    ],
)
def test_wrong_types_are_described_not_dumped(old: str, new: str, message: str) -> None:
    assert problems(GOOD.replace(old, new)) == [message]


@pytest.mark.parametrize(
    ("item", "message"),
    [
        ("{param: tools}", "parameter 'tools' is a list of values, which a block cannot write"),
        ("{param: given}", "parameter 'given' is a list of values, which a block cannot write"),
        ("{param: label, format: c}", "'label' is text: a number format does not apply to it"),
        ("{param: comment, format: c}",
         "'comment' is text: a number format does not apply to it"),
    ],
)
def test_items_that_cannot_write_their_parameter(item: str, message: str) -> None:
    text = GOOD.replace("formats:", "variables: {label: abc}\nformats:") \
        .replace('          - " G0"\n', f"          - {item}\n")
    [found] = problems(text)
    key = "format" if "format" in item else "param"
    assert found.startswith(f"post.yaml:11:{13 + item.index(key) + len(key) + 2}: {message}")


def test_a_post_that_is_not_utf8_names_the_line(tmp_path: Path) -> None:
    post = tmp_path / "latin1.yaml"
    post.write_bytes(GOOD.replace("name: Test", "name: Fr\xe4se").encode("latin-1"))
    [message] = (p for p in _cli("check", str(post)).stderr.splitlines())
    assert message == f"{post}:3:11: not UTF-8 text (byte 0xe4 here); save the file as UTF-8"


def test_a_utf16_post_with_a_byte_order_mark_loads(tmp_path: Path) -> None:
    post = tmp_path / "utf16.yaml"
    post.write_bytes(GOOD.encode("utf-16"))
    assert api.load_post(post).machine.name == "Test"


def test_a_number_too_long_for_python_is_located() -> None:
    [message] = problems(GOOD.replace("  c: {decimals: 3}", "  c: {decimals: 3}\n  d: {width: "
                                      + "9" * 5000 + "}"))
    assert message == "post.yaml:6:14: YAML error: a number of more than 4300 digits"


def test_replace_on_fixed_text_is_refused() -> None:
    text = GOOD.replace('- " G0"', '- {text: " G0", replace: {"G": "g"}}')
    [message] = problems(text)
    assert "replace applies to parameter and computed values" in message
