"""Run CL commands through a compiled post: modal state, numbering, machine limits.

The engine keeps what a control keeps: the latest value of every parameter
(PPU's flat parameter table), the *registers* — the last value written for
each modal word, so "write only when changed" compares with what the
control really holds — and the block counter.  It knows nothing about any
machine; everything machine-specific is in the compiled post.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime
from typing import Any, NoReturn

from postdsl import arcs, frames
from postdsl.cl.holes import MAX_PECKS, TooManyPecks, hole_moves
from postdsl.cl.model import (
    DRILL_SETUPS,
    PREVIOUS,
    ArcMove,
    BreakChip,
    CLCommand,
    CoolantOff,
    CustomCycle,
    CutterCompensation,
    CycleEnd,
    CycleHole,
    DeepDrill,
    DrillSetup,
    LinearMove,
    Operation,
    OperationEnd,
    PlainMove,
    ProgramEnd,
    ProgramStart,
    RapidMove,
    SafeRetract,
    SinglePeck,
    SpindleOff,
    SpindleOn,
    ToolChange,
    WorkPlane,
    command_fields,
    plain_command,
    plain_move_of,
)
from postdsl.compile.codegen import generated
from postdsl.compile.compiler import CompiledCommand, CompiledPost
from postdsl.compile.runtime import MISSING as _MISSING
from postdsl.compile.runtime import NCLine, PostEvalError
from postdsl.errors import CLError, Location
from postdsl.lang.expr import ExprEvalError
from postdsl.run import rules
from postdsl.run.program import ProgramSummary, summarize
from postdsl.run.rotary import RotaryPass, refuse_rotaries
from postdsl.run.rules import shown

#: per record class: (field name, sticky) pairs, computed once
_FIELDS: dict[type, tuple[tuple[str, bool], ...]] = {}


def _fields(cls: type[CLCommand]) -> tuple[tuple[str, bool], ...]:
    fields = _FIELDS.get(cls)
    if fields is None:
        fields = tuple((f.name, bool(f.metadata.get("sticky"))) for f in command_fields(cls)
                       if f.name != "params")
        _FIELDS[cls] = fields
    return fields


class _StateOnlyTable:
    """Stands in for a table the post lacks while :meth:`Engine.in_state` applies values."""

    table = ""
    parameters: Mapping[str, Any] = {}


_STATE_ONLY: Any = _StateOnlyTable()


@dataclass(frozen=True, slots=True)
class _Kind:
    """What the engine needs to know of a record class, worked out once per class."""

    #: (field name, sticky) pairs, and a function reading those fields as a tuple
    fields: tuple[tuple[str, bool], ...]
    read: Callable[[CLCommand], tuple[Any, ...]]
    #: a move or a hole: the tool travels (for first_move and prev_x/y/z)
    motion: bool
    tool_change: bool
    spindle_on: bool


_KINDS: dict[type, _Kind] = {}


def _kind(cls: type[CLCommand]) -> _Kind:
    kind = _KINDS.get(cls)
    if kind is None:
        fields = _fields(cls)
        names = tuple(name for name, _sticky in fields)
        getter = operator.attrgetter(*names) if names else None

        def read(command: CLCommand) -> tuple[Any, ...]:
            if getter is None:
                return ()
            return (getter(command),) if len(names) == 1 else getter(command)

        kind = _KINDS[cls] = _Kind(
            fields, read,
            motion=issubclass(cls, (RapidMove, LinearMove, ArcMove, DrillSetup, CycleHole)),
            tool_change=issubclass(cls, ToolChange), spindle_on=issubclass(cls, SpindleOn))
    return kind



def _take_fields(kind: _Kind, command: CLCommand, values: dict[str, Any],
                 changed: set[str], moved: set[str]) -> None:
    """Take a record's fields into the registers: what changed, each prev_ value, `given`.

    A field the record leaves out keeps its value when it is sticky (a modal
    coordinate) and becomes None otherwise.  A prev_ value is the one before this
    record, however many of its steps set the name (``moved``).  ``given`` is what
    the record itself carries, for posts that write only those words (FreeCAD-style
    posts print a command's own axes, never the kept ones).
    """
    given = []
    for (name, sticky), value in zip(kind.fields, kind.read(command), strict=True):
        if value is not None:
            given.append(name)
        elif sticky:
            continue
        old = values.get(name, _MISSING)
        if old != value:
            changed.add(name)
            if name not in moved:
                moved.add(name)
                values[PREVIOUS + name] = None if old is _MISSING else old
            values[name] = value
    values["given"] = tuple(given)

class Engine:
    """Posts one program.  Create one per program: state carries over between commands."""

    #: run the traced flavour of the generated tables (:class:`postdsl.run.trace.TracingEngine`)
    traced = False

    # What a machine refuses (postdsl.run.rules), as methods: the generated code calls them
    _check_values = rules.check_values
    _check_limits = rules.check_limits
    _arc_extremes = rules.arc_extremes
    _check_cutting = rules.check_cutting
    _stalling_speed = rules.stalling_speed
    _arc_as_line = rules.arc_as_line
    _check_arc_radius = rules.check_arc_radius
    _check_first_peck = rules.check_first_peck
    _check_peck_written = rules.check_peck_written

    def __init__(self, post: CompiledPost, *, now: datetime, cl_file: str = "<cl>") -> None:
        self.post = post
        self.cl_file = cl_file
        self.values: dict[str, Any] = {}
        self.changed: set[str] = set()
        self.registers: dict[str, Any] = {}
        #: registers a 'forced' item wrote during the current command (then forgot)
        self.forced: set[str] = set()
        numbering = post.numbering
        self.number = numbering.start
        self._retract_given = False
        self._expanding = False
        self._by_condition = False
        #: per drilling setup posted, in order: whether its holes were written as moves
        self.expanded_setups: list[bool] = []
        #: the post's tables as generated functions (:mod:`postdsl.compile.codegen`): the only way
        #: a table is written; a tracing engine runs their traced flavour
        self._generated = generated(post, traced=self.traced)
        #: the CL line of the command being posted, for errors found deep inside its blocks
        self._current_line: int | None = None
        #: the CL line a program_start or program_end the CL left out is written at
        self._implied_at: int | None = None
        #: id(drilling table) -> the formats it writes the pecks with (_check_peck_written)
        self._peck_formats: dict[int, list[tuple[str, Any, Any]]] = {}
        #: id(arc table) -> the output resolution of its centre words (_check_arc_radius)
        self._arc_steps: dict[int, float] = {}
        #: motion commands posted since the last tool change (for ``first_move``)
        self._moves_since_tool = 0
        #: the table of the open drilling cycle the control holds (None: none is open)
        self._cycle_table: CompiledCommand | None = None
        #: a move inside the open cycle wrote the motion word: the control's cycle ended
        self._cycle_ended = False
        #: the feed of the open cycle (a move inside it may give another)
        self._cycle_feed: Any = None
        #: a tool is loaded (a tool_change was posted)
        self._tool_loaded = False
        #: why the speed the last spindle_on set cannot cut (it is 0 or written as S0), or
        #: None; judged once there, not again on every cutting move
        self._speed_stalls: str | None = None
        self.values.update(post.variables)
        self.values.update(post.flags)
        self.values.update({
            "year": now.year, "month": now.month, "day": now.day, "hour": now.hour,
            "minute": now.minute, "second": now.second,
            "machine_name": post.machine.name, "controller": post.machine.controller,
            "cl_file": cl_file, "cycle": "", "spindle": "off", "coolant": "off",
            "first_move": False, "given": (), "operation": "",
            "compensation": "off", "compensation_start": "", "compensation_waiting": "",
        })
        #: the cutter compensation side a record asked for, until the move in X/Y that
        #: writes it (None: none waits); the moves take the general path meanwhile
        self._comp_wait: str | None = None
        #: names a record changed, whose ``prev_`` value is the one before it (until the
        #: next record starts: then ``prev_`` catches up, see :meth:`_previous`)
        self._moved: set[str] = set()
        self._fill_previous()
        #: tool changes posted so far, the index of the next one in the program summary
        self._tool_changes = 0
        #: a CAM operation is open: operation_end is due before the next boundary
        self._in_operation = False
        #: record class -> its generated lane (:func:`postdsl.compile.codegen.generated`): the
        #: whole of :meth:`post_command` for a rapid or linear move in one function
        self._generated_lanes: dict[type, Callable[[Engine, CLCommand], list[NCLine]]] = {}
        #: record class -> the same lane on a plain move's fields (:meth:`texts`)
        self._field_lanes: dict[type, Callable[..., None]] = {}
        for cls in (RapidMove, LinearMove):
            if post.machine.kinematics.axes:
                break  # a move's rotary words: the lanes write X Y Z F only
            lane = self._generated.lanes.get(cls.name)
            if lane is not None:
                self._generated_lanes[cls] = lane
            field_lane = self._generated.field_lanes.get(cls.name)
            if field_lane is not None:
                self._field_lanes[cls] = field_lane
        #: the post writes spindle_on: a cutting move needs the spindle turning
        self._spindle_table = post.commands.get("spindle_on") is not None

    @classmethod
    def in_state(cls, post: CompiledPost, commands: Iterable[CLCommand],
                 summary: ProgramSummary, *, now: datetime,
                 cl_file: str = "<cl>") -> Engine:
        """An engine as if ``commands`` had been posted, with ``summary`` loaded.

        A preview renders one command's blocks in the middle of a program: the
        kept values (tool, spindle, position, the open cycle) must be those the
        earlier commands left, while their blocks are not written and no
        register remembers a word, so the previewed blocks write every word
        they would write after the commands' values changed.
        """
        engine = cls(post, now=now, cl_file=cl_file)
        for command in commands:
            engine.changed = set()
            engine._apply(command, post.commands.get(command.name) or _STATE_ONLY)
        engine.load_summary(summary)
        engine.registers.clear()
        return engine

    # --- running ----------------------------------------------------------------------

    def run(self, commands: Iterable[CLCommand],
            summary: ProgramSummary | None = None) -> Iterator[NCLine]:
        """Post a whole program; adds program_start/program_end when the CL lacks them.

        ``summary`` is what a first pass over the same program found (see
        :class:`postdsl.cl.source.CLSource`); with it the commands are posted as they
        come and never held.  Without it the summary is folded here, over the
        sequence given (an iterator is read into a list first).
        """
        if summary is None:
            if not isinstance(commands, Sequence):
                commands = list(commands)
            summary = summarize(commands, self.post.machine.rapid_rate,
                                self.post.machine.kinematics)
        self.load_summary(summary)
        commands = self._through_rotaries(commands)
        last: CLCommand | None = None
        step = self._step
        lanes = self._generated_lanes
        for command in commands:
            lane = lanes.get(command.__class__)
            if lane is not None and last is not None and self._comp_wait is None:
                # a rapid or linear move with its generated lane: it opens an operation
                # (no boundary to post) and is posted in one call
                last = command
                self._in_operation = True
                yield from lane(self, command)
                continue
            yield from step(command, last is None)
            last = command
        yield from self._end(last)

    def texts(self, records: Iterable[CLCommand | PlainMove],
              summary: ProgramSummary) -> Iterator[list[str]]:
        """:meth:`run` for a program written to a file: the lines' texts, in batches.

        ``records`` are commands, or plain moves as a reader hands them on without a
        command object (:data:`~postdsl.cl.model.PlainMove`); a plain move goes through
        its table's generated lane on its fields, which gives each text straight to the
        batch: nothing of a line but its text is made.  The same lines as :meth:`run`
        (the test suite compares them); a batch is handed on once it holds about a
        thousand lines, so the memory stays flat.  The batches of :meth:`sourced_texts`
        without their sources: one loop for both (``post --no-verify`` pays a list of
        sources it drops, about a percent).
        """
        for batch, _ in self.sourced_texts(records, summary):
            yield batch

    def sourced_texts(self, records: Iterable[CLCommand | PlainMove],
                      summary: ProgramSummary) -> Iterator[tuple[list[str], list[Any]]]:
        """:meth:`texts`, each batch with the source of each of its lines, for verify.

        A source is the line's :class:`NCLine` (what :meth:`run` gives), or, for the
        lines a straight move's generated lane wrote, the move's
        :data:`~postdsl.cl.model.PlainMove` (its class names the table, its second field
        the CL line): verify needs the table's ``verify:`` and the CL line of a line the
        control refuses, and nothing more is made per line.  The same texts as
        :meth:`texts` (``tests/test_post_verify.py`` compares them).
        """
        self.load_summary(summary)
        records = self._through_rotaries(records)
        batch: list[str] = []
        sources: list[Any] = []
        add, note = batch.append, sources.append
        step = self._step
        lanes = self._field_lanes
        last: Any = None
        started = False
        # a CLCommand or a PlainMove tuple, told apart by `type(record)` (the speed of this
        # loop), which mypy does not narrow
        record: Any
        for record in records:
            kind = type(record)
            if kind is not tuple and started and kind in lanes:
                record = plain_move_of(record)
                kind = tuple
            if kind is tuple:
                lane = lanes.get(record[0])
                if lane is not None and started and self._comp_wait is None:
                    self._in_operation = True
                    before = len(batch)
                    lane(self, add, record)
                    written = len(batch) - before
                    if written == 1:
                        note(record)
                    elif written:
                        sources.extend([record] * written)
                    last = record
                    if len(batch) >= _BATCH:
                        yield batch, sources
                        batch, sources = [], []
                        add, note = batch.append, sources.append
                    continue
                record = plain_command(record)
            for line in step(record, not started):
                add(line.text)
                note(line)
            started = True
            last = record
            if len(batch) >= _BATCH:
                yield batch, sources
                batch, sources = [], []
                add, note = batch.append, sources.append
        for line in self._end(last if started else None):
            add(line.text)
            note(line)
        if batch:
            yield batch, sources

    def _through_rotaries(self, records: Iterable[Any]) -> Iterable[Any]:
        """The CL's part-frame moves as the machine's rotaries make them
        (:mod:`postdsl.run.rotary`); on a 3-axis post, a rotary move refused at its line."""
        kin = self.post.machine.kinematics
        if not kin.axes:
            return refuse_rotaries(records, self._where)
        rotaries = RotaryPass(kin, self._where)
        return (rotaries.step(plain_command(r) if type(r) is tuple else r) for r in records)

    def _step(self, command: CLCommand, first: bool) -> Iterator[NCLine]:
        """One command of a program, with what its place in the program adds: the
        program_start the CL left out (``first``), the end of an operation it closes.
        Each line comes as soon as it is made: one the command refuses comes after them."""
        if first and not isinstance(command, ProgramStart):
            self._implied_at = command.line
            yield from self.post_command(ProgramStart())
            self._implied_at = None
        if command.__class__ is SafeRetract:
            command = self._safe_retract(command)
        # what the record does to an open operation, worked out once per class: the
        # generator of _operation_boundary is made only where one may close
        boundary = _BOUNDARIES.get(command.__class__)
        if boundary is None:
            boundary = _boundary(command.__class__)
        if boundary is _OPENS:
            self._in_operation = True
        elif boundary is _CLOSES:
            yield from self._operation_boundary(command)
        yield from self.post_command(command)

    def _end(self, last: CLCommand | None) -> Iterator[NCLine]:
        """The program_start and program_end the CL left out, after its ``last`` command
        (None: it had none)."""
        if last is None:
            yield from self.post_command(ProgramStart())
        if not isinstance(last, ProgramEnd):
            self._implied_at = last.line if last is not None else None
            end = ProgramEnd()
            yield from self._operation_boundary(end)
            yield from self.post_command(end)
            self._implied_at = None

    def _operation_boundary(self, command: CLCommand) -> Iterator[NCLine]:
        """Post ``operation_end`` where ``command`` ends an operation that moved the tool.

        An operation is under way from its first move; the next ``operation`` record, a
        tool change or the program's end closes it.  A tool change between an operation
        record and its first move belongs to that operation and ends nothing.  The event
        is posted only when the post has a table for it.
        """
        if isinstance(command, (Operation, ToolChange, ProgramEnd)):
            if self._in_operation and OperationEnd.name in self.post.commands:
                yield from self.post_command(OperationEnd(line=command.line))
            self._in_operation = False
        elif isinstance(command, (RapidMove, LinearMove, ArcMove, DrillSetup, CycleHole)):
            self._in_operation = True

    def load_summary(self, summary: ProgramSummary) -> None:
        """Program values, and the first tool's data so a header can describe it."""
        self.summary = summary
        self.values.update(summary.values())
        first = summary.tool_records.get(summary.tools[0]) if summary.tools else None
        if first is not None:
            for name, _sticky in _fields(ToolChange):
                self.values.setdefault(name, getattr(first, name))
        self._fill_previous()

    def post_command(self, command: CLCommand) -> Iterable[NCLine]:
        """Apply one CL command to the state and write its table; the lines it wrote.

        The lines come as a list, made whole before they are returned: a table is
        written at once, and a list costs less than a generator per command.
        """
        if self._comp_wait is None:
            generated_lane = self._generated_lanes.get(command.__class__)
            if generated_lane is not None:
                return generated_lane(self, command)
        if command.__class__ is SafeRetract:
            command = self._safe_retract(command)
            if command.__class__ is RapidMove:
                return self.post_command(command)
        command = self._without_zero_peck(command)
        self._current_line = command.line
        table = self._table_for(command)
        self.changed = set()
        self.forced = set()
        self._previous()
        self._apply(command, table)
        # the move in X/Y that starts or ends the cutter compensation a record asked for
        starting = self._comp_wait is not None and (
            command.__class__ is LinearMove or command.__class__ is RapidMove) and (
            "x" in self.changed or "y" in self.changed)
        if starting:
            self.values["compensation_start"] = self._comp_wait
        restore: dict[str, Any] = {}
        expand = table.expand
        if isinstance(command, DrillSetup):
            expand = self._expands(command, table)
        if isinstance(command, CycleHole) and not self._expanding:
            table, restore = self._hole_table(command, table)
        # a setup expanded by its expand_if (and its holes) is not written by its table:
        # the rules of the cycle the table would write do not apply to its moves
        if not (self._by_condition and self._expanding
                and isinstance(command, (DrillSetup, CycleHole))):
            for condition, message in table.reject:
                if self._test(condition, command):
                    raise CLError(f"{command.name}: {message}", self._where(command))
        if command.__class__ is CutterCompensation:
            self._check_compensation_mode(command)
            self._wait_for_compensation_move(command)
        if isinstance(command, DrillSetup) and not expand:
            self._check_first_peck(command, table)
            self._check_peck_written(command, table)
        self._check_cutting(command)
        if isinstance(command, ArcMove) and table.expand:
            lines = self._chords(command, table)
        elif isinstance(command, ArcMove) and self._arc_as_line(command):
            self._moves_since_tool -= 1  # the line is the same move (first_move stays)
            return self.post_command(LinearMove(x=command.x, y=command.y, z=command.z,
                                                feed=command.feed, line=command.line))
        elif expand or (self._expanding and isinstance(command, CycleHole)):
            lines = list(self._expand(command))
        else:
            if isinstance(command, ArcMove):
                self._check_arc_radius(command, table)
            try:
                lines = self.write_table(table, command)
            except ExprEvalError as exc:
                self._table_failed(table, command, exc)
            if lines and isinstance(command, (RapidMove, LinearMove, ArcMove)):
                self._move_in_cycle(command)
        self._after(command, table)
        if restore:
            self.values.update(restore)
        if starting:
            self.values.update(compensation=self._comp_wait, compensation_start="",
                               compensation_waiting="")
            self._comp_wait = None
        return lines

    def _wait_for_compensation_move(self, command: CLCommand) -> None:
        """A side other than the one in force waits for the next move in X/Y, which
        writes it: a control starts and ends compensation on a move in the plane."""
        side = getattr(command, "compensation_side", "off")
        self._comp_wait = None if side == self.values["compensation"] else side
        self.values["compensation_waiting"] = self._comp_wait or ""

    def _table_failed(self, table: CompiledCommand, command: CLCommand,
                      exc: ExprEvalError) -> NoReturn:
        """A table's expression failed at run time: the CL line and the place in the post."""
        where = (f" ({self.post.source.source.locate(exc.path)})"
                 if isinstance(exc, PostEvalError) else "")
        implied = " (the CL has none: it is written before this record)" \
            if not command.line and self._implied_at else ""
        raise CLError(f"{command.name}{implied}: post table '{table.table}' cannot be written: "
                      f"{exc}{where}", self._where(command)) from None

    # --- drilling cycles the control holds ---------------------------------------------

    def _hole_table(self, command: CycleHole,
                    table: CompiledCommand) -> tuple[CompiledCommand, dict[str, Any]]:
        """The table a hole of the open cycle is written with.

        The control drills a hole block with the cycle values it was last given.  When
        a move ended the control's cycle (it wrote the motion word, or closed a modal
        call), or when the post's ``new_cycle_if`` says so (the hole's top changed and
        the control has no word for it on a hole block), the hole goes out through the
        drilling setup's table: a new cycle with this hole's values.  Otherwise a hole
        whose top, bottom or retract plane changed must be written by a table that
        writes them; one that writes none would drill it at the previous hole's depth.
        A new cycle drills at the cycle's feed, not at the feed of a move made inside
        it; the values to put back after the hole are returned with the table.
        """
        setup = self._cycle_table
        if setup is None:
            return table, {}
        renew = self._cycle_ended or (table.new_cycle_if is not None
                                      and self._test(table.new_cycle_if, command))
        if renew:
            self._cycle_ended = False
            restore = {"feed": self.values.get("feed")}
            self.values["feed"] = self._cycle_feed
            return setup, restore
        moved = sorted({"top", "bottom", "retract"} & self.changed)
        if moved and not (table.writes & _HOLE_GEOMETRY):
            values = self.values
            raise CLError(
                f"cycle_hole: this hole's top is {shown(values['top'])} (bottom "
                f"{shown(values['bottom'])}, retract {shown(values['retract'])}), not the "
                f"previous hole's, but the post's table '{table.table}' writes neither top, "
                f"depth, bottom, clearance nor retract: the control would drill it with the "
                f"previous hole's values (write them, or give the table new_cycle_if)",
                self._where(command))
        return table, {}

    def _move_in_cycle(self, command: CLCommand) -> None:
        """A move inside an open cycle must give the control its motion word again.

        A canned cycle replaces the motion word the control holds (the engine forgets
        the motion register after every hole), so a block that moves without it is
        another hole on an ISO control.  A move table that wrote blocks but not the
        motion word is refused; one that did ends the control's cycle, and the next
        hole starts a new one (:meth:`_hole_table`).
        """
        if self._cycle_table is None:
            return
        motion = self.post.motion_register
        if motion not in self.registers and motion not in self.forced:
            raise CLError(
                f"{command.name} inside an open drilling cycle: the post's table writes no "
                f"motion word (register '{self.post.motion_register}'), so the control "
                f"would take the block for another hole; write it (modal: "
                f"{self.post.motion_register}) or end the cycle first", self._where(command))
        self._cycle_ended = True

    # --- what cutting needs -----------------------------------------------------------

    def _safe_retract(self, command: SafeRetract) -> CLCommand:
        """The CAM's "go safe" before the first tool, as this post writes it.

        A post with a ``safe_retract`` table writes it there (its own retract in machine
        coordinates, or nothing when its tool change retracts first).  Without one the
        record is the rapid_move it is -- refused before any tool on a machine with a
        tool changer, with what the post lacks.
        """
        if SafeRetract.name in self.post.commands:
            return command
        if not self._tool_loaded and self.post.machine.tool_changer:
            height = "a safe height" if command.z is None else f"Z{shown(command.z)}"
            raise CLError(
                f"safe_retract (the CAM's move to {height} before the first tool): "
                f"the post {self.post.file} has no safe_retract table, and the machine has a "
                f"tool changer: with no tool loaded the control has no length offset for that "
                f"height; give the post a safe_retract table that writes its own retract in "
                f"machine coordinates (G91 G28 Z0, G53 G0 Z0, L Z... M91), or one with no "
                f"blocks when its tool change retracts Z first", self._where(command))
        return RapidMove(z=command.z, line=command.line)


    def _expands(self, command: DrillSetup, table: CompiledCommand) -> bool:
        """Whether this drilling setup's holes are written as moves, and note it.

        ``expand: true`` always; ``expand_if:`` when its condition holds for the setup's
        values (the cycle cannot write them: unequal pecks, a retract plane the control
        does not reach).  The decision holds for the setup's holes, and is kept in
        :attr:`expanded_setups` for ``postdsl verify``, whose CL side expects the moves.
        """
        condition = table.expand_if
        by_condition = condition is not None and self._test(condition, command)
        self._by_condition = by_condition
        self._expanding = table.expand or by_condition
        self.expanded_setups.append(self._expanding)
        return self._expanding


    def _chords(self, command: ArcMove, table: CompiledCommand) -> list[NCLine]:
        """An arc the control cannot run, written as chords through ``linear_move``
        (``arc_move: {expand: true, tolerance: …}``); the geometry is :mod:`postdsl.arcs`."""
        values = self.values
        start = (values["prev_x"], values["prev_y"], values["prev_z"])
        centre = (start[0] + values["i"], start[1] + values["j"], start[2] + values["k"])
        end = (values["x"], values["y"], values["z"])
        tolerance = table.tolerance or 0.0
        try:
            points = arcs.chords(start, end, centre, command.arc_direction == "cw",
                                 command.plane, tolerance)
        except arcs.TooManyChords as exc:
            raise CLError(f"arc_move: radius {shown(values['radius'])} to tolerance "
                          f"{shown(tolerance)} makes {exc}", self._where(command)) from None
        self._moves_since_tool -= 1  # the chords are the arc's move (first_move stays)
        lines: list[NCLine] = []
        for x, y, z in points:
            lines.extend(self.post_command(LinearMove(x=x, y=y, z=z, feed=command.feed,
                                                      line=command.line)))
        return lines

    def _without_zero_peck(self, command: CLCommand) -> CLCommand:
        """A peck cycle with peck 0 ("no pecking", as the CL vocabulary defines it) drills in
        one feed: it is posted as ``single_peck``.  Its own table would write a peck cycle
        with a zero step, which controls refuse or, worse, read as "use the last peck".
        """
        if not isinstance(command, (DeepDrill, BreakChip)) or command.peck or \
                command.first_peck is not None:
            return command
        if "single_peck" not in self.post.commands:
            raise CLError(f"{command.name} with peck 0 (no pecking) drills in one feed and is "
                          f"posted as single_peck, but the post {self.post.file} has no "
                          f"table for single_peck", self._where(command))
        return SinglePeck(**{f.name: getattr(command, f.name) for f in command_fields(
            type(command))}, line=command.line)

    def _test(self, condition: Any, command: CLCommand) -> bool:
        try:
            return bool(condition.evaluate(self))
        except ExprEvalError as exc:
            raise CLError(f"{command.name}: {exc}", self._where(command)) from None

    def _table_for(self, command: CLCommand) -> CompiledCommand:
        if isinstance(command, CustomCycle):
            table = self.post.custom_cycles.get(command.cycle)
            if table is None:
                known = ", ".join(self.post.custom_cycles) or "none"
                if not command.cycle:
                    raise CLError(f"custom_cycle: no 'cycle' names the post's custom cycle (it "
                                  f"has: {known})", self._where(command))
                raise CLError(f"the post {self.post.file} has no custom cycle '{command.cycle}'"
                              f" (it has: {known})", self._where(command))
            return table
        table = self.post.commands.get(command.name)
        if command.__class__ is WorkPlane and self.post.machine.tilted_plane is None:
            raise CLError(f"work_plane: {self.post.machine.name} does not tilt the working "
                          f"plane (its post has no machine.tilted_plane): a three-axis "
                          f"machine cannot cut in a tilted plane, and its moves would be "
                          f"cut in the part frame", self._where(command))
        if table is None and command.facts_only:
            return _NO_TABLE
        if table is None:
            raise CLError(f"the post {self.post.file} has no table for CL command "
                          f"'{command.name}' (add one under commands:, or a redirect or "
                          f"expand fallback)", self._where(command))
        return table

    def _check_compensation_mode(self, command: CLCommand) -> None:
        """A CL does not say whether its path is the tool centre or the part contour: with
        the mode off, compensation on is refused rather than guessed (off is harmless)."""
        if self.post.machine.cutter_compensation != "off" or \
                getattr(command, "compensation_side", "off") == "off":
            return
        raise CLError(
            f"{command.name}: cutter compensation is refused: the post's cutter_compensation "
            f"mode is off (declare machine.cutter_compensation, or post with --option "
            f"cutter_compensation=wear when the CL is the tool centre and the control's "
            f"register holds wear only, =control when the CL is the part contour)",
            self._where(command))

    def write_table(self, table: CompiledCommand, command: CLCommand) -> list[NCLine]:
        """The lines of ``table`` for ``command``, by its generated function.

        An expression that fails at run time is raised as :class:`PostEvalError`, with
        the place in the post of its condition or item.
        """
        run = self._generated.table(table)
        if run is None:  # a record of facts the post does not write (_NO_TABLE)
            return []
        return run(self, command.name, command.line)

    def _next_number(self) -> None:
        """Block numbers past the maximum: start again only when the post says ``wrap``.

        A control that searches for a block number (a restart, a GOTO) finds the first of
        two equal ones, so numbers that wrap without the post asking are a silent hazard.
        """
        numbering = self.post.numbering
        if self.number <= numbering.maximum:
            return
        if numbering.wrap:
            self.number = numbering.start
            return
        where = Location(self.cl_file, self._current_line or None)
        raise CLError(f"the block numbers run out: block number {self.number} is above the "
                      f"maximum {numbering.maximum} of the post {self.post.file} (raise "
                      f"block_numbers maximum, or set wrap: true to start again at "
                      f"{numbering.start})", where)

    def _each_tool(self, render: Callable[[Engine], str | None]) -> Iterator[str]:
        """A ``for_each: tool`` block, once per tool of the program, with its values."""
        names = [name for name, _sticky in _fields(ToolChange)]
        saved = {name: self.values.get(name) for name in names}
        for tool in self.summary.tools:
            record = self.summary.tool_records.get(tool)
            for name in names:
                self.values[name] = getattr(record, name) if record else None
            self.values["tool_number"] = tool
            text = render(self)
            if text is not None:
                yield text
        self.values.update(saved)

    # --- state ------------------------------------------------------------------------

    def _where(self, command: CLCommand) -> Location:
        """The CL line of ``command``; for a program_start or program_end the CL leaves
        out (it has no line), the record it is written next to: a header that cannot be
        written (a machining time too long for its format) is still located."""
        if not command.line and self._implied_at:
            return Location(self.cl_file, self._implied_at)
        return Location(self.cl_file, command.line or None)

    def _set(self, name: str, value: Any) -> None:
        values = self.values
        old = values.get(name, _MISSING)
        if old != value:
            self.changed.add(name)
            if name not in self._moved:
                self._moved.add(name)
                values[PREVIOUS + name] = None if old is _MISSING else old
            values[name] = value

    def _look_ahead(self) -> None:
        """At a tool change: the next tool and this tool's speed, from the program summary."""
        summary = getattr(self, "summary", None)
        index = self._tool_changes
        self._tool_changes += 1
        tools = summary.tool_sequence if summary is not None else []
        speeds = summary.tool_speeds if summary is not None else []
        self._set("next_tool", tools[index + 1] if index + 1 < len(tools) else None)
        self._set("next_spindle_speed", speeds[index] if index < len(speeds) else None)

    def _previous(self) -> None:
        """A new record: what the last one changed is now its own ``prev_`` value."""
        moved = self._moved
        if moved:
            values = self.values
            for name in moved:
                values[PREVIOUS + name] = values.get(name)
            moved.clear()

    def _fill_previous(self) -> None:
        """Values no record has changed yet (variables, the date, the program summary)."""
        values = self.values
        for name, value in list(values.items()):
            if not name.startswith(PREVIOUS):
                values.setdefault(PREVIOUS + name, value)

    def _apply(self, command: CLCommand, table: CompiledCommand) -> None:
        values = self.values
        changed = self.changed
        kind = _kind(command.__class__)
        # first_move: many posts write the first move after a tool change differently (XY
        # first, then the tool length offset with Z), so the engine says which move that is.
        if kind.tool_change:
            self._moves_since_tool = 0
            self._tool_loaded = True
            self._look_ahead()
        elif kind.spindle_on:
            self._speed_stalls = self._stalling_speed(command)  # type: ignore[arg-type]  # spindle_on: a SpindleOn
        motion = kind.motion
        self._set("first_move", motion and self._moves_since_tool == 0)
        if motion:
            self._moves_since_tool += 1
            values["prev_x"] = values.get("x")
            values["prev_y"] = values.get("y")
            values["prev_z"] = values.get("z")
        _take_fields(kind, command, values, changed, self._moved)
        if isinstance(command, ArcMove):
            self._arc(command)
        elif isinstance(command, DrillSetup):
            self._retract_given = command.retract is not None
            self._set("cycle", command.name)
            if command.first_peck is None:  # every peck is peck deep
                self._set("first_peck", values.get("peck"))
            self._hole(command)
        elif isinstance(command, CycleHole):
            # a custom cycle's name lands in 'cycle' too: a hole needs a drilling setup
            if values.get("cycle") not in DRILL_SETUPS:
                raise CLError("cycle_hole outside a drilling cycle" + (
                    f" (the last cycle was the custom cycle '{values['cycle']}')"
                    if values.get("cycle") else ""), self._where(command))
            self._hole(command)
        elif isinstance(command, CycleEnd):
            self._set("cycle", "")
        elif isinstance(command, SpindleOff):
            self._set("spindle", "off")
        elif isinstance(command, CoolantOff):
            self._set("coolant", "off")
        elif isinstance(command, CustomCycle):
            self._custom(command, table)
        elif isinstance(command, WorkPlane):
            self._work_plane(command)
        self._check_values(command)
        self._check_limits(command)

    def _arc(self, command: ArcMove) -> None:
        values = self.values
        start = (values.get("prev_x"), values.get("prev_y"), values.get("prev_z"))
        if None in start:
            raise CLError("arc_move before the tool position is known (give a move first)",
                          self._where(command))
        centre = (command.cx if command.cx is not None else start[0],
                  command.cy if command.cy is not None else start[1],
                  command.cz if command.cz is not None else start[2])
        for name, c, s in zip("ijk", centre, start, strict=True):
            self._set(name, c - s)  # type: ignore[operator]  # start known: refused above
        a, b = {"xy": (0, 1), "zx": (2, 0), "yz": (1, 2)}[command.plane]
        radius = math.hypot(start[a] - centre[a], start[b] - centre[b])  # type: ignore[operator]  # (as above)
        end = (values["x"], values["y"], values["z"])
        end_radius = math.hypot(end[a] - centre[a], end[b] - centre[b])

        def point(p: tuple[Any, ...]) -> str:  # in the arc's plane, as the user gave it
            return f"({shown(p[a])}, {shown(p[b])})"

        if radius < 1e-9:
            raise CLError(f"arc_move: the centre {point(centre)} is the start point: an arc "
                          f"needs a radius", self._where(command))
        if abs(end_radius - radius) > max(1e-3, radius * 1e-4):
            raise CLError(f"arc_move: the start {point(start)} and the end {point(end)} are "
                          f"not on one circle about the centre {point(centre)} (radius "
                          f"{radius:.4f} at the start, {end_radius:.4f} at the end)",
                          self._where(command))
        self._set("radius", radius)

    def _work_plane(self, command: WorkPlane) -> None:
        """The plane's angles in the convention the post's control states them in."""
        angles: tuple[float, float, float] = (0.0, 0.0, 0.0)
        if command.work_plane != "reset":
            x_axis = (command.x_axis_i, command.x_axis_j, command.x_axis_k)
            z_axis = (command.z_axis_i, command.z_axis_j, command.z_axis_k)
            problem = frames.axes_problem(x_axis, z_axis)
            if problem is not None:
                raise CLError(f"work_plane: {problem}", self._where(command))
            frame = frames.frame_of((command.origin_x, command.origin_y, command.origin_z),
                                    x_axis, z_axis)
            convention = self.post.machine.tilted_plane
            assert convention is not None  # refused in _table_for
            angles = frames.control_angles(convention, frame)
        for index, angle in enumerate(angles, start=1):
            self._set(f"plane_angle_{index}", angle)

    def _hole(self, command: DrillSetup | CycleHole) -> None:
        values = self.values
        top = values["top"]
        self._set("bottom", top - values["depth"])
        if not self._retract_given:
            self._set("retract", top + values["clearance"])

    def _custom(self, command: CustomCycle, table: CompiledCommand) -> None:
        for name, value in table.parameters.items():
            self._set(name, value)
        for name, value in command.params.items():
            if name not in table.parameters:
                known = ", ".join(table.parameters) or "none"
                raise CLError(f"custom cycle '{command.cycle}' has no parameter '{name}' "
                              f"(it has: {known})", self._where(command))
            self._set(name, value)

    def _after(self, command: CLCommand, table: CompiledCommand) -> None:
        registers = self.registers
        if isinstance(command, (DrillSetup, CycleHole)) and not self._expanding:
            # The control moved the tool by itself: Z is no longer what was last written,
            # so forget it unless the post says where the cycle leaves the tool; and the
            # cycle replaced the motion word, so the next move must write its own.
            registers.pop("z", None)
            registers.pop(self.post.motion_register, None)
            self.values["z"] = self.values["retract"]
            self._moved.add("z")  # the next record starts from the retract plane
            if isinstance(command, DrillSetup):
                self._cycle_table = table
                self._cycle_feed = self.values.get("feed")
                self._cycle_ended = False
        elif isinstance(command, CycleEnd):
            self._cycle_table = None
            self._cycle_ended = False
        for name in table.reset:
            registers.pop(name, None)
        for name, expression in table.assume:
            try:
                registers[name] = expression.evaluate(self)
            except ExprEvalError as exc:
                raise CLError(f"{command.name}: assume {name}: {exc}",
                              self._where(command)) from None
        if table.set:
            self._set_flags(command, table)

    def _set_flags(self, command: CLCommand, table: CompiledCommand) -> None:
        """``set:`` after the table's blocks, in order: each sees the flags set before it."""
        for (name, expression), path in zip(table.set, table.set_paths, strict=True):
            try:
                value = expression.evaluate(self)
            except ExprEvalError as exc:
                raise CLError(f"{command.name}: set {name}: {exc} "
                              f"({self.post.source.locate(path)})",
                              self._where(command)) from None
            self._set(name, value)


    # --- drilling without a control cycle ----------------------------------------------

    def _expand(self, command: CLCommand) -> Iterator[NCLine]:
        """Write a hole as rapid/linear/dwell commands through the post's own tables."""
        values = self.values
        try:
            moves = hole_moves(
                x=values["x"], y=values["y"], top=values["top"], bottom=values["bottom"],
                clearance=values["clearance"], retract=values["retract"],
                feed=values.get("feed"), peck=values.get("peck") or 0.0,
                dwell=values.get("dwell") or 0.0, cycle=values.get("cycle") or "",
                start_z=values.get("prev_z"), line=command.line,
                first_peck=values.get("first_peck"))
        except TooManyPecks as exc:
            raise CLError(f"{command.name}: peck {shown(values.get('peck'))} makes {exc.shown} "
                          f"pecks to the depth {shown(values['top'] - values['bottom'])} (at "
                          f"most {MAX_PECKS} are written)", self._where(command)) from None
        hole_values = {k: values.get(k) for k in ("top", "depth", "bottom", "clearance",
                                                  "retract", "peck", "first_peck", "dwell",
                                                  "cycle")}
        for move in moves:
            yield from self.post_command(move)
        self.values.update(hole_values)


#: what a record class does to an open CAM operation (see Engine._operation_boundary)
_OPENS, _CLOSES, _NEITHER = object(), object(), object()
#: lines of text :meth:`Engine.texts` hands on at a time
_BATCH = 1024
_BOUNDARIES: dict[type, object] = {}


def _boundary(cls: type) -> object:
    """Whether records of ``cls`` may close an operation, open one, or neither."""
    if issubclass(cls, (Operation, ToolChange, ProgramEnd)):
        found = _CLOSES
    elif issubclass(cls, (RapidMove, LinearMove, ArcMove, DrillSetup, CycleHole)):
        found = _OPENS
    else:
        found = _NEITHER
    _BOUNDARIES[cls] = found
    return found

#: the table of a record of facts the post does not write (CLCommand.facts_only)
_NO_TABLE = CompiledCommand(name="", blocks=())

#: what a hole block must write for the control to drill a hole of another top
_HOLE_GEOMETRY = frozenset(("top", "depth", "bottom", "clearance", "retract"))

