"""The APT / ISO 4343 CL source reader: every record of the subset, with its meaning."""

from __future__ import annotations

import math

import pytest

from postdsl.api import read_cl, read_cl_text
from postdsl.cl.apt import looks_like_apt
from postdsl.cl.native import command_to_record
from postdsl.errors import CLError
from tests.conftest import EXAMPLES

START = "PARTNO/TEST\n"
END = "END\nFINI\n"


def read(body: str, head: str = START, tail: str = END) -> list[dict]:
    """The CL records of an APT text (detected from the content), as native records."""
    return [command_to_record(c) for c in read_cl_text(head + body + tail, "t.apt")]


def body(body: str, **kwargs: str) -> list[dict]:
    """Only the records of ``body``: without program_start and program_end."""
    records = read(body, **kwargs)
    assert records[0]["cmd"] == "program_start" and records[-1] == {"cmd": "program_end"}
    return records[1:-1]


def error(text: str) -> CLError:
    with pytest.raises(CLError) as info:
        read_cl_text(text, "t.apt", "apt")
    return info.value


MOVE = "FEDRAT/100\nGOTO/0,0,0\n"  # a known position and feed for arcs


# --- program records ----------------------------------------------------------------------


def test_partno_gives_the_name_and_an_o_number() -> None:
    assert read("", head="PARTNO/O20 FEELER PROBE\n")[0] == {
        "cmd": "program_start", "program_name": "FEELER PROBE", "program_number": 20}
    assert read("", head="PARTNO O0021\n")[0] == {
        "cmd": "program_start", "program_name": "O0021", "program_number": 21}
    assert read("", head="PARTNO/BRACKET 20\n")[0] == {
        "cmd": "program_start", "program_name": "BRACKET 20"}
    assert read("", head="")[0] == {"cmd": "program_start"}


def test_partno_and_pprint_text_is_verbatim() -> None:
    """No $$ comment and no $ continuation inside PARTNO/PPRINT text (as in APT)."""
    records = read("PPRINT/COST $$ 5, (A)  $\nPPRINT  second line\n",
                   head="PARTNO/PART $$ 1\n")
    assert records[0]["program_name"] == "PART $$ 1"
    assert records[1:3] == [{"cmd": "comment", "comment": "COST $$ 5, (A)  $"},
                            {"cmd": "comment", "comment": "second line"}]


def test_end_and_fini_end_the_program_once() -> None:
    assert read("", tail="END\nFINI\n")[-2:] == [{"cmd": "program_start", "program_name":
                                                  "TEST"}, {"cmd": "program_end"}]
    assert read("", tail="FINI\n")[-1] == {"cmd": "program_end"}
    assert read("", tail="END\n")[-1] == {"cmd": "program_end"}
    assert error(START + "END\nFINI\nGOTO/1,2,3\n").message.endswith("after FINI (FINI must "
                                                                     "be the last record)")
    assert "only FINI may follow END" in error(START + "END\nRAPID\nFINI\n").message


def test_a_file_without_end_or_fini_is_refused() -> None:
    exc = error(START + "RAPID\nGOTO/1,2,3\n")
    assert str(exc) == ("t.apt:3: the CL file ends without END or FINI (truncated? posting it "
                        "would end the program early)")


def test_partno_after_other_records_is_refused() -> None:
    exc = error("PPRINT/X\nPARTNO/LATE\nEND\n")
    assert str(exc) == "t.apt:2: PARTNO/LATE: PARTNO must come before every other record " \
                       "except UNITS"


# --- units ----------------------------------------------------------------------------------


def test_inch_files_are_converted_to_mm() -> None:
    records = body("CUTTER/0.5,0.125\nLOADTL/3\nFEDRAT/10\nGOTO/1,2,-0.5\nFEDRAT/10,IPM\n"
                   "GOTO/2,2,-0.5\nFEDRAT/MMPM,300\nGOTO/3,2,-0.5\n"
                   "CYCLE/DEEP,1,INCR,0.25,IPM,4,0.1\nGOTO/4,4,0\nCYCLE/OFF\n",
                   head="PARTNO/INCH PART\nUNITS/INCHES\n")
    assert records[0] == {"cmd": "tool_change", "tool_number": 3, "tool_diameter": 12.7,
                          "tool_corner_radius": 3.175}
    assert records[1] == {"cmd": "linear_move", "x": 25.4, "y": 50.8, "z": -12.7,
                          "feed": 254.0}
    assert records[2]["feed"] == 254.0 and records[3]["feed"] == 300.0
    setup = records[5]
    assert setup["cmd"] == "deep_drill"
    assert (setup["x"], setup["y"], setup.get("top", 0.0)) == (101.6, 101.6, 0.0)
    assert setup["depth"] == 25.4 and setup["peck"] == 6.35 and setup["feed"] == 101.6
    assert setup["clearance"] == pytest.approx(2.54)


def test_units_mm_changes_nothing_and_must_come_first() -> None:
    assert body("FEDRAT/100\nGOTO/1,2,3\n", head="UNITS/MM\nPARTNO/P\n") == [
        {"cmd": "linear_move", "x": 1.0, "y": 2.0, "z": 3.0, "feed": 100.0}]
    exc = error(START + "RAPID\nGOTO/1,2,3\nUNITS/INCHES\nEND\n")
    assert str(exc) == "t.apt:4: UNITS/INCHES: UNITS must come before the first length in " \
                       "the file"
    assert "UNITS must be MM or INCHES, not 'CM'" in error(START + "UNITS/CM\nEND\n").message


# --- tool, spindle, coolant, feed ---------------------------------------------------------


def test_loadtl_and_cutter_in_either_order() -> None:
    assert body("CUTTER/10,2\nLOADTL/1\nLOADTL/2,ADJUST,2\nCUTTER/6\nRAPID\nGOTO/0,0,50\n")[:2] \
        == [{"cmd": "tool_change", "tool_number": 1, "tool_diameter": 10.0,
             "tool_corner_radius": 2.0},
            {"cmd": "tool_change", "tool_number": 2, "tool_diameter": 6.0}]
    assert "whole number" in error(START + "LOADTL/1.5\nEND\n").message
    assert "corner radius" in error(START + "CUTTER/10,6\nEND\n").message


def test_spindl() -> None:
    assert body("SPINDL/2500,RPM,CLW\nSPINDL/RPM,800,CCLW\nSPINDL/OFF\n") == [
        {"cmd": "spindle_on", "spindle_speed": 2500.0},
        {"cmd": "spindle_on", "spindle_speed": 800.0, "spindle": "ccw"},
        {"cmd": "spindle_off"},
    ]
    # RPM is ISO 4343's default unit (SolidWorks CAM writes SPINDL/1000,CLW)
    assert body("SPINDL/2500,CLW\n") == [{"cmd": "spindle_on", "spindle_speed": 2500.0}]
    assert "SPINDL needs a speed and CLW or CCLW" in error(
        START + "SPINDL/2500,RPM\nEND\n").message
    assert "'SFM' is not supported" in error(START + "SPINDL/200,SFM,CLW\nEND\n").message


def test_coolnt() -> None:
    assert body("COOLNT/ON\nCOOLNT/FLOOD\nCOOLNT/MIST\nCOOLNT/OFF\n") == [
        {"cmd": "coolant_on"}, {"cmd": "coolant_on"}, {"cmd": "coolant_on", "coolant": "mist"},
        {"cmd": "coolant_off"}]
    assert body("COOLNT/THRU\n") == [{"cmd": "coolant_on", "coolant": "through"}]
    assert "COOLNT must be ON or FLOOD or MIST or THRU or OFF, not 'AIR'" in error(
        START + "COOLNT/AIR\nEND\n").message


def test_fedrat_and_feed_moves() -> None:
    assert body("FEDRAT/250\nGOTO/1,2,3\nFEDRAT/MMPM,100\nGOTO/1,2,2\n") == [
        {"cmd": "linear_move", "x": 1.0, "y": 2.0, "z": 3.0, "feed": 250.0},
        {"cmd": "linear_move", "x": 1.0, "y": 2.0, "z": 2.0, "feed": 100.0}]
    exc = error(START + "GOTO/1,2,3\nEND\n")
    assert str(exc) == "t.apt:2: GOTO/1,2,3: GOTO is a feed move but no FEDRAT was given " \
                       "before it"
    assert "is not supported (FEDRAT/f[,MMPM|IPM|MMPR|IPR])" in error(
        START + "FEDRAT/0.1,PERREV\nEND\n").message


def test_a_feed_per_revolution_is_its_feed_per_minute_at_the_speed_in_force() -> None:
    """FEDRAT/f,MMPR|IPR (G95): exactly f times the rpm (times 25.4 for inches), again at
    every speed change while it is in force; a feed move while no speed is known is
    refused at its line, naming the FEDRAT."""
    records = body("SPINDL/1200,CLW\nFEDRAT/0.07,MMPR\nGOTO/1,2,3\nSPINDL/RPM,900,CLW\n"
                   "GOTO/1,2,2\nFEDRAT/IPR,0.003\nGOTO/1,2,1\nFEDRAT/300\nSPINDL/500,CLW\n"
                   "GOTO/1,2,0\n")
    assert [r["feed"] for r in records if r["cmd"] == "linear_move"] == [84.0, 63.0, 68.58,
                                                                          300.0]
    exc = error(START + "FEDRAT/0.1,MMPR\nGOTO/1,2,3\nEND\n")
    assert str(exc) == ("t.apt:3: GOTO/1,2,3: GOTO is a feed move with a feed per revolution "
                        "(FEDRAT/0.1,MMPR, line 2) but no spindle speed is in force: the feed "
                        "per minute it means is not known")
    exc = error(START + "SPINDL/800,CLW\nFEDRAT/0.1,MMPR\nSPINDL/OFF\nGOTO/1,2,3\nEND\n")
    assert exc.location.line == 5 and "no spindle speed is in force" in exc.message


# --- motion ---------------------------------------------------------------------------------


def test_rapid_applies_to_the_next_goto_only() -> None:
    assert body("RAPID\nGOTO/1,2,50\nFEDRAT/100\nGOTO/1,2,0,0,0,1\n") == [
        {"cmd": "rapid_move", "x": 1.0, "y": 2.0, "z": 50.0},
        {"cmd": "linear_move", "x": 1.0, "y": 2.0, "z": 0.0, "feed": 100.0}]


def test_a_tilted_tool_axis_goes_to_the_post_with_its_move() -> None:
    """MULTAX GOTOs carry their tool axis (unit length) when it changes; the post solves
    its rotaries from it or refuses it (tests/test_rotary.py)."""
    s = math.sqrt(0.5)
    assert body("RAPID\nGOTO/1,2,50,0,0.7071,0.7071\nFEDRAT/100\nGOTO/1,3,50,0,0.7071,0.7071\n"
                "GOTO/1,2,50,0,0,1\n") == [
        {"cmd": "rapid_move", "x": 1.0, "y": 2.0, "z": 50.0,
         "tool_i": 0.0, "tool_j": pytest.approx(s), "tool_k": pytest.approx(s)},
        {"cmd": "linear_move", "x": 1.0, "y": 3.0, "z": 50.0, "feed": 100.0},
        {"cmd": "linear_move", "x": 1.0, "y": 2.0, "z": 50.0, "feed": 100.0,
         "tool_i": 0.0, "tool_j": 0.0, "tool_k": 1.0}]
    exc = error(START + "RAPID\nGOTO/1,2,50,0,0,0\nEND\n")
    assert str(exc) == "t.apt:3: GOTO/1,2,50,0,0,0: tool axis (0, 0, 0) has no direction"
    exc = error(START + "TLAXIS/0,1,0\nFEDRAT/100\nGOTO/0,0,0\nCIRCLE/0,0,0,0,1,0,5\n"
                "GOTO/5,0,0\nEND\n")
    assert "an arc along the tool axis (0, 1, 0): only along +Z is read" in str(exc)


def test_from_sets_the_start_without_motion() -> None:
    records = body("FROM/10,0,0\nFEDRAT/100\nCIRCLE/0,0,0,0,0,1,10\nGOTO/0,10,0\n")
    assert records == [{"cmd": "arc_move", "x": 0.0, "y": 10.0, "z": 0.0, "cx": 0.0, "cy": 0.0,
                        "feed": 100.0}]


def test_circle_goto_senses_and_planes() -> None:
    records = body(MOVE + "GOTO/10,0,0\n"
                   "CIRCLE/0,0,0,0,0,1,10\nGOTO/0,10,0\n"          # ccw about +Z
                   "CIRCLE/0,0,0,0,0,-1,10\nGOTO/10,0,0\n"         # cw: axis -Z
                   "CIRCLE/0,0,0,0,0,1,10\nGOTO/10,0,-3\n"         # a helical full turn
                   "CIRCLE/0,0,-3,0,1,0,10\nGOTO/0,0,7\n"          # XZ plane, ccw about +Y
                   "CIRCLE/0,5,7,-1,0,0,5\nGOTO/0,5,12\n")         # YZ plane, cw: axis -X
    arcs = records[2:]
    assert arcs[0] == {"cmd": "arc_move", "x": 0.0, "y": 10.0, "z": 0.0, "cx": 0.0, "cy": 0.0,
                       "feed": 100.0}
    assert arcs[1]["arc_direction"] == "cw" and (arcs[1]["x"], arcs[1]["y"]) == (10.0, 0.0)
    assert arcs[2] == {"cmd": "arc_move", "x": 10.0, "y": 0.0, "z": -3.0, "cx": 0.0, "cy": 0.0,
                       "feed": 100.0}
    assert arcs[3] == {"cmd": "arc_move", "x": 0.0, "y": 0.0, "z": 7.0, "cx": 0.0, "cz": -3.0,
                       "plane": "zx", "feed": 100.0}
    assert arcs[4] == {"cmd": "arc_move", "x": 0.0, "y": 5.0, "z": 12.0, "cy": 5.0, "cz": 7.0,
                       "plane": "yz", "arc_direction": "cw", "feed": 100.0}


def test_circle_errors() -> None:
    exc = error(START + MOVE + "GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nGOTO/5,0,0\nEND\n")
    assert str(exc) == "t.apt:6: GOTO/5,0,0: the GOTO end point is 5.0000 from the centre, " \
                       "not the radius 10.0000"
    exc = error(START + MOVE + "CIRCLE/0,0,0,0,0.6,0.8,5\nGOTO/5,0,0\nEND\n")
    assert "is not along X, Y or Z" in exc.message and exc.location.line == 4
    exc = error(START + MOVE + "CIRCLE/5,0,0,0,0,1,5\nRAPID\nGOTO/1,1,1\nEND\n")
    assert str(exc) == "t.apt:5: RAPID: RAPID after CIRCLE (line 4): the CIRCLE needs its " \
                       "GOTO first"
    exc = error(START + "FEDRAT/100\nCIRCLE/5,0,0,0,0,1,5\nGOTO/10,0,0\nEND\n")
    assert "the arc starts where the tool is, which is not known here" in exc.message


def test_catia_tlon_gofwd_arcs() -> None:
    records = body(MOVE + "GOTO/20,15,0\n"
                   "INDIRV/0,1,0\n"                                   # +Y at 180 deg: cw
                   "TLON,GOFWD/(CIRCLE/30,15,0,10),ON,(LINE/30,15,0,30,25,0)\n"
                   "INDIRV/ 1.0, 0.0, 0.0\n"                          # +X at 90 deg: cw again
                   "TLON,GOFWD/ (CIRCLE/ 30.0, 15.0, 0.0,$\n"
                   " 10.0),ON,2,INTOF,(LINE/ 30.0, 15.0, 0.0,$\n"
                   " 30.0, 25.0, 0.0)\n"                              # a full circle
                   "INDIRV/-1,0,0\n"
                   "TLON,GOFWD/(CIRCLE/30,15,0,0,0,1,10),ON,(LINE/30,15,0,20,15,0)\n")
    assert records[2] == {"cmd": "arc_move", "x": 30.0, "y": 25.0, "z": 0.0, "cx": 30.0,
                          "cy": 15.0, "arc_direction": "cw", "feed": 100.0}
    full = records[3]
    assert full["arc_direction"] == "cw"
    assert (full["x"], full["y"]) == pytest.approx((30.0, 25.0))
    quarter = records[4]
    assert quarter.get("arc_direction", "ccw") == "ccw"
    assert (quarter["x"], quarter["y"]) == pytest.approx((20.0, 15.0))
    exc = error(START + MOVE + "TLON,GOFWD/(CIRCLE/0,5,0,5),ON,(LINE/0,5,0,5,5,0)\nEND\n")
    assert exc.message.endswith("TLON,GOFWD needs an INDIRV/i,j,k (the start direction) "
                                "before it")
    exc = error(START + MOVE + "INDIRV/1,0,0\nTLON,GOFWD/(CIRCLE/0,5,0,5),ON,(POINT/1,2,3)\n"
                "END\n")
    assert "expected TLON,GOFWD/(CIRCLE/xc,yc,zc,r),ON," in exc.message


def test_movarc_by_angle() -> None:
    records = body(MOVE + "GOTO/10,0,0\n"
                   "MOVARC/0,0,0,0,0,1,10,ANGLE,90\n"     # ccw to (0,10)
                   "MOVARC/0,0,0,0,0,1,10,ANGLE,-90\n"    # cw back to (10,0)
                   "MOVARC/0,0,0,0,0,-1,10,ANGLE,90\n"    # cw about -Z: to (0,-10)
                   "MOVARC/0,0,0,0,0,1,10,ANGLE,360\n")   # a full circle
    arcs = records[2:]
    assert [a.get("arc_direction", "ccw") for a in arcs] == ["ccw", "cw", "cw", "ccw"]
    ends = [(a["x"], a["y"]) for a in arcs]
    expected = [(0, 10), (10, 0), (0, -10), (0, -10)]
    assert all(math.isclose(e[0], x, abs_tol=1e-9) and math.isclose(e[1], y, abs_tol=1e-9)
               for e, (x, y) in zip(ends, expected, strict=True))
    assert "not 0" in error(START + MOVE + "MOVARC/0,0,0,0,0,1,0,ANGLE,0\nEND\n").message


def test_delay() -> None:
    assert body("DELAY/0.5\n") == [{"cmd": "dwell", "dwell": 0.5}]
    assert "DELAY takes one value, got 2" in error(START + "DELAY/REV,2\nEND\n").message


# --- drilling -------------------------------------------------------------------------------


def test_cycle_goto_points_are_hole_tops() -> None:
    records = body("CYCLE/DRILL,10,MMPM,200,2\nGOTO/10,10,0\nGOTO/30,10,0\nGOTO/50,10,-5\n"
                   "CYCLE/OFF\n")
    assert records == [
        {"cmd": "cycle_start"},
        {"cmd": "single_peck", "x": 10.0, "y": 10.0, "depth": 10.0, "clearance": 2.0,
         "feed": 200.0},  # top 0 is the default, left out of the record
        {"cmd": "cycle_hole", "x": 30.0, "y": 10.0, "top": 0.0},
        {"cmd": "cycle_hole", "x": 50.0, "y": 10.0, "top": -5.0},
        {"cmd": "cycle_end"},
    ]


@pytest.mark.parametrize(("record", "setup", "fields"), [
    ("CYCLE/DRILL,10,MMPM,200,2,DWELL,0.5", "single_peck", {"dwell": 0.5}),
    ("CYCLE/DEEP,20,INCR,4,MMPM,150,2", "deep_drill", {"peck": 4.0}),
    ("CYCLE/BRKCHP,20,INCR,3,MMPM,150,2,DWELL,1", "break_chip", {"peck": 3.0, "dwell": 1.0}),
    ("CYCLE/TAP,15,MMPM,750,5", "tapping", {}),
    ("CYCLE/TAP,15,MMPM,750,5,DWELL,0.2,RIGID", "rigid_tapping", {"dwell": 0.2}),
    ("CYCLE/TAP,15,MMPM,750,5,RIGID,DWELL,0.2", "rigid_tapping", {"dwell": 0.2}),
])
def test_every_cycle_setup(record: str, setup: str, fields: dict) -> None:
    records = body(f"{record}\nGOTO/1,2,3\nCYCLE/OFF\n")
    assert [r["cmd"] for r in records] == ["cycle_start", setup, "cycle_end"]
    for name, value in fields.items():
        assert records[1][name] == value
    assert records[1]["top"] == 3.0


def test_a_counter_clockwise_spindle_makes_left_hand_taps() -> None:
    records = body("SPINDL/400,RPM,CCLW\nCYCLE/TAP,12,MMPM,600,5\nGOTO/1,2,0\n"
                   "CYCLE/TAP,12,MMPM,600,5,RIGID\nGOTO/3,2,0\nCYCLE/OFF\n"
                   "SPINDL/400,RPM,CLW\nCYCLE/TAP,12,MMPM,600,5\nGOTO/5,2,0\nCYCLE/OFF\n")
    assert [r["cmd"] for r in records if r["cmd"].startswith(("tapping", "rigid"))] == [
        "tapping_ccw", "rigid_tapping_ccw", "tapping"]
    # a new CYCLE ends the active one
    assert [r["cmd"] for r in records[:6]] == ["spindle_on", "cycle_start", "tapping_ccw",
                                              "cycle_end", "cycle_start", "rigid_tapping_ccw"]


def test_cycle_off_outside_a_cycle_changes_nothing() -> None:
    assert body("CYCLE/OFF\nCYCLE/DRILL,1,MMPM,1,1\nCYCLE/OFF\n") == []


def test_cycle_errors() -> None:
    exc = error(START + "CYCLE/DEEP,20,MMPM,150,2\nEND\n")
    assert str(exc) == "t.apt:2: CYCLE/DEEP,20,MMPM,150,2: expected " \
                       "CYCLE/DEEP,d,INCR,q,MMPM,f,c[,DWELL,s]"
    assert "'RIGID' is not an option of CYCLE/DRILL" in error(
        START + "CYCLE/DRILL,10,MMPM,200,2,RIGID\nEND\n").message
    exc = error(START + "CYCLE/DRILL,10,MMPM,200,2\nGOTO/1,2,3\nEND\n")
    assert str(exc) == "t.apt:4: END: END inside CYCLE/DRILL (line 2): end the cycle with " \
                       "CYCLE/OFF first"
    exc = error(START + "CYCLE/DRILL,10,MMPM,200,2\nRAPID\nGOTO/1,2,3\nEND\n")
    assert exc.message.startswith("RAPID: RAPID inside CYCLE/DRILL")
    assert "the cycle" in error(START + "CYCLE/THREAD,10\nEND\n").message


# --- syntax ---------------------------------------------------------------------------------


def test_continuation_and_comments() -> None:
    text = ("$$ a comment line\n"
            "PARTNO/CONT\n"
            "FEDRAT/$  $$ the value follows\n"
            "   120\n"
            "GOTO/1.5,$\n"
            "\n"
            "$$ a comment inside the record\n"
            "  -2.25,$\n"
            "  .5   $$ the end of the record\n"
            "goto/ +3 , 4. , -0.5\n"
            "END\nFINI\n")
    records = [command_to_record(c) for c in read_cl_text(text, "t.apt")]
    assert records[1:3] == [
        {"cmd": "linear_move", "x": 1.5, "y": -2.25, "z": 0.5, "feed": 120.0},
        {"cmd": "linear_move", "x": 3.0, "y": 4.0, "z": -0.5, "feed": 120.0}]
    assert [c.line for c in read_cl_text(text, "t.apt")][1:3] == [5, 10]


def test_a_malformed_record_names_its_line_and_text() -> None:
    exc = error(START + "FEDRAT/100\nGOTO/1,,3\nEND\n")
    assert str(exc) == "t.apt:3: GOTO/1,,3: a value is missing (two commas in a row, or a " \
                       "comma at the end)"
    exc = error(START + "FEDRAT/100\nGOTO/1,2\nEND\n")
    assert str(exc) == "t.apt:3: GOTO/1,2: GOTO needs x,y,z or x,y,z,i,j,k, got 2 values"
    exc = error(START + "FEDRAT/100\nGOTO/1,2,1E3\nEND\n")
    assert str(exc) == "t.apt:3: GOTO/1,2,1E3: z must be a plain decimal number, not '1E3'"
    exc = error(START + "FEDRAT/100\nGOTO/1,$\n2,(3\nEND\n")
    assert str(exc) == "t.apt:3: GOTO/1,2,(3: unbalanced parentheses"
    exc = error(START + "GOTO\nEND\n")
    assert str(exc) == "t.apt:2: GOTO: GOTO needs values: GOTO/…"
    exc = error(START + "RAPID/5\nEND\n")
    assert str(exc) == "t.apt:2: RAPID/5: RAPID takes no values"
    exc = error(START + "GOTO/1,2,$\n")
    assert str(exc) == "t.apt:2: GOTO/1,2,: the record is continued with '$' but the file " \
                       "ends (truncated?)"


def test_an_unknown_record_is_never_skipped() -> None:
    exc = error(START + "FEDRAT/100\nOPSKIP\nEND\n")
    assert exc.location is not None and (exc.location.file, exc.location.line) == ("t.apt", 3)
    assert exc.message.startswith("OPSKIP: unknown APT record 'OPSKIP' (this reader knows for "
                                  "ISO 4343 APT: CIRCLE, COOLNT, CUTCOM, CUTTER, CYCLE, ")
    exc = error(START + "TOOL-PATH/PLANAR_MILL\nEND\n")
    assert exc.message.startswith("TOOL-PATH/PLANAR_MILL: unknown APT record 'TOOL-PATH'")
    exc = error(START + "TOOL PATH/X,TOOL,Y\nSPINDL/\u00e9\nEND\n")
    assert str(exc).startswith("t.apt:3: SPINDL/")


# --- detection and the examples -------------------------------------------------------------


def test_detection_by_content() -> None:
    assert looks_like_apt(["$$ header", "PARTNO/X"])
    assert looks_like_apt(["PARTNO X"]) and looks_like_apt(["TLON,GOFWD/(CIRCLE/1,2,3,4)"])
    assert looks_like_apt(["RAPID"]) and looks_like_apt(["CUTCOM/LEFT"])
    assert not looks_like_apt(['{"cmd": "program_start"}'])
    assert not looks_like_apt(["G0 X1 Y2", "M6 T1"])
    assert not looks_like_apt(["Command G1 [ F:3.3 X:7 ]"])
    assert not looks_like_apt(["(Path: T1: D16)"])


def test_the_bundled_apt_examples_read() -> None:
    milling = read_cl(EXAMPLES / "feeler_milling.apt")
    names = [c.name for c in milling]
    assert names[0] == "program_start" and names[-1] == "program_end"
    assert names.count("arc_move") == 10
    drilling = read_cl(EXAMPLES / "feeler_drilling.apt")
    setups = [c.name for c in drilling if c.name.endswith(("peck", "drill", "chip", "tapping",
                                                            "_ccw"))]
    assert setups == ["single_peck", "single_peck", "deep_drill", "break_chip", "tapping",
                      "rigid_tapping", "tapping_ccw", "rigid_tapping_ccw"]



# --- hostile input ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "what"),
    [
        ("GOTO/" + "9" * 400 + ",0,0\n", "x"),
        ("FEDRAT/" + "9" * 400 + "\n", "the feed"),
        ("LOADTL/" + "9" * 400 + "\n", "the tool number"),
    ],
)
def test_a_number_too_large_for_a_double_is_refused(text: str, what: str) -> None:
    """float('999…') is inf, silently: the reader must not pass it on as a coordinate."""
    problem = error(START + text + END)
    assert problem.location is not None and problem.location.line == 2
    assert f"{what} must be a finite number" in problem.message


def test_sub_records_nested_too_deeply_are_a_located_error() -> None:
    text = "TLON,GOFWD/(CIRCLE/" + "(A/" * 5000 + "1" + ")" * 5000 + ")\n"
    problem = error(START + text + END)
    assert str(problem).startswith("t.apt:2: ")
    assert "nested too deeply" in problem.message


def test_the_message_of_a_huge_record_is_shortened() -> None:
    """An 800 kB record must not be echoed whole to the terminal."""
    problem = error(START + "GOTO/" + "1," * 400_000 + "1\n" + END)
    assert str(problem).startswith("t.apt:2: GOTO/1,1,1")
    assert "got 400001 values" in problem.message
    assert len(str(problem)) < 300


def test_a_line_beyond_the_bound_is_refused_without_reading_on() -> None:
    problem = error(START + "GOTO/" + "1," * 1_000_000 + "1\n" + END)
    assert str(problem) == ("t.apt:2: line 2 is longer than 1,000,000 characters: this is not "
                            "a CL file, or a damaged one")


def test_byte_order_marks_and_crlf_are_read(tmp_path) -> None:
    text = START + "LOADTL/1\nRAPID\nGOTO/1,2,3\n" + END
    expected = read(text[len(START):-len(END)])
    for name, data in (("bom.apt", b"\xef\xbb\xbf" + text.replace("\n", "\r\n").encode()),
                       ("utf16.apt", text.encode("utf-16"))):
        path = tmp_path / name
        path.write_bytes(data)
        assert [command_to_record(c) for c in read_cl(path)] == expected


def test_bore_and_ream_cycles_are_the_boring_setups() -> None:
    """CYCLE/BORE and CYCLE/REAM feed out (G85, G89 with a dwell); BORE,DRAG stops the
    spindle at the bottom (G86); the oriented, back and manual bores are refused."""
    records = body("CYCLE/BORE,20,MMPM,80,5\nGOTO/10,10,0\nCYCLE/REAM,12,MMPM,60,2,DWELL,0.5\n"
                   "GOTO/20,10,0\nCYCLE/BORE,20,MMPM,80,5,DRAG\nGOTO/30,10,0\nCYCLE/OFF\n")
    setups = [r for r in records if r["cmd"].startswith("boring")]
    assert setups == [
        {"cmd": "boring", "x": 10.0, "y": 10.0, "depth": 20.0, "clearance": 5.0,
         "feed": 80.0},
        {"cmd": "boring", "x": 20.0, "y": 10.0, "depth": 12.0, "clearance": 2.0,
         "dwell": 0.5, "feed": 60.0},
        {"cmd": "boring_spindle_stop", "x": 30.0, "y": 10.0, "depth": 20.0,
         "clearance": 5.0, "feed": 80.0}]
    for mode, why in (("NODRAG", "fine boring"), ("BACK", "back boring"),
                      ("MANUAL", "a manual retract")):
        exc = error(START + f"CYCLE/BORE,20,MMPM,80,5,{mode}\nEND\n")
        assert exc.message.startswith(f"CYCLE/BORE,20,MMPM,80,5,{mode}: CYCLE/BORE,{mode} is "
                                      f"refused: {why}")
    assert "CYCLE/REAM,DRAG is refused" in error(
        START + "CYCLE/REAM,20,MMPM,80,5,DRAG\nEND\n").message
