"""APT dialects: what SolidWorks CAM, Creo, NX, CATIA and Fusion write, read by their tables."""

from __future__ import annotations

import pytest

from postdsl.api import read_cl_text
from postdsl.cl.apt_dialects import DIALECTS, ISO
from postdsl.cl.native import command_to_record
from postdsl.errors import CLError


def read(text: str) -> list[dict]:
    return [command_to_record(c) for c in read_cl_text(text, "d.apt", "apt")]


def error(text: str) -> CLError:
    with pytest.raises(CLError) as info:
        read_cl_text(text, "d.apt", "apt")
    return info.value


def named(records: list[dict], *names: str) -> list[dict]:
    return [r for r in records if r["cmd"] in names]


# --- SolidWorks CAM / CAMWorks --------------------------------------------------------------

SWCAM = """\
PARTNO/1
UNIT/MM
INSERT/[HOLDER=C40-32ERP412] 3.0mm SCREW MACH DRILL
CUTTER/3.,0,1.5,.62132,22.5,0,46.
LOAD/TOOL,14
CSI_SET_FLUTE_LENGTH/16.
CSI_SET_EXTENSION_LENGTH/25.
SELECT/TOOL,15
COOLNT/FLOOD
SPINDL/1200,RPM,CLW
TRNTYP/WORLD,0,0,0
CSYS/1.,0,0,0,0,1.,0,0,0,0,1.,0
RAPID/
GOTO/110.,212.,25.
CYCLE/INIT
CYCLE/DRILL,FEDTO,7.5,MMPM,326.77,RAPTO,3.,RTRCTO,25.,DWELL,0
GOTO/110.,212.,0
GOTO/9.,110.,0
CYCLE/OFF
CYCLE/DEEP2,FEDTO,24.6205,1STPECK,2.,SUBPECK,2.,MMPM,670.56,RAPTO,3.,RTRCTO,25.
GOTO/110.,212.,-5.
CYCLE/OFF
FEDRAT/80,MMPM
GOTO/10,0,-1
CIRCLE/5,0,-1,0,0,1.
GOTO/0,0,-1
CUTCOM/OFF
FINI
"""


def test_a_solidworks_cam_file_reads() -> None:
    records = read(SWCAM)
    assert named(records, "comment") == [
        {"cmd": "comment", "comment": "[HOLDER=C40-32ERP412] 3.0mm SCREW MACH DRILL"}]
    assert named(records, "tool_change") == [
        {"cmd": "tool_change", "tool_number": 14, "tool_diameter": 3.0}]
    assert named(records, "single_peck", "deep_drill", "cycle_hole") == [
        {"cmd": "single_peck", "x": 110.0, "y": 212.0, "depth": 7.5,
         "clearance": 3.0, "retract": 25.0, "feed": 326.77},
        {"cmd": "cycle_hole", "x": 9.0, "y": 110.0, "top": 0.0},
        {"cmd": "deep_drill", "x": 110.0, "y": 212.0, "top": -5.0, "depth": 24.6205,
         "clearance": 3.0, "retract": 20.0, "peck": 2.0, "feed": 670.56}]
    # CIRCLE with six values: the radius is the start point's distance from the centre
    assert named(records, "arc_move") == [
        {"cmd": "arc_move", "x": 0.0, "y": 0.0, "z": -1.0, "cx": 5.0, "cy": 0.0,
         "feed": 80.0}], "counter-clockwise about +Z, the default"


@pytest.mark.parametrize(("change", "line", "number", "message"), [
    ("CUTCOM/OFF", "CUTCOM/ON", 27, "CUTCOM/ON: CUTCOM without LEFT, RIGHT or OFF: the side "
                                    "of the path is not given"),
    ("CUTCOM/OFF", "CUTCOM/LEFT,ZXPLAN", 27, "cutter compensation in the ZX plane is not read"),
    ("TRNTYP/WORLD,0,0,0", "TRNTYP/WORLD,0,0,5.", 11,
     "TRNTYP/WORLD,0,0,5.: TRNTYP moves the coordinate system: the CL has no way to carry a "
     "transformation"),
    ("CSYS/1.,0,0,0,0,1.,0,0,0,0,1.,0", "CSYS/-1.,0,0,0,0,-1.,0,0,0,0,1.,0", 12,
     "CSYS is not the identity"),
    ("1STPECK,2.", "1STPECK,0", 20, "CYCLE/DEEP2 needs a first peck (1STPECK) greater than 0"),
    ("LOAD/TOOL,14", "LOAD/TOOL,14,ADJUST,3", 5, "LOAD/TOOL with another length offset"),
])
def test_what_solidworks_cam_writes_and_no_post_can_honour_is_refused(
        change: str, line: str, number: int, message: str) -> None:
    exc = error(SWCAM.replace(change, line))
    assert message in exc.message
    assert exc.location is not None and exc.location.line == number


def test_unequal_pecks_of_deep2_read_as_a_first_peck_and_the_later_pecks() -> None:
    [hole] = named(read(SWCAM.replace("1STPECK,2.", "1STPECK,5.")), "deep_drill")
    assert (hole["first_peck"], hole["peck"], hole["depth"]) == (5.0, 2.0, 24.6205)


def test_equal_pecks_of_deep2_carry_no_first_peck() -> None:
    [hole] = named(read(SWCAM), "deep_drill")
    assert hole["peck"] == 2.0 and "first_peck" not in hole


# --- Creo / Pro/ENGINEER ---------------------------------------------------------------------

CREO = """\
$$*          Pro/CLfile  Version 8.0 - 8.0.3.0
$$-> MFGNO / MFG0004
PARTNO / MFG0004
$$-> FEATNO / 32
MACHIN / UNCX01, 1
$$-> CUTCOM_GEOMETRY_TYPE / OUTPUT_ON_CENTER
UNITS / INCHES
LOADTL / 1
$$-> CUTTER / 3.000000
$$-> CSYS / 1.0000000000, 0.0000000000, 0.0000000000, 0.0000000000,  $
            0.0000000000, 1.0000000000, 0.0000000000, 0.0000000000,  $
            0.0000000000, 0.0000000000, 1.0000000000, 0.0000000000
SPINDL / RPM, 900.000000,  CLW
RAPID
GOTO / 1.0000000000, 2.0000000000, 2.0000000000
CYCLE / DEEP, DEPTH, 1.000000, STEP, 0.250000, IPM, 2.000000, CLEAR,$
 0.100000
GOTO / 1.0000000000, 2.0000000000, 0.5000000000
CYCLE / OFF
FEDRAT / 10.0, IPM
GOTO / 1.0, 2.0, 0.0
SPINDL / OFF
$$-> END /
FINI
"""


def test_a_creo_file_reads_with_its_continued_comment_and_inch_units() -> None:
    records = read(CREO)
    assert records[0] == {"cmd": "program_start", "program_name": "MFG0004"}
    assert named(records, "deep_drill") == [
        {"cmd": "deep_drill", "x": 25.4, "y": 50.8, "top": 12.7, "depth": 25.4,
         "clearance": pytest.approx(2.54), "peck": 6.35, "feed": 50.8}]
    assert named(records, "linear_move") == [
        {"cmd": "linear_move", "x": 25.4, "y": 50.8, "z": 0.0, "feed": 254.0}]


def test_a_comment_ending_in_a_dollar_does_not_swallow_the_next_record() -> None:
    records = read("PARTNO/T\n$$ the next record is continued with $\nRAPID\nGOTO/1,2,3\n"
                   "FINI\n")
    assert named(records, "rapid_move") == [{"cmd": "rapid_move", "x": 1.0, "y": 2.0,
                                             "z": 3.0}]


# --- NX, CATIA, Fusion ----------------------------------------------------------------------

NX = """\
TOOL PATH/PLANAR_MILL,TOOL,FLAT_TOOL
TLDATA/MILL,10.0000,0.5000,50.0000,0.0000,0.0000
MSYS/0.0000,0.0000,0.0000,1.0000000,0.0000000,0.0000000,0.0000000,1.0000000,0.0000000
$$ centerline data
PAINT/PATH
PAINT/SPEED,10
LOAD/TOOL,1,ADJUST,1
SPINDL/RPM,3000,CLW
PAINT/COLOR,186
RAPID
GOTO/0.0000,0.0000,50.0000,0.0000000,0.0000000,1.0000000
FEDRAT/MMPM,250.0000
GOTO/10.0000,0.0000,-1.0000
CIRCLE/5.0000,0.0000,-1.0000,0.0000000,0.0000000,1.0000000,5.0000,0.0600,0.5000,10.0000,0.0000
GOTO/0.0000,0.0000,-1.0000
GOHOME/0.0000,0.0000,50.0000
PAINT/SPEED,10
PAINT/TOOL,NOMORE
END-OF-PATH
"""


def test_an_nx_clsf_reads() -> None:
    records = read(NX)
    assert named(records, "tool_change") == [
        {"cmd": "tool_change", "tool_number": 1, "tool_diameter": 10.0,
         "tool_corner_radius": 0.5}]
    assert [r["cmd"] for r in records] == [
        "program_start", "tool_change", "spindle_on", "rapid_move", "linear_move",
        "arc_move", "rapid_move", "program_end"], "GOHOME is a rapid; END-OF-PATH ends it"
    assert records[-2] == {"cmd": "rapid_move", "x": 0.0, "y": 0.0, "z": 50.0}


def test_an_nx_path_ends_with_end_of_path_and_not_before() -> None:
    exc = error(NX.replace("END-OF-PATH\n", ""))
    assert exc.message.startswith("the CL file ends without END or FINI")
    exc = error(NX.replace("END-OF-PATH\n", "END-OF-PATH\nRAPID\nGOTO/0,0,60\n"))
    assert exc.message.startswith("the CL file ends without END or FINI")
    assert "TIMES" in error(NX.replace(",10.0000,0.0000\n", ",10.0000,0.0000,TIMES,2\n")
                            ).message


@pytest.mark.parametrize(("old", "new", "message"), [
    ("MSYS/0.0000,0.0000,0.0000,1.0000000", "MSYS/0.0000,0.0000,10.0000,2.0000000",
     "MSYS: the X axis (2, 0, 0) is not a unit vector"),
    ("GOTO/0.0000,0.0000,50.0000,0.0000000,0.0000000,1.0000000",
     "GOTO/0.0000,0.0000,50.0000,0.0000000,0.7071068,0.7071068",
     "tool axis (0, 0.707107, 0.707107) is not +Z: only 3-axis programs can be posted"),
    ("TLDATA/MILL", "TLDATA/TURN", "TLDATA describes no milling tool"),
    ("RAPID\nGOTO/0.0000,0.0000,50.0000,0.0000000,0.0000000,1.0000000",
     "FROM/0,0,50,0,1,0", "tool axis (0, 1, 0) is not +Z"),
])
def test_what_nx_writes_and_no_post_can_honour_is_refused(old: str, new: str,
                                                         message: str) -> None:
    assert message in error(NX.replace(old, new)).message


def test_catia_and_fusion_files_read() -> None:
    catia = ("$$*CATIA0\n$$*Part1\nPARTNO PART1\nTPRINT/T1 End Mill D 10\nMULTAX\n"
             "$$ OPERATION NAME : Tool Change.1\nCUTTER/ 20.000000, 3.000000\n"
             "TOOLNO/1, 20.000000, 3.000000,, 120.000000,$\n 0.0\n"
             "LOADTL/1,1\nSPINDL/ 1000.0000,RPM,CLW\nRAPID\nGOTO  /  0.0, 0.0, 5.0, 0.0, 0.0, "
             "1.0\nFEDRAT/ 100.0000,MMPM\nGOTO  /  1.0, 0.0, 5.0, 0.0, 0.0, 1.0\nEND\nFINI\n")
    assert [r["cmd"] for r in read(catia)] == [
        "program_start", "tool_change", "spindle_on", "rapid_move", "linear_move",
        "program_end"]
    assert "TLAXIS" in error(catia.replace("MULTAX\n", "TLAXIS/0,1,0\n")).message
    assert "a value is missing" in error(catia.replace("LOADTL/1,1", "LOADTL/1,,1")).message
    fusion = ("MACHIN/\nMODE/MILL\nPARTNO/'1001'\nPPRINT/'1001'\nUNITS/MM\nMULTAX/OFF\n"
              "CUTTER/6, 0, 0, 0, 0, 0, 20\nLOADTL/2, 0, 20, 0\nSPINDL/5000, RPM, CLW\n"
              "RAPID\nGOTO/10, 0, 0\nFEDRAT/300, MMPM\n"
              "MOVARC/0, 0, 0, 0, 0, 1, 10, ANGLE, 90\nGOTO/0, 10, 0\nEND\nFINI\n")
    records = read(fusion)
    assert records[0] == {"cmd": "program_start", "program_name": "1001"}
    assert [r["cmd"] for r in records] == [
        "program_start", "comment", "tool_change", "spindle_on", "rapid_move", "arc_move",
        "program_end"], "the GOTO after MOVARC repeats its end: no further move"
    assert "MODE/MILL" in error(fusion.replace("MODE/MILL", "MODE/TURN")).message


def test_a_file_mixing_two_dialects_is_refused() -> None:
    exc = error("PARTNO/1\nUNIT/MM\nTLDATA/MILL,10,0,50,0,0\nFINI\n")
    assert str(exc).startswith("d.apt:3: TLDATA/MILL,10,0,50,0,0: TLDATA is written by "
                               "NX (CLSF), but this file reads as SolidWorks CAM / CAMWorks "
                               "(line 2: UNIT/MM)")


@pytest.mark.parametrize(("record", "command"), [("STOP", "program_stop"),
                                                 ("OPSTOP", "optional_stop")])
def test_a_program_stop_is_read_not_dropped(record: str, command: str) -> None:
    commands = read_cl_text(f"PARTNO/1\n{record}\nFINI\n", "d.apt", "apt")
    assert [(c.name, c.line) for c in commands if c.name == command] == [(command, 2)]


def test_a_stop_inside_a_cycle_is_refused() -> None:
    exc = error("PARTNO/1\nLOADTL/1\nSPINDL/RPM,100,CLW\nFEDRAT/100\nGOTO/0,0,10\n"
                "CYCLE/DRILL,5,MMPM,100,2\nGOTO/0,0,0\nSTOP\nCYCLE/OFF\nFINI\n")
    assert "STOP inside CYCLE/DRILL" in exc.message
    assert exc.location is not None and exc.location.line == 8


def test_every_dialect_lists_every_iso_record_and_a_reason_for_each() -> None:
    for dialect in DIALECTS.values():
        assert set(ISO) <= set(dialect.records)
        for word, rule in dialect.records.items():
            assert rule.action in ("read", "ignore", "refuse"), word
            assert len(rule.why) > 10, word


def test_the_readme_names_every_dialect_and_its_own_records() -> None:
    from tests.conftest import ROOT

    section = (ROOT / "docs" / "reference" / "cl-input.md").read_text(encoding="utf-8")
    for dialect in DIALECTS.values():
        assert dialect.title.split(" (")[0] in section, dialect.title
        for word in dialect.records:
            assert f"`{word}" in section, f"{dialect.title}: {word} is not in cl-input.md"


def test_keyword_cycles_of_other_families_are_refused_not_guessed() -> None:
    """NX writes FEDTO,-72 and RTRCTO,AUTO: another reference than SolidWorks CAM's."""
    nx = NX.replace("FEDRAT/MMPM,250.0000\n", "CYCLE/DRILL,DEEP,STEP,20.0000,CLEAR,3.0000,"
                    "FEDTO,-72.0000,RTRCTO,AUTO,MMPM,250.0000\nGOTO/67.5,145.9,70.0\n"
                    "CYCLE/OFF\nFEDRAT/MMPM,250.0000\n")
    assert "the keyword form of CYCLE is read for SolidWorks CAM and Creo files" in error(
        nx).message
    plain = "PARTNO/1\nCYCLE/DRILL,FEDTO,5,MMPM,100,RAPTO,2\nGOTO/0,0,0\nCYCLE/OFF\nFINI\n"
    assert "whose reference is not known here" in error(plain).message


@pytest.mark.parametrize("text", ["STOP  change fixture", "STOP", "M00", "G28 Z0"])
def test_an_insert_that_is_a_command_is_refused(text: str) -> None:
    exc = error(SWCAM.replace("INSERT/[HOLDER=C40-32ERP412] 3.0mm SCREW MACH DRILL",
                              f"INSERT/{text}"))
    assert "INSERT passes a command to the control" in exc.message
    assert exc.location is not None and exc.location.line == 3


def test_a_record_of_one_family_waits_for_its_evidence() -> None:
    """APT's own INSERT passes code to the control: only SolidWorks CAM's is a comment."""
    exc = error("PARTNO/1\nINSERT/[HOLDER=X] DRILL\nFINI\n")
    assert exc.message.startswith("INSERT/[HOLDER=X] DRILL: unknown APT record 'INSERT'")
    assert named(read("PARTNO/1\nLOAD/TOOL,3\nFINI\n"), "tool_change") == [
        {"cmd": "tool_change", "tool_number": 3}]


def test_the_cycle_end_says_whether_the_file_cancelled_the_cycle() -> None:
    """CYCLE/OFF is a cancel; a CYCLE that follows without one ends the first by itself."""
    from postdsl.cl.model import CycleEnd

    def ends(text: str) -> list[tuple[str, int]]:
        return [(c.ended_by, c.line) for c in read_cl_text(text, "d.apt", "apt")
                if isinstance(c, CycleEnd)]

    assert ends(SWCAM) == [("cancel", 19), ("cancel", 22)]
    assert ends(SWCAM.replace("GOTO/9.,110.,0\nCYCLE/OFF\n", "GOTO/9.,110.,0\n")) == [
        ("next_cycle", 19), ("cancel", 21)]
