"""HEIDENHAIN TNC 640 fixed cycles: a ``CYCL DEF`` and its Q parameters as a hole.

From the TNC 640 User's Manual, Cycle Programming, "Fixed cycles: drilling" and
"Fixed cycles: tapping / thread milling".  Every cycle positions at FMAX to the
set-up clearance Q200 above the surface coordinate Q203, works down to Q203 +
Q201 (the depth is negative: its sign is the working direction, and a positive
depth is refused here as the control's ``displayDepthErr`` refuses it), and
leaves at FMAX to the set-up clearance, or to the 2nd set-up clearance Q204
when that is greater ("Q204 only comes into effect if it is greater than
Q200").  The cycle is defined once and runs at every ``M99`` (or ``CYCL CALL``)
at the position the block reached:

- 200 DRILLING: infeeds of Q202 at Q206, back to Q200 at FMAX after each (one
  plunge when Q202 is the depth or more), Q211 dwell at depth, Q210 dwell at the
  top after each retract;
- 201 REAMING: one plunge at Q206 to the depth, Q211 dwell there, back to Q200 at
  the retraction feed Q208 (0: at Q206), then FMAX to Q204 -- a bore fed out;
- 202 BORING (Q200 Q201 Q206 Q211 Q208 Q203 Q204 Q214 Q336, the order of the cycle
  manual): one plunge at Q206, Q211 dwell, the spindle oriented to the angle Q336, the
  tool disengaged from the wall in the direction Q214 (1 -X, 2 -Y, 3 +X, 4 +Y of the
  working plane, as Autodesk's Heidenhain post maps a CL shift direction to it; 0 no
  disengaging), out at Q208 and back: a fine bore.  How far it disengages is the
  control's own distance, not a parameter, and no source read here states it: the
  model compares the direction, not the amount.  Q214=0 (the edge drags the wall on
  the way out) is refused;
- 203 UNIVERSAL DRILLING: 200 with Q212 decrement, Q205 minimum plunging depth,
  Q213 chip breaks (backing off Q256) before the tool leaves the hole, Q208
  retraction feed;
- 206 TAPPING (floating tap holder): the spindle's own direction (M3
  right-hand, M4 left-hand) reversed at the bottom after the dwell Q211;
- 207 RIGID TAPPING: the feed is the pitch Q239 times the speed, the sign of
  Q239 the hand of the thread (+ right, - left);
- 209 TAPPING W/ CHIP BRKG: 207 in infeeds of Q257, backing off Q256 times the
  pitch (Q256 = 0: out of the hole), Q336 the spindle angle, Q403 the speed
  factor for retraction.

A cycle's Q parameters are read in the order of the cycle's definition in that manual
(the order the TNC writes them when the cycle is defined): a Q parameter out of that
order, or one left out, is refused -- the control does not load such a block.  Only the
parameters a later software version added at the end (Q395 of 200 and 203) may be left
out.

What the verify cannot compare (a dwell at the top, a decrement, chip breaks
that stop before the bottom) is refused rather than passed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from postdsl.check.controls.base import ControlError
from postdsl.check.controls.events import Origin

#: cycle number -> (the name the control writes, its Q parameters in the order of the
#: cycle's definition, the ones at the end that may be left out)
CYCLES: dict[int, tuple[str, tuple[int, ...], tuple[int, ...]]] = {
    200: ("DRILLING", (200, 201, 206, 202, 210, 203, 204, 211), (395,)),
    201: ("REAMING", (200, 201, 206, 211, 208, 203, 204), ()),
    202: ("BORING", (200, 201, 206, 211, 208, 203, 204, 214, 336), ()),
    203: ("UNIVERSAL DRILLING",
          (200, 201, 206, 202, 210, 203, 204, 212, 213, 205, 211, 208, 256), (395,)),
    206: ("TAPPING", (200, 201, 206, 211, 203, 204), ()),
    207: ("RIGID TAPPING", (200, 201, 239, 203, 204), ()),
    209: ("TAPPING W/ CHIP BRKG", (200, 201, 239, 203, 204, 257, 256, 336, 403), ()),
}


@dataclass(frozen=True)
class CycleDef:
    """A defined fixed cycle: its number and Q parameters."""

    number: int
    q: dict[int, float]


@dataclass(frozen=True)
class HoleShape:
    """What one call of a cycle does, in the terms of an events
    :class:`~postdsl.check.controls.events.Hole`.

    ``feed`` is None for a rigid tap: its feed is the pitch times the speed at the call.
    """

    r: float
    bottom: float
    leave: float
    kind: str
    dwell: float
    peck: float
    feed: float | None
    pitch: float = 0.0
    #: a fine bore's disengaging direction (cycle 202's Q214)
    shift_direction: str | None = None


#: cycle 202's Q214: the direction the tool disengages in
_DISENGAGING = {1.0: "-x", 2.0: "-y", 3.0: "+x", 4.0: "+y"}


#: the Q parameters that are lengths in the program's unit (inches in an INCH program),
#: by cycle: 209's Q256 is a factor of the pitch, 203's a distance
_LENGTHS = frozenset({200, 201, 202, 203, 204, 205, 212, 239, 257})
#: the feeds: 1/10 inch/min in an INCH program (the module heidenhain's docstring)
_FEEDS = frozenset({206, 208})


def in_mm(number: int, q: dict[int, float]) -> dict[int, float]:
    """An INCH program's cycle parameters in mm and mm/min, the order kept."""
    lengths = _LENGTHS | ({256} if number == 203 else set())
    return {key: value * 25.4 if key in lengths else value * 2.54 if key in _FEEDS
            else value for key, value in q.items()}


def define(origin: Origin, number: int, name: str, q: dict[int, float]) -> CycleDef:
    """A ``CYCL DEF`` block checked against the cycle's parameter list, in its order.

    ``q`` holds the Q parameters in the order the block gives them.
    """
    if number not in CYCLES:
        raise ControlError(origin, f"cycle {number} is not one the TNC 640 model knows "
                                   f"(200 201 202 203 206 207 209, 9 DWELL TIME)")
    expected, needed, optional = CYCLES[number]
    if name != expected:
        raise ControlError(origin, f"cycle {number} is {expected}, not '{name}'")
    extra = [key for key in q if key not in needed and key not in optional]
    if extra:
        raise ControlError(origin, f"Q{extra[0]} is not a parameter of cycle {number}")
    order = needed + optional
    for index, key in enumerate(q):
        if key != order[index]:
            if order[index] not in q:
                raise ControlError(origin, f"CYCL DEF {number} without Q{order[index]} (the "
                                           f"cycle's parameters in order: "
                                           f"{' '.join(f'Q{k}' for k in order)})")
            raise ControlError(origin, f"CYCL DEF {number}: Q{key} where the cycle's definition "
                                       f"has Q{order[index]} (the TNC reads them in its order: "
                                       f"{' '.join(f'Q{k}' for k in order)})")
    if len(q) < len(needed):
        raise ControlError(origin, f"CYCL DEF {number} without Q{needed[len(q)]}")
    if q.get(395, 0.0) != 0.0:
        raise ControlError(origin, "Q395=1 (depth to the full diameter) is not modelled: the "
                                   "depth is measured to the tool tip")
    return CycleDef(number, dict(q))


def shape(origin: Origin, cycle: CycleDef) -> HoleShape:
    """The hole one call of ``cycle`` makes; a ControlError for what the model cannot follow."""
    q = cycle.q
    n = cycle.number
    depth = q[201]
    if depth >= 0:
        raise ControlError(origin, f"cycle {n}: Q201 depth {depth:+g} is not negative (its sign "
                                   f"is the working direction: the tool would not go into the "
                                   f"part)")
    if q[200] < 0 or q[204] < 0:
        raise ControlError(origin, f"cycle {n}: a negative set-up clearance (Q200, Q204)")
    surface = q[203]
    r = surface + q[200]
    leave = surface + max(q[200], q[204])
    bottom = surface + depth
    if n in (200, 203):
        return _drilling(origin, cycle, r, bottom, leave)
    if n == 201:
        feed = _feed(origin, q[206])
        if q[208] not in (0.0, feed):
            raise ControlError(origin, f"cycle 201: retraction feed Q208={q[208]:g} other than "
                                       f"the plunging feed Q206={feed:g} is not modelled")
        return HoleShape(r, bottom, leave, "bore", _dwell(origin, q[211]), 0.0, feed)
    if n == 202:
        feed = _feed(origin, q[206])
        if q[214] not in _DISENGAGING:
            raise ControlError(origin, f"cycle 202: Q214={q[214]:g} -- 0 leaves the tool's "
                                       f"edge on the wall on the way out (not modelled); 1 to "
                                       f"4 disengage in -X -Y +X +Y")
        if q[208] < 0:
            raise ControlError(origin, f"cycle 202: a negative retraction feed Q208={q[208]:g}")
        return HoleShape(r, bottom, leave, "fine_bore", _dwell(origin, q[211]), 0.0, feed,
                         shift_direction=_DISENGAGING[q[214]])
    if n == 206:
        return HoleShape(r, bottom, leave, "tap", _dwell(origin, q[211]), 0.0,
                         _feed(origin, q[206]))
    pitch = q[239]
    if pitch == 0:
        raise ControlError(origin, f"cycle {n}: Q239 pitch 0")
    peck = 0.0
    if n == 209:
        peck = q[257]
        if peck < 0 or q[256] < 0 or q[403] <= 0:
            raise ControlError(origin, "cycle 209: a negative Q257 or Q256, or Q403 not above 0")
    return HoleShape(r, bottom, leave, "rigid_tap", 0.0, peck, None, pitch)


def _drilling(origin: Origin, cycle: CycleDef, r: float, bottom: float,
              leave: float) -> HoleShape:
    q = cycle.q
    n = cycle.number
    depth = -q[201]
    infeed = q[202]
    if infeed <= 0:
        raise ControlError(origin, f"cycle {n}: Q202 plunging depth must be above 0")
    if q[210] != 0:
        raise ControlError(origin, f"cycle {n}: Q210 dwell at the top is not modelled")
    feed = _feed(origin, q[206])
    dwell = _dwell(origin, q[211])
    if infeed >= depth:
        return HoleShape(r, bottom, leave, "drill", dwell, 0.0, feed)
    if n == 200:
        return HoleShape(r, bottom, leave, "peck", dwell, infeed, feed)
    if q[212] != 0:
        raise ControlError(origin, "cycle 203: Q212 decrement is not modelled")
    breaks = q[213]
    pecks = math.ceil(depth / infeed - 1e-9)
    if breaks == 0:
        return HoleShape(r, bottom, leave, "peck", dwell, infeed, feed)
    if breaks < pecks - 1:
        raise ControlError(origin, f"cycle 203: {breaks:g} chip breaks, then a retract out of "
                                   f"the hole, in {pecks} infeeds: not modelled")
    if q[256] <= 0:
        raise ControlError(origin, "cycle 203: chip breaking with Q256 distance 0")
    return HoleShape(r, bottom, leave, "chip_break", dwell, infeed, feed)


def _feed(origin: Origin, value: float) -> float:
    if value <= 0:
        raise ControlError(origin, f"plunging feed Q206={value:g}")
    return value


def _dwell(origin: Origin, value: float) -> float:
    if value < 0:
        raise ControlError(origin, f"a negative dwell {value:g}")
    return value
