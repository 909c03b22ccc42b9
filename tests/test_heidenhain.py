"""The HEIDENHAIN TNC 640 post (machines/heidenhain.yaml) and its Klartext control model.

The model is tested on hand-written Klartext against a small CL program: the right
program verifies, and each wrong one -- an arc the wrong way, a positive depth, a
hole without its M99, a block number out of step -- is flagged.  The post's corpus
snapshots are verified in tests/test_snapshots.py; here the rules its header
promises are checked on small programs.
"""

from __future__ import annotations

import json
import re

import pytest

from postdsl import api
from postdsl.check.controls import ControlError, control_model
from postdsl.check.controls.events import ArcMove, Dwell, FeedMove, Hole, Rapid
from postdsl.check.motion import cl_events
from postdsl.check.verify import first_divergence
from postdsl.cl.readers import read_cl_text
from tests.conftest import ROOT, THESIS_TIME, compiled_post

MODEL = "heidenhain-tnc640"

#: a plate: a line, a counter-clockwise arc, a helix, a dwell and two drilled holes
CL = [
    {"cmd": "program_start", "program_name": "PLATE"},
    {"cmd": "tool_change", "tool_number": 5, "tool_diameter": 10},
    {"cmd": "spindle_on", "spindle_speed": 3000, "spindle": "cw"},
    {"cmd": "rapid_move", "x": 0, "y": 0},
    {"cmd": "rapid_move", "z": 5},
    {"cmd": "linear_move", "z": -2, "feed": 100},
    {"cmd": "linear_move", "x": 10, "feed": 500},
    {"cmd": "arc_move", "x": 20, "y": 10, "cx": 10, "cy": 10, "arc_direction": "ccw"},
    {"cmd": "arc_move", "x": 20, "y": 10, "z": -4, "cx": 10, "cy": 10, "arc_direction": "cw"},
    {"cmd": "dwell", "dwell": 0.5},
    {"cmd": "rapid_move", "z": 20},
    {"cmd": "single_peck", "x": 30, "y": 30, "top": 0, "depth": 10, "clearance": 2,
     "retract": 20, "feed": 150},
    {"cmd": "cycle_hole", "x": 50, "y": 30},
    {"cmd": "cycle_end"},
    {"cmd": "program_end"},
]

NC = """\
0 BEGIN PGM PLATE MM
1 TOOL CALL 5 Z S3000
2 M3
3 L X+0 Y+0 R0 FMAX
4 L Z+5 R0 FMAX
5 L Z-2 R0 F100
6 L X+10 R0 F500
7 CC X+10 Y+10
8 C X+20 Y+10 DR+ R0
9 CP IPA-360 IZ-2 DR- R0
10 CYCL DEF 9.0 DWELL TIME
11 CYCL DEF 9.1 DWELL 0.5
12 L Z+20 R0 FMAX
13 CYCL DEF 200 DRILLING ~
  Q200=+2 ;SET-UP CLEARANCE ~
  Q201=-10 ;DEPTH ~
  Q206=+150 ;FEED RATE FOR PLNGNG ~
  Q202=+10 ;PLUNGING DEPTH ~
  Q210=+0 ;DWELL TIME AT TOP ~
  Q203=+0 ;SURFACE COORDINATE ~
  Q204=+20 ;2ND SET-UP CLEARANCE ~
  Q211=+0 ;DWELL TIME AT DEPTH
14 L X+30 Y+30 R0 FMAX M99
15 L X+50 Y+30 R0 FMAX M99
16 M5
17 M30
18 END PGM PLATE MM
"""


def _cl_text(records: list[dict]) -> str:
    return "\n".join(json.dumps(record) for record in records) + "\n"


def _divergence(nc: str, records: list[dict] | None = None) -> str | None:
    commands = read_cl_text(_cl_text(records or CL), fmt="native")
    return first_divergence(control_model(MODEL).replay(nc.splitlines()),
                            cl_events(commands, "<cl>"), 0.001)


def _events(nc: str) -> list:
    return list(control_model(MODEL).replay(nc.splitlines()))


def test_the_right_program_does_what_the_cl_says() -> None:
    assert _divergence(NC) is None


def test_the_model_reads_lines_arcs_helices_dwells_and_holes() -> None:
    events = _events(NC)
    feeds = [e for e in events if isinstance(e, FeedMove)]
    assert [(e.end, e.feed) for e in feeds] == [((0, 0, -2), 100), ((10, 0, -2), 500)]
    arc, helix = [e for e in events if isinstance(e, ArcMove)]
    assert (arc.clockwise, arc.centre, arc.end) == (False, (10, 10, -2), (20, 10, -2))
    assert arc.feed == 500                       # F stays in force after FMAX and CC
    assert helix.clockwise and helix.sweep == pytest.approx(2 * 3.141592653589793)
    assert helix.end == pytest.approx((20, 10, -4))
    assert [e.seconds for e in events if isinstance(e, Dwell)] == [0.5]
    holes = [e for e in events if isinstance(e, Hole)]
    assert [(h.x, h.y, h.r, h.bottom, h.leave, h.kind, h.feed) for h in holes] == [
        (30, 30, 2, -10, 20, "drill", 150), (50, 30, 2, -10, 20, "drill", 150)]


def test_fmax_acts_in_its_block_only() -> None:
    events = _events(NC)
    rapids = [e for e in events if isinstance(e, Rapid) and e.origin.line in (4, 5, 13)]
    assert [e.end[:2] for e in rapids[:2]] == [(0, 0), (0, 0)]
    assert [e.end[2] for e in rapids[:2]] == [None, 5]     # X Y at the height after TOOL CALL
    assert rapids[2].end == pytest.approx((20, 10, 20))   # after the helix's computed end


@pytest.mark.parametrize(("wrong", "right", "found"), [
    ("8 C X+20 Y+10 DR- R0", "8 C X+20 Y+10 DR+ R0", "arc clockwise, CL says counter-clockwise"),
    ("9 CP IPA+360 IZ-2 DR+ R0", "9 CP IPA-360 IZ-2 DR- R0",
     "arc counter-clockwise, CL says clockwise"),
    ("9 CP IPA-360 IZ-2 DR+ R0", "9 CP IPA-360 IZ-2 DR- R0", "the angle's sign is the direction's"),
    ("  Q201=+10 ;DEPTH ~", "  Q201=-10 ;DEPTH ~", "Q201 depth +10 is not negative"),
    ("  Q202=+4 ;PLUNGING DEPTH ~", "  Q202=+10 ;PLUNGING DEPTH ~",
     "peck4.000, CL says peck0.000"),
    ("  Q204=+0 ;2ND SET-UP CLEARANCE ~", "  Q204=+20 ;2ND SET-UP CLEARANCE ~",
     "below the CL's retract"),
    ("15 L X+50 Y+30 R0 FMAX", "15 L X+50 Y+30 R0 FMAX M99", "the NC program ends, the CL "
                                                            "still has a hole"),
    ("11 CYCL DEF 9.1 DWELL 0.2", "11 CYCL DEF 9.1 DWELL 0.5", "dwell 0.2 s, CL says 0.5 s"),
    ("6 L X+10 R0", "6 L X+10 R0 F500", "feed 100.000 mm/min, CL says 500"),
    # RL stays in force: the circle's R0 would end it there, which a TNC refuses
    ("6 L X+10 RL F500", "6 L X+10 R0 F500", "R0 on a circle: radius compensation starts "
                                             "and ends on a straight line L"),
    ("7 L X+10 Y+10", "7 CC X+10 Y+10", "a feed move to X10.000 Y10.000"),
    ("13 L Z+20 R0 FMAX", "12 L Z+20 R0 FMAX", "block number 13, the TNC's next is 12"),
    ("18 END PGM PLAT MM", "18 END PGM PLATE MM", "does not close BEGIN PGM PLATE MM"),
    ("1 TOOL CALL 5 Z S2000", "1 TOOL CALL 5 Z S3000", "spindle 2000 rpm, CL says 3000"),
    ("1 TOOL CALL 4 Z S3000", "1 TOOL CALL 5 Z S3000", "with tool 4, CL says tool 5"),
    ("2 M4", "2 M3", "spindle ccw, CL says cw"),
])
def test_a_wrong_program_is_flagged(wrong: str, right: str, found: str) -> None:
    assert right in NC
    divergence = _divergence(NC.replace(right, wrong, 1))
    assert divergence is not None and found in divergence, divergence


@pytest.mark.parametrize(("program", "message"), [
    ("L X+0 R0 FMAX", "a block without its number"),
    ("1 BEGIN PGM A MM", "block number 1, the TNC's next is 0"),
    ("0 BEGIN PGM A MM\n1 L X+0 Y+0 R0 FMAX\n2 L X+5 R0", "a feed move before any F"),
    ("0 BEGIN PGM A MM\n1 TOOL CALL 1 Z S100\n2 L X+0 Y+0 Z+0 R0 FMAX\n3 C X+1 Y+0 DR+ F9",
     "C before any CC"),
    ("0 BEGIN PGM A MM\n1 L X+0 Y+0 R0 FMAX M99", "M99) without a CYCL DEF"),
    ("0 BEGIN PGM A MM\n1 CYCL DEF 200 DRILLING ~\n  Q200=+2 ;SET-UP CLEARANCE",
     "CYCL DEF 200 without Q201"),
    ("0 BEGIN PGM A MM\n1 CYCL DEF 204 BACK BORING", "cycle 204 is not one"),
    ("0 BEGIN PGM A MM\n1 CYCL DEF 202 BORING ~\n  Q200=+3 ~\n  Q201=-15 ~\n  Q206=+60 ~\n"
     "  Q211=+0 ~\n  Q208=+0 ~\n  Q203=+0 ~\n  Q204=+30 ~\n  Q214=+0 ~\n  Q336=+0\n"
     "2 L X+0 Y+0 R0 FMAX M99", "cycle 202: Q214=0 -- 0 leaves the tool's edge on the wall"),
    ("0 BEGIN PGM A MM\n1 TCH PROBE 419 DATUM IN ONE AXIS", "the post must declare it"),
    ("0 BEGIN PGM A MM\n1 CYCL DEF 9.1 DWELL 1", "right after 9.0 DWELL TIME"),
    ("0 BEGIN PGM A MM\n1 M30\n2 L X+0 R0 FMAX", "a block after M30"),
    ("0 BEGIN PGM A MM\n1 M30", "does not end with END PGM"),
    ("0 BEGIN PGM A INCH\n1 M30\n2 END PGM A MM", "END PGM A MM does not close BEGIN PGM A INCH"),
    ("0 BEGIN PGM A MM\n1 TOOL CALL 1 X S100", "tool axis X"),
])
def test_the_model_refuses_what_it_cannot_follow(program: str, message: str) -> None:
    with pytest.raises(ControlError, match=message.replace("(", r"\(").replace(")", r"\)")):
        _events(program)


def test_cycle_203_with_a_break_before_every_infeed_is_chip_breaking() -> None:
    program = NC.replace("13 CYCL DEF 200 DRILLING ~", "13 CYCL DEF 203 UNIVERSAL DRILLING ~")
    program = program.replace("  Q211=+0 ;DWELL TIME AT DEPTH\n", "  Q212=+0 ;DECREMENT ~\n"
                              "  Q213=+3 ;NR OF BREAKS ~\n  Q205=+0 ;MIN. PLUNGING DEPTH ~\n"
                              "  Q211=+0 ;DWELL TIME AT DEPTH ~\n"
                              "  Q208=+0 ;RETRACTION FEED RATE ~\n"
                              "  Q256=+0.2 ;DIST FOR CHIP BRKNG\n")
    program = program.replace("  Q202=+10 ;PLUNGING DEPTH", "  Q202=+4 ;PLUNGING DEPTH")
    holes = [e for e in _events(program) if isinstance(e, Hole)]
    assert [(h.kind, h.peck) for h in holes] == [("chip_break", 4)] * 2
    with pytest.raises(ControlError, match="1 chip breaks, then a retract"):
        _events(program.replace("Q213=+3", "Q213=+1"))


def test_rigid_tapping_feeds_the_pitch_times_the_speed() -> None:
    program = ("0 BEGIN PGM T MM\n1 TOOL CALL 7 Z S400\n2 L X+0 Y+0 R0 FMAX\n3 L Z+30 R0 FMAX\n"
               "4 CYCL DEF 207 RIGID TAPPING ~\n  Q200=+5 ;SET-UP CLEARANCE ~\n"
               "  Q201=-12 ;DEPTH OF THREAD ~\n  Q239=-1.25 ;THREAD PITCH ~\n"
               "  Q203=+0 ;SURFACE COORDINATE ~\n  Q204=+30 ;2ND SET-UP CLEARANCE\n"
               "5 L X+10 Y+10 R0 FMAX M99\n6 END PGM T MM")
    hole, = [e for e in _events(program) if isinstance(e, Hole)]
    assert (hole.kind, hole.direction, hole.feed, hole.bottom) == ("rigid_tap", "ccw", 500, -12)


# --- the post --------------------------------------------------------------------------------

def _post(records: list[dict]) -> list[str]:
    return [line.text for line in api.post_commands(
        compiled_post(ROOT / "machines" / "heidenhain.yaml"),
        read_cl_text(_cl_text(records), fmt="native"), now=THESIS_TIME)]


def test_the_post_writes_the_hand_written_program_and_it_verifies() -> None:
    lines = _post(CL)
    assert lines[0] == "0 BEGIN PGM PLATE MM" and lines[-1].endswith(" END PGM PLATE MM")
    assert [line.split(" ", 1)[0] for line in lines if not line.startswith(" ")] == \
        [str(n) for n in range(len([line for line in lines if not line.startswith(" ")]))]
    for expected in ("TOOL CALL 5 Z S3000", "C X+20 Y+10 DR+ R0", "CP IPA-360 IZ-2 DR- R0",
                     "CYCL DEF 9.1 DWELL 0.5", "CYCL DEF 200 DRILLING ~",
                     "L X+50 Y+30 R0 FMAX M99"):
        assert any(line.split(" ", 1)[1] == expected for line in lines if line[0] != " "), expected
    verdict = api.verify_commands(compiled_post(ROOT / "machines" / "heidenhain.yaml"),
                                  read_cl_text(_cl_text(CL), fmt="native"), now=THESIS_TIME)
    assert verdict.ok and verdict.holes == 2


def test_a_new_speed_for_the_same_tool_is_a_tool_call_without_a_number() -> None:
    records = CL[:7] + [{"cmd": "spindle_on", "spindle_speed": 4000, "spindle": "cw"}] + CL[7:]
    lines = [line.split(" ", 1)[1] for line in _post(records) if line[0] != " "]
    assert lines.count("TOOL CALL Z S4000") == 1 and lines.count("TOOL CALL 5 Z S3000") == 1


@pytest.mark.parametrize(("change", "reason"), [
    ({"cmd": "coolant_on", "coolant": "mist"}, "mist coolant has no standard TNC 640 M"),
    ({"cmd": "arc_move", "x": 24, "y": 12, "z": 0, "cx": 20, "cz": 0, "plane": "zx",
      "arc_direction": "cw"}, "a helix in the ZX plane"),
    ({"cmd": "arc_move", "x": 21, "y": 14, "z": 0, "cy": 10, "cz": 0, "plane": "yz",
      "arc_direction": "cw"}, "a helix in the YZ plane"),
    ({"cmd": "rigid_tapping", "x": 1, "y": 1, "top": 0, "depth": 5, "clearance": 2,
      "retract": 20, "dwell": 0.5, "feed": 500}, "207 and 209 (rigid tapping) have no dwell"),
    ({"cmd": "tapping", "x": 1, "y": 1, "top": 0, "depth": 5, "clearance": 2,
      "retract": 20, "peck": 2, "feed": 500}, "206 (tapping with a floating holder) has no peck"),
    ({"cmd": "rigid_tapping", "x": 1, "y": 1, "top": 0, "depth": 5, "clearance": 2,
      "retract": 20, "feed": 1357.95}, "does not give the CL's feed"),
])
def test_the_post_refuses_what_it_cannot_write(change: dict, reason: str) -> None:
    records = CL[:10] + [change] + CL[-1:]
    if change.get("feed") == 1357.95:
        # pitch 0.12345 at 11000 rpm: 4 decimals make it 0.1234 or 0.1235, 0.55 mm/min off
        records[2] = {"cmd": "spindle_on", "spindle_speed": 11000, "spindle": "cw"}
    with pytest.raises(api.CLError, match=reason.replace("(", r"\(").replace(")", r"\)")):
        _post(records)


@pytest.mark.parametrize("change", [
    {"cmd": "single_peck", "x": 1, "y": 1, "top": 0, "depth": 5, "clearance": 2,
     "retract": 1, "feed": 500},
    {"cmd": "deep_drill", "x": 1, "y": 1, "top": 0, "depth": 12, "clearance": 2,
     "retract": 20, "first_peck": 5, "peck": 2, "feed": 500},
    {"cmd": "break_chip", "x": 1, "y": 1, "top": 0, "depth": 12, "clearance": 2,
     "retract": 20, "first_peck": 5, "peck": 2, "feed": 500},
])
def test_holes_no_cycle_can_write_are_drilled_as_moves(change: dict) -> None:
    """A retract below Q200, or a first peck other than Q202: no CYCL DEF, the holes as L moves."""
    records = CL[:10] + [change] + CL[-1:]
    text = "\n".join(_post(records))
    assert "CYCL DEF 20" not in text and "M99" not in text
    assert " L Z-5 R0" in text or " L Z-12 R0" in text
    verdict = api.verify_commands(compiled_post(ROOT / "machines" / "heidenhain.yaml"),
                                  read_cl_text(_cl_text(records), fmt="native"), now=THESIS_TIME)
    assert verdict.ok, str(verdict.divergence)
    assert verdict.holes == 0 and verdict.cuts > 4  # the hole's plunges, as cuts


#: after the helix (X20 Y10 Z-4): three quarters in ZX, counter-clockwise (Z towards X),
#: then a half circle in YZ, clockwise
ARCS_OUT_OF_XY = [
    {"cmd": "arc_move", "x": 24, "z": 0, "cx": 20, "cz": 0, "plane": "zx",
     "arc_direction": "ccw"},
    {"cmd": "arc_move", "y": 14, "z": 4, "cy": 10, "cz": 4, "plane": "yz",
     "arc_direction": "cw"},
]


def test_arcs_in_the_zx_and_yz_planes_are_cc_and_c_in_their_axes_and_verify() -> None:
    records = CL[:10] + ARCS_OUT_OF_XY + CL[-1:]
    blocks = [line.split(" ", 1)[1] for line in _post(records) if line[0] != " "]
    at = blocks.index("CC X+20 Z+0")
    assert blocks[at:at + 4] == ["CC X+20 Z+0", "C X+24 Z+0 DR+ R0",
                                     "CC Y+10 Z+4", "C Y+14 Z+4 DR- R0"]
    verdict = api.verify_commands(compiled_post(ROOT / "machines" / "heidenhain.yaml"),
                                  read_cl_text(_cl_text(records), fmt="native"), now=THESIS_TIME)
    assert verdict.ok, str(verdict.divergence)
    events = [e for e in _events("\n".join(_post(records))) if isinstance(e, ArcMove)]
    zx, yz = events[-2:]
    assert (zx.plane, zx.clockwise) == ("zx", False)
    assert (zx.centre, zx.end) == (pytest.approx((20, 10, 0)), pytest.approx((24, 10, 0)))
    # DR+ turns Z towards X: from below the centre round by -X and +Z to +X, three quarters
    assert zx.sweep == pytest.approx(3 * 3.141592653589793 / 2)
    assert (yz.plane, yz.clockwise) == ("yz", True)
    assert (yz.centre, yz.end) == (pytest.approx((24, 10, 4)), pytest.approx((24, 14, 4)))


@pytest.mark.parametrize(("wrong", "right", "found"), [
    ("C X+24 Z+0 DR- R0", "C X+24 Z+0 DR+ R0", "arc clockwise, CL says counter-clockwise"),
    ("C Y+14 Z+4 DR+ R0", "C Y+14 Z+4 DR- R0", "arc counter-clockwise, CL says clockwise"),
    ("CC X+20 Y+0", "CC X+20 Z+0", "C around a CC in the XY plane"),
])
def test_a_wrong_arc_outside_xy_is_flagged(wrong: str, right: str, found: str) -> None:
    records = CL[:10] + ARCS_OUT_OF_XY + CL[-1:]
    nc = "\n".join(_post(records))
    assert right in nc
    try:
        divergence = _divergence(nc.replace(right, wrong, 1), records)
    except ControlError as error:
        divergence = str(error)
    assert divergence is not None and found in divergence, divergence


def test_the_model_refuses_a_helix_around_a_centre_outside_xy() -> None:
    program = ("0 BEGIN PGM A MM\n1 TOOL CALL 1 Z S100\n2 L X+0 Y+0 Z+0 R0 FMAX\n"
               "3 CC X+5 Z+0\n4 CP IPA+90 IZ-1 DR+ R0 F100")
    with pytest.raises(ControlError, match="CP around a CC in the ZX plane"):
        _events(program)


def test_after_a_helix_and_an_arc_a_move_back_to_an_earlier_z_writes_its_z() -> None:
    """The helix's IZ leaves Z unwritten and a C writes only X Y: Z-2 must be written again."""
    records = CL[:9] + [
        {"cmd": "arc_move", "x": 10, "y": 20, "cx": 10, "cy": 10, "arc_direction": "ccw"},
        {"cmd": "linear_move", "z": -2},
    ] + CL[-1:]
    blocks = [line.split(" ", 1)[1] for line in _post(records) if line[0] != " "]
    at = blocks.index("C X+10 Y+20 DR+ R0")
    assert blocks[at + 1] == "L Z-2 R0"
    verdict = api.verify_commands(compiled_post(ROOT / "machines" / "heidenhain.yaml"),
                                  read_cl_text(_cl_text(records), fmt="native"), now=THESIS_TIME)
    assert verdict.ok, str(verdict.divergence)


# --- BLK FORM ---------------------------------------------------------------------------------

def test_blk_form_is_the_box_the_tool_centre_travels_in_right_after_begin_pgm() -> None:
    lines = _post(CL)
    # X0..50 (the second hole), Y0..30, Z-10 (the holes' bottom) .. Z20 (the retract)
    assert lines[1:3] == ["1 BLK FORM 0.1 Z X+0 Y+0 Z-10", "2 BLK FORM 0.2 X+50 Y+30 Z+20"]
    verdict = api.verify_commands(compiled_post(ROOT / "machines" / "heidenhain.yaml"),
                                  read_cl_text(_cl_text(CL), fmt="native"), now=THESIS_TIME)
    assert verdict.ok, str(verdict.divergence)


def test_blk_form_false_writes_no_blank() -> None:
    post = api.load_post(ROOT / "machines" / "heidenhain.yaml", {"blk_form": False})
    lines = [line.text for line in api.post_commands(
        post, read_cl_text(_cl_text(CL), fmt="native"), now=THESIS_TIME)]
    assert not any("BLK FORM" in line for line in lines)
    assert lines[1] == "1 ; T5 D10"


def test_a_program_whose_moves_span_no_box_has_no_blk_form() -> None:
    """All moves in one plane: MAX would not be above MIN in Z, which the TNC refuses."""
    records = [CL[0], CL[1], CL[2], {"cmd": "rapid_move", "x": 0, "y": 0, "z": 5},
               {"cmd": "linear_move", "x": 10, "y": 10, "feed": 100}, CL[-1]]
    lines = _post(records)
    assert not any("BLK FORM" in line for line in lines)


@pytest.mark.parametrize(("program", "message"), [
    ("0 BEGIN PGM A MM\n1 BLK FORM 0.1 Z X+0 Y+0 Z-10\n2 L X+0 R0 FMAX",
     "BLK FORM 0.1 without its BLK FORM 0.2"),
    ("0 BEGIN PGM A MM\n1 BLK FORM 0.1 Z X+0 Y+0 Z-10\n2 BLK FORM 0.2 X+50 Y+0 Z+0",
     "the MAX point is not above the MIN point"),
    ("0 BEGIN PGM A MM\n1 ; T1\n2 BLK FORM 0.1 Z X+0 Y+0 Z-10", "BLK FORM after other blocks"),
    ("0 BEGIN PGM A MM\n1 BLK FORM 0.1 X X+0 Y+0 Z-10", "BLK FORM 0.1 X: the model knows"),
    ("0 BEGIN PGM A MM\n1 BLK FORM 0.1 Z X+0 Y+0", "cannot read 'BLK FORM 0.1 Z X+0 Y+0'"),
])
def test_the_model_refuses_a_wrong_blk_form(program: str, message: str) -> None:
    with pytest.raises(ControlError, match=re.escape(message)):
        _events(program)


def test_a_blk_form_moves_nothing() -> None:
    program = NC.replace("0 BEGIN PGM PLATE MM\n", "0 BEGIN PGM PLATE MM\n"
                         "1 BLK FORM 0.1 Z X+0 Y+0 Z-10\n2 BLK FORM 0.2 X+50 Y+30 Z+20\n")
    lines, number = [], 0
    for line in program.splitlines():
        if not line.startswith(" "):
            line, number = f"{number} {line.split(' ', 1)[1]}", number + 1
        lines.append(line)
    assert _divergence("\n".join(lines)) is None
