"""``postdsl verify``: the posted program replayed through its control model, compared with the CL.

A post broken on purpose must fail verify at the first place it goes wrong,
named by the CL line, the NC line and what differs; a clean post passes; the
command line exits 4 and ``post --verify`` writes nothing when it fails.
(The corpus runs through verify in tests/test_snapshots.py.)
"""

from __future__ import annotations

import itertools
import subprocess
import sys
from pathlib import Path

import pytest

from postdsl import api
from postdsl.check.controls.events import Dwell, FeedMove, Hole, Origin, Rapid, Tooling
from postdsl.check.motion import cl_events
from postdsl.check.verify import verify_events
from postdsl.cl.model import ArcMove as CLArc
from postdsl.cl.model import Dwell as CLDwell
from postdsl.cl.model import LinearMove, RapidMove, SpindleOn, ToolChange
from tests.conftest import DATA, EXAMPLES, MACHINES, THESIS_TIME

FEELER = (MACHINES / "feeler.yaml").read_text(encoding="utf-8")
EMCO = (MACHINES / "emco.yaml").read_text(encoding="utf-8")


def broken(text: str, after: str, old: str, new: str) -> api.CompiledPost:
    """The post with the first ``old`` after ``after`` replaced: one deliberate mistake."""
    start = text.index(after)
    at = text.index(old, start)
    return api.load_post_text(text[:at] + new + text[at + len(old):], "broken.yaml")


def divergence(post: api.CompiledPost, cl: Path) -> str:
    verdict = api.verify_commands(post, api.read_cl(cl), cl_file=cl.name, now=THESIS_TIME)
    assert verdict.divergence is not None, "verify passed a broken post"
    return str(verdict.divergence)


@pytest.mark.parametrize(("post", "cl", "cuts", "holes"), [
    ("feeler", "feeler_milling.apt", 17, 0),
    ("feeler", "feeler_drilling.apt", 13, 13),
    ("emco", "emco_drilling.jsonl", 22, 22),
])
def test_a_correct_post_verifies(post: str, cl: str, cuts: int, holes: int) -> None:
    verdict = api.verify_commands(api.load_post(post), api.read_cl(EXAMPLES / cl), cl_file=cl,
                                  now=THESIS_TIME)
    assert verdict.ok, verdict.divergence
    assert (verdict.cuts, verdict.holes) == (cuts, holes)


def test_a_coordinate_never_written_is_caught_at_the_first_move_that_needs_it() -> None:
    y_item = '{param: y, prefix: " Y", format: coord, mode: changed'
    post = broken(FEELER, "  linear_move:", y_item + "}", y_item + ', if: "false"}')
    # feeler_milling.apt:24 is "GOTO/50,30,-2" after the arc to (50,0): its block loses
    # its only word, so the control stays at Y0 and the next arc (line 27, centre I10
    # from there) cannot end on its circle: the control refuses the program there
    assert divergence(post, EXAMPLES / "feeler_milling.apt") == (
        "feeler_milling.apt:27: NC line 22: N160 G2 X60. Y40. I10. J0.: the arc's end is not "
        "on its circle: radius 10.0000 at the start, 40.0000 at the end")


def test_a_format_with_no_decimals_fails_at_the_machine_resolution() -> None:
    clean = api.verify_commands(api.load_post("emco"), api.read_cl(DATA / "emco_thesis.dump.txt"),
                                cl_file="emco_thesis.dump.txt", now=THESIS_TIME)
    assert clean.ok, clean.divergence
    post = broken(EMCO, "formats:", "decimals: {option: program_units, mm: 3, inch: 4}",
                  "decimals: 0")
    # the first cut after the rapid to Z12.5 (written Z13: half away from zero) starts
    # 0.5 mm high: the tolerance is the machine's 0.001 mm, not the format's 1 mm
    assert divergence(post, DATA / "emco_thesis.dump.txt") == (
        "emco_thesis.dump.txt:16: NC line 14: N140 G1 X7 Y-7 F200: feed move starts at "
        "X6.000 Y-20.000 Z13.000, CL says X6.000 Y-20.000 Z12.500")


def test_a_drilling_table_without_r_is_caught_at_the_first_hole() -> None:
    post = broken(FEELER, "  single_peck:",
                  '{expr: "top + clearance", prefix: " R", format: coord, modal: hole_r}', '""')
    assert divergence(post, EXAMPLES / "feeler_drilling.apt") == (
        "feeler_drilling.apt:15: NC line 18: N110 G95 G99 G81 X10. Y10. Z-10. F0.2: "
        "G81 needs R and Z")


def test_a_hole_with_the_wrong_bottom_names_the_hole_and_both_values() -> None:
    post = broken(FEELER, "  single_peck:",
                  '{param: bottom, prefix: " Z", format: coord, modal: hole_z}',
                  '{expr: "bottom + 1", prefix: " Z", format: coord, modal: hole_z}')
    assert divergence(post, EXAMPLES / "feeler_drilling.apt") == (
        "feeler_drilling.apt:15: NC line 18: N110 G95 G99 G81 X10. Y10. Z-9. R2. F0.2: "
        "hole 1: bottom Z-9.000, CL says bottom Z-10.000")


def test_a_wrong_length_offset_is_caught() -> None:
    post = broken(FEELER, "  rapid_move:", '{param: tool_number, prefix: " H", format: int}',
                  '" H9"')
    message = divergence(post, EXAMPLES / "feeler_milling.apt")
    assert message.endswith("with length offset 9, CL says tool 1's own")


def test_a_post_without_a_control_cannot_be_verified() -> None:
    text = FEELER.replace("  control: fanuc-0i", "  #").replace("  resolution: 0.001", "  #")
    post = api.load_post_text(text, "nocontrol.yaml")
    with pytest.raises(api.PostError, match="declares no machine/control"):
        api.verify_commands(post, api.read_cl(EXAMPLES / "feeler_milling.apt"))


def test_control_without_resolution_is_a_located_load_error() -> None:
    text = FEELER.replace("  resolution: 0.001", "  #")
    with pytest.raises(api.PostError) as caught:
        api.load_post_text(text, "half.yaml")
    assert "machine/control needs machine/resolution" in str(caught.value)
    assert str(caught.value).startswith("half.yaml:38:")


def test_an_unknown_control_is_refused_by_the_schema() -> None:
    with pytest.raises(api.PostError, match="heidenhain"):
        api.load_post_text(FEELER.replace("control: fanuc-0i", "control: heidenhain"), "x.yaml")


# --- the comparison itself ---------------------------------------------------------------------

def test_verify_streams_and_stops_at_the_first_divergence() -> None:
    """An endless NC side: verify reads only up to the divergence."""
    tooling = Tooling(1, 1, "cw", 1000)

    def nc():
        yield Rapid(Origin(1, "G0 X0 Y0 Z1"), (None, None, None), (0, 0, 1))
        for n in itertools.count(2):
            yield FeedMove(Origin(n, "G1 X5"), (0, 0, 1), (5, 0, 1), 100, tooling)

    cl = [ToolChange(tool_number=1, line=1), SpindleOn(spindle_speed=1000, line=2),
          RapidMove(x=0, y=0, z=1, line=3), LinearMove(x=6, feed=100, line=4)]
    verdict = verify_events(nc(), cl_events(cl, "p.jsonl"), 0.001)
    assert str(verdict.divergence) == ("p.jsonl:4: NC line 2: G1 X5: feed move ends at X5.000 "
                                       "Y0.000 Z1.000, CL says X6.000 Y0.000 Z1.000")


def test_a_rapid_below_the_cl_path_is_a_divergence() -> None:
    tooling = Tooling(1, 1, "cw", 1000)
    cl = [ToolChange(tool_number=1, line=1), SpindleOn(spindle_speed=1000, line=2),
          RapidMove(x=0, y=0, z=50, line=3), RapidMove(x=20, y=0, line=4),
          RapidMove(z=1, line=5), LinearMove(x=25, feed=100, line=6)]
    # the NC goes down first, then sideways at Z1: under the CL's traverse at Z50
    nc = [Rapid(Origin(1, "G0 X0 Y0 Z50"), (None, None, None), (0, 0, 50)),
          Rapid(Origin(2, "G0 Z1"), (0, 0, 50), (0, 0, 1)),
          Rapid(Origin(3, "G0 X20"), (0, 0, 1), (20, 0, 1)),
          FeedMove(Origin(4, "G1 X25"), (20, 0, 1), (25, 0, 1), 100, tooling)]
    assert str(verify_events(nc, cl_events(cl, "p.jsonl"), 0.001).divergence) == (
        "p.jsonl:6: NC line 4: G1 X25: a rapid sideways at Z1.000, below the CL's Z50.000")


def test_the_rapids_around_a_dwell_are_one_stretch() -> None:
    """A dwell moves nothing: a manual tool change's rapid, a dwell for the spindle, then
    the CL's first rapid are one stretch, the rapid judged against where the CL goes (it
    was judged against the unknown height after the tool change, and correct NC from
    real G-code was refused); a rapid into the part before a dwell is still caught."""
    cl = [ToolChange(tool_number=1, line=1), SpindleOn(spindle_speed=1000, line=2),
          CLDwell(dwell=1, line=3), RapidMove(x=0, y=0, z=2, line=4),
          LinearMove(z=-1, feed=100, line=5)]
    tooling = Tooling(1, 1, "cw", 1000)

    def nc(lift: float) -> list:
        return [Rapid(Origin(1, f"G0 Z{lift}"), (None, None, None), (None, None, lift)),
                Dwell(Origin(2, "G4 P1"), 1.0),
                Rapid(Origin(3, "G0 X0 Y0 Z2"), (None, None, lift), (0, 0, 2)),
                FeedMove(Origin(4, "G1 Z-1"), (0, 0, 2), (0, 0, -1), 100, tooling)]

    assert verify_events(nc(25), cl_events(cl, "p.jsonl"), 0.001).ok
    assert str(verify_events(nc(-5), cl_events(cl, "p.jsonl"), 0.001).divergence) == (
        "p.jsonl:5: NC line 4: G1 Z-1: a rapid down to Z-5.000, below the CL's lowest point "
        "Z2.000 between these cuts")


def test_a_short_arc_written_as_a_full_circle_is_a_divergence() -> None:
    cl = [ToolChange(tool_number=1, line=1), SpindleOn(spindle_speed=1000, line=2),
          RapidMove(x=10, y=0, z=0, line=3),
          CLArc(x=9.99999999, y=0.0004, cx=0, cy=0, arc_direction="ccw", feed=100, line=4)]
    post = api.load_post("feeler")
    # what a post writes for it when it rounds the end onto the start
    nc = list(api.control_model("fanuc-0i").replay([
        "T1", "M6", "S1000 M3", "G43 H1", "G0 X10. Y0. Z0.", "G3 X10. Y0. I-10. J0. F100"]))
    message = str(verify_events(nc, cl_events(cl, "p.jsonl"), post.machine.resolution)
                  .divergence)
    # the CL arc is shorter than the resolution: it cuts nothing, the circle is extra
    assert message == ("p.jsonl:4: NC line 6: G3 X10. Y0. I-10. J0. F100: a ccw arc to "
                       "X10.000 Y0.000 Z0.000 that the CL does not have")


def test_a_first_peck_the_control_plunges_unlike_the_cl_is_a_divergence() -> None:
    """A control with a first infeed of its own (a first plunge, a degression) reports it
    on the hole; the CL's first peck must be the one it plunges, and a CL without one
    plunges first by its peck."""
    from postdsl.check.controls.events import Hole
    from postdsl.cl.model import DeepDrill

    tooling = Tooling(1, 1, "cw", 1000)
    cl = [ToolChange(tool_number=1, line=1), SpindleOn(spindle_speed=1000, line=2),
          RapidMove(x=10, y=10, z=20, line=3),
          DeepDrill(x=10, y=10, top=0, depth=10, clearance=2, peck=2, first_peck=4, feed=100,
                    line=4)]

    def nc(first_peck: float | None) -> list:
        return [Rapid(Origin(1, "G0 X10 Y10 Z20"), (None, None, None), (10, 10, 20)),
                Rapid(Origin(2, "hole"), (10, 10, 20), (10, 10, 2)),
                Hole(Origin(2, "hole"), (10, 10, 20), 10, 10, 2, -10, 2, "peck", "cw", 0.0,
                     2.0, 100, tooling, first_peck)]

    def verdict(first_peck: float | None, commands: list = cl) -> str | None:
        found = verify_events(nc(first_peck), cl_events(commands, "p.jsonl"), 0.001).divergence
        return None if found is None else str(found)

    assert verdict(4.0) is None
    assert verdict(None) == "p.jsonl:4: NC line 2: hole: hole 1: first peck 2.000, CL says 4.000"
    assert verdict(3.0) == "p.jsonl:4: NC line 2: hole: hole 1: first peck 3.000, CL says 4.000"
    same = [*cl[:3], DeepDrill(x=10, y=10, top=0, depth=10, clearance=2, peck=2, feed=100,
                               line=4)]
    assert verdict(None, same) is None
    assert verdict(4.0, same) == ("p.jsonl:4: NC line 2: hole: hole 1: first peck 4.000, "
                                  "CL says 2.000")


# --- the command line --------------------------------------------------------------------------

def without_h() -> str:
    """The Feeler post whose first move after a tool change writes G43 without H."""
    at = FEELER.index('" H", format: int}', FEELER.index("  rapid_move:"))
    return FEELER[:at] + '" H", format: int, if: "false"}' + FEELER[at + 18:]


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "postdsl.cli", *args], capture_output=True,
                          text=True, check=False, cwd=MACHINES.parent)


def test_verify_exits_0_with_a_summary_and_4_with_the_divergence(tmp_path: Path) -> None:
    ok = run("verify", "feeler", "examples/feeler_drilling.apt")
    assert ok.returncode == 0, ok.stderr
    assert "does what the CL says (13 cuts, 13 of them holes" in ok.stderr
    wrong = tmp_path / "wrong.yaml"
    wrong.write_text(without_h(), encoding="utf-8")
    bad = run("verify", str(wrong), "examples/feeler_milling.apt")
    assert bad.returncode == 4, bad.stderr
    assert bad.stderr.startswith("examples/feeler_milling.apt:")
    assert "Traceback" not in bad.stderr


def test_post_verify_writes_nothing_when_verify_fails(tmp_path: Path) -> None:
    out = tmp_path / "prog.nc"
    wrong = tmp_path / "wrong.yaml"
    wrong.write_text(without_h(), encoding="utf-8")
    bad = run("post", "--verify", str(wrong), "examples/feeler_milling.apt", "-o", str(out))
    assert bad.returncode == 4 and not out.exists()
    good = run("post", "--verify", "feeler", "examples/feeler_milling.apt", "-o", str(out))
    assert good.returncode == 0, good.stderr
    assert out.read_text(encoding="utf-8") == run("post", "feeler",
                                                  "examples/feeler_milling.apt").stdout


@pytest.mark.parametrize(("speed", "feed", "refusal"), [
    (0, 100, "spindle at 0 rpm"),
    (0.4, 100, "spindle at 0.4 rpm"),        # written S0
    (1000, 0.04, "below the minimum feed"),   # would be written F0.0 (1 decimal)
])
def test_cutting_with_the_spindle_stopped_or_no_feed_is_refused_before_verify(
        speed: float, feed: float, refusal: str, tmp_path: Path) -> None:
    """The engine refuses these at post time; verify never sees such a program."""
    cl = tmp_path / "p.jsonl"
    cl.write_text("\n".join([
        '{"cmd": "tool_change", "tool_number": 1}',
        f'{{"cmd": "spindle_on", "spindle_speed": {speed}}}',
        '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 5}',
        f'{{"cmd": "linear_move", "z": -1, "feed": {feed}}}',
        '{"cmd": "program_end"}']) + "\n", encoding="utf-8")
    with pytest.raises(api.CLError, match=refusal) as caught:
        api.verify_commands(api.load_post("feeler"), api.read_cl(cl), cl_file=cl.name,
                            now=THESIS_TIME)
    assert caught.value.location.line == 4


@pytest.mark.parametrize(("good", "bad", "message"), [
    ("""{text: " M3", if: "spindle == 'cw'"}""", """{text: " M5", if: "spindle == 'cw'"}""",
     "feed move with the spindle stopped"),
    ('{param: feed, prefix: " F", format: feed, mode: changed, modal: f}\n\n  # G2/G3',
     '{text: " F0.0"}\n\n  # G2/G3', "feed move without a feed rate (F0.000)"),
])
def test_verify_catches_a_post_that_cuts_with_the_spindle_stopped_or_no_feed(
        good: str, bad: str, message: str, tmp_path: Path) -> None:
    """A post broken past the engine's checks: it writes M5 for M3, or a fixed F0.0."""
    assert good in FEELER
    post = api.load_post_text(FEELER.replace(good, bad, 1), "broken.yaml")
    cl = tmp_path / "p.jsonl"
    cl.write_text("\n".join([
        '{"cmd": "tool_change", "tool_number": 1}',
        '{"cmd": "spindle_on", "spindle_speed": 1000}',
        '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 5}',
        '{"cmd": "linear_move", "z": -1, "feed": 100}',
        '{"cmd": "program_end"}']) + "\n", encoding="utf-8")
    found = divergence(post, cl)
    assert found.startswith("p.jsonl:4: NC line ") and found.endswith(message), found


PECK_0 = "".join(line + "\n" for line in (
    '{"cmd": "program_start", "program_name": "P0"}',
    '{"cmd": "tool_change", "tool_number": 3, "tool_diameter": 8.5}',
    '{"cmd": "spindle_on", "spindle_speed": 1500, "spindle": "cw"}',
    '{"cmd": "rapid_move", "x": 10, "y": 10, "z": 20}',
    '{"cmd": "cycle_start"}',
    '{"cmd": "deep_drill", "x": 10, "y": 10, "top": 0, "depth": 25, "clearance": 2, '
    '"retract": 20, "peck": 0, "feed": 120}',
    '{"cmd": "cycle_hole", "x": 70, "y": 10}',
    '{"cmd": "cycle_end"}',
    '{"cmd": "cycle_start"}',
    '{"cmd": "break_chip", "x": 10, "y": 30, "top": 0, "depth": 25, "clearance": 2, '
    '"retract": 20, "peck": 0, "feed": 120}',
    '{"cmd": "cycle_end"}',
    '{"cmd": "spindle_off"}',
    '{"cmd": "program_end"}'))


@pytest.mark.parametrize("machine", ["fanuc", "feeler", "linuxcnc", "grbl", "emco", "vmc500",
                                     "heidenhain"])
def test_peck_0_no_pecking_verifies_as_the_drill_the_post_writes(machine: str) -> None:
    """``peck: 0`` is a valid CL value ("no pecking"): the posts write a plain drilling cycle,
    which verify refused as "a drill cycle, CL says peck" (a false alarm, issue 25)."""
    verdict = api.verify_commands(api.load_post(machine), api.read_cl_text(PECK_0, "p0.jsonl"),
                                  cl_file="p0.jsonl", now=THESIS_TIME)
    assert verdict.ok, verdict.divergence
    assert verdict.cuts == 3


def test_cycles_that_peck_are_compared_by_their_kind() -> None:
    post = broken(FEELER, "  break_chip:", '" G73"', '" G83"')  # chip breaking as full retract
    cl = api.read_cl_text(PECK_0.replace('"peck": 0,', '"peck": 5,'), "p5.jsonl")
    verdict = api.verify_commands(post, cl, cl_file="p5.jsonl", now=THESIS_TIME)
    assert "hole 3: a peck cycle, CL says chip break" in str(verdict.divergence)


def test_hmcnc_settings_are_not_read_out_of_a_cl_comment() -> None:
    """A CL comment is written as ``//text``; one that reads like the machine's settings
    (``//feed 6000mm/min``) changed what the model took for the machine's speed, steps and
    tool: a right program failed verify (issue 25)."""
    lines = (EXAMPLES / "hmcnc_sign.jsonl").read_text(encoding="utf-8").splitlines()
    comment = '{{"cmd": "comment", "comment": "{}"}}'.format
    out = []
    for line in lines:
        if '"cmd": "tool_change"' in line:  # before the tool change: after the start
            out += [comment("steps/mm 100X100Y100Z"), comment("feed 6000mm/min"),
                    comment("spindle 1000rpm")]
        out.append(line)
        if '"cmd": "spindle_on"' in line:
            out.append(comment("tool 7"))
    text = "\n".join(out) + "\n"
    post = api.load_post("hmcnc")
    nc = [line.text for line in api.post_commands(post, api.read_cl_text(text, "sign.jsonl"),
                                                  now=THESIS_TIME)]
    assert "//feed 6000mm/min" in nc and "//tool 7" in nc  # written as they are
    verdict = api.verify_commands(post, api.read_cl_text(text, "sign.jsonl"),
                                  cl_file="sign.jsonl", now=THESIS_TIME)
    assert verdict.ok, verdict.divergence


def test_the_level_a_hole_is_left_at_is_the_cls_in_either_direction() -> None:
    """A program that leaves a hole higher than the CL's retract (G98 for G99, Q204 written
    absolute) does not do what the CL says either; nor one that leaves it at a level the
    program does not state (G98 right after a tool change).  LinuxCNC's G33.1 read with
    its rapid up leaves at either level (``via``)."""
    tooling = Tooling(1, 1, "cw", 1000)

    def hole(leave: float | None, via: float | None = None) -> list:
        return [Hole(Origin(1), (0, 0, 50), 0, 0, 2, -10, leave, "drill", "cw", 0, 0, 100,
                     tooling, None, via)]

    def compare(nc: list, cl: list) -> str | None:
        verdict = verify_events(nc, cl, 0.001)
        return None if verdict.ok else verdict.divergence.message  # type: ignore[union-attr]

    assert compare(hole(20.0), hole(20.0)) is None
    assert compare(hole(20.0005), hole(20.0)) is None  # within the resolution
    assert compare(hole(50.0), hole(20.0)) == "hole 1: the tool is left at Z50.000, above " \
                                             "the CL's retract Z20.000"
    assert compare(hole(2.0), hole(20.0)) == "hole 1: the tool is left at Z2.000, below the " \
                                            "CL's retract Z20.000"
    assert "a level the program does not state" in str(compare(hole(None), hole(20.0)))
    assert compare(hole(50.0, via=2.0), hole(2.0)) is None
    assert compare(hole(50.0, via=2.0), hole(50.0)) is None
    assert compare(hole(50.0, via=2.0), hole(20.0)) is not None
