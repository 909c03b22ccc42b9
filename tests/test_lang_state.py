"""Readable state and structures with parameters (issue 12), through real posts.

Two posts in tests/data/lang are written as the issue's trial posts needed to be:
a LinuxCNC mill (flags for a deferred M8, a pending G80 and G90 G99 once per operation;
next-tool pre-staging; drilling cycles sharing one structure with parameters) and a
Heidenhain TNC (TOOL CALL with the spindle speed of the record after it; helices with
their turn computed by atan2).  Their programs are read line by line as a machinist would;
the LinuxCNC one is replayed by ``postdsl verify`` and by LinuxCNC's own rs274.  Small
inline posts pin down each rule and each load-time error.
"""

from __future__ import annotations

import textwrap
from datetime import UTC, datetime
from pathlib import Path

import pytest

from postdsl import api
from postdsl.cl.model import (
    ArcMove,
    CoolantOn,
    CycleEnd,
    CycleHole,
    DeepDrill,
    Dwell,
    LinearMove,
    Operation,
    ProgramEnd,
    ProgramStart,
    RapidMove,
    SinglePeck,
    SpindleOn,
    ToolChange,
)
from postdsl.errors import CLError, PostError
from tests.test_rs274_oracle import needs_rs274, run_rs274

DATA = Path(__file__).parent / "data" / "lang"
NOW = datetime(2024, 3, 5, tzinfo=UTC)


def _post(post: api.CompiledPost, commands: list[object]) -> list[str]:
    return [line.text for line in api.post_commands(post, commands, now=NOW)]


# ------------------------------------------------------------------------------------------
# The LinuxCNC post
# ------------------------------------------------------------------------------------------

DRILL_AND_CONTOUR = [
    ProgramStart(),
    Operation(operation="Drill (2 holes)"),
    ToolChange(tool_number=3, tool_diameter=6),
    SpindleOn(spindle_speed=1200),
    CoolantOn(),
    RapidMove(x=10, y=10, z=20),
    DeepDrill(x=10, y=10, top=0, depth=12, clearance=2, peck=4, feed=120),
    CycleHole(x=30, y=10),
    Operation(operation="Spot"),
    SinglePeck(x=50, y=10, top=0, depth=1, clearance=2, feed=100),
    CycleEnd(),
    Operation(operation="Contour"),
    ToolChange(tool_number=5, tool_diameter=10),
    SpindleOn(spindle_speed=8000),
    RapidMove(x=0, y=0, z=5),
    LinearMove(z=-2, feed=300),
    LinearMove(x=20),
    ArcMove(x=30, y=10, cx=20, cy=10, arc_direction="ccw"),
    RapidMove(z=20),
    ProgramEnd(),
]


def test_the_linuxcnc_post_keeps_its_own_state() -> None:
    lines = _post(api.load_post(DATA / "linuxcnc_state.yaml"), DRILL_AND_CONTOUR)
    assert lines == [
        "G21 G90 G17 G94 G54",
        "(Drill [2 holes])",
        "T3 M6",
        "G43 H3",
        "T5",  # next_tool: tool 5 is staged while tool 3 cuts
        "S1200 M3",
        # coolant_on wrote nothing: M8 goes with the first move (flag coolant_due)
        "G0 X10 Y10 Z20 M8",
        # the first cycle of the operation sets G90 G99 (flag retract_mode_due)
        "G90 G99 G83 X10 Y10 Z-12 R2 Q4 F120",
        "X30 Y10",
        # the CL never ended the cycle: the operation's end does (flag cycle_open)
        "G80",
        "(Spot)",
        "G90 G99 G81 X50 Y10 Z-1 R2 F100",  # the same structure, with code G81, no Q
        "G80",  # the CL's cycle_end; the operation's end then has no cycle to cancel
        "(Contour)",
        "(T3 OUT, T5 IN)",  # prev_tool_number, written with str(x, 'int')
        "T5 M6",
        "G43 H5",  # no next tool: nothing staged
        "S8000 M3",
        "G0 X0 Y0 Z5",
        "G1 Z-2 F300",
        "G1 X20",
        "G3 X30 Y10 I0 J10",
        "G0 Z20",
        "M5 M9",
        "M2",
    ]


def test_the_linuxcnc_program_replays_as_the_cl_moves() -> None:
    post = api.load_post(DATA / "linuxcnc_state.yaml")
    verdict = api.verify_commands(post, DRILL_AND_CONTOUR, now=NOW)
    assert verdict.ok, verdict.divergence
    assert (verdict.holes, verdict.cuts) == (3, 6)


@needs_rs274
def test_linuxcnc_runs_the_program(tmp_path: Path) -> None:
    """rs274 accepts every block; its canned cycles drill at the CL's holes and depths."""
    lines = _post(api.load_post(DATA / "linuxcnc_state.yaml"), DRILL_AND_CONTOUR)
    trace = run_rs274([f"N{n} {line}" for n, line in enumerate(lines, start=1)], tmp_path)
    bottoms = {(round(m.end[0], 3), round(m.end[1], 3), round(m.end[2], 3))
               for m in trace.moves if m.kind == "feed" and m.end[2] < -0.5}
    assert {(10, 10, -12), (30, 10, -12), (50, 10, -1), (0, 0, -2)} <= bottoms
    arcs = [m for m in trace.moves if m.kind == "arc"]
    assert len(arcs) == 1 and arcs[0].end[:2] == pytest.approx((30, 10))


# ------------------------------------------------------------------------------------------
# The Heidenhain post
# ------------------------------------------------------------------------------------------


def test_the_tnc_post_calls_the_tool_with_the_speed_of_the_next_record() -> None:
    program = [
        ProgramStart(program_name="POCKET"),
        Operation(operation="Helix bore"),
        ToolChange(tool_number=3, tool_diameter=6),
        SpindleOn(spindle_speed=4500),
        RapidMove(x=30, y=0, z=2),
        LinearMove(z=0, feed=200),
        ArcMove(x=30, y=0, z=-2, cx=20, cy=0, arc_direction="ccw", feed=400),
        ArcMove(x=20, y=10, z=-3, cx=20, cy=0, arc_direction="cw"),
        ArcMove(x=10, y=0, cx=20, cy=0, arc_direction="ccw"),
        RapidMove(z=20),
        ToolChange(tool_number=4),
        RapidMove(x=0, y=0),
        ProgramEnd(),
    ]
    assert _post(api.load_post(DATA / "tnc_klartext.yaml"), program) == [
        "0 BEGIN PGM POCKET MM",
        "1 * - Helix bore",
        "2 TOOL CALL 3 Z S4500",  # S from the spindle_on after the tool change
        "3 L X+30 Y+0 Z+2 R0 FMAX M3",  # M3 with the first positioning move
        "4 L Z+0 R0 F200",
        "5 CC X+20 Y+0",
        "6 CP IPA+360 IZ-2 DR+ F400",  # a full turn down 2 mm
        "7 CC X+20 Y+0",
        "8 CP IPA-270 IZ-1 DR-",  # from 0 to 90 degrees clockwise: 270 degrees
        "9 CC X+20 Y+0",
        "10 C X+10 Y+0 DR+",  # no change in Z: a plain arc
        "11 L Z+20 R0 FMAX",
        "12 TOOL CALL 4 Z",  # this tool never turns: no S
        "13 L X+0 Y+0 Z+20 R0 FMAX",
        "14 L Z+100 R0 FMAX M30",
        "15 END PGM POCKET MM",
    ]


# ------------------------------------------------------------------------------------------
# The rules, one at a time
# ------------------------------------------------------------------------------------------

BASE = """
postdsl: 1
machine: {name: Test mill, tool_changer: false}
output: {block_numbers: {default: false}}
formats:
  c: {decimals: 3, trailing_zeros: false}
  int: {integer: true}
"""


def make(text: str) -> api.CompiledPost:
    return api.load_post_text(BASE + textwrap.dedent(text), "post.yaml")


def load_errors(text: str) -> list[str]:
    with pytest.raises(PostError) as info:
        make(text)
    return [str(problem) for problem in info.value.problems] or [str(info.value)]


MOVES = """
commands:
  program_start: {blocks: []}
  program_end: {blocks: []}
  rapid_move:
    blocks:
      - items: ["G0", {param: x, prefix: " X", format: c}, {param: z, prefix: " Z", format: c}]
"""

PREV = MOVES + """
  linear_move:
    blocks:
      - items:
          - "G1"
          - {param: x, prefix: " X", format: c}
          - {param: feed, prefix: " F", format: int}
          - {expr: "' (' + str(prev_feed, 'int') + ' BEFORE)'",
             if: "defined(prev_feed) and feed != prev_feed"}
          - {expr: "' (FROM X' + str(prev_x, 'c') + ')'"}
"""


def test_prev_is_the_value_before_the_current_record_changed_it() -> None:
    lines = _post(make(PREV), [RapidMove(x=0, z=5), LinearMove(x=10, feed=200),
                               LinearMove(x=20), LinearMove(x=25, feed=100)])
    assert lines == [
        "G0 X0 Z5",
        "G1 X10 F200 (FROM X0)",  # no feed before this record: prev_feed has no value
        "G1 X20 F200 (FROM X10)",  # the record left the feed alone: prev_feed is 200 too
        "G1 X25 F100 (200 BEFORE) (FROM X20)",
    ]


def test_prev_of_a_parameter_without_a_value_is_a_located_error() -> None:
    post = make(PREV.replace('if: "defined(prev_feed) and feed != prev_feed"',
                             'if: "feed != prev_feed"'))
    with pytest.raises(CLError) as info:
        _post(post, [RapidMove(x=0, z=5), LinearMove(x=10, feed=200, line=4)])
    assert str(info.value) == (
        "<cl>:4: linear_move: post table 'linear_move' cannot be written: parameter "
        "'prev_feed' has no value (post.yaml:22:13)")


FLAGS = MOVES + """
  coolant_on:
    set: {coolant_due: "true", count: "count + 1"}
    blocks: []
  linear_move:
    set: {coolant_due: "false"}
    blocks:
      - items:
          - "G1"
          - {param: x, prefix: " X", format: c}
          - {text: " M8", if: coolant_due}
          - {expr: "' (' + str(count, 'int') + ')'", if: coolant_due}
flags:
  coolant_due: false
  count: 0
"""


def test_flags_are_set_after_the_blocks_and_read_by_the_next_record() -> None:
    lines = _post(make(FLAGS), [RapidMove(x=0, z=5), LinearMove(x=1, feed=100), CoolantOn(),
                                LinearMove(x=2), LinearMove(x=3), CoolantOn(),
                                LinearMove(x=4)])
    assert lines == ["G0 X0 Z5", "G1 X1", "G1 X2 M8 (1)", "G1 X3", "G1 X4 M8 (2)"]


@pytest.mark.parametrize(("change", "message"), [
    ('set: {coolant_dew: "true"}',
     "post.yaml:17:11: 'coolant_dew' is not a flag (declare it under flags: with its initial "
     "value) (did you mean 'coolant_due'?)"),
    ('set: {coolant_due: "coolant_du"}',
     "post.yaml:17:25: bad expression: unknown name 'coolant_du'; did you mean "
     "'coolant_due'?"),
])
def test_set_is_checked_when_the_post_loads(change: str, message: str) -> None:
    text = FLAGS.replace('set: {coolant_due: "true", count: "count + 1"}', change)
    assert message in load_errors(text)


def test_a_flag_may_not_hide_a_parameter() -> None:
    errors = load_errors(FLAGS + "  feed: 3\n")
    assert "post.yaml:30:3: flag 'feed' hides the parameter of that name" in errors


def test_a_set_that_fails_is_located_in_the_post_and_the_cl() -> None:
    text = FLAGS.replace('count: "count + 1"', 'count: "count / 0"')
    with pytest.raises(CLError) as info:
        _post(make(text), [RapidMove(x=0, z=5), CoolantOn(line=7)])
    assert str(info.value) == ("<cl>:7: coolant_on: set count: division by zero in "
                               "'count / 0' (post.yaml:17:40)")


EVENTS = MOVES + """
  operation: {blocks: [{items: ["(OP ", {param: operation}, ")"]}]}
  tool_change:
    reset: [x, z, feed]
    blocks: [{items: ["T", {param: tool_number, format: int},
                      {param: next_tool, prefix: " NEXT T", format: int,
                       if: "defined(next_tool)"}]}]
  operation_end: {blocks: [{items: ["(END OF OPERATION)"]}]}
"""


def test_operation_end_comes_once_before_each_boundary() -> None:
    lines = _post(make(EVENTS), [
        Operation(operation="A"), ToolChange(tool_number=1), RapidMove(x=0, z=5),
        Operation(operation="B"), RapidMove(x=1),
        ToolChange(tool_number=2), RapidMove(x=2),  # no operation record: the move opens one
        ToolChange(tool_number=1), ProgramEnd()])
    assert lines == [
        "(OP A)", "T1 NEXT T2", "G0 X0 Z5",
        "(END OF OPERATION)", "(OP B)", "G0 X1 Z5",
        "(END OF OPERATION)", "T2 NEXT T1", "G0 X2 Z5",
        "(END OF OPERATION)", "T1",  # the last tool change: no next tool
    ]


def test_without_an_operation_end_table_nothing_is_written() -> None:
    text = EVENTS.replace('  operation_end: {blocks: [{items: ["(END OF OPERATION)"]}]}\n', "")
    lines = _post(make(text), [Operation(operation="A"), RapidMove(x=0, z=5), ProgramEnd()])
    assert lines == ["(OP A)", "G0 X0 Z5"]


STRUCTURES = MOVES + """
  dwell:
    blocks:
      - {use: word, with: {letter: "'P'", value: "dwell * 1000"}}
      - {use: word, if: "dwell > 1", with: {letter: "'Q'", value: dwell}}
structures:
  word:
    - items: [{expr: "letter + str(value, 'int')"}]
"""


def test_use_with_parameters_and_a_condition() -> None:
    lines = _post(make(STRUCTURES), [Dwell(dwell=0.5), Dwell(dwell=2)])
    assert lines == ["P500", "P2000", "Q2"]


@pytest.mark.parametrize(("use", "message"), [
    ('{use: word, with: {letter: "\'P\'"}}',
     "post.yaml:18:9: use: word: block 0 items/0/expr as this use: makes it: unknown name "
     "'value'"),
    ('{use: word, with: {letter: "\'P\'", value: dwell, valeu: "1"}}',
     "post.yaml:18:57: structure 'word' does not read 'valeu' (did you mean 'value'?)"),
    ('{use: word, with: {letter: "\'P\'", value: dwell, feed: "1"}}',
     "post.yaml:18:57: structure parameter 'feed' hides the parameter of that name"),
    ('{use: word, if: "dwel > 1", with: {letter: "\'P\'", value: dwell}}',
     "post.yaml:18:26: bad expression: unknown name 'dwel'; did you mean 'dwell'?"),
    ('{use: word, with: {letter: "\'P\' +", value: dwell}}',
     "post.yaml:18:42: bad expression: unexpected end of expression"),
])
def test_use_misuse_is_located(use: str, message: str) -> None:
    text = STRUCTURES.replace(
        '{use: word, with: {letter: "\'P\'", value: "dwell * 1000"}}', use)
    assert load_errors(text) == [message]  # once, where it is written


def test_nested_structures_pass_their_parameters_on() -> None:
    text = STRUCTURES.replace("""  word:
    - items: [{expr: "letter + str(value, 'int')"}]""", """  word:
    - {use: spaced, with: {text: "letter + str(value, 'int')"}}
  spaced:
    - items: [" ", {expr: text}, " "]""")
    assert _post(make(text), [Dwell(dwell=2)]) == [" P2000 ", " Q2 "]


def test_a_structure_loop_through_another_is_located() -> None:
    text = STRUCTURES.replace("""  word:
    - items: [{expr: "letter + str(value, 'int')"}]""", """  word:
    - {use: other}
  other:
    - {use: word}""")
    errors = load_errors(text)
    assert any("structure loop: word -> other -> word" in error for error in errors), errors


def test_the_readme_q_line_structure_writes_heidenhain_cycle_parameters() -> None:
    text = BASE.replace("  int: {integer: true}", "  int: {integer: true}\n"
                        "  signed: {decimals: 3, trailing_zeros: false, sign: always}") + """
structures:
  q_line:
    - items: [{expr: "'Q' + str(q, 'int') + '=' + str(value, 'signed') + ' ;' + label"}]
commands:
  program_start: {blocks: []}
  program_end: {blocks: []}
  rapid_move: {blocks: [{items: ["L"]}]}
  deep_drill:
    blocks:
      - {use: q_line, with: {q: "200", value: clearance, label: "'SET-UP CLEARANCE'"}}
      - {use: q_line, if: "peck > 0", with: {q: "202", value: peck, label: "'PLUNGING DEPTH'"}}
  single_peck:
    blocks:
      - {use: q_line, with: {q: "200", value: clearance, label: "'SET-UP CLEARANCE'"}}
"""
    post = api.load_post_text(text, "post.yaml")
    lines = _post(post, [RapidMove(x=0, y=0, z=10),
                         DeepDrill(top=0, depth=10, clearance=2, peck=2.5, feed=100),
                         SinglePeck(top=0, depth=10, clearance=2, feed=100)])
    assert lines == ["L", "Q200=+2 ;SET-UP CLEARANCE", "Q202=+2.5 ;PLUNGING DEPTH",
                     "Q200=+2 ;SET-UP CLEARANCE"]


def test_str_writes_with_the_format_the_options_make() -> None:
    text = """
postdsl: 1
machine: {name: Test mill, tool_changer: false}
output: {block_numbers: {default: false}}
options:
  precision: {type: int, default: 3, description: decimals of a coordinate}
formats:
  coord: {decimals: {option: precision}}
commands:
  program_start: {blocks: []}
  program_end: {blocks: []}
  rapid_move: {blocks: [{items: [{expr: "'G0 X' + str(x, 'coord')"}]}]}
"""
    for options, expected in ((None, "G0 X1.250"), ({"precision": "1"}, "G0 X1.3")):
        post = api.load_post_text(text, "post.yaml", options)
        assert _post(post, [RapidMove(x=1.25, y=0, z=0)]) == [expected]
