"""Hostile posts and CL values: every one refused with its place, quickly, never a crash."""

from __future__ import annotations

import textwrap
import time
from datetime import UTC, datetime

import pytest

from postdsl import api
from postdsl.cl.model import (
    ArcMove,
    BreakChip,
    CustomCycle,
    CycleHole,
    DeepDrill,
    Dwell,
    LinearMove,
    RapidMove,
)
from postdsl.errors import CLError, PostError

NOW = datetime(2024, 3, 5, 7, 8, 9, tzinfo=UTC)

BASE = """\
postdsl: 1
machine: {name: Mill, tool_changer: false, travel: {x: [-100, 100], y: [-100, 100], z: [-50, 200]}}
output:
  block_numbers: {prefix: N, suffix: " ", start: 10, increment: 10, maximum: 9999}
formats:
  c: {decimals: 3, trailing_zeros: false, point: always}
  int: {integer: true}
commands:
  program_start: {blocks: []}
  program_end: {blocks: [{items: [" M30"]}]}
  rapid_move: {blocks: [{items: ["G0", {param: x, prefix: " X", format: c},
                                 {param: y, prefix: " Y", format: c},
                                 {param: z, prefix: " Z", format: c}]}]}
"""


def make_post(commands: str = "", extra: str = "") -> api.CompiledPost:
    text = BASE + textwrap.indent(textwrap.dedent(commands), "  ") + textwrap.dedent(extra)
    return api.load_post_text(text, "test.yaml")


def post(post_: api.CompiledPost, *commands) -> list[str]:
    return [line.text for line in api.post_commands(post_, list(commands), now=NOW)]


# --- structures: use: fan-out -----------------------------------------------------------------


def test_structures_that_fan_out_are_refused_quickly_at_the_use() -> None:
    structures = ["structures:", "  s0:", "    - {items: [' G0']}"]
    for level in range(1, 8):
        structures.append(f"  s{level}:")
        structures += [f"    - {{use: s{level - 1}}}"] * 7
    text = BASE + "  linear_move: {blocks: [{use: s7}]}\n" + "\n".join(structures) + "\n"
    started = time.perf_counter()
    with pytest.raises(PostError) as caught:
        api.load_post_text(text, "fan.yaml")
    assert time.perf_counter() - started < 10  # it took minutes; it takes milliseconds
    assert caught.value.message == ("'use: s7' makes table 'linear_move' expand to more than "
                                    "10,000 blocks (structures using structures multiply)")
    assert (caught.value.location.file, caught.value.location.line) == ("fan.yaml", 14)


def test_a_structure_used_a_few_times_is_fine() -> None:
    post_ = make_post("linear_move: {blocks: [{use: two}, {use: two}]}\n",
                      "structures:\n  one: [{items: [' G1']}]\n  two: [{use: one}, {use: one}]\n")
    assert len(post_.commands["linear_move"].blocks) == 4


# --- text in the post itself ------------------------------------------------------------------


@pytest.mark.parametrize("item", [
    '"G0\\rM30"', '{text: "A\\nB"}', '{param: x, prefix: " X\\r", format: c}',
    '{param: x, suffix: "\\u0085", format: c}', '{param: x, format: c, replace: {"(": "\\r"}}',
    '"\\t G0"',
])
def test_control_characters_in_the_posts_own_text_are_refused_with_file_line_column(
        item: str) -> None:
    text = BASE + f"  linear_move: {{blocks: [{{items: [{item}]}}]}}\n"
    with pytest.raises(PostError) as caught:
        api.load_post_text(text, "cr.yaml")
    location = caught.value.location
    assert (location.file, location.line) == ("cr.yaml", text.count("\n"))
    assert location.column is not None
    assert "control character" in caught.value.message


def test_control_characters_in_the_block_number_prefix_are_refused() -> None:
    text = BASE.replace('suffix: " "', 'suffix: "\\r"')
    with pytest.raises(PostError) as caught:
        api.load_post_text(text, "cr.yaml")
    assert caught.value.location.line == 4
    assert "control character" in caught.value.message


# --- YAML nesting -----------------------------------------------------------------------------


@pytest.mark.slow  # ruamel's recursion to its limit: ~20 s
def test_a_yaml_document_nested_too_deeply_names_a_line() -> None:
    text = BASE + "variables:\n  deep: " + "[" * 5000 + "]" * 5000 + "\n"
    with pytest.raises(PostError) as caught:
        api.load_post_text(text, "deep.yaml")
    assert "nested too deeply" in caught.value.message
    assert caught.value.location.line == text.count("\n")


# --- expressions that overflow at run time ----------------------------------------------------


@pytest.mark.parametrize("expression", [
    "(x + 99999999999999)" + " * 99999999999999" * 25,
    "x * 1e300 * 1e300",
    "-(x * 1e300 * 1e300)",
    "(x + 1e300) * 1e300 / 1e300",
])
def test_an_expression_that_overflows_stops_at_the_item_and_the_cl_line(expression: str) -> None:
    items = "[' G1', {expr: '" + expression + "', prefix: ' X', format: c}]"
    post_ = make_post(f"linear_move: {{blocks: [{{items: {items}}}]}}\n")
    with pytest.raises(CLError) as caught:
        post(post_, RapidMove(x=1, y=1, z=1, line=3), LinearMove(x=2, feed=100, line=4))
    assert caught.value.location.line == 4
    assert "test.yaml:" in caught.value.message
    assert "out of range" in caught.value.message or "too large" in caught.value.message


def test_huge_integers_from_repeated_products_are_refused_not_crashed() -> None:
    expression = " * ".join(["(x + 99999999999999)"] * 80)
    items = "[' G1', {expr: '" + expression + "', prefix: ' X', format: c}]"
    post_ = make_post(f"linear_move: {{blocks: [{{items: {items}}}]}}\n")
    with pytest.raises(CLError) as caught:
        post(post_, RapidMove(x=1, y=1, z=1, line=3), LinearMove(x=2, feed=100, line=4))
    assert caught.value.location.line == 4


# --- custom cycles and further holes ----------------------------------------------------------

CYCLES = """\
custom_cycles:
  probe: {parameters: {target: {default: 0}}, blocks: [{items: [" G65 P9810"]}]}
"""


def test_a_further_hole_after_a_custom_cycle_is_refused_with_the_cl_line() -> None:
    post_ = make_post("cycle_hole: {blocks: [{items: [{param: x, prefix: ' X', format: c}]}]}\n",
                      CYCLES)
    with pytest.raises(CLError) as caught:
        post(post_, RapidMove(x=1, y=1, z=1, line=2), CustomCycle(cycle="probe", line=3),
             CycleHole(x=5, y=5, line=4))
    assert caught.value.location.line == 4
    assert "cycle_hole" in caught.value.message and "drilling cycle" in caught.value.message


# --- pecking ----------------------------------------------------------------------------------

DRILLING = """\
single_peck: {blocks: [{items: [" G81", {param: x, prefix: " X", format: c},
                                {param: bottom, prefix: " Z", format: c}]}]}
deep_drill: {blocks: [{items: [" G83", {param: x, prefix: " X", format: c},
                               {param: bottom, prefix: " Z", format: c},
                               {param: peck, prefix: " Q", format: c}]}]}
break_chip: {redirect: deep_drill}
cycle_hole: {blocks: [{items: [{param: x, prefix: " X", format: c}]}]}
"""


@pytest.mark.parametrize("setup", [DeepDrill, BreakChip])
def test_peck_zero_means_no_pecking(setup) -> None:
    post_ = make_post(DRILLING)
    lines = post(post_, setup(x=5, y=5, top=0, depth=10, clearance=2, feed=100, peck=0, line=2),
                 CycleHole(x=7, line=3))
    assert lines == ["N10  G81 X5. Z-10.", "N20  X7.", "N30  M30"]


def test_a_peck_cycle_with_a_peck_is_still_a_peck_cycle() -> None:
    post_ = make_post(DRILLING)
    lines = post(post_, DeepDrill(x=5, y=5, top=0, depth=10, clearance=2, feed=100, peck=3))
    assert lines[0] == "N10  G83 X5. Z-10. Q3."


def test_peck_zero_without_a_single_feed_table_says_so() -> None:
    post_ = make_post(DRILLING.split("deep_drill")[0].replace("single_peck", "tapping")
                      + "deep_drill" + DRILLING.split("deep_drill", 1)[1])
    with pytest.raises(CLError) as caught:
        post(post_, DeepDrill(x=5, y=5, top=0, depth=10, clearance=2, feed=100, line=7))
    assert caught.value.location.line == 7
    assert "peck 0" in caught.value.message and "single_peck" in caught.value.message


# --- block numbering --------------------------------------------------------------------------


def _numbered(numbers: str) -> str:
    return BASE.replace("{prefix: N, suffix: \" \", start: 10, increment: 10, maximum: 9999}",
                        numbers)


def test_an_increment_that_cannot_fit_below_the_maximum_is_refused() -> None:
    text = _numbered("{start: 10, increment: 10000, maximum: 9999}")
    with pytest.raises(PostError) as caught:
        api.load_post_text(text, "n.yaml")
    assert caught.value.location.line == 4
    assert "increment" in caught.value.message


def test_block_numbers_running_out_stop_at_the_cl_line() -> None:
    post_ = api.load_post_text(_numbered("{start: 10, increment: 10, maximum: 30}"), "n.yaml")
    moves = [RapidMove(x=i, y=0, z=0, line=i + 1) for i in range(5)]
    with pytest.raises(CLError) as caught:
        post(post_, *moves)
    assert caught.value.location.line == 4
    assert "block number" in caught.value.message and "30" in caught.value.message


def test_block_numbers_wrap_only_when_the_post_says_so() -> None:
    post_ = api.load_post_text(
        _numbered("{start: 10, increment: 10, maximum: 30, wrap: true}"), "n.yaml")
    lines = post(post_, *[RapidMove(x=i, y=0, z=0) for i in range(4)])
    assert [line.split()[0] for line in lines] == ["N10", "N20", "N30", "N10", "N20"]


# --- arcs within the travel -------------------------------------------------------------------


def _arcs() -> api.CompiledPost:
    return make_post("linear_move: {blocks: [{items: [' G1']}]}\n"
                     "arc_move: {blocks: [{items: [' G2', {param: x, prefix: ' X', format: c},"
                     " {param: y, prefix: ' Y', format: c}]}]}\n")


def test_an_arc_bulging_outside_the_travel_is_refused() -> None:
    # a half circle from (90, 0) to (90, 60) about (90, 30), counter-clockwise: through X 120
    with pytest.raises(CLError) as caught:
        post(_arcs(), RapidMove(x=90, y=0, z=0, line=2),
             ArcMove(x=90, y=60, cx=90, cy=30, arc_direction="ccw", feed=100, line=3))
    assert caught.value.location.line == 3
    assert "X 120" in caught.value.message and "travel" in caught.value.message


def test_the_same_arc_the_other_way_stays_inside() -> None:
    lines = post(_arcs(), RapidMove(x=90, y=0, z=0),
                 ArcMove(x=90, y=60, cx=90, cy=30, arc_direction="cw", feed=100))
    assert lines[1] == "N20  G2 X90. Y60."


def test_an_arc_in_the_zx_plane_is_checked_in_z() -> None:
    # a half circle from (Z -40, X 20) to (Z -40, X -20) about (Z -40, X 0): through Z -60
    # one way round, Z -20 the other
    refused = []
    for direction in ("cw", "ccw"):
        try:
            post(_arcs(), RapidMove(x=20, y=0, z=-40, line=2),
                 ArcMove(x=-20, z=-40, cx=0, cz=-40, plane="zx", arc_direction=direction,
                         feed=100, line=3))
        except CLError as exc:
            refused.append(exc.message)
    assert len(refused) == 1 and "Z -60" in refused[0]


def test_a_full_circle_is_checked_all_round() -> None:
    # start = end = (-40, 0), centre (50, 0): the circle reaches X 140
    with pytest.raises(CLError) as caught:
        post(_arcs(), RapidMove(x=-40, y=0, z=0, line=2),
             ArcMove(x=-40, y=0, cx=50, cy=0, arc_direction="ccw", feed=100, line=3))
    assert caught.value.location.line == 3
    assert "X 140" in caught.value.message


# --- words no control takes -------------------------------------------------------------------


def test_a_value_with_more_digits_than_the_format_allows_stops_at_its_cl_line() -> None:
    post_ = make_post("dwell: {blocks: [{items: [' G4', {param: dwell, prefix: ' P', "
                      "format: c}]}]}\n")
    with pytest.raises(CLError) as caught:
        post(post_, Dwell(dwell=1e300, line=6))
    message = caught.value.message
    assert caught.value.location.line == 6
    assert "word P" in message and "301 digits" in message and "max_digits" in message
    assert "test.yaml:14:" in message


def test_the_default_width_takes_what_machines_are_given() -> None:
    post_ = make_post("dwell: {blocks: [{items: [' G4', {param: dwell, prefix: ' P', "
                      "format: c}]}]}\n")
    assert post(post_, Dwell(dwell=99_999_999.5))[0] == "N10  G4 P99999999.5"
    with pytest.raises(CLError):
        post(post_, Dwell(dwell=100_000_000))


def test_a_format_can_narrow_the_width() -> None:
    text = BASE.replace("  int: {integer: true}",
                        "  int: {integer: true}\n  ms: {integer: true, multiplier: 1000, "
                        "max_digits: 5}")
    narrow = api.load_post_text(text + "  dwell: {blocks: [{items: [' G4', {param: dwell, "
                                "prefix: ' P', format: ms}]}]}\n", "ms.yaml")
    assert post(narrow, Dwell(dwell=99.999))[0] == "N10  G4 P99999"
    with pytest.raises(CLError) as caught:
        post(narrow, Dwell(dwell=100, line=2))
    assert "word P of parameter 'dwell': the value 100 times 1000 has 6 digits" in \
        caught.value.message


def test_a_custom_cycle_argument_without_a_format_is_bounded_too() -> None:
    cycle = ("custom_cycles:\n  probe: {parameters: {target: {default: 0}}, blocks: [{items: "
             "[' G65 P9810', {param: target, prefix: ' X'}]}]}\n")
    post_ = make_post("", cycle)
    assert post(post_, CustomCycle(cycle="probe", params={"target": 12.5}))[0] == \
        "N10  G65 P9810 X12.5"
    with pytest.raises(CLError) as caught:
        post(post_, CustomCycle(cycle="probe", params={"target": 1e300}, line=5))
    assert caught.value.location.line == 5
    assert "word X" in caught.value.message and "301 digits" in caught.value.message


def test_a_character_yaml_does_not_allow_names_its_line_and_column() -> None:
    text = BASE + "  linear_move: {blocks: [{items: [' G1\x01']}]}\n"
    with pytest.raises(PostError) as caught:
        api.load_post_text(text, "ctl.yaml")
    location = caught.value.location
    assert (location.line, location.column) == (text.count("\n"), 39)
    assert "U+0001" in caught.value.message


def test_a_block_number_maximum_its_format_cannot_write_is_refused() -> None:
    text = _numbered("{start: 10, increment: 10, maximum: 999999999, format: int}")
    with pytest.raises(PostError) as caught:
        api.load_post_text(text, "n.yaml")
    assert caught.value.location.line == 4
    assert "max_digits" in caught.value.message


def test_a_peck_zero_cycle_posted_as_single_peck_keeps_its_cl_line() -> None:
    """Refusals of the single_peck it becomes still name the peck cycle's line."""
    post_ = make_post('''\
        single_peck:
          reject: [{if: "depth > 5", message: "too deep"}]
          blocks: [{items: [" G81"]}]
        ''')
    with pytest.raises(CLError) as caught:
        post(post_, DeepDrill(x=0, y=0, top=0, depth=10, clearance=2, peck=0, feed=100,
                              line=7))
    assert caught.value.location.line == 7
