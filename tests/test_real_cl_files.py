"""Real CL files from CAM systems (tests/data/real, sources in SOURCES.md) through every machine.

Each file must post on a machine, or be refused at its line for a reason a
machinist accepts -- the message is part of the expectation below, so a new
refusal (or a refusal that goes away) fails here.  The motion of every program
that posts is checked against the CL: ``MOTION_CHECKS`` gives every machine
``postdsl verify`` (its control model against the CL), and the machines writing
Fanuc, LinuxCNC or GRBL G-code LinuxCNC's ``rs274`` too (its moves against the
model's, NC line by NC line).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from postdsl import api
from tests.conftest import DATA, THESIS_TIME
from tests.test_reader_gcode import Cut, compare_cuts, posted_for_rs274, rs274_cuts
from tests.test_rs274_oracle import HAVE_RS274, for_rs274, needs_rs274, run_rs274

REAL = DATA / "real"
#: every bundled machine (the Heidenhain post is not yet bundled)
MACHINES = ("feeler", "vmc500", "emco", "fanuc", "linuxcnc", "grbl", "hmcnc")
#: the machines whose NC output LinuxCNC's rs274 reads (Fanuc, LinuxCNC and GRBL G-code)
RS274_MACHINES = ("feeler", "fanuc", "linuxcnc", "grbl")

#: the spindle speed each machine refuses, as its message says it
_SPEED = {"vmc500": "is outside the range of VMC 500 (0 to 8000 rpm)",
          "emco": "is outside the range of EMCO Concept Mill 105 (150 to 5000 rpm)",
          "feeler": "is outside the range of Feeler VMP-45A (0 to 10000 rpm)",
          "fanuc": "is outside the range of Fanuc/Haas generic VMC (0 to 12000 rpm)"}
#: hmCNC's spindle is set by hand on the machine: a program cannot give it a speed
_HM_SPEED = ("spindle_on: the hmCNC spindle turns at the speed set on it "
             "(option spindle_speed_rpm); the CL's speed cannot be written")
#: the machines without cutter compensation refuse CUTCOM/LEFT for their control's reason
_NO_CUTCOM = {"vmc500": "the VMC 500 post knows no cutter compensation of the Acramatic 2100",
              "grbl": "GRBL 1.1 has no cutter radius compensation"}
_CSYS = "CSYS is not the identity: the CL has no way to carry a transformation"
#: FreeCAD's grbl post writes the tool change as a comment "(M6 T1.0)": a machine with a
#: tool changer would run the program with whatever tool (and length offset) it holds
_NO_TOOL = ("rapid_move before any tool is loaded: the machine has a tool changer, and motion "
            "needs a tool and its length offset (give a tool_change first")
#: a G28 G91 Z0 or G53 G0 Z.. of the input: the posts without a machine_retract table
_NO_RETRACT = "has no table for CL command 'machine_retract'"
_G53 = "machine_retract: a retract to a machine Z (G53) is not written by this post"
#: hmCNC's rapid table writes X, Y and Z, and cannot write a first rapid in Z alone (a post
#: gap, not a machinist's reason: reported, listed here so that it is seen when it changes)
_HM_Z_ONLY = "rapid_move: post table 'rapid_move' cannot be written: parameter 'x' has no value"
_PARAMS = "parameters ('#') and expressions ('[…]') are not read"
_NO_END = ("the program ends without M2 or M30 (RS274's end of program): the file may be "
           "cut short")
_AFTER_END = "nothing may follow the program end: ( Profile1 )"
_TOOL_0 = "tool_change: tool number 0 is not a tool of "
#: the machines' names as their refusals give them
MACHINE_NAMES = {"feeler": "Feeler VMP-45A", "vmc500": "VMC 500",
                 "emco": "EMCO Concept Mill 105", "fanuc": "Fanuc/Haas generic VMC",
                 "linuxcnc": "LinuxCNC mill", "grbl": "GRBL 1.1 router"}

#: file -> machine -> None (posts) or (CL line, the refusal's message, or a part of it)
EXPECTED: dict[str, dict[str, tuple[int, str] | None]] = {
    "creo_bohren_1.ncl": {"feeler": None, "fanuc": None, "linuxcnc": None, "grbl": None,
                          "vmc500": (13, f"spindle speed 9000 rpm {_SPEED['vmc500']}"),
                          "emco": (13, f"spindle speed 9000 rpm {_SPEED['emco']}"),
                          "hmcnc": (13, _HM_SPEED)},
    "creo_profilfraesen_2.ncl": {
        **{m: (13, f"spindle speed 15915.5 rpm {_SPEED[m]}") for m in _SPEED},
        "linuxcnc": None, "grbl": None, "hmcnc": (13, _HM_SPEED)},
    # CYCLE/DEEP2 with a first peck of 5 and later pecks of 2, RTRCTO 25 above R: the
    # Fanuc-family posts and the VMC500 write those holes as moves (expand_if); the EMCO
    # has 10 tools, hmCNC no tool changer at all
    "swcam_paralelipipedo_furos.apt": {
        "feeler": None, "vmc500": None, "fanuc": None, "linuxcnc": None, "grbl": None,
        "emco": (5, "tool 15 does not exist on EMCO Concept Mill 105 (tools 1 to 10)"),
        "hmcnc": (5, "tool_change: hmCNC has no pause to change a tool in: post each "
                     "tool's work as its own program")},
    "swcam_suporte_parede_side_drill.apt": {
        "feeler": None, "vmc500": None, "fanuc": None, "linuxcnc": None, "grbl": None,
        "emco": (5, "tool 20 does not exist on EMCO Concept Mill 105 (tools 1 to 10)"),
        "hmcnc": (8, "coolant_on: hmCNC has no coolant")},
    # CUTCOM/LEFT around a tool-centre path: the posts' declared mode (wear, their
    # option's default) writes G41 D21 on the lead-in line, G40 on the lead-out
    "swcam_lateral_leg_holder.apt": {
        "feeler": None, "fanuc": None, "linuxcnc": None,
        **{m: (19, _NO_CUTCOM[m]) for m in _NO_CUTCOM},
        "emco": (5, "tool 21 does not exist on EMCO Concept Mill 105 (tools 1 to 10)"),
        "hmcnc": (8, "coolant_on: hmCNC has no coolant")},
    "swcam_guincho_lbar1.apt": {m: (13, _CSYS) for m in MACHINES},
    "swcam_telemecanique_tilt_support1.apt": {m: (13, _CSYS) for m in MACHINES},
    # machines without a tool changer (LinuxCNC's post, GRBL) run them with the tool the
    # operator mounted; machines with one refuse the first move, which has no tool
    # the G0 Z6 before the first tool is the job's safe_retract (the posts with a tool
    # changer write it into their tool change); the first move in X Y is refused
    "freecad_grbl_helix.nc": {
        "feeler": (31, _NO_TOOL), "fanuc": (31, _NO_TOOL), "linuxcnc": None, "grbl": None,
        "vmc500": (24, f"spindle speed 9000 rpm {_SPEED['vmc500']}"),
        "emco": (24, f"spindle speed 9000 rpm {_SPEED['emco']}"),
        "hmcnc": (24, _HM_SPEED)},
    "freecad_grbl_drill.nc": {
        "feeler": (30, _NO_TOOL), "fanuc": (30, _NO_TOOL), "linuxcnc": None, "grbl": None,
        "vmc500": (20, f"spindle speed 9000 rpm {_SPEED['vmc500']}"),
        "emco": (20, f"spindle speed 9000 rpm {_SPEED['emco']}"),
        "hmcnc": (20, _HM_SPEED)},
    # --- programs written for this corpus in the styles of CAM systems' posts (SOURCES.md):
    # the G-code reader (tests/test_reader_gcode.py checks them against rs274 too)
    "styled_fusion_linuxcnc_bracket.ngc": {
        "fanuc": None, "linuxcnc": None,
        **{m: (7, _NO_RETRACT) for m in ("feeler", "vmc500", "emco", "grbl", "hmcnc")}},
    "styled_fusion_mach3_inch_face.tap": {
        "fanuc": None, "linuxcnc": None,
        **{m: (6, _NO_RETRACT) for m in ("feeler", "vmc500", "emco", "grbl", "hmcnc")}},
    # Fusion's grbl post names the tool (T1) but never loads it (no M6: grbl has no changer)
    "styled_fusion_grbl_pocket.nc": {
        "linuxcnc": None, "grbl": None, "feeler": (15, _NO_TOOL), "fanuc": (15, _NO_TOOL),
        "vmc500": (13, f"spindle speed 10000 rpm {_SPEED['vmc500']}"),
        "emco": (13, f"spindle speed 10000 rpm {_SPEED['emco']}"), "hmcnc": (13, _HM_SPEED)},
    "styled_vectric_mach3_atc_profile.tap": {
        "fanuc": None, "linuxcnc": None, "grbl": None,
        **{m: (21, f"spindle speed 12000 rpm {_SPEED[m]}") for m in ("feeler", "vmc500",
                                                                      "emco")},
        "hmcnc": (20, _HM_Z_ONLY)},
    # Estlcam for a router: no tool change at all
    "styled_estlcam_engrave.nc": {
        "linuxcnc": None, "grbl": None, "feeler": (15, _NO_TOOL), "fanuc": (15, _NO_TOOL),
        "vmc500": (13, f"spindle speed 10000 rpm {_SPEED['vmc500']}"),
        "emco": (13, f"spindle speed 10000 rpm {_SPEED['emco']}"), "hmcnc": (13, _HM_SPEED)},
    "styled_pycam_surface.ngc": {
        **{m: None for m in ("feeler", "vmc500", "emco", "fanuc", "linuxcnc", "grbl")},
        "hmcnc": (19, _HM_Z_ONLY)},
    # Carbide Create's first block after the header: G53 G0 Z-5 (5 mm below the machine's
    # top); the posts retract to their reference position instead, and refuse to guess
    "styled_carbide_create_pocket.nc": {
        "fanuc": (7, _G53), "linuxcnc": (7, _G53),
        **{m: (7, _NO_RETRACT) for m in ("feeler", "vmc500", "emco", "grbl", "hmcnc")}},
    "styled_linuxcnc_subroutine.ngc": {m: (2, _PARAMS) for m in MACHINES},
    # --- real G-code of CAM systems other than FreeCAD (the plain G-code reader; SOURCES.md)
    # PyCAM 0.5.1.1: F and S alone, G61, T4 M6, axis words alone on modal blocks
    "pycam_shapeoko_calibration.ngc": {
        **{m: None for m in ("feeler", "vmc500", "fanuc", "linuxcnc", "grbl")},
        "emco": (91, "Y 177.8 is outside the travel of EMCO Concept Mill 105 (-150 to 150)"),
        "hmcnc": (85, _HM_Z_ONLY)},
    # dxf2gcode: T1M6, S5000M03, F alone before each plunge and cut, blanks inside words
    # (X  34.897), G64 P0.01, and an M2 without a line end
    "dxf2gcode_erin7.ngc": {
        **{m: None for m in ("feeler", "vmc500", "fanuc", "linuxcnc", "grbl")},
        "emco": (172, "X 298.338 is outside the travel of EMCO Concept Mill 105 (-200 to 200)"),
        "hmcnc": (11, "coolant_on: hmCNC has no coolant")},
    # SketchUcam: an inch program (G20) whose arcs are in radius form (G3 … R1.0625)
    "sketchucam_arc_rword_test.gcode": {
        **{m: (14, f"spindle speed 15000 rpm {_SPEED[m]}") for m in _SPEED},
        "linuxcnc": None, "grbl": None, "hmcnc": (14, _HM_SPEED)},
    # pcb2gcode: an inch PCB isolation job; T1, then M6 and M0 for the operator, G64 P
    "pcb2gcode_multivibrator_back.ngc": {
        **{m: (20, f"spindle speed 12000 rpm {_SPEED[m]}") for m in ("feeler", "vmc500",
                                                                     "emco")},
        "fanuc": None, "linuxcnc": None, "grbl": None, "hmcnc": (13, _HM_Z_ONLY)},
    # pcb2gcode: holes drilled with a mill as helical full circles (G2 … Z.. I..)
    "pcb2gcode_multivibrator_milldrill.ngc": {
        **{m: (20, f"spindle speed 10000 rpm {_SPEED[m]}") for m in ("vmc500", "emco")},
        "feeler": None, "fanuc": None, "linuxcnc": None, "grbl": None,
        "hmcnc": (13, _HM_Z_ONLY)},
    # CamBam names its one tool T0 ("T0 M6"): no machine here has a tool 0
    "cambam_ordbot_handle.nc": {
        **{m: (7, f"{_TOOL_0}{MACHINE_NAMES[m]} (declare machine.tools.min_number: 0 "
                  f"where tool 0 is real)") for m in MACHINE_NAMES},
        "hmcnc": (5, _HM_Z_ONLY)},
    # a CamBam file holding more after its M30 (line 2161), which no control would run
    "cambam_electric_turtle.nc": {m: (2162, _AFTER_END) for m in MACHINES},
    # jscut and the Universal Gcode Sender's designer write no M2 or M30 (grbl needs none):
    # a file without its end may be cut short, and is refused at its last line
    "jscut_jsdc.gcode": {m: (2428, _NO_END) for m in MACHINES},
    "ugs_designer.gcode": {m: (1363, _NO_END) for m in MACHINES},
}

MotionCheck = Callable[[Path, api.CompiledPost, Path], None]


def _verify(path: Path, post: api.CompiledPost, tmp_path: Path) -> None:
    """postdsl verify: the NC replayed through the machine's control model, cut by cut."""
    verdict = api.verify_commands(post, api.read_cl(path), cl_file=str(path), now=THESIS_TIME)
    assert verdict.ok, str(verdict.divergence)
    assert verdict.cuts + verdict.holes > 0


#: rs274's tool table: the real files use tools up to T20 (tests/test_rs274_oracle.py's
#: table stops at T9); lengths 0, as the comparison is of the programmed tool tip
_TOOL_TABLE = "".join(f"T{n} P{n} Z0 D0\n" for n in range(1, 100))


def _rs274(path: Path, post: api.CompiledPost, tmp_path: Path) -> None:
    """LinuxCNC's rs274 makes, NC line by NC line, the moves the control model makes.

    ``postdsl verify`` compared the model's moves with the CL (:func:`_verify`); rs274, an
    interpreter postdsl does not share, must cut what the model cuts and nothing more.
    """
    from postdsl.check.controls import NCInput, control_model
    from tests.test_controls_rs274 import cross_check

    if not HAVE_RS274:
        pytest.skip("the G-code oracle rs274 is not installed")
    lines = [line.text for line in api.post_commands(post, api.read_cl(path),
                                                     cl_file=str(path), now=THESIS_TIME)]
    assert post.machine.control is not None
    if post.machine.control.startswith("fanuc"):
        numbered = for_rs274(lines)  # the documented rewrite: P in ms, N words renumbered
    else:  # LinuxCNC and GRBL G-code is rs274's own: only numbered ('%' stays bare)
        numbered = [line if line.strip() == "%" else f"N{n} {line}"
                    for n, line in enumerate(lines, start=1)]
    trace = run_rs274(numbered, tmp_path, _TOOL_TABLE)
    assert trace.units == {"CANON_UNITS_MM"}
    model = control_model(post.machine.control)
    # the model reads the program as the control does (a Fanuc's G4 P in ms, not the
    # rewrite's seconds); its lines are numbered as rs274's are, one per NC line
    replayed = lines if post.machine.control.startswith("fanuc") else numbered
    events = list(model.replay(NCInput(n, line) for n, line in enumerate(replayed, start=1)))
    counted = cross_check(events, trace)
    assert counted["feed"] + counted["arc"] + counted["hole"] > 0


def _verify_and_rs274(path: Path, post: api.CompiledPost, tmp_path: Path) -> None:
    _verify(path, post, tmp_path)
    _rs274(path, post, tmp_path)


#: machine -> the independent checks of its NC output's motion against the CL: the
#: control model of ``postdsl verify`` for every machine, and LinuxCNC's rs274 for the
#: machines whose G-code it reads
MOTION_CHECKS: dict[str, MotionCheck] = {
    m: _verify_and_rs274 if m in RS274_MACHINES else _verify for m in MACHINES}


def test_every_real_file_is_listed_and_every_listed_file_exists() -> None:
    files = {p.name for p in REAL.iterdir() if p.suffix != ".md"}
    assert files == set(EXPECTED)
    assert all(set(machines) == set(MACHINES) for machines in EXPECTED.values())
    sources = (REAL / "SOURCES.md").read_text(encoding="utf-8")
    assert all(f"`{name}`" in sources for name in files)


def test_every_bundled_machine_is_run() -> None:
    """A new bundled post joins this corpus (Heidenhain's is being written elsewhere)."""
    bundled = {p.stem for p in (Path(__file__).parent.parent / "machines").glob("*.yaml")}
    # the 3+2 posts (tests/test_tilted_planes.py) post 3-axis files as the posts they extend,
    # and so do the 4-axis posts (tests/test_rotary.py)
    bundled -= {"fanuc_3plus2", "heidenhain_3plus2", "sinumerik_3plus2",
                "linuxcnc_xyza", "fanuc_4axis", "linuxcnc_xyza_rezero", "emco_4axis"}
    assert bundled - {"heidenhain", "tnc"} <= set(MACHINES) <= bundled


@pytest.mark.parametrize(("name", "machine"),
                         [(n, m) for n in EXPECTED for m in MACHINES])
def test_a_real_file_posts_or_is_refused_for_its_reason(name: str, machine: str,
                                                        tmp_path: Path) -> None:
    path = REAL / name
    expected = EXPECTED[name][machine]
    post = api.load_post(machine)
    if expected is None:
        commands = api.read_cl(path)
        api.post_commands(post, commands, cl_file=str(path), now=THESIS_TIME)
        MOTION_CHECKS[machine](path, post, tmp_path)
        return
    line, message = expected
    with pytest.raises(api.CLError) as caught:
        api.post_commands(post, api.read_cl(path), cl_file=str(path), now=THESIS_TIME)
    assert caught.value.location is not None
    assert (caught.value.location.file, caught.value.location.line) == (str(path), line)
    assert message in caught.value.message


def test_some_real_file_posts_on_every_machine_but_emco_and_hmcnc() -> None:
    """hmCNC sets its spindle speed by hand and has no tool changer or coolant, the EMCO has
    tools 1 to 10 and at most 5000 rpm: every real file asks for more (the EMCO posts one
    with its tool renumbered, below); every other machine posts at least one real file."""
    assert set(MOTION_CHECKS) == set(MACHINES)
    posting = {m for name, machines in EXPECTED.items() for m, e in machines.items()
               if e is None and not name.startswith("styled_")}
    assert posting == set(MACHINES) - {"hmcnc", "emco"}


def test_with_its_tool_in_the_emcos_magazine_the_side_drill_posts_there(
        tmp_path: Path) -> None:
    """The EMCO refuses the SolidWorks CAM side drill only for its tool 20: renumbered to
    tool 2 (what the machinist does when setting up the job), it posts, its unequal pecks
    drilled as moves, and verify finds its motion right."""
    text = (REAL / "swcam_suporte_parede_side_drill.apt").read_text(encoding="utf-8")
    assert text.count("LOAD/TOOL,20") == 1
    path = tmp_path / "side_drill_tool_2.apt"
    path.write_text(text.replace("LOAD/TOOL,20", "LOAD/TOOL,2"), encoding="utf-8")
    post = api.load_post("emco")
    nc = api.post_commands(post, api.read_cl(path), cl_file=str(path), now=THESIS_TIME)
    assert not any("CYCLE83" in line.text for line in nc)
    _verify(path, post, tmp_path)


def test_the_tool_change_freecads_grbl_post_writes_as_a_comment_loads_no_tool() -> None:
    """'(M6 T1.0)' is a comment: no tool is loaded, and the first move says so, located."""
    from postdsl.cl.model import ToolChange

    for name, line in (("freecad_grbl_helix.nc", 31), ("freecad_grbl_drill.nc", 30)):
        text = (REAL / name).read_text(encoding="utf-8")
        assert "(M6 T1.0)" in text
        assert text.splitlines()[line - 1].startswith("G0 X")
        assert not any(isinstance(c, ToolChange) for c in api.read_cl(REAL / name))


def test_unequal_pecks_and_a_high_retract_plane_are_drilled_as_moves() -> None:
    """The SolidWorks CAM CYCLE/DEEP2 (first peck 5, later 2, RTRCTO above R): the posts
    whose cycles take one peck, or leave the tool at R, write no cycle for it but the
    pecks the CL asks for -- the first to 5 below the top, the next 2 deeper each."""
    from postdsl.cl.model import DeepDrill

    path = REAL / "swcam_suporte_parede_side_drill.apt"
    setups = [c for c in api.read_cl(path) if isinstance(c, DeepDrill)]
    assert [(s.first_peck, s.peck) for s in setups] == [(5.0, 2.0), (5.0, 2.0)]
    for machine in ("feeler", "fanuc", "linuxcnc", "vmc500"):
        post = api.load_post(machine)
        nc = api.post_commands(post, api.read_cl(path), cl_file=str(path), now=THESIS_TIME)
        assert not any("G83" in line.text for line in nc), machine
        for setup in setups:
            drilled = [line for line in nc if line.cl_line == setup.line]
            assert {line.command for line in drilled} <= {"cycle_start", "rapid_move",
                                                          "linear_move"}, machine
            feeds = [line.text for line in drilled if line.command == "linear_move"]
            # the hole's depth 5.03163 from its top: one peck of 5, then 0.03163 more
            assert len(feeds) == 2, (machine, feeds)


def test_freecad_post_output_reads_in_mm_per_minute() -> None:
    """grbl_MIHO_post writes F30.00 for 30 mm/min: read as such, never x60."""
    from postdsl.cl.model import ArcMove, LinearMove

    helix = api.read_cl(REAL / "freecad_grbl_helix.nc")
    feeds = {c.feed for c in helix if isinstance(c, (LinearMove, ArcMove)) and c.feed}
    assert feeds == {30.0, 300.0}
    assert sum(isinstance(c, ArcMove) for c in helix) > 10
    drill = api.read_cl(REAL / "freecad_grbl_drill.nc")
    assert {c.feed for c in drill if isinstance(c, LinearMove) and c.feed} == {30.0}


def test_the_creo_drill_cycle_reads_from_the_hole_top() -> None:
    from postdsl.cl.model import CycleHole, DeepDrill

    commands = api.read_cl(REAL / "creo_bohren_1.ncl")
    [setup] = [c for c in commands if isinstance(c, DeepDrill)]
    assert (setup.x, setup.y, setup.top, setup.depth, setup.peck, setup.clearance,
            setup.feed) == (pytest.approx(-7.2290790757), -23.0, 0.5, 3.5, 1.0, 1.0, 50.0)
    assert [(c.x, c.y) for c in commands if isinstance(c, CycleHole)] == [
        (pytest.approx(-16.780389118), -23.0)]


#: file -> (the refused record, what it is replaced with to read on, then None when the rest
#: of the file reads, or the (line, message) of the next refusal)
_REST: dict[str, tuple[str, str, tuple[int, str] | None]] = {
    "swcam_guincho_lbar1.apt": ("CSYS/-1.,0,0,0,0,-1.,0,0,0,0,1.,0",
                                "CSYS/1.,0,0,0,0,1.,0,0,0,0,1.,0", None),
    # the tilt is in the GOTOs' tool axis too: read (a 4-axis post solves it), and refused
    # at the first drilling cycle along it
    "swcam_telemecanique_tilt_support1.apt": (
        "CSYS/0,-0.984808,-0.173648,0,1.,0,0,0,0,-0.173648,.984808,0",
        "CSYS/1.,0,0,0,0,1.,0,0,0,0,1.,0",
        (324, "a drilling cycle along the tool axis (-0.173648, 0, 0.984808)")),
}


@pytest.mark.parametrize("name", sorted(_REST))
def test_a_file_refused_by_its_reader_is_refused_at_its_first_such_record_only(
        name: str) -> None:
    """With the refused record read as one that can be honoured, the rest of the file
    reads: the refusal was the file's first problem, not one of many."""
    record, replacement, then = _REST[name]
    text = (REAL / name).read_text(encoding="utf-8")
    assert record in text
    changed = text.replace(record, replacement)
    if then is None:
        assert api.read_cl_text(changed, name, "apt")
        return
    with pytest.raises(api.CLError) as caught:
        api.read_cl_text(changed, name, "apt")
    assert caught.value.location is not None and caught.value.location.line == then[0]
    assert then[1] in caught.value.message


# --- real G-code of CAM systems other than FreeCAD: rs274 reads the program itself --------

def _cut_something(cuts: list[Cut]) -> list[Cut]:
    """rs274's cuts without the feed moves that go nowhere on a machine of 0.001 mm steps
    (a ``G01 F100`` block alone is one to rs274, a feed set to the CL; CamBam's
    ``G1 Y32.7692`` after ``Y32.7691`` is one step of no length: the posts, writing 3
    decimals of mm, write neither); an arc that ends where it starts is a full circle."""
    def step(point: tuple[float, ...]) -> tuple[float, ...]:
        return tuple(round(value, 3) for value in point)
    return [cut for cut in cuts if cut.kind == "arc" or step(cut.start) != step(cut.end)]


def _rs274_agrees(program: list[str], posted: list[str], tmp_path: Path, inch: bool) -> int:
    """LinuxCNC's rs274 reads the CAM's program and the posted program: the same cuts, one
    by one.  rs274 prints 4 decimals of the program's unit (0.0001 inch is 0.00254 mm);
    the posts write 3 decimals of mm, each value within half a step of the CAM's, so an
    arc's centre (its start plus I, J) is within one step: 0.0015 mm."""
    original = _cut_something(rs274_cuts(program, tmp_path))
    again = _cut_something(rs274_cuts(posted, tmp_path))
    return compare_cuts(again, original, 0.003 if inch else 0.0015)


#: the real G-code programs that post, and the G-code posts whose output rs274 compares
#: with the program itself (Feeler's and GRBL's G-code differs from rs274's in its canned
#: cycles and G30 blocks; their output is checked by the control models' cross-check)
RS274_PROGRAMS = {"pycam_shapeoko_calibration.ngc": ("linuxcnc", "fanuc"),
                  "dxf2gcode_erin7.ngc": ("linuxcnc", "fanuc"),
                  "sketchucam_arc_rword_test.gcode": ("linuxcnc",),
                  "pcb2gcode_multivibrator_back.ngc": ("linuxcnc", "fanuc"),
                  "pcb2gcode_multivibrator_milldrill.ngc": ("linuxcnc", "fanuc")}


@needs_rs274
@pytest.mark.parametrize(("name", "machine"),
                         [(n, m) for n, machines in RS274_PROGRAMS.items() for m in machines])
def test_rs274_cuts_the_posted_program_as_the_cams_own(name: str, machine: str,
                                                       tmp_path: Path) -> None:
    """An independent reading of the CAM's program (rs274) against postdsl's (the posted
    program, read by rs274 too): the reader is right when every cut is the same."""
    path = REAL / name
    assert EXPECTED[name][machine] is None
    text = path.read_text(encoding="utf-8")
    cuts = _rs274_agrees(text.splitlines(), posted_for_rs274(machine, path), tmp_path,
                         "G20" in text)
    assert cuts > 100


#: file -> (what the machinist changes at set-up, to what, the machines it then posts on
#: and whose output rs274 compares with the changed program, or the next refusal)
SET_UPS: dict[str, tuple[str, str, tuple[str, ...] | tuple[int, str]]] = {
    # CamBam's tool 0, loaded as tool 1: posts, and cuts as CamBam's program does
    "cambam_ordbot_handle.nc": ("T0 M6\r\n", "T1 M6\r\n", ("fanuc",)),
    # the end the file lacks, written: the UGS designer's job posts and cuts as written
    "ugs_designer.gcode": ("M5\n", "M5\nM2\n", ("linuxcnc",)),
    # jscut writes no spindle start at all (a router switched by hand): the first cut
    # is refused for it, on a machine whose spindle the program runs
    "jscut_jsdc.gcode": ("G0 X0 Y0 F2540\n", "G0 X0 Y0 F2540\nM2\n",
                         (3, "linear_move: a cutting move with the spindle stopped")),
}


@needs_rs274
@pytest.mark.parametrize("name", sorted(SET_UPS))
def test_a_refused_real_program_set_up_as_a_machinist_would_posts(name: str,
                                                                   tmp_path: Path) -> None:
    """The refusal was the program's only problem: changed as the machinist does at the
    machine, it posts, verify passes, and rs274 reads it as the CAM wrote it."""
    old, new, then = SET_UPS[name]
    text = (REAL / name).read_bytes().decode("utf-8")
    assert text.count(old) == 1 and text.endswith(old) == (name != "cambam_ordbot_handle.nc")
    path = tmp_path / name
    path.write_bytes(text.replace(old, new).encode("utf-8"))
    if isinstance(then[0], int):
        with pytest.raises(api.CLError) as caught:
            api.post_commands(api.load_post("linuxcnc"), api.read_cl(path), cl_file=str(path),
                              now=THESIS_TIME)
        assert caught.value.location is not None and caught.value.location.line == then[0]
        assert str(then[1]) in caught.value.message
        return
    for machine in then:
        post = api.load_post(str(machine))
        _verify(path, post, tmp_path)
        program = path.read_text(encoding="utf-8").splitlines()
        assert _rs274_agrees(program, posted_for_rs274(str(machine), path), tmp_path,
                             False) > 100


def test_after_the_first_program_end_a_camBam_file_holds_another() -> None:
    """The CamBam file is refused at the line after its first M30, which a control stops
    at: what comes before reads whole."""
    lines = (REAL / "cambam_electric_turtle.nc").read_text(encoding="utf-8").splitlines()
    assert lines[2160] == "M30" and lines.count("M30") > 2
    assert api.read_cl_text("\n".join(lines[:2161]) + "\n", "turtle.nc", "gcode")


#: the real G-code of CAM systems other than FreeCAD (SOURCES.md)
CAM_GCODE = ("pycam_shapeoko_calibration.ngc", "dxf2gcode_erin7.ngc",
             "sketchucam_arc_rword_test.gcode",
             "pcb2gcode_multivibrator_back.ngc", "pcb2gcode_multivibrator_milldrill.ngc",
             "cambam_ordbot_handle.nc", "cambam_electric_turtle.nc", "jscut_jsdc.gcode",
             "ugs_designer.gcode")


@pytest.mark.parametrize("name", CAM_GCODE)
def test_another_cams_g_code_goes_to_the_g_code_reader_by_its_evidence(name: str) -> None:
    """No ``--format``: the first lines say plain RS274 G-code (a T before M6, F or S
    alone, or only what every RS274 program writes), not FreeCAD's output."""
    from postdsl.cl.readers import detect_format

    lines = (REAL / name).read_text(encoding="utf-8").splitlines()
    assert detect_format(lines, name) == "gcode"
