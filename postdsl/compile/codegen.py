"""Write a compiled post out as Python source, once, and run its tables as functions.

This is the only way a post's tables are written.  Walking blocks and calling one
closure per item would decide, for a million moves, millions of times what the post
already decided when it loaded.  Like Jinja2 turning a template into a module, this
writes one function per block with its items inlined - constants, output modes with
their registers, the format call, the feed-zero check, replace tables, conditions
from the expression syntax tree - and one function per table that calls them in order.

A *traced* flavour of the same module (``generate(post, traced=True)``) records, for
each line a block writes, which item wrote which words: :mod:`postdsl.run.trace` runs it
for ``postdsl explain`` and the editor's trace, so what is traced is what is posted.

Nothing the user wrote is pasted as code: texts and names go in through ``repr``,
expressions through :mod:`postdsl.lang.expr.codegen` from their syntax tree, and every
other object (a number format, a closure, a location) is a constant bound by name in
the module's namespace.  The generated text is compiled with ``compile()`` and run in
a fresh namespace; :mod:`postdsl.codecache` keeps the compiled code between runs.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from postdsl.cl.model import PREVIOUS
from postdsl.compile.compiler import (
    CompiledBlock,
    CompiledCommand,
    CompiledItem,
    CompiledPost,
    post_reads,
    table_expressions,
)
from postdsl.compile.runtime import MISSING, NCLine, PostEvalError
from postdsl.lang.expr import Expression, ExprEvalError, nodes
from postdsl.lang.expr.codegen import NAMESPACE, emit_expression
from postdsl.lang.expr.runtime import no_value
from postdsl.lang.format_codegen import count_text
from postdsl.lang.formats import DigitsError

#: a generated table: (engine, CL command name, CL line) -> the NC lines it wrote
TableFunction = Callable[[Any, str, int], list[Any]]

#: a generated lane: (engine, CL command) -> the NC lines of a rapid or linear move
LaneFunction = Callable[[Any, Any], list[Any]]

#: a generated lane on a record's fields: (engine, add, PlainMove) -> None, each NC
#: line's text handed to ``add``
FieldLaneFunction = Callable[..., None]

#: the record classes whose tables get a lane, by CL command name (see :meth:`_Generator._lane`)
LANE_COMMANDS = ("rapid_move", "linear_move")

@dataclass(frozen=True)
class GeneratedSource:
    """The module text and the objects it names (bound into its namespace when run)."""

    source: str
    constants: dict[str, Any]
    #: (section, table name) -> the name of its function in the module
    tables: dict[tuple[str, str], str]
    #: CL command name -> the name of its lane function (rapid and linear moves)
    lanes: dict[str, str]
    #: CL command name -> the name of its lane taking the record's fields
    field_lanes: dict[str, str]


class GeneratedPost:
    """The generated functions of one compiled post, looked up by table object."""

    def __init__(self, post: CompiledPost, functions: dict[tuple[str, str], TableFunction],
                 lanes: dict[str, LaneFunction] | None = None,
                 field_lanes: dict[str, FieldLaneFunction] | None = None):
        self._by_id: dict[int, TableFunction] = {}
        #: CL command name -> its lane: the whole posting of a straight move in one call
        self.lanes: dict[str, LaneFunction] = lanes or {}
        #: CL command name -> the same lane on the record's fields, writing text only
        self.field_lanes: dict[str, FieldLaneFunction] = field_lanes or {}
        for section, tables in (("commands", post.commands),
                                ("custom_cycles", post.custom_cycles)):
            for table in tables.values():
                function = functions.get((section, table.table))
                if function is not None:
                    self._by_id[id(table)] = function
        self._post = post  # keeps the tables (and so their ids) alive

    def table(self, table: CompiledCommand) -> TableFunction | None:
        return self._by_id.get(id(table))


def generate(post: CompiledPost, *, traced: bool = False) -> GeneratedSource:
    """The module text of ``post``: deterministic, so its hash can key a cache.

    ``traced``: each block function also hands what it wrote to
    ``state._trace_block(block, text, parts, items)`` (the words, and the item that
    wrote each); there are no text lanes, as nothing traced is written to a file.
    """
    return _Generator(post, traced=traced).run()


def generated(post: CompiledPost, *, traced: bool = False) -> GeneratedPost:
    """The generated functions of ``post``, made once per compiled post and flavour
    (cached on it)."""
    key = "_generated_traced" if traced else "_generated"
    cached = post.__dict__.get(key)
    if cached is None:
        from postdsl.codecache import compiled_code

        made = generate(post, traced=traced)
        namespace: dict[str, Any] = {**_runtime(), **made.constants}
        exec(compiled_code(made.source), namespace)  # our own generated text, never user text
        cached = GeneratedPost(post, {key: namespace[name]
                                      for key, name in made.tables.items()},
                               {command: namespace[name]
                                for command, name in made.lanes.items()},
                               {command: namespace[name]
                                for command, name in made.field_lanes.items()})
        object.__setattr__(post, key, cached)  # a cache, not state: frozen is fine
    return cached


class _Code:
    """Lines of Python with an indentation level.

    ``with code.indented():`` indents the lines written inside.  The code is its own
    context manager, not a ``contextlib`` generator: a post's module takes about a
    thousand of them, made again on every run of ``postdsl post``.
    """

    def __init__(self) -> None:
        self.lines: list[str] = []
        self.level = 0

    def __call__(self, text: str) -> None:
        self.lines.append("    " * self.level + text)

    def indented(self) -> _Code:
        return self

    def __enter__(self) -> None:
        self.level += 1

    def __exit__(self, *exc: object) -> None:
        self.level -= 1


class _Located:
    """The ``try:`` of :meth:`_Generator._located`, and its handlers when the body is written."""

    def __init__(self, code: _Code, where: str) -> None:
        self.code = code
        self.where = where

    def __enter__(self) -> None:
        self.code("try:")
        self.code.level += 1

    def __exit__(self, kind: type[BaseException] | None, *exc: object) -> None:
        code = self.code
        code.level -= 1
        if kind is not None:
            return
        where = self.where
        code("except KeyError as error:")
        with code.indented():
            code(f"raise _PostEvalError(str(_no_value(error.args[0])), {where}) from None")
        code("except _ExprEvalError as error:")
        with code.indented():
            code(f"raise _PostEvalError(str(error), {where}) from None")


class _Generator:
    def __init__(self, post: CompiledPost, *, traced: bool = False) -> None:
        self.post = post
        self.traced = traced
        #: the bound name of the item being written (what a traced block records)
        self._item_name = ""
        self.constants: dict[str, Any] = {}
        self._ids: dict[int, str] = {}
        self.code = _Code()
        #: (section, table name) -> the names of its block functions
        self._blocks: dict[tuple[str, str], list[str]] = {}
        #: registers that may hold a raw value (not the written text): some table's
        #: ``assume:`` sets it, or a ``changed_value`` item keeps its value there
        self._assumed = {name for tables in (post.commands, post.custom_cycles)
                         for table in tables.values() for name, _expression in table.assume}
        self._assumed |= _value_registers(post)
        #: what the post's tables may read (None: not known), for the text-only lanes
        self._reads = post_reads(post)
        #: where an item's word goes: ``parts.append(word)`` in a block function; a
        #: local of its own when a text lane writes the block in (:meth:`_inline_block`)
        self._put: Callable[[str], str] = self._append
        #: parameter name -> the local holding its current value (a text lane's fields)
        self._param_locals: dict[str, str] = {}
        #: the function being written has ``changed`` as a local already (a text lane)
        self._changed_local = False
        #: field -> its bit in the local ``given`` (a text lane that sets ``given``)
        self._given_bits: dict[str, int] = {}

    def _append(self, word: str) -> str:
        """A block function's ``put``: the word to its parts (and, traced, its item too)."""
        if self.traced:
            return f"parts.append({word}); items.append({self._item_name})"
        return f"parts.append({word})"

    def bind(self, value: Any) -> str:
        """A module constant holding ``value`` (one name per object)."""
        name = self._ids.get(id(value))
        if name is None:
            name = f"_k{len(self.constants)}"
            self.constants[name] = value
            self._ids[id(value)] = name
        return name

    def run(self) -> GeneratedSource:
        code = self.code
        code('"""A post\'s tables, generated by postdsl.compile.codegen."""')
        tables: dict[tuple[str, str], str] = {}
        for section, commands in (("commands", self.post.commands),
                                  ("custom_cycles", self.post.custom_cycles)):
            for table in commands.values():
                key = (section, table.table)
                if key not in tables:
                    tables[key] = self._table(len(tables), table, section)
        lanes: dict[str, str] = {}
        field_lanes: dict[str, str] = {}
        for command in LANE_COMMANDS:
            lane = self.post.commands.get(command)
            if lane is not None and not lane.expand and not lane.reject and all(
                    block.for_each is None for block in lane.blocks):
                blocks = self._blocks[("commands", lane.table)]
                lanes[command] = self._lane(command, lane, blocks)
                if not self.traced:
                    field_lanes[command] = self._lane(command, lane, blocks, fields=True)
        return GeneratedSource("\n".join(code.lines) + "\n", self.constants, tables, lanes,
                               field_lanes)

    # --- tables and blocks ----------------------------------------------------------

    def _table(self, number: int, table: CompiledCommand, section: str) -> str:
        code = self.code
        blocks = [self._block(f"_b{number}_{index}", block)
                  for index, block in enumerate(table.blocks)]
        self._blocks[(section, table.table)] = blocks
        name = f"_t{number}"
        code("")
        code(f"def {name}(state, command, line):")
        with code.indented():
            code(f"# table {table.table!r}: the lines it writes, each with where it came from")
            code("out = []")
            for index, (block, function) in enumerate(zip(table.blocks, blocks, strict=True)):
                made = f"_LINE(_NCLine, (text, command, {table.table!r}, line, {index}))"
                if block.for_each == "tool":
                    code(f"for text in state._each_tool({function}):")
                    with code.indented():
                        code(f"out.append({made})")
                    continue
                code(f"text = {function}(state)")
                code("if text is not None:")
                with code.indented():
                    code(f"out.append({made})")
            code("return out")
        return name

    def _lane(self, command: str, table: CompiledCommand, blocks: list[str], *,
              fields: bool = False) -> str:
        """The posting of a rapid or linear move in one function: what
        :meth:`postdsl.run.engine.Engine.post_command` does for one, step for step, with the
        record's fields, the machine's limits and the table's blocks written in.

        Nearly every record of a long program is one of these.  Two flavours are written
        from this one text: ``_lane_<command>(state, command)`` returns the NC lines
        (with where each came from, for previews, review and traces), and, with
        ``fields``, ``_fields_<command>(state, add, record)`` takes the record as a
        :data:`~postdsl.cl.model.PlainMove` (its fields, no command object) and hands
        each line's text to ``add``: posting to a file needs nothing else, so neither a
        command object nor an ``NCLine`` is made -- a refusal makes the command it names.
        """
        code = self.code
        lane = _Lane(self, command, table, fields)
        if fields:
            name = f"_fields_{command}"
            arguments = ", ".join(f"in_{field}" for field, _sticky in lane.fields_of)
            code("")
            code(f"def {name}(state, add, record):")
            code(f"    _kind, line, {arguments} = record")
        else:
            name = f"_lane_{command}"
            code("")
            code(f"def {name}(state, command):")
        with code.indented():
            code(f"# the {command} records, posted through table {table.table!r}")
            self._lane_start(lane)
            now = self._lane_fields(lane)
            self._lane_checks(lane, now)
            self._lane_blocks(lane, blocks, now)
        return name

    def _lane_start(self, lane: _Lane) -> None:
        """The record's line, fresh ``changed`` and ``forced``, the last record's changes
        made its prev_ values, ``first_move``."""
        code = self.code
        code(f"state._current_line = {'line' if lane.fields else 'command.line'}")
        if self.traced:
            code("state.record = command  # the lines' record, for the trace")
        if lane.make_changed:
            code("changed = set()")
            code("state.changed = changed")
        if lane.make_forced:
            code("state.forced = set()")
        code("values = state.values")
        if lane.any_previous:
            code("moved = state._moved")
            code("if moved:  # the last record's changes are now its prev_ values")
            with code.indented():
                code("for moved_name in moved:")
                with code.indented():
                    code(f"values[{PREVIOUS!r} + moved_name] = values.get(moved_name)")
                code("moved.clear()")
        if lane.keep_first:
            code("first = state._moves_since_tool == 0")
            code("old = values.get('first_move', _MISSING)")
            code("if old != first:")
            with code.indented():
                if lane.keep_changed:
                    code("changed.add('first_move')")
                if lane.keeps(PREVIOUS + "first_move"):
                    code("moved.add('first_move')")
                    code(f"values[{PREVIOUS + 'first_move'!r}] = "
                         f"None if old is _MISSING else old")
                code("values['first_move'] = first")
        code("state._moves_since_tool += 1")

    def _lane_fields(self, lane: _Lane) -> dict[str, str]:
        """The record's fields into the values (prev_x/y/z first, then ``given``); the
        locals a text lane keeps each sticky field's value in, by field."""
        code = self.code
        #: fields whose value is already in their ``now_`` local (text lane)
        read_now: set[str] = set()
        for axis in "xyz":
            if lane.keeps(PREVIOUS + axis):
                if lane.inline and axis in lane.sticky_fields:
                    code(f"values[{PREVIOUS + axis!r}] = now_{axis} = values.get({axis!r})")
                    read_now.add(axis)
                else:
                    code(f"values[{PREVIOUS + axis!r}] = values.get({axis!r})")
        # `given`: the fields the record carries, as a bit per field; the tuple of each
        # combination is made here once
        if lane.keep_given:
            code("given = 0")
        now: dict[str, str] = {}
        for bit, (field, sticky) in enumerate(lane.fields_of):
            if lane.inline and sticky:
                now[field] = self._field_local(field, bit, lane.keep_given, lane.keep_changed,
                                               lane.keeps(PREVIOUS + field), field in read_now)
            else:
                self._field_value(lane, field, sticky, bit)
        if lane.keep_given:
            combinations = tuple(tuple(field for bit, (field, _sticky)
                                       in enumerate(lane.fields_of) if mask >> bit & 1)
                                 for mask in range(1 << len(lane.fields_of)))
            code(f"values['given'] = {self.bind(combinations)}[given]")
        return now

    def _field_value(self, lane: _Lane, field: str, sticky: bool, bit: int) -> None:
        """One field into the values, as the engine's ``_take_fields`` takes it."""
        code = self.code
        code(f"value = {lane.read(field)}")
        code("if value is not None:")
        code.level += 1
        if lane.keep_given:
            code(f"given |= {1 << bit}")
        if not sticky:
            code.level -= 1
        code(f"old = values.get({field!r}, _MISSING)")
        code("if old != value:")
        with code.indented():
            if lane.keep_changed:
                code(f"changed.add({field!r})")
            if lane.keeps(PREVIOUS + field):
                code(f"if {field!r} not in moved:")
                with code.indented():
                    code(f"moved.add({field!r})")
                    code(f"values[{PREVIOUS + field!r}] = "
                         f"None if old is _MISSING else old")
            code(f"values[{field!r}] = value")
        if sticky:
            code.level -= 1

    def _lane_checks(self, lane: _Lane, now: dict[str, str]) -> None:
        """The engine's checks of a straight move, each refusal worded by its method: the
        feed, the travel and feed range, and what cutting needs (tool, feed, spindle)."""
        code = self.code
        machine = self.post.machine
        record = lane.record
        if lane.has_feed:
            code(f"feed = {lane.read('feed')}")
            code("if feed is not None and not feed > 0:")
            with code.indented():
                code(f"state._check_values({record})")
        for axis in "xyz":
            limits = machine.travel.get(axis)
            if limits is None:
                continue
            low, high = float(limits[0]) - 1e-9, float(limits[1]) + 1e-9
            value = now.get(axis)
            if value is None:
                value = "value"
                code(f"value = values.get({axis!r})")
            code(f"if {value} is not None and not {low!r} <= {value} <= {high!r}:")
            with code.indented():
                code(f"state._check_limits({record})")
        feed_range = [test for bound, test in ((machine.max_feed, "feed > {!r}"),
                                               (machine.min_feed, "feed < {!r}"))
                      if bound is not None for test in [test.format(float(bound))]]
        if lane.has_feed and feed_range:
            code(f"if feed is not None and ({' or '.join(feed_range)}):")
            with code.indented():
                code(f"state._check_limits({record})")
        refusals = ["not state._tool_loaded"] if machine.tool_changer else []
        if lane.has_feed:
            spindle = (" or values.get('spindle') == 'off' or state._speed_stalls is not None"
                       if self.post.commands.get("spindle_on") is not None else "")
            feed_now = now.get("feed", "values.get('feed')")
            refusals.append(f"{feed_now} is None{spindle}")
        if refusals:
            code(f"if {' or '.join(refusals)}:")
            with code.indented():
                code(f"state._check_cutting({record})")

    def _lane_blocks(self, lane: _Lane, blocks: list[str], now: dict[str, str]) -> None:
        """The table's blocks (called, or written in), then what follows them: a move
        inside an open cycle, the table's reset, assume and set."""
        code = self.code
        table, fields, record = lane.table, lane.fields, lane.record
        given_bits = {field: 1 << bit for bit, (field, _sticky) in enumerate(lane.fields_of)
                      } if lane.keep_given else {}
        code("wrote = False" if fields else "out = []")
        code("try:")
        with code.indented():
            if not blocks:
                code("pass")  # a table without blocks writes nothing
            if lane.inline:
                code("registers = state.registers")
            for index, block in enumerate(blocks):
                if lane.inline:
                    self._inline_block(table.blocks[index], index, now, lane.keeps, given_bits)
                    continue
                code(f"text = {block}(state)")
                code("if text is not None:")
                with code.indented():
                    if fields:
                        code("add(text)")
                        code("wrote = True")
                    else:
                        code(f"out.append(_LINE(_NCLine, (text, {lane.command!r}, "
                             f"{table.table!r}, command.line, {index})))")
        code("except _ExprEvalError as error:")
        with code.indented():
            code(f"state._table_failed({self.bind(table)}, {record}, error)")
        code(f"if {'wrote' if fields else 'out'} and state._cycle_table is not None:")
        with code.indented():
            if not lane.make_forced:
                code("state.forced = set()  # no block of this table forces a register")
            code(f"state._move_in_cycle({record})")
        if table.reset or table.assume or table.set:
            code(f"state._after({record}, {self.bind(table)})")
        if not fields:
            code("return out")

    def _field_local(self, field: str, bit: int, keep_given: bool, keep_changed: bool,
                     keep_previous: bool, read: bool) -> str:
        """A text lane's update of a sticky ``field``, leaving its value in a local.

        The same as the command lane's update (``old`` read with ``_MISSING``): a missing
        value reads as None here, and None differs from any value a record carries, as
        ``_MISSING`` does; its ``prev_`` value is None either way.  What the record
        leaves in ``values`` is then in ``now_<field>``, which the limits and the blocks
        written in read instead of looking it up again (``read``: the lane has it there
        already, from setting its ``prev_`` value).
        """
        code = self.code
        local = f"now_{field}"
        given = f"in_{field}"
        if not read:
            code(f"{local} = values.get({field!r})")
        if keep_given:
            code(f"if {given} is not None:")
            code.level += 1
            code(f"given |= {1 << bit}")
            code(f"if {local} != {given}:")
        else:
            code(f"if {given} is not None and {local} != {given}:")
        with code.indented():
            if keep_changed:
                code(f"changed.add({field!r})")
            if keep_previous:
                code(f"if {field!r} not in moved:")
                with code.indented():
                    code(f"moved.add({field!r})")
                    code(f"values[{PREVIOUS + field!r}] = {local}")
            code(f"values[{field!r}] = {local} = {given}")
        if keep_given:
            code.level -= 1
        return local

    def _inlinable(self, table: CompiledCommand) -> bool:
        """Whether a text lane can write ``table``'s blocks in: words joined without a
        separator, and no line end to trim."""
        return not self.post.word_separator and not self.post.trim_line_ends

    def _inline_block(self, block: CompiledBlock, index: int, now: dict[str, str],
                      keeps: Callable[[str], bool], given_bits: dict[str, int]) -> None:
        """Block ``index`` of a text lane's table, written into the lane.

        What :meth:`_block` writes as a function, for a lane that hands the text on and
        nothing else: each item leaves its word in a local of its own (fixed words are
        constants), and the line is one f-string of them - no list of parts, no join,
        no call.  A field's value is read from the lane's local (``now``);
        ``block_number`` is stored only where a table may read it.  In a block written
        only with values, a fixed item's register is written once the block is known
        to be written, so a block left out has nothing to put back; a register some
        other item of the block also writes is saved and put back as :meth:`_block`
        does.  Errors are raised as the block function raises them, inside the lane's
        ``try``.
        """
        code = self.code
        level = code.level
        code(f"# block {index}, written in")
        if block.condition is not None:
            where = self.bind(block.path + ("if",))
            with self._located(where):
                code(f"skip = not {emit_expression(block.condition, self.bind)}")
            code("if not skip:")
            code.level += 1
        self._inline_number(block, keeps)
        deferred, kept = _deferred_registers(block)
        if block.only_with_values:
            if kept:
                code("saved = (" + "".join(f"registers.get({r!r}, _NOTHING), " for r in kept)
                     + ")")
            code("valued = False")
        pieces = self._inline_items(block, index, now, given_bits,
                                    {id(spec) for spec in deferred})
        if block.only_with_values:
            code("if valued:")
            code.level += 1
            for spec in deferred:
                if spec.mode == "forced":
                    code(f"registers.pop({spec.register!r}, None)")
                else:
                    code(f"registers[{spec.register!r}] = {spec.text!r}")
        self._inline_line(block, pieces)
        if block.only_with_values:
            code.level -= 1
            if kept:
                code("else:")
                with code.indented():
                    # nothing but fixed words: the block is not written, so the control
                    # did not receive them either - the registers must not say it did
                    self._restore_saved(kept)
        code.level = level

    def _inline_number(self, block: CompiledBlock, keeps: Callable[[str], bool]) -> None:
        """The block number a text lane's block takes, in the local ``number``."""
        code = self.code
        numbering = self.post.numbering
        if block.renumber:
            code(f"state.number = {numbering.start!r}")
        if block.numbered:
            code("number = state.number")
            code(f"if number > {numbering.maximum!r}:")
            with code.indented():
                code("state._next_number()")
                code("number = state.number")
            if keeps("block_number"):
                code("values['block_number'] = number")

    def _inline_items(self, block: CompiledBlock, index: int, now: dict[str, str],
                      given_bits: dict[str, int], waiting: set[int]) -> list[tuple[bool, str]]:
        """The items of a text lane's block: (a constant, its text | the local's name) each.

        A fixed item (known word, no condition, written every time) is a constant; its
        register is written where it stands unless it is ``waiting`` (written once the
        block is known to be written).  Any other item leaves its word in a local.
        """
        code = self.code
        pieces: list[tuple[bool, str]] = []
        saved_put, saved_locals, saved_changed = \
            self._put, self._param_locals, self._changed_local
        self._param_locals, self._changed_local = now, True
        self._given_bits = given_bits
        try:
            for number, item in enumerate(block.items):
                spec: Any = item.spec
                if _fixed(spec):
                    pieces.append((True, spec.prefix + (spec.text or "") + spec.suffix))
                    if spec.register is not None and id(spec) not in waiting:
                        self._register_effect(spec)
                    elif spec.mode == "forced" and spec.register is not None:
                        code(f"state.forced.add({spec.register!r})")
                    if block.only_with_values and item.is_value:
                        code("valued = True")
                    continue
                local = f"w{index}_{number}"
                code(f"{local} = ''")
                self._put = lambda word, local=local: f"{local} = {word}"  # type: ignore[misc]  # mypy types no lambda default
                self._item(item, block.only_with_values)
                pieces.append((False, local))
        finally:
            self._put, self._param_locals, self._changed_local = \
                saved_put, saved_locals, saved_changed
            self._given_bits = {}
        return pieces

    def _inline_line(self, block: CompiledBlock, pieces: list[tuple[bool, str]]) -> None:
        """The line of a text lane's block, as one f-string handed to ``add`` (unless it
        came out empty), with its block number."""
        code = self.code
        numbering = self.post.numbering
        words = _fstring(pieces)
        sure = any(constant and text for constant, text in pieces)  # never an empty body
        if not sure:
            code(f"body = {words}")
            code("if body:")
            code.level += 1
        if block.numbered:
            number_text = self._number_text()
            words = _fstring([(True, numbering.prefix), (False, number_text),
                              (True, numbering.suffix),
                              *(pieces if sure else [(False, "body")])])
        elif not sure:
            words = "body"
        code(f"add({words})")
        if block.numbered:
            code(f"state.number = number + {numbering.increment!r}")
        code("wrote = True")
        if not sure:
            code.level -= 1

    def _restore_saved(self, kept: Sequence[str]) -> None:
        """Put back the registers ``saved`` holds (``_NOTHING``: the register was unset)."""
        code = self.code
        for position, register in enumerate(kept):
            code(f"if saved[{position}] is _NOTHING:")
            with code.indented():
                code(f"registers.pop({register!r}, None)")
            code("else:")
            with code.indented():
                code(f"registers[{register!r}] = saved[{position}]")

    def _number_text(self) -> str:
        """The expression of the local ``number``'s text, for an f-string: the format's
        int branch written in line where it has one (:func:`count_text`; an f-string
        writes an int's own digits itself), else a call of its render function."""
        numbering = self.post.numbering
        inline = count_text(numbering.format, "number", numbering.start, numbering.maximum)
        if inline is None:
            return f"{self.bind(numbering.format.render)}(number)"
        if inline == "str(number)":
            return "number"
        self.code(f"number_text = {inline}")  # its quotes stay out of the f-string's
        return "number_text"

    def _register_effect(self, spec: Any) -> None:
        """What a fixed item written every time does to its register, where it stands."""
        if spec.mode == "forced":
            self.code(f"registers.pop({spec.register!r}, None)")
            self.code(f"state.forced.add({spec.register!r})")
        else:
            self.code(f"registers[{spec.register!r}] = {spec.text!r}")

    def _block(self, name: str, block: CompiledBlock) -> str:
        code = self.code
        numbering = self.post.numbering
        separator = self.post.word_separator
        code("")
        code(f"def {name}(state):")
        with code.indented():
            code("values = state.values")
            code("registers = state.registers")
            if block.condition is not None:
                where = self.bind(block.path + ("if",))
                test = emit_expression(block.condition, self.bind)
                self._reload_changed()
                with self._located(where):
                    code(f"if not {test}:")
                    with code.indented():
                        code("return None")
            if block.renumber:
                code(f"state.number = {numbering.start!r}")
            if block.numbered:
                # past the maximum, the engine wraps or refuses (one call per wrap, not
                # one per block)
                code(f"if state.number > {numbering.maximum!r}:")
                with code.indented():
                    code("state._next_number()")
                code("values['block_number'] = state.number")
            kept = _registers(block) if block.only_with_values else ()
            if block.only_with_values:
                code("saved = (" + "".join(f"registers.get({r!r}, _NOTHING), " for r in kept)
                     + ")")
                code("valued = False")
            code("parts = []")
            if self.traced:
                code("items = []  # the item that wrote each part")
            for item in block.items:
                self._item(item, block.only_with_values)
            if block.only_with_values:
                code("if not valued:")
                with code.indented():
                    # nothing but fixed words: the block is not written, so the control
                    # did not receive them either - the registers must not say it did
                    self._restore_saved(kept)
                    code("return None")
            if separator:
                code(f"body = {separator!r}.join([part for part in parts if part])")
            else:
                code("body = ''.join(parts)")
            code("if not body:")
            with code.indented():
                code("return None")
            if block.numbered:
                code(f"body = {numbering.prefix!r} + {self.bind(numbering.format.render)}"
                     f"(state.number) + {numbering.suffix!r} + body")
                code(f"state.number += {numbering.increment!r}")
            if self.post.trim_line_ends:
                code("body = body.rstrip(' ')")
            if self.traced:
                code(f"state._trace_block({self.bind(block)}, body, parts, items)")
            code("return body")
        return name

    def _test(self, condition: Expression) -> str:
        """An item's condition: ``'x' in given`` is a test of the lane's bit of ``x`` where
        a text lane has just made ``given`` (the tuple holds a field exactly when its bit
        is set); any other condition is written from its syntax tree."""
        match condition.tree:
            case nodes.Comparison(first=nodes.Const(value=str(field)),
                                  rest=(("in", nodes.Name(name="given")),)) \
                    if field in self._given_bits:
                return f"(given & {self._given_bits[field]})"
        return emit_expression(condition, self.bind)

    def _reload_changed(self) -> None:
        """``changed`` as a local, for the expression written next (a text lane has it)."""
        if not self._changed_local:
            self.code("changed = state.changed")

    def _located(self, where: str) -> _Located:
        """Errors inside are raised as PostEvalError, at ``where`` in the post (its path)."""
        return _Located(self.code, where)

    # --- items ----------------------------------------------------------------------

    def _item(self, item: CompiledItem, only_with_values: bool) -> None:
        code = self.code
        spec = item.spec
        if self.traced:
            self._item_name = self.bind(item)
        mark = "valued = True" if only_with_values and item.is_value else None
        if spec.kind == "text" and spec.condition is None and spec.register is None:
            code(self._put(repr(spec.prefix + (spec.text or '') + spec.suffix)))
            if mark:
                code(mark)
            return
        with self._located(self.bind(item.path)):
            if spec.condition is not None:
                self._reload_changed()
                code(f"if {self._test(spec.condition)}:")
                with code.indented():
                    self._item_body(spec, mark)
            else:
                self._item_body(spec, mark)

    def _item_body(self, spec: Any, mark: str | None) -> None:
        code = self.code
        text_of = self.bind(spec.text_of)
        if spec.kind == "text":
            code(f"text = {spec.text!r}")
        else:
            if spec.kind == "param":
                local = self._param_locals.get(spec.param)
                code(f"value = {local}" if local else f"value = values.get({spec.param!r})")
                if spec.param == "tool_number":
                    code("if value is None:")
                    with code.indented():
                        code("raise _ExprEvalError('the block writes the tool number (a tool or "
                             "its length offset), but no tool is loaded')")
            else:
                self._reload_changed()
                code(f"value = {emit_expression(spec.expression, self.bind)}")
            code("if value is not None:")
            code.level += 1
            if spec.format is not None:
                # the last value and its text: a value the state kept (an unchanged
                # feed, an axis that did not move) is the same object, not formatted again
                memo = self.bind([(_NOTHING, "")])
                code(f"last = {memo}[0]")
                code("if last[0] is value:")
                with code.indented():
                    code("text = last[1]")
                code("elif value.__class__ is float or value.__class__ is int:")
                with code.indented():
                    code("try:")
                    with code.indented():
                        code(f"text = {self.bind(spec.format.render)}(value)")
                    code("except _FORMAT_ERRORS:")
                    with code.indented():
                        code(f"{text_of}(value)  # words the error")
                        code("raise")
                    if spec.feed_check:
                        code("if _NONZERO(text) is None:")
                        with code.indented():
                            code(f"{text_of}(value)  # refuses a feed of zero")
                    for old, new in spec.replace:
                        code(f"text = text.replace({old!r}, {new!r})")
                    code(f"{memo}[0] = (value, text)  # one store: safe between threads")
                code("else:")
                with code.indented():
                    code(f"text = {text_of}(value)")
            else:
                code(f"text = {text_of}(value)")
        self._written(spec, text_of, mark)
        if spec.kind != "text":
            code.level -= 1

    def _written(self, spec: Any, text_of: str, mark: str | None) -> None:
        """The output mode: compare with, or update, the register; then the word."""
        code = self.code
        register = spec.register
        word = " + ".join([*([repr(spec.prefix)] if spec.prefix else []), "text",
                           *([repr(spec.suffix)] if spec.suffix else [])])
        if spec.mode == "changed_value":
            # the value itself, unrounded; a register another item wrote holds text
            force = ""
            if spec.force is not None:
                self._reload_changed()
                force = f" or {emit_expression(spec.force, self.bind)}"
            code(f"last = registers.get({register!r})")
            code(f"if (last != text if last.__class__ is str else last != value){force}:")
            with code.indented():
                code(f"registers[{register!r}] = value")
                code(self._put(word))
                if mark:
                    code(mark)
            return
        if spec.mode == "changed":
            code(f"last = registers.get({register!r})")
            if spec.kind != "text" and register in self._assumed:
                code("if last is not None and last.__class__ is not str:")
                with code.indented():
                    code(f"last = {text_of}(last)  # set by 'assume': a raw value")
            force = ""
            if spec.force is not None:
                self._reload_changed()
                force = f" or {emit_expression(spec.force, self.bind)}"
            code(f"if last != text{force}:")
            with code.indented():
                code(f"registers[{register!r}] = text")
                code(self._put(word))
                if mark:
                    code(mark)
            return
        if register is not None:
            if spec.mode == "forced":
                code(f"registers.pop({register!r}, None)")
                code(f"state.forced.add({register!r})")
            else:
                code(f"registers[{register!r}] = text")
        code(self._put(word))
        if mark:
            code(mark)


class _Lane:
    """What a lane of one straight-move table keeps and how it reads its record: decided
    once, before its text is written (:meth:`_Generator._lane`)."""

    def __init__(self, generator: _Generator, command: str, table: CompiledCommand,
                 fields: bool) -> None:
        from postdsl.cl.model import COMMANDS, ROTARY_FIELDS, command_fields

        self.command, self.table, self.fields = command, table, fields
        #: (field, sticky) of the record class, in the order of a PlainMove's fields
        # a lane carries the plain move's fields: the rotary fields reach only the posts of
        # machines with rotaries, which post without lanes (Engine.__init__)
        self.fields_of = [(f.name, bool(f.metadata.get("sticky")))
                          for f in command_fields(COMMANDS[command])
                          if f.name != "params" and f.name not in ROTARY_FIELDS]
        self.has_feed = any(name == "feed" for name, _sticky in self.fields_of)
        self.sticky_fields = {field for field, sticky in self.fields_of if sticky}
        if fields:
            made = ", ".join(f"{field}=in_{field}" for field, _sticky in self.fields_of)
            #: the command a refusal names (a text lane makes it only then)
            self.record = f"{generator.bind(COMMANDS[command])}({made}, line=line)"
        else:
            self.record = "command"
        # A lane writing text only keeps of a record's bookkeeping what some table of the
        # post may read (the command lane keeps all of it: previews and traces look at
        # the values).  Nothing in the engine reads it back: a move's prev_x/y/z are
        # set again by the next move before it reads them, and `changed` is made anew
        # for each record, so only this table's expressions can ask it.
        self.reads = generator._reads if fields else None
        self.any_previous = self.reads is None or any(name.startswith(PREVIOUS)
                                                      for name in self.reads)
        self.keep_changed = self.reads is None or _asks_changed(table)
        self.keep_first = self.keeps("first_move") or self.keeps(PREVIOUS + "first_move")
        self.keep_given = self.keeps("given")
        # A text lane writes the table's blocks in (see _inline_block) where it can; its
        # fields' current values are then locals, which the limits and the blocks read.
        self.inline = fields and generator._inlinable(table)
        # `changed` and `forced` are made anew for each record before anything reads them:
        # a text lane makes them only where this record may read them ('changed()' in an
        # expression, a 'set:' adding to it, a block forcing a register).  `forced` is also
        # read by _move_in_cycle, which then gets an empty one if the blocks force nothing.
        self.make_changed = not fields or self.keep_changed or bool(table.set)
        self.make_forced = not self.inline or _forces(table)

    def keeps(self, name: str) -> bool:
        return self.reads is None or name in self.reads

    def read(self, field: str) -> str:
        """The expression of a field of the record."""
        return f"in_{field}" if self.fields else f"command.{field}"


def _fstring(pieces: list[tuple[bool, str]]) -> str:
    """One f-string of ``pieces``: constant texts (their braces doubled, the whole made a
    literal by ``repr``) and Python expressions of the generated code (locals, a call of
    a bound constant) in braces.  The line is built in one step, with no list to join."""
    text = "".join(piece.replace("{", "{{").replace("}", "}}") if constant else
                   "{" + piece + "}" for constant, piece in pieces)
    return "f" + repr(text)


def _fixed(spec: Any) -> bool:
    """A fixed item: a known word, no condition, written every time."""
    return spec.kind == "text" and spec.condition is None and spec.mode != "changed"


def _deferred_registers(block: CompiledBlock) -> tuple[list[Any], list[str]]:
    """The specs of a block's fixed items whose register waits until the block is known
    to be written (only_with_values; no other item of the block writes that register),
    and the registers to save and put back instead (:func:`_registers`, less those)."""
    owners: dict[str, int] = {}
    for item in block.items:
        register = item.spec.register
        if register is not None:
            owners[register] = owners.get(register, 0) + 1
    deferred: list[Any] = [
        item.spec for item in block.items
        if block.only_with_values and _fixed(item.spec)
        and item.spec.register is not None
        and owners[item.spec.register] == 1]
    waiting = {spec.register for spec in deferred}
    kept = [register for register in _registers(block) if register not in waiting]
    return deferred, kept


def _forces(table: CompiledCommand) -> bool:
    """Whether a block of ``table`` may add to ``state.forced`` (True when not known)."""
    return any(item.spec.mode == "forced" and item.spec.register is not None
               for block in table.blocks for item in block.items)


def _value_registers(post: CompiledPost) -> set[str]:
    """The registers a ``changed_value`` item keeps a raw value in."""
    return {item.spec.register for tables in (post.commands, post.custom_cycles)
            for table in tables.values() for block in table.blocks for item in block.items
            if item.spec.mode == "changed_value" and item.spec.register is not None}


def _registers(block: CompiledBlock) -> tuple[str, ...]:
    """The registers a block's fixed items may write.

    Only these can have changed when a block of ``only_with_values`` comes out without a
    value: a value item touches its register only where it writes its word, and then the
    block is written.
    """
    registers: list[str] = []
    for item in block.items:
        if item.is_value:
            continue
        if item.spec.register is not None and item.spec.register not in registers:
            registers.append(item.spec.register)
    return tuple(registers)


def _asks_changed(table: CompiledCommand) -> bool:
    """Whether an expression of ``table`` asks ``changed()`` (True when not known)."""
    expressions = table_expressions(table)
    return expressions is None or any(
        isinstance(node, nodes.Probe) and node.function == "changed"
        for expression in expressions
        # table_expressions returns None when a tree is not known: each has its tree
        for node in nodes.walk(expression.tree))  # type: ignore[arg-type]


def _runtime() -> dict[str, Any]:
    """The names every generated module reads (the engine's error class among them)."""
    return {"_PostEvalError": PostEvalError, "_NCLine": NCLine, "_ExprEvalError": ExprEvalError,
            "_MISSING": MISSING, "_LINE": tuple.__new__,
            "_no_value": no_value, "_FORMAT_ERRORS": (DigitsError, ValueError),
            "_NONZERO": _NONZERO, "_NOTHING": _NOTHING, **NAMESPACE}


_NONZERO = re.compile("[1-9]").search

#: no value is this object: the empty memo of a formatted item
_NOTHING = object()
