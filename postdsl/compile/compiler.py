"""Compile a checked post into plain Python closures, once.

Like Jinja2 turning a template into code before rendering, every item of
every block becomes one small closure specialised for its options (text,
parameter or expression; format; output mode; condition), so the engine's
per-block work is a handful of calls with no dictionary lookups of options
and no re-parsing.  Structures (``use:``) are inlined here, redirects are
resolved here, so the engine never sees them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from postdsl.cl.model import with_previous
from postdsl.errors import Location, PostError
from postdsl.kinematics import Kinematics, kinematics_of
from postdsl.lang.control_syntax import CommentSyntax, ProgramNames, comment_syntax, program_names
from postdsl.lang.expr import Expression, ExprEvalError, compile_expr
from postdsl.lang.formats import DEFAULT_MAX_DIGITS, DigitsError, FormatSpecError, NumberFormat
from postdsl.lang.loader import CheckedPost
from postdsl.lang.post.comments import in_comment
from postdsl.lang.post.kinds import may_be_number
from postdsl.lang.post.nodes import (
    BlockEntry,
    BlockNumbers,
    Command,
    Expr,
    ExprItem,
    Item,
    MachineSpec,
    OptionRef,
    Output,
    ParamItem,
    PlainText,
    Post,
    Table,
    TextItem,
)
from postdsl.lang.post.options import OptionValueError, option_values, resolve, resolve_settings
from postdsl.lang.post.structures import Inlined, StructureLoop, inline

#: an item or block renderer: takes the engine state, returns text or None (nothing written)
Test = Callable[[Any], Any]

PathKey = tuple[Any, ...]


@dataclass(frozen=True)
class ItemSpec:
    """An item's options as data, for :mod:`postdsl.compile.codegen` to write it out as Python.

    ``text_of`` is the item's whole value-to-text closure (format, feed-zero check,
    replace table), kept so generated code can hand anything off its fast path to the
    very function the item's own closure uses: one place words every error.
    """

    #: "text", "param" or "expr"
    kind: str
    text: str | None
    param: str | None
    expression: Expression | None
    prefix: str
    suffix: str
    mode: str
    register: str | None
    format: NumberFormat | None
    format_name: str | None
    condition: Expression | None
    force: Expression | None
    replace: tuple[tuple[str, str], ...]
    text_of: Callable[[Any], str]
    #: the feed-zero check applies (the value comes from ``feed``)
    feed_check: bool
    #: the value stands inside a comment: text is escaped by the control's rule
    #: (``text_of`` does it; a number's text needs none)
    comment: bool = False


@dataclass(frozen=True)
class CompiledItem:
    """An item ready to write: the options the generated code writes it from, and what the
    engine's analyses need to know of it."""

    path: PathKey
    condition: Expression | None
    #: the options it is written from (:mod:`postdsl.compile.codegen` inlines them)
    spec: ItemSpec
    #: the parameter a parameter item writes, and its number format
    param: str | None = None
    format: NumberFormat | None = None
    #: the parameters the item's value comes from (its parameter, or its expression's names)
    writes: frozenset[str] = frozenset()
    #: a parameter or computed item, or fixed text that tells the control something
    #: (a modal word other than the motion word, or text shown only under a condition)
    is_value: bool = False


@dataclass(frozen=True)
class CompiledBlock:
    """A block ready to write, its options decided once at load time."""

    items: tuple[CompiledItem, ...]
    condition: Expression | None
    numbered: bool
    renumber: bool
    for_each: str | None
    #: where the block is defined (inside a structure when it came from ``use:``)
    path: PathKey
    #: drop the block when only its fixed-text items would be written
    only_with_values: bool = False


@dataclass(frozen=True)
class CompiledCommand:
    """A table ready to run: its blocks and everything the engine does around them."""

    name: str
    blocks: tuple[CompiledBlock, ...]
    assume: tuple[tuple[str, Expression], ...] = ()
    #: (condition, message): CL values the machine must not be given
    reject: tuple[tuple[Expression, str], ...] = ()
    reset: tuple[str, ...] = ()
    expand: bool = False
    #: a drilling setup: the condition under which its holes are written as moves
    expand_if: Expression | None = None
    #: the table the blocks come from (differs from ``name`` after a redirect)
    table: str = ""
    preview: Mapping[str, Any] = field(default_factory=dict)
    #: custom cycles: parameter defaults
    parameters: Mapping[str, Any] = field(default_factory=dict)
    #: ``verify: motion``: "none" or "unknown" when the control model must not read the
    #: lines, "rapid" when their moves are the control's rapids
    verify_motion: str | None = None
    #: ``verify: words``: machine functions of the table the control model may skip
    verify_words: frozenset[str] = frozenset()
    #: cycle_hole: when true, the hole is written through the open drilling setup's table
    new_cycle_if: Expression | None = None
    #: the format of the first item writing each parameter (what the control reads back)
    formats: Mapping[str, NumberFormat] = field(default_factory=dict)
    #: every parameter the table's items write, directly or in a computed value
    writes: frozenset[str] = frozenset()
    #: arc_move with ``expand``: the furthest (mm) a chord may stray from the arc
    tolerance: float | None = None
    #: ``set:``: flags given new values after the table's blocks, in order
    set: tuple[tuple[str, Expression], ...] = ()
    #: where each ``set:`` entry is in the post, for run-time errors
    set_paths: tuple[PathKey, ...] = ()


@dataclass(frozen=True)
class BlockNumbering:
    """The post's block numbers with every default applied, so the engine reads no options."""

    prefix: str = "N"
    suffix: str = " "
    start: int = 10
    increment: int = 10
    maximum: int = 99999
    #: start again at ``start`` past ``maximum``; otherwise posting stops there
    wrap: bool = False
    default: bool = True
    format: NumberFormat = field(default_factory=lambda: NumberFormat(integer=True))


@dataclass(frozen=True)
class Machine:
    """The machine's limits and data with defaults applied, for the engine's checks."""

    name: str
    controller: str = ""
    units: str = "mm"
    travel: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    spindle: tuple[float, float] | None = None
    min_feed: float | None = None
    max_feed: float | None = None
    rapid_rate: float = 5000.0
    max_tool_number: int | None = None
    max_tool_diameter: float | None = None
    #: the control model of ``postdsl verify`` and its tolerance (mm)
    control: str | None = None
    resolution: float | None = None
    #: the control reads a number without a decimal point in mm (calculator input);
    #: false: as its manual says by default (``postdsl.lang.control_syntax.NUMBERS``)
    calculator_input: bool = False
    #: the lowest tool number the machine has (0 only where a post declares tool 0 valid)
    min_tool_number: int = 1
    #: false for machines without a tool changer (a router): moves need no tool change
    tool_changer: bool = True
    #: the convention of the control's tilted-plane angles (postdsl.frames); None: the
    #: machine does not tilt the working plane
    tilted_plane: str | None = None
    #: what a CL's cutter_compensation means on this machine (COMPENSATION_MODES)
    cutter_compensation: str = "off"
    #: the rotary axes (``machine: rotary_axes``, ``rotary``); no axes on a 3-axis machine
    kinematics: Kinematics = field(default_factory=Kinematics)


#: the meanings a CL's cutter_compensation can have: refused; the path is the tool centre
#: (the control's register holds wear only); the path is the part contour
COMPENSATION_MODES = ("off", "wear", "control")


@dataclass(frozen=True)
class CompiledPost:
    """A post ready to run: what :class:`postdsl.run.engine.Engine` executes."""

    source: CheckedPost
    machine: Machine
    numbering: BlockNumbering
    line_ending: str
    final_newline: bool
    extension: str
    formats: Mapping[str, NumberFormat]
    variables: Mapping[str, Any]
    commands: Mapping[str, CompiledCommand]
    custom_cycles: Mapping[str, CompiledCommand]
    #: the register of the motion word (G0/G1/G2/G3): a canned cycle replaces it
    motion_register: str = "motion"
    #: put between the words of a block (none before the first, none for a suppressed one)
    word_separator: str = ""
    #: trailing spaces removed from every written line (``output.trim_line_ends``)
    trim_line_ends: bool = False
    #: the post's flags and their values at the start of a program (``flags:``)
    flags: Mapping[str, Any] = field(default_factory=dict)

    @property
    def file(self) -> str:
        return self.source.source.file


def compile_post(checked: CheckedPost,
                 options: Mapping[str, Any] | None = None) -> CompiledPost:
    """Turn a checked post into closures for one set of option values.

    ``options`` maps option names to values (text is parsed by the option's type); the
    options left out take their defaults.  Raises PostError for structure loops and for
    an option value the post does not accept (located at the option).
    """
    return _Compiler(checked, options).run()


class _Compiler:
    def __init__(self, checked: CheckedPost, options: Mapping[str, Any] | None = None) -> None:
        self.checked = checked
        self.model = model = checked.model
        try:
            self.options = option_values(model, options)
        except OptionValueError as exc:
            where = checked.locate(model.options[exc.option].path, key=True) \
                if exc.option is not None else Location(checked.source.file)
            raise PostError(str(exc), where) from None
        self.formats = dict(checked.formats)
        if any(isinstance(v, OptionRef) for f in model.formats.values()
               for v in f.values.values()):
            self.formats.update(self._formats_for_options())
        self.default_format = self.formats.get("default")
        self.structures = model.structures
        self.motion_register = model.motion_register
        control = model.machine.control if model.machine is not None else None
        #: the control's comment syntax and program-name rules (None: it states none)
        self.comments: CommentSyntax | None = comment_syntax(control)
        self.program_names: ProgramNames | None = program_names(control)

    def _formats_for_options(self) -> dict[str, NumberFormat]:
        formats: dict[str, NumberFormat] = {}
        for name, spec in self.model.formats.items():
            values = resolve_settings(spec.values, self.options)
            try:
                formats[name] = NumberFormat.from_mapping(
                    {"max_digits": DEFAULT_MAX_DIGITS, **values})
            except FormatSpecError as exc:
                path = spec.path + ((exc.key,) if exc.key in spec.values else ())
                raise PostError(f"format '{name}' with the options given: {exc.message}",
                                self.checked.locate(path)) from None
        return formats

    def run(self) -> CompiledPost:
        model = self.model
        commands: dict[str, CompiledCommand] = {}
        for name, command in model.commands.items():
            table = command
            while table.redirect is not None:
                table = model.commands[table.redirect]
            commands[name] = self._command(name, table.name, table,
                                           self.checked.known_names, table.path,
                                           preview=command.preview or table.preview or {})
        cycles: dict[str, CompiledCommand] = {}
        for name, cycle in model.custom_cycles.items():
            parameters = {p: spec.default for p, spec in (cycle.parameters or {}).items()}
            names = self.checked.known_names | with_previous(parameters)
            compiled = self._command(name, name, cycle, names, cycle.path,
                                     preview=cycle.preview or {})
            cycles[name] = CompiledCommand(**{**compiled.__dict__, "parameters": parameters})
        output = model.output or _NO_OUTPUT
        assert model.machine is not None  # the schema requires it
        machine = self._machine(model.machine)
        self._rezero_written(model.machine, machine.kinematics, commands)
        return CompiledPost(
            source=self.checked,
            machine=machine,
            numbering=self._numbering(model.block_numbers),
            line_ending="\r\n" if output.line_ending == "crlf" else "\n",
            final_newline=bool(_given(output.final_newline, True)),
            extension=str(_given(output.extension, ".nc")),
            formats=self.formats,
            variables={**{k: v.value for k, v in model.variables.items()}, **self.options},
            commands=commands,
            custom_cycles=cycles,
            motion_register=self.motion_register,
            word_separator=str(_given(output.word_separator, "")),
            trim_line_ends=bool(_given(output.trim_line_ends, False)),
            flags={name: flag.value for name, flag in model.flags.items()},
        )

    def _machine(self, spec: MachineSpec) -> Machine:
        travel = {axis: (float(r[0]), float(r[1])) for axis, r in spec.travel.items()}
        spindle = spec.spindle
        tools = spec.tools
        return Machine(
            name=str(spec.name),
            controller=str(_given(spec.controller, "")),
            units=str(_given(resolve(spec.units, self.options), "mm")),
            travel=travel,
            spindle=(float(spindle[0]), float(spindle[1])) if spindle else None,
            min_feed=spec.min_feed,
            max_feed=spec.max_feed,
            rapid_rate=self._rapid_rate(spec),
            max_tool_number=tools.max_number if tools else None,
            max_tool_diameter=tools.max_diameter if tools else None,
            control=spec.control,
            resolution=self._resolution(spec),
            calculator_input=bool(_given(spec.calculator_input, False)),
            min_tool_number=int(_given(tools.min_number if tools else None, 1)),
            tool_changer=bool(_given(spec.tool_changer, True)),
            tilted_plane=spec.tilted_plane,
            cutter_compensation=self._compensation_mode(spec),
            kinematics=self._kinematics(spec),
        )

    def _compensation_mode(self, spec: MachineSpec) -> str:
        """``machine.cutter_compensation``, or the option it names: a CL alone does not say
        whether its path is the tool centre or the part contour, so the post says it, and a
        value outside the three modes is refused at the setting, never read as one."""
        mode = _given(resolve(spec.cutter_compensation, self.options), "off")
        if mode not in COMPENSATION_MODES:
            where = f" (option {spec.cutter_compensation.option})" \
                if isinstance(spec.cutter_compensation, OptionRef) else ""
            raise PostError(f"machine/cutter_compensation{where} is one of "
                            f"{', '.join(COMPENSATION_MODES)}, not {mode!r}",
                            self.checked.locate(spec.path + ("cutter_compensation",)))
        return str(mode)

    def _rezero_written(self, spec: MachineSpec, kin: Kinematics,
                        commands: dict[str, CompiledCommand]) -> None:
        """``rotary: wrap: rezero`` sets the axis's count back before a move (the move's
        ``rezero`` value): a straight-move table that never writes it would leave the count
        unchanged while the angles it writes drop a turn -- refused, never dropped."""
        if kin.wrap != "rezero":
            return
        for name in ("rapid_move", "linear_move"):
            table = commands.get(name)
            expressions = table_expressions(table) if table is not None else []
            written = {w for block in table.blocks for item in block.items
                       for w in item.writes} if table is not None else set()
            if expressions is not None and "rezero" not in written and not any(
                    "rezero" in expression.names for expression in expressions):
                raise PostError(f"machine/rotary: wrap: rezero, but the {name} table never "
                                f"writes rezero (the count to set the axis to before the move, "
                                f"as G92 A...): the turns taken off the angles would be lost",
                                self.checked.locate(spec.path + ("rotary",)))

    def _kinematics(self, spec: MachineSpec) -> Kinematics:
        """``machine.rotary_axes``: what the schema cannot say is refused here, at the key."""
        try:
            return kinematics_of(spec.rotary_axes or (), spec.rotary)
        except ValueError as exc:
            raise PostError(f"machine/rotary_axes: {exc}",
                            self.checked.locate(spec.path + ("rotary_axes",))) from None
    def _resolution(self, spec: MachineSpec) -> float | None:
        """``machine.resolution``, or its value for the options (an inch program's step is
        another than a mm program's); one outside (0, 1] mm is refused at the setting."""
        value = resolve(spec.resolution, self.options)
        if value is None:
            return None
        if not (isinstance(value, (int, float)) and 0 < value <= 1):
            raise PostError(f"machine/resolution must be a number of mm above 0 and at most 1, "
                            f"not {value!r}", self.checked.locate(spec.path + ("resolution",)))
        return float(value)

    def _rapid_rate(self, spec: MachineSpec) -> float:
        """``machine.rapid_rate``, or the value of the option it names (a router whose one
        speed is a setting of its control): the time estimate divides by it, so an option
        value of 0 or below is refused here, at the setting."""
        rate = float(_given(resolve(spec.rapid_rate, self.options), 5000.0))
        if isinstance(spec.rapid_rate, OptionRef) and not (math.isfinite(rate) and rate > 0):
            raise PostError(f"machine/rapid_rate (option {spec.rapid_rate.option}) must be "
                            f"greater than 0, not {rate:g}",
                            self.checked.locate(spec.path + ("rapid_rate",)))
        return rate

    def _numbering(self, spec: BlockNumbers) -> BlockNumbering:
        def setting(value: Any, default: Any) -> Any:
            return _given(resolve(value, self.options), default)

        fmt = self.formats[spec.format] if spec.format is not None \
            else NumberFormat(integer=True)
        start, increment = int(setting(spec.start, 10)), int(setting(spec.increment, 10))
        maximum = int(setting(spec.maximum, 99999))
        if start + increment > maximum and any(
                isinstance(v, OptionRef) for v in (spec.start, spec.increment, spec.maximum)):
            # the checks saw the defaults; these option values leave no second number
            raise PostError(f"block numbers with the options given: start {start}, "
                            f"increment {increment} and maximum {maximum} leave no second "
                            f"block number", self.checked.locate(spec.path))
        return BlockNumbering(
            prefix=str(setting(spec.prefix, "N")),
            suffix=str(setting(spec.suffix, " ")),
            start=int(setting(spec.start, 10)),
            increment=int(setting(spec.increment, 10)),
            maximum=int(setting(spec.maximum, 99999)),
            wrap=bool(setting(spec.wrap, False)),
            default=bool(setting(spec.default, True)),
            format=fmt,
        )

    def _expr(self, expr: Expr, names: frozenset[str],
              inlined: Inlined | None = None) -> Expression:
        """The model's compiled expression, checked against the names of this table.

        A structure's expression was compiled with every custom cycle's parameters known;
        inlined into a table that lacks one, it is compiled again to raise the error.  So
        is one that reads a structure parameter (``with:``: its text as the table runs
        it) and one that writes a number with ``str()``: the model bound stand-ins for
        the formats, which may depend on options.
        """
        compiled = expr.compiled
        source = inlined.text(expr) if inlined is not None else expr.source
        if compiled is None or source != expr.source or not compiled.names <= names or \
                compiled.texts:
            return compile_expr(source, names, self.formats)
        return compiled

    def _command(self, name: str, table: str, spec: Table, names: frozenset[str],
                 path: PathKey, preview: Mapping[str, Any]) -> CompiledCommand:
        blocks = tuple(self._blocks(spec.blocks or (), names, ()))
        assume = tuple((str(reg), self._expr(src, names))
                       for reg, src in (spec.assume or {}).items())
        reject = tuple((self._expr(rule.condition, names), str(rule.message))
                       for rule in spec.reject or ())
        formats: dict[str, NumberFormat] = {}
        writes: set[str] = set()
        for block in blocks:
            for item in block.items:
                writes |= item.writes
                if item.param is not None and item.format is not None:
                    formats.setdefault(item.param, item.format)
        new_cycle = spec.new_cycle_if if isinstance(spec, Command) else None
        expand_if = spec.expand_if if isinstance(spec, Command) else None
        verify = spec.verify
        sets = spec.sets or {}
        return CompiledCommand(
            name=name,
            blocks=blocks,
            assume=assume,
            reject=reject,
            reset=tuple(str(r) for r in spec.reset or ()),
            expand=bool(isinstance(spec, Command) and spec.expand),
            table=table,
            verify_motion=verify.motion if verify is not None else None,
            verify_words=frozenset(verify.words or ()) if verify is not None else frozenset(),
            preview=dict(preview),
            new_cycle_if=self._expr(new_cycle, names) if new_cycle else None,
            expand_if=self._expr(expand_if, names) if expand_if else None,
            formats=formats,
            writes=frozenset(writes),
            tolerance=float(spec.tolerance) if isinstance(spec, Command) and
            spec.tolerance is not None else None,
            set=tuple((flag, self._expr(expr, names)) for flag, expr in sets.items()),
            set_paths=tuple(expr.path for expr in sets.values()),
        )

    def _blocks(self, blocks: tuple[BlockEntry, ...], names: frozenset[str],
                using: tuple[str, ...]) -> list[CompiledBlock]:
        """The table's blocks, structures inlined with their ``if:`` and ``with:``."""
        try:
            resolved = list(inline(self.model, blocks, using=using))
        except StructureLoop as loop:
            raise PostError(str(loop), self.checked.locate(loop.path)) from None
        return [self._block(inlined, names) for inlined in resolved]

    def _block(self, inlined: Inlined, names: frozenset[str]) -> CompiledBlock:
        block = inlined.block
        own = block.condition
        if inlined.condition is None:
            condition = None
        elif own is not None and inlined.condition == own.source:
            condition = self._expr(own, names)
        else:  # a use:'s if:, or a structure parameter in the block's own
            condition = compile_expr(inlined.condition, names, self.formats)
        inside = in_comment(block.items, self.comments)
        items = tuple(self._item(item, names, item.path, inlined, comment)
                      for item, comment in zip(block.items, inside, strict=True))
        return CompiledBlock(
            items=items,
            condition=condition,
            numbered=bool(_given(block.number, self._numbered_default())),
            renumber=bool(block.renumber),
            for_each=block.for_each,
            path=block.path,
            only_with_values=bool(block.only_with_values),
        )

    def _numbered_default(self) -> bool:
        return bool(_given(resolve(self.model.block_numbers.default, self.options), True))

    def _item(self, item: Item, names: frozenset[str], path: PathKey,
              inlined: Inlined | None = None, comment: bool = False) -> CompiledItem:
        """One item's closure.  ``comment``: its value stands inside a comment (see
        :func:`postdsl.lang.post.comments.in_comment`), so text written there is escaped by
        the control's rule, after the post's own ``replace:``; outside a comment, a
        value made of ``program_name`` is checked against the control's name rules."""
        if isinstance(item, PlainText):
            text = item.text
            return CompiledItem(path, None, spec=ItemSpec(
                "text", text, None, None, "", "", "always", None, None, None, None, None, (),
                _same, False))
        writes: frozenset[str] = frozenset()
        prefix = str(item.prefix or "")
        suffix = str(item.suffix or "")
        mode = item.output_mode
        if mode == "changed_value" and isinstance(item, TextItem):
            mode = "changed"  # fixed text: its value is its text
        condition = self._expr(item.condition, names, inlined) if item.condition else None
        force = self._expr(item.force_if, names, inlined) if item.force_if else None
        fmt = self.formats[item.format] if item.format is not None else self.default_format
        what = f"parameter '{item.param}'" if isinstance(item, ParamItem) else \
            f"expression '{item.expr.source if isinstance(item, ExprItem) and item.expr else ''}'"
        render_value = _value_renderer(fmt, what, item.format, prefix.strip())

        expression: Expression | None = None
        replace: tuple[tuple[str, str], ...] = ()
        if isinstance(item, TextItem):
            constant = item.text
            register = item.modal

            def constant_value(state: Any) -> Any:
                return constant

            def constant_text(value: str) -> str:
                return value

            # a callable each, replaced by other callables (wrappers) in the other branch
            value: Callable[[Any], Any] = constant_value
            text_of: Callable[[Any], str] = constant_text
        else:
            if isinstance(item, ParamItem):
                param = item.param
                register = _given(item.modal, param)

                def param_value(state: Any) -> Any:
                    return state.values.get(param)

                value = param_value

                writes = frozenset((param,))
                if param == "tool_number":
                    value = _needs_tool(value)
            else:
                assert isinstance(item, ExprItem) and item.expr is not None
                expression = self._expr(item.expr, names, inlined)
                register = item.modal
                if fmt is None and may_be_number(expression.tree, self.model):
                    # the checks saw the structure's own text; this is the use:'s
                    raise PostError(f"the computed item '{expression.source}' (as this "
                                    f"table's use: makes it) may write a number, and it has "
                                    f"no format: every number goes through a format",
                                    self.checked.locate(path + ("expr",)))
                value = expression.evaluate
                writes = expression.names
            text_of = render_value
            if "feed" in writes:
                text_of = _not_zero(text_of, what)
            if item.replace:
                replace = tuple(item.replace)
                text_of = _replacing(text_of, replace)
            if comment and self.comments is not None:
                text_of = _escaping(text_of, self.comments)
            elif not comment and self.program_names is not None and "program_name" in writes:
                text_of = _program_name(text_of, self.program_names, what)

        if isinstance(item, TextItem):
            # fixed text is a value when it tells the control something the block must
            # carry: a modal word other than the motion word (an axis written as text, a
            # coolant code), or text the data switches on with its own condition
            is_value = (register is not None and register != self.motion_register) \
                or condition is not None
        else:
            is_value = True
        kind = "text" if isinstance(item, TextItem) else \
            "param" if isinstance(item, ParamItem) else "expr"
        spec = ItemSpec(kind, item.text if isinstance(item, TextItem) else None,
                        item.param if isinstance(item, ParamItem) else None, expression,
                        prefix, suffix, mode, register, fmt, item.format, condition,
                        force, replace, text_of, kind != "text" and "feed" in writes,
                        comment and self.comments is not None)
        return CompiledItem(path, condition,
                            param=item.param if isinstance(item, ParamItem) else None,
                            format=fmt if isinstance(item, ParamItem) else None, writes=writes,
                            is_value=is_value, spec=spec)


_NO_OUTPUT = Output(("output",))


def _given(value: Any, default: Any) -> Any:
    """A setting's value, or ``default`` when the post leaves it out."""
    return default if value is None else value


def _value_renderer(fmt: NumberFormat | None, what: str = "the value",
                    format_name: str | None = None, word: str = "") -> Callable[[Any], str]:
    """Numbers through the item's format, text as it is; one place decides.

    It is also the last gate before the NC program, so what no block can hold stops
    here, with ``what`` (the item's parameter or expression) named: text with a line
    break or another control character (it would start a block the control executes),
    text where the item names a number format (CL text such as "ten" must not become
    the word ``Xten``), lists, infinities and NaN.
    """
    number_text = fmt.render if fmt is not None else None
    named = f"format '{format_name}'" if format_name else "the default format"

    def too_long(value: Any, error: DigitsError) -> ExprEvalError:
        # the word and the value as the control would have received them
        scaled = f" times {fmt.multiplier:g}" if fmt is not None and fmt.multiplier != 1 \
            else ""
        return ExprEvalError(f"the word {word or '(no prefix)'} of {what}: the value "
                             f"{_number(value)}{scaled} has {error.digits} digits before the "
                             f"point, "
                             f"more than the {error.allowed} {named} allows (max_digits)")

    def text_of(value: Any) -> str:
        cls = value.__class__
        if (cls is float or cls is int) and number_text is not None:  # the hot path
            try:
                return number_text(value)
            except DigitsError as exc:
                raise too_long(value, exc) from None
            except ValueError:  # nan, inf
                raise ExprEvalError(f"{what} is {_number(value)}, which cannot be written") \
                    from None
        if cls is str:
            if format_name is not None:
                raise ExprEvalError(f"{what} is the text {_short(value)}, but the item writes "
                                    f"it as a number (format '{format_name}')")
            if not value.isprintable():
                bad = next(c for c in value if not c.isprintable())
                raise ExprEvalError(f"{what} is text holding the control character "
                                    f"{bad!r}, which would break the NC block")
            return value  # type: ignore[no-any-return]  # a str: cls is str
        if isinstance(value, (list, tuple, dict, set, frozenset)):
            kind = "list" if isinstance(value, (list, tuple)) else type(value).__name__
            raise ExprEvalError(f"{what} is the {kind} {_short(value)}, which cannot be "
                                f"written as NC text")
        if isinstance(value, float) and not math.isfinite(value):
            raise ExprEvalError(f"{what} is {value!r}, which cannot be written")
        if number_text is None:
            if isinstance(value, (int, float)) and not isinstance(value, bool) and \
                    not -_UNFORMATTED_LIMIT < value < _UNFORMATTED_LIMIT:
                digits = len(f"{abs(value):.0f}") if abs(value) < 1e300 else 301
                raise too_long(value, DigitsError(digits, DEFAULT_MAX_DIGITS))
            return _unformatted(value)
        try:
            return number_text(value)
        except DigitsError as exc:
            raise too_long(value, exc) from None

    return text_of


def _same(value: Any) -> Any:
    return value


def _not_zero(text_of: Callable[[Any], str], what: str) -> Callable[[Any], str]:
    """A feed word that comes out as zero (F0, F0.0) would stop the axes or be refused."""

    def checked(value: Any) -> str:
        text = text_of(value)
        if isinstance(value, (int, float)) and not any(c in "123456789" for c in text):
            raise ExprEvalError(f"{what} is {_short(value)}, which the format writes as "
                                f"{text!r}: a feed of zero")
        return text

    return checked


def _needs_tool(value: Callable[[Any], Any]) -> Callable[[Any], Any]:
    """A tool number word (T, a length offset H) with no tool loaded cannot be written."""

    def tool(state: Any) -> Any:
        number = value(state)
        if number is None:
            raise ExprEvalError("the block writes the tool number (a tool or its length "
                                "offset), but no tool is loaded")
        return number

    return tool


def motion_register(post: CheckedPost | Post) -> str:
    """The register of the motion word, as the post names it (``motion`` by default)."""
    model = post.model if isinstance(post, CheckedPost) else post
    return model.motion_register


#: a number written without a format (a custom cycle's argument) is bounded as a post's
#: formats are by default; beyond it str() would write "1e+300"
_UNFORMATTED_LIMIT = 10**DEFAULT_MAX_DIGITS


def _number(value: Any) -> str:
    """A number for a message, however long: its first digits and how many there are."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 64:
        if value.bit_length() > 14_000:  # str() refuses more than 4,300 digits
            return f"a whole number of about {value.bit_length() * 3 // 10:,} digits"
        text = str(value)
        digits = len(text.lstrip("-"))
        return text if digits <= 20 else f"{text[:10]}…({digits} digits)"
    return repr(value)


def _replacing(text_of: Callable[[Any], str],
               replacements: tuple[tuple[str, str], ...]) -> Callable[[Any], str]:
    """The item's ``replace`` table, applied in order to the written value."""

    def replaced(value: Any) -> str:
        text = text_of(value)
        for old, new in replacements:
            text = text.replace(old, new)
        return text

    return replaced


def _escaping(text_of: Callable[[Any], str], syntax: CommentSyntax) -> Callable[[Any], str]:
    """Text written inside a comment, escaped by the control's rule.

    CL text (a comment, an operation's or a tool's name) holding the character that
    closes the comment would end it there, and the rest of the text would be read as
    NC words: ``end of roughing) M30 (`` ends the program.  The control's comment syntax
    says which characters break out and what stands in for each; a number's text is
    left as its format wrote it (the test costs one class comparison)."""
    escape = syntax.escape

    def escaped(value: Any) -> str:
        text = text_of(value)
        if value.__class__ is str:
            return escape(text)
        return text

    return escaped


def _program_name(text_of: Callable[[Any], str], rules: ProgramNames,
                  what: str) -> Callable[[Any], str]:
    """A program name the control would refuse to load is refused at the CL line.

    Outside a comment, text made of ``program_name`` is the name the control files
    the program under (Heidenhain's ``BEGIN PGM``): a character the control does not
    take there makes a program it refuses at load.  The name is checked as written,
    after the post's own ``replace:``, and never changed silently."""

    def named(value: Any) -> str:
        text = text_of(value)
        problem = rules.problem(text)
        if problem is not None:
            raise ExprEvalError(f"{what} writes the program name {_short(text)}: {problem}")
        return text

    return named


def _short(value: Any, limit: int = 60) -> str:
    text = repr(list(value) if isinstance(value, tuple) else value)
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _unformatted(value: Any) -> str:
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return str(value)


def post_reads(post: CompiledPost) -> frozenset[str] | None:
    """The value names the tables of ``post`` may read: in their expressions and
    conditions, and the parameters their items write; None when an item's reads are not
    known (an item made without its options: its closure may read anything)."""
    names: set[str] = set()
    for tables in (post.commands, post.custom_cycles):
        for table in tables.values():
            expressions = table_expressions(table)
            if expressions is None:
                return None
            for expression in expressions:
                names.update(expression.names)
            for block in table.blocks:
                for item in block.items:
                    names.update(item.writes)  # a parameter item's parameter among them
    return frozenset(names)


def table_expressions(table: CompiledCommand) -> list[Expression] | None:
    """Every expression of ``table``; None when an item's or an expression's syntax
    tree is not known."""
    found: list[Expression | None] = [expression for _name, expression in table.assume]
    found.extend(condition for condition, _message in table.reject)
    found.extend(expression for _flag, expression in table.set)
    found.extend((table.expand_if, table.new_cycle_if))
    for block in table.blocks:
        found.append(block.condition)
        for item in block.items:
            spec = item.spec
            if spec is None:
                return None
            found.extend((item.condition, spec.condition, spec.force, spec.expression))
    expressions = [expression for expression in found if expression is not None]
    if any(expression.tree is None for expression in expressions):
        return None
    return expressions
