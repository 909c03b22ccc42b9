"""NC that used to come out wrong (issue 9), each case as a machinist would catch it.

Every test here posts a CL program that a bundled post, or the engine, turned into
an NC program that runs wrong on the control: a Z-only block inside a canned cycle
(another hole), a modal cycle call left open over a move (the hole drilled twice),
a hole drilled with the previous hole's depth, a CL value dropped without a word,
the first moves after a tool change without Z and F, a 0.0002 mm arc run as a
full circle, a cycle returning to another height than the engine assumed, cutting
with the spindle stopped, and a block of fixed text that moved the tool dropped.
"""

from __future__ import annotations

import functools
import json
import re
from datetime import UTC, datetime

import pytest

from postdsl import api
from postdsl.cl.model import (
    COMMANDS,
    DRILL_SETUPS,
    ArcMove,
    CoolantOn,
    CycleEnd,
    CycleHole,
    CycleStart,
    LinearMove,
    RapidMove,
    SpindleOff,
    SpindleOn,
    ToolChange,
)
from postdsl.errors import CLError, PostError
from tests.conftest import EXAMPLES, ROOT

NOW = datetime(2024, 3, 5, 7, 8, 9, tzinfo=UTC)
MACHINES = ("vmc500", "emco", "feeler")


@functools.cache
def bundled(machine: str) -> api.CompiledPost:
    return api.load_post(machine)


def nc(machine: str | api.CompiledPost, records: list) -> list[str]:
    """The program body (the header's computed extents and times left out)."""
    post = bundled(machine) if isinstance(machine, str) else machine
    return [line.text for line in api.post_commands(post, records, now=NOW)
            if line.command != "program_start"]


def nc_cl(machine: str, text: str) -> list[str]:
    return nc(machine, api.read_cl_text(text, "job.jsonl"))


def jsonl(*records: dict) -> str:
    """Native CL text of a whole program, one record a line, ending with program_end."""
    if not records or records[-1] != {"cmd": "program_end"}:
        records = (*records, {"cmd": "program_end"})
    return "".join(json.dumps(record) + "\n" for record in records)


def body(line: str) -> str:
    """A block without its number and the spaces around it."""
    return re.sub(r"^N\d+", "", line).strip()


TOOL = [ToolChange(tool_number=1, line=1), SpindleOn(spindle_speed=1000, line=2)]

# --- 1. a move inside a canned cycle ------------------------------------------------------


def g82_then_up() -> list:
    return [*TOOL, RapidMove(x=40, y=20, z=80, line=3), CycleStart(line=4),
            COMMANDS["single_peck"](x=40, y=20, top=70, depth=50, clearance=5,
                                         dwell=0.5, feed=200, line=5),
            RapidMove(z=80, line=6)]


def test_a_rapid_inside_a_fanuc_cycle_writes_g0_so_it_is_not_another_hole() -> None:
    lines = nc("feeler", [*g82_then_up(), CycleEnd(line=7)])
    g82 = next(i for i, line in enumerate(lines) if " G82 " in line)
    # was "N120 Z80." -- on a Fanuc a Z-only block in G82 mode drills another hole
    assert body(lines[g82 + 1]) == "G0 Z80."
    assert body(lines[g82 + 2]) == "G80 G94"


def test_a_hole_after_a_move_that_ended_the_cycle_is_a_new_cycle() -> None:
    lines = nc("feeler", [*g82_then_up(), CycleHole(x=60, line=7), CycleEnd(line=8)])
    g0 = lines.index(next(line for line in lines if body(line) == "G0 Z80."))
    # the G0 cancelled G82: the next hole must carry the whole cycle again
    assert body(lines[g0 + 1]) == "G99 G82 X60. Y20. Z20. R75. P500 F0.2"


def test_the_emco_closes_the_modal_call_before_a_move() -> None:
    lines = [body(line) for line in nc("emco", [*g82_then_up(), CycleEnd(line=7)])]
    call = next(i for i, line in enumerate(lines) if line.startswith("MCALL CYCLE82("))
    # was: the Z80 move inside the modal call (Sinumerik drills after every motion block)
    assert lines[call + 1:call + 4] == ["X40.000 Y20.000", "MCALL", "Z80.000"]
    assert lines.count("MCALL") == 1  # cycle_end has nothing left to close


def test_no_motion_block_inside_an_open_modal_call() -> None:
    """Read every EMCO corpus program: between MCALL CYCLE and MCALL only hole positions."""
    for example in ("emco_drilling.jsonl", "emco_pocket.gcode", "vmc500_cycles.jsonl",
                    "feeler_drilling.apt"):
        open_call = False
        for line in nc("emco", api.read_cl(EXAMPLES / example)):
            text = body(line)
            if text.startswith("MCALL CYCLE"):
                open_call = True
            elif text == "MCALL":
                open_call = False
            elif open_call:
                assert text.replace("G0", "").split()[0][0] in "XY" and "Z" not in text, \
                    f"{example}: {line} inside an open MCALL"


MOTION_AS_PLAIN_TEXT = """
postdsl: 1
machine: {name: Test mill}
formats: {c: {decimals: 3, trailing_zeros: false, point: always}}
output: {block_numbers: {default: false}}
commands:
  program_start: {blocks: []}
  program_end: {blocks: []}
  tool_change: {reset: [x, y, z, feed], blocks: [{items: ["T1 M6"]}]}
  spindle_on: {blocks: [{items: ["M3"]}]}
  rapid_move:
    blocks:
      - items: [" G0", {param: z, prefix: " Z", format: c, mode: changed}]
  cycle_start: {blocks: []}
  single_peck:
    blocks:
      - items: [" G81", {param: bottom, prefix: " Z", format: c},
                {param: feed, prefix: " F", format: c}]
  cycle_hole: {blocks: [{items: [{param: x, prefix: " X", format: c}]}]}
  cycle_end: {blocks: [{items: [" G80"]}]}
"""


def test_a_move_in_an_open_cycle_that_writes_no_motion_word_is_refused() -> None:
    post = api.load_post_text(MOTION_AS_PLAIN_TEXT, "plain.yaml")
    with pytest.raises(CLError, match=r"job:6: rapid_move inside an open drilling cycle: "
                                      r"the post's table writes no motion word"):
        api.post_commands(post, g82_then_up(), cl_file="job", now=NOW)


def test_the_same_move_with_its_motion_word_named_posts() -> None:
    text = MOTION_AS_PLAIN_TEXT.replace('[" G0", {param: z', '[{text: " G0", modal: motion}, '
                                        '{param: z')
    post = api.load_post_text(text, "named.yaml")
    lines = [line.text for line in api.post_commands(post, [*g82_then_up(), CycleEnd()],
                                                     now=NOW)]
    assert lines[-2:] == [" G0 Z80.", " G80"]


def test_a_feed_move_inside_a_fanuc_cycle_feeds_per_minute_and_ends_the_cycle() -> None:
    records = [*g82_then_up()[:-1], LinearMove(z=90, feed=500, line=6),
               CycleHole(x=60, line=7), CycleEnd(line=8)]
    lines = [body(line) for line in nc("feeler", records)]
    g82 = next(i for i, line in enumerate(lines) if " G82 " in line)
    # G95 is active for the cycle: F500 would be 500 mm per revolution without G94
    assert lines[g82 + 1:g82 + 3] == ["G94 G1 Z90. F500", "G95 G99 G82 X60. Y20. Z20. R75. "
                                                            "P500 F0.2"]


def test_a_forced_motion_word_counts_as_written() -> None:
    text = MOTION_AS_PLAIN_TEXT.replace('[" G0", {param: z', '[{text: " G0", modal: motion, '
                                        'mode: forced}, {param: z')
    post = api.load_post_text(text, "forced.yaml")
    lines = [line.text for line in api.post_commands(post, [*g82_then_up(), CycleEnd()],
                                                     now=NOW)]
    assert lines[-2:] == [" G0 Z80.", " G80"]


# --- 3. a hole whose top differs from the cycle's ------------------------------------------


def two_tops() -> list:
    return [*TOOL, RapidMove(x=10, y=10, z=50, line=3), CycleStart(line=4),
            COMMANDS["single_peck"](x=10, y=10, top=0, depth=10, clearance=2,
                                         feed=200, line=5),
            CycleHole(x=30, y=10, line=6), CycleHole(x=50, y=10, top=-5, line=7),
            CycleEnd(line=8)]


def test_the_vmc500_drills_a_lower_hole_with_its_own_r_and_depth() -> None:
    lines = [body(line) for line in nc("vmc500", two_tops())]
    # was " X50." alone: the Acramatic drilled it from R0 to Z10 -- 5 mm too shallow
    assert "G82 X50. Y10. Z10.0 R-5.0 F200.0" in lines
    assert "X50." not in lines


def test_the_emco_drills_a_lower_hole_with_a_new_modal_call() -> None:
    lines = [body(line) for line in nc("emco", two_tops())]
    hole = lines.index("X50.000 Y10.000")
    assert lines[hole - 2:hole] == ["MCALL", "MCALL CYCLE81(-3.000, -5.000, 2.000, -15.000)"]


def test_the_feeler_writes_r_and_z_on_the_lower_hole() -> None:
    lines = [body(line) for line in nc("feeler", two_tops())]
    assert "X50. Z-15. R-3." in lines


XY_ONLY_HOLES = MOTION_AS_PLAIN_TEXT.replace('" G0", {param: z', '{text: " G0", modal: motion}, '
                                             '{param: z')


def test_a_hole_table_that_writes_no_depth_is_refused_when_the_top_changes() -> None:
    post = api.load_post_text(XY_ONLY_HOLES, "xy.yaml")
    with pytest.raises(CLError, match=r"job:7: cycle_hole: this hole's top is -5 \(bottom -15,"
                                      r" retract -3\), not the previous hole's, but the post's "
                                      r"table 'cycle_hole' writes neither top"):
        api.post_commands(post, two_tops(), cl_file="job", now=NOW)


def test_new_cycle_if_belongs_to_cycle_hole_only() -> None:
    text = XY_ONLY_HOLES.replace("  single_peck:\n", "  single_peck:\n    new_cycle_if: "
                                 "\"changed(top)\"\n")
    with pytest.raises(PostError, match=r"xy.yaml:\d+:\d+: new_cycle_if applies to cycle_hole "
                                        r"only"):
        api.load_post_text(text, "xy.yaml")


# --- 4. no CL value dropped -----------------------------------------------------------------


def test_the_feeler_refuses_a_pecked_left_hand_rigid_tap() -> None:
    with pytest.raises(CLError, match=r":4: rigid_tapping_ccw: peck rigid tapping"):
        nc_cl("feeler", jsonl(
            {"cmd": "tool_change", "tool_number": 8},
            {"cmd": "spindle_on", "spindle_speed": 600, "spindle": "ccw"},
            {"cmd": "rapid_move", "x": 25, "y": 20, "z": 20},
            {"cmd": "rigid_tapping_ccw", "x": 25, "y": 20, "top": 0, "depth": 12,
             "clearance": 2, "peck": 4, "feed": 750}))


def test_the_feeler_writes_g73_without_p_and_refuses_its_dwell() -> None:
    def chip(**dwell: float) -> str:
        return jsonl({"cmd": "tool_change", "tool_number": 3},
                     {"cmd": "spindle_on", "spindle_speed": 1500},
                     {"cmd": "rapid_move", "x": 40, "y": 30, "z": 20},
                     {"cmd": "break_chip", "x": 40, "y": 30, "top": 0, "depth": 18,
                      "clearance": 1.5, "peck": 3, "feed": 100, **dwell},
                     {"cmd": "cycle_end"})

    [g73] = [line for line in nc_cl("feeler", chip()) if " G73 " in line]
    assert " P" not in g73 and g73.endswith(" G73 X40. Y30. Z-18. R1.5 Q3. F0.0667")
    with pytest.raises(CLError, match=r":4: break_chip: the Fanuc 0i's G73 has no "
                                      r"dwell"):
        nc_cl("feeler", chip(dwell=0.2))


@pytest.mark.parametrize("machine", ["vmc500", "feeler"])
@pytest.mark.parametrize(("setup", "spindle"), [("tapping", "ccw"), ("rigid_tapping", "ccw"),
                                                ("tapping_ccw", "cw"),
                                                ("rigid_tapping_ccw", "cw")])
def test_a_tap_against_the_spindle_direction_is_refused(machine: str, setup: str,
                                                        spindle: str) -> None:
    """These controls tap the way the spindle turns: a left-hand tap in M3 cuts right-hand."""
    records = hole_program(setup)
    records[1] = SpindleOn(spindle_speed=500, spindle=spindle, line=2)
    with pytest.raises(CLError, match=rf":5: {setup}: a (right|left)-hand tap needs the "
                                      rf"spindle turning"):
        nc(machine, records)


def hole_program(setup: str, **values: float | None) -> list:
    ccw = setup.endswith("_ccw")
    fields = {"x": 0, "y": 0, "top": 0, "depth": 10, "clearance": 2, "feed": 100}
    fields.update({k: v for k, v in values.items() if v is not None})
    return [ToolChange(tool_number=1, line=1),
            SpindleOn(spindle_speed=500, spindle="ccw" if ccw else "cw", line=2),
            RapidMove(x=0, y=0, z=50, line=3), CycleStart(line=4),
            COMMANDS[setup](**fields, line=5), CycleEnd(line=6), RapidMove(z=50, line=7)]


@pytest.mark.parametrize("machine", MACHINES)
@pytest.mark.parametrize("setup", DRILL_SETUPS)
@pytest.mark.parametrize(("field", "one", "other"), [
    ("peck", 2, 3), ("dwell", 0.5, 0.7), ("retract", 12, 15), ("feed", 100, 150),
])
def test_no_drilling_table_drops_a_cl_value(machine: str, setup: str, field: str, one: float,
                                            other: float) -> None:
    """Two CL holes that differ in one value must give two programs, or a refusal."""
    try:
        first = nc(machine, hole_program(setup, **{field: one}))
        second = nc(machine, hole_program(setup, **{field: other}))
    except CLError as exc:
        assert ":5: " in str(exc) or ":7: " in str(exc), str(exc)  # located at the hole
        return
    assert first != second, f"{machine} {setup}: {field} {one} and {other} give one program"


@pytest.mark.parametrize(("machine", "coolant"), [
    ("vmc500", "mist"), ("vmc500", "through"), ("emco", "through"), ("feeler", "through")])
def test_a_coolant_the_post_has_no_code_for_is_refused_not_written_as_flood(
        machine: str, coolant: str) -> None:
    with pytest.raises(CLError, match=r":3: coolant_on: .*(coolant|spindle)"):
        nc(machine, [*TOOL, CoolantOn(coolant=coolant, line=3)])


# --- 5. after a tool change ----------------------------------------------------------------

JOB_GCODE = """\
(T1: D10 end mill)
M6 T1
M3 S2000
(Pocket)
G0 Z20
G0 X10 Y10
G1 F5 X10 Y10 Z-1
G1 F5 X40 Y10 Z-1
G0 Z20
(T2: D5 drill)
M6 T2
M3 S1800
(Slot)
G0 Z20
G0 X10 Y10
G1 F5 X10 Y10 Z-1
G1 F5 X10 Y40 Z-1
G0 Z20
"""

JOB_DUMP = """\
(Path: T1: D10 end mill)
Command (T1: D10 end mill) [ ]
Command M6 [ T:1 ]
Command M3 [ S:2000 ]
(Path: Pocket)
Command (Pocket) [ ]
Command G0 [ Z:20 ]
Command G0 [ X:10 Y:10 ]
Command G1 [ F:5 X:10 Y:10 Z:-1 ]
Command G1 [ F:5 X:40 Y:10 Z:-1 ]
Command G0 [ Z:20 ]
(Path: T2: D5 drill)
Command (T2: D5 drill) [ ]
Command M6 [ T:2 ]
Command M3 [ S:1800 ]
(Path: Slot)
Command (Slot) [ ]
Command G0 [ Z:20 ]
Command G0 [ X:10 Y:10 ]
Command G1 [ F:5 X:10 Y:10 Z:-1 ]
Command G1 [ F:5 X:10 Y:40 Z:-1 ]
Command G0 [ Z:20 ]
"""


def test_after_a_tool_change_the_emco_writes_z_and_f_again() -> None:
    job = api.read_cl_text(JOB_GCODE, "job.gcode", feed_units="mm/s")
    lines = [body(line) for line in nc("emco", job)]
    change = lines.index("M6 T2")
    # as the thesis listing after every M6: the control's Z and F are not the registers'
    assert lines[change + 3:change + 6] == ["G0 Z20.000", "X10.000 Y10.000",
                                            "G1 Z-1.000 F300"]


@pytest.mark.parametrize("machine", MACHINES)
def test_one_job_as_freecad_gcode_and_as_a_dump_gives_one_program(machine: str) -> None:
    gcode = nc(machine, api.read_cl_text(JOB_GCODE, "job.gcode", feed_units="mm/s"))
    dump = nc(machine, api.read_cl_text(JOB_DUMP, "job.dump.txt"))
    assert gcode == dump


def test_a_tool_change_that_forgets_nothing_is_a_load_error() -> None:
    text = MOTION_AS_PLAIN_TEXT.replace("tool_change: {reset: [x, y, z, feed], ",
                                        "tool_change: {")
    with pytest.raises(PostError, match=r"tool_change: after a tool change the control's axes "
                                        r"and feed are unknown; add reset: \[feed, x, z\]"):
        api.load_post_text(text, "forgets.yaml")


# --- 6. arcs shorter than the output resolution ---------------------------------------------


def arc(end_angle_deg: float, *, ccw: bool = True) -> list:
    import math
    a = math.radians(end_angle_deg)
    return [*TOOL, RapidMove(x=10, y=0, z=0, line=3),
            ArcMove(x=10 * math.cos(a), y=10 * math.sin(a), cx=0, cy=0,
                    arc_direction="ccw" if ccw else "cw", feed=500, line=4)]


@pytest.mark.parametrize("machine", MACHINES)
def test_an_arc_shorter_than_the_resolution_is_not_a_full_circle(machine: str) -> None:
    sweep = 0.0002 / 10 * 180 / 3.141592653589793  # 0.0002 mm of arc
    lines = [body(line) for line in nc(machine, arc(sweep))]
    assert not any(re.search(r"\bG[23]\b", line) for line in lines), lines


@pytest.mark.parametrize("machine", MACHINES)
def test_a_real_full_circle_is_still_one(machine: str) -> None:
    lines = [body(line) for line in nc(machine, arc(0))]
    [circle] = [line for line in lines if re.search(r"\bG3\b", line)]
    assert "I-10." in circle and "J0." in circle


def test_a_short_apt_movarc_is_not_a_full_circle() -> None:
    apt = ("PARTNO/O1 SHORT ARC\nUNITS/MM\nLOADTL/1\nSPINDL/1000,RPM,CLW\nFEDRAT/500\n"
           "GOTO/10,0,0\nMOVARC/0,0,0,0,0,1,10,ANGLE,0.0000114\nEND\nFINI\n")
    lines = nc("feeler", api.read_cl_text(apt, "short.apt"))
    assert not any(re.search(r"\bG[23]\b", line) for line in lines), lines


def test_an_arc_of_almost_a_full_turn_whose_end_is_written_on_its_start_is_refused() -> None:
    with pytest.raises(CLError, match=r":4: arc_move: the arc sweeps 359\.99.* degrees, but the "
                                      r"post writes its end onto its start"):
        nc("feeler", arc(-0.0001))


# --- 7. G98: the cycle returns where the engine says ----------------------------------------


G98_JOB = [
    {"cmd": "tool_change", "tool_number": 2},
    {"cmd": "spindle_on", "spindle_speed": 1000},
    {"cmd": "rapid_move", "x": 0, "y": 0, "z": 10},
    {"cmd": "single_peck", "x": 0, "y": 0, "top": 0, "depth": 5, "clearance": 2,
     "retract": 20, "feed": 100},
    {"cmd": "cycle_hole", "x": 30},
    {"cmd": "cycle_end"},
    {"cmd": "rapid_move", "z": 20},
    {"cmd": "rapid_move", "x": 60},
]


def test_g98_starts_from_the_cl_retract_plane() -> None:
    lines = [body(line) for line in nc_cl("feeler", jsonl(*G98_JOB))]
    g81 = next(i for i, line in enumerate(lines) if " G81 " in line)
    # was: G98 from Z10, so the tool returned to Z10 and travelled there, not at Z20
    # (G0 is still the motion mode: no cycle is open yet)
    assert lines[g81 - 1:g81 + 2] == ["Z20.", "G95 G98 G81 X0. Y0. Z-5. R2. F0.1",
                                      "X30."]


# --- 8. cutting needs a tool, a feed and a turning spindle ----------------------------------


@pytest.mark.parametrize("machine", MACHINES)
@pytest.mark.parametrize(("records", "message"), [
    ([ToolChange(tool_number=1, line=1), SpindleOn(spindle_speed=0, line=2),
      RapidMove(x=0, y=0, z=5, line=3), LinearMove(z=-1, feed=100, line=4)],
     r":4: linear_move: a cutting move with the spindle at 0 rpm"),
    ([ToolChange(tool_number=1, line=1), SpindleOn(spindle_speed=1000, line=2),
      SpindleOff(line=3), RapidMove(x=0, y=0, z=5, line=4),
      LinearMove(z=-1, feed=100, line=5)],
     r":5: linear_move: a cutting move with the spindle stopped"),
    ([ToolChange(tool_number=1, line=1), SpindleOn(spindle_speed=1000, line=2),
      RapidMove(x=0, y=0, z=5, line=3), LinearMove(z=-1, line=4)],
     r":4: linear_move: a cutting move before any feed is known"),
    ([RapidMove(x=0, y=0, z=5, line=1)], r":1: rapid_move before any tool is loaded"),
    ([ToolChange(tool_number=0, line=1)], r":1: tool_change: tool number 0 is not a tool"),
])
def test_what_cutting_needs_is_refused_at_its_cl_line(machine: str, records: list,
                                                      message: str) -> None:
    if machine == "emco" and records[1:2] == [SpindleOn(spindle_speed=0, line=2)]:
        pytest.skip("the EMCO's spindle range (150 rpm up) refuses 0 rpm already")
    with pytest.raises(CLError, match=message):
        nc(machine, records)


def test_a_speed_that_is_written_s0_is_refused() -> None:
    with pytest.raises(CLError, match=r":4: linear_move: a cutting move with the spindle at "
                                      r"0.4 rpm \(written '0'\), set at CL line 2"):
        nc("feeler", [ToolChange(tool_number=1, line=1), SpindleOn(spindle_speed=0.4, line=2),
                      RapidMove(x=0, y=0, z=5, line=3), LinearMove(z=-1, feed=100, line=4)])


def test_a_feed_that_is_written_f0_is_refused() -> None:
    """By the machine's feed range, and where a post declares none, by its format."""
    program = [*TOOL, RapidMove(x=0, y=0, z=5, line=3), LinearMove(z=-1, feed=0.01, line=4)]
    with pytest.raises(CLError, match=r":4: feed 0.01 mm/min is below the minimum feed"):
        nc("feeler", program)
    text = (ROOT / "machines" / "feeler.yaml").read_text(encoding="utf-8")
    without_range = re.sub(r"(?m)^  min_feed: .*\n", "", text)
    assert without_range != text
    with pytest.raises(CLError, match=r":4: linear_move: post table 'linear_move' cannot be "
                                      r"written: parameter 'feed' is 0.01, which the format "
                                      r"writes as '0': a feed of zero"):
        nc(api.load_post_text(without_range, "feeler.yaml"), program)


ROUTER = """
postdsl: 1
machine: {name: Router, tool_changer: false, tools: {min_number: 0}}
formats: {c: {decimals: 3}, int: {integer: true}}
output: {block_numbers: {default: false}}
commands:
  program_start: {blocks: []}
  program_end: {blocks: []}
  tool_change: {reset: [x, y, z], blocks: [{items: ["T", {param: tool_number, format: int}]}]}
  rapid_move:
    blocks:
      - items: ["G0", {param: x, prefix: " X", format: c}, {param: z, prefix: " Z", format: c}]
      - if: "first_move"
        items: ["G43 H", {param: tool_number, format: int}]
"""


def test_a_machine_without_a_tool_changer_moves_without_a_tool_change() -> None:
    post = api.load_post_text(ROUTER.replace('      - if: "first_move"\n'
                                             '        items: ["G43 H", {param: tool_number, '
                                             'format: int}]\n', ""), "router.yaml")
    assert nc(post, [RapidMove(x=1, z=5)]) == ["G0 X1.000 Z5.000"]
    assert nc(post, [ToolChange(tool_number=0), RapidMove(x=1, z=5)]) == [
        "T0", "G0 X1.000 Z5.000"]  # tool 0 is real where the post declares it


def test_a_tool_length_offset_with_no_tool_is_refused() -> None:
    post = api.load_post_text(ROUTER, "router.yaml")
    with pytest.raises(CLError, match=r":1: rapid_move: post table 'rapid_move' cannot be "
                                      r"written: the block writes the tool number"):
        nc(post, [RapidMove(x=1, z=5, line=1)])


# --- 9. a block of fixed text that moves the tool -------------------------------------------

TEXT_MOVE = """
postdsl: 1
machine: {name: Test mill, tool_changer: false}
formats: {c: {decimals: 3, sign: always}}
output: {block_numbers: {default: false}}
commands:
  program_start: {blocks: []}
  program_end: {blocks: []}
  rapid_move:
    blocks:
      - only_with_values: true
        items:
          - "L"
          - {param: x, prefix: " X", format: c, mode: changed}
          - {param: z, prefix: " Z", format: c, mode: changed, if: "z != 0"}
          - {text: " Z+0", modal: z, mode: changed, if: "z == 0"}
          - " FMAX"
"""


def test_fixed_text_that_moves_the_tool_is_not_dropped() -> None:
    post = api.load_post_text(TEXT_MOVE, "text.yaml")
    lines = nc(post, [RapidMove(x=5, z=4), RapidMove(z=0), RapidMove(z=0)])
    # was ["L X+5.000 Z+4.000 FMAX"]: the move to Z0 vanished
    assert lines == ["L X+5.000 Z+4.000 FMAX", "L Z+0 FMAX"]
