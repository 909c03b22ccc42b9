"""Arcs as chords, for controls that have no circular interpolation.

Hobby routers (GRBL builds without arcs), laser and plasma controls take only straight
lines.  A post for them says ``arc_move: {expand: true, tolerance: 0.01}`` and the engine
writes each arc as chords through the post's own ``linear_move`` table.

A chord spanning the angle θ of a circle of radius r strays from the arc by its sagitta,
r (1 - cos(θ / 2)), so every chord here spans at most the angle whose sagitta is the
tolerance.  The arc is divided evenly, so all chords are equally long and the toolpath
has no odd short segment at its end.  The third axis of a helix moves in proportion to
the angle, as it does on the arc, so chord and helix differ only in the arc's plane.  The
last point is the CL's end point itself, not a recomputed one, so the next move starts
exactly where the arc ended.
"""

from __future__ import annotations

import math
from typing import Final

Point = tuple[float, float, float]

#: the axes (as indices of x, y, z) of the arc's plane and of its normal, per plane, in the
#: order the plane's rotation is measured (G17 XY, G18 ZX, G19 YZ)
PLANE_AXES: Final = {"xy": (0, 1, 2), "zx": (2, 0, 1), "yz": (1, 2, 0)}

#: most chords one arc is written as: a tolerance of 1e-9 mm is a unit mistake, and the
#: millions of lines it would take are a program no control can load
MAX_CHORDS: Final = 10_000


class TooManyChords(ValueError):
    """The tolerance asks for more chords than :data:`MAX_CHORDS`."""

    def __init__(self, count: int) -> None:
        super().__init__(f"{count} chords (at most {MAX_CHORDS} are written)")
        self.count = count


def sweep(start: Point, end: Point, centre: Point, clockwise: bool, plane: str) -> float:
    """The angle the arc turns through, in radians: (0, 2π], a full circle when the end
    is the start in the arc's plane."""
    a, b, _ = PLANE_AXES[plane]
    begin = math.atan2(start[b] - centre[b], start[a] - centre[a])
    finish = math.atan2(end[b] - centre[b], end[a] - centre[a])
    angle = (begin - finish) if clockwise else (finish - begin)
    angle %= 2 * math.pi
    if angle < 1e-9:
        # start and end together (within a nanoradian): the CL's full circle
        angle = 2 * math.pi
    return angle


def chord_count(radius: float, angle: float, tolerance: float) -> int:
    """The fewest equal chords over ``angle`` whose sagitta is at most ``tolerance``."""
    # no chord strays further than the diameter: past it, one chord spans any arc
    widest = 2 * math.pi if tolerance >= 2 * radius else 2 * math.acos(1 - tolerance / radius)
    count = max(1, math.ceil(angle / widest))
    if count > MAX_CHORDS:
        raise TooManyChords(count)
    return count


def chords(start: Point, end: Point, centre: Point, clockwise: bool, plane: str,
           tolerance: float) -> list[Point]:
    """The end points of the chords from ``start`` along the arc to ``end``.

    ``centre`` is the arc's centre (its coordinate along the plane's normal is not used).
    The radius is taken at the start; should the end lie a rounding error off that
    circle, the radius changes evenly along the arc so that the chords still meet the end.

    Raises:
        TooManyChords: when the tolerance would need more than :data:`MAX_CHORDS` chords.
    """
    a, b, n = PLANE_AXES[plane]
    radius = math.hypot(start[a] - centre[a], start[b] - centre[b])
    end_radius = math.hypot(end[a] - centre[a], end[b] - centre[b])
    angle = sweep(start, end, centre, clockwise, plane)
    count = chord_count(max(radius, end_radius), angle, tolerance)
    begin = math.atan2(start[b] - centre[b], start[a] - centre[a])
    turn = -angle if clockwise else angle
    points: list[Point] = []
    for step in range(1, count):
        fraction = step / count
        theta = begin + turn * fraction
        r = radius + (end_radius - radius) * fraction
        point = [0.0, 0.0, 0.0]
        point[a] = centre[a] + r * math.cos(theta)
        point[b] = centre[b] + r * math.sin(theta)
        point[n] = start[n] + (end[n] - start[n]) * fraction
        points.append((point[0], point[1], point[2]))
    points.append(end)
    return points
