"""Each control model reads the words of a line as its control does (issue 25).

Comments by each control's syntax (``postdsl.control_syntax.COMMENTS``): parentheses
end at the first ``)``, ``;`` runs to the end of the line only outside them, ``%`` as
the control treats it; M2/M30 end the program.  Where LinuxCNC's interpreter ``rs274``
reads the same text, it is asked too.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from postdsl.controls import ControlError, control_model
from postdsl.controls.events import FeedMove, Rapid, SpindleChanged
from tests.test_rs274_oracle import RS274, needs_rs274, run_rs274

TOOLS = RS274.parent / "tool.tbl"


def events(control: str, program: str, **settings: bool) -> list:
    return list(control_model(control, **settings).replay(program.strip().splitlines()))


def feeds(control: str, program: str, **settings: bool) -> list[tuple]:
    return [e.end for e in events(control, program, **settings) if isinstance(e, FeedMove)]


def rs274_errors(program: Path) -> str:
    """What rs274 prints for a program it refuses."""
    result = subprocess.run([str(RS274), "-t", str(TOOLS), "-g", str(program)],
                            capture_output=True, text=True, stdin=subprocess.DEVNULL,
                            timeout=60, check=False)
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
    # ... a '%' line in a file that did not start with one is an error (rs274 agrees)
    assert "'%'" in refusal("linuxcnc", ISO_START + "%\nG1 Z-1 F9").message
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
    result = rs274_errors(bare)
    assert "Bad character '%'" in result


def test_sinumerik_and_acramatic_comments_run_from_the_semicolon() -> None:
    moves = [e for e in events("sinumerik-828d", "G0 X1 Y2 Z3 ;a (b\nG0 X4 ; c)")
             if isinstance(e, Rapid)]
    assert [m.end for m in moves] == [(1, 2, 3), (4, 2, 3)]
