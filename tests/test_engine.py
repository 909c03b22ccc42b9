"""The engine: output modes, conditions, numbering, fallbacks and machine limits."""

from __future__ import annotations

import textwrap
from datetime import UTC, datetime

import pytest

from postdsl import api
from postdsl.cl.model import (
    ArcMove,
    Comment,
    CustomCycle,
    CycleEnd,
    CycleHole,
    CycleStart,
    DeepDrill,
    Dwell,
    LinearMove,
    ProgramEnd,
    ProgramStart,
    RapidMove,
    SinglePeck,
    SpindleOn,
    TappingCcw,
    ToolChange,
)
from postdsl.compile import codegen
from postdsl.errors import CLError
from postdsl.run.trace import trace_lines
from tests.conftest import ROOT

NOW = datetime(2024, 3, 5, 7, 8, 9, tzinfo=UTC)

BASE = """
postdsl: 1
machine: {name: Test mill, tool_changer: false,
          travel: {x: [-100, 100], y: [-100, 100], z: [-50, 200]},
          spindle: [100, 6000], max_feed: 5000, tools: {max_number: 12, max_diameter: 40}}
output:
  block_numbers: {prefix: N, suffix: "", start: 10, increment: 10, maximum: 9999}
formats:
  c: {decimals: 3, trailing_zeros: false, point: always}
  int: {integer: true}
commands:
  program_start: {blocks: []}
  program_end: {blocks: [{items: [" M30"]}]}
"""


def make_post(commands: str, base: str = BASE, extra: str = "") -> api.CompiledPost:
    text = base + textwrap.indent(textwrap.dedent(commands), "  ") + textwrap.dedent(extra)
    return api.load_post_text(text, "test.yaml")


def post(post_: api.CompiledPost, *commands) -> list[str]:
    return [line.text for line in api.post_commands(post_, list(commands), now=NOW)]


MOVES = """
rapid_move:
  blocks:
    - items:
        - {text: " G0", mode: changed, modal: motion}
        - {param: x, prefix: " X", format: c, mode: changed}
        - {param: y, prefix: " Y", format: c, mode: changed}
        - {param: z, prefix: " Z", format: c, mode: changed}
linear_move:
  blocks:
    - items:
        - {text: " G1", mode: changed, modal: motion}
        - {param: x, prefix: " X", format: c, mode: changed}
        - {param: y, prefix: " Y", format: c, mode: changed}
        - {param: z, prefix: " Z", format: c, mode: changed}
        - {param: feed, prefix: " F", format: int, mode: changed}
"""


def test_changed_items_are_written_only_when_their_text_changes() -> None:
    p = make_post(MOVES)
    lines = post(p, RapidMove(x=1, y=2, z=3), RapidMove(x=1.0001, y=5),
                 LinearMove(x=4, feed=100), LinearMove(y=7, feed=100.2), LinearMove(x=4))
    # 1.0001 formats as "1." like 1: unchanged; the last move changes nothing -> no block
    assert lines == ["N10 G0 X1. Y2. Z3.", "N20 Y5.", "N30 G1 X4. F100", "N40 Y7.", "N50 M30"]


def test_always_items_are_written_every_time_and_update_the_register() -> None:
    p = make_post(MOVES.replace("{param: x, prefix: \" X\", format: c, mode: changed}\n"
                                "        - {param: y", "{param: x, prefix: \" X\", format: c}\n"
                                "        - {param: y", 1))
    lines = post(p, RapidMove(x=1, y=2, z=3), RapidMove(x=1, y=2, z=3),
                 LinearMove(x=1, y=9, feed=100))
    # the always X of the second rapid set the register: the changed X of G1 stays quiet
    assert lines[:3] == ["N10 G0 X1. Y2. Z3.", "N20 X1.", "N30 G1 Y9. F100"]


def test_forced_item_is_written_and_forces_the_next_changed_item_of_its_register() -> None:
    p = make_post(MOVES + """
dwell:
  blocks:
    - items: [" G4", {param: x, prefix: " X", format: c, mode: forced}]
""")
    lines = post(p, RapidMove(x=1, y=2, z=3), Dwell(dwell=1), RapidMove(y=4), RapidMove(y=5))
    # the forced X in the dwell block makes the next rapid write X again, once
    assert lines[:4] == ["N10 G0 X1. Y2. Z3.", "N20 G4 X1.", "N30 X1. Y4.", "N40 Y5."]


def test_force_if_writes_a_changed_item_when_the_condition_holds() -> None:
    p = make_post(MOVES + """
arc_move:
  blocks:
    - items:
        - {text: " G2", if: "arc_direction == 'cw'", mode: changed, modal: motion}
        - {text: " G3", if: "arc_direction == 'ccw'", mode: changed, modal: motion}
        - {param: x, prefix: " X", format: c, mode: changed}
        - {param: y, prefix: " Y", format: c, mode: changed, force_if: "changed(z)"}
        - {param: z, prefix: " Z", format: c, mode: changed}
        - {param: i, prefix: " I", format: c}
        - {param: j, prefix: " J", format: c}
""")
    lines = post(p, RapidMove(x=10, y=0, z=5),
                 ArcMove(x=0, y=10, cx=0, cy=0, arc_direction="ccw", feed=100),
                 ArcMove(x=-10, y=10, z=4, cx=-5, cy=10, arc_direction="ccw"),
                 ArcMove(x=0, y=10, z=4, cx=-5, cy=10, arc_direction="cw"))
    assert lines[1] == "N20 G3 X0. Y10. I-10. J0."
    assert lines[2] == "N30 X-10. Y10. Z4. I-5. J0."  # Y unchanged but Z changed: forced
    assert lines[3] == "N40 G2 X0. I5. J0."


def test_block_and_item_conditions() -> None:
    p = make_post("""
spindle_on:
  blocks:
    - items:
        - {text: " M3", if: "spindle == 'cw'"}
        - {text: " M4", if: "spindle == 'ccw'"}
        - {param: spindle_speed, prefix: " S", format: int}
    - if: "spindle_speed > 3000"
      items: [" (HIGH SPEED)"]
""")
    assert post(p, SpindleOn(spindle_speed=500))[:1] == ["N10 M3 S500"]
    assert post(p, SpindleOn(spindle_speed=4000, spindle="ccw"))[:2] == \
        ["N10 M4 S4000", "N20 (HIGH SPEED)"]


def test_block_numbering_start_increment_maximum_unnumbered_and_renumber() -> None:
    base = BASE.replace("start: 10, increment: 10, maximum: 9999",
                        "start: 5, increment: 5, maximum: 15, wrap: true")
    p = make_post("""
comment:
  blocks:
    - number: false
      items: ["(", {param: comment}, ")"]
dwell:
  blocks:
    - items: [" G4"]
tool_change:
  blocks:
    - renumber: true
      items: [" T", {param: tool_number, format: int}]
""", base=base)
    lines = post(p, Dwell(), Comment_("a"), Dwell(), Dwell(), Dwell(), ToolChange(tool_number=3),
                 Dwell())
    assert lines == ["N5 G4", "(a)", "N10 G4", "N15 G4", "N5 G4", "N5 T3", "N10 G4", "N15 M30"]


def Comment_(text: str):
    from postdsl.cl.model import Comment

    return Comment(comment=text)


def test_block_number_parameter_and_format() -> None:
    """A block's number as a parameter (``int``) and as the N word (its own format)."""
    base = BASE.replace("suffix: \"\", start: 10", "suffix: \"\", format: four, start: 10")
    text = (base.replace("formats:\n", "formats:\n  four: {integer: true, leading_zeros: 4}\n")
            + "  dwell:\n    blocks:\n      - items: [\" G4 (block \", "
              "{param: block_number, format: int}, \")\"]\n")
    p = api.load_post_text(text, "t.yaml")
    assert post(p, Dwell())[0] == "N0010 G4 (block 10)"


def test_unmapped_cl_command_is_an_error_naming_command_and_line() -> None:
    p = make_post(MOVES)
    with pytest.raises(CLError) as info:
        post(p, RapidMove(x=1, y=1, z=1, line=3), Dwell(dwell=2, line=4))
    assert info.value.location.line == 4
    assert "no table for CL command 'dwell'" in str(info.value)


def test_redirect_uses_the_other_commands_table() -> None:
    p = make_post("""
tapping:
  blocks:
    - items: [" G84", {param: x, prefix: " X", format: c}]
tapping_ccw: {redirect: tapping}
cycle_start: {blocks: []}
cycle_end: {blocks: [{items: [" G80"]}]}
""")
    lines = post(p, CycleStart(), TappingCcw(x=3, y=4, top=0, depth=5, clearance=2, feed=100),
                 CycleEnd())
    assert lines[:2] == ["N10 G84 X3.", "N20 G80"]


def test_expand_fallback_writes_holes_as_moves() -> None:
    p = make_post(MOVES + """
dwell:
  blocks: [{items: [" G4 P", {param: dwell, format: c}]}]
cycle_start: {blocks: []}
cycle_end: {blocks: []}
single_peck: {expand: true}
deep_drill: {expand: true}
cycle_hole: {blocks: []}
""")
    lines = post(p, RapidMove(x=0, y=0, z=50), CycleStart(),
                 SinglePeck(x=10, y=20, top=0, depth=5, clearance=2, dwell=0.5, feed=100),
                 CycleHole(x=30), CycleEnd())
    # first hole from Z50 down to the approach plane, second hole from the retract plane
    assert lines == [
        "N10 G0 X0. Y0. Z50.",
        "N20 X10. Y20.", "N30 Z2.", "N40 G1 Z-5. F100", "N50 G4 P0.5", "N60 G0 Z2.",
        "N70 X30.", "N80 G1 Z-5.", "N90 G4 P0.5", "N100 G0 Z2.",
        "N110 M30",
    ]
    pecks = post(p, RapidMove(x=0, y=0, z=10), CycleStart(),
                 DeepDrill(x=0, y=0, top=0, depth=7, clearance=2, peck=3, feed=50), CycleEnd())
    # pecks of 3 to -3, -6, then the bottom -7; full retract to the approach plane between
    assert pecks[1:] == [
        "N20 Z2.", "N30 G1 Z-3. F50", "N40 G0 Z2.", "N50 Z-2.", "N60 G1 Z-6.", "N70 G0 Z2.",
        "N80 Z-5.", "N90 G1 Z-7.", "N100 G0 Z2.", "N110 M30",
    ]


def test_drilling_cycle_forgets_z_unless_the_post_assumes_it() -> None:
    cycle = """
cycle_start: {blocks: []}
cycle_end: {reset: [motion], blocks: [{items: [" G80"]}]}
single_peck:
  blocks: [{items: [" G81", {param: x, prefix: " X", format: c}]}]
"""
    p = make_post(MOVES + cycle)
    program = [RapidMove(x=0, y=0, z=7), CycleStart(),
               SinglePeck(x=0, y=0, top=0, depth=5, clearance=7, feed=100), CycleEnd(),
               RapidMove(z=7)]
    # without 'assume' the control's Z is unknown after the cycle: Z7 is written again
    assert post(p, *program)[-2] == "N40 G0 Z7."
    p = make_post(MOVES + cycle.replace("single_peck:\n", "single_peck:\n  assume: "
                                        "{z: \"top + clearance\"}\n"))
    # the post says the cycle leaves the tool at top + clearance = 7: no Z to write
    assert post(p, *program)[-2] == "N40 G0"


def test_reset_forgets_registers() -> None:
    p = make_post(MOVES + """
tool_change:
  reset: [x, y, z, motion, feed]
  blocks: [{items: [" T", {param: tool_number, format: int}, " M6"]}]
""")
    lines = post(p, RapidMove(x=1, y=2, z=3), ToolChange(tool_number=2), RapidMove(x=1, y=2, z=3))
    assert lines[:3] == ["N10 G0 X1. Y2. Z3.", "N20 T2 M6", "N30 G0 X1. Y2. Z3."]


def test_for_each_tool_writes_a_block_per_tool_and_program_values() -> None:
    p = make_post("""
program_start:
  blocks:
    - number: false
      items: ["(TOOLS ", {param: tool_count, format: int}, ")"]
    - for_each: tool
      number: false
      items: ["(T", {param: tool_number, format: int}, ")"]
    - number: false
      items: ["(X ", {param: min_x, format: c}, " TO ", {param: max_x, format: c}, ")"]
tool_change: {reset: [x, y, z, feed], blocks: []}
""" + MOVES, base=BASE.replace("  program_start: {blocks: []}\n", ""))
    lines = post(p, ProgramStart(), ToolChange(tool_number=4), RapidMove(x=-5, y=0, z=0),
                 ToolChange(tool_number=2), ToolChange(tool_number=4), RapidMove(x=7),
                 ProgramEnd())
    assert lines[:4] == ["(TOOLS 2)", "(T4)", "(T2)", "(X -5. TO 7.)"]


def test_custom_cycle_parameters_defaults_and_unknown_parameter() -> None:
    p = make_post("", extra="""
custom_cycles:
  probe_x:
    parameters:
      target: {default: 0}
      feed_probe: {default: 200}
    blocks:
      - items: [" G65 P9023", {param: target, prefix: " X", format: c},
                {param: feed_probe, prefix: " F", format: int}]
""")
    assert post(p, CustomCycle(cycle="probe_x", params={"target": 12.5}))[0] == \
        "N10 G65 P9023 X12.5 F200"
    with pytest.raises(CLError, match="has no parameter 'speed'"):
        post(p, CustomCycle(cycle="probe_x", params={"speed": 1}, line=9))
    with pytest.raises(CLError, match="no custom cycle 'probe_y'"):
        post(p, CustomCycle(cycle="probe_y"))


@pytest.mark.parametrize(
    ("command", "message"),
    [
        (RapidMove(x=150, y=0, z=0, line=7),
         "X 150 is outside the travel of Test mill (-100 to 100)"),
        (LinearMove(x=0, y=0, z=0, feed=9000, line=7), "feed 9000 mm/min exceeds the maximum"),
        (SpindleOn(spindle_speed=8000, line=7), "spindle speed 8000 rpm is outside the range"),
        (ToolChange(tool_number=13, line=7), "tool 13 does not exist on Test mill"),
        (ToolChange(tool_number=1, tool_diameter=50, line=7), "tool diameter 50 mm exceeds"),
        (SinglePeck(x=0, y=0, top=0, depth=60, clearance=2, feed=10, line=7),
         "Z -60 is outside the travel"),
    ],
)
def test_values_outside_the_machine_are_located_errors(command, message) -> None:
    p = make_post(MOVES + """
spindle_on: {blocks: []}
tool_change: {reset: [x, y, z, feed], blocks: []}
single_peck: {blocks: []}
""")
    with pytest.raises(CLError) as info:
        post(p, command)
    assert message in info.value.message
    assert info.value.location.line == 7


def test_arc_whose_end_is_not_on_the_circle_is_rejected() -> None:
    p = make_post(MOVES + "arc_move: {blocks: []}\n")
    with pytest.raises(CLError, match="not on one circle"):
        post(p, RapidMove(x=10, y=0, z=0), ArcMove(x=0, y=12, cx=0, cy=0, line=2))


def test_program_start_and_end_are_added_when_the_cl_lacks_them() -> None:
    p = make_post(MOVES)
    assert post(p, RapidMove(x=1, y=1, z=1)) == ["N10 G0 X1. Y1. Z1.", "N20 M30"]


def test_built_in_date_and_time_come_from_the_posting_time() -> None:
    p = make_post("""
comment:
  blocks:
    - items: [" ", {param: day, format: int}, ".", {param: month, format: int}, ".",
              {param: year, format: int}, " ", {param: hour, format: int}, ":",
              {param: minute, format: int}]
""")
    assert post(p, Comment_("x"))[0] == "N10 5.3.2024 7:8"


def test_only_with_values_drops_a_block_of_bare_words_and_keeps_the_registers_true() -> None:
    p = make_post(MOVES.replace("rapid_move:\n  blocks:\n    - items:",
                                "rapid_move:\n  blocks:\n    - only_with_values: true\n"
                                "      items:") + """
comment:
  reset: [motion]
  blocks: [{number: false, items: ["(", {param: comment}, ")"]}]
""")
    lines = post(p, RapidMove(x=1, y=2, z=3), Comment_("c"), RapidMove(z=3), RapidMove(z=4))
    # the rapid to where the tool is would be a lone "G0": dropped, and since G0 was not
    # written, the next rapid still writes it
    assert lines[:3] == ["N10 G0 X1. Y2. Z3.", "(c)", "N20 G0 Z4."]


def test_reject_stops_posting_with_the_posts_message_at_the_cl_line() -> None:
    p = make_post(MOVES + """
coolant_on:
  reject:
    - {if: "coolant == 'through'", message: "this machine has no through-spindle coolant"}
  blocks: [{items: [" M8"]}]
""")
    from postdsl.cl.model import CoolantOn

    assert post(p, CoolantOn(coolant="flood"))[0] == "N10 M8"
    with pytest.raises(CLError) as info:
        post(p, CoolantOn(coolant="through", line=12))
    assert str(info.value) == ("<cl>:12: coolant_on: this machine has no through-spindle "
                               "coolant")


# --- values no machine can be given, and values no NC block can hold ------------------------

DRILLING = MOVES + """
spindle_on: {blocks: []}
tool_change: {reset: [x, y, z, feed], blocks: []}
dwell: {blocks: [{items: [" G4 P", {param: dwell, format: c}]}]}
cycle_start: {blocks: []}
cycle_end: {blocks: []}
cycle_hole: {blocks: [{items: [" X", {param: x, format: c}]}]}
single_peck: {blocks: [{items: [" G81 Z", {param: bottom, format: c}]}]}
deep_drill: {expand: true}
"""


@pytest.mark.parametrize(
    ("command", "message"),
    [
        (SinglePeck(x=0, y=0, top=0, depth=0, clearance=2, feed=10, line=7),
         "single_peck: depth 0 must be greater than 0 (measured down from the top)"),
        (SinglePeck(x=0, y=0, top=0, depth=-5, clearance=2, feed=10, line=7),
         "single_peck: depth -5 must be greater than 0 (measured down from the top)"),
        (DeepDrill(x=0, y=0, top=0, depth=5, peck=-1, clearance=2, feed=10, line=7),
         "deep_drill: peck -1 must not be negative"),
        (SinglePeck(x=0, y=0, top=0, depth=5, dwell=-1, clearance=2, feed=10, line=7),
         "single_peck: dwell -1 must not be negative"),
        (SinglePeck(x=0, y=0, top=0, depth=5, clearance=-2, feed=10, line=7),
         "single_peck: clearance -2 must not be negative"),
        (SinglePeck(x=0, y=0, top=0, depth=5, clearance=2, retract=-1, feed=10, line=7),
         "single_peck: retract -1 is below the top of the hole (0)"),
        (SinglePeck(x=0, y=0, top=0, depth=5, clearance=2, feed=0, line=7),
         "single_peck: feed 0 must be greater than 0"),
        (LinearMove(x=1, feed=-100, line=7), "linear_move: feed -100 must be greater than 0"),
        (Dwell(dwell=-1, line=7), "dwell: dwell -1 must not be negative"),
        (SpindleOn(spindle_speed=-500, line=7),
         "spindle_on: spindle speed -500 must not be negative"),
        (ToolChange(tool_number=-1, line=7), "tool_change: tool number -1 must not be negative"),
        (ToolChange(tool_number=1, tool_diameter=-8, line=7),
         "tool_change: tool diameter -8 must not be negative"),
    ],
)
def test_values_no_machine_can_be_given_are_located_errors(command, message) -> None:
    """The APT and FreeCAD readers refuse these; native CL and API records must be refused too."""
    p = make_post(DRILLING, base=BASE.replace("spindle: [100, 6000], ", ""))
    with pytest.raises(CLError) as info:
        post(p, RapidMove(x=0, y=0, z=10), CycleStart(), command)
    assert info.value.message == message
    assert info.value.location.line == 7


def test_a_further_hole_above_the_retract_plane_is_refused() -> None:
    p = make_post(DRILLING)
    with pytest.raises(CLError) as info:
        post(p, SpindleOn(spindle_speed=1000), RapidMove(x=0, y=0, z=10), CycleStart(),
             SinglePeck(x=0, y=0, top=0, depth=5, clearance=2, retract=5, feed=10),
             CycleHole(x=10, top=8, line=9))
    assert str(info.value) == "<cl>:9: cycle_hole: retract 5 is below the top of the hole (8)"


def test_an_expanded_hole_with_a_tiny_peck_is_refused_not_written_for_ever() -> None:
    p = make_post(DRILLING)
    with pytest.raises(CLError) as info:
        post(p, RapidMove(x=0, y=0, z=10), CycleStart(),
             DeepDrill(x=0, y=0, top=0, depth=20, peck=1e-9, clearance=2, feed=10, line=4))
    assert str(info.value).startswith("<cl>:4: deep_drill: peck 1e-09 makes 20000000000 pecks")


def test_an_arc_of_radius_zero_says_so() -> None:
    p = make_post(MOVES + "arc_move: {blocks: []}\n")
    with pytest.raises(CLError) as info:
        post(p, RapidMove(x=10, y=0, z=0), ArcMove(x=10, y=0, cx=10, cy=0, line=2))
    assert str(info.value) == ("<cl>:2: arc_move: the centre (10, 0) is the start point: "
                               "an arc needs a radius")


def test_the_arc_error_names_the_start_and_the_centre() -> None:
    p = make_post(MOVES + "arc_move: {blocks: []}\n")
    with pytest.raises(CLError) as info:
        post(p, RapidMove(x=10, y=0, z=0), ArcMove(x=0, y=12, cx=0, cy=0, line=2))
    assert info.value.message == ("arc_move: the start (10, 0) and the end (0, 12) are not on "
                                  "one circle about the centre (0, 0) (radius 10.0000 at the "
                                  "start, 12.0000 at the end)")


COMMENT = """
comment: {blocks: [{number: false, items: ["(", {param: comment}, ")"]}]}
"""


@pytest.mark.parametrize("text", ["a\nN999 G0 Z-100", "a\rG0 Z-100", "a\u2028b", "bell\x07"])
def test_text_that_would_break_the_block_is_refused(text: str) -> None:
    """A line break in a comment would start a block the control executes."""
    p = make_post(COMMENT)
    with pytest.raises(CLError) as info:
        post(p, Comment_("ok"), Comment(comment=text, line=3))
    assert str(info.value).startswith("<cl>:3: comment: post table 'comment' cannot be "
                                      "written: parameter 'comment' is text holding the control "
                                      "character ")


def test_text_where_the_item_gives_a_number_format_is_refused() -> None:
    """CL text such as "ten" for a probing distance must not become the word Xten."""
    p = make_post("", extra="""
custom_cycles:
  probe_x:
    parameters: {travel: {default: 10}, label: {default: side}}
    blocks:
      - items: [" G65 P9023", {param: travel, prefix: " X", format: c}, " (",
                {param: label}, ")"]
""")
    assert post(p, CustomCycle(cycle="probe_x", params={"label": "left"}))[0] == \
        "N10 G65 P9023 X10. (left)"
    with pytest.raises(CLError) as info:
        post(p, CustomCycle(cycle="probe_x", params={"travel": "ten"}, line=5))
    assert str(info.value) == ("<cl>:5: custom_cycle: post table 'probe_x' cannot be written: "
                               "parameter 'travel' is the text 'ten', but the item writes it "
                               "as a number (format 'c') (test.yaml:19:31)")


@pytest.mark.parametrize(
    ("expression", "message"),
    [
        ("tools", "expression 'tools' is the list [1], which cannot be written as NC text"),
        ("x * 1e308 * 10", "number out of range (too large) in 'x * 1e308 * 10'"),
    ],
)
def test_computed_values_no_block_can_hold_are_located_errors(expression: str,
                                                              message: str) -> None:
    p = make_post(f"""
tool_change:
  reset: [x, y, z, feed]
  blocks: [{{items: [" T", {{expr: "{expression}", format: c}}]}}]
rapid_move: {{blocks: []}}
""")
    with pytest.raises(CLError) as info:
        post(p, RapidMove(x=1, y=0, z=0), ToolChange(tool_number=1, line=4))
    assert str(info.value) == (f"<cl>:4: tool_change: post table 'tool_change' cannot be "
                               f"written: {message} (test.yaml:17:29)")


def test_a_custom_cycle_record_without_a_cycle_name_says_so() -> None:
    p = make_post("", extra="custom_cycles:\n  probe_x: {blocks: []}\n")
    with pytest.raises(CLError) as info:
        post(p, CustomCycle(line=3))
    assert str(info.value) == ("<cl>:3: custom_cycle: no 'cycle' names the post's custom cycle "
                               "(it has: probe_x)")


def test_a_huge_value_is_shortened_in_the_message() -> None:
    p = make_post(MOVES)
    with pytest.raises(CLError) as info:
        post(p, RapidMove(x=10**400, y=0, z=0, line=2))
    assert str(info.value) == ("<cl>:2: X 1000000000…(401 digits) is outside the travel of "
                               "Test mill (-100 to 100)")


def test_a_run_time_expression_error_names_the_place_in_the_post_too() -> None:
    """Division by zero is found only when a CL value reaches it: the message names the CL
    line that caused it and the post's condition or item that failed."""
    p = make_post("""
dwell:
  blocks:
    - items: [" G4", {expr: "1 / dwell", prefix: " F", format: c}]
    - if: "10 / dwell > 1"
      items: [" M0"]
""")
    with pytest.raises(CLError) as info:
        post(p, Dwell(dwell=0, line=6))
    assert str(info.value) == ("<cl>:6: dwell: post table 'dwell' cannot be written: division "
                               "by zero in '1 / dwell' (test.yaml:17:24)")
    p = make_post("""
dwell:
  blocks:
    - if: "10 / dwell > 1"
      items: [" M0"]
""")
    with pytest.raises(CLError) as info:
        post(p, Dwell(dwell=0, line=6))
    assert str(info.value).endswith("division by zero in '10 / dwell' (test.yaml:17:14)")


def test_replace_keeps_cl_text_from_closing_a_comment_early() -> None:
    p = make_post("""
comment:
  blocks:
    - number: false
      items: ["(", {param: comment, replace: {"(": "[", ")": "]"}}, ")"]
""")
    # without the replacement the control would run "G0 Z-100" as code
    assert post(p, Comment_("T1) G0 Z-100 (x"))[0] == "(T1] G0 Z-100 [x)"


def test_for_each_tool_lines_are_traced_to_their_block_for_every_tool() -> None:
    """The traced flavour of the generated code records a for_each block once per tool,
    each line with the block's path and its words."""
    p = make_post("""
program_start:
  blocks:
    - for_each: tool
      number: false
      items: ["(T", {param: tool_number, format: int}, ")"]
tool_change: {reset: [x, y, z, feed], blocks: []}
""" + MOVES, base=BASE.replace("  program_start: {blocks: []}\n", ""))
    program = [ProgramStart(), ToolChange(tool_number=4), RapidMove(x=-5, y=0, z=0),
               ToolChange(tool_number=2), RapidMove(x=7), ProgramEnd()]
    traced = list(trace_lines(p, program, now=NOW))
    assert [t.line.text for t in traced] == post(p, *program)
    tools = [t for t in traced if t.line.table == "program_start"]
    assert [t.line.text for t in tools] == ["(T4)", "(T2)"]
    assert {t.block_path for t in tools} == {("commands", "program_start", "blocks", 0)}
    assert [[w.text for w in t.words] for t in tools] == [["(T", "4", ")"], ["(T", "2", ")"]]


def test_a_move_table_with_a_for_each_block_is_posted_without_a_lane() -> None:
    """A rapid_move table with a for_each block gets no lane (the lanes write each block
    once); its generated table function runs through post_command, each tool's line in
    turn, as for any other record."""
    p = make_post(MOVES.replace("rapid_move:\n  blocks:\n", """rapid_move:
  blocks:
    - for_each: tool
      number: false
      items: ["(T", {param: tool_number, format: int}, ")"]
""") + """
tool_change: {reset: [x, y, z, feed], blocks: []}
""")
    assert "rapid_move" not in codegen.generated(p).lanes
    program = [ToolChange(tool_number=3), RapidMove(x=1, y=2, z=3),
               ToolChange(tool_number=5), RapidMove(x=4)]
    # the second tool change resets X Y Z: the kept Y and Z are written again
    assert post(p, *program) == ["(T3)", "(T5)", "N10 G0 X1. Y2. Z3.", "(T3)", "(T5)",
                                 "N20 X4. Y2. Z3.", "N30 M30"]
    assert [t.line.text for t in trace_lines(p, program, now=NOW)] == post(p, *program)


@pytest.mark.parametrize("machine", sorted(p.stem for p in (ROOT / "machines").glob("*.yaml")))
def test_every_table_of_every_library_post_has_a_generated_function(machine: str) -> None:
    """No table is left to another executor: each of a library post's tables and custom
    cycles has its function in the plain module and in its traced flavour."""
    p = api.load_post(machine)
    tables = [*p.commands.values(), *p.custom_cycles.values()]
    for traced in (False, True):
        functions = codegen.generated(p, traced=traced)
        assert all(functions.table(table) is not None for table in tables)
