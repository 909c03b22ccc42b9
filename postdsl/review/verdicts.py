"""Does a text change reach the machine?  Both postings replayed through the control model.

Two postings whose text differs (a comment, a fourth decimal the control does not
resolve, a word order, a split block) may still make the machine do the same: the
verdict is ``format only`` when the control model (``api.control_events``) replays
both into the same positions, feeds, spindle and tool states, each within half the
machine's resolution (a value the control rounds to the same step; an arc's centre,
the sum of two rounded values, within one and a half steps), and ``motion changed``
otherwise, with the first event that differs located on both sides: its CL record and
its NC line before and after.

The events are compared as streams, one at a time, so a long program costs its replay
and no more memory than its lines.  Moves that go nowhere are skipped: splitting a
block in two, or writing a position the tool is already at, does not move the tool.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from itertools import zip_longest
from typing import Any

from postdsl import api
from postdsl.review.results import MotionDifference

Key = tuple[Any, ...]


def same(old: Any, new: Any, tolerance: float) -> bool:
    """Two keys alike, numbers within ``tolerance`` of each other (half the resolution: a
    value the control rounds to the same step of its grid)."""
    if isinstance(old, float) or isinstance(new, float):
        if isinstance(old, (int, float)) and isinstance(new, (int, float)) \
                and not isinstance(old, bool) and not isinstance(new, bool):
            return abs(old - new) <= tolerance
        return False
    if isinstance(old, tuple) and isinstance(new, tuple):
        return len(old) == len(new) and all(same(a, b, tolerance)
                                            for a, b in zip(old, new, strict=True))
    return bool(old == new)


def alike(old: Key, new: Key, tolerance: float) -> bool:
    """Two events' keys alike; an arc's centre (its start plus the rounded offsets, I J K)
    may be three times as far off as a position."""
    if old[0] == "arc" and new[0] == "arc" and len(old) == len(new):
        return same(old[:4] + old[5:], new[:4] + new[5:], tolerance) \
            and same(old[4], new[4], 3 * tolerance)
    return same(old, new, tolerance)


def _tooling(tooling: Any) -> Key:
    return (tooling.tool, tooling.length_offset, tooling.spindle,
            tooling.speed, tooling.work_offset)


def event_key(event: Any, step: float) -> Key | None:
    """What an event does, without where it comes from; None: it does nothing (a move
    shorter than ``step``)."""
    kind = type(event).__name__
    if kind in ("Rapid", "FeedMove"):
        end = tuple(event.end)
        if same(end, tuple(event.start), step):
            return None
        if kind == "Rapid":
            return ("rapid", end)
        return ("feed", end, event.feed, _tooling(event.tooling))
    if kind == "ArcMove":
        # the start, the end, the centre and the direction make the arc; its sweep only
        # tells a full circle from none (the sweep itself moves with every rounding)
        turns = math.floor((event.sweep + 1e-3) / math.tau)
        return ("arc", tuple(event.end), event.feed, _tooling(event.tooling),
                tuple(event.centre), event.clockwise, event.plane, turns)
    if kind == "Hole":
        return ("hole", event.x, event.y, event.r, event.bottom, event.leave, event.kind,
                event.direction, event.dwell, event.peck, event.feed, _tooling(event.tooling),
                event.first_peck, event.via)
    if kind == "Dwell":
        return ("dwell", event.seconds)
    if kind == "ToolLoaded":
        return ("tool", event.tool)
    if kind == "SpindleChanged":
        return ("spindle", event.direction, event.speed)
    if kind == "LengthOffsetChanged":
        return ("length offset", event.register)
    if kind == "NotFollowed":
        return ("not followed", event.moves)
    if kind == "ProgramEnded":
        return ("end",)
    return (kind,)


_WHAT = {"rapid": "a rapid move", "feed": "a feed move", "arc": "an arc", "hole": "a hole",
         "dwell": "a dwell", "tool": "the tool", "spindle": "the spindle",
         "length offset": "the length offset", "not followed": "lines the control skips",
         "end": "the program end"}


def _keyed(post: api.CompiledPost, lines: Sequence[api.NCLine], step: float
           ) -> Iterator[tuple[Key, int]]:
    """(key, NC line) of every event that does something; a refused line is a key too."""
    events = api.control_events(post, lines)
    while True:
        try:
            event = next(events)
        except StopIteration:
            return
        except Exception as exc:  # the control refuses a line (ControlError): what it does
            origin = getattr(exc, "origin", None)
            if origin is None:
                raise
            yield ("refused", getattr(exc, "message", str(exc))), int(origin.line)
            return
        key = event_key(event, step)
        if key is not None:
            yield key, event.origin.line


#: what the fields of a key are, for the message
_FIELDS = {"rapid": ("", "the end point"),
           "feed": ("", "the end point", "the feed", "the tool or spindle"),
           "arc": ("", "the end point", "the feed", "the tool or spindle", "the centre",
                   "the direction", "the plane", "the full turns"),
           "hole": ("", "X", "Y", "the R level", "the depth", "the level left at", "the cycle",
                    "the spindle direction", "the dwell", "the peck", "the feed",
                    "the tool or spindle", "the first peck", "the level the cycle ends at")}


def _describe(old: Key | None, new: Key | None, tolerance: float) -> str:
    if old is None or new is None:
        return "an event on one side only"
    if old[0] != new[0]:
        return f"{_WHAT.get(str(old[0]), old[0])} became {_WHAT.get(str(new[0]), new[0])}"
    what = _WHAT.get(str(old[0]), str(old[0]))
    fields = _FIELDS.get(str(old[0]), ())
    for index, name in enumerate(fields):
        scale = 3 if name == "the centre" else 1
        if index and index < len(old) and not same(old[index], new[index], scale * tolerance):
            return f"{what}: {name}"
    return what


def first_motion_difference(old_post: api.CompiledPost, old_lines: Sequence[api.NCLine],
                            new_post: api.CompiledPost, new_lines: Sequence[api.NCLine]
                            ) -> MotionDifference | None:
    """Where the two postings first move differently, or None when they move alike.

    Raises PostError when either post has no control model (nothing to replay with).
    """
    resolution = max(old_post.machine.resolution or 0.0, new_post.machine.resolution or 0.0)
    resolution = resolution if resolution > 0 and math.isfinite(resolution) else 0.001
    # half a step, and a little more for the binary fractions of decimal numbers
    step = resolution / 2 * (1 + 1e-6)
    sentinel = (None, 0)
    for (old_key, old_at), (new_key, new_at) in zip_longest(
            _keyed(old_post, old_lines, step), _keyed(new_post, new_lines, step),
            fillvalue=sentinel):
        if old_key == new_key or (old_key is not None and new_key is not None
                                  and alike(old_key, new_key, step)):
            continue
        old_line = old_lines[old_at - 1] if 1 <= old_at <= len(old_lines) else None
        new_line = new_lines[new_at - 1] if 1 <= new_at <= len(new_lines) else None
        either = old_line or new_line
        cl_line = either.cl_line if either is not None else 0
        return MotionDifference(
            cl_line, (old_at, old_line.text) if old_line else None,
            (new_at, new_line.text) if new_line else None, _describe(old_key, new_key, step))
    return None
