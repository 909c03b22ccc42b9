"""The library's public API: what the CLI, the editor and the review tool call.

Nothing outside ``postdsl`` should import the engine's modules directly;
this module is the seam, so the engine can change inside without breaking
the tools on top.
"""

from __future__ import annotations

import io
import os
import re
import sys
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any, BinaryIO, TextIO

from postdsl.cl.model import (
    COMMANDS,
    DRILL_SETUPS,
    EVENTS,
    GROUPS,
    PARAMETERS,
    CLCommand,
    DrillSetup,
    LinearMove,
    ParamInfo,
    PlainMove,
    ProgramStart,
    RapidMove,
    ToolChange,
    command_fields,
    with_previous,
)
from postdsl.cl.native import record_to_command
from postdsl.cl.readers import read_cl, read_cl_text
from postdsl.cl.source import STDIN, CLSource
from postdsl.compile.compiler import CompiledCommand, CompiledPost, compile_post, post_reads
from postdsl.compile.runtime import NCLine
from postdsl.errors import CLError, Location, PostError, VerifyError, printable
from postdsl.lang.expr import ExprError, ExprEvalError, compile_expr
from postdsl.lang.formats import FormatSpecError, NumberFormat
from postdsl.lang.loader import PostSource, check, parse_yaml
from postdsl.lang.post import Post, build_post
from postdsl.lang.post.build import build_item, format_stand_ins
from postdsl.lang.post.build import known_names as document_names
from postdsl.lang.post.nodes import (
    Block,
    Command,
    CustomCycle,
    Expr,
    ExprItem,
    Item,
    Option,
    ParamItem,
    PlainText,
    Structure,
    Table,
    TextItem,
    Use,
)
from postdsl.lang.post.options import resolve as resolve_option
from postdsl.resources import machines_dir, resolve_machine
from postdsl.run.engine import Engine
from postdsl.run.program import MOVE_VALUES, ProgramSummary, summarize_source
from postdsl.run.writer import (
    UnsafeTarget,
    copy_spooled,
    join_lines,
    open_atomic,
    spooled,
    write_atomic,
)

if TYPE_CHECKING:
    from postdsl.check.controls import NCInput
    from postdsl.check.controls.events import Origin
    from postdsl.check.toolpath import VIEW_AXES, LineSource, Segment, Toolpath, projector
    from postdsl.check.verify import Verdict
    from postdsl.newmachine import NewMachine, new_machine
    from postdsl.results import CheckResult, ExpressionCheck, PostProblem, PreviewResult
    from postdsl.run.trace import TracedLine, WordMeaning, WordWriter, looks_like_word

#: names of the API that live in modules posting does not need (the control models, the
#: toolpath and its pictures, tracing, verifying, new machines, what the editor's previews
#: and checks return): each is imported when first asked for (:func:`__getattr__`), so
#: ``postdsl post`` does not load them
_LAZY = {
    "PreviewResult": "postdsl.results", "PostProblem": "postdsl.results",
    "CheckResult": "postdsl.results", "ExpressionCheck": "postdsl.results",
    "NewMachine": "postdsl.newmachine", "new_machine": "postdsl.newmachine",
    "Segment": "postdsl.check.toolpath", "Toolpath": "postdsl.check.toolpath",
    "VIEW_AXES": "postdsl.check.toolpath", "projector": "postdsl.check.toolpath",
    "TracedLine": "postdsl.run.trace", "WordWriter": "postdsl.run.trace",
    "WordMeaning": "postdsl.run.trace",
    "looks_like_word": "postdsl.run.trace", "Verdict": "postdsl.check.verify",
    "control_model": "postdsl.check.controls",
}


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


__all__ = [
    "VIEW_AXES",
    "Block",
    "CLCommand",
    "CLError",
    "CheckResult",
    "Command",
    "CompiledPost",
    "CustomCycle",
    "Expr",
    "ExprItem",
    "ExpressionCheck",
    "FormatSpecError",
    "Item",
    "Location",
    "NCLine",
    "NewMachine",
    "Option",
    "Options",
    "ParamInfo",
    "ParamItem",
    "PlainText",
    "Post",
    "PostError",
    "PostProblem",
    "PostSource",
    "PreviewResult",
    "Segment",
    "Structure",
    "Table",
    "TextItem",
    "Toolpath",
    "TracedLine",
    "Use",
    "Verdict",
    "VerifyError",
    "WordMeaning",
    "WordWriter",
    "arguments_swapped",
    "check_expression",
    "check_source",
    "command_doc",
    "command_groups",
    "commands_setting",
    "compile_source",
    "control_events",
    "corpus_programs",
    "example_program",
    "explain_line",
    "explain_text",
    "item_model",
    "iter_post",
    "load_post",
    "load_post_text",
    "looks_like_word",
    "new_machine",
    "parameters",
    "place_in_post",
    "plot_file",
    "post_commands",
    "post_model",
    "post_options",
    "post_text",
    "post_verified",
    "posting_time",
    "preview_command",
    "projector",
    "read_cl",
    "read_cl_text",
    "render_number",
    "resolve_option",
    "same_motion",
    "toolpath",
    "toolpath_file",
    "toolpath_of_lines",
    "trace_line",
    "unknown_command_message",
    "verify_commands",
    "verify_file",
    "without_block_number",
    "word_meaning",
    "word_writers",
    "write_atomic",
    "write_program",
]


#: option values by name, as ``--option NAME=VALUE`` gives them (text) or typed values
Options = Mapping[str, Any]


def load_post(machine: str | Path, options: Options | None = None) -> CompiledPost:
    """A bundled machine's name or a post path -> a compiled post, or a PostError.

    ``options`` sets the post's options (the others keep their defaults); an unknown
    name or a value the option's type or choices refuse is a PostError at the option.
    """
    # the checked post from the cache when it is there: no YAML parse, no checks
    from postdsl.compile.postcache import load_checked

    return compile_post(load_checked(resolve_machine(str(machine))), options)


def load_post_text(text: str, file: str = "<post>", options: Options | None = None) \
        -> CompiledPost:
    """Compile a post from YAML text (the editor's unsaved buffer)."""
    return compile_source(PostSource(file, parse_yaml(text, file), text), options)


def compile_source(source: PostSource, options: Options | None = None) -> CompiledPost:
    return compile_post(check(source), options)


def post_model(data: Mapping[str, Any], file: str = "<post>") -> Post:
    """The typed model of a post document that may not be valid (the editor's, mid-edit):
    whatever of it has the right shape."""
    return build_post(data, file, lenient=True)


def item_model(value: Any) -> Item:
    """A YAML item (a string or a mapping, as the clipboard holds one) as a model item."""
    return build_item(value)


def _model(post: Post | Mapping[str, Any]) -> Post:
    return post if isinstance(post, Post) else post_model(post)


def post_options(post: CompiledPost | Post) -> list[Option]:
    """The options a post declares, in file order (name, type, default, choices…)."""
    model = post.source.model if isinstance(post, CompiledPost) else post
    return list(model.options.values())


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


def iter_post(post: CompiledPost, commands: Iterable[CLCommand], *, cl_file: str = "<cl>",
              now: datetime | None = None) -> Iterator[NCLine]:
    """Post CL commands line by line, so a caller can stop early or report progress."""
    engine = Engine(post, now=now or posting_time(), cl_file=cl_file)
    return engine.run(commands)


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


def post_file(machine: str | Path, cl_path: str | Path, output: str | Path | None = None,
              fmt: str | None = None, feed_units: str | None = None,
              verify: bool = True, options: Options | None = None,
              notice: Callable[[str], None] | None = None) -> str:
    """Post a CL file with a machine; write ``output`` atomically when given.  Returns the text.

    ``feed_units`` ("mm/min" or "mm/s") says what F means in FreeCAD G-code whose text
    does not tell (see the FreeCAD reader).  The program is verified as it is posted
    (see :func:`write_program`; ``verify=False`` does not): a divergence raises
    VerifyError and nothing is written.
    The text is held to be returned; :func:`write_program` posts a program of any length
    in flat memory.
    """
    collected = io.StringIO()
    write_program(machine, cl_path, output, fmt, feed_units, verify=verify,
                  copy_to=collected, options=options, notice=notice)
    return collected.getvalue()


#: what :func:`write_program` tells ``notice`` of a post it cannot verify
NO_CONTROL_MODEL = ("the post declares no machine/control and machine/resolution: the program "
                    "is posted without verifying it")


def write_program(machine: str | Path, cl_path: str | Path, output: str | Path | None = None,
                  fmt: str | None = None, feed_units: str | None = None, *,
                  verify: bool = True, progress: PassProgress | None = None,
                  stdout: BinaryIO | None = None, copy_to: TextIO | None = None,
                  options: Options | None = None,
                  notice: Callable[[str], None] | None = None) -> int:
    """Post a CL file as a stream, in two passes; returns the number of NC lines.

    The first pass reads the whole file for what headers need (tools, extents,
    time; the moves are folded only for a post that reads an extent or the time)
    and every reader check; the second posts and writes each line as it is
    made, into a temporary file renamed over ``output`` once the program is complete
    (:func:`postdsl.run.writer.open_atomic`), or, without ``output``, copied to
    ``stdout`` once complete: a CL error halfway leaves nothing written.  ``cl_path``
    ``-`` is standard input.  ``progress(pass_name, bytes_read, bytes_total)`` is told
    how far each pass has read (total None when the size is not known up front).
    ``copy_to`` receives the text as well (:func:`post_file` returns it).  ``options``
    are the post's option values (see :func:`load_post`).

    **Verified by default**: every line is replayed through the model of the
    machine's control as it is written, against the CL's own records (the ones the
    posting pass replays; never the engine's values), and a program that does not do
    what the CL says raises VerifyError naming the CL line and the NC line: nothing is
    written, neither ``output`` nor ``stdout`` (``copy_to`` may have received part of
    it).  ``verify=False`` posts without it.  A post without a control model
    (``machine.control`` and ``machine.resolution``) is posted unverified, and
    ``notice`` is told so (:data:`NO_CONTROL_MODEL`), once.
    """
    post = load_post(machine, options)
    if verify and (post.machine.control is None or post.machine.resolution is None):
        verify = False
        if notice is not None:
            notice(NO_CONTROL_MODEL)
    keep = ((_input_file(cl_path), "the CL program being posted"), (post.file, "the post"))
    with CLSource(cl_path, fmt, feed_units) as source:
        summary = summarize_source(source, post.machine.rapid_rate,
                                   _pass(progress, "reading", source.size),
                                   moves=_reads_move_values(post),
                                   kinematics=post.machine.kinematics)
        records = source.records(_pass(progress, "posting", source.size))
        engine = Engine(post, now=posting_time(), cl_file=source.name)
        if output is None:
            with spooled() as stream:
                count = _write_lines(post, engine, records, summary, stream, copy_to,
                                     source.name if verify else None)
                if stdout is not None:
                    copy_spooled(stream, stdout)
                    stdout.flush()
            return count
        try:
            with open_atomic(output, keep) as stream:
                return _write_lines(post, engine, records, summary, stream, copy_to,
                                    source.name if verify else None)
        except UnsafeTarget as exc:
            raise CLError(f"cannot write the NC program: {exc.message}",
                          Location(str(output))) from None
        except OSError as exc:
            raise _unwritable(output, exc, "the NC program") from None


def _reads_move_values(post: CompiledPost) -> bool:
    """Whether ``post`` may read a summary value only the moves give (an extent, the
    machining time): else its first pass leaves the moves out (see
    :func:`~postdsl.run.program.summarize_source`)."""
    reads = post_reads(post)
    return reads is None or not reads.isdisjoint(MOVE_VALUES)


#: a progress callback: (pass name, bytes read, bytes in the file or None)
PassProgress = Callable[[str, int, "int | None"], None]


def _pass(progress: PassProgress | None, name: str,
          total: int | None) -> Callable[[int], None] | None:
    if progress is None:
        return None
    return lambda done: progress(name, done, total)


def _write_lines(post: CompiledPost, engine: Engine,
                 records: Iterable[CLCommand | PlainMove], summary: ProgramSummary,
                 stream: TextIO, copy_to: TextIO | None, verify_file: str | None) -> int:
    """Post ``records`` into ``stream`` a batch at a time, joined as :func:`post_text` joins.

    With ``verify_file`` (the CL file's name) the lines are replayed through the
    control model as they are written (:func:`_verified_batches`); a divergence raises
    VerifyError (and the caller's atomic output is then not written).
    """
    ending = post.line_ending
    write = stream.write if copy_to is None else _tee(stream.write, copy_to.write)
    count = 0
    last = ""

    def put(batch: list[str]) -> None:  # one write per thousand lines, not one per line
        nonlocal count, last
        write(ending.join(batch) if count == 0 else ending + ending.join(batch))
        count += len(batch)
        last = batch[-1]

    if verify_file is None:
        for batch in engine.texts(records, summary):
            put(batch)
    else:
        verdict = _post_verified(post, engine, records, summary, verify_file, put)
        if verdict.divergence is not None:
            raise VerifyError(str(verdict.divergence))
    if post.final_newline and (count > 1 or last):
        write(ending)
    return count


def _post_verified(post: CompiledPost, engine: Engine,
                   records: Iterable[CLCommand | PlainMove], summary: ProgramSummary,
                   cl_file: str, put: Callable[[list[str]], None]) -> Verdict:
    """Post ``records`` a batch of lines at a time into ``put``, each line replayed
    through the control model and compared with the CL as it comes; the verdict.

    The two sides stay independent: the NC side is the text, read by the control model
    as the control reads it; the CL side is made from the same CL records the engine
    posts, in one pass over them shared through :func:`itertools.tee` (the records are
    the CL's truth; the engine's values are never read).  The comparison stops at the
    first divergence: the caller writes atomically, so nothing is then written.
    """
    import itertools

    from postdsl.check.controls.events import Origin  # verifying only, as the control models

    nc_records, cl_records = itertools.tee(records)
    current: list[Any] = [[], 0]  # the sources of the batch being replayed, lines before it
    notes = _LineNotes(post)

    def nc_lines() -> Iterator[NCInput | str]:
        number = 0
        note_of, as_input = notes.of, notes.input
        # a straight move's lane whose table declares nothing: its lines are plain text
        plain_lane = {cls: note_of((cls,)) is None for cls in (RapidMove, LinearMove)}
        for batch, sources in engine.sourced_texts(nc_records, summary):
            put(batch)
            current[0], current[1] = sources, number
            for text, source in zip(batch, sources, strict=True):
                number += 1
                if source.__class__ is tuple and plain_lane[source[0]]:
                    yield text
                    continue
                note = note_of(source)
                yield text if note is None else as_input(number, text, note)

    def cl_of(nc_line: int) -> Origin | None:
        sources, before = current
        if not 0 < nc_line - before <= len(sources):
            return None
        source = sources[nc_line - before - 1]
        line = source[1] if source.__class__ is tuple else source.cl_line
        return Origin(line, "", cl_file) if line else None

    return _compare(post, nc_lines(), cl_records, cl_file, cl_of, engine.expanded_setups,
                    plain=True)


class _LineNotes:
    """What each table declares to verify (``verify:``), worked out once per table."""

    def __init__(self, post: CompiledPost) -> None:
        self.post = post
        self._by_table: dict[tuple[str, str], tuple[str | None, frozenset[str]] | None] = {}
        self._by_class: dict[type, tuple[str | None, frozenset[str]] | None] = {}

    def of(self, source: Any) -> tuple[str | None, frozenset[str]] | None:
        """(declared motion, declared words) of a line's table; None: nothing declared."""
        if source.__class__ is tuple:  # a straight move's lane: its class's table
            cls = source[0]
            if cls not in self._by_class:
                self._by_class[cls] = _declared(self.post.commands.get(cls.name))
            return self._by_class[cls]
        key = (source.command, source.table)
        if key not in self._by_table:
            self._by_table[key] = _declared(_table_of(self.post, source.command, source.table))
        return self._by_table[key]

    @staticmethod
    def input(number: int, text: str, note: tuple[str | None, frozenset[str]]) -> NCInput:
        from postdsl.check.controls import NCInput  # replaying only: posting needs no control model

        return NCInput(number, text, note[0], note[1])


def _table_of(post: CompiledPost, command: str, table: str) -> CompiledCommand | None:
    return post.custom_cycles.get(table) if command == "custom_cycle" \
        else post.commands.get(table)


def _declared(table: CompiledCommand | None) -> tuple[str | None, frozenset[str]] | None:
    """A table's ``verify:`` for the control model, or None when it declares nothing."""
    if table is None:
        return None
    words = _declared_words(table)
    if table.verify_motion is None and not words:
        return None
    return table.verify_motion, words


def _tee(first: Callable[[str], Any], second: Callable[[str], Any]) -> Callable[[str], None]:
    def write(text: str) -> None:
        first(text)
        second(text)
    return write


def _input_file(cl_path: str | Path) -> str | Path | int:
    """The CL file as :func:`~postdsl.run.writer.open_atomic` compares it with the target:
    ``-`` is standard input, by its descriptor (redirected from a file, that file)."""
    if str(cl_path) != STDIN:
        return cl_path
    try:
        return sys.stdin.fileno()
    except (AttributeError, ValueError, OSError):  # no standard input, or not a file
        return cl_path


def _write_output(output: str | Path, text: str, what: str,
                  keep: Iterable[tuple[str | Path | int, str]]) -> None:
    """Write a result atomically; every refusal a CLError naming ``output`` and saying why."""
    try:
        write_atomic(output, text, keep=keep)
    except UnsafeTarget as exc:
        raise CLError(f"cannot write {what}: {exc.message}", Location(str(output))) from None
    except OSError as exc:
        raise _unwritable(output, exc, what) from None


def _unwritable(output: str | Path, exc: OSError, what: str) -> CLError:
    """Why ``output`` cannot be written, in terms of the path the user gave.

    The OS names the temporary file the program is written through.
    """
    folder = Path(output).parent
    reason = (f"the folder {printable(str(folder))} does not exist"
              if not folder.exists() else
              f"{printable(str(folder))} is not a folder" if not folder.is_dir() else
              exc.strerror or str(exc))
    return CLError(f"cannot write {what}: {reason}", Location(str(output)))


# --- verify: does the NC program do what the CL says? -----------------------------------------


def verify_commands(post: CompiledPost, commands: Sequence[CLCommand], *,
                    cl_file: str = "<cl>", now: datetime | None = None,
                    written: list[NCLine] | None = None) -> Verdict:
    """Post ``commands`` and replay the program through the post's control model.

    The NC lines are posted, replayed and compared as a stream; ``written``,
    when given, collects them.  A post without ``machine.control`` is a PostError.
    """
    _control_of(post)
    engine = Engine(post, now=now or posting_time(), cl_file=cl_file)
    return _replay(post, engine.run(commands), commands, cl_file,
                   written.append if written is not None else None, engine.expanded_setups)


def post_verified(post: CompiledPost, commands: Sequence[CLCommand],
                  on_line: Callable[[NCLine], None], *, cl_file: str = "<cl>",
                  now: datetime | None = None) -> Verdict:
    """Post ``commands`` once: every line to ``on_line``, and the verdict of replaying them.

    What :func:`verify_commands` does, for a caller that shows the whole program beside
    its verdict (the editor's preview): the lines after a divergence are still posted
    and handed on, so the program is not posted a second time to be shown.  A refusal
    of the engine is raised once the lines before it have been handed on.
    """
    _control_of(post)
    engine = Engine(post, now=now or posting_time(), cl_file=cl_file)
    lines = engine.run(commands)
    verdict = _replay(post, lines, commands, cl_file, on_line, engine.expanded_setups)
    for line in lines:  # past a divergence: the rest of the program, as post writes it
        on_line(line)
    return verdict


def _control_of(post: CompiledPost) -> Any:
    """The control model that replays the post's programs, or a PostError."""
    machine = post.machine
    if machine.control is None or machine.resolution is None:
        raise PostError("the post declares no machine/control and machine/resolution: "
                        "postdsl verify needs the control model to replay the program with",
                        Location(post.file))
    from postdsl.check.controls import control_model  # the control models: verifying only

    model = control_model(machine.control, calculator_input=machine.calculator_input)
    model.set_kinematics(machine.kinematics)
    return model


def _replay(post: CompiledPost, posted: Iterable[NCLine], commands: Iterable[CLCommand],
            cl_file: str, on_line: Callable[[NCLine], None] | None,
            expanded_setups: Sequence[bool]) -> Verdict:
    """Compare the posted lines, replayed through the control model, with the CL commands.

    Both sides are streams read in step (``commands`` is a pass over the same CL the
    lines were posted from); ``on_line`` sees every posted line as it is replayed.
    ``expanded_setups`` is the engine's record of which drilling setups it wrote as
    moves (``expand: true``, or ``expand_if:`` holding): the NC side is read first, so
    the engine has posted a setup by the time the CL side reaches its first hole.
    """
    from postdsl.check.controls.events import Origin  # verifying only, as the control models

    latest: dict[int, int] = {}  # the NC line being replayed -> its CL line

    def nc_lines() -> Iterator[NCInput]:
        for number, line in enumerate(posted, start=1):
            if on_line is not None:
                on_line(line)
            latest.clear()
            latest[number] = line.cl_line
            yield _nc_input(post, number, line)

    def cl_of(nc_line: int) -> Origin | None:
        cl_line = latest.get(nc_line)
        return Origin(cl_line, "", cl_file) if cl_line else None

    return _compare(post, nc_lines(), commands, cl_file, cl_of, expanded_setups)


def _compare(post: CompiledPost, nc_lines: Iterable[NCInput | str],
             records: Iterable[CLCommand | PlainMove], cl_file: str,
             cl_of: Callable[[int], Origin | None], expanded_setups: Sequence[bool], *,
             plain: bool = False) -> Verdict:
    """The NC lines replayed through the post's control model, compared with the CL's
    ``records``.  ``plain``: both sides hand plain feed moves on as tuples (the fast path
    of :mod:`postdsl.check.verify`; the same verdict, the same messages)."""
    from postdsl.check.motion import cl_events  # verifying only, as the control models
    from postdsl.check.verify import verify_events

    model = _control_of(post)
    model.plain_feeds = plain
    if post.machine.cutter_compensation == "control":
        records = _contour_as_tool_centre(model, records, cl_file)

    def declared(command: CLCommand) -> str | None:
        table = (post.custom_cycles.get(getattr(command, "cycle", ""))
                 if command.name == "custom_cycle" else post.commands.get(command.name))
        return table.verify_motion if table is not None else None

    arc_table = post.commands.get("arc_move")
    chord_tolerance = arc_table.tolerance if arc_table is not None and arc_table.expand \
        else None

    at: list[Any] = [None, -1]  # the setup the CL side is at, and its index (asked per hole)
    # a post none of whose drilling tables can write its holes as moves expands none
    expands = any(table.expand or table.expand_if is not None
                  for name, table in post.commands.items() if name in DRILL_SETUPS)

    def expanded(setup: DrillSetup) -> bool:
        if at[0] is not setup:
            at[0], at[1] = setup, at[1] + 1
        index: int = at[1]
        if index < len(expanded_setups):
            return expanded_setups[index]
        table = post.commands.get(setup.name)  # not posted: the programs diverged before
        return table is not None and table.expand

    return verify_events(model.replay(nc_lines),
                         cl_events(records, cl_file, declared, expanded if expands else None,
                                   chord_tolerance, plain=plain,
                                   kinematics=post.machine.kinematics),
                         # not None: _control_of refused a post without a resolution
                         post.machine.resolution, cl_of, _axis_steps(model), cl_file)  # type: ignore[arg-type]


def _contour_as_tool_centre(model: Any, records: Iterable[CLCommand | PlainMove],
                            cl_file: str) -> Iterable[CLCommand | PlainMove]:
    """cutter_compensation: control -- the CL is the part contour.  The model's registers
    hold the CL's tool radii, and the CL side is the contour offset by the control's rules:
    the CL is read whole first for its tools (only in this mode)."""
    from postdsl.check.contour import tool_centre  # verifying only, as the control models
    from postdsl.cl.model import ToolChange

    records = list(records)
    diameters = {r.tool_number: r.tool_diameter for r in records if isinstance(r, ToolChange)}
    model.configure_compensation("control", diameters)
    if model.compensation_rules is None:
        return records  # the control has none: the post refuses the record
    return tool_centre(records, model.compensation_rules, cl_file)


def _axis_steps(model: Any) -> Callable[[], Sequence[float] | None] | None:
    """The model's axis steps, or None for a model that never knows any (the tolerance is
    then the resolution throughout, and verify need not ask at every comparison)."""
    from postdsl.check.controls.iso import IsoControl  # verifying only

    return None if type(model).axis_steps is IsoControl.axis_steps else model.axis_steps


def _nc_input(post: CompiledPost, number: int, line: NCLine) -> NCInput:
    """An NC line for the control model, with what its table declares (``verify:``)."""
    from postdsl.check.controls import NCInput  # replaying only: posting needs no control model

    table = (post.custom_cycles.get(line.table) if line.command == "custom_cycle"
             else post.commands.get(line.table))
    return NCInput(number, line.text, table.verify_motion if table is not None else None,
                   _declared_words(table))


def _declared_words(table: CompiledCommand | None) -> frozenset[str]:
    if table is None:
        return frozenset()
    from postdsl.check.controls.base import number_key  # replaying only

    return frozenset(word[0] + number_key(word[1:]) for word in table.verify_words)


def verify_file(machine: str | Path, cl_path: str | Path, fmt: str | None = None,
                feed_units: str | None = None, options: Options | None = None,
                progress: PassProgress | None = None) -> Verdict:
    """Verify a CL file with a machine; raises VerifyError at the first divergence.

    Streams as :func:`write_program` does, and compares as it does: a first pass for the
    program summary, then the posted lines replayed and compared with the records the
    first pass kept, in step.
    """
    post = load_post(machine, options)
    _control_of(post)
    with CLSource(cl_path, fmt, feed_units) as source:
        summary = summarize_source(source, post.machine.rapid_rate,
                                   _pass(progress, "reading", source.size),
                                   moves=_reads_move_values(post),
                                   kinematics=post.machine.kinematics)
        engine = Engine(post, now=posting_time(), cl_file=source.name)
        records = source.records(_pass(progress, "verifying", source.size))
        verdict = _post_verified(post, engine, records, summary, source.name,
                                 lambda batch: None)
    if verdict.divergence is not None:
        raise VerifyError(str(verdict.divergence))
    return verdict


# --- toolpath: the program's motion as drawable segments -------------------------------------


def toolpath_of_lines(post: CompiledPost, lines: Sequence[NCLine],
                      tolerance: float | None = None,
                      tool_diameters: Mapping[int, float] | None = None) -> Toolpath:
    """Replay posted lines through the post's control model into drawable segments.

    Each segment names its NC line and the CL command and table that wrote it
    (see :mod:`postdsl.check.toolpath`).  A line the control model refuses ends the
    path: ``stopped`` says which and why, the segments before it are kept.
    A post without ``machine.control`` is a PostError.  ``tolerance`` (mm) is how far
    the chords drawn for an arc may stray from it (default ``toolpath.ARC_TOLERANCE``).
    ``tool_diameters`` (the CL's) let a post in the cutter_compensation mode ``control``
    draw the tool centre the control makes of the contour; without them, or in the other
    modes, the radius registers count as 0 (the programmed path).
    """
    # the toolpath and the control models are not needed to post: imported when drawn
    from postdsl.check.controls import control_model
    from postdsl.check.toolpath import ARC_TOLERANCE, LineSource
    from postdsl.check.toolpath import collect as collect_toolpath

    control = post.machine.control
    if control is None:
        raise PostError("the post declares no machine/control: a toolpath is the program "
                        "replayed through the control model", Location(post.file))
    model = control_model(control, calculator_input=post.machine.calculator_input)
    if post.machine.cutter_compensation == "control" and tool_diameters:
        model.configure_compensation("control", dict(tool_diameters))
    model.set_kinematics(post.machine.kinematics)

    def source(number: int) -> LineSource | None:
        if not 1 <= number <= len(lines):
            return None
        line = lines[number - 1]
        return LineSource(line.command, line.table, line.cl_line)

    inputs = (_nc_input(post, number, line) for number, line in enumerate(lines, start=1))
    # a rapid carries no tooling: the plane in force is the model's while it yields it
    return collect_toolpath(model.replay(inputs), source,
                            ARC_TOLERANCE if tolerance is None else tolerance,
                            lambda: model.frame)


def control_events(post: CompiledPost, lines: Iterable[NCLine]) -> Iterator[Any]:
    """The posted lines replayed through the post's control model, as its events.

    The events (``postdsl.check.controls.events``: moves, holes, tool, spindle and offset
    changes) name their NC line, 1-based.  ``postdsl review`` compares two postings'
    events within the machine's resolution to tell a format change from a motion
    change.  A post without ``machine.control`` is a PostError; a line the model
    refuses raises ControlError when the iteration reaches it.
    """
    model = _control_of(post)
    return model.replay(  # type: ignore[no-any-return]  # the model is found by name
        _nc_input(post, number, line) for number, line in enumerate(lines, start=1))


def toolpath(post: CompiledPost, commands: Iterable[CLCommand], *, cl_file: str = "<cl>",
             now: datetime | None = None) -> tuple[list[NCLine], Toolpath]:
    """Post CL commands and replay the program: (the NC lines, their toolpath)."""
    commands = commands if isinstance(commands, Sequence) else list(commands)
    lines = post_commands(post, commands, cl_file=cl_file, now=now)
    diameters = {c.tool_number: c.tool_diameter for c in commands
                 if isinstance(c, ToolChange)}
    return lines, toolpath_of_lines(post, lines, tool_diameters=diameters)


def toolpath_file(machine: str | Path, cl_path: str | Path, fmt: str | None = None,
                  feed_units: str | None = None, options: Options | None = None) \
        -> tuple[CompiledPost, Toolpath]:
    """Post a CL file with a machine and replay it: (the post, the toolpath)."""
    post = load_post(machine, options)
    _, path = toolpath(post, read_cl(cl_path, fmt, feed_units), cl_file=str(cl_path))
    return post, path


def plot_file(machine: str | Path, cl_path: str | Path, output: str | Path,
              views: Sequence[str] | None = None, fmt: str | None = None,
              feed_units: str | None = None, options: Options | None = None) -> Toolpath:
    """Draw a CL file's toolpath as SVG (``views``: xy, xz, yz, iso) into ``output``, atomically.

    Returns the toolpath; when the control model refused a line (``stopped``)
    the picture shows the path up to it and says so.  ``views`` default to all four.
    """
    from postdsl.check.svgplot import ALL_VIEWS, render_svg  # drawing only, not posting

    views = ALL_VIEWS if views is None else views
    post, path = toolpath_file(machine, cl_path, fmt, feed_units, options)
    title = f"{post.machine.name or Path(str(machine)).stem}: {Path(cl_path).name}"
    _write_output(output, render_svg(path, views, title), "the picture",
                  keep=((_input_file(cl_path), "the CL program being drawn"),
                        (post.file, "the post")))
    return path


def same_motion(post: CompiledPost, old: Toolpath, new: Toolpath) -> bool:
    """Whether two toolpaths move the tool alike, within the machine's resolution."""
    from postdsl.check.toolpath import motion_key  # comparing toolpaths (review) only

    resolution = post.machine.resolution or 0.001
    return (old.stopped is None) == (new.stopped is None) and \
        motion_key(old.segments, resolution) == motion_key(new.segments, resolution)


# --- editor support (the table editor, tui/) -------------------------------------------------


def check_source(source: PostSource, options: Options | None = None) -> CheckResult:
    """Check and compile a post document without raising: an editor re-checks after every edit.

    Each problem keeps the document path its check found it at (``PostError.path``), so
    the editor can mark the item or field a problem is about.  A problem in a base
    post (``extends:``) has no node in this document: its path is ``()``.
    """
    from postdsl.results import CheckResult, PostProblem

    try:
        return CheckResult(compile_source(source, options))
    except PostError as exc:
        return CheckResult(None, [
            PostProblem(p.path if p.path is not None and p.location is not None and
                        p.location.file == source.file else (), p.message,
                        p.location or Location(source.file))
            for p in exc.problems])


def command_groups() -> dict[str, list[str]]:
    """CL command names by group (program, tool and spindle, motion…), as editors list them."""
    groups: dict[str, list[str]] = {group: [] for group in GROUPS}
    for name, cls in COMMANDS.items():
        groups.setdefault(cls.group, []).append(name)
    return groups


def command_doc(name: str) -> str:
    """What a CL command means ('' for names outside the vocabulary, e.g. custom cycles)."""
    cls = COMMANDS.get(name) or EVENTS.get(name)
    return cls.doc if cls is not None else ""


def place_in_post(path: tuple[Any, ...]) -> str:
    """A path in a post document in an editor's words: ``deep_drill, block 2, item 3``,
    ``formats › coord › decimals``."""
    if path and path[0] in ("commands", "custom_cycles", "structures") and len(path) >= 2:
        from postdsl.run.trace import place  # tracing is the editor's, not posting's

        return place(path)
    return " › ".join(str(part) for part in path)


def commands_setting(name: str) -> list[str]:
    """The CL commands whose records carry parameter ``name`` (in vocabulary order)."""
    return [command for command, cls in COMMANDS.items()
            if any(f.name == name for f in command_fields(cls))]


def parameters() -> Mapping[str, ParamInfo]:
    """Every CL parameter a post may print or test, with its meaning (the editor's picker)."""
    return PARAMETERS


def check_expression(source: str, post: Post | Mapping[str, Any],
                     extra_names: Iterable[str] = ()) -> ExpressionCheck:
    """Validate a condition or computed value while it is typed.

    Known names are the CL parameters, the variables and options of the post (its
    model or document) and ``extra_names`` (a custom cycle's parameters), as for the
    loader.
    """
    from postdsl.results import ExpressionCheck

    if isinstance(post, Post):
        names = with_previous({*PARAMETERS, *post.variables, *post.options, *post.flags})
        formats = {name: NumberFormat() for name in post.formats}
    else:  # a document: only its names are needed, not a whole model
        names = document_names(post)
        formats = format_stand_ins(post)
    names |= with_previous(extra_names)
    if not source.strip():
        return ExpressionCheck(error="the expression is empty")
    try:
        return ExpressionCheck(compile_expr(source, names, formats).names)
    except ExprError as exc:
        return ExpressionCheck(error=exc.message, column=exc.column)


def render_number(spec: Mapping[str, Any], value: float) -> str:
    """``value`` written with a format as a post declares it (the editors' live examples).

    Raises FormatSpecError, whose ``key`` names the option at fault.
    """
    return NumberFormat.from_mapping(dict(spec)).render(value)


def example_program(machine: str | Path) -> Path | None:
    """The CL program bundled for a machine (``examples/<machine>_*``), else the first
    program ``corpus.yaml`` lists for it (a library post has no example of its own), or
    None."""
    folder = machines_dir().parent / "examples"
    name = Path(str(machine)).stem
    candidates = sorted(p for p in folder.glob(f"{name}_*") if p.is_file()) \
        if folder.is_dir() else []
    if candidates:
        return candidates[0]
    listed = [path for path in _listed_programs(name) if path.is_file()]
    return listed[0] if listed else None


def _listed_programs(name: str) -> list[Path]:
    """The programs ``corpus.yaml`` lists for machine ``name`` (none when it cannot be read)."""
    root = machines_root()
    corpus = root / "corpus.yaml"
    if not corpus.is_file():
        return []
    try:
        data = parse_yaml(corpus.read_text(encoding="utf-8"), str(corpus))
    except (PostError, OSError, UnicodeDecodeError):
        return []
    entries = data.get(name) if isinstance(data, Mapping) else None
    if not isinstance(entries, list):
        return []
    return [root / str(entry) for entry in entries if isinstance(entry, str)]


# --- tracing: from an NC word to the cell that wrote it ------------------------------------------


def trace_line(post: CompiledPost, commands: Iterable[CLCommand], number: int, *,
               cl_file: str = "<cl>", now: datetime | None = None) -> TracedLine | None:
    """NC line ``number`` (1-based) of the program ``commands`` posts, with the CL record,
    table, block and item that wrote each of its words, the conditions that fired and the
    registers after it; None when the program is shorter.  Posts up to that line only."""
    if number < 1:
        return None
    from postdsl.run.trace import trace_lines  # tracing only, not posting

    return next(trace_lines(post, commands, now=now or posting_time(), cl_file=cl_file,
                            wanted=number), None)


def explain_text(post: CompiledPost, traced: TracedLine, cl_file: str = "<cl>") -> list[str]:
    """A traced line in words, as ``postdsl explain`` prints it."""
    from postdsl.run.trace import explain  # tracing only, not posting

    return explain(traced, post.source.model, cl_file)


def explain_line(machine: str | Path, cl_path: str | Path, number: int,
                 fmt: str | None = None, options: Options | None = None) -> list[str]:
    """``postdsl explain``: where NC line ``number`` of a posted CL file comes from."""
    post = load_post(machine, options)
    commands = list(read_cl(cl_path, fmt))
    traced = trace_line(post, commands, number, cl_file=str(cl_path))
    if traced is None:
        count = len(post_commands(post, commands, cl_file=str(cl_path)))
        raise CLError(f"the program has {count} NC line{'s' if count != 1 else ''}, "
                      f"no line {number}", Location(str(cl_path)))
    return explain_text(post, traced, str(cl_path))


def machines_root() -> Path:
    """The folder that holds ``machines/``, ``examples/`` and ``corpus.yaml``."""
    return machines_dir().parent


def corpus_programs(machine: str | Path) -> list[Path]:
    """The CL programs ``corpus.yaml`` lists for a machine, the showcase (its first) first;
    the bundled example when the corpus does not name the machine.  Missing files are left
    out: a sample list must only offer what can be opened."""
    listed = _listed_programs(Path(str(machine)).stem)
    example = example_program(machine)
    if not listed and example is not None:
        listed = [example]
    return [path for path in listed if path.is_file()]


def arguments_swapped(machine: str, cl_file: str) -> bool:
    """``postdsl post FILE MACHINE``: the machine argument is a CL file and the CL argument
    names a machine.  Said plainly, rather than as the YAML error reading a CL file as a
    post would give."""
    machine_path = Path(machine)
    if machine_path.suffix.lower() in (".yaml", ".yml") or not machine_path.is_file():
        return False
    from postdsl.resources import bundled_machines

    return cl_file in bundled_machines() or Path(cl_file).suffix.lower() in (".yaml", ".yml")


def word_writers(post: Post | Mapping[str, Any], word: str) -> list[WordWriter]:
    """Every item of the post (its model, or a document) whose fixed text or prefix writes
    ``word``, as a whole NC word."""
    from postdsl.run.trace import word_writers as _word_writers  # the editor's and preview's

    return _word_writers(_model(post), word)


def word_meaning(post: Post | Mapping[str, Any], word: str) -> WordMeaning | None:
    """The table of the post (its model, or a document) for what ``word`` means on ISO
    controls (``G83``: deep drilling, which another control's post writes as a cycle
    call), when the post does not write the word itself; None otherwise."""
    from postdsl.run.trace import word_meaning as _word_meaning  # preview and palette only

    return _word_meaning(_model(post), word)


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
