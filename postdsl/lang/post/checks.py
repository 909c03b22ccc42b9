"""The meaning of a post, checked on its typed model: what a JSON Schema cannot express.

Command, parameter, format and structure names, expressions, redirects, ranges,
options: every problem is collected (not just the first) as a :class:`Problem` at a
YAML path, which the loader turns into ``file:line:column``.
"""

from __future__ import annotations

import difflib
import itertools
import math
import re
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any

from postdsl.cl.model import COMMANDS, DRILL_SETUPS, EVENTS, PARAMETERS, with_previous
from postdsl.lang.control_syntax import NumberSyntax, number_syntax
from postdsl.lang.expr import ExprError, compile_expr
from postdsl.lang.formats import DEFAULT_MAX_DIGITS, DigitsError, FormatSpecError, NumberFormat
from postdsl.lang.post import nodes as n
from postdsl.lang.post.kinds import kind, may_be_number
from postdsl.lang.post.options import OPTION_TYPES, resolve, resolve_settings, type_matches
from postdsl.lang.post.structures import StructureLoop, inline, item_exprs, reads

PathKey = tuple[Any, ...]

#: most blocks one table may expand to through ``use:``; the bundled posts' largest has
#: under 20, and a control program's header or a probing cycle a few dozen
MAX_TABLE_BLOCKS = 10_000


@dataclass
class Problem:
    path: PathKey
    message: str
    key: bool = False
    offset: int = 0
    #: the file the node was written in, when another than the post's own (extends:)
    file: str | None = None


def hint(name: str, candidates: Iterable[str]) -> str:
    close = difflib.get_close_matches(name, list(candidates), n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


def finite_problems(node: Any, path: PathKey = ()) -> list[Problem]:
    """.nan and .inf are YAML numbers the schema lets through; no post means them.

    A walk over every value of the document, whatever its key: it reads no key by name.
    """
    if isinstance(node, float) and not math.isfinite(node):
        text = ".nan" if node != node else (".inf" if node > 0 else "-.inf")
        where = "/".join(str(p) for p in path)
        return [Problem(path, f"{where}: {text} is not a finite number")]
    found: list[Problem] = []
    if isinstance(node, Mapping):
        for key, value in node.items():
            found += finite_problems(value, path + (key,))
    elif isinstance(node, list):
        for index, value in enumerate(node):
            found += finite_problems(value, path + (index,))
    return found


#: the option type each ``output.block_numbers`` setting takes
_NUMBERING_TYPES = {"prefix": "string", "suffix": "string", "start": "int",
                    "increment": "int", "maximum": "int", "wrap": "bool", "default": "bool"}
#: the ``machine:`` settings that may be ``{option: NAME}``, and the option type each takes
_MACHINE_TYPES: dict[PathKey, str] = {("machine", "rapid_rate"): "number",
                                      ("machine", "resolution"): "number",
                                      ("machine", "units"): "string"}
#: option types a setting of a type also takes (an int option is a number)
_WIDER = {"number": ("int",)}


class Semantics:
    """Checks the model of a schema-valid post for meaning; collects problems."""

    def __init__(self, post: n.Post) -> None:
        self.post = post
        self.problems: list[Problem] = []
        self.formats: dict[str, NumberFormat] = {}
        self.variables = set(post.variables)
        self.flags = set(post.flags)
        self.known_names = with_previous(frozenset(PARAMETERS) | frozenset(self.variables)
                                         | frozenset(post.options) | frozenset(self.flags))
        self.structures = post.structures
        #: structure -> the parameters its use: sites give with with:
        self.parameters = _parameters(post)

    def add(self, path: PathKey, message: str, *, key: bool = False, offset: int = 0,
            node: Any = None) -> None:
        self.problems.append(Problem(path, message, key, offset,
                                     getattr(node, "file", None)))

    def run(self) -> list[Problem]:
        post = self.post
        for name in self.variables & set(PARAMETERS):
            self.add(("variables", name), f"variable '{name}' hides the parameter of that name",
                     key=True, node=post.variables[name])
        for name in sorted(self.flags & (set(PARAMETERS) | self.variables | set(post.options))):
            what = "parameter" if name in PARAMETERS else \
                "variable" if name in self.variables else "option"
            self.add(post.flags[name].path, f"flag '{name}' hides the {what} of that name",
                     key=True, node=post.flags[name])
        self._options()
        self._machine()
        self._formats()
        self._block_numbers()
        for name, command in post.commands.items():
            self._command(command.path, name, command, self.known_names)
        for name, cycle in post.custom_cycles.items():
            params = set(cycle.parameters or {})
            for pname in params & set(PARAMETERS):
                self.add(("custom_cycles", name, "parameters", pname),
                         f"cycle parameter '{pname}' hides the CL parameter of that name",
                         key=True, node=cycle)
            self._command(cycle.path, name, cycle, self.known_names | with_previous(params),
                          custom=True)
        for name, structure in self.structures.items():
            # a structure may serve custom cycles too, so their parameters are known in it
            self._blocks(structure.blocks, self.known_names
                         | with_previous(self._all_cycle_params())
                         | self.parameters.get(name, frozenset()), seen=(name,))
        self._expansion()
        self.problems += decimal_point_problems(post, self.formats)
        self.problems += tilted_plane_problems(post)
        self._comment_text()
        return self.problems

    def _comment_text(self) -> None:
        """CL text goes into comments, and a comment's text is the control's to escape.

        Free text from the CL (a comment, an operation's or a tool's name, the file's
        name) written outside any comment is read as NC words: ``X0 M30`` in a tool
        name would run.  Only a program name where the control files the program
        under it (its name rules, checked at the CL line) may stand there.  Inside a
        comment the compiler escapes CL text by the control's rule, after the item's
        ``replace:``: a replace that maps to a character breaking the comment would be
        undone there, so it is reported rather than silently changed.  A post that names
        no known control has no comment syntax to check against.
        """
        from postdsl.lang.control_syntax import comment_syntax, program_names
        from postdsl.lang.post.comments import in_comment

        control = self.post.machine.control if self.post.machine is not None else None
        syntax = comment_syntax(control)
        if syntax is None:
            return
        names_ok = program_names(control) is not None
        seen: set[PathKey] = set()
        tables: list[n.Table] = [*self.post.commands.values(),
                                 *self.post.custom_cycles.values()]
        for table in tables:
            try:
                resolved = list(itertools.islice(inline(self.post, table.blocks),
                                                 MAX_TABLE_BLOCKS + 1))
            except StructureLoop:
                continue  # reported where it is
            for inlined in resolved[:MAX_TABLE_BLOCKS]:
                items = inlined.block.items
                for item, inside in zip(items, in_comment(items, syntax), strict=True):
                    if item.path in seen:
                        continue
                    seen.add(item.path)
                    if inside:
                        self._breaking_replace(item, syntax, control)
                    else:
                        self._text_as_code(item, syntax, control, names_ok)

    def _breaking_replace(self, item: n.Item, syntax: Any, control: str | None) -> None:
        for old, new in item.replace or ():
            bad = sorted({c for c in syntax.breaks if c in str(new)})
            if bad:
                shown = " ".join(repr(c) for c in bad)
                self.add(item.path + ("replace", old), f"replace maps {old!r} to {new!r} "
                         f"inside a comment, but {shown} breaks out of a {control} comment: "
                         f"the compiler escapes CL text there by the control's rule (leave "
                         f"this replace out)", node=item)

    def _text_as_code(self, item: n.Item, syntax: Any, control: str | None,
                      names_ok: bool) -> None:
        if isinstance(item, n.ParamItem):
            read = {item.param}
        elif isinstance(item, n.ExprItem) and item.expr is not None and \
                item.expr.compiled is not None:
            read = set(item.expr.compiled.names)
        else:
            return
        found = sorted({name[len("prev_"):] if name.startswith("prev_") else name
                        for name in read} & CL_TEXT - ({"program_name"} if names_ok else set()))
        if found:
            where = f"'{syntax.opens}' ... '{syntax.closes}'" if syntax.closes else \
                f"'{syntax.opens}' to the end of the block"
            self.add(item.path, f"CL text ({', '.join(found)}) written outside a comment: "
                     f"the control would read text such as 'X0 M30' in it as NC words; "
                     f"write it inside a {control} comment: {where}", node=item)

    # --- options --------------------------------------------------------------------------

    def _options(self) -> None:
        for name, option in self.post.options.items():
            if name in PARAMETERS:
                self.add(option.path, f"option '{name}' hides the parameter of that name",
                         key=True, node=option)
            elif name in self.variables:
                self.add(option.path, f"option '{name}' hides the variable of that name",
                         key=True, node=option)
            if not type_matches(option.type, option.default):
                self.add(option.path + ("default",),
                         f"option '{name}': the default {option.default!r} is not "
                         f"{OPTION_TYPES[option.type]}", node=option)
            for index, choice in enumerate(option.choices or ()):
                if not type_matches(option.type, choice):
                    self.add(option.path + ("choices", index),
                             f"option '{name}': the choice {choice!r} is not "
                             f"{OPTION_TYPES[option.type]}", node=option)
            if option.choices is not None and option.default not in option.choices and \
                    type_matches(option.type, option.default):
                self.add(option.path + ("default",),
                         f"option '{name}': the default {option.default!r} is not one of "
                         f"its choices", node=option)
        for ref in self._option_refs():
            referred = self.post.options.get(ref.option)
            if referred is None:
                self.add(ref.path + ("option",), f"unknown option '{ref.option}'"
                         f"{hint(ref.option, self.post.options)}", node=ref)
                continue
            if ref.by_value is not None:
                self.check_by_value(ref, referred)
                continue
            wanted = _NUMBERING_TYPES.get(ref.path[-1]) if ref.path[:2] == \
                ("output", "block_numbers") else _MACHINE_TYPES.get(ref.path)
            if wanted is not None and referred.type not in (wanted, *_WIDER.get(wanted, ())):
                where = "/".join(str(p) for p in ref.path)
                self.add(ref.path + ("option",), f"{where} is {OPTION_TYPES[wanted]}, but "
                         f"option '{ref.option}' is {OPTION_TYPES[referred.type]}", node=ref)

    def check_by_value(self, ref: n.OptionRef, option: n.Option) -> None:
        """``{option: units, mm: 3, inch: 4}``: a string option with choices, each given a
        value (the value's own type is checked where the setting is used)."""
        where = "/".join(str(p) for p in ref.path)
        if option.type != "string" or option.choices is None:
            self.add(ref.path + ("option",), f"{where} gives a value for each value of option "
                     f"'{ref.option}', which must then be text with choices", node=ref)
            return
        given = [key for key, _ in ref.by_value or ()]
        missing = [str(c) for c in option.choices if str(c) not in given]
        extra = [key for key in given if key not in map(str, option.choices)]
        if missing or extra:
            self.add(ref.path + ("option",), f"{where} must give a value for each choice of "
                     f"option '{ref.option}' ({', '.join(map(str, option.choices))})"
                     + (f": {', '.join(missing)} missing" if missing else "")
                     + (f": {', '.join(extra)} is not a choice" if extra else ""), node=ref)
        if ref.path == ("machine", "units"):
            for key, value in ref.by_value or ():
                if value not in ("mm", "inch"):
                    self.add(ref.path + (key,), f"machine/units is mm or inch, not {value!r}",
                             node=ref)

    def _option_refs(self) -> list[n.OptionRef]:
        refs = [v for spec in self.post.formats.values() for v in spec.values.values()
                if isinstance(v, n.OptionRef)]
        numbers = self.post.block_numbers
        refs += [getattr(numbers, k) for k in numbers.given
                 if isinstance(getattr(numbers, k), n.OptionRef)]
        machine = self.post.machine
        if machine is not None:
            refs += [value for value in (machine.rapid_rate, machine.resolution, machine.units,
                                         machine.cutter_compensation)
                     if isinstance(value, n.OptionRef)]
        return refs

    def _usable(self, name: str) -> bool:
        option = self.post.options.get(name)
        return option is not None and type_matches(option.type, option.default)

    def _defaults(self) -> dict[str, Any]:
        return {name: option.default for name, option in self.post.options.items()}

    # --- machine, formats, numbering ------------------------------------------------------

    def _machine(self) -> None:
        """Ranges the machine checks every posted value against must be ranges."""
        machine = self.post.machine
        if machine is None:
            return
        ranges: list[tuple[PathKey, tuple[Any, Any]]] = [
            (("machine", "travel", axis), r) for axis, r in machine.travel.items()]
        if machine.spindle is not None:
            ranges.append((("machine", "spindle"), machine.spindle))
        if (machine.control is not None) != (machine.resolution is not None):
            given, missing = ("control", "resolution") if machine.control is not None \
                else ("resolution", "control")
            self.add(("machine", given), f"machine/{given} needs "
                     f"machine/{missing}: postdsl verify replays the "
                     f"program with the control model at that resolution", key=True,
                     node=machine)
        if machine.min_feed is not None and machine.max_feed is not None:
            ranges.append((("machine", "min_feed"), (machine.min_feed, machine.max_feed)))
        for path, (low, high) in ranges:
            if low > high:
                where = "/".join(str(p) for p in path)
                self.add(path, f"{where}: the minimum {low} is above the maximum {high}",
                         node=machine)

    def _formats(self) -> None:
        defaults = self._defaults()
        for name, spec in self.post.formats.items():
            if any(isinstance(v, n.OptionRef) and not self._usable(v.option)
                   for v in spec.values.values()):
                continue  # an unknown option, or a default of the wrong type: reported
            values = resolve_settings(spec.values, defaults)
            try:
                # every word of a post gets a width a control takes, unless it names one
                self.formats[name] = NumberFormat.from_mapping(
                    {"max_digits": DEFAULT_MAX_DIGITS, **values})
            except FormatSpecError as exc:
                path = spec.path + ((exc.key,) if exc.key and exc.key in values else ())
                self.add(path, f"format '{name}': {exc.message}", key=bool(exc.key), node=spec)

    def _block_numbers(self) -> None:
        output = self.post.output
        if output is not None and output.word_separator is not None:
            self._plain_text(output.path + ("word_separator",), output.word_separator,
                             "word separator", output)
        numbers = self.post.block_numbers
        given = numbers.given
        here = numbers.path
        for key in ("prefix", "suffix"):
            if key in given:
                self._plain_text(here + (key,), getattr(numbers, key), f"block number {key}")
        if numbers.format is not None:
            self._format_ref(here + ("format",), numbers.format)
        defaults = self._defaults()

        def setting(value: Any, default: int) -> Any:
            value = resolve(value, defaults)
            return default if value is None else value

        # an option's value is checked when the post is compiled with it; here its default
        start = setting(numbers.start, 10)
        maximum = setting(numbers.maximum, 99999)
        increment = setting(numbers.increment, 10)
        number_format = self.formats.get(str(numbers.format or ""))
        allowed = number_format.max_digits if number_format is not None else None
        if maximum < start:
            self.add(here + ("maximum",), f"maximum {maximum} is below start {start}")
        elif allowed is not None and len(str(maximum)) > allowed:
            self.add(here + ("maximum",),
                     f"maximum {maximum} has more digits than the "
                     f"{allowed} its format '{numbers.format}' writes (max_digits)")
        elif start + increment > maximum:
            # the second block would have no number: every program would stop (or wrap
            # onto the first number at once)
            key = "increment" if "increment" in given else "maximum"
            self.add(here + (key,),
                     f"increment {increment} leaves no second block number "
                     f"between start {start} and maximum {maximum}")

    def _format_ref(self, path: PathKey, name: str, node: Any = None) -> None:
        if name not in self.formats and name not in self.post.formats:
            self.add(path, f"unknown format '{name}'{hint(name, self.post.formats)}",
                     node=node)

    def _expr(self, expr: n.Expr) -> None:
        if expr.error is not None:
            self.add(expr.path, f"bad expression: {expr.error.message}",
                     offset=expr.error.column, node=expr)

    # --- tables ---------------------------------------------------------------------------

    def _command(self, path: PathKey, name: str, command: n.Table,
                 names: frozenset[str], custom: bool = False) -> None:
        if not custom and name not in COMMANDS and name not in EVENTS:
            self.add(path, f"unknown CL command '{name}'{hint(name, COMMANDS)}", key=True,
                     node=command)
            return
        if isinstance(command, n.Command):
            self._command_only(path, name, command, names)
        if name == "tool_change" and not custom:
            self._tool_change_forgets(path, command)
        for rule in command.reject or ():
            self._expr(rule.condition)
        for expr in (command.assume or {}).values():
            self._expr(expr)
        for flag, expr in (command.sets or {}).items():
            if flag not in self.flags:
                self.add(path + ("set", flag), f"'{flag}' is not a flag (declare it under "
                         f"flags: with its initial value){hint(flag, self.flags)}", key=True,
                         node=command)
            self._expr(expr)
        for pname in command.preview or {}:
            if pname not in names:
                self.add(path + ("preview", pname),
                         f"unknown parameter '{pname}'{hint(pname, names)}", key=True,
                         node=command)
        if command.blocks is not None:
            self._blocks(command.blocks, names, seen=())
            self._inlined(command, names)

    def _inlined(self, table: n.Table, names: frozenset[str]) -> None:
        """Check what ``use:`` makes of structures in this table, located at the ``use:``.

        A structure's block is checked where it is written with its parameters as names;
        here it is checked as the table runs it: under the ``use:``'s ``if:``, with each
        parameter replaced by its ``with:`` expression, in the table's names.  A parameter
        the ``use:`` gives no value is an unknown name here.  A mistake already reported
        where it is written is not reported again.
        """
        try:
            resolved = list(itertools.islice(inline(self.post, table.blocks),
                                             MAX_TABLE_BLOCKS + 1))
        except StructureLoop as loop:
            if len(set(loop.chain)) > 1:  # a structure using itself is reported where it is
                self.add(loop.path, str(loop), node=table)
            return
        if len(resolved) > MAX_TABLE_BLOCKS:
            return  # too big to run: _expansion() says so
        for block in resolved:
            if block.use_path is None or self._reported(block.use_path) or \
                    self._reported(block.block.path):
                continue
            sources: list[tuple[str, str]] = []
            own = block.block.condition
            if block.condition is not None and block.condition != (own.source if own else None):
                sources.append(("if", block.condition))
            for path, expr in item_exprs(block.block):
                text = block.text(expr)
                if text != expr.source:
                    where = "/".join(str(p) for p in path[len(block.block.path):])
                    sources.append((where, text))
            for where, source in sources:
                try:
                    compile_expr(source, names, self.formats)
                except ExprError as exc:
                    structure, index = block.block.path[1], block.block.path[2]
                    self.add(block.use_path, f"use: {structure}: block {index} {where} as "
                             f"this use: makes it: {exc.message}", node=table)

    def _reported(self, path: PathKey) -> bool:
        """A problem was found at ``path`` or inside it."""
        return any(problem.path[:len(path)] == path for problem in self.problems)

    def _command_only(self, path: PathKey, name: str, command: n.Command,
                      names: frozenset[str]) -> None:
        """What only a CL command's table has: redirect, expand, new_cycle_if."""
        commands = self.post.commands
        target = command.redirect
        if target is not None:
            seen = [name]
            while target is not None:
                if target not in COMMANDS:
                    self.add(path + ("redirect",),
                             f"unknown CL command '{target}'{hint(target, COMMANDS)}",
                             node=command)
                    break
                if target in seen:
                    self.add(path + ("redirect",),
                             "redirect loop: " + " -> ".join(seen + [target]), node=command)
                    break
                if target not in commands:
                    self.add(path + ("redirect",),
                             f"redirect to '{target}', which has no table", node=command)
                    break
                seen.append(target)
                target = commands[target].redirect
        if name == "arc_move":
            self._arc_chords(path, command)
        elif command.tolerance is not None:
            self.add(path + ("tolerance",), "tolerance applies to arc_move with expand: true "
                     "only", key=True, node=command)
        if command.expand and name != "arc_move":
            if name not in DRILL_SETUPS:
                self.add(path + ("expand",), "only drilling setups and arc_move can be "
                         "expanded into moves", node=command)
            elif name == "boring_spindle_stop":
                self.add(path + ("expand",), "boring_spindle_stop cannot be expanded into "
                         "moves (the spindle stops at the bottom); give it a table", node=command)
            elif name == "fine_boring":
                self.add(path + ("expand",), "fine_boring cannot be expanded into moves (the "
                         "spindle stops oriented at the bottom); give it a table", node=command)
            elif "tapping" in name:
                self.add(path + ("expand",),
                         "tapping cannot be expanded into moves (the spindle must reverse in "
                         "step with the feed); give it a table or redirect it", node=command)
        if command.expand_if is not None:
            self._expand_if(path, name, command)
        if command.new_cycle_if is not None:
            if name != "cycle_hole":
                self.add(path + ("new_cycle_if",), "new_cycle_if applies to cycle_hole only",
                         node=command)
            self._expr(command.new_cycle_if)

    def _expand_if(self, path: PathKey, name: str, command: n.Command) -> None:
        """``expand_if:``: a drilling setup whose cycle is written unless the condition holds.

        The cycle's table must exist to be written the rest of the time, so neither
        ``expand: true`` (always moves) nor ``redirect:`` (another table decides) goes
        with it; tapping cannot be written as moves at all.
        """
        if name not in DRILL_SETUPS:
            self.add(path + ("expand_if",), "expand_if applies to drilling setups only "
                     "(single_peck, deep_drill, break_chip)", node=command)
        elif "tapping" in name:
            self.add(path + ("expand_if",), "tapping cannot be expanded into moves (the "
                     "spindle must reverse in step with the feed)", node=command)
        if command.expand:
            self.add(path + ("expand_if",), "expand_if with expand: true: the holes are "
                     "always expanded, so the condition is never read", node=command)
        if command.redirect is not None:
            self.add(path + ("expand_if",), "expand_if with redirect: the redirected "
                     "table decides (give expand_if there)", node=command)
        if not command.blocks:
            self.add(path + ("expand_if",), "expand_if needs the table's blocks: they "
                     "write the cycle whenever the condition is false", node=command)
        self._expr(command.expand_if)  # type: ignore[arg-type]  # the caller checked not None

    def _arc_chords(self, path: PathKey, command: n.Command) -> None:
        """``arc_move: {expand: true, tolerance: t}``: arcs as chords through linear_move."""
        if not command.expand:
            if command.tolerance is not None:
                self.add(path + ("tolerance",), "tolerance applies to arc_move with expand: "
                         "true only", key=True, node=command)
            return
        if command.tolerance is None:
            self.add(path + ("expand",), "an expanded arc_move needs a tolerance: how far "
                     "(mm) a chord may stray from the arc, e.g. tolerance: 0.01", node=command)
        if "linear_move" not in self.post.commands:
            self.add(path + ("expand",), "an expanded arc_move is written as chords through "
                     "linear_move, and the post has no table for linear_move", node=command)

    def _tool_change_forgets(self, path: PathKey, command: n.Table) -> None:
        """After a tool change the control's axes and feed are unknown: the post must say so.

        A tool change moves the spindle to the changer (G30/G28, a macro behind M6), so
        the axis positions and the feed the registers remember are no longer what the
        control holds; the next move must write its Z and F again, as the real
        programs do after every M6.  The table states it with ``reset:`` (or ``assume:``
        where the post knows what the control holds): every register an item writing
        x, y, z or the feed uses.
        """
        if isinstance(command, n.Command) and command.redirect is not None:
            return
        stated = set(command.reset or ()) | set(command.assume or {})
        missing = sorted(motion_registers(self.post) - stated)
        if missing:
            self.add(path, "tool_change: after a tool change the control's axes and feed are "
                     f"unknown; add reset: [{', '.join(missing)}] (the registers of the X, Y, "
                     "Z and feed words), or assume: what the control holds", key=True,
                     node=command)

    def _blocks(self, blocks: tuple[n.BlockEntry, ...], names: frozenset[str],
                seen: tuple[str, ...]) -> None:
        for block in blocks:
            if isinstance(block, n.Use):
                target = block.use
                if target not in self.structures:
                    self.add(block.path + ("use",), f"unknown structure '{target}'"
                             f"{hint(target, self.structures)}", node=block)
                elif target in seen:
                    self.add(block.path + ("use",),
                             "structure uses itself: " + " -> ".join(seen + (target,)),
                             node=block)
                if block.condition is not None:
                    self._expr(block.condition)
                self._with(block, names)
                continue
            if block.condition is not None:
                self._expr(block.condition)
            for item in block.items:
                if isinstance(item, n.PlainText):
                    self._plain_text(item.path, item.text, "fixed text", item)
                    continue
                self._item(item, names)

    def _with(self, use: n.Use, names: frozenset[str]) -> None:
        """A ``use:``'s ``with:``: parameters the structure reads, each a valid expression."""
        read = reads(self.post, use.use)
        for key, expr in (use.bindings or {}).items():
            if key in self.known_names:
                self.add(expr.path, f"structure parameter '{key}' hides the parameter of "
                         f"that name", key=True, node=use)
            elif use.use in self.structures and key not in read:
                self.add(expr.path, f"structure '{use.use}' does not read '{key}'"
                         f"{hint(key, read - self.known_names)}", key=True, node=use)
            self._expr(expr)

    def _all_cycle_params(self) -> frozenset[str]:
        params: set[str] = set()
        for cycle in self.post.custom_cycles.values():
            params |= set(cycle.parameters or {})
        return frozenset(params)

    def _plain_text(self, path: PathKey, text: Any, what: str, node: Any = None) -> None:
        """Text the post writes into blocks must not break them.

        A carriage return, line feed or other control character in a post's own text
        passes every other check and ends the block where it stands: the rest becomes a
        block of its own, one the control executes but nobody sees in the table.
        """
        if not isinstance(text, str) or text.isprintable():
            return
        bad = next(c for c in text if not c.isprintable())
        self.add(path, f"control character {bad!r} (U+{ord(bad):04X}) in "
                 f"the {what}: it would break the NC block", node=node)

    def _item(self, item: n.Item, names: frozenset[str]) -> None:
        path = item.path
        if isinstance(item, n.TextItem):
            self._plain_text(path + ("text",), item.text, "fixed text", item)
        for key in ("prefix", "suffix"):
            value = getattr(item, key)
            if value is not None:
                self._plain_text(path + (key,), value, key, item)
        for old, new in item.replace or ():
            self._plain_text(path + ("replace", old), old, "replace table", item)
            self._plain_text(path + ("replace", old), new, "replace table", item)
        mode = item.output_mode
        if isinstance(item, n.ParamItem):
            pname = item.param
            if pname not in names:
                self.add(path + ("param",), f"unknown parameter '{pname}'{hint(pname, names)}",
                         node=item)
            elif kind(pname, self.post) == "list":
                self.add(path + ("param",), f"parameter '{pname}' is a list of values, which "
                         f"a block cannot write (test it in a condition, e.g. 'z' in given)",
                         node=item)
            elif item.format is not None and kind(pname, self.post) == "text":
                self.add(path + ("format",), f"'{pname}' is text: a number format does not "
                         f"apply to it (leave the format out)", node=item)
            elif item.format is None and is_number(pname, self.post) and \
                    "default" not in self.formats:
                self.add(path + ("param",), f"number parameter '{pname}' needs a format (or "
                         f"define a format named 'default')", node=item)
        if isinstance(item, n.ExprItem) and item.expr is not None:
            self._expr(item.expr)
            compiled = item.expr.compiled
            if item.format is None and "default" not in self.formats and \
                    compiled is not None and may_be_number(compiled.tree, self.post):
                # str() would write Python's repr: (Q-3.3333333333333335), Q85.71428571428571
                self.add(path + ("expr",), f"the computed item '{item.expr.source}' may write "
                         f"a number, and it has no format: every number goes through a "
                         f"format (give it format: NAME, or define a format named "
                         f"'default')", node=item)
        for expr in (item.condition, item.force_if):
            if expr is not None:
                self._expr(expr)
        if item.format is not None:
            self._format_ref(path + ("format",), item.format, item)
        if mode != "always" and isinstance(item, n.TextItem) and item.modal is None:
            self.add(path + ("mode",),
                     f"a text item in mode '{mode}' needs 'modal: <register>' naming what it "
                     f"compares with (e.g. modal: motion for G0/G1)", node=item)
        if mode != "always" and isinstance(item, n.ExprItem) and item.modal is None:
            self.add(path + ("mode",),
                     f"a computed item in mode '{mode}' needs 'modal: <register>'", node=item)
        if item.replace is not None and isinstance(item, n.TextItem):
            self.add(path + ("replace",), "replace applies to parameter and computed values; "
                     "write fixed text as it should appear", node=item)
        if item.force_if is not None and mode not in ("changed", "changed_value"):
            self.add(path + ("force_if",), "force_if only applies to items in mode 'changed' "
                     "or 'changed_value'",
                     node=item)

    def _expansion(self) -> None:
        """Refuse a table whose ``use:`` blocks expand beyond :data:`MAX_TABLE_BLOCKS`.

        Structures that each use the previous one a few times multiply: seven levels of
        seven make 823,543 blocks from a few lines, which the compiler would inline for
        minutes.  Each structure's size is counted once, so this costs what the text does.
        """
        sizes: dict[str, int] = {}

        def size(name: str) -> int:
            known = sizes.get(name)
            if known is not None:
                return known
            sizes[name] = 0  # a loop: reported by the compiler, counted as nothing here
            structure = self.structures.get(name)
            total = table(structure.blocks if structure is not None else ())
            sizes[name] = total
            return total

        def table(blocks: tuple[n.BlockEntry, ...]) -> int:
            total = 0
            for block in blocks:
                total += size(block.use) if isinstance(block, n.Use) else 1
                if total > MAX_TABLE_BLOCKS:
                    return MAX_TABLE_BLOCKS + 1
            return total

        tables: list[n.Table] = [*self.post.commands.values(),
                                 *self.post.custom_cycles.values()]
        for command in tables:
            blocks = command.blocks or ()
            if table(blocks) <= MAX_TABLE_BLOCKS:
                continue
            biggest = max(blocks, key=lambda b: size(b.use) if isinstance(b, n.Use) else 1)
            self.add(biggest.path + ("use",),
                     f"'use: {getattr(biggest, 'use', None)}' makes table '{command.name}' "
                     f"expand to more than {MAX_TABLE_BLOCKS:,} blocks (structures using "
                     f"structures multiply)", node=biggest)


#: values a coordinate format is tried on: does it write each with a decimal point?
_POINT_SAMPLES = (10.0, -2.0, 0.0, 125.0)


def decimal_point_problems(post: n.Post, formats: Mapping[str, NumberFormat]) -> list[Problem]:
    """Coordinates the control would read in its least input increment: a word at one of
    the control's point letters (``postdsl.lang.control_syntax.NUMBERS``) whose format can
    write a number without a decimal point, on a machine not set to calculator input.

    On such a control (in its default setting, the table says which) ``Z-10`` is
    0.010 mm.  One problem per format, at the format, naming the letters it writes.  A
    format with an implied point at the least increment (``point: never`` with as many
    decimals) is right and passes.  Lines a post declares the control model does not
    read (``verify: {motion: none|unknown}``: a macro call, whose arguments the macro
    reads) are left out: what the macro makes of them is its own; fixed text is not
    read here either (``postdsl verify`` reads both as the control does).
    """
    machine = post.machine
    if machine is None or machine.calculator_input:
        return []
    syntax = number_syntax(machine.control)
    if syntax is None:
        return []
    letters: dict[str, list[str]] = {}  # format -> the letters it writes, in order
    seen: set[PathKey] = set()
    tables: list[n.Table] = [*post.commands.values(), *post.custom_cycles.values()]
    for table in tables:
        if table.verify is not None and table.verify.motion in ("none", "unknown"):
            continue
        for resolved in post.resolved(table.blocks):
            for item in resolved.block.items:
                if item.path in seen or not isinstance(item, (n.ParamItem, n.ExprItem)):
                    continue
                seen.add(item.path)
                prefix = (item.prefix or "").rstrip().upper()
                letter = prefix[-1:]
                if letter not in syntax.letters or (len(prefix) > 1 and prefix[-2].isalpha()):
                    continue
                name = item.format or "default"
                if name in formats and letter not in letters.setdefault(name, []):
                    letters[name].append(letter)
    found: list[Problem] = []
    for name, written in letters.items():
        sample = _pointless(formats[name], syntax)
        spec = post.formats.get(name)
        if sample is None or not written or spec is None:
            continue
        word = f"{written[0]}{sample}"
        found.append(Problem(
            spec.path, f"format '{name}' writes {' '.join(written)} words without a decimal "
            f"point ({word}): {syntax.what}, so {word} is "
            f"{float(sample) * syntax.increment:g} mm; give it 'point: always', or declare "
            f"machine/calculator_input: true if the control is set to calculator input",
            key=True, file=getattr(spec, "file", None)))
    return found


def _pointless(number_format: NumberFormat, syntax: NumberSyntax) -> str | None:
    """A number the format writes without a point (that the control would scale), or None."""
    if number_format.point == "never":
        implied = 10.0 ** -number_format.decimals
        if number_format.multiplier == 1 and math.isclose(implied, syntax.increment):
            return None  # an implied point at the least increment: X10000 is 10 mm
    for value in _POINT_SAMPLES:
        try:
            text = number_format.render(value)
        except (DigitsError, ValueError, OverflowError):  # too narrow for it: proves nothing
            continue
        if syntax.pointless(text):
            return text
    return None


def _parameters(post: n.Post) -> dict[str, frozenset[str]]:
    """Each structure's parameters: the names its ``use:`` sites give with ``with:``."""
    found: dict[str, set[str]] = {}
    for _, table in post.tables():
        for entry in table.blocks or ():
            if isinstance(entry, n.Use):
                found.setdefault(entry.use, set()).update(entry.bindings or {})
    return {name: frozenset(names) for name, names in found.items()}


#: CL fields of free text (no choices): whatever the CAM system or its user typed
CL_TEXT = frozenset(("program_name", "project", "author", "operation", "tool_type",
                     "tool_name", "comment", "cl_file"))


def motion_registers(post: n.Post) -> set[str]:
    """The registers of every item that writes X, Y, Z or the feed (directly or computed)."""
    registers: set[str] = set()
    for _, table in post.tables():
        for block in table.blocks or ():
            if isinstance(block, n.Use):
                continue
            for item in block.items:
                if isinstance(item, n.ParamItem) and item.param in ("x", "y", "z", "feed"):
                    registers.add(str(item.modal if item.modal is not None else item.param))
                elif isinstance(item, n.ExprItem) and item.modal is not None and \
                        item.expr is not None and re.search(r"\bfeed\b", item.expr.source):
                    registers.add(str(item.modal))
    return registers


def is_number(name: str, post: n.Post) -> bool:
    info = PARAMETERS.get(name)
    if info is not None:
        return info.kind == "number"
    if name in post.variables:
        value = post.variables[name].value
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    option = post.options.get(name)
    return option is not None and option.type in ("int", "number")


#: what a tilted-plane block must state: the plane's origin and its three angles
PLANE_WRITES = ("origin_x", "origin_y", "origin_z", "plane_angle_1", "plane_angle_2",
                "plane_angle_3")
_PLANE_ANGLES = frozenset(PLANE_WRITES[3:])


def tilted_plane_problems(post: n.Post) -> list[Problem]:
    """A tilting machine's post must write the plane; a three-axis post must not pretend to.

    With ``machine.tilted_plane`` the engine derives plane_angle_1-3 in the control's
    convention, and the control needs the origin and all three angles to set the plane
    up: a ``work_plane`` table that leaves one out would cut every later move in a
    plane the control does not have (a dropped angle reads as 0).  Without it the
    angles are in no convention at all (the engine refuses the record), so a table
    writing them would be a 3+2 post missing its machine declaration.
    """
    machine = post.machine
    convention = machine.tilted_plane if machine is not None else None
    table = post.commands.get("work_plane")
    if convention is None:
        if table is None:
            return []
        return [Problem(path, f"the work_plane table writes {name}, but the machine "
                              f"declares no tilted_plane (the convention of the control's "
                              f"plane angles): add machine.tilted_plane, or leave the angles "
                              f"out (a three-axis post refuses work_plane)",
                        file=getattr(table, "file", None))
                for path, name in _written(post, table) if name in _PLANE_ANGLES][:1]
    if table is None:
        assert machine is not None  # a convention is declared in it
        return [Problem(machine.path + ("tilted_plane",),
                        f"the machine tilts the working plane ({convention}) but the post "
                        f"has no work_plane table: add commands/work_plane writing the "
                        f"control's tilted-plane block from {', '.join(PLANE_WRITES)}",
                        file=machine.file)]
    written = {name for _, name in _written(post, table)}
    missing = [name for name in PLANE_WRITES if name not in written]
    if not missing:
        return []
    return [Problem(table.path, f"the work_plane table does not write {', '.join(missing)}: "
                                f"the control sets its tilted plane up from the origin and "
                                f"all three angles ({convention}), and a value left out is "
                                f"a plane the CL does not have", key=True,
                    file=getattr(table, "file", None))]


def _written(post: n.Post, table: n.Table) -> Iterator[tuple[PathKey, str]]:
    """(item path, name) for every CL name a table's items write, structures inlined and
    their parameters replaced by what the ``use:`` binds them to; conditions write nothing."""
    try:
        blocks = list(itertools.islice(inline(post, table.blocks), MAX_TABLE_BLOCKS))
    except StructureLoop:
        return  # reported where it is
    for inlined in blocks:
        for item in inlined.block.items:
            if isinstance(item, n.ParamItem):
                text = inlined.bindings.get(item.param)
                if text is None:
                    yield item.path, item.param
                    continue
            elif isinstance(item, n.ExprItem) and item.expr is not None:
                text = inlined.text(item.expr)
            else:
                continue
            try:
                names = compile_expr(text).names
            except ExprError:
                continue  # reported where it is written
            for name in sorted(names):
                yield item.path, name
