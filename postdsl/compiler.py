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

from postdsl.errors import PostError
from postdsl.expr import Expression, ExprEvalError, compile_expr
from postdsl.formats import DEFAULT_MAX_DIGITS, DigitsError, NumberFormat
from postdsl.loader import CheckedPost

#: an item or block renderer: takes the engine state, returns text or None (nothing written)
Render = Callable[[Any], "str | None"]
Test = Callable[[Any], Any]

PathKey = tuple[Any, ...]


@dataclass(frozen=True)
class CompiledItem:
    render: Render
    path: PathKey
    condition: Expression | None
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
    name: str
    blocks: tuple[CompiledBlock, ...]
    assume: tuple[tuple[str, Expression], ...] = ()
    #: (condition, message): CL values the machine must not be given
    reject: tuple[tuple[Expression, str], ...] = ()
    reset: tuple[str, ...] = ()
    expand: bool = False
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


@dataclass(frozen=True)
class BlockNumbering:
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
    #: the lowest tool number the machine has (0 only where a post declares tool 0 valid)
    min_tool_number: int = 1
    #: false for machines without a tool changer (a router): moves need no tool change
    tool_changer: bool = True


@dataclass(frozen=True)
class CompiledPost:
    """A post ready to run: what :class:`postdsl.engine.Engine` executes."""

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

    @property
    def file(self) -> str:
        return self.source.source.file


def compile_post(checked: CheckedPost) -> CompiledPost:
    """Turn a checked post into closures; raises PostError only for structure loops."""
    return _Compiler(checked).run()


class _Compiler:
    def __init__(self, checked: CheckedPost) -> None:
        self.checked = checked
        self.data = checked.data
        self.formats = dict(checked.formats)
        self.default_format = self.formats.get("default")
        self.structures = self.data.get("structures") or {}
        self.motion_register = motion_register(self.data)

    def run(self) -> CompiledPost:
        data = self.data
        commands_data = data.get("commands") or {}
        commands: dict[str, CompiledCommand] = {}
        for name, command in commands_data.items():
            table = name
            while "redirect" in commands_data[table]:
                table = commands_data[table]["redirect"]
            commands[name] = self._command(name, table, commands_data[table],
                                           self.checked.known_names, ("commands", table),
                                           preview=command.get("preview") or
                                           commands_data[table].get("preview") or {})
        cycles: dict[str, CompiledCommand] = {}
        for name, cycle in (data.get("custom_cycles") or {}).items():
            parameters = {p: (spec or {}).get("default")
                          for p, spec in (cycle.get("parameters") or {}).items()}
            names = self.checked.known_names | frozenset(parameters)
            compiled = self._command(name, name, cycle, names, ("custom_cycles", name),
                                     preview=cycle.get("preview") or {})
            cycles[name] = CompiledCommand(**{**compiled.__dict__, "parameters": parameters})
        output = data.get("output") or {}
        return CompiledPost(
            source=self.checked,
            machine=self._machine(data["machine"]),
            numbering=self._numbering(output.get("block_numbers") or {}),
            line_ending="\r\n" if output.get("line_ending") == "crlf" else "\n",
            final_newline=bool(output.get("final_newline", True)),
            extension=str(output.get("extension", ".nc")),
            formats=self.formats,
            variables={k: _plain(v) for k, v in (data.get("variables") or {}).items()},
            commands=commands,
            custom_cycles=cycles,
            motion_register=self.motion_register,
        )

    def _machine(self, spec: Mapping[str, Any]) -> Machine:
        travel = {axis: (float(r[0]), float(r[1]))
                  for axis, r in (spec.get("travel") or {}).items()}
        spindle = spec.get("spindle")
        tools = spec.get("tools") or {}
        return Machine(
            name=str(spec["name"]),
            controller=str(spec.get("controller", "")),
            units=str(spec.get("units", "mm")),
            travel=travel,
            spindle=(float(spindle[0]), float(spindle[1])) if spindle else None,
            min_feed=spec.get("min_feed"),
            max_feed=spec.get("max_feed"),
            rapid_rate=float(spec.get("rapid_rate", 5000.0)),
            max_tool_number=tools.get("max_number"),
            max_tool_diameter=tools.get("max_diameter"),
            control=spec.get("control"),
            resolution=float(spec["resolution"]) if "resolution" in spec else None,
            min_tool_number=int(tools.get("min_number", 1)),
            tool_changer=bool(spec.get("tool_changer", True)),
        )

    def _numbering(self, spec: Mapping[str, Any]) -> BlockNumbering:
        fmt = self.formats[spec["format"]] if "format" in spec else NumberFormat(integer=True)
        return BlockNumbering(
            prefix=str(spec.get("prefix", "N")),
            suffix=str(spec.get("suffix", " ")),
            start=int(spec.get("start", 10)),
            increment=int(spec.get("increment", 10)),
            maximum=int(spec.get("maximum", 99999)),
            wrap=bool(spec.get("wrap", False)),
            default=bool(spec.get("default", True)),
            format=fmt,
        )

    def _command(self, name: str, table: str, spec: Mapping[str, Any], names: frozenset[str],
                 path: PathKey, preview: Mapping[str, Any]) -> CompiledCommand:
        blocks = tuple(self._blocks(spec.get("blocks") or [], names, path + ("blocks",), ()))
        assume = tuple((str(reg), compile_expr(src, names, self.formats))
                       for reg, src in (spec.get("assume") or {}).items())
        reject = tuple((compile_expr(rule["if"], names, self.formats), str(rule["message"]))
                       for rule in spec.get("reject") or ())
        formats: dict[str, NumberFormat] = {}
        writes: set[str] = set()
        for block in blocks:
            for item in block.items:
                writes |= item.writes
                if item.param is not None and item.format is not None:
                    formats.setdefault(item.param, item.format)
        new_cycle = spec.get("new_cycle_if")
        return CompiledCommand(
            name=name,
            blocks=blocks,
            assume=assume,
            reject=reject,
            reset=tuple(str(r) for r in spec.get("reset") or ()),
            expand=bool(spec.get("expand", False)),
            table=table,
            verify_motion=(spec.get("verify") or {}).get("motion"),
            verify_words=frozenset(str(w) for w in (spec.get("verify") or {}).get("words", ())),
            preview={k: _plain(v) for k, v in preview.items()},
            new_cycle_if=compile_expr(new_cycle, names, self.formats) if new_cycle else None,
            formats=formats,
            writes=frozenset(writes),
            tolerance=float(spec["tolerance"]) if "tolerance" in spec else None,
        )

    def _blocks(self, blocks: list[Any], names: frozenset[str], path: PathKey,
                using: tuple[str, ...]) -> list[CompiledBlock]:
        compiled: list[CompiledBlock] = []
        for index, block in enumerate(blocks):
            if "use" in block:
                target = block["use"]
                if target in using:
                    raise PostError("structure loop: " + " -> ".join(using + (target,)),
                                    self.checked.source.locate(path + (index, "use")))
                compiled += self._blocks(self.structures[target], names,
                                         ("structures", target), using + (target,))
                continue
            here = path + (index,)
            condition = compile_expr(block["if"], names, self.formats) if "if" in block else None
            items = tuple(self._item(item, names, here + ("items", i))
                          for i, item in enumerate(block["items"]))
            compiled.append(CompiledBlock(
                items=items,
                condition=condition,
                numbered=bool(block.get("number", self._numbered_default())),
                renumber=bool(block.get("renumber", False)),
                for_each=block.get("for_each"),
                path=here,
                only_with_values=bool(block.get("only_with_values", False)),
            ))
        return compiled

    def _numbered_default(self) -> bool:
        return bool(((self.data.get("output") or {}).get("block_numbers") or {})
                    .get("default", True))

    def _item(self, item: Any, names: frozenset[str], path: PathKey) -> CompiledItem:
        if isinstance(item, str):
            text = str(item)
            return CompiledItem(lambda state: text, path, None)
        writes: frozenset[str] = frozenset()
        prefix = str(item.get("prefix", ""))
        suffix = str(item.get("suffix", ""))
        mode = item.get("mode", "always")
        condition = compile_expr(item["if"], names, self.formats) if "if" in item else None
        force = compile_expr(item["force_if"], names, self.formats) if "force_if" in item else None
        fmt = self.formats[item["format"]] if "format" in item else self.default_format
        what = f"parameter '{item['param']}'" if "param" in item else \
            f"expression '{item.get('expr', '')}'"
        render_value = _value_renderer(fmt, what, item.get("format"),
                                       str(item.get("prefix", "")).strip())

        if "text" in item:
            constant = str(item["text"])
            register = item.get("modal")

            def value(state: Any) -> Any:
                return constant

            def text_of(value: Any) -> str:
                return value
        else:
            if "param" in item:
                param = str(item["param"])
                register = item.get("modal", param)

                def value(state: Any) -> Any:
                    return state.values.get(param)

                writes = frozenset((param,))
                if param == "tool_number":
                    value = _needs_tool(value)
            else:
                expression = compile_expr(item["expr"], names, self.formats)
                register = item.get("modal")
                value = expression.evaluate
                writes = expression.names
            text_of = render_value
            if "feed" in writes:
                text_of = _not_zero(text_of, what)
            if item.get("replace"):
                text_of = _replacing(text_of, tuple((str(old), str(new)) for old, new
                                                    in item["replace"].items()))

        render = _mode_renderer(mode, value, text_of, prefix, suffix, register,
                                condition.evaluate if condition else None,
                                force.evaluate if force else None)
        if "text" in item:
            # fixed text is a value when it tells the control something the block must
            # carry: a modal word other than the motion word (an axis written as text, a
            # coolant code), or text the data switches on with its own condition
            is_value = (register is not None and register != self.motion_register) \
                or condition is not None
        else:
            is_value = True
        return CompiledItem(render, path, condition, param=item.get("param"),
                            format=fmt if "param" in item else None, writes=writes,
                            is_value=is_value)


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
            return value
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


def motion_register(data: Mapping[str, Any]) -> str:
    """The register of the motion word, as the post names it (``motion`` by default)."""
    return str((data.get("output") or {}).get("motion_register", "motion"))


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


def _mode_renderer(mode: str, value: Callable[[Any], Any], text_of: Callable[[Any], str],
                   prefix: str, suffix: str, register: str | None,
                   condition: Test | None, force: Test | None) -> Render:
    """The closure for one item, specialised by output mode (the engine's hot path)."""

    if mode == "changed":
        assert register is not None

        def render(state: Any) -> str | None:
            if condition is not None and not condition(state):
                return None
            current = value(state)
            if current is None:
                return None
            text = text_of(current)
            registers = state.registers
            last = registers.get(register)
            if last is not None and last.__class__ is not str:
                last = text_of(last)  # set by 'assume': a raw value
            if last == text and not (force is not None and force(state)):
                return None
            registers[register] = text
            return prefix + text + suffix

        return render

    def render_always(state: Any) -> str | None:
        if condition is not None and not condition(state):
            return None
        current = value(state)
        if current is None:
            return None
        text = text_of(current)
        if register is not None:
            if mode == "forced":
                state.registers.pop(register, None)
                state.forced.add(register)  # written, though no longer remembered
            else:
                state.registers[register] = text
        return prefix + text + suffix

    return render_always


def _plain(value: Any) -> Any:
    """ruamel scalars -> plain Python values (so they compare and hash as users expect)."""
    if isinstance(value, bool) or value is None:
        return value
    if isinstance(value, int):
        return int(value)
    if isinstance(value, float):
        return float(value)
    if isinstance(value, str):
        return str(value)
    return value
