"""3+2 tilted planes: the work_plane record, each control's tilted-plane block, and verify
replaying the plane in the part frame.

rs274 (LinuxCNC's interpreter) has no G68.2, PLANE or CYCLE800: these programs have no
independent oracle, so verify -- the control models applying each control's rotation
convention, compared with the CL's plane at every cut -- is the check, and each mutation
a post could make is shown caught here.
"""

from __future__ import annotations

import itertools
import json
import math
import re
from pathlib import Path

import pytest

from postdsl import api, frames
from postdsl.check import toolpath
from postdsl.check.controls import control_model
from postdsl.check.controls.base import ControlError
from postdsl.cl.model import WorkPlane
from postdsl.errors import CLError, PostError
from tests.conftest import ROOT, THESIS_TIME

CL = ROOT / "examples" / "tilted_planes.jsonl"
#: CL lines: the two planes, the reset, and the first cut in each frame
PLANE_1, PLANE_2, RESET = 6, 15, 26
CUT_1, CUT_2, CUT_TOP = 9, 18, 29


def _words(machine: str, cl_line: int) -> list[str]:
    lines = api.post_commands(api.load_post(machine), api.read_cl(CL), cl_file=CL.name,
                              now=THESIS_TIME)
    return [re.sub(r"^(N\d+ |\d+ )", "", line.text).strip() for line in lines
            if line.cl_line == cl_line]


# --- the conventions -------------------------------------------------------------------


@pytest.mark.parametrize("convention", sorted(frames.CONVENTIONS))
def test_each_convention_gives_back_the_rotation_its_angles_were_read_from(
        convention: str) -> None:
    steps = (-170.0, -90.0, -35.5, 0.0, 30.0, 90.0, 180.0)
    for angles in itertools.product(steps, repeat=3):
        rotation = frames.CONVENTIONS[convention].rotation(*angles)
        back = frames.control_angles(convention, frames.Frame((0, 0, 0), rotation))
        again = frames.CONVENTIONS[convention].rotation(*back)
        assert all(math.isclose(rotation[i][j], again[i][j], abs_tol=1e-9)
                   for i in range(3) for j in range(3)), (angles, back)


def test_the_conventions_are_the_controls_own() -> None:
    """A tool tilted 30 degrees towards +X (about Y): Fanuc's Euler Z-X'-Z'' needs I90 J30
    K-90 (turn X onto Y, tilt about it, turn back); Heidenhain's fixed axes and
    Sinumerik's axis-by-axis turn need the second angle alone."""
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    plane = frames.frame_of((0, 0, 0), (c, 0, -s), (s, 0, c))
    assert [round(a, 9) for a in frames.control_angles("euler_zxz", plane)] == [90, 30, -90]
    assert [round(a, 9) for a in frames.control_angles("fixed_xyz", plane)] == [0, 30, 0]
    assert [round(a, 9) for a in frames.control_angles("rotated_xyz", plane)] == [0, 30, 0]
    # a compound plane: the orders differ, and each gives the plane back in its own
    compound = frames.Frame((0, 0, 0), frames.product(frames.rx(45), frames.rz(30)))
    found = {name: frames.control_angles(name, compound) for name in frames.CONVENTIONS}
    assert len({tuple(round(a, 6) for a in angles) for angles in found.values()}) == 4
    assert [round(a, 9) for a in found["euler_zxz"]] == [0, 45, 30]
    assert [round(a, 9) for a in found["rotated_xyz"]] == [45, 0, 30]


# --- the posts ---------------------------------------------------------------------------

WRITTEN = {
    "fanuc_3plus2": (
        ["G91 G28 Z0.", "G90", "G69", "G68.2 X100. Y0. Z40. I90. J30. K-90.", "G53.1"],
        ["G91 G28 Z0.", "G90", "G69", "G68.2 X0. Y0. Z40. I0. J45. K30.", "G53.1"],
        ["G91 G28 Z0.", "G90", "G69"]),
    "heidenhain_3plus2": (
        ["L M140 MB MAX", "PLANE RESET STAY", "TRANS DATUM RESET",
         "TRANS DATUM AXIS X+100 Y+0 Z+40", "PLANE SPATIAL SPA+0 SPB+30 SPC+0 TURN MB MAX FMAX"],
        ["L M140 MB MAX", "PLANE RESET STAY", "TRANS DATUM RESET",
         "TRANS DATUM AXIS X+0 Y+0 Z+40",
         "PLANE SPATIAL SPA+40.8934 SPB-20.7048 SPC+22.2077 TURN MB MAX FMAX"],
        ["L M140 MB MAX", "PLANE RESET STAY", "TRANS DATUM RESET",
         "PLANE RESET TURN MB MAX FMAX"]),
    "sinumerik_3plus2": (
        ['CYCLE800(1,"TC1",0,57,100.000,0.000,40.000,0,30,0,0,0,0,-1,0,0)'],
        ['CYCLE800(1,"TC1",0,57,0.000,0.000,40.000,45,0,30,0,0,0,-1,0,0)'],
        ['CYCLE800(1,"TC1",0,57,0.000,0.000,0.000,0,0,0,0,0,0,-1,0,0)', "CYCLE800()"]),
}


@pytest.mark.parametrize("machine", sorted(WRITTEN))
def test_each_post_writes_its_controls_tilted_plane_block_and_it_verifies(machine: str) -> None:
    assert (_words(machine, PLANE_1), _words(machine, PLANE_2), _words(machine, RESET)) \
        == WRITTEN[machine]
    verdict = api.verify_commands(api.load_post(machine), api.read_cl(CL), cl_file=CL.name)
    assert verdict.divergence is None, verdict.divergence
    assert verdict.cuts >= 10 and verdict.holes == 2  # the holes on the 45° bevel too


def test_the_3plus2_posts_extend_the_library_posts() -> None:
    for machine, base in (("fanuc_3plus2", "fanuc"), ("heidenhain_3plus2", "heidenhain"),
                          ("sinumerik_3plus2", "emco")):
        text = (ROOT / "machines" / f"{machine}.yaml").read_text(encoding="utf-8")
        assert f"\nextends: {base}\n" in text


@pytest.mark.parametrize("machine", ["fanuc", "heidenhain", "emco", "linuxcnc", "grbl"])
def test_a_three_axis_post_refuses_a_work_plane_with_the_reason(machine: str) -> None:
    with pytest.raises(CLError) as caught:
        list(api.post_commands(api.load_post(machine), api.read_cl(CL), cl_file=CL.name))
    assert caught.value.location is not None and caught.value.location.line == PLANE_1
    assert "does not tilt the working plane" in caught.value.message
    assert "a three-axis machine cannot cut in a tilted plane" in caught.value.message


@pytest.mark.parametrize("machine", sorted(WRITTEN))
def test_a_tool_change_inside_a_tilted_plane_is_refused(machine: str) -> None:
    records = [json.loads(line) for line in CL.read_text(encoding="utf-8").splitlines()]
    at = next(i for i, r in enumerate(records) if r["cmd"] == "operation" and i > PLANE_1)
    records.insert(at, {"cmd": "tool_change", "tool_number": 2, "tool_diameter": 6})
    text = "".join(json.dumps(r) + "\n" for r in records)
    with pytest.raises(CLError, match="a tool change inside a") as caught:
        list(api.post_commands(api.load_post(machine), api.read_cl_text(text, "t.jsonl")))
    assert caught.value.location is not None and caught.value.location.line == at + 1


def test_a_plane_whose_axes_are_not_a_frame_is_refused_at_its_line() -> None:
    text = CL.read_text(encoding="utf-8").replace('"z_axis_k": 0.866025404',
                                                  '"z_axis_k": 0.9', 1)
    with pytest.raises(CLError, match=r"the plane's Z axis .* is not a unit vector") as caught:
        list(api.post_commands(api.load_post("fanuc_3plus2"),
                               api.read_cl_text(text, "t.jsonl")))
    assert caught.value.location is not None and caught.value.location.line == PLANE_1


# --- mutations verify must catch -------------------------------------------------------

#: what each mutation overrides in a post extending the library post, and the CL line of
#: the first cut that goes wrong
MUTATIONS = {
    # the angles computed in another convention than the control reads
    "euler order": {
        "fanuc_3plus2": ("machine: {name: m, tilted_plane: euler_zyz}", {}, CUT_1),
        "heidenhain_3plus2": ("machine: {name: m, tilted_plane: rotated_xyz}", {}, CUT_2),
        "sinumerik_3plus2": ("machine: {name: m, tilted_plane: fixed_xyz}", {}, CUT_2),
    },
    "sign reversed": {
        "fanuc_3plus2": ("", {"commands/work_plane/blocks/3/items/5":
                              '{expr: "-plane_angle_2", prefix: " J", format: angle}'}, CUT_1),
        "heidenhain_3plus2": ("", {"commands/work_plane/blocks/4/items/2":
                                   '{expr: "-plane_angle_2", prefix: " SPB", format: angle}'},
                              CUT_1),
        "sinumerik_3plus2": ("", {"structures/swivel/0/items/11":
                                  "{expr: \"-plane_angle_2 if work_plane == 'tilted' else 0\", "
                                  "format: angle}"},
                             CUT_1),
    },
    # the plane is not cancelled before the three-axis operation
    "no cancel": {
        "fanuc_3plus2": ("", {"commands/work_plane/blocks/2/if": "\"work_plane == 'tilted'\""},
                         CUT_TOP),
        "heidenhain_3plus2": ("", {"commands/work_plane/blocks/5/items/0":
                                   '"PLANE RESET STAY"'}, CUT_TOP),
        "sinumerik_3plus2": ("", {"commands/work_plane/blocks/0/if":
                                  "\"work_plane == 'tilted'\""}, CUT_TOP),
    },
    # the second plane's blocks dropped: its operation runs in the first plane
    "plane change dropped": {
        "fanuc_3plus2": ("", {f"commands/work_plane/blocks/{n}/if":
                              "\"origin_x > 50 or work_plane == 'reset'\"" for n in (2, 3, 4)},
                         CUT_2),
        "heidenhain_3plus2": ("", {f"commands/work_plane/blocks/{n}/if":
                                   "\"origin_x > 50 or work_plane == 'reset'\""
                                   for n in (1, 2, 3, 4)}, CUT_2),
        "sinumerik_3plus2": ("", {"commands/work_plane/blocks/0/if":
                                  "\"origin_x > 50 or work_plane == 'reset'\""}, CUT_2),
    },
}


@pytest.mark.parametrize(("mutation", "machine"), [
    (mutation, machine) for mutation, posts in MUTATIONS.items() for machine in posts])
def test_verify_catches_a_mutated_tilted_plane(mutation: str, machine: str,
                                               tmp_path: Path) -> None:
    machine_yaml, overrides, line = MUTATIONS[mutation][machine]
    text = f"postdsl: 1\nextends: {ROOT / 'machines' / machine}.yaml\n{machine_yaml}\n"
    if overrides:
        text += "override:\n" + "".join(f"  {key}: {value}\n" for key, value in overrides.items())
    path = tmp_path / "mutant.yaml"
    path.write_text(text, encoding="utf-8")
    mutant = api.load_post(path)
    verdict = api.verify_commands(mutant, api.read_cl(CL), cl_file=CL.name)
    assert verdict.divergence is not None, f"{mutation} on {machine} went unnoticed"
    assert verdict.divergence.cl is not None and verdict.divergence.cl.line == line, \
        str(verdict.divergence)


# --- the control models ------------------------------------------------------------------


@pytest.mark.parametrize(("model", "program", "message"), [
    ("fanuc-0i", "G53.1", "G53.1 without a tilted plane"),
    ("fanuc-0i", "G68.2 X0 Y0 Z0 I0 J30.\nG53.1", "G68.2 without K"),
    ("fanuc-0i", "G68.2 I0 J30. K0\nG53.1\nG68.2 I0 J0 K0", "cancel it with G69 first"),
    ("fanuc-0i", "T1 M6\nG0 G43 H1 Z50.\nS1000 M3\nG68.2 I0 J30. K0\nG0 X0 Y0 Z5.\n"
                 "G1 Z0 F100.", "a cut after G68.2 without G53.1"),
    ("sinumerik-828d", 'CYCLE800(1,"TC1",0,27,0,0,0,0,30,0,0,0,0,-1,0,0)',
     "swivel mode 27 is not modelled"),
    ("sinumerik-828d", 'T1 M6\nM3 S1000\nCYCLE800(1,"TC1",0,57,0,0,0,0,30,0,0,0,0,0,0,0)\n'
                       "G0 X0 Y0 Z5\nG1 Z0 F100", "the rotary axes not turned"),
])
def test_the_models_refuse_a_tilted_plane_their_control_would_not_run(
        model: str, program: str, message: str) -> None:
    with pytest.raises(ControlError, match=re.escape(message)):
        list(control_model(model).replay(program.split("\n")))


def test_the_heidenhain_model_refuses_a_cut_while_the_head_stays() -> None:
    program = ["0 BEGIN PGM T MM", "1 TOOL CALL 1 Z S1000", "2 M3",
               "3 PLANE SPATIAL SPA+0 SPB+30 SPC+0 STAY", "4 L X+0 Y+0 Z+5 R0 FMAX",
               "5 L Z+0 R0 F100", "6 END PGM T MM"]
    with pytest.raises(ControlError, match="rotary axes not where the last PLANE says"):
        list(control_model("heidenhain-tnc640").replay(program))


def test_a_model_maps_the_planes_coordinates_to_the_part_frame() -> None:
    """G68.2 I90 J30 K-90: the plane's X+10 is 10 mm along the tilted X axis from its
    origin, in the part frame."""
    model = control_model("fanuc-0i")
    list(model.replay(["G68.2 X100. Y0. Z40. I90. J30. K-90.", "G53.1"]))
    assert model.frame is not None
    x, y, z = model.frame.to_part((10, 0, 0))
    assert (round(x, 6), round(y, 6), round(z, 6)) == (round(100 + 10 * math.cos(
        math.radians(30)), 6), 0, round(40 - 10 * math.sin(math.radians(30)), 6))
    list(model.replay(["G69"]))
    assert model.frame is None


# --- APT -------------------------------------------------------------------------------

NX = """\
TOOL PATH/PLANAR_MILL,TOOL,FLAT_TOOL
TLDATA/MILL,10.0000,0.5000,50.0000,0.0000,0.0000
MSYS/0.0000,0.0000,0.0000,1.0000000,0.0000000,0.0000000,0.0000000,1.0000000,0.0000000
LOAD/TOOL,1,ADJUST,1
SPINDL/RPM,3000,CLW
MSYS/100.0000,0.0000,40.0000,0.8660254,0.0000000,-0.5000000,0.0000000,1.0000000,0.0000000
RAPID
GOTO/0.0000,0.0000,50.0000,0.0000000,0.0000000,1.0000000
FEDRAT/MMPM,250.0000
GOTO/10.0000,0.0000,-1.0000
GOTO/0.0000,0.0000,-1.0000
GOHOME/0.0000,0.0000,50.0000
MSYS/0.0000,0.0000,0.0000,1.0000000,0.0000000,0.0000000,0.0000000,1.0000000,0.0000000
RAPID
GOTO/0.0000,0.0000,50.0000,0.0000000,0.0000000,1.0000000
GOTO/0.0000,0.0000,-1.0000
END-OF-PATH
"""


def test_an_nx_msys_is_a_work_plane_and_the_identity_its_reset() -> None:
    records = [r for r in api.read_cl_text(NX, "part.cls") if isinstance(r, WorkPlane)]
    assert [(r.line, r.work_plane) for r in records] == [(6, "tilted"), (13, "reset")]
    plane = records[0]
    assert (plane.origin_x, plane.origin_z) == (100.0, 40.0)
    assert (round(plane.z_axis_i, 6), plane.z_axis_j, round(plane.z_axis_k, 6)) == \
        (0.5, 0.0, round(math.sqrt(0.75), 6))
    verdict = api.verify_commands(api.load_post("fanuc_3plus2"),
                                  api.read_cl_text(NX, "part.cls"), cl_file="part.cls")
    assert verdict.divergence is None, verdict.divergence
    lines = [line.text for line in api.post_commands(api.load_post("fanuc_3plus2"),
                                                     api.read_cl_text(NX, "part.cls"))]
    assert "N90 G68.2 X100. Y0. Z40. I90. J30. K-90." in lines


def test_an_msys_that_is_no_frame_is_refused_at_its_line() -> None:
    with pytest.raises(CLError, match="MSYS: the X and Y axes are not at right angles") as caught:
        api.read_cl_text(NX.replace("0.8660254,0.0000000,-0.5000000,0.0000000,1.0000000",
                                    "0.8660254,0.0000000,-0.5000000,0.6000000,0.8000000"),
                         "part.cls")
    assert caught.value.location is not None and caught.value.location.line == 6


def test_the_heidenhain_model_reads_the_plane_functions_optional_words() -> None:
    """MB with a distance, a positioning feed, SEQ and TABLE ROT choose how the head gets
    there; the plane is TRANS DATUM's origin turned as SPA SPB SPC say."""
    program = ["0 BEGIN PGM T MM", "1 TOOL CALL 1 Z S1000", "2 M3",
               "3 TRANS DATUM AXIS X+10 Y+0 Z+0",
               "4 PLANE SPATIAL SPA+0 SPB+30 SPC+0 TURN MB 50 F2000 SEQ- TABLE ROT",
               "5 L X+0 Y+0 Z+5 R0 FMAX", "6 L Z+0 R0 F100", "7 PLANE RESET TURN MB MAX FMAX",
               "8 TRANS DATUM RESET", "9 END PGM T MM"]
    model = control_model("heidenhain-tnc640")
    [cut] = [e for e in model.replay(program) if type(e).__name__ == "FeedMove"]
    plane = cut.tooling.frame
    assert plane is not None and plane.origin == (10.0, 0.0, 0.0)
    assert [round(c, 6) for c in plane.tool_axis] == [0.5, 0.0, round(math.sqrt(0.75), 6)]
    assert model.frame is None


# --- the plot: the tool tip in the part frame, the tool axis where it tilts ----------------

#: each plane of the CL, in the part frame: (origin, X axis, Z axis) as its work_plane gives
PLANES = {PLANE_1: ((100, 0, 40), (0.866025404, 0, -0.5), (0.5, 0, 0.866025404)),
          PLANE_2: ((0, 0, 40), (0.866025404, 0.353553391, 0.353553391),
                    (0, -0.707106781, 0.707106781))}


def _height_over(plane: int, point: tuple[float, float, float]) -> float:
    """How far a point of the part lies above a plane's face, along its tool axis."""
    origin, _, z_axis = PLANES[plane]
    return sum((p - o) * n for p, o, n in zip(point, origin, z_axis, strict=True))


@pytest.mark.parametrize("machine", sorted(WRITTEN))
def test_the_plot_draws_each_bevel_cut_on_its_bevel_in_the_part_frame(machine: str) -> None:
    """The cuts made inside a plane are drawn where they land on the part: every point of
    the first bevel's cuts 1 mm under its face (Z-1 in the plane), of the second's 0.5 mm,
    the holes 6 mm deep along the tilted axis; the top face stays in the part frame."""
    _, path = api.toolpath_file(ROOT / "machines" / f"{machine}.yaml", CL)
    assert path.stopped is None
    feeds = {line: [s for s in path.segments if s.cl_line == line and s.kind == "feed"]
             for line in range(1, 40)}
    for line, plane, depth in ((10, PLANE_1, -1.0), (11, PLANE_1, -1.0), (12, PLANE_1, -1.0),
                               (19, PLANE_2, -0.5)):
        (cut,) = feeds[line]
        for point in cut.points:
            assert _height_over(plane, point) == pytest.approx(depth, abs=1e-3), (line, point)
    # the first bevel's pass along its Y: the part's Y from 10 to 50 at X 86.51, Z 46.63
    (along,) = feeds[10]
    assert along.points[0] == pytest.approx((86.5096, 10.0, 46.634), abs=1e-3)
    assert along.points[-1] == pytest.approx((86.5096, 50.0, 46.634), abs=1e-3)
    # the second bevel's pass along its X, turned 30 deg in the plane: 60 mm in the part
    (pass_2,) = feeds[19]
    assert math.dist(pass_2.points[0], pass_2.points[-1]) == pytest.approx(60.0, abs=1e-3)
    assert pass_2.points[-1][2] > pass_2.points[0][2] + 20  # it climbs the bevel
    holes = [s for s in path.segments if s.kind == "hole"]
    assert len(holes) == 2
    for hole in holes:
        top, bottom, _ = hole.points
        assert _height_over(PLANE_2, bottom) == pytest.approx(-6.0, abs=1e-3)
        assert _height_over(PLANE_2, top) == pytest.approx(3.0, abs=1e-3)
    # the top face in the part frame, as written
    (face,) = feeds[30]
    assert face.points == ((-8.0, 10.0, 39.5), (108.0, 10.0, 39.5))
    # and every rapid inside a plane is in the part frame too: none dives under the part
    assert all(p[2] > 39 for s in path.segments if s.kind == "rapid" for p in s.points)


@pytest.mark.parametrize("machine", sorted(WRITTEN))
def test_the_plot_draws_the_tool_axis_where_it_tilts(machine: str) -> None:
    """A line along the plane's tool axis from the tip at the first cut of each plane;
    none in the part frame (a 3-axis program draws none)."""
    _, path = api.toolpath_file(ROOT / "machines" / f"{machine}.yaml", CL)
    axes = [s for s in path.segments if s.kind == "axis"]
    assert [s.cl_line for s in axes] == [CUT_1, CUT_2]
    for segment, plane in zip(axes, (PLANE_1, PLANE_2), strict=True):
        tip, top = segment.points
        direction = [(b - a) / toolpath.AXIS_LENGTH for a, b in zip(tip, top, strict=True)]
        assert direction == pytest.approx(PLANES[plane][2], abs=1e-6)
        first_cut = next(s for s in path.segments if s.cl_line == segment.cl_line
                         and s.kind == "feed")
        assert tip == first_cut.points[0]
    _, flat = api.toolpath_file(ROOT / "machines" / "fanuc.yaml",
                                ROOT / "examples" / "boring.jsonl")
    assert not [s for s in flat.segments if s.kind == "axis"]


def test_the_svg_shows_the_tilted_tool_axis(tmp_path: Path) -> None:
    out = tmp_path / "tilted.svg"
    api.plot_file(ROOT / "machines" / "fanuc_3plus2.yaml", CL, out, views=["xz"])
    text = out.read_text(encoding="utf-8")
    assert text.count('<path class="axis"') == 1
    assert text.count('class="axis-tip"') == 2  # a dot on the tip of each plane's axis
    assert "tool axis</text>" in text
    # seen from the front, the first plane's axis leans 30 deg from vertical towards +X
    path = re.search(r'<path class="axis"[^>]* d="M(\S+) (\S+) L(\S+) (\S+)', text)
    assert path is not None
    x0, y0, x1, y1 = (float(v) for v in path.groups())
    assert math.degrees(math.atan2(x1 - x0, y0 - y1)) == pytest.approx(30.0, abs=0.5)
    flat = tmp_path / "square.svg"
    api.plot_file(ROOT / "machines" / "fanuc.yaml", ROOT / "examples" / "boring.jsonl", flat)
    assert "axis" not in flat.read_text(encoding="utf-8").replace('class="axes"', "")


# --- the program summary: extents in the part frame --------------------------------------


def test_the_summary_extents_are_the_parts_whatever_plane_a_move_is_made_in() -> None:
    """min_/max_ over the tool tip in the part frame: the bevels' moves turned out of their
    planes (the lowest point is the top face's Z39.5, not the holes' Z-6 of the second
    plane; the highest the first plane's retract, 30 mm up its tilted axis).  They agree
    with the plot of the posted program, which the control models put in the part frame
    independently, and the reader's first pass gives the same as the commands."""
    from postdsl.cl.source import CLSource
    from postdsl.run.program import summarize, summarize_source

    summary = summarize(api.read_cl(CL), rapid_rate=10000)
    extents = summary.extents
    assert extents["min_z"] == pytest.approx(39.5)
    assert extents["max_z"] == pytest.approx(86.4356, abs=1e-3)
    assert extents["min_x"] == pytest.approx(-8.0)
    assert extents["max_x"] == pytest.approx(110.6699, abs=1e-3)
    assert extents["min_y"] == pytest.approx(-17.204, abs=1e-3)
    assert extents["max_y"] == pytest.approx(50.0)
    for machine in sorted(WRITTEN):
        _, path = api.toolpath_file(ROOT / "machines" / f"{machine}.yaml", CL)
        # the summary bounds an arc by its ends (the first bevel's arc bulges to the
        # plane's Y55 between them): the plot's chords of CL line 11 are left out here
        low, high = toolpath.bounds_of(s for s in path.segments
                                       if s.kind != "axis" and s.cl_line != 11) or ((), ())
        assert low == pytest.approx((extents["min_x"], extents["min_y"], extents["min_z"]),
                                    abs=1e-3)
        assert high == pytest.approx((extents["max_x"], extents["max_y"], extents["max_z"]),
                                     abs=1e-3)
    with CLSource(CL) as source:
        first_pass = summarize_source(source, 10000)
    assert first_pass.extents == extents
    assert first_pass.machining_time == pytest.approx(summary.machining_time)


def test_the_summary_time_does_not_depend_on_the_plane_a_move_is_made_in() -> None:
    """A plane moves and turns the moves, not their lengths: the same moves in a tilted
    plane and in the part frame take the same time, and the tool's way into the plane is
    measured from where it really is."""
    from postdsl.run.program import summarize

    moves = [{"cmd": "rapid_move", "x": 0, "y": 0, "z": 10},
             {"cmd": "linear_move", "z": 0, "feed": 600},
             {"cmd": "linear_move", "x": 60, "y": 80}]
    tilt = {"cmd": "work_plane", "origin_x": 0, "origin_y": 0, "origin_z": 10,
            "x_axis_i": 0, "x_axis_j": 1, "x_axis_k": 0, "z_axis_i": 1, "z_axis_j": 0,
            "z_axis_k": 0}
    before = {"cmd": "rapid_move", "x": 10, "y": 0, "z": 10}  # the plane's (0, 0, 10)

    def time_of(records: list[dict[str, object]]) -> float:
        text = "".join(json.dumps(r) + "\n" for r in [*records, {"cmd": "program_end"}])
        return summarize(api.read_cl_text(text, "t.jsonl"), rapid_rate=6000).machining_time

    flat = time_of([before, *moves])
    tilted = time_of([before, tilt, *moves])
    assert tilted == pytest.approx(flat - 10 / 6000 * 60)  # no rapid: the tool is there
    assert flat == pytest.approx(10 / 6000 * 60 + (10 + 100) / 600 * 60)


# --- the post check: a tilting machine's post writes the plane, a 3-axis one does not ------


def _post_error(tmp_path: Path, text: str) -> PostError:
    path = tmp_path / "mill.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(PostError) as caught:
        api.load_post(path)
    return caught.value


def test_a_work_plane_table_that_leaves_an_angle_out_is_refused_at_the_table(
        tmp_path: Path) -> None:
    """K written as a constant: the control would tilt about two angles only."""
    error = _post_error(tmp_path, "postdsl: 1\nextends: fanuc_3plus2\n\noverride:\n"
                                  "  commands/work_plane/blocks/3/items/6: \" K0.\"\n")
    assert "the work_plane table does not write plane_angle_3" in str(error)
    assert "euler_zxz" in str(error)
    assert re.search(r"fanuc_3plus2\.yaml:\d+", str(error)), str(error)  # the table's line


def test_a_tilting_machine_without_a_work_plane_table_is_refused_at_its_declaration(
        tmp_path: Path) -> None:
    error = _post_error(tmp_path, "postdsl: 1\nextends: fanuc\n\nmachine:\n"
                                  "  name: mill\n  tilted_plane: euler_zxz\n")
    assert "mill.yaml:6" in str(error)
    assert "tilts the working plane (euler_zxz) but the post has no work_plane table" \
        in str(error)


def test_a_three_axis_post_writing_plane_angles_is_refused_at_the_item(tmp_path: Path) -> None:
    error = _post_error(tmp_path, "postdsl: 1\nextends: fanuc\n\ncommands:\n"
                                  "  work_plane:\n    blocks:\n"
                                  "      - items: [\" G68.2\", {param: plane_angle_1, "
                                  "prefix: \" I\"}]\n")
    assert "mill.yaml:7" in str(error)
    assert "writes plane_angle_1, but the machine declares no tilted_plane" in str(error)


@pytest.mark.parametrize("words", ["L B+30 C+0 R0 FMAX", "L A-15 R0 FMAX", "L C+90 R0 F500"])
def test_the_heidenhain_model_refuses_rotary_moves_after_stay_with_the_reason(
        words: str) -> None:
    """PLANE ... STAY leaves the axes where they are for the program to position: whether
    its angles give the plane's tool axis is the machine's kinematics, not checked here."""
    program = ["0 BEGIN PGM T MM", "1 TOOL CALL 1 Z S1000", "2 M3",
               "3 PLANE SPATIAL SPA+0 SPB+30 SPC+0 STAY", f"4 {words}", "5 END PGM T MM"]
    with pytest.raises(ControlError) as caught:
        list(control_model("heidenhain-tnc640").replay(program))
    assert caught.value.origin.line == 5
    assert "after PLANE ... STAY" in caught.value.message
    assert "write PLANE ... TURN" in caught.value.message
    # after TURN the same word is no rotary positioning the model reads at all
    turned = [line.replace(" STAY", " TURN") for line in program]
    with pytest.raises(ControlError, match="is not a word the TNC 640 model knows"):
        list(control_model("heidenhain-tnc640").replay(turned))
