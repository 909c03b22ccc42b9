"""What a machine refuses before a table is written: the rules the engine checks a record by.

Values no machine can be given, the machine's travel, feed, spindle and tool limits,
what a cutting move needs (a tool, a feed, a turning spindle), arcs the control would
run as something else, and pecks a table cannot write as the CL gives them.  Each rule
reads the engine's state and refuses with the record's CL line; none writes NC.  They
are bound as methods of :class:`~postdsl.run.engine.Engine`, so the generated code of a
post (:mod:`postdsl.compile.codegen`) calls them on the engine it runs with, and every refusal
is worded once, here.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from postdsl.cl.model import (
    ArcMove,
    CLCommand,
    CycleHole,
    DrillSetup,
    Dwell,
    LinearMove,
    RapidMove,
    SpindleOn,
    ToolChange,
)
from postdsl.compile.compiler import CompiledCommand
from postdsl.errors import CLError
from postdsl.lang.expr import ExprEvalError, nodes
from postdsl.lang.expr.compiler import Compiler
from postdsl.lang.expr.runtime import Evaluator
from postdsl.lang.formats import DigitsError

if TYPE_CHECKING:
    from postdsl.run.engine import Engine


def check_values(engine: Engine, command: CLCommand) -> None:
    """Values no machine can be given, whatever its limits.

    The APT and FreeCAD readers refuse these as they read; native CL and records made
    in code meet them here, so every reader and the API share one rule.  A hole of
    depth 0 drills nothing and a negative one drills upwards: both are CAM export
    errors, refused rather than guessed.
    """
    values = engine.values
    problem: str | None = None
    if isinstance(command, DrillSetup):
        if not command.depth > 0:
            problem = (f"depth {shown(command.depth)} must be greater than 0 (measured "
                       f"down from the top)")
        else:
            problem = _negative(command, ("peck", "first_peck", "dwell", "clearance"))
            if problem is None and command.first_peck is not None and not command.peck:
                problem = (f"a first peck of {shown(command.first_peck)} needs the later "
                           f"pecks' depth (peck is 0: no pecking)")
            elif problem is None and command.first_peck == 0:
                problem = "first peck 0 must be greater than 0 (or left out: the peck)"
    elif isinstance(command, Dwell):
        problem = _negative(command, ("dwell",))
    elif isinstance(command, SpindleOn):
        problem = _negative(command, ("spindle_speed",))
    elif isinstance(command, ToolChange):
        problem = _negative(command, ("tool_number", "tool_diameter", "tool_corner_radius"))
        if problem is None and command.tool_number < engine.post.machine.min_tool_number:
            problem = (f"tool number {command.tool_number} is not a tool of "
                       f"{engine.post.machine.name} (declare machine.tools.min_number: 0 "
                       f"where tool 0 is real)")
    feed = getattr(command, "feed", None)
    if problem is None and feed is not None and not feed > 0:
        problem = f"feed {shown(feed)} must be greater than 0"
    if problem is None and isinstance(command, (DrillSetup, CycleHole)):
        # the tool leaves every hole to the retract plane and moves on at rapid rate
        top, retract = values["top"], values["retract"]
        if retract < top - 1e-9:
            problem = f"retract {shown(retract)} is below the top of the hole ({shown(top)})"
    if problem is not None:
        raise CLError(f"{command.name}: {problem}", engine._where(command))


def check_limits(engine: Engine, command: CLCommand) -> None:
    machine = engine.post.machine
    values = engine.values
    checks: list[tuple[str, Any]] = []
    if isinstance(command, (RapidMove, LinearMove, ArcMove)):
        checks = [("x", values.get("x")), ("y", values.get("y")), ("z", values.get("z"))]
    elif isinstance(command, (DrillSetup, CycleHole)):
        checks = [("x", values.get("x")), ("y", values.get("y")),
                  ("z", values.get("bottom")), ("z", values.get("retract"))]
    bulges = engine._arc_extremes(command) if isinstance(command, ArcMove) else []
    for index, (axis, value) in enumerate(checks + bulges):
        limits = machine.travel.get(axis)
        if limits is not None and value is not None and not (
                limits[0] - 1e-9 <= value <= limits[1] + 1e-9):
            how = " (the arc reaches it between its end points)" if index >= len(checks) \
                else ""
            raise CLError(f"{axis.upper()} {shown(value)} is outside the travel of "
                          f"{machine.name} ({shown(limits[0])} to {shown(limits[1])}){how}",
                          engine._where(command))
    if isinstance(command, SpindleOn) and machine.spindle is not None:
        low, high = machine.spindle
        if not low <= command.spindle_speed <= high:
            raise CLError(f"spindle speed {shown(command.spindle_speed)} rpm is outside the "
                          f"range of {machine.name} ({shown(low)} to {shown(high)} rpm)",
                          engine._where(command))
    feed = getattr(command, "feed", None)
    if feed is not None and machine.max_feed is not None and feed > machine.max_feed:
        raise CLError(f"feed {shown(feed)} mm/min exceeds the maximum feed of {machine.name} "
                      f"({shown(machine.max_feed)} mm/min)", engine._where(command))
    if feed is not None and machine.min_feed is not None and feed < machine.min_feed:
        raise CLError(f"feed {shown(feed)} mm/min is below the minimum feed of {machine.name} "
                      f"({shown(machine.min_feed)} mm/min)", engine._where(command))
    if isinstance(command, ToolChange):
        if machine.max_tool_number is not None and command.tool_number > \
                machine.max_tool_number:
            raise CLError(f"tool {command.tool_number} does not exist on {machine.name} "
                          f"(tools 1 to {machine.max_tool_number})", engine._where(command))
        if machine.max_tool_diameter is not None and command.tool_diameter > \
                machine.max_tool_diameter:
            raise CLError(f"tool diameter {shown(command.tool_diameter)} mm exceeds the "
                          f"{shown(machine.max_tool_diameter)} mm {machine.name} takes",
                          engine._where(command))


def arc_extremes(engine: Engine, command: ArcMove) -> list[tuple[str, float]]:
    """The points of an arc farthest along its plane's axes, where its sweep passes them.

    An arc between two points inside the travel can bulge outside it; the extremes
    are where the arc crosses the axis directions through its centre (0, 90, 180 and
    270 degrees).  The third axis of a helix moves linearly, so its end points bound it.
    """
    values = engine.values
    axes = command.plane  # "xy", "zx" or "yz": the first two axes of the arc's plane
    start = [values.get(f"prev_{axis}") for axis in axes]
    end = [values.get(axis) for axis in axes]
    offsets = [values.get("ijk"["xyz".index(axis)]) for axis in axes]
    if None in start or None in end or None in offsets:
        return []
    centre = [s + o for s, o in zip(start, offsets, strict=True)]  # type: ignore[operator]  # no None: returned above
    radius = values["radius"]
    begin = math.atan2(start[1] - centre[1], start[0] - centre[0])
    finish = math.atan2(end[1] - centre[1], end[0] - centre[0])
    ccw = command.arc_direction == "ccw"
    sweep = (finish - begin) if ccw else (begin - finish)
    sweep %= 2 * math.pi
    if sweep < 1e-9:  # start and end together: a full circle
        sweep = 2 * math.pi
    extremes: list[tuple[str, float]] = []
    for quarter in range(4):
        angle = quarter * math.pi / 2
        travelled = ((angle - begin) if ccw else (begin - angle)) % (2 * math.pi)
        if travelled <= sweep:
            axis = axes[quarter % 2]
            sign = 1 if quarter in (0, 1) else -1
            extremes.append((axis, centre[quarter % 2] + sign * radius))
    return extremes


def check_cutting(engine: Engine, command: CLCommand) -> None:
    """Refuse motion the machine cannot make safely: no tool, no feed, no spindle.

    Motion before any tool change has no tool length offset to run with (unless the
    machine has no tool changer), a cutting move needs a feed the control can be
    given, and a cutting move with the spindle stopped, or turning at a speed the
    post writes as S0, breaks the tool.  Each is refused with the CL line.  A post
    without a ``spindle_on`` table runs a spindle the program does not switch (a
    router's), so only the first two apply to it.
    """
    if not isinstance(command, (RapidMove, LinearMove, ArcMove, DrillSetup, CycleHole)):
        return
    machine = engine.post.machine
    if not engine._tool_loaded and machine.tool_changer:
        raise CLError(f"{command.name} before any tool is loaded: the machine has a tool "
                      f"changer, and motion needs a tool and its length offset (give a "
                      f"tool_change first; a rapid in Z alone to a safe height before the "
                      f"first tool is a safe_retract, which the post writes as its own "
                      f"retract)", engine._where(command))
    if isinstance(command, RapidMove) or (engine._expanding and isinstance(
            command, (DrillSetup, CycleHole))):
        return  # an expanded hole is checked move by move
    values = engine.values
    if values.get("feed") is None:
        raise CLError(f"{command.name}: a cutting move before any feed is known",
                      engine._where(command))
    spindle_table = engine.post.commands.get("spindle_on")
    if spindle_table is None:
        return  # a post without spindle_on: the program does not run the spindle
    if values.get("spindle") == "off":
        raise CLError(f"{command.name}: a cutting move with the spindle stopped (no "
                      f"spindle_on, or a spindle_off since)",
                      engine._where(command))
    if engine._speed_stalls is not None:
        raise CLError(f"{command.name}: a cutting move with the spindle at "
                      f"{engine._speed_stalls}", engine._where(command))


def stalling_speed(engine: Engine, command: SpindleOn) -> str | None:
    """The speed of ``command`` as a message when no cut may run at it, else None."""
    spindle_table = engine.post.commands.get("spindle_on")
    speed = command.spindle_speed
    fmt = spindle_table.formats.get("spindle_speed") if spindle_table else None
    if not isinstance(speed, (int, float)):
        return None
    try:
        # too many digits (1e20) or no number (nan) is no stall: the machine's speed
        # range or the table's S word refuses it, with the CL line
        text = fmt.render(speed) if fmt is not None else None
    except (DigitsError, ValueError):
        return None
    if speed > 0 and (text is None or any(c in "123456789" for c in text)):
        return None
    written = f" (written {text!r})" if text is not None else ""
    return f"{shown(speed)} rpm{written}, set at CL line {command.line}"


def arc_as_line(engine: Engine, command: ArcMove) -> bool:
    """An arc the control would run as a full circle, or write as the line it is.

    A control reads an arc whose end equals its start as a full circle.  When the
    post's formats write the end of a short arc onto its start, the arc is shorter
    than the output resolution: it is written as the straight line it is within that
    resolution.  An arc that sweeps more than half a turn but ends (as written) where
    it began is refused: neither a line nor a full circle would be right.  A CL arc
    whose end is its start is a full circle, and stays one.
    """
    values = engine.values
    table = engine.post.commands.get("arc_move")
    a, b = {"xy": ("x", "y"), "zx": ("z", "x"), "yz": ("y", "z")}[command.plane]
    start = {axis: values.get(f"prev_{axis}") for axis in (a, b)}
    end = {axis: values.get(axis) for axis in (a, b)}
    if any(v is None for v in (*start.values(), *end.values())):
        return False
    # no None (returned above)
    if all(abs(start[axis] - end[axis]) < 1e-9  # type: ignore[operator]
           for axis in (a, b)):
        return False  # a full circle in the CL
    default = engine.post.formats.get("default")
    for axis in (a, b):
        fmt = (table.formats.get(axis) if table else None) or default
        if fmt is None or \
                fmt.render(start[axis]) != fmt.render(end[axis]):  # type: ignore[arg-type]  # (as above)
            return False
    centre_a = start[a] + values[{"x": "i", "y": "j", "z": "k"}[a]]
    centre_b = start[b] + values[{"x": "i", "y": "j", "z": "k"}[b]]
    begin = math.atan2(start[b] - centre_b, start[a] - centre_a)
    finish = math.atan2(end[b] - centre_b, end[a] - centre_a)
    sweep = (finish - begin) % (2 * math.pi)
    if command.arc_direction == "cw":
        sweep = 2 * math.pi - sweep
    if sweep > math.pi:
        raise CLError(f"arc_move: the arc sweeps {math.degrees(sweep):.9g} degrees, but "
                      f"the post writes its end onto its start, which the control would "
                      f"run as a full circle", engine._where(command))
    return True


def check_arc_radius(engine: Engine, command: ArcMove, table: CompiledCommand) -> None:
    """Refuse an arc whose radius rounds below the output resolution.

    Its centre is written onto its start (``G3 X10.001 Y0. I0. J0.``, ``R0.``, or a
    Heidenhain ``CC`` on the start point): every control alarms on an arc of radius 0
    or one whose end is not on its circle, a full circle included.  The resolution is
    the coarsest step of the formats that write the arc's centre or radius in the
    post's arc table (else the machine's ``resolution``); an arc that small is a CAM
    export mistake, refused with its CL line rather than written.
    """
    step = engine._arc_steps.get(id(table))
    if step is None:
        steps = [_format_step(fmt) for name, fmt in table.formats.items()
                 if name in _ARC_CENTRE]
        step = max(steps) if steps else (engine.post.machine.resolution or 0.0)
        engine._arc_steps[id(table)] = step
    radius = engine.values.get("radius")
    if radius is not None and radius < step / 2:
        raise CLError(f"arc_move: radius {shown(radius)} rounds below the output "
                      f"resolution {shown(step)}: the centre would be written on the "
                      f"start point, an arc no control can cut", engine._where(command))


def check_first_peck(engine: Engine, command: DrillSetup, table: CompiledCommand) -> None:
    """A first peck unlike the later ones is written, expanded or refused -- never dropped.

    A table that writes one peck depth would have the control drill every peck at it:
    deeper than the CAM allowed after the first, or shallower at the start.  The post
    writes ``first_peck`` (a control with a first infeed), expands the hole into moves
    (``expand: true``), or the hole is refused here with the table's name.
    """
    first, peck = engine.values.get("first_peck"), engine.values.get("peck")
    if first is None or peck is None or abs(first - peck) <= 1e-9 \
            or "first_peck" in table.writes:
        return
    raise CLError(f"{command.name}: a first peck of {shown(first)} and later pecks of "
                  f"{shown(peck)}, but the post's table '{table.table}' writes one peck "
                  f"depth (not first_peck): the control would drill every peck at it "
                  f"(write first_peck, or expand the hole into moves: expand_if: "
                  f"\"first_peck != peck\")",
                  engine._where(command))


def check_peck_written(engine: Engine, command: DrillSetup, table: CompiledCommand) -> None:
    """Refuse a peck the post's format writes as zero (``Q0.``, ``K0.0``, ``Q202=+0``).

    A control reads a zero peck as "no pecking" or alarms, or (some) takes the last
    Q it was given: the CL's pecked hole is not drilled as it says.  A peck of exactly
    0 is "no pecking" and is posted as ``single_peck`` before it gets here.  The
    formats are those the table writes ``peck`` and ``first_peck`` with: a parameter
    item's, an item computing ``-peck``-like values of it alone, or the ``str(peck,
    'fmt')`` of a text expression (a Heidenhain Q line).
    """
    formats = engine._peck_formats.get(id(table))
    if formats is None:
        formats = engine._peck_formats[id(table)] = _peck_formats(table, engine.post.formats)
    for name, fmt, written in formats:
        value = engine.values.get(name)
        if not isinstance(value, (int, float)) or not value > 0:
            continue
        try:
            text = fmt.render(written(engine) if written is not None else value)
        except (DigitsError, ValueError, ExprEvalError):
            continue  # too long, or no value: the item's own rendering words the error
        if not any(c in "123456789" for c in text):
            raise CLError(f"{command.name}: {name.replace('_', ' ')} {shown(value)} is "
                          f"written {text!r}: a peck that rounds to zero, which the "
                          f"control reads as no pecking or refuses", engine._where(command))


def _negative(command: CLCommand, names: tuple[str, ...]) -> str | None:
    """The first of ``names`` that is negative, as a message."""
    for name in names:
        value = getattr(command, name)
        if value is not None and value < 0:
            return f"{name.replace('_', ' ')} {shown(value)} must not be negative"
    return None


_PECKS = ("peck", "first_peck")


def _peck_formats(table: CompiledCommand, formats: Mapping[str, Any]
                  ) -> list[tuple[str, Any, Evaluator | None]]:
    """(peck parameter, format, what is written) for every way ``table`` writes a peck as a
    number; what is written is None for the peck itself, else the expression of it the
    format renders (``str(peck / 25.4 if program_units == 'inch' else peck, 'q')``: a
    peck in an inch program, which rounds to zero sooner)."""
    found: list[tuple[str, Any, Evaluator | None]] = []
    for block in table.blocks:
        for item in block.items:
            spec = item.spec
            if spec.kind == "param" and spec.param in _PECKS and spec.format is not None:
                found.append((spec.param, spec.format, None))
            elif spec.kind == "expr" and spec.expression is not None and \
                    spec.expression.tree is not None:
                names = spec.expression.names & set(_PECKS)
                if spec.format is not None and len(names) == 1 and \
                        spec.expression.names <= names:
                    found.append((next(iter(names)), spec.format, None))  # -peck, peck * 1000
                for node in nodes.walk(spec.expression.tree):
                    if not isinstance(node, nodes.Text) or node.format not in formats:
                        continue
                    if isinstance(node.value, nodes.Name) and node.value.name in _PECKS:
                        found.append((node.value.name, formats[node.format], None))
                        continue
                    pecks = {name.name for name in nodes.walk(node.value)
                             if isinstance(name, nodes.Name)} & set(_PECKS)
                    if len(pecks) == 1:
                        written = Compiler(spec.expression.source, formats) \
                            .compile(node.value).run
                        found.append((pecks.pop(), formats[node.format], written))
    return found


#: the parameters whose words place an arc's centre (or give its radius)
_ARC_CENTRE = frozenset(("i", "j", "k", "cx", "cy", "cz", "radius"))


def _format_step(fmt: Any) -> float:
    """The smallest step a number format writes, in the CL's units (mm)."""
    step = 1.0 if fmt.integer else 10.0 ** -fmt.decimals
    return step / abs(fmt.multiplier) if fmt.multiplier else step


def shown(value: object) -> str:
    """A number as a message shows it (any other value as str() writes it)."""
    if isinstance(value, float):
        return f"{value:g}"
    text = str(value)
    return text if len(text) <= 20 else f"{text[:10]}…({len(text.lstrip('-'))} digits)"
