"""The library's public API: what the CLI, the editor and the review tool call.

Nothing outside ``postdsl`` should import the engine's modules directly;
this module is the seam, so the engine can change inside without breaking
the tools on top.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from postdsl.cl.model import COMMANDS, CLCommand, ProgramStart, command_fields
from postdsl.cl.readers import read_cl, read_cl_text
from postdsl.compiler import CompiledPost, compile_post
from postdsl.engine import Engine, NCLine
from postdsl.errors import CLError, Location, PostError
from postdsl.expr import ExprEvalError
from postdsl.loader import PostSource, check, parse_yaml, read_source
from postdsl.program import ProgramSummary
from postdsl.resources import resolve_machine
from postdsl.writer import join_lines, write_atomic

__all__ = [
    "CLCommand", "CLError", "CompiledPost", "NCLine", "PostError", "PreviewResult",
    "compile_source", "load_post", "load_post_text", "post_commands", "post_text",
    "posting_time", "preview_command", "read_cl", "read_cl_text", "without_block_number",
    "write_atomic",
]


def load_post(machine: str | Path) -> CompiledPost:
    """A bundled machine's name or a post path -> a compiled post, or a PostError."""
    return compile_source(read_source(resolve_machine(str(machine))))


def load_post_text(text: str, file: str = "<post>") -> CompiledPost:
    """Compile a post from YAML text (the editor's unsaved buffer)."""
    return compile_source(PostSource(file, parse_yaml(text, file), text))


def compile_source(source: PostSource) -> CompiledPost:
    return compile_post(check(source))


def posting_time() -> datetime:
    """Now, or ``SOURCE_DATE_EPOCH`` (UTC) when set, so posted programs are reproducible."""
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch:
        try:
            return datetime.fromtimestamp(int(epoch), tz=UTC)
        except (ValueError, OverflowError):
            raise CLError(f"SOURCE_DATE_EPOCH must be whole seconds, not '{epoch}'") from None
    return datetime.now().astimezone()


def post_commands(post: CompiledPost, commands: Iterable[CLCommand], *,
                  cl_file: str = "<cl>", now: datetime | None = None) -> list[NCLine]:
    """Post CL commands; every line with its origin.  Raises CLError on bad input."""
    engine = Engine(post, now=now or posting_time(), cl_file=cl_file)
    return list(engine.run(commands))


def post_text(post: CompiledPost, lines: Iterable[NCLine]) -> str:
    """NC lines -> the program text with the post's line ending."""
    return join_lines((line.text for line in lines), post.line_ending, post.final_newline)


def without_block_number(post: CompiledPost, line: NCLine) -> str:
    """``line``'s text without its block-number word (``N120 G1 X5.`` -> ``G1 X5.``).

    A review compares programs on these keys, so a new start, increment or one
    more numbered block near the top shows up as renumbering, not as a change
    of every line.  Only lines the post numbered lose anything: the line's
    table block says whether it was numbered, so a comment that happens to
    start with ``N12`` keeps it.
    """
    table = (post.custom_cycles.get(line.table) if line.command == "custom_cycle"
             else post.commands.get(line.table))
    if table is None or not 0 <= line.block < len(table.blocks) \
            or not table.blocks[line.block].numbered:
        return line.text
    numbering = post.numbering
    text = line.text
    if not text.startswith(numbering.prefix):
        return text
    match = _BLOCK_NUMBER.match(text, len(numbering.prefix))
    if match is None or not text.startswith(numbering.suffix, match.end()):
        return text
    return text[match.end() + len(numbering.suffix):]


#: the number of a block-number word, however its format pads or points it
_BLOCK_NUMBER = re.compile(r" *[-+]?[0-9]+(?:\.[0-9]*)?")


# --- preview --------------------------------------------------------------------------------


@dataclass
class PreviewResult:
    """A command's blocks for sample values, with what its conditions said."""

    command: str
    lines: list[NCLine]
    values: dict[str, Any]
    #: (path of the block or item in the post, condition source, result)
    conditions: list[tuple[tuple[Any, ...], str, bool]] = field(default_factory=list)
    error: str | None = None


_SAMPLE_ORDER = ("program_start", "tool_change", "spindle_on", "coolant_on", "rapid_move",
                 "linear_move")


def _sample_engine(post: CompiledPost, now: datetime) -> Engine:
    """An engine whose state looks like the middle of a typical program."""
    engine = Engine(post, now=now, cl_file="<preview>")
    for name in _SAMPLE_ORDER:
        record = COMMANDS[name](**{k: v for k, v in COMMANDS[name].example.items()
                                   if k != "cmd"})
        engine.changed = set()
        engine._apply(record, post.commands.get(name) or _EMPTY)  # state only, nothing written
    engine.load_summary(ProgramSummary(
        tools=[1, 2], machining_time=238.0,
        extents={"min_x": 40.0, "max_x": 100.0, "min_y": 20.0, "max_y": 20.0,
                 "min_z": 16.9957, "max_z": 150.0}))
    engine.registers.clear()
    return engine


def preview_command(post: CompiledPost, command: str,
                    overrides: Mapping[str, Any] | None = None,
                    now: datetime | None = None) -> PreviewResult:
    """PPU's Preview: one command's blocks for its sample values plus ``overrides``.

    ``command`` is a CL command name or a custom cycle name.  Errors in the
    values (e.g. a parameter without a value used in arithmetic) come back in
    ``error`` instead of raising, so an editor can show them beside the table.
    """
    from postdsl.cl.model import CustomCycle

    table = post.commands.get(command) or post.custom_cycles.get(command)
    if table is None:
        raise PostError(f"the post has no table for '{command}'", Location(post.file))
    engine = _sample_engine(post, now or posting_time())
    sample = {**table.preview, **(overrides or {})}
    if command in post.custom_cycles and command not in post.commands:
        params = {k: v for k, v in sample.items() if k in table.parameters}
        record: CLCommand = CustomCycle(cycle=command, params=params)
        rest = {k: v for k, v in sample.items() if k not in table.parameters}
    else:
        cls = COMMANDS[command]
        names = {f.name for f in command_fields(cls)}
        fields = {k: v for k, v in cls.example.items() if k != "cmd"}
        fields.update({k: v for k, v in sample.items() if k in names})
        record = cls(**fields)
        rest = {k: v for k, v in sample.items() if k not in names}
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


class _EmptyTable:
    """Stands in for a missing table while the preview's sample state is built."""

    table = ""
    parameters: Mapping[str, Any] = {}


_EMPTY: Any = _EmptyTable()


def post_file(machine: str | Path, cl_path: str | Path, output: str | Path | None = None,
              fmt: str | None = None) -> str:
    """Post a CL file with a machine; write ``output`` atomically when given.  Returns the text."""
    post = load_post(machine)
    commands = read_cl(cl_path, fmt)
    text = post_text(post, post_commands(post, commands, cl_file=str(cl_path)))
    if output is not None:
        try:
            write_atomic(output, text)
        except OSError as exc:
            raise CLError(f"cannot write the NC program: {exc}", Location(str(output))) \
                from None
    return text
