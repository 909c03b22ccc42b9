"""Tilted working planes (3+2): a frame in the part, and each control's angles for it.

A work plane is an origin and a rotation in the part frame: the rotation's columns are
the plane's X, Y and Z axes (Z the tool axis) seen from the part.  A point ``p`` given in
the plane is ``origin + R p`` in the part.  Moves inside a plane are three-axis moves in
its frame, as every control below runs them once the plane is declared.

Controls state the rotation by three angles, each in a convention of its own.  The
conventions are plain geometry, named by it; which control reads which is a fact of the
control, stated in its model (``postdsl/check/controls/``) and chosen by a post with
``machine.tilted_plane``.  Each has its forward rotation (what a control does with the
angles: the control models use it) and its inverse (the angles a post writes for a
plane: the engine uses it):

- ``euler_zxz``: Euler angles Z-X'-Z'' -- turn about Z by the first, then about the new
  X by the second, then about the newest Z by the third; R = Rz(1) Rx(2) Rz(3);
- ``euler_zyz``: Euler angles Z-Y'-Z''; R = Rz(1) Ry(2) Rz(3);
- ``fixed_xyz``: about the fixed X by the first, then the fixed Y, then the fixed Z;
  R = Rz(3) Ry(2) Rx(1);
- ``rotated_xyz``: axis by axis, each turn about an axis of the frame the previous one
  left: X, then Y', then Z''; R = Rx(1) Ry(2) Rz(3).

The inverses return angles in degrees; where the plane is parallel to the part's XY
(the middle angle 0 or 180°, or ±90° for the X-Y-Z orders), the rotation about Z is
put whole into the first angle and the last is 0, as the controls' manuals show it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

Matrix = tuple[tuple[float, float, float], tuple[float, float, float],
               tuple[float, float, float]]
Vector = tuple[float, float, float]

IDENTITY: Matrix = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
_SINGULAR = 1e-9


@dataclass(frozen=True, slots=True)
class Frame:
    """A work plane in the part: its origin and its rotation (columns: X, Y, Z axes)."""

    origin: Vector
    rotation: Matrix

    def to_part(self, point: Sequence[float]) -> Vector:
        """A point given in the plane, in the part frame."""
        r, o = self.rotation, self.origin
        x, y, z = point
        return (o[0] + r[0][0] * x + r[0][1] * y + r[0][2] * z,
                o[1] + r[1][0] * x + r[1][1] * y + r[1][2] * z,
                o[2] + r[2][0] * x + r[2][1] * y + r[2][2] * z)

    @property
    def tool_axis(self) -> Vector:
        r = self.rotation
        return (r[0][2], r[1][2], r[2][2])

    @property
    def x_axis(self) -> Vector:
        r = self.rotation
        return (r[0][0], r[1][0], r[2][0])


def rx(deg: float) -> Matrix:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return ((1.0, 0.0, 0.0), (0.0, c, -s), (0.0, s, c))


def ry(deg: float) -> Matrix:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return ((c, 0.0, s), (0.0, 1.0, 0.0), (-s, 0.0, c))


def rz(deg: float) -> Matrix:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return ((c, -s, 0.0), (s, c, 0.0), (0.0, 0.0, 1.0))


def product(*matrices: Matrix) -> Matrix:
    """The matrices multiplied left to right (the rightmost turns first, in fixed axes)."""
    out = IDENTITY
    for m in matrices:
        rows = [tuple(float(sum(out[i][k] * m[k][j] for k in range(3))) for j in range(3))
                for i in range(3)]
        out = ((rows[0][0], rows[0][1], rows[0][2]), (rows[1][0], rows[1][1], rows[1][2]),
               (rows[2][0], rows[2][1], rows[2][2]))
    return out


def _deg(value: float) -> float:
    d = math.degrees(value)
    return 0.0 if abs(d) < 1e-9 else d


def _euler_zxz(r: Matrix) -> Vector:
    sj = math.hypot(r[0][2], r[1][2])
    j = math.atan2(sj, r[2][2])
    if sj < _SINGULAR:  # plane parallel to XY: one turn about Z
        return _deg(math.atan2(r[1][0], r[0][0])), _deg(j), 0.0
    return _deg(math.atan2(r[0][2], -r[1][2])), _deg(j), _deg(math.atan2(r[2][0], r[2][1]))


def _euler_zyz(r: Matrix) -> Vector:
    sb = math.hypot(r[0][2], r[1][2])
    b = math.atan2(sb, r[2][2])
    if sb < _SINGULAR:
        return _deg(math.atan2(-r[0][1], r[1][1])), _deg(b), 0.0
    return _deg(math.atan2(r[1][2], r[0][2])), _deg(b), _deg(math.atan2(r[2][1], -r[2][0]))


def _fixed_xyz(r: Matrix) -> Vector:
    cb = math.hypot(r[0][0], r[1][0])
    b = math.atan2(-r[2][0], cb)
    if cb < _SINGULAR:
        return _deg(math.atan2(-r[1][2], r[1][1])), _deg(b), 0.0
    return _deg(math.atan2(r[2][1], r[2][2])), _deg(b), _deg(math.atan2(r[1][0], r[0][0]))


def _axis_by_axis_xyz(r: Matrix) -> Vector:
    cb = math.hypot(r[0][0], r[0][1])
    b = math.atan2(r[0][2], cb)
    if cb < _SINGULAR:
        return _deg(math.atan2(r[2][1], r[1][1])), _deg(b), 0.0
    return _deg(math.atan2(-r[1][2], r[2][2])), _deg(b), _deg(math.atan2(-r[0][1], r[0][0]))


@dataclass(frozen=True, slots=True)
class Convention:
    """How a control states a rotation by three angles: the rotation of three angles, and
    the three angles of a rotation."""

    name: str
    rotation: Callable[[float, float, float], Matrix]
    angles: Callable[[Matrix], Vector]
    words: str


CONVENTIONS: dict[str, Convention] = {
    "euler_zxz": Convention(
        "euler_zxz", lambda a, b, c: product(rz(a), rx(b), rz(c)), _euler_zxz,
        "Euler angles Z-X'-Z''"),
    "euler_zyz": Convention(
        "euler_zyz", lambda a, b, c: product(rz(a), ry(b), rz(c)), _euler_zyz,
        "Euler angles Z-Y'-Z''"),
    "fixed_xyz": Convention(
        "fixed_xyz", lambda a, b, c: product(rz(c), ry(b), rx(a)), _fixed_xyz,
        "about the fixed X, then the fixed Y, then the fixed Z"),
    "rotated_xyz": Convention(
        "rotated_xyz", lambda a, b, c: product(rx(a), ry(b), rz(c)), _axis_by_axis_xyz,
        "axis by axis: X, then Y', then Z''"),
}


def frame_of(origin: Sequence[float], x_axis: Sequence[float],
             z_axis: Sequence[float]) -> Frame:
    """The frame of a plane given by its origin, X axis and Z axis (unit, at right angles:
    the caller has checked, see :func:`axes_problem`)."""
    xi, xj, xk = x_axis
    zi, zj, zk = z_axis
    y = (zj * xk - zk * xj, zk * xi - zi * xk, zi * xj - zj * xi)
    rotation: Matrix = ((xi, y[0], zi), (xj, y[1], zj), (xk, y[2], zk))
    return Frame((float(origin[0]), float(origin[1]), float(origin[2])), rotation)


def axes_problem(x_axis: Sequence[float], z_axis: Sequence[float]) -> str | None:
    """What is wrong with a plane's X and Z axes as given (None: unit and at right angles)."""
    for name, v in (("X", x_axis), ("Z", z_axis)):
        length = math.sqrt(sum(c * c for c in v))
        if abs(length - 1.0) > 1e-6:
            return f"the plane's {name} axis ({', '.join(f'{c:g}' for c in v)}) is not a " \
                   f"unit vector (length {length:.6f})"
    dot = sum(a * b for a, b in zip(x_axis, z_axis, strict=True))
    if abs(dot) > 1e-6:
        return f"the plane's X and Z axes are not at right angles (X.Z = {dot:.6f})"
    return None


def control_angles(convention: str, frame: Frame) -> Vector:
    """The three angles (degrees) a control of ``convention`` writes for ``frame``."""
    return CONVENTIONS[convention].angles(frame.rotation)


def frame_from_angles(convention: str, origin: Sequence[float],
                      angles: Sequence[float]) -> Frame:
    """The frame a control of ``convention`` sets up from an origin and its three angles."""
    a, b, c = angles
    return Frame((float(origin[0]), float(origin[1]), float(origin[2])),
                 CONVENTIONS[convention].rotation(a, b, c))


def frame_difference(nc: Frame | None, cl: Frame | None, resolution: float,
                     reach: float = 100.0) -> str | None:
    """How two planes differ, as a machinist would say it, or None when they agree.

    They agree when their origins are within ``resolution`` and every axis within
    ``resolution`` over ``reach`` mm (a point ``reach`` mm from the origin lands within
    about the resolution); no plane is the part frame itself.
    """
    a = nc if nc is not None else Frame((0.0, 0.0, 0.0), IDENTITY)
    b = cl if cl is not None else Frame((0.0, 0.0, 0.0), IDENTITY)
    turn = resolution / reach + 1e-9
    if any(abs(p - q) > turn for p, q in zip(a.tool_axis, b.tool_axis, strict=True)):
        return f"tool axis {_vec(a.tool_axis)}{_named(nc)}, CL says {_vec(b.tool_axis)}" \
               f"{_named(cl)}"
    if any(abs(p - q) > turn for p, q in zip(a.x_axis, b.x_axis, strict=True)):
        return f"the plane's X axis {_vec(a.x_axis)}, CL says {_vec(b.x_axis)}"
    if any(abs(p - q) > resolution + 1e-9 for p, q in zip(a.origin, b.origin, strict=True)):
        return f"the plane's origin {_vec(a.origin, 3)}, CL says {_vec(b.origin, 3)}"
    return None


def _named(frame: Frame | None) -> str:
    return " (no tilted plane)" if frame is None else " (a tilted plane)"


def _vec(v: Sequence[float], decimals: int = 4) -> str:
    return "(" + ", ".join(f"{c:.{decimals}f}" for c in v) + ")"
