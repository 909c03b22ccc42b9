"""Verifying: the posted lines replayed through the machine's control model and
compared with the CL they were posted from.

Apart from posting because a program needs no control model to be written: the control
models, the CL's motion events and the comparison are imported inside the functions that
replay, so ``postdsl post --no-verify`` never loads them.  Both the in-memory calls
(:func:`verify_commands`, :func:`post_verified`, review's :func:`control_events`) and the
streamed ones (:mod:`postdsl.api.files`) compare through :func:`_compare`, so a program
gets the same verdict however it is posted.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Sequence
from datetime import datetime
from typing import TYPE_CHECKING, Any

from postdsl.api.posting import posting_time
from postdsl.cl.model import (
    DRILL_SETUPS,
    CLCommand,
    DrillSetup,
    LinearMove,
    PlainMove,
    RapidMove,
)
from postdsl.compile.compiler import CompiledCommand, CompiledPost
from postdsl.compile.runtime import NCLine
from postdsl.errors import Location, PostError
from postdsl.run.engine import Engine
from postdsl.run.program import ProgramSummary

if TYPE_CHECKING:
    from postdsl.check.controls import NCInput
    from postdsl.check.controls.events import Origin
    from postdsl.check.verify import Verdict


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
                                   stops=model.reports_stops,
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
