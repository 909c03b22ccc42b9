"""Options: a post declares them, the user sets them when posting, checks locate misuse."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from postdsl import api
from postdsl.cl.model import CLCommand, ProgramEnd, ProgramStart, RapidMove
from postdsl.errors import PostError
from tests.conftest import ROOT, THESIS_EPOCH

POST = """\
postdsl: 1
machine:
  name: Family
  tool_changer: false
options:
  line_numbers: {type: bool, default: true, description: number the blocks}
  precision: {type: int, default: 3, choices: [2, 3, 4]}
  comments: {type: bool, default: true}
  program: {type: string, default: "O1000"}
output:
  block_numbers: {default: {option: line_numbers}, start: 10, increment: 10}
formats:
  coord: {decimals: {option: precision}, trailing_zeros: true}
commands:
  program_start:
    blocks:
      - items: [{expr: program}]
      - items: ["(FAMILY)"]
        if: comments
  rapid_move:
    blocks:
      - items:
          - "G0"
          - {param: x, prefix: " X", format: coord}
  program_end:
    blocks:
      - items: ["M30"]
"""


def program() -> list[CLCommand]:
    return [ProgramStart(line=1), RapidMove(line=2, x=1.23456), ProgramEnd(line=3)]


def posted(options: dict[str, object] | None = None) -> list[str]:
    post = api.load_post_text(POST, "family.yaml", options)
    return [line.text for line in api.post_commands(post, program())]


def test_defaults_apply_when_no_option_is_given() -> None:
    assert posted() == ["N10 O1000", "N20 (FAMILY)", "N30 G0 X1.235", "N40 M30"]


def test_options_switch_numbering_decimals_and_conditions() -> None:
    lines = posted({"line_numbers": "false", "precision": "4", "comments": "no",
                    "program": "O2000"})
    assert lines == ["O2000", "G0 X1.2346", "M30"]


def test_typed_option_values_are_taken_as_they_are() -> None:
    assert posted({"line_numbers": False, "precision": 2})[2] == "G0 X1.23"


@pytest.mark.parametrize(("given", "message"), [
    ({"precision": "five"}, "family.yaml:7:3: option 'precision' is one of 2, 3, 4, not 'five'"),
    ({"precision": "5"}, "family.yaml:7:3: option 'precision' is one of 2, 3, 4, not 5"),
    ({"line_numbers": "maybe"},
     "family.yaml:6:3: option 'line_numbers' is true or false, not 'maybe'"),
    ({"decimals": "3"}, "family.yaml: unknown option 'decimals' (the post's options: "
                        "line_numbers, precision, comments, program)"),
])
def test_a_wrong_option_is_a_located_error_naming_what_is_allowed(
        given: dict[str, object], message: str) -> None:
    with pytest.raises(PostError) as info:
        posted(given)
    assert str(info.value) == message


@pytest.mark.parametrize(("change", "message"), [
    (("precision: {type: int, default: 3,", "precision: {type: int, default: 3.5,"),
     "post.yaml:7:35: option 'precision': the default 3.5 is not a whole number"),
    (("choices: [2, 3, 4]", "choices: [2, 4]"),
     "post.yaml:7:35: option 'precision': the default 3 is not one of its choices"),
    (("choices: [2, 3, 4]", "choices: [2, 3, x]"),
     "post.yaml:7:54: option 'precision': the choice 'x' is not a whole number"),
    (("  comments: {", "  x: {type: bool, default: true}\n  comments: {"),
     "post.yaml:8:3: option 'x' hides the parameter of that name"),
    (("{option: precision}", "{option: precisio}"),
     "post.yaml:13:30: unknown option 'precisio' (did you mean 'precision'?)"),
    (("if: comments", "if: coments"),
     "post.yaml:19:13: bad expression: unknown name 'coments'; did you mean 'comments'?"),
])
def test_option_declarations_are_checked_and_located(change: tuple[str, str],
                                                     message: str) -> None:
    assert change[0] in POST
    with pytest.raises(PostError) as info:
        api.load_post_text(POST.replace(*change), "post.yaml")
    assert [str(p) for p in info.value.problems] == [message]


def test_an_option_may_not_hide_a_variable() -> None:
    text = POST.replace("options:", "variables:\n  comments: 1\noptions:")
    with pytest.raises(PostError) as info:
        api.load_post_text(text, "post.yaml")
    assert str(info.value) == "post.yaml:10:3: option 'comments' hides the variable of that name"


def test_a_value_that_makes_a_format_invalid_is_refused_at_the_format() -> None:
    text = POST.replace("choices: [2, 3, 4]", "choices: [2, 3, 40]")
    with pytest.raises(PostError) as info:
        api.load_post_text(text, "post.yaml", {"precision": "40"})
    assert str(info.value) == ("post.yaml:13:21: format 'coord' with the options given: "
                                "decimals must be from 0 to 15, not 40")


def test_the_options_are_listed_by_the_api() -> None:
    post = api.load_post_text(POST, "family.yaml")
    options = api.post_options(post)
    assert [(o.name, o.type, o.default) for o in options] == [
        ("line_numbers", "bool", True), ("precision", "int", 3), ("comments", "bool", True),
        ("program", "string", "O1000")]
    assert options[1].choices == (2, 3, 4)
    assert options[0].description == "number the blocks"


def run(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "SOURCE_DATE_EPOCH": str(THESIS_EPOCH)}
    return subprocess.run([sys.executable, "-m", "postdsl.cli", *args], capture_output=True,
                          text=True, env=env, cwd=cwd, check=False)


def test_the_command_line_sets_options(tmp_path: Path) -> None:
    post = tmp_path / "family.yaml"
    post.write_text(POST, encoding="utf-8")
    cl = tmp_path / "prog.jsonl"
    cl.write_text('{"cmd": "program_start"}\n{"cmd": "rapid_move", "x": 1.23456}\n'
                  '{"cmd": "program_end"}\n', encoding="utf-8")
    result = run("post", str(post), str(cl), "--option", "line_numbers=false",
                 "--option", "precision=2")
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == ["O1000", "(FAMILY)", "G0 X1.23", "M30"]
    bad = run("post", str(post), str(cl), "--option", "precision=9")
    assert bad.returncode == 1
    assert bad.stderr.strip() == f"{post}:7:3: option 'precision' is one of 2, 3, 4, not 9"
    assert bad.stdout == ""
    shape = run("preview", str(post), "rapid_move", "--option", "precision")
    assert shape.returncode == 2 and "'precision' is not NAME=VALUE" in shape.stderr


def test_a_numbering_setting_takes_an_option_of_its_type() -> None:
    text = POST.replace("start: 10,", "start: {option: comments},")
    with pytest.raises(PostError) as info:
        api.load_post_text(text, "post.yaml")
    assert str(info.value) == ("post.yaml:11:68: output/block_numbers/start is a whole "
                               "number, but option 'comments' is true or false")


def test_option_values_that_leave_no_block_numbers_are_refused() -> None:
    text = POST.replace("  program: {", "  first: {type: int, default: 10}\n  program: {")
    text = text.replace("start: 10,", "start: {option: first},")
    assert posted_text(text, {"first": "20"})[0] == "N20 O1000"
    with pytest.raises(PostError) as info:
        posted_text(text, {"first": "99995"})
    assert str(info.value) == ("post.yaml:12:18: block numbers with the options given: start "
                               "99995, increment 10 and maximum 99999 leave no second block "
                               "number")


def posted_text(text: str, options: dict[str, object]) -> list[str]:
    post = api.load_post_text(text, "post.yaml", options)
    return [line.text for line in api.post_commands(post, program())]


RAPID_POST = POST.replace("  tool_changer: false\n", "  tool_changer: false\n"
                          "  rapid_rate: {option: speed}\n").replace(
    "  program: {", "  speed: {type: number, default: 600}\n  program: {").replace(
    '      - items: [{expr: program}]\n',
    '      - items: [{expr: program}, {param: machining_time, prefix: " (", suffix: " S)", '
    'format: coord}]\n')


def rapids() -> list[CLCommand]:
    return [ProgramStart(line=1), RapidMove(line=2, x=0.0, y=0.0, z=0.0),
            RapidMove(line=3, x=600.0), ProgramEnd(line=4)]


def test_the_machine_rapid_rate_may_be_a_number_option() -> None:
    """A router's one speed is a setting of its control: the time estimate follows it."""
    def first_line(options: dict[str, object]) -> str:
        post = api.load_post_text(RAPID_POST, "post.yaml", options)
        return next(iter(api.post_commands(post, rapids()))).text

    assert api.load_post_text(RAPID_POST, "post.yaml").machine.rapid_rate == 600.0
    assert first_line({}) == "N10 O1000 (60.000 S)"             # 600 mm at 600 mm/min
    assert first_line({"speed": "1200"}) == "N10 O1000 (30.000 S)"
    assert first_line({"speed": 2400}) == "N10 O1000 (15.000 S)"


@pytest.mark.parametrize(("change", "message"), [
    (("rapid_rate: {option: speed}", "rapid_rate: {option: comments}"),
     "post.yaml:5:24: machine/rapid_rate is a number, but option 'comments' is true or false"),
    (("rapid_rate: {option: speed}", "rapid_rate: {option: sped}"),
     "post.yaml:5:24: unknown option 'sped' (did you mean 'speed'?)"),
    (("rapid_rate: {option: speed}", "rapid_rate: {opt: speed}"), "post.yaml:5:"),
])
def test_a_rapid_rate_option_of_another_type_or_name_is_a_located_error(
        change: tuple[str, str], message: str) -> None:
    with pytest.raises(PostError) as info:
        api.load_post_text(RAPID_POST.replace(*change), "post.yaml")
    assert str(info.value).startswith(message), str(info.value)


@pytest.mark.parametrize("value", ["0", "-600"])
def test_a_rapid_rate_option_value_no_machine_has_is_refused_at_the_setting(value: str) -> None:
    with pytest.raises(PostError) as info:
        api.load_post_text(RAPID_POST, "post.yaml", {"speed": value})
    assert str(info.value) == (f"post.yaml:5:15: machine/rapid_rate (option speed) must be "
                               f"greater than 0, not {float(value):g}")
