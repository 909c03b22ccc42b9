"""Program-level values from a first pass over the CL: tools, extents, machining time.

Headers print them before the first move is posted, so they must be known
up front.  Values the CAM system gave (e.g. its own time estimate in
``program_start``) win over computed ones.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

from postdsl.cl.model import (
    ArcMove,
    CLCommand,
    CycleHole,
    DrillSetup,
    Dwell,
    LinearMove,
    ProgramStart,
    RapidMove,
    SpindleOn,
    ToolChange,
)


@dataclass
class ProgramSummary:
    tools: list[int] = field(default_factory=list)
    #: each tool's first tool change, for tool lists and headers (type, diameter…)
    tool_records: dict[int, ToolChange] = field(default_factory=dict)
    extents: dict[str, float | None] = field(default_factory=dict)
    machining_time: float = 0.0
    #: every tool change's tool, in program order (a tool may come back), for next_tool
    tool_sequence: list[int] = field(default_factory=list)
    #: per tool change: the speed of the first spindle_on after it (None: none follows)
    tool_speeds: list[float | None] = field(default_factory=list)

    def values(self) -> dict[str, Any]:
        return {"tools": list(self.tools), "tool_count": len(self.tools), **self.extents,
                "machining_time": self.machining_time,
                "next_tool": self.tool_sequence[0] if self.tool_sequence else None,
                "next_spindle_speed": None}


class _Bounds:
    def __init__(self) -> None:
        self.low: dict[str, float] = {}
        self.high: dict[str, float] = {}

    def add(self, axis: str, value: float | None) -> None:
        if value is None:
            return
        if axis not in self.low or value < self.low[axis]:
            self.low[axis] = value
        if axis not in self.high or value > self.high[axis]:
            self.high[axis] = value

    def as_params(self) -> dict[str, float | None]:
        out: dict[str, float | None] = {}
        for axis in "xyz":
            out[f"min_{axis}"] = self.low.get(axis)
            out[f"max_{axis}"] = self.high.get(axis)
        return out


def arc_length(start: tuple[float, float, float], end: tuple[float, float, float],
               centre: tuple[float, float, float], clockwise: bool, plane: str) -> float:
    """Length of a circular or helical arc (a full circle when start and end coincide)."""
    a, b, n = {"xy": (0, 1, 2), "zx": (2, 0, 1), "yz": (1, 2, 0)}[plane]
    r = math.hypot(start[a] - centre[a], start[b] - centre[b])
    a0 = math.atan2(start[b] - centre[b], start[a] - centre[a])
    a1 = math.atan2(end[b] - centre[b], end[a] - centre[a])
    sweep = (a0 - a1) if clockwise else (a1 - a0)
    sweep %= 2 * math.pi
    if sweep < 1e-9:
        sweep = 2 * math.pi
    return math.hypot(r * sweep, end[n] - start[n])


def summarize(commands: Iterable[CLCommand], rapid_rate: float) -> ProgramSummary:
    """One pass over the CL: tools in order of first use, extents, estimated time (s).

    The time model: rapids at ``rapid_rate``, cuts at their feed, dwells as
    given, and each hole as rapid to the clearance plane, feed down and back
    up at the cycle feed (pecking retracts are ignored: an estimate, which
    the CAM's own figure overrides).
    """
    summary = ProgramSummary()
    bounds = _Bounds()
    pos: list[float | None] = [None, None, None]
    feed: float | None = None
    given_time: float | None = None
    seconds = 0.0
    cycle: DrillSetup | None = None

    def travel(target: list[float | None], rate: float | None) -> float:
        if rate is None or rate <= 0 or None in pos or None in target:
            return 0.0
        return math.dist(pos, target) / rate * 60.0  # type: ignore[arg-type]

    for command in commands:
        if isinstance(command, ProgramStart):
            given_time = command.machining_time
        elif isinstance(command, ToolChange):
            summary.tool_records.setdefault(command.tool_number, command)
            summary.tool_sequence.append(command.tool_number)
            summary.tool_speeds.append(None)
            if command.tool_number not in summary.tools:
                summary.tools.append(command.tool_number)
        elif isinstance(command, (RapidMove, LinearMove, ArcMove)):
            target = [command.x if command.x is not None else pos[0],
                      command.y if command.y is not None else pos[1],
                      command.z if command.z is not None else pos[2]]
            if isinstance(command, RapidMove):
                seconds += travel(target, rapid_rate)
            else:
                feed = command.feed if command.feed is not None else feed
                if isinstance(command, ArcMove) and None not in pos and None not in target:
                    centre = (command.cx if command.cx is not None else pos[0],
                              command.cy if command.cy is not None else pos[1],
                              command.cz if command.cz is not None else pos[2])
                    length = arc_length(tuple(pos), tuple(target), centre,  # type: ignore[arg-type]
                                        command.arc_direction == "cw", command.plane)
                    if feed:
                        seconds += length / feed * 60.0
                else:
                    seconds += travel(target, feed)
            pos = target
            for axis, value in zip("xyz", pos, strict=True):
                bounds.add(axis, value)
        elif isinstance(command, SpindleOn):
            if summary.tool_speeds and summary.tool_speeds[-1] is None:
                summary.tool_speeds[-1] = command.spindle_speed
        elif isinstance(command, Dwell):
            seconds += command.dwell
        elif isinstance(command, (DrillSetup, CycleHole)):
            if isinstance(command, DrillSetup):
                cycle = command
            if cycle is None:
                continue
            top = cycle.top if isinstance(command, DrillSetup) or command.top is None \
                else command.top
            x = command.x if command.x is not None else pos[0]
            y = command.y if command.y is not None else pos[1]
            retract = cycle.retract if cycle.retract is not None else top + cycle.clearance
            bottom = top - cycle.depth
            seconds += travel([x, y, pos[2]], rapid_rate)
            cut_feed = cycle.feed if cycle.feed is not None else feed
            if cut_feed:
                seconds += 2 * (top + cycle.clearance - bottom) / cut_feed * 60.0
            seconds += cycle.dwell
            for axis, value in (("x", x), ("y", y), ("z", bottom), ("z", retract),
                                ("z", top + cycle.clearance)):
                bounds.add(axis, value)
            pos = [x, y, retract]
    summary.extents = bounds.as_params()
    summary.machining_time = given_time if given_time is not None else seconds
    return summary
