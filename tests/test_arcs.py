"""Arc linearisation: every chord within the tolerance of the true arc, ending on its end.

The oracle is the arc itself: points sampled densely along the circle (or helix) between
two chord ends must lie within the tolerance of that chord, and each chord end must lie on
the arc.  Posted through a post, the written NC is read back and checked the same way.
"""

from __future__ import annotations

import math
import re
import textwrap
from datetime import UTC, datetime

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from postdsl import api, arcs
from postdsl.cl.model import (
    ArcMove,
    LinearMove,
    ProgramEnd,
    ProgramStart,
    RapidMove,
    ToolChange,
)
from postdsl.errors import CLError, PostError

Point = tuple[float, float, float]


def _on_plane(plane: str, a: float, b: float, n: float) -> Point:
    ia, ib, in_ = arcs.PLANE_AXES[plane]
    point = [0.0, 0.0, 0.0]
    point[ia], point[ib], point[in_] = a, b, n
    return (point[0], point[1], point[2])


def _arc_point(plane: str, centre: Point, radius: float, angle: float, n: float) -> Point:
    ia, ib, _ = arcs.PLANE_AXES[plane]
    return _on_plane(plane, centre[ia] + radius * math.cos(angle),
                     centre[ib] + radius * math.sin(angle), n)


def _distance_to_segment(p: Point, a: Point, b: Point) -> float:
    ab = [b[i] - a[i] for i in range(3)]
    ap = [p[i] - a[i] for i in range(3)]
    length = sum(c * c for c in ab)
    t = 0.0 if length == 0 else max(0.0, min(1.0, sum(ap[i] * ab[i] for i in range(3)) / length))
    return math.dist(p, [a[i] + t * ab[i] for i in range(3)])


def _assert_follows_arc(points: list[Point], start: Point, centre: Point, radius: float,
                        begin: float, turn: float, plane: str, tolerance: float,
                        slack: float = 1e-9) -> None:
    """Each chord is within ``tolerance`` (+ ``slack`` for rounding) of the arc it spans."""
    _, _, n = arcs.PLANE_AXES[plane]
    end_n = points[-1][n]
    count = len(points)
    previous = start
    for index, point in enumerate(points, start=1):
        # the chord spans the arc's angles from (index - 1) / count to index / count
        for sample in range(21):
            fraction = (index - 1 + sample / 20) / count
            on_arc = _arc_point(plane, centre, radius, begin + turn * fraction,
                                start[n] + (end_n - start[n]) * fraction)
            assert _distance_to_segment(on_arc, previous, point) <= tolerance + slack
        previous = point


planes = st.sampled_from(["xy", "zx", "yz"])
coordinates = st.floats(min_value=-500, max_value=500)


@given(plane=planes, cx=coordinates, cy=coordinates, radius=st.floats(0.01, 300),
       begin=st.floats(-math.pi, math.pi), sweep=st.floats(0.001, 2 * math.pi),
       clockwise=st.booleans(), rise=st.floats(-20, 20), tolerance=st.floats(0.0005, 1.0))
@example(plane="xy", cx=0, cy=0, radius=10, begin=0, sweep=2 * math.pi, clockwise=False,
         rise=0, tolerance=0.01)  # a full circle
@example(plane="zx", cx=5, cy=-5, radius=1, begin=1, sweep=4 * math.pi / 3, clockwise=True,
         rise=-3, tolerance=2.5)  # a tolerance wider than the arc: one chord
def test_chords_stay_within_tolerance_and_end_on_the_end(
        plane: str, cx: float, cy: float, radius: float, begin: float, sweep: float,
        clockwise: bool, rise: float, tolerance: float) -> None:
    centre = _on_plane(plane, cx, cy, 0.0)
    turn = -sweep if clockwise else sweep
    start = _arc_point(plane, centre, radius, begin, 7.0)
    end = _arc_point(plane, centre, radius, begin + turn, 7.0 + rise)
    if sweep > 2 * math.pi - 1e-9 or math.dist(start, end) < 1e-7 * radius:
        end = _on_plane(plane, *(start[i] for i in arcs.PLANE_AXES[plane][:2]), 7.0 + rise)
        turn = -2 * math.pi if clockwise else 2 * math.pi
    points = arcs.chords(start, end, centre, clockwise, plane, tolerance)
    assert points[-1] == end  # exactly the CL's end, not a recomputed point
    # the chords span the arc the CL means, however the angle was rounded
    assert abs(arcs.sweep(start, end, centre, clockwise, plane) - abs(turn)) < 1e-6
    _assert_follows_arc(points, start, centre, radius, begin, turn, plane, tolerance,
                        slack=1e-9 * max(1.0, radius))
    # and no more chords than the tolerance needs: one fewer would stray too far
    if len(points) > 1:
        fewer = abs(turn) / (len(points) - 1)
        assert radius * (1 - math.cos(fewer / 2)) > tolerance * (1 - 1e-6)


def test_a_full_circle_turns_once_all_the_way_round() -> None:
    start = (10.0, 0.0, 0.0)
    points = arcs.chords(start, start, (0.0, 0.0, 0.0), False, "xy", 0.01)
    # the sagitta of 2π/n at r = 10 is at most 0.01: n = ceil(π / acos(0.999)) = 71
    assert len(points) == 71
    angles = [math.atan2(y, x) for x, y, _ in points]
    assert angles[0] == pytest.approx(2 * math.pi / 71)
    assert points[-1] == start


def test_a_tolerance_that_asks_for_millions_of_chords_is_refused() -> None:
    with pytest.raises(arcs.TooManyChords, match=r"chords \(at most 10000 are written\)"):
        arcs.chords((1000.0, 0.0, 0.0), (1000.0, 0.0, 0.0), (0.0, 0.0, 0.0), False, "xy",
                    1e-9)


# ------------------------------------------------------------------------------------------
# Through a post: a router without arcs
# ------------------------------------------------------------------------------------------

ROUTER = """
postdsl: 1
machine: {name: Test router, tool_changer: false, travel: {x: [-200, 200], y: [-200, 200],
          z: [-50, 100]}}
output: {block_numbers: {default: false}}
formats:
  c: {decimals: 3, trailing_zeros: false}
  f: {integer: true}
commands:
  program_start: {blocks: []}
  program_end: {blocks: [{items: ["M2"]}]}
  rapid_move:
    blocks:
      - items: ["G0", {param: x, prefix: " X", format: c}, {param: y, prefix: " Y", format: c},
                {param: z, prefix: " Z", format: c}]
  linear_move:
    blocks:
      - items: ["G1", {param: x, prefix: " X", format: c, mode: changed},
                {param: y, prefix: " Y", format: c, mode: changed},
                {param: z, prefix: " Z", format: c, mode: changed},
                {param: feed, prefix: " F", format: f, mode: changed}]
  arc_move: {expand: true, tolerance: 0.01}
"""

NOW = datetime(2024, 3, 5, tzinfo=UTC)
WORD = re.compile(r"([XYZ])(-?[0-9.]+)")


def _post(text: str, *moves: object) -> list[str]:
    compiled = api.load_post_text(text, "router.yaml")
    commands = [ProgramStart(), *moves, ProgramEnd()]
    return [line.text for line in api.post_commands(compiled, commands, now=NOW)]


def _positions(lines: list[str], start: Point) -> list[Point]:
    """The tool positions of the G1 lines, as a control reads them (modal axes kept)."""
    position = list(start)
    points: list[Point] = []
    for line in lines:
        if not line.startswith("G1"):
            continue
        for axis, value in WORD.findall(line):
            position["XYZ".index(axis)] = float(value)
        points.append((position[0], position[1], position[2]))
    return points


@pytest.mark.parametrize(("plane", "start", "centre", "end", "clockwise"), [
    ("xy", (20.0, 0.0, -1.0), (0.0, 0.0, None), (20.0, 0.0, -1.0), False),  # full circle
    ("xy", (20.0, 0.0, 0.0), (0.0, 0.0, None), (0.0, 20.0, -6.0), True),  # helix, 3/4 turn
    ("zx", (10.0, 5.0, 0.0), (0.0, None, 0.0), (0.0, 5.0, 10.0), False),
    ("yz", (5.0, 10.0, 0.0), (None, 0.0, 0.0), (5.0, -10.0, 0.0), True),
])
def test_a_router_post_writes_arcs_as_chords_through_linear_move(
        plane: str, start: Point, centre: tuple[float | None, ...], end: Point,
        clockwise: bool) -> None:
    arc = ArcMove(x=end[0], y=end[1], z=end[2], cx=centre[0], cy=centre[1], cz=centre[2],
                  plane=plane, arc_direction="cw" if clockwise else "ccw", feed=800)
    lines = _post(ROUTER, RapidMove(x=start[0], y=start[1], z=start[2]), arc)
    assert lines[0].startswith("G0 ")
    assert lines[1].endswith(" F800") and all("F" not in line for line in lines[2:])
    assert all(line.startswith("G1") for line in lines[1:-1]) and lines[-1] == "M2"
    points = _positions(lines[1:-1], start)
    assert points[-1] == pytest.approx(end, abs=1e-9)
    full_centre = tuple(c if c is not None else s for c, s in zip(centre, start, strict=True))
    ia, ib, _ = arcs.PLANE_AXES[plane]
    radius = math.hypot(start[ia] - full_centre[ia], start[ib] - full_centre[ib])
    begin = math.atan2(start[ib] - full_centre[ib], start[ia] - full_centre[ia])
    sweep = arcs.sweep(start, end, full_centre, clockwise, plane)
    # written to 0.001 mm: each coordinate may be off by half of it
    _assert_follows_arc(points, start, full_centre, radius, begin,
                        -sweep if clockwise else sweep, plane, 0.01, slack=0.0009)


def test_only_the_first_chord_of_an_arc_after_a_tool_change_is_the_first_move() -> None:
    text = ROUTER.replace('["G1", {param: x', '[{text: "(first) ", if: first_move}, "G1", '
                          '{param: x') + textwrap.indent(textwrap.dedent("""
        tool_change: {blocks: [{items: ["M0"]}], reset: [x, y, z, feed]}
        """), "  ")
    lines = _post(text, RapidMove(x=10, y=0, z=5), ToolChange(tool_number=2),
                  ArcMove(x=-10, y=0, z=5, cx=0, cy=0, feed=300), LinearMove(x=0, y=0))
    assert lines[1] == "M0"
    assert lines[2].startswith("(first) G1 X")
    assert not any("(first)" in line for line in lines[3:])
    # the last chord ends exactly on the arc's end (-10, 0): the next move writes X only
    assert lines[-3] == "G1 X-10 Y0"
    assert lines[-2] == "G1 X0"


@pytest.mark.parametrize(("arc_table", "message"), [
    ("{expand: true}", "router.yaml:22:22: an expanded arc_move needs a tolerance"),
    ("{expand: true, tolerance: 0}", "router.yaml:22:"),
    ("{tolerance: 0.01, blocks: []}", "tolerance applies to arc_move with expand: true only"),
])
def test_misuse_is_located(arc_table: str, message: str) -> None:
    text = ROUTER.replace("{expand: true, tolerance: 0.01}", arc_table)
    with pytest.raises(PostError) as info:
        api.load_post_text(text, "router.yaml")
    assert message in str(info.value)


def test_an_expanded_arc_needs_a_linear_move_table() -> None:
    text = textwrap.dedent(ROUTER).replace("  linear_move:", "  dwell:")
    with pytest.raises(PostError, match="through linear_move, and the post has no table"):
        api.load_post_text(text, "router.yaml")


def test_too_fine_a_tolerance_is_refused_at_the_cl_line() -> None:
    text = ROUTER.replace("tolerance: 0.01", "tolerance: 0.000001")
    with pytest.raises(CLError, match=r"radius 190 to tolerance 1e-06 makes \d+ chords"):
        _post(text, RapidMove(x=190, y=0, z=0),
              ArcMove(x=190, y=0, z=0, cx=0, cy=0, feed=100))
