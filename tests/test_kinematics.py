"""The rotary geometry the posts and the control models share (postdsl.kinematics)."""

from __future__ import annotations

import json
import math

import pytest

from postdsl.kinematics import (
    Kinematics,
    KinematicsError,
    RotaryAxis,
    modulo_turn,
    rezero_by,
    solve,
    tip_path_length,
    to_machine,
    to_part,
    tool_axis,
    unwind,
)

A_TABLE = Kinematics((RotaryAxis("a", "x", continuous=True),))
TRUNNION = Kinematics((RotaryAxis("a", "x", limits=(-30.0, 120.0)),
                       RotaryAxis("c", "z", continuous=True)))
HEAD_TABLE = Kinematics((RotaryAxis("b", "y", kind="head", limits=(-90.0, 90.0)),
                         RotaryAxis("c", "z", continuous=True)))


def close(u, v, tol=1e-9):
    return all(abs(a - b) < tol for a, b in zip(u, v, strict=True))


def test_positive_a_turns_the_tool_right_handed_about_x_relative_to_the_part() -> None:
    # ISO 841: +A seen from the part: the tool leans towards -Y
    assert close(tool_axis(A_TABLE, {"a": 90.0}), (0.0, -1.0, 0.0))
    # the part turns the other way under the tool: a point on +Y comes to the top
    assert close(to_machine(A_TABLE, (5.0, -20.0, 0.0), {"a": 90.0}), (5.0, 0.0, 20.0))


def test_direction_minus_one_turns_the_other_way() -> None:
    reverse = Kinematics((RotaryAxis("a", "x", direction=-1, continuous=True),))
    assert close(tool_axis(reverse, {"a": 90.0}), (0.0, 1.0, 0.0))


def test_pivot_is_the_point_the_table_turns_about() -> None:
    kin = Kinematics((RotaryAxis("a", "x", pivot=(0.0, 0.0, -50.0)),))
    assert close(to_machine(kin, (0.0, 0.0, -50.0), {"a": 37.0}), (0.0, 0.0, -50.0))
    assert close(to_machine(kin, (0.0, 0.0, 0.0), {"a": 90.0}), (0.0, 50.0, -50.0))


@pytest.mark.parametrize("kin", [A_TABLE, TRUNNION])
def test_to_part_undoes_to_machine(kin: Kinematics) -> None:
    angles = {"a": 33.0, "c": -71.0}
    tip = (12.5, -3.25, 40.0)
    assert close(to_part(kin, to_machine(kin, tip, angles), angles), tip)


def test_a_table_solves_the_tool_axis_in_the_yz_plane() -> None:
    angles = solve(A_TABLE, (0.0, -math.sin(math.radians(40)), math.cos(math.radians(40))), {})
    assert angles == pytest.approx({"a": 40.0})


def test_a_table_refuses_an_axis_leaning_along_x() -> None:
    with pytest.raises(KinematicsError, match="no rotary solution"):
        solve(A_TABLE, (0.5, 0.0, 0.866), {})


def test_continuous_axis_takes_the_turn_nearest_the_last_angle() -> None:
    assert solve(A_TABLE, (0.0, 0.0, 1.0), {"a": 350.0}) == pytest.approx({"a": 360.0})
    assert unwind(A_TABLE.axes[0], 10.0, 715.0, "unwound") == pytest.approx(730.0)
    assert unwind(A_TABLE.axes[0], 730.0, 715.0, "modulo") == pytest.approx(10.0)


@pytest.mark.parametrize("kin", [TRUNNION, HEAD_TABLE])
@pytest.mark.parametrize("vector", [(0.3, -0.4, 0.866), (-0.5, 0.5, 0.7071), (0.0, -1.0, 0.0)])
def test_five_axis_solutions_give_the_tool_axis_back(kin: Kinematics, vector) -> None:
    norm = math.sqrt(sum(c * c for c in vector))
    v = tuple(c / norm for c in vector)
    angles = solve(kin, v, {})
    assert close(tool_axis(kin, angles), v, 1e-9)
    for axis in kin.axes:
        if axis.limits:
            assert axis.limits[0] <= angles[axis.name] <= axis.limits[1]


def test_limits_choose_the_other_solution_and_prefer_chooses_the_sign() -> None:
    v = (0.0, 0.5, math.sqrt(0.75))  # A = -30 with C = 0, or A = +30 with C = 180
    assert solve(TRUNNION, v, {}) == pytest.approx({"a": -30.0, "c": 0.0})
    positive = Kinematics(TRUNNION.axes, prefer="positive")
    assert solve(positive, v, {}) == pytest.approx({"a": 30.0, "c": 180.0})
    narrow = Kinematics((RotaryAxis("a", "x", limits=(0.0, 120.0)),
                         RotaryAxis("c", "z", continuous=True)))
    assert solve(narrow, v, {}) == pytest.approx({"a": 30.0, "c": 180.0})


def test_tool_axis_along_c_keeps_c_where_it_was() -> None:
    assert solve(TRUNNION, (0.0, 0.0, 1.0), {"c": 45.0}) == pytest.approx({"a": 0.0, "c": 45.0})


def test_path_length_counts_the_rotary_arc() -> None:
    # 90 degrees of A at radius 20 and 10 mm of X: a helix of length sqrt(10^2 + (10 pi)^2)
    length = tip_path_length(A_TABLE, (0.0, 0.0, 20.0), {"a": 0.0}, (10.0, 0.0, 20.0),
                             {"a": 90.0})
    assert length == pytest.approx(math.hypot(10.0, 10.0 * math.pi), rel=1e-4)


def test_a_head_without_tcp_is_refused() -> None:
    with pytest.raises(KinematicsError, match="tool-centre-point"):
        to_machine(HEAD_TABLE, (0.0, 0.0, 0.0), {"b": 30.0})


@pytest.mark.parametrize(("axes", "rotary", "message"), [
    ([{"name": "a", "about": "x"}, {"name": "a", "about": "z"}], None, "named twice"),
    ([{"name": "a", "about": "x"}, {"name": "b", "about": "x"}], None, "about the same axis"),
    ([{"name": "a", "about": "x", "limits": [10, -10]}], None, "no range"),
    ([{"name": "b", "about": "y", "kind": "head"}], None, "tool-centre-point"),
])
def test_a_machine_the_solver_cannot_serve_is_refused_at_its_key(axes, rotary, message) -> None:
    from postdsl import api
    from postdsl.errors import PostError

    text = ("postdsl: 1\nmachine:\n  name: M\n  rotary_axes: " + json.dumps(axes)
            + "\ncommands:\n  program_end: {blocks: [{items: [M30]}]}\n")
    with pytest.raises(PostError) as refused:
        api.load_post_text(text, "m.yaml")
    assert message in str(refused.value) and refused.value.location.line == 4


@pytest.mark.parametrize(("current", "target", "way", "end"), [
    (350.0, 10.0, "shortest", 370.0),     # over zero, +20
    (10.0, 350.0, "shortest", -10.0),     # back over zero, -20
    (0.0, 180.0, "shortest", 180.0),      # a half turn goes positive (Sinumerik DC)
    (10.0, 350.0, "positive", 350.0),     # ACP: +340
    (350.0, 10.0, "negative", 10.0),      # ACN: -340
    (350.0, 10.0, "within", 10.0),        # a plain angle stays within the turn: -340
    (730.0, 20.0, "shortest", 740.0),     # counted on beyond a turn, its place is 10
])
def test_a_modulo_axis_ends_where_its_word_sends_it(current: float, target: float, way: str,
                                                    end: float) -> None:
    assert modulo_turn(current, target, way) == pytest.approx(end)


def test_rezero_takes_whole_turns_off_a_count_a_turn_or_more_from_zero() -> None:
    assert rezero_by(359.999) == 0.0
    assert rezero_by(360.0) == 360.0
    assert rezero_by(725.0) == 720.0
    assert rezero_by(-370.0) == -360.0


def test_a_signed_angle_says_the_way_round_and_its_size_the_place() -> None:
    assert modulo_turn(350.0, 10.0, "signed") == pytest.approx(370.0)
    assert modulo_turn(10.0, -350.0, "signed") == pytest.approx(-10.0)
    assert modulo_turn(10.0, 10.0, "signed") == pytest.approx(10.0)
