"""The toolpath API: a posted program replayed through its control model into drawable segments."""

from __future__ import annotations

import itertools
import json
import math
from pathlib import Path

import pytest

from postdsl import api
from postdsl.check.controls.events import ArcMove, Origin, Tooling
from postdsl.check.toolpath import flatten_arc, motion_key
from tests.conftest import EXAMPLES, THESIS_TIME

SQUARE = [
    {"cmd": "program_start", "program_name": "SQUARE"},
    {"cmd": "tool_change", "tool_number": 1, "tool_type": "end_mill", "tool_diameter": 6},
    {"cmd": "spindle_on", "spindle_speed": 3000, "spindle": "cw"},
    {"cmd": "rapid_move", "x": 0, "y": 0, "z": 20},
    {"cmd": "rapid_move", "z": 2},
    {"cmd": "linear_move", "z": -1, "feed": 100},
    {"cmd": "linear_move", "x": 10, "feed": 300},
    {"cmd": "linear_move", "y": 10},
    {"cmd": "linear_move", "x": 0},
    {"cmd": "linear_move", "y": 0},
    {"cmd": "rapid_move", "z": 20},
    {"cmd": "program_end"},
]


def write_square(folder: Path) -> Path:
    path = folder / "square.jsonl"
    path.write_text("".join(json.dumps(record) + "\n" for record in SQUARE))
    return path


@pytest.mark.parametrize("machine", ["vmc500", "emco", "feeler"])
def test_a_square_replays_as_its_four_sides(tmp_path: Path, machine: str) -> None:
    post = api.load_post(machine)
    lines, path = api.toolpath(post, api.read_cl(write_square(tmp_path)), cl_file="square",
                               now=THESIS_TIME)
    assert path.stopped is None
    feeds = [s for s in path.segments if s.kind == "feed"]
    assert [(s.points[0][:2], s.points[-1][:2]) for s in feeds] == [
        ((0, 0), (0, 0)), ((0, 0), (10, 0)), ((10, 0), (10, 10)), ((10, 10), (0, 10)),
        ((0, 10), (0, 0))]
    assert all(s.points[-1][2] == -1 for s in feeds)
    # each move names the NC line the control ran it for and the CL command behind it
    for segment in feeds:
        assert segment.command == "linear_move" and segment.table == "linear_move"
        assert SQUARE[segment.cl_line - 1]["cmd"] == "linear_move"
        assert lines[segment.nc_line - 1].cl_line == segment.cl_line
    rapids = [s for s in path.segments if s.kind == "rapid"]
    assert rapids[-1].points[-1] == (0, 0, 20)
    assert path.bounds() == ((0, 0, -1), (10, 10, 20))


def test_holes_plunge_to_the_cl_bottom_and_back() -> None:
    _, path = api.toolpath_file("vmc500", EXAMPLES / "vmc500_cycles.jsonl")
    holes = [s for s in path.segments if s.kind == "hole"]
    assert len(holes) == 5
    # the thesis holes: tops at Z70, 5 mm clearance; the first is 50 deep
    first = holes[0]
    assert first.points == ((40, 20, 75), (40, 20, 20), (40, 20, 75))
    assert first.command == "single_peck"
    assert {s.points[0][2] for s in holes} == {75}


def test_arcs_are_flattened_within_the_tolerance() -> None:
    _, path = api.toolpath_file("feeler", EXAMPLES / "feeler_milling.apt")
    arcs = [s for s in path.segments if len(s.points) > 2]
    assert arcs, "the APT milling program has arcs"
    for segment in arcs:
        assert segment.kind == "feed" and segment.command == "arc_move"


def quarter(clockwise: bool) -> ArcMove:
    start, end = ((10.0, 0.0, 0.0), (0.0, 10.0, -2.0)) if not clockwise else \
        ((0.0, 10.0, 0.0), (10.0, 0.0, -2.0))
    return ArcMove(Origin(1), start, end, (0.0, 0.0, 0.0), clockwise, "xy", math.pi / 2, 10.0,
                   100.0, Tooling())


@pytest.mark.parametrize("clockwise", [False, True])
def test_flatten_arc_stays_on_the_circle(clockwise: bool) -> None:
    arc = quarter(clockwise)
    points = flatten_arc(arc, tolerance=0.01)
    assert points[0] == arc.start and points[-1] == arc.end
    assert 10 < len(points) < 40  # 0.01 mm on a 10 mm radius: about 18 chords per quarter
    for a, b in itertools.pairwise(points):
        assert math.hypot(a[0], a[1]) == pytest.approx(10)
        middle = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
        assert 10 - math.hypot(*middle) <= 0.01 + 1e-9
        assert a[0] >= 0 and a[1] >= 0  # the short way, in the first quadrant
    # a helix descends evenly
    assert [p[2] for p in points] == sorted((p[2] for p in points), reverse=True)


def test_a_line_the_control_refuses_ends_the_path_and_says_which() -> None:
    post = api.load_post("vmc500")
    lines = [api.NCLine(text, "linear_move", "linear_move", n, 0)
             for n, text in enumerate(["G0 X0 Y0 Z10", "G1 X5 F100", "G1 X6 Q&", "G1 X7"], 1)]
    path = api.toolpath_of_lines(post, lines)
    assert [s.points for s in path.segments] == [((0, 0, 10), (5, 0, 10))]
    assert path.stopped is not None and "NC line 3" in path.stopped


def test_a_post_without_a_control_model_is_refused(tmp_path: Path) -> None:
    text = Path(api.load_post("vmc500").file).read_text()
    for key in ("  control: acramatic-2100 ", "  resolution: 0.001 "):
        assert key in text
        text = text.replace(key, "  # ")
    post = api.load_post_text(text)
    with pytest.raises(api.PostError, match="no machine/control"):
        api.toolpath(post, api.read_cl(write_square(tmp_path)))


def test_motion_key_ignores_line_numbers_but_not_moves(tmp_path: Path) -> None:
    post = api.load_post("vmc500")
    commands = api.read_cl(write_square(tmp_path))
    _lines, one = api.toolpath(post, commands, now=THESIS_TIME)
    text = Path(post.file).read_text()
    assert "    start: 10\n    increment: 10\n" in text
    renumbered = api.load_post_text(text.replace("    start: 10\n    increment: 10\n",
                                                 "    start: 5\n    increment: 5\n"))
    lines_two, two = api.toolpath(renumbered, commands, now=THESIS_TIME)
    assert any(line.text.startswith("N5 ") for line in lines_two)
    assert api.same_motion(post, one, two)
    moved = json.loads(json.dumps(SQUARE))
    moved[7]["y"] = 11
    (tmp_path / "moved.jsonl").write_text("".join(json.dumps(r) + "\n" for r in moved))
    _, three = api.toolpath(post, api.read_cl(tmp_path / "moved.jsonl"), now=THESIS_TIME)
    assert not api.same_motion(post, one, three)
    assert motion_key(one.segments, 0.001) != motion_key(three.segments, 0.001)


def test_cuts_in_a_plane_are_drawn_in_the_part_frame_with_the_axis_at_each_plane_entry() -> None:
    """A tilted plane's cut is turned into the part frame, and its tool axis drawn at the
    first cut each time the plane is entered (again after the part frame); a plane that
    only shifts the zero (a datum shift) moves the points and draws no axis."""
    from postdsl import frames
    from postdsl.check.controls.events import FeedMove, Rapid
    from postdsl.check.toolpath import segments_of

    tilt = frames.frame_of((100, 0, 0), (0, 0, -1), (1, 0, 0))  # the tool along +X
    shift = frames.Frame((5, 5, 5), frames.IDENTITY)

    def cut(line: int, frame: frames.Frame | None) -> FeedMove:
        return FeedMove(Origin(line), (0.0, 0.0, 0.0), (10.0, 0.0, -1.0), 100.0,
                        Tooling(frame=frame))

    current: list[frames.Frame | None] = [tilt]
    events = [Rapid(Origin(1), (0.0, 0.0, 10.0), (0.0, 0.0, 0.0)), cut(2, tilt), cut(3, tilt),
              cut(4, None), cut(5, tilt), cut(6, shift)]
    drawn = list(segments_of(events, lambda line: None, frame_now=lambda: current[0]))
    assert [(s.kind, s.nc_line) for s in drawn] == [
        ("rapid", 1), ("axis", 2), ("feed", 2), ("feed", 3), ("feed", 4), ("axis", 5),
        ("feed", 5), ("feed", 6)]
    assert drawn[0].points == ((110.0, 0.0, 0.0), (100.0, 0.0, 0.0))  # in the plane in force
    assert drawn[2].points == ((100.0, 0.0, 0.0), (99.0, 0.0, -10.0))
    assert drawn[1].points == ((100.0, 0.0, 0.0), (115.0, 0.0, 0.0))  # 15 mm up +X
    assert drawn[4].points == ((0.0, 0.0, 0.0), (10.0, 0.0, -1.0))
    assert drawn[7].points == ((5.0, 5.0, 5.0), (15.0, 5.0, 4.0))
