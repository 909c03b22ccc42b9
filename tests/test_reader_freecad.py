"""The FreeCAD reader: both textual forms, every accepted command, drilling, errors."""

from __future__ import annotations

import textwrap

import pytest

from postdsl.cl.model import (
    ArcMove,
    BreakChip,
    Comment,
    CoolantOff,
    CoolantOn,
    CycleEnd,
    CycleHole,
    CycleStart,
    DeepDrill,
    Dwell,
    InputModes,
    LinearMove,
    Operation,
    ProgramEnd,
    ProgramStart,
    RapidMove,
    SafeRetract,
    SinglePeck,
    SpindleOff,
    SpindleOn,
    ToolChange,
)
from postdsl.cl.readers import detect_format, read_cl, read_cl_text
from postdsl.errors import CLError
from tests.conftest import DATA, EXAMPLES


def read(text: str, file: str = "job.txt", fmt: str | None = None,
         feed_units: str | None = "mm/s") -> list:
    """Read a FreeCAD text, a whole file ending with a line end; the texts here are the
    internal path (feeds in mm/s) unless a test says otherwise."""
    return read_cl_text(textwrap.dedent(text).strip("\n") + "\n", file, fmt, feed_units)


def body(records: list) -> list:
    """The records between the implicit program_start and program_end."""
    assert isinstance(records[0], ProgramStart)
    assert isinstance(records[-1], ProgramEnd)
    return records[1:-1]


# --- the two forms ------------------------------------------------------------------------

DUMP = """
    (This output produced with the dump post processor)
    (Dump is useful for inspecting the raw commands in your paths)
    (Path: T1: D16)
    Command (T1: D16) [ ]
    Command M6 [ T:1 ]
    Command M3 [ S:2000 ]
    Command M8 [ ]
    (Path: Pocket)
    Command (Pocket) [ ]
    Command G0 [ F:0 Z:20 ]
    Command G0 [ X:6 Y:-20 ]
    Command G1 [ F:3.3333 X:7 Y:-7 Z:12.5 ]
    Command G2 [ F:3.3333 I:4 J:0 K:0 X:15 Y:-7 Z:12.5 ]
    Command G3 [ F:3.3333 I:-4 J:0 X:7 Y:-7 Z:10 ]
    Command G4 [ P:0.5 ]
    Command M7 [ ]
    Command M9 [ ]
    Command M4 [ S:1500 ]
    Command M5 [ ]
    Command G0 [ Z:20 ]
"""

PLAIN = """
    (T1: D16)
    M6 T1
    M3 S2000
    M8
    (Pocket)
    G0 F0 Z20
    G0X6Y-20
    G01 F3.3333 X7 Y-7 Z12.5
    G2 F3.3333 I4 J0 K0 X15 Y-7 Z12.5
    g3 f3.3333 i-4 j0 x7 y-7 z10
    G4 P0.5
    M7
    M9
    M04 S1500
    M5
    G0 Z20
"""

EXPECTED = [
    Comment(comment="T1: D16"),
    ToolChange(tool_number=1),
    SpindleOn(spindle_speed=2000, spindle="cw"),
    CoolantOn(coolant="flood"),
    Comment(comment="Pocket"),
    RapidMove(z=20),
    RapidMove(x=6, y=-20),
    LinearMove(x=7, y=-7, z=12.5, feed=pytest.approx(199.998)),
    ArcMove(x=15, y=-7, z=12.5, cx=11, cy=-7, cz=12.5, arc_direction="cw",
            feed=pytest.approx(199.998)),
    ArcMove(x=7, y=-7, z=10, cx=11, cy=-7, arc_direction="ccw", feed=pytest.approx(199.998)),
    Dwell(dwell=0.5),
    CoolantOn(coolant="mist"),
    CoolantOff(),
    SpindleOn(spindle_speed=1500, spindle="ccw"),
    SpindleOff(),
    RapidMove(z=20),
]


def test_dump_form_reads_every_accepted_command() -> None:
    records = body(read(DUMP))
    operations = [r for r in records if isinstance(r, Operation)]
    assert [o.operation for o in operations] == ["T1: D16", "Pocket"]
    assert [r for r in records if not isinstance(r, Operation)] == EXPECTED


def test_plain_form_reads_the_same_program() -> None:
    assert body(read(PLAIN, "job.gcode")) == EXPECTED


def test_records_carry_their_source_lines() -> None:
    records = body(read(DUMP))
    assert [r.line for r in records[:4]] == [3, 4, 5, 6]  # banner lines 1-2 give no record
    assert records[-1].line == 20


def test_the_thesis_dump_reads_with_paths_as_operations() -> None:
    records = read_cl(DATA / "emco_thesis.dump.txt")
    assert isinstance(records[0], ProgramStart) and isinstance(records[-1], ProgramEnd)
    assert [r.operation for r in records if isinstance(r, Operation)] == [
        "T1: D16", "Pocket_Shape", "T4: D8", "Helix", "T6: D3", "Pocket_Shape001"]
    # the five banner lines of the dump post are its notes about itself, not comments
    assert not any(isinstance(r, Comment) and "dump" in r.comment for r in records)
    assert len([r for r in records if isinstance(r, ArcMove)]) == 4 + 8 + 12


def test_compound_records_are_operation_boundaries() -> None:
    records = body(read("""
        (compound: Drill group)
        (Path: Drill A)
        Command G0 [ Z:5 ]
    """))
    assert records == [Operation(operation="Drill group"), Operation(operation="Drill A"),
                       SafeRetract(z=5)]


def test_old_dump_brackets_are_read_too() -> None:
    assert body(read("Command G1 ( F:1 X:1 Y:0 )")) == [LinearMove(x=1, y=0, feed=60)]


def test_the_example_program_reads_as_plain_gcode() -> None:
    lines = (EXAMPLES / "emco_pocket.gcode").read_text(encoding="utf-8").splitlines()
    assert detect_format(lines) == "freecad"
    records = read_cl(EXAMPLES / "emco_pocket.gcode")
    assert sum(isinstance(r, CycleStart) for r in records) == 3


# --- values -------------------------------------------------------------------------------


def test_feeds_in_mm_per_second_become_mm_per_minute() -> None:
    [move] = body(read("G1 X1 F2.5"))
    assert move.feed == 150.0
    [rapid] = body(read("G0 X1 F200"))  # FreeCAD's rapid rate is not a feed
    assert rapid == RapidMove(x=1)


def test_omitted_axes_are_left_to_the_cl_to_keep() -> None:
    assert body(read("""
        G0 X1 Y2 Z3
        G1 Z0 F1
        G1 X5
    """)) == [RapidMove(x=1, y=2, z=3), LinearMove(z=0, feed=60), LinearMove(x=5)]


def test_relative_ijk_becomes_the_absolute_centre() -> None:
    records = body(read("""
        G0 X10 Y20 Z5
        G2 X30 Y20 I10 J0 F1
        G3 X30 Y40 I0 J10 Z4
        G2 X30 Y40 I-5
    """))
    assert [(a.cx, a.cy, a.cz) for a in records[1:]] == [
        (20, 20, None), (30, 30, None), (25, 40, None)]
    assert [a.arc_direction for a in records[1:]] == ["cw", "ccw", "cw"]


def test_arc_planes_follow_g17_g18_g19() -> None:
    records = body(read("""
        G0 X0 Y0 Z0
        G18
        G2 X10 Z0 I5 K0 F1
        G19
        G3 Y10 Z0 J5 K0
        G17
        G2 X10 Y0 I0 J0
    """))
    arcs = [r for r in records if isinstance(r, ArcMove)]
    assert [(a.plane, a.cx, a.cy, a.cz) for a in arcs] == [
        ("zx", 5, None, 0), ("yz", None, 5, 0), ("xy", 10, 10, None)]
    # the plane the input selected is a fact a post may read, at its line
    assert [(r.active_plane, r.distance_mode, r.line) for r in records
            if isinstance(r, InputModes)] == [
        ("zx", None, 2), ("yz", None, 4), ("xy", None, 6)]


def test_incremental_moves_are_added_to_the_position() -> None:
    records = body(read("""
        G0 X10 Y10 Z10
        G91
        G1 X5 Z-2 F1
        G2 X10 Y0 I5 J0
        G90
        G0 X0
    """))
    assert records == [RapidMove(x=10, y=10, z=10),
                       InputModes(distance_mode="incremental"),
                       LinearMove(x=15, z=8, feed=60),
                       ArcMove(x=25, y=10, cx=20, cy=10, arc_direction="cw"),
                       InputModes(distance_mode="absolute"),
                       RapidMove(x=0)]


def test_modal_state_commands_give_no_record_but_the_facts_posts_may_read() -> None:
    # G21 marks a post's output, which must end with M2 or M30
    assert body(read("""
        G90
        G17
        G21
        G40
        G54
        G80
        G98
        G99
        M2
    """, feed_units=None)) == [InputModes(distance_mode="absolute"),
                               InputModes(active_plane="xy"),
                               InputModes(cycle_return="initial"),
                               InputModes(cycle_return="r_plane")]


def test_program_end_is_read_from_m2_and_m30() -> None:
    for word in ("M2", "M30"):
        records = read(f"G0 X1\n{word}")
        assert records == [ProgramStart(), RapidMove(x=1), ProgramEnd()]
        assert records[-1].line == 2


def test_a_spindle_command_may_reuse_the_last_speed() -> None:
    assert body(read("M3 S800\nM5\nM4")) == [
        SpindleOn(spindle_speed=800), SpindleOff(), SpindleOn(spindle_speed=800, spindle="ccw")]


# --- drilling -----------------------------------------------------------------------------


def test_holes_of_one_cycle_group_into_cycle_hole_records() -> None:
    records = body(read("""
        G0 Z20
        G99
        G81 X10 Y10 Z-5 R2 F2
        G81 X20 Y10 Z-5 R2 F2
        G81 X30
        G80
        G0 Z20
    """))
    assert records == [
        SafeRetract(z=20),  # Z alone before any tool and any X Y: the job's "go safe"
        InputModes(cycle_return="r_plane"),  # the G99 line, for a post that echoes it
        CycleStart(),
        SinglePeck(x=10, y=10, top=2, depth=7, clearance=0, retract=2, feed=120,
                   cycle_return="r_plane"),
        CycleHole(x=20, y=10),
        CycleHole(x=30, y=10),  # R Z F are modal while the cycle is open
        CycleEnd(),
        RapidMove(z=20),
    ]
    assert records[3].top - records[3].depth == -5  # the CL bottom is FreeCAD's Z


def test_a_changed_parameter_or_another_command_starts_a_new_cycle() -> None:
    records = body(read("""
        G0 Z20
        G81 X10 Y10 Z-5 R2 F2
        G81 X20 Y10 Z-8 R2 F2
        (next)
        G81 X30 Y10 Z-8 R2 F2
    """))
    kinds = [type(r).__name__ for r in records]
    assert kinds == ["SafeRetract", "CycleStart", "SinglePeck", "CycleEnd", "CycleStart",
                     "SinglePeck", "CycleEnd", "Comment", "CycleStart", "SinglePeck",
                     "CycleEnd"]  # the cycle still open at the end is closed before the end


def test_each_drill_command_maps_to_its_setup() -> None:
    records = body(read("""
        G0 Z20
        G99
        G82 X1 Y1 Z-5 R2 P0.5 F2
        G83 X2 Y2 Z-30 R2 Q4 F2
        G73 X3 Y3 Z-30 R2 Q3 P0.2 F2
    """))
    setups = [r for r in records if isinstance(r, (SinglePeck, DeepDrill, BreakChip))]
    assert setups == [
        SinglePeck(x=1, y=1, top=2, depth=7, clearance=0, retract=2, dwell=0.5, feed=120,
                   cycle_return="r_plane"),
        DeepDrill(x=2, y=2, top=2, depth=32, clearance=0, retract=2, peck=4, feed=120,
                  cycle_return="r_plane"),
        BreakChip(x=3, y=3, top=2, depth=32, clearance=0, retract=2, peck=3, dwell=0.2,
                  feed=120, cycle_return="r_plane"),
    ]


def test_g98_returns_to_the_initial_level_and_g99_to_r() -> None:
    g98 = body(read("G0 X0 Y0 Z25\nG98\nG81 X1 Y1 Z-5 R2 F1\nG81 X2\nG80\nG1 Z0 F1"))
    assert g98[3].retract == 25
    g99 = body(read("G0 X0 Y0 Z25\nG99\nG81 X1 Y1 Z-5 R2 F1"))
    assert g99[3].retract == 2
    default = body(read("G0 X0 Y0 Z1\nG81 X1 Y1 Z-5 R2 F1"))  # G98, never below R
    assert default[2].retract == 2
    # what the file wrote is a fact of the setup; an assumed G98 is not
    assert (g98[3].cycle_return, g99[3].cycle_return, default[2].cycle_return) == (
        "initial", "r_plane", None)
    assert (g98[1], g99[1]) == (InputModes(cycle_return="initial"),
                                InputModes(cycle_return="r_plane"))


def test_the_cycle_end_says_what_ended_the_cycle() -> None:
    records = body(read("""
        G0 X0 Y0 Z20
        G81 X1 Y1 Z-5 R2 F1
        G80
        G81 X2 Y2 Z-5 R2 F1
        G83 X3 Y3 Z-5 R2 Q1 F1
        G99
        G83 X4 Y4
        G0 Z20
        G81 X5 Y5 Z-5 R2 F1
        M5
    """))
    ends = [(r.ended_by, r.line) for r in records if isinstance(r, CycleEnd)]
    # G80; the G83 after a G81; G99 changes how the next hole leaves (a new cycle, not
    # ended by the G99 itself); a move; another command
    assert ends == [("cancel", 3), ("next_cycle", 5), ("next_cycle", 7), ("motion", 8),
                    ("other", 10)]


def test_after_a_hole_the_tool_is_at_the_retract_plane() -> None:
    records = body(read("G0 X0 Y0 Z30\nG99\nG81 X5 Y6 Z-5 R3 F1\nG80\nG91\nG0 Z1"))
    assert records[-1] == RapidMove(z=4)


# --- errors -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "line", "message"),
    [
        ("Command G1 [ X:1 Y:2\n", 1, "malformed dump record"),
        ("Command G1 [ X1 ]", 1, "malformed argument 'X1'"),
        ("Command G1 [ X:1 X:2 ]", 1, "argument X given twice"),
        ("Command G1 [ X:nan ]", 1, "malformed argument"),
        ("(Path: a)\n(loose note)", 2, "unexpected line"),
        ("(banner)\nCommand G0 [ Z:5 ]\n(loose note)", 3, "unexpected line"),
        ("(Path: a)\nG1 X1", 2, "not a FreeCAD dump record"),
        ("Command (c) [ X:1 ]", 1, "a comment record takes no arguments"),
        ("G1 X1 F1\nCommand G1 [ X:1 ]", 2, "a dump record in plain FreeCAD G-code"),
        ("G1 X1 (move)", 1, "cannot read '(move)'"),
        ("X1 Y2", 1, "a line must start with a G or M command"),
        ("G1 X1 X2", 1, "argument X given twice"),
        ("G1 X1e999", 1, "not a finite number"),
        ("(unclosed", 1, "malformed comment"),
        ("G65 P1", 1, "unknown FreeCAD command G65"),
        ("G38.2 Z-5 F1", 1, "probing (G38.2) cannot be carried by the CL"),
        ("M00.5", 1, "M00.5"),
        ("G1 A10 F1", 1, "G1 takes X Y Z F, not A"),
        ("G81 X1 Y1 Z-1 R1 Q1 F1", 1, "G81 takes X Y Z R F, not Q"),
        ("G20", 1, "inch units"),
        ("G41 D1.5", 1, "D must be a register number"),
        ("G41 H1", 1, "G41 takes D, not H"),
        ("G0 X0 Y0 Z5\nG91\nG81 X1 Y1 Z-1 R1 F1", 3, "incremental mode (G91)"),
        ("G91\nG0 X1", 2, "incremental (G91) X before the X position is known"),
        ("G2 X1 Y1 I1 J0", 1, "before the tool position is known"),
        ("G1 X1 F0", 1, "a cutting move needs a positive feed"),
        ("M6", 1, "M6 needs a tool number T"),
        ("M6 T1.5", 1, "M6 needs a tool number T"),
        ("M3", 1, "M3 without a spindle speed S"),
        ("G4", 1, "G4 needs a dwell time P"),
        ("G0 X0 Y0\nG81 X1 Y1 R1 F1", 2, "G81 needs Z on its first hole"),
        ("G0 X0 Y0\nG81 X1 Y1 Z2 R1 F1", 2, "the bottom Z2 must be below R1"),
        ("G0 X0 Y0\nG83 X1 Y1 Z-5 R1 F1", 2, "G83 needs a positive peck depth Q"),
        ("G0 X0 Y0\nG82 X1 Y1 Z-5 R1 F1", 2, "G82 needs a dwell time P"),
        ("G0 X0 Y0\nG81 X1 Y1 Z-5 R1", 2, "G81 needs a feed F"),
        ("G81 Z-5 R1 F1", 1, "the hole's X and Y are not known"),
        ("M30\nG0 X1", 2, "nothing may follow the program end"),
    ],
)
def test_bad_lines_are_located_errors_naming_the_content(text: str, line: int,
                                                         message: str) -> None:
    with pytest.raises(CLError) as caught:
        read_cl_text(text + "\n", "job.nc", "freecad", "mm/s")
    error = caught.value
    assert error.location.file == "job.nc"
    assert error.location.line == line
    assert message in error.message
    bad_line = text.splitlines()[line - 1].strip()
    assert bad_line[:40] in error.message  # the line's content is quoted
    assert str(error).startswith(f"job.nc:{line}")


def test_a_plain_word_error_points_at_the_column() -> None:
    with pytest.raises(CLError) as caught:
        read_cl_text("G1 X1 F1 ?5\n", "job.nc", "freecad", "mm/s")
    assert caught.value.location.column == 10  # the '?' itself


# --- detection ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("lines", "fmt"),
    [
        (["(Path: a)", "Command G0 [ Z:5 ]"], "freecad"),
        (["(banner)", "Command G0 [ Z:5 ]"], "freecad"),
        (["G90", "G0 X1 Y2", "(comment)", "m3 s100"], "freecad"),
        # what every RS274 program writes, without FreeCAD's banner: any CAM's G-code
        (["%", "N10 G0 X1", "N20 G1 X2 F100", "; comment", "%"], "gcode"),
        (["(Exported by FreeCAD)", "%", "N10 G0 X1", "N20 G1 X2 F100"], "freecad"),
        (['{"cmd": "rapid_move", "x": 1}'], "native"),
    ],
)
def test_the_format_is_detected_from_the_content(lines: list[str], fmt: str) -> None:
    assert detect_format(lines) == fmt


@pytest.mark.parametrize("lines", [["PARTNO/TEST", "GOTO/1,2,3"], ['{"cmd": "program_end"}'],
                                   ["hello world"]])
def test_other_files_are_not_taken_for_freecad(lines: list[str]) -> None:
    from postdsl.cl.freecad import looks_like_freecad

    assert not looks_like_freecad(lines)


# --- hostile input ---------------------------------------------------------------------------


def test_byte_order_marks_crlf_and_utf16_read_as_the_plain_file(tmp_path) -> None:
    """What Windows tools make of a FreeCAD file must post exactly as the file itself."""
    for source in (EXAMPLES / "emco_pocket.gcode", DATA / "emco_thesis.dump.txt"):
        text = source.read_text(encoding="utf-8")
        expected = read_cl(source)
        variants = {"bom": b"\xef\xbb\xbf" + text.encode(), "crlf": text.replace("\n", "\r\n")
                    .encode(), "utf16": text.replace("\n", "\r\n").encode("utf-16")}
        for name, data in variants.items():
            path = tmp_path / f"{name}{source.suffix}"
            path.write_bytes(data)
            assert read_cl(path) == expected, name


def test_a_comment_that_is_not_utf8_names_its_line(tmp_path) -> None:
    path = tmp_path / "latin1.gcode"
    path.write_bytes(b"G0 X1\n(Fr\xe4se)\n")
    with pytest.raises(CLError) as info:
        read_cl(path)
    assert str(info.value).startswith(f"{path}:2:4: not UTF-8 text (byte 0xe4 here)")


# --- who wrote the file: the unit of F ------------------------------------------------------

POST_OUTPUT = """\
(Exported by FreeCAD)
(Post Processor: linuxcnc_post)
G17 G54 G40 G49 G80 G90
G21
(machine: not set, mm/min)
M6 T3 G43 H3
M3 S1000
G0 X0 Y0 Z5
G1 Z-1 F300
M2
"""


def feeds(records: list) -> list:
    return [r.feed for r in records if isinstance(r, LinearMove)]


def test_a_freecad_post_output_is_read_in_mm_per_minute() -> None:
    """The issue's case: the banner says a post wrote it, so F300 is 300 mm/min, not 18000."""
    assert feeds(read_cl_text(POST_OUTPUT, "g.nc")) == [300]


def test_a_post_output_posts_f300_on_the_fanuc() -> None:
    from postdsl import api

    text = api.post_text(api.load_post("feeler"), api.post_commands(
        api.load_post("feeler"), read_cl_text(POST_OUTPUT, "g.nc"), cl_file="g.nc"))
    assert " F300" in text and "F18000" not in text


@pytest.mark.parametrize("evidence", ["G21", "%", "; a comment", "N10 G90",
                                      "(machine units: mm/min)", "M6 T1 G43 H1"])
def test_each_sign_of_a_post_means_mm_per_minute(evidence: str) -> None:
    text = f"{evidence}\nM6 T1\nM3 S1000\nG0 X0 Y0 Z5\nG1 Z-1 F300\nM2\n"
    assert feeds(read_cl_text(text, "g.nc")) == [300]


def test_six_decimals_everywhere_mean_the_internal_path_in_mm_per_second() -> None:
    text = ("M6 T3.000000\nM3 S1000.000000\nG0 X0.000000 Y0.000000 Z5.000000\n"
            "G1 Z-1.000000 F5.000000\n")
    assert feeds(read_cl_text(text, "p.gcode")) == [300]


def test_without_evidence_the_user_must_name_the_feed_unit() -> None:
    text = "M6 T1\nM3 S1000\nG0 X0 Y0 Z5\nG1 Z-1 F300\n"
    with pytest.raises(CLError) as caught:
        read_cl_text(text, "g.nc")
    assert str(caught.value).startswith("g.nc:4: F300: nothing in the file tells")
    assert "--feed-units mm/min or --feed-units mm/s" in caught.value.message
    assert feeds(read_cl_text(text, "g.nc", feed_units="mm/min")) == [300]
    assert feeds(read_cl_text(text, "g.nc", feed_units="mm/s")) == [18000]


def test_a_feed_unit_the_file_contradicts_is_refused() -> None:
    with pytest.raises(CLError) as caught:
        read_cl_text(POST_OUTPUT, "g.nc", feed_units="mm/s")
    assert str(caught.value).startswith("g.nc:1: --feed-units mm/s contradicts the file: its "
                                        "feeds are mm/min")


def test_feed_units_apply_to_freecad_files_only() -> None:
    with pytest.raises(CLError, match="--feed-units applies to FreeCAD G-code only"):
        read_cl_text('{"cmd": "program_end"}\n', "a.jsonl", feed_units="mm/min")


def test_the_command_line_takes_the_feed_unit(tmp_path) -> None:
    from click.testing import CliRunner

    from postdsl.cli import main

    path = tmp_path / "g.nc"
    path.write_text("M6 T1\nM3 S1000\nG0 X0 Y0 Z5\nG1 Z-1 F300\n")
    refused = CliRunner().invoke(main, ["post", "feeler", str(path)])
    assert refused.exit_code == 2 and "--feed-units" in refused.output
    posted = CliRunner().invoke(main, ["post", "feeler", "--feed-units", "mm/min", str(path)])
    assert posted.exit_code == 0 and " F300" in posted.output


# --- a whole program, or none ---------------------------------------------------------------

def test_a_post_output_without_its_program_end_is_cut_short() -> None:
    with pytest.raises(CLError) as caught:
        read_cl_text(POST_OUTPUT.replace("M2\n", ""), "g.nc")
    assert str(caught.value).startswith("g.nc:9: the program ends without M2 or M30")


@pytest.mark.parametrize("cut", ["G0 X3", "G2 F5 I5 J0 X40 Y20"])
def test_a_line_cut_inside_is_refused_for_want_of_its_line_end(cut: str) -> None:
    """``G0 X30`` cut to ``X3``, an arc cut before its Y into a full circle: no line end."""
    text = "M6 T1\nM3 S1000\nG0 X30 Y20 Z1\nG1 Z0 F5\n" + cut
    with pytest.raises(CLError) as caught:
        read_cl_text(text, "p.gcode", feed_units="mm/s")
    assert str(caught.value).startswith("p.gcode:5: the last line has no line end")
    assert len(read_cl_text(text + "\n", "p.gcode", feed_units="mm/s")) > 4


def test_a_dump_cut_inside_its_last_line_is_refused() -> None:
    for text in ("Command G0 [ X:3", "Command G0 [ X:3 ]"):  # cut, or whole but unended
        with pytest.raises(CLError) as caught:
            read_cl_text("(Path: a)\nCommand G0 [ Z:5 ]\n" + text, "d.txt")
        assert str(caught.value).startswith("d.txt:3: ")


# --- what would cut wrong ------------------------------------------------------------------

def test_a_cutting_move_before_any_feed_is_refused() -> None:
    with pytest.raises(CLError) as caught:
        read("M6 T1\nM3 S100\nG0 X0 Y0 Z5\nG1 Z-1")
    assert str(caught.value) == ("job.txt:4: G1 is a cutting move but no feed F was given "
                                 "before it: G1 Z-1")


def test_an_arc_before_any_feed_is_refused() -> None:
    with pytest.raises(CLError, match=r"job\.txt:3: G2 is a cutting move but no feed F"):
        read("M6 T1\nG0 X0 Y0 Z5\nG2 X10 I5")


def test_tool_length_compensation_needs_the_loaded_tool() -> None:
    with pytest.raises(CLError) as caught:
        read("G43 H1\nM6 T1", feed_units=None)
    assert str(caught.value).startswith("job.txt:1: G43 (tool length compensation) with no "
                                        "tool loaded")
    with pytest.raises(CLError, match=r"job\.txt:2: G43 with H2 for tool T1"):
        read("M6 T1\nG43 H2", feed_units=None)
    assert body(read("M6 T1 G43 H1\nM2", feed_units=None)) == [ToolChange(tool_number=1)]


def test_taps_are_read_from_g84_and_g74() -> None:
    from postdsl.cl.model import Tapping, TappingCcw

    records = body(read("""
        M6 T1
        G0 X0 Y0 Z10
        G84 X1 Y2 Z-8 R2 F1.25
        G80
        G74 X3 Y4 Z-8 R2 F1.25
        G80
    """))
    setups = [r for r in records if isinstance(r, (Tapping, TappingCcw))]
    assert [(type(r), r.x, r.y, r.top, r.depth, r.feed) for r in setups] == [
        (Tapping, 1, 2, 2, 10, 75), (TappingCcw, 3, 4, 2, 10, 75)]


def test_a_block_of_axis_words_repeats_the_motion_in_force() -> None:
    records = body(read("M6 T1\nG0 X0 Y0 Z5\nG1 Z-1 F5\nX10\nY10\nG0 Z5\nX0 Y0"))
    moves = [(type(r).__name__, r.x, r.y, r.z) for r in records
             if isinstance(r, (LinearMove, RapidMove))]
    assert moves == [("RapidMove", 0, 0, 5), ("LinearMove", None, None, -1),
                     ("LinearMove", 10, None, None), ("LinearMove", None, 10, None),
                     ("RapidMove", None, None, 5), ("RapidMove", 0, 0, None)]


def test_block_numbers_are_read_and_not_taken_for_content() -> None:
    records = read_cl_text("N10 M6 T1\nN20 G0 X1 Y2 Z3\nN30 G1 Z0 F100\nN40 M30\n", "n.nc")
    assert [type(r).__name__ for r in records] == [
        "ProgramStart", "ToolChange", "RapidMove", "LinearMove", "ProgramEnd"]
    assert records[3].feed == 100  # N words mark a post's output: mm/min


def test_a_file_of_numbered_blocks_is_detected_as_plain_gcode() -> None:
    """N words are what every RS274 program may write: without FreeCAD's banner, plain
    G-code (F per minute by RS274's rule); with it, FreeCAD's post output."""
    assert detect_format(["N10 G90", "N20 G0 X1"]) == "gcode"
    assert detect_format(["N5 (Exported by FreeCAD)", "N10 G90", "N20 G0 X1"]) == "freecad"


def test_an_undetectable_file_names_the_line_that_fits_no_format() -> None:
    with pytest.raises(CLError) as caught:
        read_cl_text("(a comment)\nG0 X1\nthis is prose\n", "x.txt")
    assert str(caught.value).startswith("x.txt:3: cannot tell the CL format: this line is "
                                        "neither a JSON record, an APT record (WORD/…) nor a "
                                        "G-code block: this is prose")
    with pytest.raises(CLError) as caught:
        read_cl_text("\n\nG0 X1\nGOTO/1,2,3\n", "y.txt")
    assert str(caught.value).startswith("y.txt:4: cannot tell the CL format: line 3 reads as "
                                        "freecad but this one as apt: GOTO/1,2,3")


def test_a_percent_line_may_follow_leading_comments_but_not_a_block() -> None:
    text = "(Exported by FreeCAD)\n%\nM6 T1\nG0 X1\nM30\n%\n"
    assert [type(r).__name__ for r in read_cl_text(text, "p.nc")] == [
        "ProgramStart", "Comment", "ToolChange", "RapidMove", "ProgramEnd"]
    with pytest.raises(CLError, match=r"p\.nc:3: '%' inside the program"):
        read_cl_text("(Exported by FreeCAD)\nM6 T1\n%\nG0 X1\nM30\n", "p.nc")


def test_axis_words_alone_drill_again_while_the_cycle_is_open() -> None:
    """FreeCAD's --modal leaves out a repeated G81: ``X30`` alone is the next hole (RS274);
    after another command closed the cycle it starts none (no R was given to it)."""
    records = body(read("""
        G0 Z20
        G99
        G81 X10 Y10 Z-5 R2 F2
        X20
        Y30
        G80
        G0 Z20
    """))
    assert records[3:7] == [
        SinglePeck(x=10, y=10, top=2, depth=7, clearance=0, retract=2, feed=120,
                   cycle_return="r_plane"),
        CycleHole(x=20, y=10), CycleHole(x=20, y=30), CycleEnd()]
    with pytest.raises(CLError, match="a line must start with a G or M command"):
        body(read("G0 Z20\nG81 X10 Y10 Z-5 R2 F2\n(next)\nX20\n"))
