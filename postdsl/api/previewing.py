"""Previewing one table: a command's blocks for sample values, as the editor shows
them beside the table (PPU's Preview), and why a name has no preview.

Apart from posting because the sample program a preview runs in is the editor's, not a
CL file's, and its results (:mod:`postdsl.results`) are imported only when asked for.
"""

from __future__ import annotations

from collections.abc import Mapping
from datetime import datetime
from typing import TYPE_CHECKING, Any

from postdsl.api.posting import posting_time
from postdsl.api.tracing import word_writers
from postdsl.cl.model import (
    COMMANDS,
    DRILL_SETUPS,
    EVENTS,
    ProgramStart,
    ToolChange,
    command_fields,
)
from postdsl.cl.native import record_to_command
from postdsl.compile.compiler import CompiledPost
from postdsl.errors import CLError, Location, PostError
from postdsl.lang.expr import ExprEvalError
from postdsl.run.engine import Engine
from postdsl.run.program import ProgramSummary

if TYPE_CHECKING:
    from postdsl.results import PreviewResult


_SAMPLE_ORDER = ("program_start", "tool_change", "spindle_on", "coolant_on", "rapid_move",
                 "linear_move")


def _sample_engine(post: CompiledPost, now: datetime, command: str = "") -> Engine:
    """An engine whose state looks like the middle of a typical program.

    A further hole or the end of a cycle only makes sense inside a cycle, so
    for those the post's first drilling setup is applied too.
    """
    order = list(_SAMPLE_ORDER)
    if command in ("cycle_hole", "cycle_end"):
        order.append(next((n for n in DRILL_SETUPS if n in post.commands), DRILL_SETUPS[0]))
    records = [COMMANDS[name](**{k: v for k, v in COMMANDS[name].example.items() if k != "cmd"})
               for name in order]
    sample_tools = {1: ToolChange(tool_number=1, tool_type="drill", tool_diameter=8),
                    2: ToolChange(tool_number=2, tool_type="tap", tool_diameter=10)}
    summary = ProgramSummary(
        tools=[1, 2], tool_records=sample_tools, machining_time=238.0,
        extents={"min_x": 40.0, "max_x": 100.0, "min_y": 20.0, "max_y": 20.0,
                 "min_z": 16.9957, "max_z": 150.0})
    return Engine.in_state(post, records, summary, now=now, cl_file="<preview>")


def preview_command(post: CompiledPost, command: str,
                    overrides: Mapping[str, Any] | None = None,
                    now: datetime | None = None) -> PreviewResult:
    """PPU's Preview: one command's blocks for its sample values plus ``overrides``.

    ``command`` is a CL command name or a custom cycle name.  Errors in the
    values (a text where the CL has a number, a parameter without a value used
    in arithmetic) come back in ``error`` instead of raising, so an editor can
    show them beside the table.
    """
    from postdsl.results import PreviewResult

    table = post.commands.get(command) or post.custom_cycles.get(command)
    if table is None:
        raise PostError(f"the post has no table for '{command}'", Location(post.file))
    known = post.source.known_names | frozenset(table.parameters)
    for name in overrides or {}:
        if name not in known:  # '--set feeed=100' must not be ignored in silence
            from difflib import get_close_matches  # a mistyped name only

            close = get_close_matches(name, sorted(known), n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            return PreviewResult(command, [], dict(overrides or {}),
                                 error=f"unknown parameter '{name}'{hint}")
    engine = _sample_engine(post, now or posting_time(), command)
    sample = {**table.preview, **(overrides or {})}
    if command in post.custom_cycles and command not in post.commands:
        params = {k: v for k, v in sample.items() if k in table.parameters}
        raw: dict[str, Any] = {"cmd": "custom_cycle", "cycle": command, "params": params}
        rest = {k: v for k, v in sample.items() if k not in table.parameters}
    else:
        cls = COMMANDS.get(command) or EVENTS[command]
        names = {f.name for f in command_fields(cls)}
        raw = dict(cls.example)
        raw.update({k: v for k, v in sample.items() if k in names})
        rest = {k: v for k, v in sample.items() if k not in names}
    try:
        # sample values are checked as CL values are: 'x=abc' must not reach the engine
        # an event (operation_end) is no CL record: it carries no values to read
        record = cls() if command in EVENTS else record_to_command(raw, Location("<preview>"))
    except CLError as exc:
        return PreviewResult(command, [], dict(sample), error=exc.message)
    engine.values.update(rest)
    if isinstance(record, ProgramStart):
        engine.values.update({k: v for k, v in rest.items()})
    result = PreviewResult(command, [], {})
    try:
        result.lines = list(engine.post_command(record))
    except (CLError, ExprEvalError) as exc:
        result.error = exc.message if isinstance(exc, CLError) else str(exc)
    result.values = dict(engine.values)
    for block in table.blocks:
        for path, condition in [(block.path, block.condition)] + [
                (item.path, item.condition) for item in block.items]:
            if condition is None:
                continue
            try:
                fired = bool(condition.evaluate(engine))
            except ExprEvalError:
                fired = False
            result.conditions.append((path, condition.source, fired))
    return result


def unknown_command_message(post: CompiledPost, name: str) -> str:
    """Why ``name`` has no preview: the NC word's writers, or the valid command names."""
    from postdsl.run.trace import looks_like_word  # preview only, not posting

    if looks_like_word(name):
        writers = word_writers(post.source.model, name)
        if writers:
            return "\n".join(w.sentence(name.strip().upper()) for w in writers)
        return f"no table of {post.file} writes '{name}'"
    tables = sorted(set(post.commands) | set(post.custom_cycles))
    from difflib import get_close_matches  # a mistyped name only

    close = get_close_matches(name, tables, n=1)
    hint = f"did you mean '{close[0]}'? " if close else ""
    known = "" if name not in COMMANDS else f"'{name}' is a CL command, but "
    return (f"{known}the post has no table for '{name}'; {hint}"
            f"its tables: {', '.join(tables)}")
