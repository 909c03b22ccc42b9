"""machines/linuxcnc.yaml against FreeCAD 0.20's own linuxcnc_post, line for line.

The references in tests/data/freecad/ were written by FreeCAD itself
(scripts/freecad_reference.py, README there): five jobs, each exported with
linuxcnc_post in nine option sets.  Only the ``(Output Time:…)`` header line is left
out of the comparison (it is the time of the export).

FreeCAD's post writes some programs LinuxCNC refuses (it never writes K, so a G18/G19
arc loses its centre; with --axis-modal it leaves out I/J equal to the last ones):
the post matches those only with ``parity``; its default output must pass rs274.
"""

from __future__ import annotations

import difflib
import re
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import pytest

from postdsl import api
from tests.conftest import DATA, MACHINES, ROOT, compiled_post
from tests.test_rs274_oracle import needs_rs274, rs274_process

FREECAD = DATA / "freecad"
NOW = datetime(2026, 11, 23, 11, 26, 20, tzinfo=UTC)

#: FreeCAD's option sets (scripts/freecad_reference.py OPTION_SETS) as the post's settings
OPTION_SETS: dict[str, dict[str, Any]] = {
    "default": {},
    "no_header": {"header": False},
    "no_comments": {"comments": False},
    "line_numbers": {"line_numbers": True},
    "precision4": {"precision": 4},
    "modal": {"header": False, "modal": True},
    "axis_modal": {"header": False, "axis_modal": True},
    "modal_axis_modal": {"header": False, "modal": True, "axis_modal": True},
    "preamble": {"header": False, "preamble": "G17 G90 G64 P0.01", "postamble": "M5 M2"},
}
#: FreeCAD's reference jobs (scripts/freecad_reference.py JOBS): the post reproduces all
JOBS = ["pocket", "helix", "raster", "planes", "drilling", "modal"]



def post_for(settings: dict[str, Any]) -> Any:
    """The LinuxCNC post with FreeCAD's arguments set as post options."""
    return compiled_post(MACHINES / "linuxcnc.yaml", settings)


def posted(job: str, settings: dict[str, Any], form: str = "dump.txt") -> list[str]:
    post = post_for(settings)
    commands = api.read_cl(FREECAD / f"{job}.{form}")
    text = api.post_text(post, api.post_commands(post, commands, cl_file=job, now=NOW))
    return text.splitlines()


def reference(job: str, option_set: str) -> list[str]:
    return (FREECAD / f"{job}.{option_set}.ngc").read_text(encoding="utf-8").splitlines()


def without_time(lines: list[str]) -> list[str]:
    return [line for line in lines if "(Output Time:" not in line]


def diff(expected: list[str], actual: list[str]) -> str:
    return "\n".join(difflib.unified_diff(expected, actual, "FreeCAD", "postdsl", lineterm=""))


@pytest.mark.parametrize("option_set", list(OPTION_SETS))
@pytest.mark.parametrize("job", JOBS)
def test_parity_matches_freecad_line_for_line(job: str, option_set: str) -> None:
    expected = without_time(reference(job, option_set))
    actual = without_time(posted(job, {**OPTION_SETS[option_set], "parity": True}))
    assert actual == expected, diff(expected, actual)


def test_the_header_states_the_time_where_freecad_does() -> None:
    expected, actual = reference("pocket", "default"), posted("pocket", {})
    assert expected[2].startswith("(Output Time:") and len(actual) == len(expected)
    assert actual[2] == "(Output Time:2026-11-23 11:26:20)"


@pytest.mark.parametrize("option_set", [s for s in OPTION_SETS if "axis_modal" not in s])
@pytest.mark.parametrize("job", JOBS)
def test_the_default_differs_only_by_k_of_g18_g19_arcs(job: str, option_set: str) -> None:
    """Without parity the post writes K where FreeCAD's drops it; nothing else differs."""
    expected = without_time(reference(job, option_set))
    actual = without_time(posted(job, OPTION_SETS[option_set]))
    with_k = [line for line in actual if " K" in line]
    assert ([line.split(" K")[0] + " F" + line.split(" F")[1] if " K" in line else line
             for line in actual] == expected), diff(expected, actual)
    assert bool(with_k) == (job == "planes")
    assert all(line.lstrip("N0123456789 ").startswith(("G2 ", "G3 ", "X")) for line in with_k)


@pytest.mark.parametrize("job", ["pocket", "helix"])
def test_axis_modal_keeps_the_arc_centre_unless_parity(job: str) -> None:
    """FreeCAD's --axis-modal leaves out I/J equal to the last given; the default keeps them."""
    settings = OPTION_SETS["axis_modal"]
    actual = without_time(posted(job, settings))
    expected = without_time(reference(job, "axis_modal"))
    arcs = [line for line in actual if line.startswith(("G2 ", "G3 "))]
    assert arcs and all(" I" in line and " J" in line for line in arcs)
    assert any(line.startswith(("G2 ", "G3 ")) and not (" I" in line and " J" in line)
               for line in expected)
    assert actual != expected


def rs274_errors(lines: list[str], tmp_path: Path) -> list[str]:
    program, table = tmp_path / "program.ngc", tmp_path / "tools.tbl"
    program.write_text("\n".join(lines) + "\n", encoding="utf-8")
    table.write_text("".join(f"T{n} P{n} Z0 D6\n" for n in range(1, 10)), encoding="utf-8")
    result = rs274_process(table, program)
    errors = [line for line in result.stderr.splitlines() if line.strip() != "executing"]
    return errors if result.returncode == 0 else [f"exit {result.returncode}", *errors]


@needs_rs274
@pytest.mark.parametrize("option_set", list(OPTION_SETS))
@pytest.mark.parametrize("job", JOBS)
def test_the_default_passes_rs274(job: str, option_set: str, tmp_path: Path) -> None:
    assert rs274_errors(posted(job, OPTION_SETS[option_set]), tmp_path) == []


@needs_rs274
def test_freecads_own_g18_arc_is_refused_by_rs274(tmp_path: Path) -> None:
    """Why parity is not the default: the K FreeCAD drops leaves a zero-radius arc."""
    errors = rs274_errors(reference("planes", "default"), tmp_path)
    assert any("Zero-radius arc" in line for line in errors), errors


#: lines of FreeCAD's output that come from the job's objects, not their commands: the
#: G-code form (Path.toGCode) has no object labels, and G54 is read as the CL's default
_OBJECT_LINES = ("(begin operation: ", "(finish operation: ", "(machine units: ", "G54 ")


def gcode_form_and_reference(job: str, option_set: str) -> tuple[list[str], list[str]]:
    """The post's output for the job's G-code form, and FreeCAD's without its object lines."""
    settings = {**OPTION_SETS[option_set], "parity": True}
    actual = without_time(posted(job, settings, form="gcode"))
    expected = [line for line in without_time(reference(job, option_set))
                if not line.lstrip("N0123456789 ").startswith(_OBJECT_LINES)]
    if option_set == "line_numbers":  # the numbers differ by the lines left out
        actual = [re.sub(r"^N\d+ ", "", line) for line in actual]
        expected = [re.sub(r"^N\d+ ", "", line) for line in expected]
    return actual, expected


#: FreeCAD's axis_modal forgets the last words at each object; the G-code form has no
#: objects, so there the post leaves out words FreeCAD repeats (test below).  The form
#: cannot tell where an object starts.  What each object's path begins with (FreeCAD
#: 0.20 source): an operation (PathOp.execute) "(Label)" and, when its Comment is set,
#: "(Comment)"; a tool controller (toolchange_generator) "(Label)" then "M6 T"; PathPost's
#: fixture object the work offset ("G54") then "G0 Z"; a Comment object "(its text)" and
#: nothing else; a Stop object "M0"/"M1"; a Custom operation "(Label)" "(Begin Custom)"
#: and then the user's own G-code, comments included; a dressup its base operation's path
#: (the base's label, not its own).  So "(A)" "(B)" is an operation A with the comment B,
#: or a Comment object A and then an operation B -- and a Custom operation's G-code may
#: hold any comment lines, "(End Custom)" and another label included.  Reading a comment
#: as an object start would be a guess, and a wrong guess writes words FreeCAD does not.
_ACROSS_OBJECTS = {("drilling", "axis_modal"), ("drilling", "modal_axis_modal")}


@pytest.mark.parametrize(("job", "option_set"), [
    (job, option_set) for job in JOBS for option_set in OPTION_SETS
    if (job, option_set) not in _ACROSS_OBJECTS])
def test_the_gcode_form_gives_the_same_moves(job: str, option_set: str) -> None:
    actual, expected = gcode_form_and_reference(job, option_set)
    assert actual == expected, diff(expected, actual)


@pytest.mark.parametrize(("job", "option_set"), sorted(_ACROSS_OBJECTS))
def test_the_gcode_form_has_no_objects(job: str, option_set: str) -> None:
    """Where FreeCAD's axis_modal starts a new object it writes the words again (its
    parse() state is per object); the G-code form has no objects, so the post leaves
    them out there (the G0 Z and the R of the operation's first hole) and nowhere else."""
    actual, expected = gcode_form_and_reference(job, option_set)
    assert len(actual) == len(expected)
    differing = [(want, got) for want, got in zip(expected, actual, strict=True)
                 if want != got]
    assert len(differing) == 4  # Drilling001 and Drilling002: the G0 Z10 and the R1
    assert all(set(got.split()) < set(want.split()) for want, got in differing)
    assert {word for want, got in differing for word in set(want.split()) - set(got.split())
            } == {"Z10.000", "R1.000"}


@needs_rs274
@pytest.mark.parametrize("program", ["tests/data/emco_thesis.dump.txt",
                                     "examples/emco_pocket.gcode",
                                     "examples/feeler_milling.apt",
                                     "examples/linuxcnc_rigid_tapping.jsonl"])
def test_the_corpus_programs_pass_rs274(program: str, tmp_path: Path) -> None:
    post = api.load_post(MACHINES / "linuxcnc.yaml")
    lines = api.post_commands(post, api.read_cl(ROOT / program), cl_file=program, now=NOW)
    assert rs274_errors(api.post_text(post, lines).splitlines(), tmp_path) == []


@pytest.mark.parametrize(("start_z", "expected"), [
    (2.0, ["G0 Z20.000 ", "G0 X10.000 Y10.000 ", "G98 "]),    # up first, then sideways
    (50.0, ["G0 X10.000 Y10.000 ", "G0 Z20.000 ", "G98 "]),   # sideways first, then down
])
def test_g98_starts_the_cycle_from_the_retract_plane(start_z: float, expected: list[str],
                                                      tmp_path: Path) -> None:
    """G98 returns to the Z the cycle started from: the tool is put at the CL's retract."""
    program = tmp_path / "holes.jsonl"
    program.write_text("\n".join([
        '{"cmd": "tool_change", "tool_number": 1}',
        '{"cmd": "spindle_on", "spindle_speed": 1000, "spindle": "cw"}',
        f'{{"cmd": "rapid_move", "x": 0, "y": 0, "z": {start_z}}}',
        '{"cmd": "cycle_start"}',
        '{"cmd": "single_peck", "x": 10, "y": 10, "top": 0, "depth": 5, "clearance": 2, '
        '"retract": 20, "feed": 100}',
        '{"cmd": "cycle_hole", "x": 30, "y": 10}',
        '{"cmd": "cycle_end"}', '{"cmd": "program_end"}']) + "\n", encoding="utf-8")
    post = post_for({})
    commands = api.read_cl(program)
    lines = api.post_text(post, api.post_commands(post, commands, now=NOW)).splitlines()
    cycle = lines.index("G81 X10.000 Y10.000 Z-5.000 F100.000 R2.000 ")
    assert lines[cycle - 3:cycle] == expected
    assert lines[cycle + 1:cycle + 3] == ["G81 X30.000 Y10.000 Z-5.000 F100.000 R2.000 ", "G80 "]
    assert api.verify_commands(post, commands, now=NOW).ok


def test_the_bundled_example_is_the_pocket_reference_job() -> None:
    """examples/linuxcnc_pocket.dump.txt (the editor's sample) is FreeCAD's, not a copy edited."""
    example = ROOT / "examples" / "linuxcnc_pocket.dump.txt"
    assert example.read_bytes() == (FREECAD / "pocket.dump.txt").read_bytes()


@needs_rs274
def test_axis_modal_drilling_keeps_r_and_p_unless_parity(tmp_path: Path) -> None:
    """FreeCAD's --axis-modal drops R (and P) equal to the last cycle's: rs274 refuses a
    new cycle without R.  The default writes them on every hole; parity drops them."""
    assert "R clearance plane unspecified in cycle" in rs274_errors(
        reference("drilling", "axis_modal"), tmp_path)
    for settings, kept in ((OPTION_SETS["axis_modal"], True),
                           ({**OPTION_SETS["axis_modal"], "parity": True}, False)):
        holes = [line for line in posted("drilling", settings)
                 if line.startswith(("G81 ", "G82 ", "G83 "))]
        assert len(holes) == 9
        assert all(" R1.000 " in line for line in holes) is kept
        assert all(" P0.500 " in line for line in holes if line.startswith("G82 ")) is kept


def _cycle(ended_by: str, then: list[str]) -> list[str]:
    """A native CL program: one G81 hole at X10 Y10, its cycle ended by ``ended_by``."""
    return [
        '{"cmd": "tool_change", "tool_number": 1}',
        '{"cmd": "spindle_on", "spindle_speed": 1000, "spindle": "cw"}',
        '{"cmd": "rapid_move", "x": 10, "y": 10, "z": 5}',
        '{"cmd": "cycle_start"}',
        '{"cmd": "single_peck", "x": 10, "y": 10, "top": 0, "depth": 5, "clearance": 2, '
        '"feed": 100}',
        f'{{"cmd": "cycle_end", "ended_by": "{ended_by}"}}', *then,
        '{"cmd": "program_end"}']


_AWAY = ['{"cmd": "rapid_move", "z": 20}']
_NEXT = ['{"cmd": "cycle_start"}',
         '{"cmd": "deep_drill", "x": 30, "y": 10, "top": 0, "depth": 5, "clearance": 2, '
         '"peck": 1, "feed": 100}', '{"cmd": "cycle_end"}']


@needs_rs274
@pytest.mark.parametrize(("ended_by", "then", "parity", "cancels"), [
    ("cancel", _AWAY, False, True),
    ("cancel", _AWAY, True, True),
    ("other", ['{"cmd": "comment", "comment": "up"}', *_AWAY], False, True),
    ("other", ['{"cmd": "comment", "comment": "up"}', *_AWAY], True, False),  # as FreeCAD
    ("motion", _AWAY, False, False),        # the G0 ends the cycle, as RS274 reads it
    ("next_cycle", _NEXT, False, False),    # G83 follows G81 directly
])
def test_g80_where_the_input_cancelled_the_cycle(ended_by: str, then: list[str], parity: bool,
                                               cancels: bool, tmp_path: Path) -> None:
    program = tmp_path / "hole.jsonl"
    program.write_text("\n".join(_cycle(ended_by, then)) + "\n", encoding="utf-8")
    post = post_for({"parity": parity})
    commands = api.read_cl(program)
    lines = api.post_text(post, api.post_commands(post, commands, now=NOW)).splitlines()
    hole = lines.index("G81 X10.000 Y10.000 Z-5.000 F100.000 R2.000 ")
    assert (lines[hole + 1] == "G80 ") is cancels
    assert api.verify_commands(post, commands, now=NOW).ok
    assert rs274_errors(lines, tmp_path) == []


@needs_rs274
def test_the_input_modes_are_echoed_but_never_g91(tmp_path: Path) -> None:
    """FreeCAD's post echoes G90, G17-G19, G98/G99 where its path has them; the CL's
    coordinates are absolute, so an input's G91 is not written (its moves are)."""
    program = tmp_path / "modes.gcode"
    program.write_text("\n".join([
        "G90", "G17", "M6 T1", "M3 S1000", "G0 X0 Y0 Z10", "G91", "G1 X5 F1", "G90",
        "G18", "G2 X10 Z10 I2.5 K0", "G17", "G98", "G81 X1 Y1 Z-5 R2 F1", "G80", "M2"]) + "\n",
        encoding="utf-8")
    post = post_for({"header": False, "comments": False})
    commands = api.read_cl(program, feed_units="mm/s")
    lines = api.post_text(post, api.post_commands(post, commands, now=NOW)).splitlines()
    body = lines[lines.index("G21") + 1:lines.index("M05")]
    assert body == [
        "G90 ", "G17 ", "M5", "M6 T1 ", "G43 H1 ", "M3 S1000 ", "G0 X0.000 Y0.000 Z10.000 ",
        "G1 X5.000 F60.000 ", "G90 ", "G18 ", "G2 X10.000 Z10.000 I2.500 K0.000 ",
        # the cycle goes over the hole at the G98 level itself (RS274's first move of a
        # cycle, from at or above R), as FreeCAD writes it: no G0 X1 Y1 before it
        "G17 ", "G98 ", "G81 X1.000 Y1.000 Z-5.000 F60.000 R2.000 ", "G80 "]
    assert api.verify_commands(post, commands, now=NOW).ok
    assert rs274_errors(lines, tmp_path) == []


_TAPS = [
    '{"cmd": "tool_change", "tool_number": 2}',
    '{"cmd": "spindle_on", "spindle_speed": 500, "spindle": "cw"}',
    '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 30}',
    '{"cmd": "cycle_start"}',
    '{"cmd": "tapping", "x": 10, "y": 10, "top": 0, "depth": 12, "clearance": 3, '
    '"retract": 20, "dwell": 0.3, "feed": 625}',
    '{"cmd": "cycle_hole", "x": 30, "y": 10}',
    '{"cmd": "cycle_end"}',
    '{"cmd": "spindle_on", "spindle_speed": 500, "spindle": "ccw"}',
    '{"cmd": "cycle_start"}',
    '{"cmd": "tapping_ccw", "x": 50, "y": 10, "top": 0, "depth": 12, "clearance": 3, '
    '"feed": 625}',
    '{"cmd": "cycle_end"}',
    '{"cmd": "program_end"}']


def _post_lines(records: list[str], tmp_path: Path, settings: dict[str, Any] | None = None
                ) -> tuple[list[str], Any, list[Any]]:
    program = tmp_path / "taps.jsonl"
    program.write_text("\n".join(records) + "\n", encoding="utf-8")
    post = post_for({"header": False, "comments": False, **(settings or {})})
    commands = api.read_cl(program)
    return api.post_text(post, api.post_commands(post, commands, now=NOW)).splitlines(), \
        post, commands


@needs_rs274
def test_taps_are_g84_and_g74_with_p_on_every_tap(tmp_path: Path) -> None:
    """A floating-holder tap: G84 right hand under M3, G74 left hand under M4, F the CL's
    feed (pitch x rpm).  P is written on every tap, P0 too: LinuxCNC keeps P from one
    cycle to the next, and the G74 would dwell the G84's 0.3 s."""
    lines, post, commands = _post_lines(_TAPS, tmp_path)
    body = lines[lines.index("G43 H2 ") + 1:lines.index("M05")]
    assert body == [
        "M3 S500 ", "G0 X0.000 Y0.000 Z30.000 ",
        "G0 X10.000 Y10.000 ", "G0 Z20.000 ", "G98 ",   # to the retract, which G98 returns to
        "G84 X10.000 Y10.000 Z-12.000 F625.000 R3.000 P0.300 ",
        "G84 X30.000 Y10.000 Z-12.000 F625.000 R3.000 P0.300 ", "G80 ",
        "M4 S500 ", "G99 ",                              # no retract given: back to R
        "G74 X50.000 Y10.000 Z-12.000 F625.000 R3.000 P0.000 ", "G80 "]
    assert api.verify_commands(post, commands, now=NOW).ok
    assert rs274_errors(lines, tmp_path) == []


@pytest.mark.parametrize(("change", "message"), [
    (('"spindle": "ccw"}', '"spindle": "cw"}'), "G74 taps left-hand"),
    (('"spindle": "cw"}', '"spindle": "ccw"}'), "G84 taps right-hand"),
    (('"dwell": 0.3,', '"peck": 2,'), "tap in one stroke"),
    # a rigid tap (G33.1) has no dwell, no peck, and taps the way the spindle turns
    (('"cmd": "tapping"', '"cmd": "rigid_tapping"'), "rigid tap with a dwell cannot"),
])
def test_a_tap_linuxcnc_cannot_cut_as_given_is_refused_at_its_line(
        change: tuple[str, str], message: str, tmp_path: Path) -> None:
    records = [line.replace(*change) for line in _TAPS]
    with pytest.raises(api.CLError) as caught:
        _post_lines(records, tmp_path)
    assert message in str(caught.value) and caught.value.location is not None


@needs_rs274
@pytest.mark.parametrize(("start_z", "expected"), [
    (1.0, ["G98 ", "G81 X1.000 Y1.000 Z-5.000 F60.000 R2.000 "]),   # G98 from below R: as G99
    (2.0, ["G98 ", "G81 X1.000 Y1.000 Z-5.000 F60.000 R2.000 "]),   # from R itself
    # from above R: the cycle's own first move goes over the hole at that height
    (9.0, ["G98 ", "G81 X1.000 Y1.000 Z-5.000 F60.000 R2.000 "]),
])
def test_a_g98_the_input_wrote_is_kept_where_it_returns_to_r(
        start_z: float, expected: list[str], tmp_path: Path) -> None:
    """LinuxCNC's G98 returns to the higher of the start Z and R: from at or below R it is
    G99's return, so the post keeps FreeCAD's G98 and writes no G99 after it."""
    program = tmp_path / "low.gcode"
    program.write_text(f"G90\nM6 T1\nM3 S1000\nG0 X0 Y0 Z{start_z:g}\nG98\n"
                       "G81 X1 Y1 Z-5 R2 F1\nG80\nG0 Z20\nM2\n", encoding="utf-8")
    post = post_for({"header": False, "comments": False})
    commands = api.read_cl(program, feed_units="mm/s")
    lines = api.post_text(post, api.post_commands(post, commands, now=NOW)).splitlines()
    start = lines.index(f"G0 X0.000 Y0.000 Z{start_z:.3f} ")
    assert lines[start + 1:lines.index("G80 ")] == expected
    assert api.verify_commands(post, commands, now=NOW).ok
    assert rs274_errors(lines, tmp_path) == []


_RIGID = [line.replace('"cmd": "tapping"', '"cmd": "rigid_tapping"').replace('"dwell": 0.3, ', '')
          for line in _TAPS]


@needs_rs274
def test_rigid_taps_are_g33_1_from_r_and_back_up(tmp_path: Path) -> None:
    """LinuxCNC's G33.1 taps from where the tool is to Z at K (feed / speed) and back:
    over the hole, down to R at rapid, G33.1, up to the retract plane; right hand under
    M3, left hand under M4; no G80 (no cycle was started)."""
    records = [line.replace('"cmd": "tapping_ccw"', '"cmd": "rigid_tapping_ccw"')
               for line in _RIGID]
    lines, post, commands = _post_lines(records, tmp_path)
    body = lines[lines.index("G43 H2 ") + 1:lines.index("M05")]
    assert body == [
        "M3 S500 ", "G0 X0.000 Y0.000 Z30.000 ",
        "G0 X10.000 Y10.000 ", "G0 Z3.000 ", "G33.1 Z-12.000 K1.2500 ", "G0 Z20.000 ",
        "G0 X30.000 ", "G0 Z3.000 ", "G33.1 Z-12.000 K1.2500 ", "G0 Z20.000 ",
        "M4 S500 ",
        "G0 X50.000 ", "G0 Z3.000 ", "G33.1 Z-12.000 K1.2500 "]  # no retract: left at R
    result = api.verify_commands(post, commands, now=NOW)
    assert result.ok, result
    assert rs274_errors(lines, tmp_path) == []


def test_a_rigid_tap_from_below_the_retract_plane_goes_up_before_moving_over(
        tmp_path: Path) -> None:
    records = [line.replace('"z": 30', '"z": 1') for line in _RIGID[:6]] + [
        '{"cmd": "cycle_end"}', '{"cmd": "program_end"}']
    lines, post, commands = _post_lines(records, tmp_path)
    start = lines.index("G0 X0.000 Y0.000 Z1.000 ")
    assert lines[start + 1:start + 5] == ["G0 Z20.000 ", "G0 X10.000 Y10.000 ", "G0 Z3.000 ",
                                          "G33.1 Z-12.000 K1.2500 "]
    assert api.verify_commands(post, commands, now=NOW).ok


def _one_rigid_hole(speed: float, feed: float, spindle: str = "cw", extra: str = "") -> list[str]:
    return [
        '{"cmd": "tool_change", "tool_number": 2}',
        f'{{"cmd": "spindle_on", "spindle_speed": {speed}, "spindle": "{spindle}"}}',
        '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 30}', '{"cmd": "cycle_start"}',
        '{"cmd": "rigid_tapping", "x": 10, "y": 10, "top": 0, "depth": 12, "clearance": 3, '
        f'"retract": 20, "feed": {feed}{extra}}}', '{"cmd": "cycle_end"}',
        '{"cmd": "program_end"}']


@pytest.mark.parametrize(("records", "message"), [
    (_one_rigid_hole(500, 625, spindle="ccw"), "right-hand rigid tap needs it turning clockwise"),
    (_one_rigid_hole(500, 625, extra=', "peck": 3'), "a pecked rigid tap cannot be written"),
    (_one_rigid_hole(500, 625, extra=', "dwell": 0.2'), "a rigid tap with a dwell cannot"),
    # 0.700049 mm/rev at 12000 rpm: K0.7000 feeds 8400.0, 0.59 mm/min off the CL's feed
    (_one_rigid_hole(12000, 8400.588), "the pitch K (feed / speed, 4 decimals) does not give"),
])
def test_a_rigid_tap_linuxcnc_cannot_cut_as_given_is_refused(records: list[str], message: str,
                                                             tmp_path: Path) -> None:
    with pytest.raises(api.CLError) as caught:
        _post_lines(records, tmp_path)
    assert message in str(caught.value) and caught.value.location is not None


def test_a_pitch_four_decimals_give_within_half_a_mm_per_min_is_written(tmp_path: Path) -> None:
    """0.69444 mm/rev at 3000 rpm: K0.6944 feeds 2083.2, 0.13 mm/min off: written, verified."""
    lines, post, commands = _post_lines(_one_rigid_hole(3000, 2083.33), tmp_path)
    assert "G33.1 Z-12.000 K0.6944 " in lines
    assert api.verify_commands(post, commands, now=NOW).ok


@pytest.mark.parametrize(("override", "divergence"), [
    # no rapid up after the tap: the tool stays at R, below the CL's retract plane
    ("structures/rigid_tap/5: {if: 'false', items: ['G0 ']}",
     "hole 1: the tool is left at Z3.000, below the CL's retract Z20.000"),
    # the pitch as feed / speed doubled: the tap feeds at twice the CL's feed
    ("structures/rigid_tap/4/items/3: {expr: 'feed / spindle_speed * 2', prefix: K, "
     "suffix: ' ', format: pitch}", "hole 1: feed 1250.000 mm/min, CL says 625"),
    # the tap started from the retract plane, not R
    ("structures/rigid_tap/3/items/2: {param: retract, prefix: Z, suffix: ' ', format: coord, "
     "modal: z}", "hole 1: R level Z20.000, CL says R level Z3.000"),
])
def test_verify_catches_a_post_that_writes_g33_1_wrong(override: str, divergence: str,
                                                       tmp_path: Path) -> None:
    broken = tmp_path / "broken.yaml"
    broken.write_text(f"postdsl: 1\nextends: {MACHINES / 'linuxcnc.yaml'}\n"
                      f"override:\n  {override}\n", encoding="utf-8")
    program = tmp_path / "tap.jsonl"
    program.write_text("\n".join(_one_rigid_hole(500, 625)) + "\n", encoding="utf-8")
    post = api.load_post(broken)
    commands = api.read_cl(program)
    result = api.verify_commands(post, commands, now=NOW)
    assert not result.ok and divergence in str(result), str(result)


#: jobs FreeCAD posted that the post was not written against (scripts/freecad_random_jobs.py):
#: random cuts, arcs and drilling groups, in the modal option sets and the default
RANDOM = FREECAD / "random"
RANDOM_SETS = ["modal", "axis_modal", "modal_axis_modal", "default"]


def _random_posted(job: str, option_set: str, parity: bool) -> tuple[list[str], bool]:
    post = post_for({**OPTION_SETS[option_set], "header": False, "parity": parity})
    commands = api.read_cl(RANDOM / f"{job}.dump.txt")
    text = api.post_text(post, api.post_commands(post, commands, cl_file=job, now=NOW))
    return text.splitlines(), api.verify_commands(post, commands, cl_file=job, now=NOW).ok


_RANDOM_JOBS = sorted(p.name.split(".")[0] for p in RANDOM.glob("*.dump.txt"))


@pytest.mark.parametrize("option_set", RANDOM_SETS)
@pytest.mark.parametrize("job", _RANDOM_JOBS)
def test_parity_matches_freecad_on_random_jobs(job: str, option_set: str) -> None:
    expected = (RANDOM / f"{job}.{option_set}.ngc").read_text(encoding="utf-8").splitlines()
    actual, _ = _random_posted(job, option_set, parity=True)
    assert actual == expected, diff(expected, actual)


@pytest.mark.parametrize("option_set", RANDOM_SETS)
@pytest.mark.parametrize("job", _RANDOM_JOBS)
def test_without_parity_random_jobs_verify(job: str, option_set: str) -> None:
    """FreeCAD's --axis-modal leaves out R (Q, P) on a new cycle and I J of an arc (verify
    refuses its output); without parity the post writes them, and the Z of a further hole
    (it keeps no bottom as the last Z: the tool is at the retract plane), and nothing
    else, and the program does what the job says.  Without --axis-modal the two agree."""
    expected = (RANDOM / f"{job}.{option_set}.ngc").read_text(encoding="utf-8").splitlines()
    actual, verified = _random_posted(job, option_set, parity=False)
    assert verified
    if "axis_modal" not in option_set:
        assert actual == expected, diff(expected, actual)
    else:
        assert len(actual) == len(expected)
        for want, got in zip(expected, actual, strict=True):
            assert set(want.split()) <= set(got.split())
            assert {word[0] for word in set(got.split()) - set(want.split())} <= set("RIJQPZ")


def test_the_random_jobs_are_there() -> None:
    assert len(list(RANDOM.glob("*.dump.txt"))) == 6
    assert all((RANDOM / f"r{seed}.{s}.ngc").is_file() for seed in range(6) for s in RANDOM_SETS)


@needs_rs274
@pytest.mark.parametrize("option_set", RANDOM_SETS)
@pytest.mark.parametrize("job", _RANDOM_JOBS)
def test_without_parity_random_jobs_pass_rs274(job: str, option_set: str,
                                               tmp_path: Path) -> None:
    actual, _ = _random_posted(job, option_set, parity=False)
    assert rs274_errors(actual, tmp_path) == []
