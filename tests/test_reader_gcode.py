"""The plain G-code reader (postdsl/cl/gcode.py) and the moves before the first tool.

* Each word of RS274 G-code as CAM systems write it: what it becomes in the CL, or the
  located refusal with its reason.
* The programs written in CAM systems' styles (tests/data/real/styled_*, SOURCES.md)
  posted with the LinuxCNC and Fanuc posts: LinuxCNC's rs274 runs the posted program
  and the program itself, and every cut (feed move and arc, canned cycles expanded by
  rs274) must start, end, turn and feed alike.
* FreeCAD's Job starts with ``G54`` and ``G0 Z<clearance>`` before its first tool: a
  safe_retract, which every post with a tool changer now posts (its tool change
  retracts Z first); every FreeCAD reference job posts there and verifies, and rs274
  finds the Fanuc-family output cutting as FreeCAD's own LinuxCNC output does.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import pytest

from postdsl import api
from postdsl.cl.model import (
    ArcMove,
    Comment,
    InputModes,
    LinearMove,
    MachineRetract,
    OptionalStop,
    ProgramEnd,
    ProgramStart,
    ProgramStop,
    RapidMove,
    SafeRetract,
    SpindleOn,
    ToolChange,
    WorkOffset,
)
from postdsl.cl.readers import detect_format, read_cl_text
from postdsl.errors import CLError
from tests.conftest import DATA, MACHINES, THESIS_TIME
from tests.test_rs274_oracle import for_rs274, needs_rs274, rs274_process

REAL = DATA / "real"
FREECAD = DATA / "freecad"


def read(text: str) -> list:
    """The records of a G-code program (without program_start/program_end)."""
    records = read_cl_text(text.strip() + "\n", "job.nc", "gcode")
    return [r for r in records if not isinstance(r, (ProgramStart, ProgramEnd))]


def refused(text: str) -> CLError:
    with pytest.raises(CLError) as caught:
        read_cl_text(text.strip() + "\n", "job.nc", "gcode")
    return caught.value


# --- the words ----------------------------------------------------------------------------


def test_a_block_runs_in_rs274s_order_of_execution() -> None:
    """S and M3 on a motion block start the spindle before the move; T1 M6, T1M6, M6 T1,
    N2 T1 M6 and T1 then M6 all load tool 1."""
    records = read("T1 M6\nG0 X0 Y0 S15000 M3\nM30")
    assert records == [ToolChange(tool_number=1), SpindleOn(spindle_speed=15000, spindle="cw"),
                       RapidMove(x=0, y=0)]
    for block in ("T1M6", "M6 T1", "N2 T1 M6", "T1\nM6", "t1 m06"):
        assert read(f"{block}\nM30")[0] == ToolChange(tool_number=1), block


def test_feed_and_speed_alone_on_a_block_are_modal() -> None:
    """F alone is the feed of the next cutting move (which carries it, since the CL's feed
    in force is the last move's); S alone sets the speed, or changes it while turning."""
    records = read("T1 M6\nF200\nS1000\nM3\nG1 X1 F300\nF500\nG1 X2\nG1 X3\nS2000\nM30")
    assert records == [
        ToolChange(tool_number=1), SpindleOn(spindle_speed=1000, spindle="cw"),
        LinearMove(x=1, feed=300), LinearMove(x=2, feed=500), LinearMove(x=3),
        SpindleOn(spindle_speed=2000, spindle="cw")]


def test_comments_after_code_and_alone_become_comment_records() -> None:
    records = read("G40 (disable tool radius compensation)\n; note\nG0 X1 ; go\nM2")
    assert records == [Comment(comment="disable tool radius compensation"),
                       Comment(comment="note"), Comment(comment="go"), RapidMove(x=1)]


def test_path_modes_are_facts() -> None:
    records = read("G61\nG64 P0.01\nG61.1\nG94\nM2")
    assert records == [InputModes(path_mode="exact_stop"),
                       InputModes(path_mode="blend", path_tolerance=0.01),
                       InputModes(path_mode="exact_path")]


def test_inches_are_converted_exactly() -> None:
    """Every length and feed after G20 is the decimal written times 25.4, rounded once
    (0.1 inch is 2.54 mm exactly, where 0.1 * 25.4 in floating point is not)."""
    records = read("G20\nT1 M6\nG0 X0.1 Y0 Z0.6\nG1 Z-0.02 F20.\nG2 X0.45 Y0.35 I0 J0.35\n"
                   "G21\nG1 X1\nM30")
    rapid, feed, arc, mm = records[1:]
    assert (rapid.x, rapid.z) == (2.54, 15.24)
    assert (feed.z, feed.feed) == (-0.508, 508.0)
    assert (arc.x, arc.y, arc.cx, arc.cy) == (11.43, 8.89, 2.54, 8.89)
    assert mm.x == 1.0
    assert read("G20\nG64 P0.001\nM2") == [InputModes(path_mode="blend", path_tolerance=0.0254)]


def test_a_g28_or_g53_retract_of_z_is_a_machine_retract() -> None:
    records = read("T1 M6\nG0 X1 Y1 Z5\nG28 G91 Z0.\nG90\nG53 G0 Z-5.\nG0 Z5\nM30")
    retracts = [r for r in records if isinstance(r, MachineRetract)]
    assert retracts == [MachineRetract(), MachineRetract(machine_z=-5.0)]


@pytest.mark.parametrize(("program", "line", "reason"), [
    ("G0 X1\nG41.1 D6\nM2", 2, "dynamic cutter compensation (G41.1: a diameter in the "
                                "program) is not read"),
    ("G42.1 D6\nM2", 1, "dynamic cutter compensation (G42.1"),
    ("G0 X1\nG41 D1.5\nM2", 2, "D must be a register number"),
    ("G0 X1\nG1 X2 D1 F100\nM2", 2, "D is not a word of this block"),
    ("G95\nG1 X1 F0.1\nM2", 2, "per revolution (G95) with no spindle speed S in force"),
    ("G93\nM2", 1, "inverse-time feed (G93) is not read"),
    ("G54.1 P3\nM2", 1, "extended work offsets (G54.1 P) are not read from G-code"),
    ("G59.1\nM2", 1, "work offset G59.1 is not read"),
    ("#1 = 5\nM2", 1, "parameters ('#') and expressions ('[…]') are not read"),
    ("G1 X[1+2] F5\nM2", 1, "parameters ('#') and expressions"),
    ("O100 sub\nM2", 1, "O words (subprograms, loops, program numbers) are not read"),
    ("o100 call\nM2", 1, "O words"),
    ("/G0 X1\nM2", 1, "block delete ('/') is not read"),
    ("G28 X0 Y0\nM2", 1, "G28 moves in machine coordinates"),
    ("G53 Z0\nM2", 1, "G53 is read only as a rapid to an absolute machine Z"),
    ("G53 G1 Z0 F100\nM2", 1, "G53 moves in machine coordinates (other words)"),
    ("G0 X1\nG28 G90 Z10\nM2", 2, "G28 through another Z than the tool's own"),
    ("G90.1\nM2", 1, "absolute arc centres (G90.1) are not read"),
    ("G0 G1 X1\nM2", 1, "two motion codes (G0 G1) in one block"),
    ("G0 X1 S100\nM2", None, None),  # S alone on a block with a move: a speed, no error
    ("G0 X1\nG4 P1 Q2\nM2", 2, "Q is not a word of this block"),
    ("X1 Y1\nM2", 1, "axis words without a motion mode"),
    ("G0 X1 X2\nM2", 1, "two X words in one block"),
    ("G0 X1\nM30\nG0 X2", 3, "nothing may follow the program end"),
    ("G0 X1\nG0 X2", 2, "the program ends without M2 or M30"),
    ("G0 X1\n%\nG0 X2\nM2", 2, "'%' inside the program"),
    ("G0 X1 (open\nM2", 1, "a comment is not closed"),
    ("M6\nM2", 1, "M6 needs a tool number T"),
    ("G65 P9810\nM2", 1, "G65 is not a code this reader knows"),
    ("G0 X0 Y0\nG2 X1 Y0 R0.4\nM2", 2, "the radius R0.4 is too short for the arc's chord"),
    ("G0 X0 Y0\nG2 X0 Y0 R1\nM2", 2, "with its end point at its start point"),
    ("G0 X0 Y0\nG2 X1 Y1 I1 R1\nM2", 2, "an arc with both R and I J K"),
    ("G2 X1 Y1 R1\nM2", 1, "G2 before the tool position is known"),
])
def test_what_the_cl_cannot_carry_is_refused_at_its_line(program: str, line: int | None,
                                                        reason: str | None) -> None:
    if line is None:
        read(program)
        return
    error = refused(program)
    assert error.location is not None and error.location.line == line, str(error)
    assert reason is not None and reason in error.message
    assert str(error).startswith(f"job.nc:{line}")


def test_work_offsets_and_stops_are_read_as_rs274_runs_them() -> None:
    """G55 selects work offset 2, G54 the first again; M0 on a move block stops after the
    move (RS274 runs a stop last), M1 alone is the optional stop."""
    assert read("G0 X1 Y1\nG55\nG0 X2 M0\nM1\nG54\nM30") == [
        RapidMove(x=1, y=1), WorkOffset(work_offset_index=2), RapidMove(x=2), ProgramStop(),
        OptionalStop(), WorkOffset(work_offset_index=1)]
    error = refused("G0 X1\nG30 G91 Z0\nM30")
    assert error.location is not None and error.location.line == 2
    assert "a return to the second reference point" in error.message


def test_tape_marks_and_block_numbers_are_read() -> None:
    assert read("%\nN10 G0 X1\nN20 M30\n%") == [RapidMove(x=1)]


def test_plain_gcode_is_detected_by_evidence() -> None:
    """A file another CAM wrote goes to the G-code reader: a T before M6, an S or F alone,
    or only what every RS274 program writes (G21, N, %) without FreeCAD's banner."""
    assert detect_format(["G21", "T1 M6", "G0 X1"]) == "gcode"
    assert detect_format(["F200", "S1000", "G0 X1"]) == "gcode"
    assert detect_format(["G21", "G0 X1", "G1 X2 F100"]) == "gcode"
    assert detect_format(["(Exported by FreeCAD)", "G21", "G0 X1"]) == "freecad"
    assert detect_format(["G0 X1.000000", "G1 X2.000000 F1.000000"]) == "freecad"
    for name in (p.name for p in REAL.glob("styled_*")):
        lines = (REAL / name).read_text(encoding="utf-8").splitlines()
        assert detect_format(lines) == "gcode", name


# --- moves before the first tool ----------------------------------------------------------

TOOL_CHANGER_POSTS = ("fanuc", "heidenhain", "emco", "vmc500", "feeler")
JOBS = ("pocket", "helix", "drilling", "raster", "planes", "modal")


def test_the_jobs_go_safe_before_its_first_tool_is_a_safe_retract() -> None:
    commands = api.read_cl(FREECAD / "pocket.default.ngc")
    first_tool = next(i for i, c in enumerate(commands) if isinstance(c, ToolChange))
    before = [c for c in commands[:first_tool]
              if isinstance(c, (RapidMove, SafeRetract, LinearMove, ArcMove))]
    assert before == [SafeRetract(z=15.0)]
    assert before[0].line == 10


def test_motion_in_x_or_y_before_any_tool_stays_refused_without_the_tool_changer_hint(
        ) -> None:
    program = "G54\nG0 Z15\nG0 X10 Y10\nM6 T1\nM30\n"
    for machine in TOOL_CHANGER_POSTS:
        with pytest.raises(CLError) as caught:
            api.post_commands(api.load_post(machine), read_cl_text(program, "j.nc"),
                              now=THESIS_TIME)
        assert caught.value.location.line == 3, machine
        assert "rapid_move before any tool is loaded: the machine has a tool changer" \
            in caught.value.message
        assert "tool_changer: false" not in caught.value.message


def _without_table(machine: str, tmp_path: Path) -> api.CompiledPost:
    text = (MACHINES / f"{machine}.yaml").read_text(encoding="utf-8")
    text, count = re.subn(r"\n  safe_retract:\n    blocks: \[\]\n", "\n", text)
    assert count == 1
    path = tmp_path / f"{machine}.yaml"
    path.write_text(text, encoding="utf-8")
    return api.load_post(path)


def test_a_tool_changer_post_without_the_table_says_what_it_lacks(tmp_path: Path) -> None:
    post = _without_table("fanuc", tmp_path)
    with pytest.raises(CLError) as caught:
        api.post_commands(post, api.read_cl(FREECAD / "pocket.default.ngc"), now=THESIS_TIME)
    assert caught.value.location.line == 10
    assert "safe_retract (the CAM's move to Z15 before the first tool): the post" \
        in caught.value.message
    assert "give the post a safe_retract table" in caught.value.message
    assert "tool_changer: false" not in caught.value.message


def test_a_post_without_a_tool_changer_writes_it_as_the_rapid_it_is() -> None:
    post = api.load_post("linuxcnc")
    texts = [line.text for line in api.post_commands(
        post, api.read_cl(FREECAD / "pocket.default.ngc"), now=THESIS_TIME)]
    first_tool = next(i for i, t in enumerate(texts) if t.startswith("M6 T1"))
    assert "G0 Z15.000 " in texts[:first_tool]
    native = read_cl_text('{"cmd": "safe_retract", "z": 20}\n{"cmd": "program_end"}\n',
                          "n.jsonl")
    assert [c for c in native if isinstance(c, SafeRetract)] == [SafeRetract(z=20)]
    lines = [line.text for line in api.post_commands(post, native, now=THESIS_TIME)]
    assert "G0 Z20.000 " in lines


def test_an_explicit_retract_is_written_and_verified(tmp_path: Path) -> None:
    """A post may write its own retract there (G91 G28 Z0 then G90): the control model
    follows it (Z unknown after the reference return, as at the top) and verify passes."""
    text = (MACHINES / "fanuc.yaml").read_text(encoding="utf-8").replace(
        "  safe_retract:\n    blocks: []\n",
        "  safe_retract:\n    blocks:\n      - use: home_z\n      - items: [\" G90\"]\n")
    path = tmp_path / "fanuc_retract.yaml"
    path.write_text(text, encoding="utf-8")
    post = api.load_post(path)
    commands = api.read_cl(FREECAD / "pocket.default.ngc")
    nc = api.post_commands(post, commands, now=THESIS_TIME)
    written = [line.text for line in nc if line.command == "safe_retract"]
    assert written == ["N20 G91 G28 Z0.", "N30 G90"]
    assert api.verify_commands(post, commands, now=THESIS_TIME).ok


#: (job file, post) -> the refusal, located, with its reason: FreeCAD's own output that no
#: control runs as FreeCAD meant it, or a spindle faster than the machine turns
_FREECAD_REFUSED = {
    # FreeCAD 0.20's linuxcnc post drops K of a G18/G19 arc (rs274 refuses the same file)
    **{(f"planes.{s}.ngc", p): "the centre (0, 10) is the start point"
       for s in ("default", "line_numbers", "modal", "modal_axis_modal", "no_comments",
                 "no_header", "precision4", "axis_modal", "preamble")
       for p in TOOL_CHANGER_POSTS},
    # its --axis-modal drops R on the first hole of a new object (rs274 refuses it too)
    **{(f"drilling.{s}.ngc", p): "G81 needs R on its first hole"
       for s in ("axis_modal", "modal_axis_modal") for p in TOOL_CHANGER_POSTS},
    # and R on the first hole of another cycle when it equals the last cycle's
    **{(f"modal.{s}.ngc", p): "G83 needs R on its first hole"
       for s in ("axis_modal", "modal_axis_modal") for p in TOOL_CHANGER_POSTS},
}
_SPEEDS = {("helix", "emco"): 8000, ("raster", "emco"): 12000, ("raster", "vmc500"): 12000,
           ("raster", "feeler"): 12000}


def _job_files() -> list[str]:
    return sorted(p.name for p in FREECAD.iterdir() if p.suffix in (".ngc", ".gcode", ".txt"))


@pytest.mark.parametrize("machine", TOOL_CHANGER_POSTS)
def test_every_freecad_job_posts_on_every_tool_changer_post(machine: str) -> None:
    """Every form of every reference job posts and verifies, but for FreeCAD's own broken
    output and the speeds a machine cannot turn (each refused at its line)."""
    post = api.load_post(machine)
    posted = set()
    for name in _job_files():
        job = name.split(".")[0]
        commands = None
        try:
            commands = api.read_cl(FREECAD / name)
            api.post_commands(post, commands, cl_file=name, now=THESIS_TIME)
        except CLError as error:
            expected = _FREECAD_REFUSED.get((name, machine))
            if expected is None and (job, machine) in _SPEEDS:
                expected = f"spindle speed {_SPEEDS[job, machine]} rpm is outside the range"
            assert expected is not None and expected in error.message, f"{name}: {error}"
            assert error.location is not None and error.location.line
            continue
        assert (name, machine) not in _FREECAD_REFUSED and (job, machine) not in _SPEEDS
        verdict = api.verify_commands(post, commands, cl_file=name, now=THESIS_TIME)
        assert verdict.ok, f"{name}: {verdict.divergence}"
        posted.add(job)
    assert posted == set(JOBS) - {job for job, m in _SPEEDS if m == machine}


# --- rs274: the posted program cuts as the program itself ---------------------------------

_CALL = re.compile(r"^\s*\d+\s+N\S+\s+([A-Z_0-9]+)\((.*)\)\s*$")


@dataclass
class Cut:
    kind: str  # "feed" or "arc"
    start: tuple[float, ...]
    end: tuple[float, ...]
    feed: float
    arc: tuple[float, ...] = ()  # ARC_FEED's centre (2) and rotation (1), in mm


def rs274_cuts(program: list[str], tmp_path: Path) -> list[Cut]:
    """rs274's feed moves and arcs of a program, in mm (an inch program converted)."""
    ngc, table = tmp_path / "program.ngc", tmp_path / "tools.tbl"
    ngc.write_text("\n".join(program) + "\n", encoding="utf-8")
    table.write_text("".join(f"T{n} P{n} Z0 D0\n" for n in range(1, 200)), encoding="utf-8")
    result = rs274_process(table, ngc)
    errors = [line for line in result.stderr.splitlines() if line.strip() != "executing"]
    assert result.returncode == 0 and not errors, errors
    scale, feed, pos = 1.0, 0.0, (0.0, 0.0, 0.0)
    cuts = []
    for raw in result.stdout.splitlines():
        match = _CALL.match(raw)
        if match is None:
            continue
        name, args = match.groups()
        values = [v.strip() for v in args.split(",")]
        if name == "USE_LENGTH_UNITS":
            scale = 25.4 if "INCHES" in args else 1.0
        elif name == "SET_FEED_RATE":
            feed = float(args) * scale
        elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "ARC_FEED"):
            numbers = [float(v) * scale for v in values[:6]]
            if name == "ARC_FEED":  # first, second end, first, second centre, turn, axis end
                end = (numbers[0], numbers[1], numbers[5])
                cuts.append(Cut("arc", pos, end, feed,
                                (numbers[2], numbers[3], float(values[4]))))
            else:
                end = tuple(numbers[:3])
                if name == "STRAIGHT_FEED":
                    cuts.append(Cut("feed", pos, end, feed))
            pos = end
    return cuts


def _same(a: tuple[float, ...], b: tuple[float, ...], tolerance: float) -> bool:
    return all(abs(p - q) <= tolerance for p, q in zip(a, b, strict=True))


def compare_cuts(posted: list[Cut], original: list[Cut], tolerance: float) -> int:
    assert len(posted) == len(original), (len(posted), len(original))
    for number, (got, want) in enumerate(zip(posted, original, strict=True), start=1):
        where = f"cut {number}: posted {got}, program {want}"
        assert got.kind == want.kind, where
        assert _same(got.start, want.start, tolerance), where
        assert _same(got.end, want.end, tolerance), where
        assert _same(got.arc, want.arc, tolerance), where
        assert abs(got.feed - want.feed) <= 0.5, where
    return len(posted)


#: the one rewrite the programs need before rs274 takes them: Vectric's safe-start block
#: holds G00 and G80 (Mach3 takes both; rs274 refuses two codes of one modal group)
def as_rs274_reads_it(text: str) -> list[str]:
    return [re.sub(r"(G00G21G17G90G40G49)G80$", r"\1", line) for line in text.splitlines()]


def posted_for_rs274(machine: str, path: Path) -> list[str]:
    post = api.load_post(machine)
    lines = [line.text for line in api.post_commands(post, api.read_cl(path),
                                                     cl_file=path.name, now=THESIS_TIME)]
    return for_rs274(lines) if machine == "fanuc" else lines


_POSTING = {"styled_fusion_linuxcnc_bracket.ngc": ("linuxcnc", "fanuc"),
            "styled_fusion_mach3_inch_face.tap": ("linuxcnc", "fanuc"),
            "styled_vectric_mach3_atc_profile.tap": ("linuxcnc", "fanuc"),
            "styled_pycam_surface.ngc": ("linuxcnc", "fanuc"),
            "styled_estlcam_engrave.nc": ("linuxcnc",),
            "styled_fusion_grbl_pocket.nc": ("linuxcnc",)}


@needs_rs274
@pytest.mark.parametrize(("name", "machine"),
                         [(n, m) for n, machines in _POSTING.items() for m in machines])
def test_a_styled_program_posted_cuts_as_the_program_itself(name: str, machine: str,
                                                            tmp_path: Path) -> None:
    path = REAL / name
    original = rs274_cuts(as_rs274_reads_it(path.read_text(encoding="utf-8")), tmp_path)
    posted = rs274_cuts(posted_for_rs274(machine, path), tmp_path)
    inch = "G20" in path.read_text(encoding="utf-8")
    # rs274 prints 4 decimals of the program's unit: 0.0001 inch is 0.00254 mm
    assert compare_cuts(posted, original, 0.003 if inch else 0.001) > 5


#: the form rs274 runs of each job: FreeCAD's LinuxCNC output; planes' K-less arcs are
#: refused by rs274 too, so that job is compared with the LinuxCNC post's own output
_RS274_JOBS = {"pocket": "pocket.default.ngc", "helix": "helix.default.ngc",
               "drilling": "drilling.default.ngc", "raster": "raster.default.ngc",
               "planes": "planes.dump.txt"}


@needs_rs274
@pytest.mark.parametrize(("job", "machine"),
                         [(j, m) for j in _RS274_JOBS for m in ("fanuc", "feeler")
                          if (j, m) not in _SPEEDS])
def test_rs274_cuts_a_freecad_job_posted_for_a_fanuc_as_freecads_own_output(
        job: str, machine: str, tmp_path: Path) -> None:
    path = FREECAD / _RS274_JOBS[job]
    if path.suffix == ".ngc":
        reference = path.read_text(encoding="utf-8").splitlines()
    else:
        reference = posted_for_rs274("linuxcnc", path)
    original = rs274_cuts(reference, tmp_path)
    lines = [line.text for line in api.post_commands(api.load_post(machine), api.read_cl(path),
                                                     cl_file=path.name, now=THESIS_TIME)]
    posted = rs274_cuts(for_rs274(lines), tmp_path)
    if machine == "feeler":  # its drilling runs in feed per revolution: compare the path
        for cut in (*posted, *original):
            cut.feed = 0.0
    assert compare_cuts(posted, original, 0.001) > 3


def test_a_last_line_that_ends_the_program_needs_no_line_end() -> None:
    """FreeCAD writes its postamble (``M5 M2``) without a line end: the line that ends
    the program is whole; a last line without its end that does not end it is refused
    (``G0 X30`` cut to ``G0 X3``), as is a cut ``M30`` (``M3`` ends nothing)."""
    text = "(Exported by FreeCAD)\nG21\nM6 T1\nM3 S1000\nG0 X1\nM5 M2"
    assert isinstance(read_cl_text(text, "p.ngc")[-1], ProgramEnd)
    for cut, message in (("G0 X3", "the last line has no line end"),
                         ("M3", "the last line has no line end")):
        with pytest.raises(CLError) as caught:
            read_cl_text(f"(Exported by FreeCAD)\nG21\nM6 T1\nM3 S1000\nG0 X1\n{cut}",
                         "p.ngc")
        assert message in caught.value.message
    with pytest.raises(CLError) as caught:
        read_cl_text("G21\nT1 M6\nG0 X1\nG0 X3", "p.nc")
    assert "the last line has no line end" in caught.value.message


# --- arcs in radius form, as rs274 reads them ----------------------------------------------

#: R arcs in the three planes, the shorter arc (R > 0) and the longer (R < 0), absolute and
#: incremental, in mm and in inches (SketchUcam writes its arcs so)
_R_ARCS = """G21 G90 G17
G0 X0 Y0 Z0
G1 F100
G2 X10 Y0 R5
G3 X20 Y0 R5
G2 X30 Y10 R-10
G3 X40 Y0 R10
G91 G2 X-5 Y5 R5
G90 G18 G2 X30 Z5 R8
G3 X20 Z-5 R-8
G19 G2 Y20 Z0 R12
G3 Y30 Z10 R-9
G17 G20 G2 X1.5 Y1 R0.75
G3 X1 Y1.25 Z-0.1 R-0.4
M2"""


@needs_rs274
def test_an_arc_in_radius_form_has_the_centre_rs274_gives_it(tmp_path: Path) -> None:
    """Each R arc of the program ends where rs274 ends it, around the centre rs274 finds
    (the shorter arc for R > 0, the longer for R < 0, in each plane, G90 and G91)."""
    arcs = [r for r in read(_R_ARCS) if isinstance(r, ArcMove)]
    cuts = [c for c in rs274_cuts(_R_ARCS.splitlines(), tmp_path) if c.kind == "arc"]
    assert len(arcs) == len(cuts) == 11
    for arc, cut in zip(arcs, cuts, strict=True):
        axes = {"xy": (0, 1), "zx": (2, 0), "yz": (1, 2)}[arc.plane]
        centre = (arc.cx, arc.cy, arc.cz)
        end = (arc.x, arc.y, arc.z)
        # rs274's ARC_FEED: the plane's first and second end, then its centre
        for given, index in ((cut.end[0], axes[0]), (cut.end[1], axes[1])):
            assert end[index] is None or end[index] == pytest.approx(given, abs=0.003), arc
        for given, index in ((cut.arc[0], axes[0]), (cut.arc[1], axes[1])):
            assert centre[index] == pytest.approx(given, abs=0.003), arc
