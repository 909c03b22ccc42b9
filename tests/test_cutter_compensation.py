"""cutter_compensation: read from APT CUTCOM, G-code and FreeCAD G40-G42 and native CL,
given a meaning by the post's declared mode (off, wear, control), written on the lead-in
and lead-out moves in each control's words or refused, and replayed by verify: the tool
centre (wear) or the contour offset by the tool radius (control), checked against rs274."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from postdsl import api
from postdsl.check.controls import NCInput, control_model
from postdsl.check.controls.base import ControlError
from postdsl.check.controls.compensation import FANUC, LINUXCNC, CompensatedPath
from postdsl.check.controls.events import ArcMove, FeedMove, Origin, Tooling
from postdsl.cl.model import CutterCompensation
from postdsl.errors import CLError, PostError
from tests.conftest import ROOT, THESIS_TIME
from tests.test_rs274_oracle import for_rs274, needs_rs274, run_rs274

CENTRE = ROOT / "examples" / "cutter_compensation.jsonl"
CONTOUR = ROOT / "examples" / "cutter_compensation_contour.jsonl"
#: the posts whose control compensates, and the ones that refuse (with their reason)
COMPENSATING = ("fanuc", "feeler", "linuxcnc", "emco", "heidenhain")


def sides(commands) -> list[tuple[str, int | None, int]]:
    return [(c.compensation_side, c.compensation_register, c.line) for c in commands
            if isinstance(c, CutterCompensation)]


def apt(body: str) -> str:
    return f"PARTNO/T\nUNITS/MM\n{body}\nFINI\n"


@pytest.mark.parametrize(("record", "side", "register"), [
    ("CUTCOM/LEFT", "left", None), ("CUTCOM/RIGHT", "right", None),
    ("CUTCOM/ON,LEFT", "left", None),
    ("CUTCOM/LEFT,XYPLAN,3", "left", 3), ("CUTCOM/RIGHT,12", "right", 12),
    ("CUTCOM/ON,RIGHT,XYPLAN", "right", None),
])
def test_apt_cutcom_forms_are_read(record: str, side: str, register: int | None) -> None:
    text = apt(f"{record}\nCUTCOM/OFF")
    assert sides(api.read_cl_text(text, "c.apt", "apt")) == [(side, register, 3),
                                                             ("off", None, 4)]


@pytest.mark.parametrize(("record", "message"), [
    ("CUTCOM/ON", "CUTCOM without LEFT, RIGHT or OFF: the side of the path is not given"),
    ("CUTCOM/LEFT,RIGHT", "one side only"),
    ("CUTCOM/LEFT,YZPLAN", "cutter compensation in the YZ plane is not read"),
    ("CUTCOM/OFF,3", "CUTCOM/OFF takes no register"),
    ("CUTCOM/LEFT,2.5", "one register number, a whole number"),
])
def test_apt_cutcom_without_a_side_or_in_another_plane_is_refused(record: str,
                                                                  message: str) -> None:
    with pytest.raises(CLError, match=re.escape(message)) as caught:
        api.read_cl_text(apt(record), "c.apt", "apt")
    assert caught.value.location is not None and caught.value.location.line == 3


@pytest.mark.parametrize("fmt", ["gcode", "freecad"])
def test_g41_g42_g40_are_read_where_the_side_changes(fmt: str) -> None:
    """A G40 in force (the safe-start block) is no record; D is the register."""
    text = ("G40 G90\nG0 X-20 Y0 Z5\nG1 Z-1 F100\nG41 D1\nG1 X0 Y0\nG1 X10\nG40 G1 X20 Y-20\n"
            "G42 D4\nG1 X0\nG40\nG1 X-5\nM2\n")
    feeds = "mm/min" if fmt == "freecad" else None
    assert sides(api.read_cl_text(text, "c.ngc", fmt, feeds)) == [
        ("left", 1, 4), ("off", None, 7), ("right", 4, 8), ("off", None, 10)]


def test_the_mode_off_refuses_compensation_at_its_line_with_the_hint() -> None:
    post = api.load_post("fanuc", {"cutter_compensation": "off"})
    with pytest.raises(CLError) as caught:
        api.post_commands(post, api.read_cl(CENTRE), cl_file=CENTRE.name)
    assert caught.value.location is not None and caught.value.location.line == 7
    assert "the post's cutter_compensation mode is off" in caught.value.message
    assert "--option cutter_compensation=wear" in caught.value.message


def test_a_mode_outside_the_three_is_refused_at_the_setting() -> None:
    text = (ROOT / "machines" / "fanuc.yaml").read_text(encoding="utf-8")
    old = "cutter_compensation: {option: cutter_compensation}"
    assert old in text
    with pytest.raises(PostError, match="one of off, wear, control"):
        api.load_post_text(text.replace(old, "cutter_compensation: {option: header}").replace(
            "options:\n", "options:\n  header: {type: string, default: centre}\n", 1),
            "fanuc.yaml")
    with pytest.raises(Exception, match="cutter_compensation"):
        api.load_post("fanuc", {"cutter_compensation": "centre"})


#: what each post writes on the lead-in (CL line 8) and the lead-out (CL line 18)
WRITTEN = {
    "fanuc": ("G41 D1 X5. F400.", "G1 G40 X20. Y50."),
    "feeler": ("G41 D1 X5. F400", "G1 G40 X20. Y50."),
    "linuxcnc": ("G1 G41 D1 X5.000 Y35.000 F400.000", "G1 G40 X20.000 Y50.000"),
    "emco": ("G41 D1 X5.000 F400", "G1 G40 X20.000 Y50.000"),
    "heidenhain": ("L X+5 RL F400", "L X+20 Y+50 R0"),
}


def words(lines, cl_line: int) -> list[str]:
    return [re.sub(r"^(N\d+|\d+)\s+", "", line.text).strip() for line in lines
            if line.cl_line == cl_line]


@pytest.mark.parametrize("machine", sorted(WRITTEN))
def test_each_post_writes_compensation_on_the_lead_in_and_lead_out(machine: str) -> None:
    post = api.load_post(machine)
    assert post.machine.cutter_compensation == "wear"  # the library posts' declared mode
    lines = api.post_commands(post, api.read_cl(CENTRE), cl_file=CENTRE.name, now=THESIS_TIME)
    assert words(lines, 7) == []  # the record itself writes nothing: its move does
    assert (words(lines, 8), words(lines, 18)) == tuple([w] for w in WRITTEN[machine])
    verdict = api.verify_commands(post, api.read_cl(CENTRE), cl_file=CENTRE.name)
    assert verdict.ok, verdict.divergence


@pytest.mark.parametrize(("machine", "cl", "reason"), [
    ("grbl", CENTRE, "GRBL 1.1 has no cutter radius compensation"),
    ("vmc500", CENTRE, "knows no cutter compensation of the Acramatic 2100"),
    ("hmcnc", ROOT / "examples" / "cutter_compensation_router.jsonl",
     "hmCNC's code has no cutter compensation"),
])
def test_a_post_without_compensation_refuses_it_for_its_controls_reason(
        machine: str, cl: Path, reason: str) -> None:
    with pytest.raises(CLError) as caught:
        api.post_commands(api.load_post(machine), api.read_cl(cl), cl_file=cl.name)
    assert caught.value.location is not None and caught.value.location.line == 7
    assert reason in caught.value.message


def test_the_cl_register_is_written_where_it_gives_one() -> None:
    commands = [c if not isinstance(c, CutterCompensation) or c.compensation_side == "off"
                else CutterCompensation(compensation_side="right", compensation_register=21,
                                        line=c.line) for c in api.read_cl(CENTRE)]
    lines = api.post_commands(api.load_post("fanuc"), commands, cl_file=CENTRE.name)
    assert words(lines, 8) == ["G42 D21 X5. F400."]


_LEAD_IN_ARC = """{"cmd": "program_start", "program_name": "ARC"}
{"cmd": "tool_change", "tool_number": 1, "tool_diameter": 10}
{"cmd": "spindle_on", "spindle_speed": 2000, "spindle": "cw"}
{"cmd": "rapid_move", "x": 0, "y": 0, "z": 5}
{"cmd": "linear_move", "z": -1, "feed": 100}
{"cmd": "cutter_compensation", "compensation_side": "left"}
{"cmd": "linear_move", "z": -2}
{"cmd": "arc_move", "x": 20, "y": 0, "cx": 10, "cy": 0, "arc_direction": "cw"}
{"cmd": "program_end"}
"""


@pytest.mark.parametrize(("machine", "control"), [
    ("fanuc", "Fanuc"), ("feeler", "Fanuc 0i-MD"), ("linuxcnc", "LinuxCNC"),
    ("emco", "Sinumerik 828D"), ("heidenhain", "TNC")])
def test_an_arc_lead_in_is_refused_at_the_arc(machine: str, control: str) -> None:
    """A Z move does not start compensation (no X or Y): the arc after it would."""
    commands = api.read_cl_text(_LEAD_IN_ARC, "arc.jsonl", "native")
    with pytest.raises(CLError) as caught:
        api.post_commands(api.load_post(machine), commands, cl_file="arc.jsonl")
    assert caught.value.location is not None and caught.value.location.line == 8
    assert control in caught.value.message and "arc" in caught.value.message


@pytest.mark.parametrize("machine", COMPENSATING)
def test_a_tool_change_with_compensation_on_is_refused(machine: str) -> None:
    text = _LEAD_IN_ARC.replace(
        '{"cmd": "arc_move", "x": 20, "y": 0, "cx": 10, "cy": 0, "arc_direction": "cw"}',
        '{"cmd": "linear_move", "x": 20}\n{"cmd": "tool_change", "tool_number": 2, '
        '"tool_diameter": 6}')
    with pytest.raises(CLError, match="compensation is on at a tool change") as caught:
        api.post_commands(api.load_post(machine), api.read_cl_text(text, "t.jsonl", "native"),
                          cl_file="t.jsonl")
    assert caught.value.location is not None and caught.value.location.line == 9


# --- the control mode: the CL is the part contour -----------------------------------------


@pytest.mark.parametrize("machine", ["fanuc", "feeler", "linuxcnc", "emco", "heidenhain"])
def test_a_contour_verifies_with_the_controls_offset_path(machine: str) -> None:
    post = api.load_post(machine, {"cutter_compensation": "control"})
    verdict = api.verify_commands(post, api.read_cl(CONTOUR), cl_file=CONTOUR.name)
    assert verdict.ok, verdict.divergence
    assert verdict.cuts >= 15


@pytest.mark.parametrize(("machine", "old", "new"), [
    ("fanuc", '{text: " G41", if:', '{text: " G42", if:'),
    ("linuxcnc", '{text: "G41 ", if:', '{text: "G42 ", if:'),
    ("heidenhain", '" RL"\n', '" RR"\n'),
])
def test_verify_sees_the_wrong_side(machine: str, old: str, new: str) -> None:
    """The same contour, the tool on its other side: verify finds the first offset move."""
    text = (ROOT / "machines" / f"{machine}.yaml").read_text(encoding="utf-8")
    assert old in text
    wrong = api.load_post_text(text.replace(old, new), f"{machine}.yaml",
                               {"cutter_compensation": "control"})
    verdict = api.verify_commands(wrong, api.read_cl(CONTOUR), cl_file=CONTOUR.name)
    assert verdict.divergence is not None


def test_the_wear_mode_on_a_contour_cl_is_a_divergence_in_the_control_mode() -> None:
    """The mode is what the CL's path means: the tool centre CL read as a contour is
    offset by the radius, and a post whose control would not offset it is caught."""
    text = (ROOT / "machines" / "fanuc.yaml").read_text(encoding="utf-8")
    no_words = text.replace('{text: " G41", if:', '{text: "", if:')
    post = api.load_post_text(no_words, "fanuc.yaml", {"cutter_compensation": "control"})
    verdict = api.verify_commands(post, api.read_cl(CONTOUR), cl_file=CONTOUR.name)
    assert verdict.divergence is not None


def test_a_start_up_beyond_the_fanuc_model_is_said_not_checked() -> None:
    """Fanuc's start-up type decides the path when the lead-in is not in line with the
    next move: verify says it cannot check it, at the line, and the post stops there."""
    text = CONTOUR.read_text(encoding="utf-8").replace(
        '{"cmd": "linear_move", "x": 5, "y": 30, "feed": 400}',
        '{"cmd": "linear_move", "x": 5, "y": 20, "feed": 400}')
    commands = api.read_cl_text(text, "c.jsonl", "native")
    post = api.load_post("fanuc", {"cutter_compensation": "control"})
    verdict = api.verify_commands(post, commands, cl_file="c.jsonl")
    assert verdict.divergence is not None
    assert "verify cannot check this stretch" in verdict.divergence.message
    # LinuxCNC's entry is square to the move itself: modelled, and verified
    linuxcnc = api.load_post("linuxcnc", {"cutter_compensation": "control"})
    assert api.verify_commands(linuxcnc, commands, cl_file="c.jsonl").ok


# --- the geometry ---------------------------------------------------------------------------

_T = Tooling(1, 1)


def _line(a: tuple[float, float], b: tuple[float, float], n: int) -> FeedMove:
    return FeedMove(Origin(n), (a[0], a[1], 0.0), (b[0], b[1], 0.0), 100.0, _T)


def _ends(moves) -> list[tuple[float, float]]:
    return [(round(m.end[0], 6), round(m.end[1], 6)) for m in moves]


def test_a_concave_corner_ends_both_moves_where_their_offsets_meet() -> None:
    """Left of a path turning left (towards the tool): the offsets cross one radius from
    both lines."""
    path = CompensatedPath("left", 2.0, FANUC)
    out = path.move(_line((-10, 0), (0, 0), 1)) + path.move(_line((0, 0), (10, 0), 2))
    out += path.move(_line((10, 0), (10, 10), 3)) + path.cancel(_line((10, 10), (0, 20), 4))
    assert _ends(out) == [(0.0, 2.0), (8.0, 2.0), (8.0, 10.0), (0.0, 20.0)]


def test_a_convex_corner_is_an_arc_on_linuxcnc_and_the_intersection_on_fanuc() -> None:
    lines = [_line((-10, 0), (0, 0), 1), _line((0, 0), (10, 0), 2),
             _line((10, 0), (10, -10), 3)]
    linuxcnc, fanuc = CompensatedPath("left", 2.0, LINUXCNC), CompensatedPath("left", 2.0,
                                                                                FANUC)
    arc_path = [m for line in lines for m in linuxcnc.move(line)]
    assert isinstance(arc_path[-1], ArcMove) and arc_path[-1].clockwise
    assert arc_path[-1].centre[:2] == (10.0, 0.0)
    assert arc_path[-1].sweep == pytest.approx(math.pi / 2)
    assert _ends(arc_path) == [(0.0, 2.0), (10.0, 2.0), (12.0, 0.0)]
    assert _ends([m for line in lines for m in fanuc.move(line)]) == [(0.0, 2.0), (12.0, 2.0)]


def test_an_arc_smaller_than_the_tool_on_its_inside_is_refused() -> None:
    path = CompensatedPath("left", 5.0, LINUXCNC)
    path.move(_line((-20, 0), (0, 0), 1))
    arc = ArcMove(Origin(2), (0.0, 0.0, 0.0), (6.0, 0.0, 0.0), (3.0, 0.0, 0.0), False, "xy",
                  math.pi, 3.0, 100.0, _T)
    with pytest.raises(ControlError, match="not larger than the tool radius"):
        path.move(arc)


@pytest.mark.parametrize(("text", "message"), [
    ("G0 X0 Y0 Z5\nG41 G1 X10 F100", "G41 without a D register"),
    ("G0 X0 Y0 Z5\nG41 D1\nG2 X10 Y0 I5 J0 F100", "starts (G41) on an arc"),
    ("G0 X0 Y0 Z5\nG41 D1 G1 X10 F100\nG42 D1 G1 X20", "while cutter compensation is on"),
    ("G0 X0 Y0 Z5\nG41 D1 G1 X10 F100\nG81 X0 Y0 Z-1 R1", "canned cycle with cutter "
                                                           "compensation on"),
    ("G0 X0 Y0 Z5\nG41 D1 G1 X10 F100\nM2", "ends with cutter compensation on"),
])
def test_the_models_refuse_what_the_control_refuses(text: str, message: str) -> None:
    model = control_model("linuxcnc")
    model.configure_compensation("control", {1: 4.0})
    with pytest.raises(ControlError, match=re.escape(message)):
        list(model.replay(text.split("\n")))


def test_grbl_knows_no_g41() -> None:
    with pytest.raises(ControlError, match="G41 is not a code"):
        list(control_model("grbl-1.1").replay(["G0 X0 Y0 Z5", "G41 G1 X10 F100"]))


# --- rs274, LinuxCNC's own interpreter, offsets the same programs ---------------------------


def _rs274_moves(machine: str, cl: Path, mode: str, tmp_path: Path
                 ) -> tuple[list[tuple[float, ...]], list[tuple[float, ...]]]:
    """The model's cut end points and rs274's, in order, with rs274 given the CL tool
    diameters in its tool table (which the standalone interpreter reads in inches)."""
    post = api.load_post(machine, {"cutter_compensation": mode})
    commands = api.read_cl(cl)
    lines = [line.text for line in api.post_commands(post, commands, cl_file=cl.name,
                                                     now=THESIS_TIME)]
    fanuc = machine == "fanuc"
    numbered = for_rs274(lines) if fanuc else [
        line if line.strip() == "%" else f"N{n} {line}" for n, line in enumerate(lines, 1)]
    diameters = {c.tool_number: c.tool_diameter for c in commands if c.name == "tool_change"}
    table = "".join(f"T{n} P{n} Z0 D{diameters.get(n, 0) / 25.4 if mode == 'control' else 0}\n"
                    for n in range(1, 10))
    trace = run_rs274(numbered, tmp_path, table)
    assert post.machine.control is not None
    model = control_model(post.machine.control)
    model.configure_compensation(mode, diameters)
    replayed = lines if fanuc else numbered
    ours = [tuple(round(v, 4) for v in e.end) for e in model.replay(
        NCInput(n, line) for n, line in enumerate(replayed, start=1))
        if isinstance(e, (FeedMove, ArcMove))]
    theirs = [tuple(round(v, 4) for v in m.end) for m in trace.moves
              if m.kind in ("feed", "arc")]
    return ours, theirs


@needs_rs274
@pytest.mark.parametrize(("machine", "cl", "mode"), [
    ("linuxcnc", CONTOUR, "control"),   # convex corner arcs, concave intersections
    ("linuxcnc", CENTRE, "wear"),
    ("fanuc", CENTRE, "control"),       # no sharp convex corner: Fanuc's path is rs274's
    ("fanuc", CENTRE, "wear"),
])
def test_rs274_offsets_the_program_as_the_model_does(machine: str, cl: Path, mode: str,
                                                     tmp_path: Path) -> None:
    ours, theirs = _rs274_moves(machine, cl, mode, tmp_path)
    assert len(ours) >= 11
    assert len(ours) == len(theirs)
    for a, b in zip(ours, theirs, strict=True):
        assert a == pytest.approx(b, abs=1e-3)


@needs_rs274
def test_at_a_sharp_convex_corner_fanuc_and_rs274_part(tmp_path: Path) -> None:
    """LinuxCNC rounds a convex corner with an arc, Fanuc's type C goes to the offsets'
    intersection: the Fanuc model's path differs from rs274's exactly there."""
    ours, theirs = _rs274_moves("fanuc", CONTOUR, "control", tmp_path)
    assert len(theirs) == len(ours) + 2  # rs274's two corner arcs at the notch
    for a, b in zip(ours[:6], theirs[:6], strict=True):
        assert a == pytest.approx(b, abs=1e-3)
    assert (20.0, -5.0, -3.0) in ours and (20.0, -5.0, -3.0) not in theirs


def test_a_move_in_z_alone_leaves_the_compensation_for_the_move_in_x_y() -> None:
    """CAM systems write CUTCOM before the plunge (SolidWorks CAM before its FEDRAT and
    GOTO): the plunge carries nothing, the first move in X/Y carries G41."""
    text = CENTRE.read_text(encoding="utf-8").replace(
        '{"cmd": "linear_move", "z": -3, "feed": 150}\n'
        '{"cmd": "cutter_compensation", "compensation_side": "left"}\n',
        '{"cmd": "cutter_compensation", "compensation_side": "left"}\n'
        '{"cmd": "linear_move", "z": -3, "feed": 150}\n')
    commands = api.read_cl_text(text, "z.jsonl", "native")
    lines = api.post_commands(api.load_post("fanuc"), commands, cl_file="z.jsonl")
    assert (words(lines, 7), words(lines, 8)) == (["G1 Z-3. F150."], ["G41 D1 X5. F400."])
    assert api.verify_commands(api.load_post("fanuc"), commands, cl_file="z.jsonl").ok


def test_a_linuxcnc_entry_move_no_longer_than_the_radius_is_said_at_its_line() -> None:
    text = CONTOUR.read_text(encoding="utf-8").replace(
        '{"cmd": "rapid_move", "x": -25, "y": 30, "z": 20}',
        '{"cmd": "rapid_move", "x": 1, "y": 30, "z": 20}')
    post = api.load_post("linuxcnc", {"cutter_compensation": "control"})
    verdict = api.verify_commands(post, api.read_cl_text(text, "e.jsonl", "native"),
                                  cl_file="e.jsonl")
    assert verdict.divergence is not None and verdict.divergence.cl is not None
    assert verdict.divergence.cl.line == 8
    assert "is not longer than the tool radius (5)" in verdict.divergence.message


def test_the_linuxcnc_program_reads_back_as_the_same_compensation(tmp_path: Path) -> None:
    """The plain G-code reader reads the post's G41 D1 and G40 as the CL had them."""
    post = api.load_post("linuxcnc")
    text = "\n".join(line.text for line in api.post_commands(
        post, api.read_cl(CENTRE), cl_file=CENTRE.name, now=THESIS_TIME)) + "\n"
    again = api.read_cl_text(text, "back.ngc", "gcode")
    assert [(side, register) for side, register, _ in sides(again)] == [
        ("left", 1), ("off", None)]
    assert api.verify_commands(post, again, cl_file="back.ngc").ok


@pytest.mark.parametrize(("block", "message"), [
    ("6 CC X+10 Y+0\n7 C X+20 Y+0 DR- RL", "RL on a circle: radius compensation starts and "
                                          "ends on a straight line L"),
    ("6 L X+10 RL\n7 L X+20 RR", "RR while the other radius compensation is on"),
    ("6 L X+10 RL R0", "two radius compensations"),
])
def test_the_tnc_model_starts_and_ends_radius_compensation_on_an_l(block: str,
                                                                   message: str) -> None:
    program = ("0 BEGIN PGM A MM\n1 TOOL CALL 1 Z S1000\n2 M3\n3 L X+0 Y+0 Z+5 R0 FMAX\n"
               "4 L Z-1 R0 F100\n5 L X+1 R0\n" + block)
    with pytest.raises(ControlError, match=re.escape(message)):
        list(control_model("heidenhain-tnc640").replay(program.split("\n")))


def test_the_backplot_of_a_contour_draws_the_tool_centre() -> None:
    """In the control mode the editor's toolpath is the control's offset path: the top
    edge at Y30 is cut with the centre at Y35 (wear: at Y30, as programmed)."""
    commands = api.read_cl(CONTOUR)
    for mode, top in (("control", 35.0), ("wear", 30.0)):
        post = api.load_post("linuxcnc", {"cutter_compensation": mode})
        _, path = api.toolpath(post, commands, cl_file=CONTOUR.name)
        assert path.stopped is None
        [edge] = [s for s in path.segments if s.cl_line == 9 and s.kind == "feed"]
        assert edge.points[-1][:2] == pytest.approx((35.0, top)), mode
