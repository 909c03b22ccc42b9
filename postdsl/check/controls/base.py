"""What every control model shares: its input, its error, the geometry of moves.

A model reads one NC line at a time (:class:`NCInput`) and yields events
(:mod:`postdsl.check.controls.events`).  Whatever it cannot interpret is a
:class:`ControlError` naming the line: a model never guesses past a word it
does not know, because a verify that skips a word cannot vouch for it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from postdsl.check.controls.events import FeedMove, Origin, Point, Tooling

#: the in-plane axes (a, b) and the normal axis of each plane, as indices of X Y Z;
#: G17 XY, G18 ZX, G19 YZ, each seen from the positive normal (the ISO 6983 convention)
PLANE_AXES = {"xy": (0, 1, 2), "zx": (2, 0, 1), "yz": (1, 2, 0)}


class ControlError(Exception):
    """A line the control model cannot interpret, or a program the control would refuse."""

    def __init__(self, origin: Origin, message: str) -> None:
        super().__init__(f"{origin}: {message}")
        self.origin = origin
        self.message = message


@dataclass(frozen=True, slots=True)
class NCInput:
    """One NC line for a model, with what the post declared about it.

    ``declared`` is None for a line to interpret, ``"none"`` for a line the post
    says moves nothing and ``"unknown"`` for one that moves the tool somewhere
    the model cannot follow (a probing macro); ``skip_words`` are words the post
    declared as machine functions without motion (``M32`` probe off).
    """

    line: int
    text: str
    declared: str | None = None
    skip_words: frozenset[str] = frozenset()


#: a straight feed move as the fast paths of verify pass it on, without the objects of an
#: event: (line, text, start, end, feed mm/min, tooling) -- the NC line and its text, or the
#: CL line and its command's name; both points known.  Most of a program's lines are such
#: moves, and an Origin and a FeedMove cost more than reading the line: verify compares
#: the tuples and makes the event (:func:`feed_event`) only for a message.
PlainFeed = tuple[int, str, tuple[float, float, float], tuple[float, float, float],
                  "float | None", Tooling]


def feed_event(plain: PlainFeed, file: str = "") -> FeedMove:
    """The FeedMove a :data:`PlainFeed` stands for (``file``: the CL file of a CL move)."""
    line, text, start, end, feed, tooling = plain
    return FeedMove(Origin(line, text, file), start, end, feed, tooling)


def number_key(text: str) -> str:
    """``'03'`` -> ``'3'``, ``'84.1'`` -> ``'84.1'``: G and M numbers compared as written values."""
    value = float(text)
    return str(int(value)) if value == int(value) else repr(value)


def arc_geometry(origin: Origin, start: Point, end: tuple[float, float, float],
                 centre: tuple[float, float, float], clockwise: bool, plane: str,
                 radius_tolerance: float) -> tuple[float, float]:
    """(sweep in radians, radius) of an arc; a control refuses ends off the circle.

    An end equal to the start is a full circle, as every ISO control runs it.
    """
    a, b, _ = PLANE_AXES[plane]
    s = (float(start[0]), float(start[1]), float(start[2]))  # type: ignore[arg-type]  # callers refuse a None start
    r1 = math.hypot(s[a] - centre[a], s[b] - centre[b])
    r2 = math.hypot(end[a] - centre[a], end[b] - centre[b])
    if r1 <= 0:
        raise ControlError(origin, "the arc has radius 0")
    if abs(r1 - r2) > radius_tolerance and abs(r1 - r2) > 0.001 * r1:
        raise ControlError(origin, f"the arc's end is not on its circle: radius {r1:.4f} at the "
                                   f"start, {r2:.4f} at the end")
    a0 = math.atan2(s[b] - centre[b], s[a] - centre[a])
    a1 = math.atan2(end[b] - centre[b], end[a] - centre[a])
    sweep = ((a0 - a1) if clockwise else (a1 - a0)) % (2 * math.pi)
    if s[a] == end[a] and s[b] == end[b]:
        sweep = 2 * math.pi
    return sweep, r1


def centre_from_radius(origin: Origin, start: Point, end: tuple[float, float, float],
                       radius: float, clockwise: bool, plane: str) -> tuple[float, float, float]:
    """The centre of an arc given by its radius: R > 0 the short way, R < 0 the long way."""
    a, b, n = PLANE_AXES[plane]
    s = (float(start[0]), float(start[1]), float(start[2]))  # type: ignore[arg-type]  # callers refuse a None start
    da, db = end[a] - s[a], end[b] - s[b]
    chord = math.hypot(da, db)
    if chord == 0:
        raise ControlError(origin, "a radius arc cannot be a full circle")
    half = chord / 2
    if abs(radius) < half - 1e-6:
        raise ControlError(origin, f"radius {abs(radius):g} is shorter than half the chord "
                                   f"{half:.4f}")
    offset = math.sqrt(max(radius * radius - half * half, 0.0))
    # the centre lies left of the chord for a short clockwise arc (seen from the normal)
    side = -1.0 if clockwise else 1.0
    if radius < 0:
        side = -side
    ma, mb = s[a] + da / 2, s[b] + db / 2
    centre = [0.0, 0.0, 0.0]
    centre[a] = ma - side * offset * db / chord
    centre[b] = mb + side * offset * da / chord
    centre[n] = s[n]
    return (centre[0], centre[1], centre[2])
