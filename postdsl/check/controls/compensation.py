"""Cutter radius compensation: the tool-centre path a control makes of a programmed path.

Pure geometry in the XY plane (G17), shared by the control models (the NC side of
verify) and the CL side of verify in the ``control`` mode, where the CL is the part
contour and the control offsets it by the tool radius.  Each control's rules are
parameters (:class:`Rules`), taken from its manual:

- every programmed move is offset by the radius to the left or right of its
  direction (a line to a parallel line, an arc to a concentric arc, larger or
  smaller); Z is not offset (a helix keeps its rise);
- a *concave* corner (the path turns towards the tool): both moves end at the
  intersection of their offsets (line-line, line-arc, arc-arc, the one nearest the
  corner), as every ISO control does;
- a *convex* corner (the path turns away from the tool): LinuxCNC inserts an arc of
  the tool radius around the programmed corner (G-code manual, "Cutter Compensation");
  Fanuc (type C, Operator's Manual "Cutter compensation C") goes to the intersection of
  the two offset lines where the path turns by at most 90 degrees (a wider turn adds
  moves this model does not make: refused, so verify says it cannot check the stretch);
- start-up, the first move in the plane after G41/G42, must be straight: LinuxCNC ends it
  one radius from its programmed end, square to the move itself (interp_convert.cc,
  ``convert_straight_comp1``), then turns the corner to the next move as above; Fanuc's
  type A start-up ends square to the *next* move's start: the model follows it only where
  the two are the same (a start-up move in line with the next move) and refuses others;
- cancel, the move with G40: the last compensated move ends square to its own end, the
  cancel move goes straight from there to its programmed, uncompensated end.

Anything else (a start-up on an arc, an offset arc of radius 0 or less, offsets that do
not meet) raises :class:`~postdsl.check.controls.base.ControlError` at the move: a verify
that cannot follow the control's path says so at that line, and never passes it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from postdsl.check.controls.base import ControlError
from postdsl.check.controls.events import ArcMove, FeedMove, Rapid

#: a move of the path: what the model and the CL side hand in and get back
Move = Rapid | FeedMove | ArcMove
#: directions closer than this (radians) are one direction: no corner between them
TANGENT = 1e-6


@dataclass(frozen=True, slots=True)
class Rules:
    """What a control does where this module's geometry has a choice."""

    #: a convex corner gets an arc around the programmed corner (else: the intersection)
    convex_arc: bool
    #: start-up ends square to the start-up move itself (else: to the next move's start)
    startup_square_to_move: bool


LINUXCNC = Rules(convex_arc=True, startup_square_to_move=True)
FANUC = Rules(convex_arc=False, startup_square_to_move=False)
#: Sinumerik G450 (the default: a transition circle at outside corners), NORM start-up
#: (square to the contour's start); a TNC's transition arc at outside corners, and its
#: first RL/RR block ending square to the contour
TRANSITION_ARC = Rules(convex_arc=True, startup_square_to_move=False)


def _unit(x: float, y: float) -> tuple[float, float]:
    length = math.hypot(x, y)
    return (x / length, y / length)


def _tangent(move: Move, at_end: bool) -> tuple[float, float] | None:
    """The XY direction of travel at the start or end of a programmed move (None: no XY)."""
    sx, sy = move.start[0], move.start[1]
    ex, ey = move.end[0], move.end[1]
    if isinstance(move, ArcMove):
        px, py = (ex, ey) if at_end else (sx, sy)
        rx, ry = px - move.centre[0], py - move.centre[1]  # type: ignore[operator]  # arcs have known points
        return _unit(ry, -rx) if move.clockwise else _unit(-ry, rx)
    dx, dy = ex - sx, ey - sy  # type: ignore[operator]  # compensated moves have known points
    if math.hypot(dx, dy) < 1e-9:
        return None
    return _unit(dx, dy)


def _left(t: tuple[float, float]) -> tuple[float, float]:
    return (-t[1], t[0])


def _cross(a: tuple[float, float], b: tuple[float, float]) -> float:
    return a[0] * b[1] - a[1] * b[0]


def _with_points(move: Move, start: tuple[float, float], end: tuple[float, float]) -> Move:
    """The move with new XY start and end (Z as programmed); an arc keeps its centre."""
    s = (start[0], start[1], move.start[2])
    e = (end[0], end[1], move.end[2])
    if not isinstance(move, ArcMove):
        return replace(move, start=s, end=e)
    cx, cy = move.centre[0], move.centre[1]
    radius = math.hypot(s[0] - cx, s[1] - cy)
    a0 = math.atan2(s[1] - cy, s[0] - cx)
    a1 = math.atan2(e[1] - cy, e[0] - cx)
    sweep = (a0 - a1) if move.clockwise else (a1 - a0)
    sweep %= 2 * math.pi
    if sweep < 1e-9 and move.sweep > math.pi:
        sweep = 2 * math.pi  # a full circle stays one
    return replace(move, start=s, end=e, radius=radius, sweep=sweep)


class CompensatedPath:
    """One stretch of compensation, from the start-up move to the cancel move.

    Moves go in as programmed and come out as the tool centre, one move behind: a move's
    end is known once the next move says which corner it turns.
    """

    def __init__(self, side: str, radius: float, rules: Rules) -> None:
        #: +1 left (G41), -1 right (G42)
        self.sign = 1.0 if side == "left" else -1.0
        self.radius = radius
        self.rules = rules
        #: the programmed move held back, and its offset start and end so far
        self.held: Move | None = None
        self.held_start: tuple[float, float] = (0.0, 0.0)
        self.held_end: tuple[float, float] = (0.0, 0.0)
        self.started = False
        #: the held move is the start-up move
        self.startup = False

    def _offset_point(self, move: Move, at_end: bool) -> tuple[float, float]:
        point = move.end if at_end else move.start
        t = _tangent(move, at_end)
        assert t is not None
        n = _left(t)
        r = self.sign * self.radius
        return (point[0] + r * n[0], point[1] + r * n[1])  # type: ignore[operator]  # known

    def _check_arc(self, move: Move) -> None:
        if isinstance(move, ArcMove):
            # left of a counter-clockwise arc is towards its centre
            inward = (self.sign > 0) != move.clockwise
            if inward and move.radius - self.radius <= 1e-9:
                raise ControlError(move.origin, f"cutter compensation: the arc's radius "
                                   f"{move.radius:g} is not larger than the tool radius "
                                   f"{self.radius:g} on its inside (the control refuses it)")

    def move(self, move: Move) -> list[Move]:
        """A programmed move with compensation on: the moves that are now complete."""
        if move.start[0] is None or move.start[1] is None or move.end[0] is None \
                or move.end[1] is None:
            raise ControlError(move.origin, "cutter compensation from or to a position the "
                               "program does not state")
        if not self.started:
            return self._start_up(move)
        if _tangent(move, False) is None:
            raise ControlError(move.origin, "a move without X or Y with cutter compensation "
                               "on: beyond the model (verify cannot check this stretch)")
        self._check_arc(move)
        held = self.held
        assert held is not None
        out: list[Move] = []
        start = self._offset_point(move, False)
        t_a = _tangent(held, True)
        t_b = _tangent(move, False)
        assert t_a is not None and t_b is not None
        turn = _cross(t_a, t_b)
        dot = t_a[0] * t_b[0] + t_a[1] * t_b[1]
        angle = math.atan2(turn, dot)
        corner = (move.start[0], move.start[1])
        if self.startup and abs(angle) >= TANGENT and not self.rules.startup_square_to_move:
            raise ControlError(move.origin, "cutter compensation start-up into a move in "
                               "another direction: the control's start-up type decides the "
                               "path, beyond the model (verify cannot check this stretch); a "
                               "start-up move in line with the next move is followed")
        self.startup = False
        if abs(angle) < TANGENT:
            end = start
        elif self.sign * turn > 0:  # towards the tool: concave, the offsets meet
            end = start = self._meet(held, move, corner)
        elif self.rules.convex_arc and not isinstance(move, Rapid):
            end = self.held_end
            out.append(self._flush(end))
            arc = ArcMove(move.origin, (end[0], end[1], move.start[2]),
                          (start[0], start[1], move.start[2]),
                          (corner[0], corner[1], move.start[2]), self.sign > 0, "xy",  # type: ignore[arg-type]  # known
                          abs(angle), self.radius, move.feed, move.tooling)
            out.append(arc)
            self._hold(move, start)
            return out
        elif abs(angle) <= math.pi / 2 + 1e-9 and not isinstance(held, ArcMove) \
                and not isinstance(move, ArcMove):
            end = start = self._meet(held, move, corner)
        else:
            raise ControlError(move.origin, f"cutter compensation around a convex corner of "
                               f"{math.degrees(abs(angle)):.1f} degrees (or of an arc): the "
                               f"control adds moves this model does not make (verify cannot "
                               f"check this stretch)")
        out.append(self._flush(end))
        self._hold(move, start)
        return out

    def _start_up(self, move: Move) -> list[Move]:
        if isinstance(move, ArcMove):
            raise ControlError(move.origin, "cutter compensation starts (G41/G42) on an arc: "
                               "the control starts it on a straight move (G0/G1) in the plane")
        t = _tangent(move, True)
        if t is None:
            return [move]  # no X or Y: compensation starts on the next move in the plane
        length = math.hypot(move.end[0] - move.start[0], move.end[1] - move.start[1])  # type: ignore[operator]  # known
        if length <= self.radius:
            raise ControlError(move.origin, f"the cutter compensation start-up move "
                               f"({length:g}) is not longer than the tool radius "
                               f"({self.radius:g}): the control refuses it")
        self.started = True
        self.startup = True
        self.held = move
        self.held_start = (move.start[0], move.start[1])  # type: ignore[assignment]  # known
        self.held_end = self._offset_point(move, True)
        return []

    def _hold(self, move: Move, start: tuple[float, float]) -> None:
        self.held = move
        self.held_start = start
        self.held_end = self._offset_point(move, True)

    def _flush(self, end: tuple[float, float]) -> Move:
        held = self.held
        assert held is not None
        return _with_points(held, self.held_start, end)

    def _meet(self, a: Move, b: Move, corner: tuple[float, float]) -> tuple[float, float]:
        """Where the offsets of ``a`` (as it is held) and ``b`` cross, nearest the corner."""
        first = self._offset_shape(a, self.held_end)
        second = self._offset_shape(b, self._offset_point(b, False))
        points = _intersections(first, second)
        if not points:
            raise ControlError(b.origin, "cutter compensation: the offset paths of this move "
                               "and the one before do not meet (the control would refuse "
                               "or gouge; verify cannot check this stretch)")
        return min(points, key=lambda p: math.dist(p, corner))

    def _offset_shape(self, move: Move, through: tuple[float, float]
                      ) -> tuple[str, tuple[float, float], tuple[float, float] | float]:
        """A line (point, direction) or circle (centre, radius) the offset move lies on."""
        if isinstance(move, ArcMove):
            centre = (move.centre[0], move.centre[1])
            return ("circle", centre, math.dist(centre, through))
        t = _tangent(move, True)
        assert t is not None
        return ("line", through, t)

    def cancel(self, move: Move) -> list[Move]:
        """The move with G40: the held move ends square to its end, then this move goes
        from there to its programmed point."""
        if isinstance(move, ArcMove):
            raise ControlError(move.origin, "cutter compensation ends (G40) on an arc: the "
                               "control ends it on a straight move (G0/G1) in the plane")
        if not self.started:
            return [move]
        end = self.held_end
        out = [self._flush(end)]
        out.append(_with_points(move, end, (move.end[0], move.end[1])))  # type: ignore[arg-type]  # known
        self.held = None
        return out

    def unfinished(self) -> Move | None:
        """The held move, at the program's end or another interruption (None: none)."""
        return self.held


def _intersections(first: tuple[str, tuple[float, float], tuple[float, float] | float],
                   second: tuple[str, tuple[float, float], tuple[float, float] | float]
                   ) -> list[tuple[float, float]]:
    if first[0] == "circle" and second[0] == "line":
        first, second = second, first
    if first[0] == "line" and second[0] == "line":
        (px, py), (dx, dy) = first[1], first[2]  # type: ignore[misc]  # a line's direction
        (qx, qy), (ex, ey) = second[1], second[2]  # type: ignore[misc]  # (as above)
        det = _cross((dx, dy), (ex, ey))
        if abs(det) < 1e-12:
            return []
        t = _cross((qx - px, qy - py), (ex, ey)) / det
        return [(px + t * dx, py + t * dy)]
    if first[0] == "line":
        (px, py), (dx, dy) = first[1], first[2]  # type: ignore[misc]  # (as above)
        (cx, cy), r = second[1], second[2]
        fx, fy = px - cx, py - cy
        b = fx * dx + fy * dy
        c = fx * fx + fy * fy - r * r  # type: ignore[operator]  # a circle's radius
        disc = b * b - c
        if disc < -1e-9:
            return []
        root = math.sqrt(max(disc, 0.0))
        return [(px + t * dx, py + t * dy) for t in (-b - root, -b + root)]
    (ax, ay), ra = first[1], first[2]
    (bx, by), rb = second[1], second[2]
    d = math.hypot(bx - ax, by - ay)
    if d < 1e-12:
        return []
    a = (ra * ra - rb * rb + d * d) / (2 * d)  # type: ignore[operator]  # radii
    h2 = ra * ra - a * a  # type: ignore[operator]  # (as above)
    if h2 < -1e-9:
        return []
    h = math.sqrt(max(h2, 0.0))
    mx, my = ax + a * (bx - ax) / d, ay + a * (by - ay) / d
    return [(mx + h * (by - ay) / d, my - h * (bx - ax) / d),
            (mx - h * (by - ay) / d, my + h * (bx - ax) / d)]

