"""Rotary axes of a machine as geometry: angles for a tool axis, the tool tip in machine terms.

Pure math on the machine's ``rotary_axes`` (no control and no NC word is named here), so
that the post (which writes the angles and the machine's X Y Z) and the control models
of verify (which replay them back into the part's frame) share one definition and a
mistake in either shows as a difference.

Conventions, the ones a machinist reads on the machine:

- an angle is in degrees; ``direction: 1`` is ISO 841's: a positive angle turns the
  *tool* right-handed about the named +axis relative to the part.  A table therefore
  turns the part the other way; ``direction: -1`` is a machine wired the other way;
- axes are listed from the machine's base outward: a table axis carrying another
  (A carrying C on a trunnion) comes first, a head axis carrying another likewise;
- a pivot is the point an axis turns about, in program coordinates with every rotary
  at zero: the part frame and the machine frame coincide there.

The tool tip in the part frame is what the CL gives; for a table the machine frame is
the part turned about the pivots.  A head moves the tool, so the tip depends on the
tool's length: that needs the control's tool-centre-point function (``tcp``), and a
post without it is refused rather than guessed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

Vec = tuple[float, float, float]

#: the axis each rotary turns about, by the ISO name of the axis it moves about
UNIT: Mapping[str, Vec] = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}
Z: Vec = (0.0, 0.0, 1.0)
#: how far a tool axis may miss the reach of the rotaries before it is refused (rad)
AXIS_TOLERANCE = 1e-6
PREFERENCES = ("shortest", "positive", "negative")
WRAPS = ("unwound", "modulo", "rezero")
#: the ways a control turns a modulo axis to an angle 0 <= a < 360 (:func:`modulo_turn`)
WAYS = ("shortest", "positive", "negative", "within", "signed")


class KinematicsError(ValueError):
    """A tool axis or an angle the machine's rotaries cannot give; the caller locates it."""


@dataclass(frozen=True, slots=True)
class RotaryAxis:
    """One rotary axis of the machine (``machine: rotary_axes:`` entry)."""

    name: str  # "a", "b" or "c": the CL field and, upper case, the NC word
    about: str  # "x", "y" or "z"
    kind: str = "table"  # "table" or "head"
    direction: int = 1
    limits: tuple[float, float] | None = None
    continuous: bool = False
    pivot: Vec = (0.0, 0.0, 0.0)


@dataclass(frozen=True, slots=True)
class Kinematics:
    """The machine's rotaries and how the post chooses and writes their angles."""

    axes: tuple[RotaryAxis, ...] = ()
    #: which of several solutions: nearest the last angles, or a positive/negative first axis
    prefer: str = "shortest"
    #: a continuous axis: "unwound" (beyond 360, the nearest turn), "modulo" (0 <= a < 360),
    #: "rezero" (unwound, the control's count set back by whole turns past a full one)
    wrap: str = "unwound"
    #: the control turns the CL's tip into machine coordinates itself (TCP, TRAORI, M128)
    tcp: bool = False
    #: how fast the rotaries index at rapid (deg/min; None: not declared, an index's turn
    #: is then not timed)
    rapid_rate: float | None = None

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(axis.name for axis in self.axes)

    def axis(self, name: str) -> RotaryAxis | None:
        return next((axis for axis in self.axes if axis.name == name), None)


# --- vectors ---------------------------------------------------------------------------------


def _dot(u: Sequence[float], v: Sequence[float]) -> float:
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def _cross(u: Sequence[float], v: Sequence[float]) -> Vec:
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def _sub(u: Sequence[float], v: Sequence[float]) -> Vec:
    return (u[0] - v[0], u[1] - v[1], u[2] - v[2])


def _add(u: Sequence[float], v: Sequence[float]) -> Vec:
    return (u[0] + v[0], u[1] + v[1], u[2] + v[2])


def _scale(u: Sequence[float], s: float) -> Vec:
    return (u[0] * s, u[1] * s, u[2] * s)


def unit(v: Sequence[float]) -> Vec:
    """``v`` of length 1 (a CAM's tool axis may be written to few digits)."""
    length = math.sqrt(_dot(v, v))
    if length < 1e-12:
        raise KinematicsError("the tool axis is a zero vector")
    return (v[0] / length, v[1] / length, v[2] / length)


def rotate(v: Sequence[float], about: Sequence[float], degrees: float) -> Vec:
    """``v`` turned right-handed by ``degrees`` about the unit vector ``about`` (Rodrigues)."""
    t = math.radians(degrees)
    c, s = math.cos(t), math.sin(t)
    k = about
    kv = _cross(k, v)
    kd = _dot(k, v) * (1 - c)
    return (v[0] * c + kv[0] * s + k[0] * kd,
            v[1] * c + kv[1] * s + k[1] * kd,
            v[2] * c + kv[2] * s + k[2] * kd)


# --- forward ---------------------------------------------------------------------------------


def _turn(axis: RotaryAxis, angles: Mapping[str, float]) -> float:
    """The right-handed turn of the tool relative to the part this axis makes."""
    return axis.direction * angles.get(axis.name, 0.0)


def tool_axis(kin: Kinematics, angles: Mapping[str, float]) -> Vec:
    """The tool axis in the part frame at these angles."""
    v = Z
    for axis in reversed([a for a in kin.axes if a.kind == "head"]):
        v = rotate(v, UNIT[axis.about], _turn(axis, angles))
    for axis in [a for a in kin.axes if a.kind == "table"]:
        v = rotate(v, UNIT[axis.about], _turn(axis, angles))
    return v


def to_machine(kin: Kinematics, tip: Sequence[float], angles: Mapping[str, float]) -> Vec:
    """The machine X Y Z that puts the tool tip on ``tip`` (part frame) at these angles."""
    if kin.tcp:
        return (tip[0], tip[1], tip[2])
    _need_no_head(kin, angles)
    p: Vec = (tip[0], tip[1], tip[2])
    for axis in reversed([a for a in kin.axes if a.kind == "table"]):
        p = _add(rotate(_sub(p, axis.pivot), UNIT[axis.about], -_turn(axis, angles)), axis.pivot)
    return p


def to_part(kin: Kinematics, machine: Sequence[float], angles: Mapping[str, float]) -> Vec:
    """The tool tip in the part frame where the machine stands at ``machine`` and ``angles``."""
    if kin.tcp:
        return (machine[0], machine[1], machine[2])
    _need_no_head(kin, angles)
    p: Vec = (machine[0], machine[1], machine[2])
    for axis in [a for a in kin.axes if a.kind == "table"]:
        p = _add(rotate(_sub(p, axis.pivot), UNIT[axis.about], _turn(axis, angles)), axis.pivot)
    return p


def _need_no_head(kin: Kinematics, angles: Mapping[str, float]) -> None:
    for axis in kin.axes:
        if axis.kind == "head" and abs(angles.get(axis.name, 0.0) % 360.0) > 1e-9 \
                and abs(angles.get(axis.name, 0.0) % 360.0 - 360.0) > 1e-9:
            raise KinematicsError(
                f"head axis {axis.name.upper()} turned without tool-centre-point control "
                f"(machine: tcp): the tip would depend on the tool's length")


def is_identity(kin: Kinematics, angles: Mapping[str, float]) -> bool:
    """The rotaries leave the part frame where the machine frame is (every turn a full one)."""
    return all(abs(math.remainder(angles.get(a.name, 0.0), 360.0)) < 1e-9 for a in kin.axes)


def tip_path_length(kin: Kinematics, start: Sequence[float], start_angles: Mapping[str, float],
                    end: Sequence[float], end_angles: Mapping[str, float]) -> float:
    """Length of the path the tool tip cuts in the part, for a move the control interpolates
    linearly in X Y Z and the angles: the rotary's arc counts, not the straight line alone.

    Summed over chords of at most a degree of any axis, and again over half as long ones,
    extrapolated (Richardson): the chords' shortfall, 1e-5 of the length, falls to 1e-10.
    """
    turn = max((abs(end_angles.get(n, 0.0) - start_angles.get(n, 0.0)) for n in kin.names),
               default=0.0)
    steps = max(1, math.ceil(turn))
    coarse = _chords(kin, start, start_angles, end, end_angles, steps)
    fine = _chords(kin, start, start_angles, end, end_angles, 2 * steps)
    return (4 * fine - coarse) / 3


def _chords(kin: Kinematics, start: Sequence[float], start_angles: Mapping[str, float],
            end: Sequence[float], end_angles: Mapping[str, float], steps: int) -> float:
    length = 0.0
    before = to_part(kin, start, start_angles)
    for i in range(1, steps + 1):
        t = i / steps
        m = tuple(s + (e - s) * t for s, e in zip(start, end, strict=True))
        angles = {n: start_angles.get(n, 0.0) + (end_angles.get(n, 0.0)
                                                 - start_angles.get(n, 0.0)) * t
                  for n in kin.names}
        here = to_part(kin, m, angles)
        length += math.dist(before, here)
        before = here
    return length


# --- inverse ---------------------------------------------------------------------------------


def _sub1(w: Vec, p: Vec, q: Vec) -> float | None:
    """The angle (deg) turning ``p`` onto ``q`` about ``w``; None: any angle does."""
    pp = _sub(p, _scale(w, _dot(w, p)))
    qq = _sub(q, _scale(w, _dot(w, q)))
    if _dot(pp, pp) < 1e-18:
        return None
    return math.degrees(math.atan2(_dot(w, _cross(pp, qq)), _dot(pp, qq)))


def _chain(kin: Kinematics) -> list[RotaryAxis]:
    """The axes in the order their rotations multiply onto the tool's Z (tool_axis)."""
    tables = [a for a in kin.axes if a.kind == "table"]
    heads = [a for a in kin.axes if a.kind == "head"]
    return list(reversed(tables)) + heads


def _turn_solutions(kin: Kinematics, v: Vec) -> list[list[float | None]]:
    """Right-handed turns (deg) of the chain's axes that bring Z onto ``v``; None: free."""
    chain = [UNIT[a.about] for a in _chain(kin)]
    if len(chain) == 0:
        return [[]] if math.dist(v, Z) < AXIS_TOLERANCE else []
    if len(chain) == 1:
        w = chain[0]
        if abs(_dot(w, v) - _dot(w, Z)) > AXIS_TOLERANCE:
            return []
        return [[_sub1(w, Z, v)]]
    if len(chain) > 2:
        raise KinematicsError("more than two rotary axes: the tool axis has no unique angles")
    w1, w2 = chain
    # R(w1, t1) R(w2, t2) Z = v (Paden-Kahan subproblem 2): c = R(w2, t2) Z = R(w1, -t1) v
    d = _dot(w1, w2)
    across = _cross(w1, w2)
    if _dot(across, across) < 1e-18:
        raise KinematicsError("two parallel rotary axes: the tool axis has no unique angles")
    denominator = d * d - 1
    alpha = (d * _dot(w2, Z) - _dot(w1, v)) / denominator
    beta = (d * _dot(w1, v) - _dot(w2, Z)) / denominator
    gamma2 = (1 - alpha * alpha - beta * beta - 2 * alpha * beta * d) / _dot(across, across)
    if gamma2 < -AXIS_TOLERANCE:
        return []
    gammas = [0.0] if gamma2 <= 1e-12 else [math.sqrt(gamma2), -math.sqrt(gamma2)]
    found: list[list[float | None]] = []
    for gamma in gammas:
        c = _add(_add(_scale(w1, alpha), _scale(w2, beta)), _scale(across, gamma))
        found.append([_sub1(w1, c, v), _sub1(w2, Z, c)])
    return found


def _near(angle: float, previous: float) -> float:
    """``angle`` plus whole turns, nearest ``previous``."""
    return previous + math.remainder(angle - previous, 360.0)


def _candidates(axis: RotaryAxis, angle: float, previous: float) -> list[float]:
    """The programmable angles for one axis reaching ``angle`` (mod 360)."""
    if axis.continuous:
        return [_near(angle, previous)]
    low, high = axis.limits if axis.limits is not None else (-360.0, 360.0)
    first = angle - 360.0 * math.floor((angle - low) / 360.0)
    return [a for a in (first, first + 360.0) if low - 1e-9 <= a <= high + 1e-9]


def solve(kin: Kinematics, vector: Sequence[float],
          previous: Mapping[str, float]) -> dict[str, float]:
    """The angles (programmed, deg) that set the tool axis to ``vector`` (part frame).

    Among the solutions within the limits: the one the post prefers -- ``shortest``: the
    least turning from ``previous``; ``positive``/``negative``: the first axis's angle of
    that sign, then the least turning.  An axis the vector leaves free keeps its angle.
    """
    v = unit(vector)
    chain = _chain(kin)
    options: list[dict[str, float]] = []
    for turns in _turn_solutions(kin, v):
        per_axis: list[list[float]] = []
        for axis, turn in zip(chain, turns, strict=True):
            last = previous.get(axis.name, 0.0)
            angle = last if turn is None else axis.direction * turn
            per_axis.append(_candidates(axis, angle, last))
        combos: list[dict[str, float]] = [{}]
        for axis, choices in zip(chain, per_axis, strict=True):
            combos = [dict(c, **{axis.name: a}) for c in combos for a in choices]
        options.extend(combos)
    if not options:
        raise KinematicsError(
            f"tool axis ({_num(v[0])}, {_num(v[1])}, {_num(v[2])}) has no rotary solution "
            f"on this machine ({_describe(kin)})")

    def travel(angles: dict[str, float]) -> float:
        return sum(abs(angles[n] - previous.get(n, 0.0)) for n in angles)

    first = kin.axes[0].name if kin.axes else ""

    def rank(angles: dict[str, float]) -> tuple[float, float]:
        sign = {"positive": 1.0, "negative": -1.0}.get(kin.prefer, 0.0)
        wrong_sign = 1.0 if sign and angles.get(first, 0.0) * sign < -1e-9 else 0.0
        return (wrong_sign, travel(angles))

    best: dict[str, float] = min(options, key=rank)
    return dict(best)


def unwind(axis: RotaryAxis, angle: float, previous: float, wrap: str) -> float:
    """The angle a continuous axis is written with: ``unwound`` -- the turn nearest the last
    one, beyond 360 as a control without roll-over counts; ``modulo`` -- 0 <= angle < 360,
    the control choosing the way round."""
    if not axis.continuous:
        return angle
    if wrap == "modulo":
        return angle % 360.0
    return _near(angle, previous)


def modulo_turn(current: float, target: float, way: str) -> float:
    """Where a modulo axis standing at ``current`` (deg, counted on) ends when told to go to
    ``target`` (its place in the turn) the ``way`` the control's word or setting says:
    ``shortest`` (a half turn goes positive), ``positive``/``negative``, ``within`` (the
    turn is not left: 350 to 10 turns back 340), ``signed`` (the sign of ``target`` is the
    direction, its size the place).  Which control means which is a fact of the control,
    written with its manual in the control models (``modulo_way``).

    Shared by the post (which angle and word to write) and the control models (where the
    table ends): a word written for the wrong way is a difference in the part frame.
    """
    if way == "signed":
        way = "negative" if math.copysign(1.0, target) < 0 else "positive"
        target = abs(target)
    place = current % 360.0
    delta = (target - place) % 360.0
    if way == "shortest":
        if delta > 180.0 + 1e-9:
            delta -= 360.0
    elif way == "negative":
        if delta > 1e-9:
            delta -= 360.0
    elif way == "within":
        delta = target - place
    elif way != "positive":
        raise KinematicsError(f"no such way round: {way!r}")
    return current + delta


def rezero_by(written: float) -> float:
    """The whole turns (deg) a ``rezero`` post takes off a continuous axis's count before a
    move would end a full turn or more from zero: the count stays within one turn, as a
    control with a bounded rotary register needs (FreeCAD's ``G92 A0`` each turn)."""
    return 360.0 * math.trunc(written / 360.0) if abs(written) >= 360.0 - 1e-9 else 0.0


def _num(value: float) -> str:
    return f"{value:.6g}"


def _describe(kin: Kinematics) -> str:
    if not kin.axes:
        return "no rotary axis"
    return ", ".join(f"{a.name.upper()} about {a.about.upper()} ({a.kind})" for a in kin.axes)


def kinematics_of(axes: Sequence[Mapping[str, object]],
                  rotary: Mapping[str, object] | None) -> Kinematics:
    """The machine's ``rotary_axes`` and ``rotary`` as the schema checked them, typed."""
    options = rotary or {}

    def number(value: object, default: float) -> float:
        return float(value) if isinstance(value, (int, float)) else default

    made = []
    for spec in axes:
        limits = spec.get("limits")
        pivot = spec.get("pivot")
        made.append(RotaryAxis(
            name=str(spec["name"]), about=str(spec["about"]),
            kind=str(spec.get("kind", "table")),
            direction=int(number(spec.get("direction"), 1)),
            limits=(number(limits[0], -360.0), number(limits[1], 360.0))
            if isinstance(limits, Sequence) else None,
            continuous=bool(spec.get("continuous", False)),
            pivot=(number(pivot[0], 0.0), number(pivot[1], 0.0), number(pivot[2], 0.0))
            if isinstance(pivot, Sequence) else (0.0, 0.0, 0.0),
        ))
    kin = Kinematics(tuple(made), prefer=str(options.get("prefer", "shortest")),
                     wrap=str(options.get("wrap", "unwound")),
                     tcp=bool(options.get("tcp", False)),
                     rapid_rate=number(options.get("rapid_rate"), 0.0) or None)
    if kin.wrap == "rezero" and sum(axis.continuous for axis in made) != 1:
        raise ValueError("rotary: wrap: rezero needs exactly one continuous axis (the one "
                         "whose count the post sets back)")
    names = [axis.name for axis in made]
    if len(set(names)) < len(names):
        raise ValueError(f"an axis named twice ({', '.join(n.upper() for n in names)})")
    if len(made) == 2 and made[0].about == made[1].about:
        raise ValueError("two rotary axes about the same axis: a tool axis has no unique angles")
    for axis in made:
        if axis.limits is not None and axis.limits[0] >= axis.limits[1]:
            raise ValueError(f"{axis.name.upper()}: limits {axis.limits[0]:g} to "
                             f"{axis.limits[1]:g} are no range")
        if axis.kind == "head" and not kin.tcp:
            raise ValueError(f"{axis.name.upper()} is a head axis: the tip then depends on the "
                             f"tool's length, which needs the control's tool-centre-point "
                             f"function (machine: rotary: {{tcp: true}})")
    return kin
