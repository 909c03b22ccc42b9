"""The 4th axis end to end: rotary CL posted by the XYZA posts, replayed by verify in the
part frame, refused by 3-axis posts; and the mutations of a rotary post verify must catch."""

from __future__ import annotations

import itertools
import math
import re
from datetime import datetime
from pathlib import Path

import pytest

import postdsl.run.rotary
from postdsl import api
from postdsl.cl.model import LinearMove, RapidMove
from postdsl.cl.readers import read_cl, read_cl_text
from postdsl.compile.runtime import NCLine
from postdsl.errors import CLError
from postdsl.run.engine import Engine
from tests.conftest import EXAMPLES, ROOT
from tests.test_rs274_oracle import TOOL_TABLE, find_rs274, for_rs274, rs274_process

NOW = datetime(2026, 1, 1, 12, 0, 0)
POSTS = ("linuxcnc_xyza", "fanuc_4axis")
PROGRAMS = ("rotary_wrap.jsonl", "rotary_four_sides.jsonl")


def post_of(name: str, change: tuple[str, str] | None = None) -> api.CompiledPost:
    path = ROOT / "machines" / f"{name}.yaml"
    if change is None:
        return api.load_post(path)
    text = path.read_text(encoding="utf-8")
    assert change[0] in text
    # the library posts extend their bases by name: the edited text loads as they do
    return api.load_post_text(text.replace(change[0], change[1]), str(path))


def commands(program: str) -> list:
    return list(read_cl(EXAMPLES / program))


def posted(post: api.CompiledPost, cl: list) -> list[NCLine]:
    return list(Engine(post, now=NOW).run(cl))


def nc(post: api.CompiledPost, cl: list) -> list[str]:
    return [line.text for line in posted(post, cl)]


def verdict_of(post: api.CompiledPost, lines: list[NCLine], cl: list) -> str | None:
    """The good post's verify of NC lines (made by whatever post, or edited)."""
    inputs = [api._nc_input(post, number, line) for number, line in enumerate(lines, start=1)]
    found = api._compare(post, inputs, cl, "<cl>", lambda _n: None, [])
    return None if found.ok else str(found.divergence)


@pytest.mark.parametrize("machine", POSTS)
@pytest.mark.parametrize("program", PROGRAMS)
def test_rotary_programs_post_and_verify(machine: str, program: str) -> None:
    post = post_of(machine)
    cl = commands(program)
    verdict = api.verify_commands(post, cl, now=NOW)
    assert verdict.ok, verdict.divergence


def test_the_wrap_turns_a_on_beyond_360_in_inverse_time() -> None:
    lines = nc(post_of("linuxcnc_xyza"), commands("rotary_wrap.jsonl"))
    cuts = [line for line in lines if " A" in f" {line}" and line.startswith(("G1", "G93"))]
    assert cuts[0].startswith("G93 G1 ")
    assert cuts[-1].startswith("G1 X60.000 Y0.000 Z19.000 A720.000 F")
    # a 10 degree step at radius 19 and 0.833 mm along X: the tip cuts 3.41 mm; 300 mm/min
    length = math.hypot(60 / 72, 19 * math.radians(10))
    assert float(cuts[1].split("F")[-1]) == pytest.approx(300 / length, abs=2e-4)
    assert any(line.startswith("G94 G1 ") and "F300.000" in line for line in lines)


def test_an_index_retracts_in_machine_coordinates_and_clamps() -> None:
    lines = nc(post_of("fanuc_4axis"), commands("rotary_four_sides.jsonl"))
    body = [line.split(" ", 1)[1] for line in lines if line.startswith("N")]
    turn = body.index("G0 A90.")
    assert body[turn - 3:turn + 4] == ["G91 G28 Z0.", "G90", "M11", "G0 A90.", "M10",
                                       "G0 X5. Y0.", "Z30."]


@pytest.mark.parametrize("machine", ["fanuc", "linuxcnc", "grbl"])
def test_three_axis_posts_refuse_rotary_cl_with_the_reason(machine: str) -> None:
    post = api.load_post(ROOT / "machines" / f"{machine}.yaml")
    with pytest.raises(CLError) as wrap:
        nc(post, commands("rotary_wrap.jsonl"))
    assert "tool axis" in str(wrap.value) and "no rotary axis" in str(wrap.value)
    with pytest.raises(CLError) as index:
        nc(post, commands("rotary_four_sides.jsonl"))
    assert "A90: this post's machine has no rotary axis" in str(index.value)


def test_a_tool_axis_the_a_table_cannot_reach_is_refused_at_its_line() -> None:
    cl = list(read_cl_text(
        '{"cmd": "tool_change", "tool_number": 1}\n'
        '{"cmd": "spindle_on", "spindle_speed": 1000, "spindle": "cw"}\n'
        '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 30}\n'
        '{"cmd": "linear_move", "x": 1, "z": 20, "tool_i": 0.5, "tool_k": 0.866, "feed": 100}\n'
        '{"cmd": "program_end"}\n',
        "leaning.jsonl"))
    with pytest.raises(CLError) as refused:
        nc(post_of("linuxcnc_xyza"), cl)
    assert refused.value.location.line == 4
    assert "no rotary solution" in str(refused.value)


# --- mutations: each a wrong rotary post, caught by the right machine's verify ------------------


@pytest.mark.parametrize("machine", POSTS)
@pytest.mark.parametrize(("mistake", "change"), [
    ("pivot offset wrong", ("pivot: [0, 0, 0]", "pivot: [0, 0, -2]")),
    ("rotary direction reversed", ("direction: 1,", "direction: -1,")),
    ("wrong unwind (modulo on an unwound axis)", ("wrap: unwound", "wrap: modulo")),
])
def test_verify_catches_a_wrong_rotary_post(machine: str, mistake: str,
                                            change: tuple[str, str]) -> None:
    good = post_of(machine)
    bad = post_of(machine, change)
    program = "rotary_wrap.jsonl"
    cl = commands(program)
    assert verdict_of(good, posted(good, cl), cl) is None
    divergence = verdict_of(good, posted(bad, cl), cl)
    assert divergence is not None, mistake


@pytest.mark.parametrize("machine", POSTS)
def test_verify_catches_a_pivot_error_on_an_indexed_part(machine: str) -> None:
    good = post_of(machine)
    bad = post_of(machine, ("pivot: [0, 0, 0]", "pivot: [0, 0, -2]"))
    cl = commands("rotary_four_sides.jsonl")
    assert verdict_of(good, posted(bad, cl), cl) is not None


@pytest.mark.parametrize("machine", POSTS)
def test_verify_catches_a_dropped_rotary_move(machine: str) -> None:
    good = post_of(machine)
    cl = commands("rotary_four_sides.jsonl")
    lines = posted(good, cl)
    turn = next(i for i, line in enumerate(lines) if "A180." in line.text)
    text = lines[turn].text.replace("A180.000", "").replace(" A180.", "")
    dropped = lines[:turn] + [lines[turn]._replace(text=text)] + lines[turn + 1:]
    divergence = verdict_of(good, dropped, cl)
    assert divergence is not None


@pytest.mark.parametrize("machine", POSTS)
def test_verify_catches_g93_from_the_linear_length_only(machine: str,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    good = post_of(machine)
    cl = commands("rotary_wrap.jsonl")

    def linear_only(kin, start, start_angles, end, end_angles) -> float:
        return math.dist(start, end)

    monkeypatch.setattr(postdsl.run.rotary, "tip_path_length", linear_only)
    lines = posted(good, cl)
    monkeypatch.undo()
    divergence = verdict_of(good, lines, cl)
    assert divergence is not None and "feed" in divergence


def test_examples_are_in_the_corpus() -> None:
    corpus = (ROOT / "corpus.yaml").read_text(encoding="utf-8")
    for program in PROGRAMS:
        assert f"examples/{program}" in corpus
    assert Path(EXAMPLES / PROGRAMS[0]).exists()


# --- rs274, LinuxCNC's own interpreter, as the independent oracle of the XYZA output -----------

_CALL = re.compile(r"\s*\d+ N\S*\s+(STRAIGHT_FEED|STRAIGHT_TRAVERSE|SET_FEED_RATE|COMMENT"
                   r"|SET_G92_OFFSET)\((.*)\)")


def _part(machine: tuple[float, ...]) -> tuple[float, float, float]:
    """The tip on the part: the machine's X Y Z turned back by A about X (written out here,
    not taken from postdsl.kinematics, so that the oracle shares no code with the post)."""
    x, y, z, a = machine[:4]
    c, s = math.cos(math.radians(a)), math.sin(math.radians(a))
    return (x, y * c - z * s, y * s + z * c)


def _tip_length(start: tuple[float, ...], end: tuple[float, ...]) -> float:
    steps = 2000
    points = [_part(tuple(s + (e - s) * i / steps for s, e in zip(start, end, strict=True)))
              for i in range(steps + 1)]
    return sum(math.dist(p, q) for p, q in itertools.pairwise(points))


@pytest.mark.skipif(find_rs274() is None, reason="rs274 not installed")
@pytest.mark.parametrize("program", PROGRAMS)
@pytest.mark.parametrize("machine", ["linuxcnc_xyza", "linuxcnc_xyza_rezero"])
def test_rs274_moves_the_xyza_program_to_the_cl_points_at_the_cl_feed(
        program: str, machine: str, tmp_path: Path) -> None:
    cl = commands(program)
    ngc = tmp_path / "program.ngc"
    ngc.write_text("\n".join(nc(post_of(machine), cl)) + "\n", encoding="utf-8")
    table = tmp_path / "tools.tbl"
    table.write_text(TOOL_TABLE, encoding="utf-8")
    result = rs274_process(table, ngc)
    errors = [line for line in result.stderr.splitlines() if line.strip() != "executing"]
    assert result.returncode == 0 and not errors, errors
    # rs274's moves, in the part frame, with the feed along the tip's path on the part
    moves: list[tuple[tuple[float, float, float], float | None]] = []
    at: tuple[float, ...] = (0.0, 0.0, 0.0, 0.0)
    rate, inverse, preset = 0.0, False, 0.0
    for match in _CALL.finditer(result.stdout):
        name, args = match.groups()
        if name == "COMMENT":
            inverse = "inverse time" in args if "feed mode" in args else inverse
            continue
        if name == "SET_FEED_RATE":
            rate = float(args)
            continue
        if name == "SET_G92_OFFSET":  # rs274 reports program coordinates: A + its G92 offset
            preset = float(args.split(",")[3])
            continue
        end = tuple(float(v) for v in args.split(",")[:4])
        end = (*end[:3], end[3] + preset)
        feed = None
        if name == "STRAIGHT_FEED":
            if inverse:  # rs274 gives F times the block's length (X Y Z, else the angle)
                linear = math.dist(at[:3], end[:3])
                minutes = (linear if linear > 1e-9 else abs(end[3] - at[3])) / rate
            else:
                minutes = _tip_length(at, end) / rate
            feed = _tip_length(at, end) / minutes
        moves.append((_part(end), feed))
        at = end
    expected: list[tuple[tuple[float | None, ...], float | None]] = []
    tip: list[float | None] = [None, None, None]
    feed_now = None
    for command in cl:
        if isinstance(command, (RapidMove, LinearMove)):
            tip = [tip[i] if getattr(command, n) is None else getattr(command, n)
                   for i, n in enumerate("xyz")]
            if isinstance(command, LinearMove):
                feed_now = command.feed if command.feed is not None else feed_now
            expected.append((tuple(tip), feed_now if isinstance(command, LinearMove) else None))
    assert len(moves) == len(expected)
    for number, ((point, feed), (cl_point, cl_feed)) in enumerate(
            zip(moves, expected, strict=True)):
        assert all(abs(p - q) < 0.002 for p, q in zip(point, cl_point, strict=True)), \
            (number, point, cl_point)
        if cl_feed is not None:
            assert feed == pytest.approx(cl_feed, abs=0.5), (number, feed, cl_feed)


# --- readers: A words of G-code, MULTAX GOTOs of APT -------------------------------------------


def test_gcode_a_words_become_the_tip_on_the_part_and_post_back_the_same() -> None:
    """X Y Z with A are where the machine stands with the part turned about X through the
    origin: the reader gives the tip on the part (and A); the XYZA post writes them back."""
    text = ("(FreeCAD rotary)\nG21 G90\nM6 T1\nM3 S5000\nG0 X0 Y0 Z30 A0\nG0 X5 A90\nG0 Z19\n"
            "G1 X35 F400\nG0 Z30\nG0 A180\nG1 Z19 F150\nG93 G1 X40 A200 F5\nM2\n")
    cl = list(read_cl_text(text.replace("G93 G1 X40 A200 F5\n", ""), "rotary.ngc"))
    moves = [c for c in cl if isinstance(c, (RapidMove, LinearMove))]
    assert (moves[1].a, moves[2].y, moves[2].z) == (90.0, pytest.approx(-19.0),
                                                    pytest.approx(0.0, abs=1e-9))
    post = post_of("linuxcnc_xyza")
    assert api.verify_commands(post, cl, now=NOW).ok
    lines = nc(post, cl)
    # the program read back is the program posted: the same words, line for line
    moved = [line for line in lines if line.startswith(("G0 ", "G1 "))]
    assert moved == ["G0 X0.000 Y0.000 Z30.000 A0.000 ", "G0 X5.000 A90.000 ", "G0 Z19.000 ",
                     "G1 X35.000 F400.000 ", "G0 Z30.000 ", "G0 A180.000 ",
                     "G1 Z19.000 F150.000 "]
    with pytest.raises(CLError, match="this post's machine has no rotary axis"):
        nc(api.load_post(ROOT / "machines" / "linuxcnc.yaml"), cl)


def test_gcode_arc_with_the_part_turned_is_refused_at_its_line() -> None:
    with pytest.raises(CLError) as refused:
        read_cl_text("G21 G90\nM6 T1\nM3 S5000\nG0 X0 Y0 Z30 A90\nG2 X10 Y0 I5 J0 F100\nM2\n",
                     "arc.ngc")
    assert refused.value.location.line == 5 and "A90" in str(refused.value)


def test_apt_multax_gotos_post_on_the_xyza_post() -> None:
    r = 19.0
    gotos = "".join(
        f"GOTO/{10 * s / 9:.4f},{-r * math.sin(math.radians(10 * s)):.4f},"
        f"{r * math.cos(math.radians(10 * s)):.4f},0,{-math.sin(math.radians(10 * s)):.6f},"
        f"{math.cos(math.radians(10 * s)):.6f}\n" for s in range(1, 10))
    text = ("PARTNO/WRAP\nMULTAX/ON\nLOADTL/1\nSPINDL/RPM,5000,CLW\nRAPID\nGOTO/0,0,30,0,0,1\n"
            "FEDRAT/300\nGOTO/0,0,19,0,0,1\n" + gotos + "RAPID\nGOTO/10,-30,0,0,-1,0\n"
            "MULTAX/OFF\nEND\nFINI\n")
    cl = list(read_cl_text(text, "wrap.apt"))
    post = post_of("linuxcnc_xyza")
    verdict = api.verify_commands(post, cl, now=NOW)
    assert verdict.ok, verdict.divergence
    lines = nc(post, cl)
    assert any(line.startswith("G93 G1 X1.111 ") and "A10.000" in line for line in lines)
    last = next(i for i, line in enumerate(lines) if "A90.000" in line)
    assert lines[last + 1:last + 3] == ["G94", "G0 Z30.000 "]  # the tool leaves radially


# --- the control models with rotaries --------------------------------------------------------


def _replayed(control: str, lines: list[str]) -> list:
    from postdsl.check.controls import control_model
    from postdsl.check.controls.events import FeedMove, Rapid
    from postdsl.kinematics import Kinematics, RotaryAxis

    model = control_model(control)
    model.set_kinematics(Kinematics((RotaryAxis("a", "x", continuous=True),)))
    return [e for e in model.replay(lines) if isinstance(e, (FeedMove, Rapid))]


@pytest.mark.parametrize("control", ["linuxcnc", "fanuc-0i"])
def test_the_model_reports_the_tip_on_the_part_and_the_feed_along_it(control: str) -> None:
    events = _replayed(control, ["G0 X0. Y0. Z20. A0.", "G93 G1 X10. A90. F6.",
                                 "G94 G1 X20. F300."])
    _rapid, turn, straight = events
    assert turn.end == pytest.approx((10.0, -20.0, 0.0))  # the top at A90 is the part's -Y
    # 1/6 min along a helix of 10 mm by a quarter turn at radius 20
    assert turn.feed == pytest.approx(6 * math.hypot(10, 10 * math.pi), rel=1e-6)
    assert turn.path == pytest.approx(math.hypot(10, 10 * math.pi), rel=1e-6)
    assert straight.feed == 300 and straight.path is None


@pytest.mark.parametrize("control", ["linuxcnc", "fanuc-0i"])
def test_g93_without_f_on_the_block_is_an_error(control: str) -> None:
    from postdsl.check.controls import ControlError

    with pytest.raises(ControlError, match="needs its own F"):
        _replayed(control, ["G0 X0. Y0. Z20. A0.", "G93 G1 X10. A90. F6.", "G1 X20. A100."])


def test_a_fanuc_a_word_without_a_point_is_in_thousandths_of_a_degree() -> None:
    rapid = _replayed("fanuc-0i", ["G0 X0. Y0. Z20. A90000"])[0]
    assert rapid.end == pytest.approx((0.0, -20.0, 0.0))


def test_the_model_refuses_an_angle_beyond_the_axis_limits() -> None:
    from postdsl.check.controls import ControlError, control_model
    from postdsl.kinematics import Kinematics, RotaryAxis

    model = control_model("linuxcnc")
    model.set_kinematics(Kinematics((RotaryAxis("a", "x", limits=(-30.0, 120.0)),)))
    with pytest.raises(ControlError, match="A130 is beyond the axis's limits -30 to 120"):
        list(model.replay(["G0 X0 Y0 Z20 A90", "G0 A130"]))


def test_a_freecad_dump_with_a_words_posts_back_as_written() -> None:
    """FreeCAD's rotary path (A with X Y Z in its Path commands; F in mm/s): the XYZA post
    writes the same axis words, the cuts that turn A in G93 at FreeCAD's feed."""
    text = ("(Path: G54)\nCommand G54 [ ]\nCommand G0 [ Z:30 ]\n(Path: TC: Endmill 6mm)\n"
            "Command (TC: Endmill 6mm) [ ]\nCommand M6 [ T:1 ]\nCommand M3 [ S:5000 ]\n"
            "(Path: Wrap)\nCommand (Wrap) [ ]\nCommand G0 [ F:0 X:0 Y:0 Z:30 A:0 ]\n"
            "Command G0 [ F:0 Z:19 ]\nCommand G1 [ F:5 X:10 A:180 ]\n"
            "Command G1 [ F:5 X:20 A:360 ]\nCommand G1 [ F:5 X:30 A:540 ]\n"
            "Command G0 [ F:0 Z:30 ]\n")
    cl = list(read_cl_text(text, "wrap.dump.txt"))
    post = post_of("linuxcnc_xyza")
    verdict = api.verify_commands(post, cl, now=NOW)
    assert verdict.ok, verdict.divergence
    moved = [line for line in nc(post, cl) if line.startswith(("G0 ", "G1 ", "G93 "))]
    inverse = f"F{300 / math.hypot(10, 19 * math.pi):.4f} "
    assert moved == ["G0 Z30.000 ", "G0 X0.000 Y0.000 Z30.000 A0.000 ", "G0 Z19.000 ",
                     "G93 G1 X10.000 A180.000 " + inverse, "G1 X20.000 A360.000 " + inverse,
                     "G1 X30.000 A540.000 " + inverse, "G0 Z30.000 "]


@pytest.mark.parametrize("machine", POSTS)
def test_verify_compares_the_tool_axis_where_the_tip_alone_cannot_tell(machine: str) -> None:
    """The tip on the A axis stays where it is at any A: only the tool axis on the part shows
    a wrong angle."""
    cl = list(read_cl_text(
        '{"cmd": "tool_change", "tool_number": 1}\n'
        '{"cmd": "spindle_on", "spindle_speed": 1000, "spindle": "cw"}\n'
        '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 30, "tool_i": 0, "tool_j": 0, "tool_k": 1}\n'
        '{"cmd": "linear_move", "z": 0, "feed": 100}\n'
        '{"cmd": "linear_move", "x": 10, "tool_j": -1, "tool_k": 0}\n'
        '{"cmd": "program_end"}\n', "on_axis.jsonl"))
    good = post_of(machine)
    lines = posted(good, cl)
    assert verdict_of(good, lines, cl) is None
    turn = next(i for i, line in enumerate(lines) if "A90." in line.text)
    wrong = lines[:turn] + [lines[turn]._replace(text=lines[turn].text.replace("A90.", "A-90."))] \
        + lines[turn + 1:]
    divergence = verdict_of(good, wrong, cl)
    assert divergence is not None and "tool axis on the part (0.0000, 1.0000" in divergence


@pytest.mark.skipif(find_rs274() is None, reason="rs274 not installed")
@pytest.mark.parametrize("program", PROGRAMS)
def test_rs274_cuts_the_fanuc_4axis_program_at_the_cl_points_and_feed(
        program: str, tmp_path: Path) -> None:
    """The Fanuc 4th-axis output through rs274 (the oracle's documented rewrites, and the
    builder's brake codes M10/M11 left out: rs274 has none): every cut ends on the CL's
    point of the part at the CL's feed along the tip's path."""
    cl = commands(program)
    lines = [line for line in for_rs274(nc(post_of("fanuc_4axis"), cl))
             if not re.fullmatch(r"N\d+ M1[01]", line)]
    ngc = tmp_path / "program.ngc"
    ngc.write_text("\n".join(lines) + "\n", encoding="utf-8")
    table = tmp_path / "tools.tbl"
    table.write_text(TOOL_TABLE, encoding="utf-8")
    result = rs274_process(table, ngc)
    errors = [line for line in result.stderr.splitlines() if line.strip() != "executing"]
    assert result.returncode == 0 and not errors, errors
    cuts: list[tuple[tuple[float, float, float], float]] = []
    at: tuple[float, ...] = (0.0, 0.0, 0.0, 0.0)
    rate, inverse = 0.0, False
    for match in _CALL.finditer(result.stdout):
        name, args = match.groups()
        if name == "COMMENT":
            inverse = "inverse time" in args if "feed mode" in args else inverse
        elif name == "SET_G92_OFFSET":
            assert all(float(v) == 0 for v in args.split(",")), "the Fanuc post writes no G92"
        elif name == "SET_FEED_RATE":
            rate = float(args)
        else:
            end = tuple(float(v) for v in args.split(",")[:4])
            if name == "STRAIGHT_FEED":
                linear = math.dist(at[:3], end[:3])
                minutes = ((linear if linear > 1e-9 else abs(end[3] - at[3])) if inverse
                           else _tip_length(at, end)) / rate
                cuts.append((_part(end), _tip_length(at, end) / minutes))
            at = end
    expected = []
    tip: list[float | None] = [None, None, None]
    feed_now = None
    for command in cl:
        if isinstance(command, (RapidMove, LinearMove)):
            tip = [tip[i] if getattr(command, n) is None else getattr(command, n)
                   for i, n in enumerate("xyz")]
        if isinstance(command, LinearMove):
            feed_now = command.feed if command.feed is not None else feed_now
            expected.append((tuple(tip), feed_now))
    assert len(cuts) == len(expected)
    for (point, feed), (cl_point, cl_feed) in zip(cuts, expected, strict=True):
        assert all(abs(p - q) < 0.002 for p, q in zip(point, cl_point, strict=True)), \
            (point, cl_point)
        assert feed == pytest.approx(cl_feed, abs=0.5)


# --- rezero: a continuous axis's count set back by whole turns (G92 A) -------------------------


def test_the_rezero_post_sets_a_back_each_turn_and_verify_passes() -> None:
    post = post_of("linuxcnc_xyza_rezero")
    cl = commands("rotary_wrap.jsonl")
    lines = posted(post, cl)
    texts = [line.text for line in lines]
    presets = [i for i, text in enumerate(texts) if text.startswith("G92 ")]
    assert presets, "the wrap passes a full turn: A must be re-zeroed"
    for i in presets:  # A stood at 350, counted -10 now: the next cut turns on to 0, +10
        assert texts[i - 1].split("A")[1].startswith("350.000")
        assert texts[i] == "G92 A-10.000"
        assert " A0.000 " in texts[i + 1]
    angles = [float(m.group(1)) for text in texts for m in [re.search(r" A(-?[\d.]+)", text)]
              if m is not None]
    assert all(-360 < a < 360 for a in angles)
    assert verdict_of(post, lines, cl) is None


@pytest.mark.parametrize(("mistake", "edit"), [
    ("the G92 dropped: the count jumps back a turn", lambda text: None),
    ("G92 A0 where A stands at 350: the part turned 10 degrees",
     lambda text: "G92 A0.000"),
])
def test_verify_catches_a_rezero_without_the_matching_count(mistake: str, edit) -> None:
    post = post_of("linuxcnc_xyza_rezero")
    cl = commands("rotary_wrap.jsonl")
    lines = []
    for line in posted(post, cl):
        if line.text.startswith("G92 "):
            text = edit(line.text)
            if text is None:
                continue
            line = line._replace(text=text)
        lines.append(line)
    assert verdict_of(post, lines, cl) is not None, mistake


def test_a_rezero_post_refuses_a_machine_without_one_continuous_axis() -> None:
    with pytest.raises(api.PostError, match="exactly one continuous axis") as refused:
        post_of("linuxcnc_xyza_rezero", (
            "rotary: {wrap: rezero, prefer: shortest}",
            "rotary: {wrap: rezero}\n  rotary_axes: [{name: a, about: x, limits: [-90, 90]}]"))
    assert refused.value.location is not None


# --- modulo axes and the words that say the way round ------------------------------------------


def emco_commands(program: str) -> list:
    """An example within the EMCO's spindle range (5000 rpm at most)."""
    text = re.sub(r'"spindle_speed": \d+', '"spindle_speed": 4000',
                  (EXAMPLES / program).read_text(encoding="utf-8"))
    return list(read_cl_text(text, program))


@pytest.mark.parametrize("program", PROGRAMS)
def test_the_sinumerik_4axis_post_writes_dc_and_verify_passes(program: str) -> None:
    post = post_of("emco_4axis")
    cl = emco_commands(program)
    lines = posted(post, cl)
    angles = [float(a) for line in lines for a in re.findall(r"A=DC\(([-\d.]+)\)", line.text)]
    assert angles and all(0 <= a < 360 for a in angles)
    assert not any(re.search(r" A[-\d]", line.text) for line in lines)
    assert verdict_of(post, lines, cl) is None


def test_over_zero_the_wrap_turns_on_the_short_way_at_its_feed() -> None:
    lines = [line.text for line in posted(post_of("emco_4axis"), emco_commands(
        "rotary_wrap.jsonl"))]
    over = next(i for i, text in enumerate(lines) if "A=DC(0.000)" in text and "F" in text)
    assert "A=DC(350.000)" in lines[over - 1]
    # 10 degrees, as each step before it: the same inverse time, not 350 degrees' worth
    assert abs(float(lines[over].split(" F")[1]) - float(lines[over - 1].split(" F")[1])) < 0.001


@pytest.mark.parametrize(("mistake", "change"), [
    ("ACN: the wrap cut the negative way round", ('" A=DC("', '" A=ACN("')),
    ("a plain A: the Sinumerik stays within the turn, 350 to 0 goes back",
     ('prefix: " A=DC(", suffix: ")"', 'prefix: " A"')),
])
def test_verify_catches_a_wrong_way_round_word(mistake: str, change: tuple[str, str]) -> None:
    good = post_of("emco_4axis")
    cl = emco_commands("rotary_wrap.jsonl")
    divergence = verdict_of(good, posted(post_of("emco_4axis", change), cl), cl)
    assert divergence is not None, mistake


def test_a_fanuc_modulo_axis_rolls_over_the_short_way() -> None:
    """Fanuc roll-over (1008#0 ROAx = 1, #1 RABx = 0): A0 after A350 turns on +10."""
    post = post_of("fanuc_4axis", ("wrap: unwound", "wrap: modulo"))
    cl = commands("rotary_wrap.jsonl")
    lines = posted(post, cl)
    assert any(" A0." in line.text and " F" in line.text for line in lines)
    assert verdict_of(post, lines, cl) is None


def test_a_modulo_cut_of_half_a_turn_is_refused_at_its_line() -> None:
    cl = list(read_cl_text(
        '{"cmd": "program_start"}\n'
        '{"cmd": "tool_change", "tool_number": 1, "tool_diameter": 6}\n'
        '{"cmd": "spindle_on", "spindle_speed": 3000, "spindle": "cw"}\n'
        '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 30, "a": 0}\n'
        '{"cmd": "linear_move", "z": 19, "feed": 100}\n'
        '{"cmd": "linear_move", "x": 5, "a": 200, "feed": 100}\n'
        '{"cmd": "program_end"}\n', "half.jsonl"))
    with pytest.raises(CLError) as refused:
        nc(post_of("emco_4axis"), cl)
    assert refused.value.location.line == 6
    assert "short way round" in str(refused.value)


# --- the tool axis where the CL gives angles ---------------------------------------------------


@pytest.mark.parametrize("machine", POSTS)
def test_verify_compares_the_angles_tool_axis_where_the_tip_alone_cannot_tell(
        machine: str) -> None:
    """The CL gives A, not a vector, and the tip sits on the A axis: only the tool axis the
    CL's A sets on the part shows an NC A of the wrong sign."""
    cl = list(read_cl_text(
        '{"cmd": "tool_change", "tool_number": 1}\n'
        '{"cmd": "spindle_on", "spindle_speed": 1000, "spindle": "cw"}\n'
        '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 30, "a": 0}\n'
        '{"cmd": "linear_move", "z": 0, "feed": 100}\n'
        '{"cmd": "linear_move", "x": 10, "a": 90}\n'
        '{"cmd": "program_end"}\n', "on_axis_a.jsonl"))
    good = post_of(machine)
    lines = posted(good, cl)
    assert verdict_of(good, lines, cl) is None
    turn = next(i for i, line in enumerate(lines) if "A90." in line.text)
    wrong = lines[:turn] + [lines[turn]._replace(text=lines[turn].text.replace("A90.", "A-90."))] \
        + lines[turn + 1:]
    divergence = verdict_of(good, wrong, cl)
    assert divergence is not None and "tool axis on the part" in divergence


# --- machining time with the rotaries ----------------------------------------------------------


def test_a_cut_turning_a_is_timed_by_the_tips_arc_on_the_part() -> None:
    """The machine stands at Y0 Z19 while A turns 90 degrees: the tip cuts a quarter circle
    of radius 19 on the part, not the chord between its ends."""
    from postdsl.run.program import summarize

    post = post_of("linuxcnc_xyza")
    cl = list(read_cl_text(
        '{"cmd": "tool_change", "tool_number": 1}\n'
        '{"cmd": "spindle_on", "spindle_speed": 1000, "spindle": "cw"}\n'
        '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 19, "a": 0}\n'
        '{"cmd": "linear_move", "y": -19, "z": 0, "a": 90, "feed": 100}\n'
        '{"cmd": "program_end"}\n', "quarter.jsonl"))
    # the machine's X Y Z stay, A turns: F = 100 / (19 pi / 2) per minute
    assert "G93 G1 A90.000 F3.3506" in [line.strip() for line in nc(post, cl)]
    plain = summarize(cl, post.machine.rapid_rate).machining_time
    turned = summarize(cl, post.machine.rapid_rate, post.machine.kinematics).machining_time
    arc, chord = 19 * math.pi / 2, 19 * math.sqrt(2)
    assert turned - plain == pytest.approx((arc - chord) / 100 * 60, abs=1e-6)


def test_an_index_is_timed_by_the_rotarys_rapid_rate_where_declared() -> None:
    from postdsl.run.program import summarize

    undeclared = post_of("fanuc_4axis")
    declared = post_of("fanuc_4axis", ("rotary: {wrap: unwound, prefer: shortest}",
                                       "rotary: {wrap: unwound, prefer: shortest, "
                                       "rapid_rate: 3600}"))
    cl = commands("rotary_four_sides.jsonl")
    rate = undeclared.machine.rapid_rate
    # each index: 90 degrees at 3600 deg/min (1.5 s) instead of its X Y Z travel
    extra, pos, angle = 0.0, [None, None, None], 0.0
    for command in cl:
        if isinstance(command, (RapidMove, LinearMove)):
            end = [p if getattr(command, n) is None else getattr(command, n)
                   for p, n in zip(pos, "xyz", strict=True)]
            if isinstance(command, RapidMove) and command.a is not None and command.a != angle:
                extra += abs(command.a - angle) / 3600 * 60 - math.dist(pos, end) / rate * 60
                angle = command.a
            pos = end
    assert extra > 2
    assert summarize(cl, rate, declared.machine.kinematics).machining_time == pytest.approx(
        summarize(cl, rate, undeclared.machine.kinematics).machining_time + extra)


# --- the plot: the tool axis where the rotaries tilt it -----------------------------------------


@pytest.mark.parametrize("machine", POSTS)
def test_the_plot_draws_the_tool_axis_round_the_wrap(machine: str) -> None:
    """The wrap turns A 720 degrees in steps of 10: the tool is drawn standing on the part
    at the first tilted cut (A10) and every 20 degrees after it (the first step of 15 or
    more): 36 times, radial to A, from the tip outward."""
    _, path = api.toolpath_file(ROOT / "machines" / f"{machine}.yaml",
                                EXAMPLES / "rotary_wrap.jsonl")
    assert path.stopped is None
    axes = [s for s in path.segments if s.kind == "axis"]
    assert len(axes) == 36
    for segment in axes:
        (x0, y0, z0), (x1, y1, z1) = segment.points
        assert x1 == pytest.approx(x0)  # A turns about X: the axis stays in the YZ plane
        assert math.hypot(y1, z1) == pytest.approx(math.hypot(y0, z0) + 15, abs=1e-6)
        assert math.hypot(y0, z0) == pytest.approx(19, abs=0.01)  # the tip on the groove
        cut = next(s for s in path.segments if s.kind == "feed" and s.nc_line == segment.nc_line)
        assert segment.points[0] == cut.points[-1]


def test_the_plot_draws_the_tool_axis_once_per_indexed_face() -> None:
    """Four sides indexed in A: the tool axis drawn at the first cut of each face the table
    tilts (A90, A180, A270; A0 is the part's Z), none on a three-axis program."""
    _, path = api.toolpath_file(ROOT / "machines" / "linuxcnc_xyza.yaml",
                                EXAMPLES / "rotary_four_sides.jsonl")
    assert len([s for s in path.segments if s.kind == "axis"]) == 3  # A90, A180, A270
    _, flat = api.toolpath_file(ROOT / "machines" / "linuxcnc_xyza.yaml",
                                EXAMPLES / "feeler_milling.apt")
    assert not [s for s in flat.segments if s.kind == "axis"]


def test_a_rezero_post_whose_moves_never_write_rezero_is_refused() -> None:
    """fanuc_4axis writes no G92: set to rezero it would drop the turns silently."""
    with pytest.raises(api.PostError, match="never writes rezero") as refused:
        post_of("fanuc_4axis", ("rotary: {wrap: unwound", "rotary: {wrap: rezero"))
    assert refused.value.location is not None and refused.value.location.line > 1


@pytest.mark.parametrize("control", ["linuxcnc", "fanuc-0i"])
def test_g92_a_sets_the_rotarys_count_where_it_stands(control: str) -> None:
    """A at 350, counted -10 after G92: A0 turns on +10 and the part is at 360 (= 0)."""
    rapid, cut = _replayed(control, ["G0 X0. Y0. Z20. A350.", "G92 A-10.",
                                     "G93 G1 X10. A0. F6."])
    assert rapid.end == pytest.approx((0.0, -20 * math.sin(math.radians(350)),
                                       20 * math.cos(math.radians(350))))
    assert cut.end == pytest.approx((10.0, 0.0, 20.0))
    assert cut.path == pytest.approx(math.hypot(10, 20 * math.radians(10)), rel=1e-6)


@pytest.mark.parametrize("control", ["linuxcnc", "fanuc-0i"])
def test_g92_on_a_linear_axis_is_not_modelled(control: str) -> None:
    from postdsl.check.controls import ControlError

    with pytest.raises(ControlError, match="G92 on X, Y or Z"):
        _replayed(control, ["G0 X0. Y0. Z20. A0.", "G92 X0. A0."])


def test_the_sinumerik_model_turns_a_modulo_axis_the_way_its_word_says() -> None:
    from postdsl.check.controls import control_model
    from postdsl.kinematics import Kinematics, RotaryAxis

    def path_of(word: str) -> float:
        model = control_model("sinumerik-828d")
        model.set_kinematics(Kinematics((RotaryAxis("a", "x", continuous=True),),
                                        wrap="modulo"))
        events = list(model.replay(["T1 D1", "M6", "G0 X0 Y0 Z20 A=DC(350)", "G93",
                                    f"G1 X10 {word} F6"]))
        return events[-1].path

    short = math.hypot(10, 20 * math.radians(20))
    long = math.hypot(10, 20 * math.radians(340))
    assert path_of("A=DC(10)") == pytest.approx(short, rel=1e-4)
    assert path_of("A=ACP(10)") == pytest.approx(short, rel=1e-4)
    assert path_of("A=ACN(10)") == pytest.approx(long, rel=1e-4)
    assert path_of("A10") == pytest.approx(long, rel=1e-4)  # within the turn: back 340


def test_the_svg_of_the_wrap_shows_the_tool_standing_round_the_part(tmp_path: Path) -> None:
    out = tmp_path / "wrap.svg"
    api.plot_file(ROOT / "machines" / "linuxcnc_xyza.yaml", EXAMPLES / "rotary_wrap.jsonl",
                  out, views=["yz"])
    text = out.read_text(encoding="utf-8")
    assert text.count('class="axis-tip"') == 36
    assert "tool axis</text>" in text
