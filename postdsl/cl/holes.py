"""A hole as the plain moves that drill it, for a control without canned cycles.

One definition serves both sides of ``postdsl verify``: the engine writes an
expanded hole (``expand: true``) with these moves through the post's own move
tables, and the CL side of the comparison expects the same moves, so a post
that expands its holes is verified move by move like any milling program.
"""

from __future__ import annotations

import math

from postdsl.cl.model import CLCommand, Dwell, LinearMove, RapidMove

#: most pecks an expanded hole is written with: a peck of 1e-9 mm is a unit mistake, and
#: writing it out would never end
MAX_PECKS = 10_000


class TooManyPecks(ValueError):
    """The peck is so small against the depth that the hole would never be written out."""

    def __init__(self, count: int | None) -> None:
        # None: more pecks than a float can count (a peck of 1e-320 against a real depth)
        shown = f"{count}" if count is not None else "more than 10^308"
        super().__init__(f"{shown} pecks (at most {MAX_PECKS} are written)")
        self.count = count
        self.shown = shown


def hole_moves(*, x: float, y: float, top: float, bottom: float, clearance: float,
               retract: float, feed: float | None, peck: float, dwell: float, cycle: str,
               start_z: float | None, line: int = 0,
               first_peck: float | None = None) -> list[CLCommand]:
    """The moves of one hole: over it, down to the feed level, the feed(s), dwell, out.

    The tool goes over the hole at its current level when that lies above the level
    the feed starts at (``top + clearance``), else at that level; a deep drill goes
    back to the feed level after every peck to clear the chips, a chip-breaking drill
    lifts by the clearance (at most 1 mm); both rapid back down to just above the last
    depth.  The tool leaves to ``retract`` at rapid.  ``first_peck`` (when it differs
    from ``peck``) is the depth of the first peck; the later ones are ``peck`` deep.
    """
    approach = top + clearance
    first_z = start_z if start_z is not None and start_z > approach else approach
    moves: list[CLCommand] = [RapidMove(x=x, y=y, z=first_z, line=line),
                              RapidMove(z=approach, line=line)]
    depths = [bottom]
    if peck > 0 and cycle in ("deep_drill", "break_chip"):
        first = first_peck if first_peck else peck
        # a subnormal peck overflows the quotient to infinity: counted before ceil() is
        # asked to make an int of it
        pecks = (top - first - bottom) / peck - 1e-9
        if not math.isfinite(pecks):
            raise TooManyPecks(None)
        count = 1 + max(0, math.ceil(pecks))
        if count > MAX_PECKS:
            raise TooManyPecks(count)
        depths = []
        level = top - first
        while level > bottom + 1e-9:
            depths.append(level)
            level -= peck
        depths.append(bottom)
    for index, depth in enumerate(depths):
        moves.append(LinearMove(z=depth, feed=feed, line=line))
        if index < len(depths) - 1:
            if cycle == "deep_drill":  # full retract to clear the chips
                moves.append(RapidMove(z=approach, line=line))
            # back down to just above the last depth (break chip: a short lift)
            moves.append(RapidMove(z=depth + min(clearance, 1.0), line=line))
    if dwell:
        moves.append(Dwell(dwell=dwell, line=line))
    if cycle == "boring":  # a bore or reamer leaves at the feed, not to mark the wall
        moves.append(LinearMove(z=approach, feed=feed, line=line))
    moves.append(RapidMove(z=retract, line=line))
    return moves
