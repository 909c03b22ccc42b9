"""The control models' rules, one by one, on small NC programs (postdsl/check/controls/).

Each rule comes from the control's manual as the model's docstring states it;
here every rule is shown on the events it yields, and every refusal on the
line it names.
"""

from __future__ import annotations

import math

import pytest

from postdsl.check.controls import CONTROLS, ControlError, NCInput, control_model
from postdsl.check.controls.events import ArcMove, Dwell, FeedMove, Hole, NotFollowed, Rapid


def events(control: str, program: str) -> list:
    return list(control_model(control).replay(program.strip().splitlines()))


def only(kind: type, control: str, program: str) -> list:
    return [e for e in events(control, program) if isinstance(e, kind)]


def refusal(control: str, program: str) -> ControlError:
    with pytest.raises(ControlError) as caught:
        events(control, program)
    return caught.value


FANUC_START = """
O1
N10 G0 G17 G40 G80 G90
N20 T1
N30 M6
N40 G54 G17 G90 G0 G94
N50 S1000 M3
N60 G0 X0. Y0.
N70 G43 H1 D1 Z50.
"""


def test_every_model_is_registered_under_the_name_posts_use() -> None:
    assert set(CONTROLS) == {"fanuc-0i", "linuxcnc", "sinumerik-828d", "acramatic-2100",
                             "grbl-1.1", "hmcnc", "heidenhain-tnc640"}
    # and posts may name exactly these (the schema's list of controls)
    import json

    from tests.conftest import ROOT
    schema = json.loads((ROOT / "schemas" / "post.schema.json").read_text(encoding="utf-8"))
    assert set(schema["$defs"]["machine"]["properties"]["control"]["enum"]) == set(CONTROLS)


# --- the ISO core (Fanuc, LinuxCNC) --------------------------------------------------------------

def test_fanuc_z_only_block_in_a_canned_cycle_is_another_hole() -> None:
    holes = only(Hole, "fanuc-0i", FANUC_START + """
N80 G99 G81 X10. Y10. Z-5. R2. F100
N90 Z-8.
N100 G80""")
    assert [(h.x, h.y, h.bottom) for h in holes] == [(10, 10, -5), (10, 10, -8)]
    # the defect of issue 9: a retract written without G0 inside the cycle
    error = refusal("fanuc-0i", FANUC_START + "N80 G98 G82 X1. Y1. Z-5. R2. P500 F100\nN90 Z80.")
    assert error.origin.line == 10 and "Z80 above R2" in error.message


def test_fanuc_cycle_repeats_on_xy_blocks_and_keeps_z_r_until_g80() -> None:
    holes = only(Hole, "fanuc-0i", FANUC_START + """
N80 G99 G83 X10. Y10. Z-20. R2. Q4. F100
N90 X30.
N100 Y30. Z-25. R-3.
N110 G80
N120 G0 X50.""")
    assert [(h.x, h.y, h.r, h.bottom, h.peck, h.kind) for h in holes] == [
        (10, 10, 2, -20, 4, "peck"), (30, 10, 2, -20, 4, "peck"), (30, 30, -3, -25, 4, "peck")]


def test_g98_returns_to_the_initial_level_and_g99_to_r() -> None:
    g98 = only(Hole, "fanuc-0i", FANUC_START + "N80 G98 G81 X1. Y1. Z-5. R2. F100\nN90 X2.")
    g99 = only(Hole, "fanuc-0i", FANUC_START + "N80 G99 G81 X1. Y1. Z-5. R2. F100\nN90 X2.")
    assert [h.leave for h in g98] == [50, 50]
    assert [h.leave for h in g99] == [2, 2]
    assert g99[1].start == (2, 1, 2)  # the next hole positions at the R level


def test_fanuc_feed_per_revolution_is_f_times_s_and_p_is_milliseconds() -> None:
    hole, = only(Hole, "fanuc-0i", FANUC_START + "N80 G95 G99 G82 X1. Y1. Z-5. R2. P500 F0.2")
    assert hole.feed == pytest.approx(200) and hole.dwell == 0.5
    dwells = only(Dwell, "fanuc-0i", FANUC_START + "N80 G4 P250\nN90 G4 X1.5")
    assert [d.seconds for d in dwells] == [0.25, 1.5]
    assert [d.seconds for d in only(Dwell, "linuxcnc", "G4 P1.5")] == [1.5]


def test_fanuc_refuses_words_a_cycle_format_does_not_list() -> None:
    error = refusal("fanuc-0i", FANUC_START + "N80 G99 G73 X1. Y1. Z-5. R2. Q3. P200 F100")
    assert "P is not a word of G73" in error.message
    no_peck = refusal("fanuc-0i", FANUC_START + "N80 G83 X1. Y1. Z-5. R2. F1")
    assert "needs a peck" in no_peck.message


def test_m29_makes_the_next_taps_rigid_and_the_hand_follows_the_code() -> None:
    program = FANUC_START + """
N80 G95 G99 G84 X1. Y1. Z-5. R2. P0 F1.5
N90 G80
N100 M29 S500
N110 G84 X2. Y1. Z-5. R2. Q2.
N120 G80
N130 M4
N140 G74 X3. Y1. Z-5. R2. F1.5"""
    holes = only(Hole, "fanuc-0i", program)
    assert [(h.kind, h.direction, h.peck) for h in holes] == [
        ("tap", "cw", 0), ("rigid_tap", "cw", 2), ("tap", "ccw", 0)]
    assert holes[1].feed == pytest.approx(750)
    assert "with the spindle cw" in refusal("fanuc-0i", FANUC_START + "N80 G74 X1. Y1. Z-5. R2.")\
        .message


def test_length_offset_and_tool_are_the_state_of_every_cut() -> None:
    moves = only(FeedMove, "fanuc-0i", FANUC_START + "N80 G1 Z-1. F100\nN90 G49\nN100 G1 X5.")
    assert [(m.tooling.tool, m.tooling.length_offset) for m in moves] == [(1, 1), (1, None)]
    assert moves[0].start == (0, 0, 50) and moves[0].end == (0, 0, -1)


def test_a_tool_change_and_a_reference_return_leave_the_position_unknown() -> None:
    error = refusal("fanuc-0i", FANUC_START + "N80 G91 G30 G0 Z0.\nN90 G90 G1 X5. F100")
    assert "does not state" in error.message and error.origin.line == 10
    rapids = only(Rapid, "fanuc-0i", "T2\nM6\nG90 G0 X1. Y1.")
    assert rapids[0].end == (None, None, None) and rapids[-1].end == (1, 1, None)


def test_arcs_by_centre_radius_and_full_circles() -> None:
    arcs = only(ArcMove, "fanuc-0i", FANUC_START + """
N80 G1 Z-1. F100
N90 G2 X10. Y10. I10. J0.
N100 G2 X20. Y0. R10.
N110 G2 X10. Y10. R-10.
N120 G3 I-5. J0.
N130 G18 G2 X5. Z4. I0. K5.""")
    assert arcs[0].centre[:2] == (10, 0) and arcs[0].clockwise
    assert arcs[0].sweep == pytest.approx(math.pi / 2)
    assert arcs[1].centre[:2] == pytest.approx((10, 0)) and arcs[1].sweep == pytest.approx(
        math.pi / 2)
    # R < 0: the long way round, about the other centre
    assert arcs[2].centre[:2] == pytest.approx((10, 0))
    assert arcs[2].sweep == pytest.approx(3 * math.pi / 2)
    assert arcs[3].sweep == pytest.approx(2 * math.pi)  # centre only: a full circle
    assert arcs[3].centre[:2] == (5, 10)
    assert arcs[4].plane == "zx" and arcs[4].centre == pytest.approx((10, 10, 4))
    assert "not on its circle" in refusal(
        "fanuc-0i", FANUC_START + "N80 G1 Z0 F1\nN90 G2 X20. Y0. I5. J0.").message


@pytest.mark.parametrize(("line", "message"), [
    ("N80 G65 P9770 Z5.", "G65"),
    ("N80 #550=#138", "macro variables"),
    ("N80 M31", "M31 is not a code"),
    ("N80 G1 X1. F1 A5.", "'A5.' is not a word"),
    ("N80 G41.1 D1", "G41.1"),
])
def test_what_the_model_does_not_know_is_refused_with_its_line(line: str, message: str) -> None:
    error = refusal("fanuc-0i", FANUC_START + line)
    assert message in error.message and error.origin.line == 9 and error.origin.text == line


def test_declared_lines_are_not_interpreted() -> None:
    model = control_model("fanuc-0i")
    lines = [NCInput(1, "G0 X0. Y0. Z10."), NCInput(2, "G65 P9770 Z5.", declared="unknown"),
             NCInput(3, "M32", skip_words=frozenset({"M32"})),
             NCInput(4, "G65 P9023", declared="none")]
    out = list(model.replay(lines))
    assert [type(e) for e in out] == [Rapid, NotFollowed, NotFollowed]
    assert model.pos == [None, None, None]


def test_linuxcnc_reads_semicolon_comments_and_has_no_m29() -> None:
    assert only(Dwell, "linuxcnc", "G4 P2 ; two seconds (not ms)")[0].seconds == 2
    assert "M29" in refusal("linuxcnc", "M29 S500").message


LINUXCNC_TAP = """
T1 M6
G43 H1
M3 S500
G0 X10 Y10 Z20
G0 Z3
"""


def test_linuxcnc_g33_1_taps_from_the_tool_to_z_at_k_and_back() -> None:
    """LinuxCNC manual, G33.1: synchronised to Z at K per revolution, back to the start."""
    holes = only(Hole, "linuxcnc", LINUXCNC_TAP + "G33.1 Z-12 K1.25\nM4\nG33.1 Z-8 K1.25")
    assert [(h.x, h.y, h.r, h.bottom, h.leave, h.kind, h.direction, h.feed, h.peck, h.dwell)
            for h in holes] == [(10, 10, 3, -12, 3, "rigid_tap", "cw", 625, 0, 0),
                                (10, 10, 3, -8, 3, "rigid_tap", "ccw", 625, 0, 0)]


def test_linuxcnc_g33_1_is_modal_and_a_rapid_straight_up_after_it_is_where_it_leaves() -> None:
    out = events("linuxcnc", LINUXCNC_TAP + "G33.1 Z-12 K1.25\nG0 Z20\nX30\nG0 Z3\n"
                 "G33.1 Z-12 K1.25\n(a comment)\nG0 X50 Z20\nZ3\nG33.1 Z-12 K1.25\nZ-6 K1")
    holes = [e for e in out if isinstance(e, Hole)]
    assert [(h.x, h.r, h.bottom, h.leave, h.feed) for h in holes] == [
        (10, 3, -12, 20, 625),   # the G0 Z20 straight up: the hole is left there
        (30, 3, -12, 3, 625),    # G0 X50 Z20 moves sideways too: left at R
        (50, 3, -12, 3, 625),    # followed by a block of axis words: G33.1 again
        (50, 3, -6, 3, 500)]
    up = [e for e in out if isinstance(e, Rapid) and e.origin.text == "G0 Z20"]
    assert len(up) == 1 and out.index(holes[0]) == out.index(up[0]) - 1  # the hole, then up


@pytest.mark.parametrize(("line", "message"), [
    ("G33.1 Z-12", "G33.1 without K"),
    ("G33.1 K1.25", "G33.1 without an axis word"),
    ("G33.1 X12 Z-12 K1.25", "move sideways in the hole"),
    ("G33.1 Z5 K1.25", "not below the tool"),
    ("G33.1 Z-12 K-1.25", "the pitch must be positive"),
    ("G33.1 Z-12 K1.25 I2", "I is not a word of G33.1"),
    ("G1 G33.1 Z-12 K1.25", "two motion codes"),
    ("M5\nG33.1 Z-12 K1.25", "spindle not turning"),
])
def test_linuxcnc_refuses_a_g33_1_it_cannot_follow(line: str, message: str) -> None:
    assert message in refusal("linuxcnc", LINUXCNC_TAP + line).message


def test_linuxcnc_g33_1_from_an_unknown_position_is_refused() -> None:
    assert "position the program does not state" in refusal(
        "linuxcnc", "T1 M6\nM3 S500\nG33.1 Z-12 K1.25").message


# --- Sinumerik 828D --------------------------------------------------------------------------

EMCO_START = """
N10 G17 G40
N20 G54 G90
N30 M6 T2
N40 M3 S3000
N50 G0 X10.000 Y10.000 Z20.000
N60 F150
"""


def test_mcall_calls_the_cycle_after_every_block_with_motion_until_a_bare_mcall() -> None:
    holes = only(Hole, "sinumerik-828d", EMCO_START + """
N70 MCALL CYCLE81(20.000, 0.000, 2.000, -2.000)
N80 X10.000 Y10.000
N90 X70.000
N100 Z80.000
N110 MCALL
N120 X0.000""")
    assert [(h.x, h.y, h.r, h.bottom, h.leave) for h in holes] == [
        (10, 10, 2, -2, 20), (70, 10, 2, -2, 20), (70, 10, 2, -2, 20)]
    assert holes[0].tooling.length_offset == 2 and holes[0].feed == 150


def test_sinumerik_cycle_arguments_by_position() -> None:
    holes = only(Hole, "sinumerik-828d", EMCO_START + """
N70 CYCLE82(20.000, 0.000, 2.000, -6.000, , 0.8)
N80 CYCLE83(20.000, 0.000, 2.000, -25.000, , , 5.000, 0.000, 0.0, , 1.0, 1)
N90 CYCLE83(15.000, 0.000, 1.500, -18.000, , , 3.000, 0.000, 0.2, , 1.0, 0)
N100 CYCLE84(20.000, 0.000, 2.000, -12.000, , 0.1, 4, , -1.250, 0.000, 600, 600, , , , 1, 4.000)
N110 CYCLE840(20.000, 0.000, 3.000, -18.000, , 0.3, 4, 3, 1, , 1.500)""")
    assert [(h.kind, h.dwell, h.peck) for h in holes] == [
        ("drill", 0.8, 0), ("peck", 0, 5), ("chip_break", 0.2, 3), ("rigid_tap", 0.1, 4),
        ("tap", 0.3, 0)]
    assert holes[3].direction == "ccw" and holes[3].feed == pytest.approx(750)
    assert "at most 5 arguments" in refusal("sinumerik-828d",
                                            EMCO_START + "N70 CYCLE81(1,0,1,-1,,9)").message
    assert "degression" in refusal("sinumerik-828d", EMCO_START + "N70 CYCLE83(20, 0, 2, -25, , , "
                                   "5, 1, 0, , 1, 1)").message


def test_sinumerik_cr_arcs_and_g4_f_dwell() -> None:
    out = events("sinumerik-828d", EMCO_START + "N70 G1 Z0 F100\nN80 G2 X30.000 Y10.000 CR=10."
                                                "\nN90 G4 F2.5\nN100 G1 X31.")
    arc, = [e for e in out if isinstance(e, ArcMove)]
    assert arc.centre[:2] == pytest.approx((20, 10)) and arc.sweep == pytest.approx(math.pi)
    assert [e.seconds for e in out if isinstance(e, Dwell)] == [2.5]
    assert [e.feed for e in out if isinstance(e, FeedMove)] == [100, 100]  # G4 F is no feed


# --- Acramatic 2100 --------------------------------------------------------------------------

VMC_START = """
 :
N10  T1 M6
N20  M3 S500 M8
N30  G0 X40. Y20. Z80.
[$CYCLE_PARAMS(2)GAGE_HT_MM] = 5.0
"""


def test_acramatic_r_is_the_top_z_the_depth_and_gage_height_the_clearance() -> None:
    holes = only(Hole, "acramatic-2100", VMC_START + """
[$CYCLE_PARAMS(2)G82_DWELL] = 0.5
N40 G82 X40. Y20. Z50.0 R70.0 F200.0
N50 G80
N60 G83 X60. Y20. Z53.0043 R70.0 F200.0 J13 K10.0
N70 G80
N80 G83 X60. Y20. Z53.0043 R70.0 F200.0 J11 K10.0 W100.
N90 G80
N100 G84.1 X100. Y20. Z35.0 R70.0J1 K10.0 P1""")
    assert [(h.r, h.bottom, h.leave, h.kind, h.peck, h.dwell) for h in holes] == [
        (75, 20, 75, "drill", 0, 0.5), (75, 70 - 53.0043, 75, "peck", 10, 0),
        (75, 70 - 53.0043, 100, "chip_break", 10, 0), (75, 35, 75, "rigid_tap", 10, 0)]
    assert holes[0].tooling.length_offset == 1  # the tool's own, with M6


def test_acramatic_refuses_what_it_cannot_model() -> None:
    variable_peck = refusal("acramatic-2100", VMC_START + "N40 G83 X1. Y1. Z5. R0. F1 J1 K1")
    assert "J11" in variable_peck.message
    assert "GAGE_HT_MM" in refusal("acramatic-2100", "N10 T1 M6\nN20 M3 S1\nN30 G0 X0 Y0 Z9\n"
                                                     "N40 G81 X1. Y1. Z5. R0. F1").message
    assert "finishing depth" in refusal("acramatic-2100", VMC_START + "[$CYCLE_PARAMS(2)"
                                        "G82_FIN_DPTH] = 1.0\nN40 G82 X1. Y1. Z5. R0. F1").message
    assert [d.seconds for d in only(Dwell, "acramatic-2100", "N10  G4 F0.5")] == [0.5]


def test_fanuc_g76_is_a_fine_boring_cycle_whose_q_is_no_peck() -> None:
    hole, = only(Hole, "fanuc-0i", FANUC_START + "N80 G99 G76 X1. Y1. Z-5. R2. Q0.2 P300 F50")
    assert (hole.kind, hole.peck, hole.dwell, hole.bottom) == ("bore", 0, 0.3, -5)
    assert "G76" in refusal("linuxcnc", "G0 X0 Y0 Z5\nG76 X1. Y1. Z-5. R2. F50").message
