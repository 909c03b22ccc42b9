"""Each control model reads the words of a line as its control does (issue 25).

Comments by each control's syntax (``postdsl.lang.control_syntax.COMMENTS``): parentheses
end at the first ``)``, ``;`` runs to the end of the line only outside them, ``%`` as
the control treats it; M2/M30 end the program.  Where LinuxCNC's interpreter ``rs274``
reads the same text, it is asked too.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from postdsl import api
from postdsl.check.controls import ControlError, control_model
from postdsl.check.controls.events import FeedMove, ProgramEnded, Rapid, SpindleChanged
from postdsl.errors import PostError
from tests.conftest import MACHINES
from tests.test_rs274_oracle import RS274, needs_rs274, rs274_process, run_rs274

TOOLS = RS274.parent / "tool.tbl"


def events(control: str, program: str, **settings: bool) -> list:
    return list(control_model(control, **settings).replay(program.strip().splitlines()))


def feeds(control: str, program: str, **settings: bool) -> list[tuple]:
    return [e.end for e in events(control, program, **settings) if isinstance(e, FeedMove)]


def rs274_errors(program: Path) -> str:
    """What rs274 prints for a program it refuses."""
    result = rs274_process(TOOLS, program)
    return result.stdout + result.stderr


def refusal(control: str, program: str) -> ControlError:
    with pytest.raises(ControlError) as caught:
        events(control, program)
    return caught.value


ISO_START = """
G21 G90 G94 G17
T1 M6
G43 H1
S1000 M3
G0 X0 Y0 Z5
"""


# --- comments ----------------------------------------------------------------------------------

@pytest.mark.parametrize("control", ["linuxcnc", "grbl-1.1"])
def test_a_semicolon_inside_parentheses_is_part_of_the_comment(control: str) -> None:
    """``(a;b)`` was cut at the ``;`` (a false alarm: "a comment is not closed")."""
    start = ISO_START.replace("T1 M6\nG43 H1\n", "") if control == "grbl-1.1" else ISO_START
    program = start + "G1 Z-1 F100 (depth; first pass) X10\nG1 Y10 ;the rest (is a comment\n"
    assert feeds(control, program) == [(10, 0, -1), (10, 10, -1)]


def test_parentheses_end_at_the_first_closing_one_and_do_not_nest() -> None:
    # the comment ends at the first ')': what follows it is code
    assert feeds("linuxcnc", ISO_START + "(a) G1 Z-2 F50 (b)") == [(0, 0, -2)]
    error = refusal("linuxcnc", ISO_START + "G1 Z-2 F50 (a (b) c)")
    assert error.origin.line == 6 and "nested comment" in error.message
    assert "not closed" in refusal("fanuc-0i", "G0 X1. (open").message
    # GRBL throws away everything up to ')' or the end of the line (protocol.c)
    assert feeds("grbl-1.1", "G21 G90\nS1000 M3\nG0 X0 Y0 Z1\nG1 Z-1 F9 (a (b)\nG1 X1 (open")\
        == [(0, 0, -1), (1, 0, -1)]


@needs_rs274
def test_rs274_reads_comments_as_the_linuxcnc_model(tmp_path: Path) -> None:
    program = ISO_START + "G1 Z-1 F100 (depth; first pass) X10\nG1 Y10 ;the rest (is a comment\nM2"
    trace = run_rs274(program.strip().splitlines(), tmp_path)
    ends = [m.end for m in trace.moves if m.kind == "feed"]
    assert feeds("linuxcnc", program) == [(10, 0, -1), (10, 10, -1)]
    assert ends == [pytest.approx(e) for e in feeds("linuxcnc", program)]
    nested = tmp_path / "nested.ngc"
    nested.write_text("G21\n(a (b) c)\nM2\n", encoding="utf-8")
    result = rs274_errors(nested)
    assert "Nested comment" in result


# --- the end of the program --------------------------------------------------------------------

INJECTED = ISO_START + """G1 Z-1 F100
G1 X10
(end of roughing) M30 (finish follows)
G1 Y10
G1 X0
M5
M2
"""


@pytest.mark.parametrize("control", ["linuxcnc", "fanuc-0i"])
def test_m30_ends_the_program_and_the_lines_after_it_are_not_run(control: str) -> None:
    got = feeds(control, INJECTED, **({"calculator_input": True} if control == "fanuc-0i"
                                       else {}))
    assert got == [(0, 0, -1), (10, 0, -1)]  # the finishing cuts after M30 never run
    end, = [e for e in events(control, INJECTED, calculator_input=True)
            if isinstance(e, ProgramEnded)]
    assert end.origin.text.startswith("(end of roughing) M30")  # where verify reports it
    # M2 too, and a line after it that the model could not even read is not read
    assert feeds("linuxcnc", ISO_START + "G1 Z-1 F9\nM2\nthis is not G-code") == [(0, 0, -1)]


@needs_rs274
def test_rs274_ends_the_program_at_the_m30_of_the_injected_comment(tmp_path: Path) -> None:
    """The comment injection of issue 25: rs274 runs the cuts before M30 and none after."""
    trace = run_rs274(INJECTED.strip().splitlines(), tmp_path)
    assert [m.end for m in trace.moves if m.kind == "feed"] == \
        [pytest.approx(e) for e in feeds("linuxcnc", INJECTED)]


def test_grbl_reads_on_after_m30_with_its_modal_state_reset() -> None:
    """GRBL (gcode.c, program flow): M2/M30 reset G1 G17 G90 G94 G54 M5 M9 and reading goes on."""
    program = "G21 G91\nS1000 M3\nG0 X1 Y1 Z1\nM30\nG0 X5 Y5 Z5\nG1 Z0 F100"
    run = events("grbl-1.1", program)
    assert SpindleChanged(run[-3].origin, "off", 1000) in run
    cut, = [e for e in run if isinstance(e, FeedMove)]
    assert cut.end == (5, 5, 0) and cut.tooling.spindle == "off"  # G90 again, spindle off


def test_percent_as_each_control_treats_it() -> None:
    # LinuxCNC: a leading '%' line, and the program ends at the next one
    program = "%\n" + ISO_START + "G1 Z-1 F9\n%\nG1 Z-5"
    assert feeds("linuxcnc", program) == [(0, 0, -1)]
    # ... a '%' line in a file that did not start with one is an error (rs274 agrees), also
    # after a comment line; blank lines before it are not a start
    assert "'%'" in refusal("linuxcnc", ISO_START + "%\nG1 Z-1 F9").message
    assert "'%'" in refusal("linuxcnc", "(hello)\n%\nG21").message
    blank_first = control_model("linuxcnc").replay(["", " ", *program.strip().splitlines()])
    assert [e.end for e in blank_first if isinstance(e, FeedMove)] == [(0, 0, -1)]
    # ... and inside a comment it is an ordinary character
    assert feeds("linuxcnc", ISO_START + "G1 Z-1 F9 (100% feed)") == [(0, 0, -1)]
    # Fanuc: '%' is the end-of-record code wherever it stands, in a comment too
    fanuc = "%\nO1\n" + ISO_START + "G1 Z-1 F9\n(100% feed)\nG1 Z-5"
    assert feeds("fanuc-0i", fanuc, calculator_input=True) == [(0, 0, -1)]
    # GRBL does not support '%'
    assert "'%'" in refusal("grbl-1.1", "%\nG0 X1").message


@needs_rs274
def test_rs274_agrees_on_percent(tmp_path: Path) -> None:
    trace = run_rs274(("%\n" + ISO_START + "G1 Z-1 F9\n%\nG1 Z-5").splitlines(), tmp_path)
    assert [m.end for m in trace.moves if m.kind == "feed"] == [pytest.approx((0, 0, -1))]
    bare = tmp_path / "bare.ngc"
    bare.write_text(ISO_START + "%\nG1 Z-1 F9\nM2\n", encoding="utf-8")
    assert "Bad character '%'" in rs274_errors(bare)
    bare.write_text("(hello)\n%\nG21\n%\n", encoding="utf-8")
    assert "Bad character '%'" in rs274_errors(bare)


def test_sinumerik_and_acramatic_comments_run_from_the_semicolon() -> None:
    moves = [e for e in events("sinumerik-828d", "G0 X1 Y2 Z3 ;a (b\nG0 X4 ; c)")
             if isinstance(e, Rapid)]
    assert [m.end for m in moves] == [(1, 2, 3), (4, 2, 3)]


# --- Fanuc: a number without a decimal point ---------------------------------------------------

FANUC = "O1\nG21 G90 G94 G17\nT1 M6\nS1000 M3\nG0 X0. Y0.\nG43 H1 Z50.\n"


def test_fanuc_reads_a_number_without_a_point_in_the_least_input_increment() -> None:
    """3401#0 = 0 (the default): X10 Z-10 R2 Q4 are 0.010, -0.010, 0.002 and 0.004 mm."""
    hole, = [e for e in events("fanuc-0i", FANUC + "G99 G83 X10 Y5. Z-10 R2 Q4 F100\nG80")
             if type(e).__name__ == "Hole"]
    assert (hole.x, hole.y, hole.bottom, hole.r, hole.peck) == (0.01, 5, -0.01, 0.002, 0.004)
    # in calculator input (3401#0 = 1) they are mm
    hole, = [e for e in events("fanuc-0i", FANUC + "G99 G83 X10 Y5. Z-10 R2 Q4 F100\nG80",
                               calculator_input=True) if type(e).__name__ == "Hole"]
    assert (hole.x, hole.bottom, hole.r, hole.peck) == (10, -10, 2, 4)
    # G04 X without a point is in 0.001 s; P (ms), S, T, H are integers either way
    dwell = [e for e in events("fanuc-0i", FANUC + "G4 X1500\nG4 P250") if
             type(e).__name__ == "Dwell"]
    assert [d.seconds for d in dwell] == [1.5, 0.25]
    # F is mm/min in G94; in G95 an F without a point is refused (its unit is a parameter)
    assert feeds("fanuc-0i", FANUC + "G1 Z-1. F100") == [(0, 0, -1)]
    assert "G95" in refusal("fanuc-0i", FANUC + "G95 G1 Z-1. F1").message


def test_only_the_fanuc_model_scales_a_number_without_a_point() -> None:
    assert feeds("linuxcnc", ISO_START + "G1 Z-10 F100") == [(0, 0, -10)]
    moves = [e for e in events("sinumerik-828d", "G0 X10 Y0 Z5") if isinstance(e, Rapid)]
    assert moves[-1].end == (10, 0, 5)


FANUC_POST = (MACHINES / "fanuc.yaml").read_text(encoding="utf-8")
COORD = """  coord:                 # X10.  Z-2.5  X12.345 : always a point, 3 decimals (0.001 mm)
    decimals: {option: program_units, mm: 3, inch: 4}
    multiplier: {option: program_units, mm: 1, inch: 0.03937007874015748}
    trailing_zeros: false
    point: always
"""
RESOLUTION = "  resolution: {option: program_units, mm: 0.001, inch: 0.00254}\n"


def test_check_flags_a_fanuc_coordinate_format_that_can_write_no_point() -> None:
    assert COORD in FANUC_POST and RESOLUTION in FANUC_POST
    api.load_post_text(FANUC_POST, "fanuc.yaml")  # the library post: points everywhere
    pointless = FANUC_POST.replace(COORD, COORD.replace("point: always", "point: needed"))
    with pytest.raises(PostError) as caught:
        api.load_post_text(pointless, "fanuc.yaml")
    problem, = caught.value.problems
    assert problem.location.line == FANUC_POST[:FANUC_POST.index(COORD)].count("\n") + 1
    assert problem.message.startswith("format 'coord' writes X Y Z I J K R Q words without a "
                                      "decimal point (X10): Fanuc parameter 3401#0 = 0")
    # a machine set to calculator input reads X10 as 10 mm: the same format is right there
    calculator = pointless.replace(RESOLUTION, RESOLUTION + "  calculator_input: true\n")
    post = api.load_post_text(calculator, "fanuc.yaml")
    assert post.machine.calculator_input is True
    # an implied point at the least increment (X10000 = 10 mm) is right too
    implied = FANUC_POST.replace(COORD, COORD.replace("trailing_zeros: false",
                                                      "trailing_zeros: true").replace(
                                                          "point: always", "point: never"))
    api.load_post_text(implied, "fanuc.yaml")
    # a control that reads every number as written has nothing to flag
    linuxcnc = pointless.replace("control: fanuc-0i", "control: linuxcnc")
    api.load_post_text(linuxcnc, "fanuc.yaml")


# --- cycle arguments by position and meaning ---------------------------------------------------

SINUMERIK = "N10 G17 G40\nN20 G54 G90\nN30 M6 T2\nN40 {m} S400\nN50 G0 X10 Y10 Z20\nN60 F500\n"


def holes_and_spindle(program: str) -> list[tuple]:
    return [(type(e).__name__, getattr(e, "direction", None)) for e in
            events("sinumerik-828d", program) if type(e).__name__ in ("Hole", "SpindleChanged")]


def test_cycle840_sdr_retracts_reversed_and_sdac_is_the_spindle_after_it() -> None:
    """CYCLE840(RTP, RFP, SDIS, DP, DPR, DTB, SDR, SDAC, ENC, MPIT, PIT): a right-hand tap
    under M3 retracts M4 (SDR=4) and leaves M3 (SDAC=3); a left-hand one under M4 is SDR=3,
    SDAC=4."""
    right = SINUMERIK.format(m="M3") + "N70 MCALL CYCLE840(20, 0, 3, -15, , 0.5, 4, 3, 1, , 1.25)" \
        "\nN80 X10\nN85 X30\nN90 MCALL"
    left = SINUMERIK.format(m="M4") + "N70 MCALL CYCLE840(20, 0, 3, -15, , 0.5, 3, 4, 1, , -1.25)" \
        "\nN80 X10\nN85 X30\nN90 MCALL"
    assert holes_and_spindle(right)[-2:] == [("Hole", "cw"), ("Hole", "cw")]
    assert holes_and_spindle(left)[-2:] == [("Hole", "ccw"), ("Hole", "ccw")]
    # the tap pulled out turning the way it cut: refused, at the line that calls it
    same = refusal("sinumerik-828d", left.replace("0.5, 3, 4, 1", "0.5, 4, 4, 1"))
    assert same.origin.line == 8 and "retracts turning M4, as it went in (ccw)" in same.message \
        and "SDR=3" in same.message
    # SDAC: the spindle after the cycle -- the next hole of the MCALL goes in with it
    after = refusal("sinumerik-828d", left.replace("0.5, 3, 4, 1", "0.5, 3, 3, 1"))
    assert after.origin.line == 9 and "the spindle cw" in after.message
    stopped = refusal("sinumerik-828d", right.replace("0.5, 4, 3, 1", "0.5, 4, 5, 1"))
    assert stopped.origin.line == 9 and "spindle off" in stopped.message
    # SDR 0: the automatic reversal needs the encoder (ENC 0)
    assert "alarm 61202" in refusal("sinumerik-828d",
                                    right.replace("0.5, 4, 3, 1", "0.5, 0, 3, 1")).message
    assert holes_and_spindle(right.replace("0.5, 4, 3, 1", "0.5, 0, , 0"))[-1] == ("Hole", "cw")


HEIDENHAIN = """0 BEGIN PGM A MM
1 TOOL CALL 1 Z S1000
2 L Z+50 R0 FMAX M3
3 CYCL DEF 200 DRILLING ~
{q}
4 L X+10 Y+10 R0 FMAX M99
5 END PGM A MM"""
Q200 = ("Q200=+2 ;SET-UP CLEARANCE ~", "Q201=-8 ;DEPTH ~", "Q206=+180 ;FEED RATE FOR PLNGNG ~",
        "Q202=+8 ;PLUNGING DEPTH ~", "Q210=+0 ;DWELL TIME AT TOP ~",
        "Q203=+0 ;SURFACE COORDINATE ~", "Q204=+30 ;2ND SET-UP CLEARANCE ~",
        "Q211=+0.5 ;DWELL TIME AT DEPTH")


def heidenhain(q: tuple[str, ...]) -> str:
    lines = [line if i < len(q) - 1 else line.rstrip(" ~") for i, line in enumerate(q)]
    return HEIDENHAIN.format(q="\n".join("  " + line for line in lines))


def test_heidenhain_cycle_parameters_are_read_in_the_order_of_the_cycle_definition() -> None:
    hole, = [e for e in events("heidenhain-tnc640", heidenhain(Q200))
             if type(e).__name__ == "Hole"]
    assert (hole.r, hole.bottom, hole.leave, hole.dwell) == (2, -8, 30, 0.5)
    swapped = (Q200[0], Q200[2], Q200[1], *Q200[3:])
    error = refusal("heidenhain-tnc640", heidenhain(swapped))
    assert error.origin.line == 12 and "Q206 where the cycle's definition has Q201" \
        in error.message
    missing = Q200[:4] + Q200[5:]
    assert "without Q210" in refusal("heidenhain-tnc640", heidenhain(missing)).message
    # Q395, added at the end in a later software version, may be left out or given there
    given = (*Q200[:-1], Q200[-1] + " ~", "Q395=+0 ;DEPTH REFERENCE")
    assert [type(e).__name__ for e in events("heidenhain-tnc640", heidenhain(given))
            ].count("Hole") == 1
