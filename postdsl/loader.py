"""Load a machine post: YAML -> schema check -> semantic checks, every problem located.

The YAML is read with ruamel.yaml in round-trip mode and the resulting
document is kept as it is: the editor changes that same document and saves
it with comments and key order intact, and every message can point at
``file:line:column`` because ruamel records where each key and value stood.

Checks run in two layers, as a compiler would: the JSON Schema
(``schemas/post.schema.json``) for the shape, then the meaning — command,
parameter, format and structure names, expressions, redirects — which a
schema cannot express.  All problems of a file are collected, not just the
first, so ``postdsl check`` lists them in one go.
"""

from __future__ import annotations

import datetime
import difflib
import functools
import io
import json
import math
import re
import sys
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import jsonschema
from ruamel.yaml import YAML
from ruamel.yaml.comments import CommentedMap, CommentedSeq
from ruamel.yaml.error import MarkedYAMLError
from ruamel.yaml.reader import ReaderError

from postdsl.cl.model import COMMANDS, DRILL_SETUPS, PARAMETERS
from postdsl.errors import Location, PostError
from postdsl.expr import ExprError, compile_expr
from postdsl.formats import DEFAULT_MAX_DIGITS, FormatSpecError, NumberFormat
from postdsl.resources import schema_path
from postdsl.textfile import TextFileError, read_text

PathKey = tuple[Any, ...]


def make_yaml() -> YAML:
    """The one YAML configuration used to read and write posts (round-trip, quotes kept)."""
    yaml = YAML()
    yaml.preserve_quotes = True
    # keep ["; ", {param: x}] as written (ruamel would drop the braces on dump)
    yaml.brace_single_entry_mapping_in_flow_sequence = True
    yaml.width = 4096
    yaml.indent(mapping=2, sequence=4, offset=2)
    return yaml


@functools.lru_cache(maxsize=1)
def post_schema() -> dict[str, Any]:
    return json.loads(schema_path("post.schema.json").read_text(encoding="utf-8"))


@functools.lru_cache(maxsize=1)
def _validator() -> jsonschema.protocols.Validator:
    schema = post_schema()
    cls = jsonschema.validators.validator_for(schema)
    return cls(schema)


@dataclass
class PostSource:
    """A post as read from YAML: the round-trip document plus where it came from."""

    file: str
    data: CommentedMap
    text: str = ""
    path: Path | None = None

    def locate(self, path: PathKey, *, key: bool = False, offset: int = 0) -> Location:
        """The file position of the node at ``path`` (a key's own position when ``key``)."""
        return Location(self.file, *locate(self.data, path, key=key, offset=offset))


@dataclass
class Problem:
    path: PathKey
    message: str
    key: bool = False
    offset: int = 0


@dataclass
class CheckedPost:
    """A post that passed every check; what the compiler consumes."""

    source: PostSource
    known_names: frozenset[str]
    formats: dict[str, NumberFormat] = field(default_factory=dict)

    @property
    def data(self) -> CommentedMap:
        return self.source.data


def parse_yaml(text: str, file: str) -> CommentedMap:
    """YAML text -> round-trip document; syntax errors become located PostErrors."""
    try:
        data = make_yaml().load(io.StringIO(text))
    except MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark is not None else None
        column = mark.column + 1 if mark is not None else None
        problem = exc.problem or exc.context or "invalid YAML"
        if "'\\t'" in problem:
            problem += " (YAML indents with spaces, not tabs)"
        raise PostError(f"YAML error: {problem}", Location(file, line, column)) from None
    except RecursionError:
        raise PostError("YAML error: the document is nested too deeply",
                        Location(file, *_deepest(text))) from None
    except ReaderError as exc:  # a character YAML does not allow (NUL, other controls)
        position = exc.position if isinstance(exc.position, int) else 0
        line = text.count("\n", 0, position) + 1
        column = position - text.rfind("\n", 0, position)
        code = exc.character if isinstance(exc.character, int) else \
            ord(exc.character[:1] or "?") if isinstance(exc.character, str) else ord("?")
        raise PostError(f"YAML error: the character U+{code:04X} is not "
                        f"allowed in YAML ({exc.reason})", Location(file, line, column)) \
            from None
    except Exception as exc:  # ruamel raises a few unmarked errors (e.g. bad unicode)
        limit = sys.get_int_max_str_digits()
        long = re.search(rf"\d{{{limit + 1},}}", text) if isinstance(exc, ValueError) else None
        if long is not None:  # int() refuses it, with advice about Python, not about the post
            line = text.count("\n", 0, long.start()) + 1
            column = long.start() - text.rfind("\n", 0, long.start())
            raise PostError(f"YAML error: a number of more than {limit} digits",
                            Location(file, line, column)) from None
        raise PostError(f"YAML error: {exc}", Location(file)) from None
    if not isinstance(data, CommentedMap):
        raise PostError("a post must be a YAML mapping (machine:, commands: …)",
                        Location(file, 1, 1))
    _check_size(data, file, text)
    return data


def _deepest(text: str) -> tuple[int, int]:
    """Line and column where ``text`` first reaches its deepest nesting.

    The parser gives up on a document nested too deeply without saying where; this scan
    points at the place well enough for a person to find it: the first bracket of the
    deepest flow collection, or else the most indented line.  Quoted text and comments
    are skipped, so brackets in strings do not count.
    """
    depth = best = 0
    where = (1, 1)
    indent_best, indent_where = -1, (1, 1)
    quote = ""
    for number, line in enumerate(text.split("\n"), start=1):
        stripped = line.lstrip(" ")
        if stripped and not stripped.startswith("#") and len(line) - len(stripped) > \
                indent_best and not depth:
            indent_best, indent_where = len(line) - len(stripped), (number, len(line) -
                                                                   len(stripped) + 1)
        for column, char in enumerate(line, start=1):
            if quote:
                if char == quote:
                    quote = ""
            elif char in "'\"":
                quote = char
            elif char == "#" and (column == 1 or line[column - 2] in " \t"):
                break
            elif char in "[{":
                depth += 1
                if depth > best:
                    best, where = depth, (number, column)
            elif char in "]}":
                depth = max(0, depth - 1)
    return where if best > 1 else indent_where


#: most values a post may expand to through YAML aliases.  The bundled posts have under
#: 1,500; nine nested levels of ten aliases ("billion laughs") would be 10**9, which the
#: schema check would walk, and its messages print, for ever.
MAX_VALUES = 200_000


def _check_size(data: CommentedMap, file: str, text: str = "") -> None:
    """Refuse a document whose aliases expand it beyond :data:`MAX_VALUES` values.

    Aliases are shared objects, so each node's expanded size is computed once: the
    cost is that of the text, not of the expansion.
    """
    sizes: dict[int, int] = {}

    def size(node: Any) -> int:
        if isinstance(node, Mapping):
            children: Iterable[Any] = node.values()
        elif isinstance(node, list):
            children = node
        else:
            return 1
        known = sizes.get(id(node))
        if known is not None:
            return known
        sizes[id(node)] = MAX_VALUES + 1  # an alias of itself: refused too
        total = 1 + sum(size(child) for child in children)
        sizes[id(node)] = total
        return total

    try:
        parts = {key: size(value) for key, value in data.items()}
    except RecursionError:
        raise PostError("YAML error: the document is nested too deeply",
                        Location(file, *_deepest(text))) from None
    if sum(parts.values()) > MAX_VALUES:
        # name the deepest key whose value is too big: the alias bomb itself
        path: tuple[Any, ...] = ()
        node: Any = data
        while isinstance(node, Mapping) and node:
            key = max(node, key=lambda k: sizes.get(id(node[k]), 1))
            if sizes.get(id(node[key]), 1) <= MAX_VALUES:
                break
            path, node = path + (key,), node[key]
        where = "/".join(str(p) for p in path) or "the document"
        count = sizes.get(id(node), 1 + sum(parts.values()))
        raise PostError(f"YAML aliases expand '{where}' to {count:,} values (at "
                        f"most {MAX_VALUES:,} are allowed in a post)",
                        Location(file, *locate(data, path, key=True)))


#: most blocks one table may expand to through ``use:``; the bundled posts' largest has
#: under 20, and a control program's header or a probing cycle a few dozen
MAX_TABLE_BLOCKS = 10_000


def read_source(path: str | Path) -> PostSource:
    """Read a post file; unreadable files are PostErrors too."""
    path = Path(path)
    try:
        text = read_text(path)
    except OSError as exc:
        raise PostError(f"cannot read post: {exc.strerror or exc}", Location(str(path))) \
            from None
    except TextFileError as exc:
        raise PostError(exc.message, Location(str(path), exc.line, exc.column)) from None
    return PostSource(str(path), parse_yaml(text, str(path)), text, path)


def check(source: PostSource) -> CheckedPost:
    """Validate a post; raise one PostError listing every problem in file order."""
    problems = list(_schema_problems(source.data))
    formats: dict[str, NumberFormat] = {}
    known: frozenset[str] = frozenset()
    if not problems:
        checker = _Semantics(source.data)
        problems = checker.run()
        formats, known = checker.formats, checker.known_names
    if problems:
        errors = [
            PostError(p.message, source.locate(p.path, key=p.key, offset=p.offset))
            for p in problems
        ]
        errors.sort(key=lambda e: (e.location.line or 0, e.location.column or 0))
        first = errors[0]
        raise PostError(first.message, first.location, errors)
    return CheckedPost(source, known, formats)


def load(path: str | Path) -> CheckedPost:
    return check(read_source(path))


# --- positions ------------------------------------------------------------------------------


def locate(data: Any, path: PathKey, *, key: bool = False, offset: int = 0) -> tuple[int, int]:
    """1-based (line, column) of the node at ``path``, falling back to its nearest parent."""
    node = data
    line, column = 1, 1
    for index, part in enumerate(path):
        last = index == len(path) - 1
        if isinstance(node, CommentedMap) and part in node:
            try:
                where = node.lc.key(part) if (key and last) else node.lc.value(part)
            except (KeyError, TypeError):  # added in memory by an editor: no position yet
                break
            value = node[part]
            quoted = not (key and last) and type(value).__name__ in (
                "SingleQuotedScalarString", "DoubleQuotedScalarString")
            line, column = where[0] + 1, where[1] + 1 + (1 if quoted else 0)
            node = value
        elif isinstance(node, CommentedSeq) and isinstance(part, int) and part < len(node):
            try:
                where = node.lc.item(part)
            except (KeyError, TypeError):
                break
            line, column = where[0] + 1, where[1] + 1
            value = node[part]
            if type(value).__name__ in ("SingleQuotedScalarString", "DoubleQuotedScalarString"):
                column += 1
            node = value
        else:
            if isinstance(node, (CommentedMap, CommentedSeq)) and index == 0:
                line, column = node.lc.line + 1, node.lc.col + 1
            break
    return line, column + offset


# --- schema ---------------------------------------------------------------------------------


def _best_error(error: jsonschema.ValidationError) -> jsonschema.ValidationError:
    """Within oneOf/anyOf, the sub-error that explains most (deepest path)."""
    if error.context:
        return _best_error(max(error.context, key=lambda e: (len(e.absolute_path),
                                                               -len(e.message))))
    return error


def _schema_problems(data: CommentedMap) -> Iterator[Problem]:
    for error in _validator().iter_errors(data):
        best = _best_error(error) if error.validator in ("oneOf", "anyOf") else error
        path = tuple(best.absolute_path)
        message = best.message
        if best.validator == "additionalProperties" and isinstance(best.instance, Mapping):
            allowed = list(best.schema.get("properties", {}))
            extras = [k for k in best.instance if k not in allowed]
            for extra in extras:
                hint = _hint(str(extra), allowed)
                yield Problem(path + (extra,), f"unknown key '{extra}'{hint}", key=True)
            continue
        where = "/".join(str(p) for p in path) or "top level"
        if best.validator == "type":
            # jsonschema's message is the value's repr: a whole list, or "TaggedScalar(…)"
            wanted = best.validator_value
            names = [_TYPE_NAMES.get(t, t) for t in
                     (wanted if isinstance(wanted, list) else [wanted])]
            message = f"expected {' or '.join(names)}, not {_describe(best.instance)}"
        elif len(message) > 200:
            message = message[:199] + "…"
        yield Problem(path, f"{where}: {message}")


_TYPE_NAMES = {"string": "text", "number": "a number", "integer": "a whole number",
               "boolean": "true or false", "object": "a mapping", "array": "a list",
               "null": "nothing"}


def _describe(value: Any) -> str:
    """A value as a message names it: its kind, and a short text for a scalar."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return f"the number {value}"
    if isinstance(value, str):
        shown = value if len(value) <= 40 else value[:39] + "…"
        return f"the text {shown!r}"
    if isinstance(value, Mapping):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    if value is None:
        return "nothing (null)"
    if isinstance(value, (datetime.date, datetime.datetime)):
        return f"the date {value}"  # YAML reads 2001-12-14 as a date: quote it for text
    tag = getattr(value, "tag", None)
    if tag is not None:
        return f"a value tagged '{getattr(tag, 'value', tag)}'"
    return f"a {type(value).__name__} value"


def _hint(name: str, candidates: Iterable[str]) -> str:
    close = difflib.get_close_matches(name, list(candidates), n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


# --- meaning --------------------------------------------------------------------------------


class _Semantics:
    """Checks a schema-valid post document for meaning; collects problems."""

    def __init__(self, data: CommentedMap) -> None:
        self.data = data
        self.problems: list[Problem] = []
        self.formats: dict[str, NumberFormat] = {}
        variables = data.get("variables") or {}
        self.variables = set(variables)
        self.known_names = frozenset(PARAMETERS) | frozenset(self.variables)
        self.structures = data.get("structures") or {}

    def run(self) -> list[Problem]:
        for name in self.variables & set(PARAMETERS):
            self.problems.append(Problem(("variables", name),
                                         f"variable '{name}' hides the parameter of that name",
                                         key=True))
        self._finite(self.data, ())
        self._machine()
        self._formats()
        self._block_numbers()
        commands = self.data.get("commands") or {}
        for name, command in commands.items():
            self._command(("commands", name), name, command, self.known_names, commands)
        for name, cycle in (self.data.get("custom_cycles") or {}).items():
            params = set(cycle.get("parameters") or {})
            for pname in params & set(PARAMETERS):
                self.problems.append(Problem(
                    ("custom_cycles", name, "parameters", pname),
                    f"cycle parameter '{pname}' hides the CL parameter of that name", key=True))
            self._command(("custom_cycles", name), name, cycle,
                          self.known_names | params, commands, custom=True)
        for name, blocks in self.structures.items():
            # a structure may serve custom cycles too, so their parameters are known in it
            self._blocks(("structures", name), blocks,
                         self.known_names | self._all_cycle_params(), seen=(name,))
        self._expansion()
        return self.problems

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
            blocks = self.structures.get(name)
            total = table(blocks if isinstance(blocks, list) else [])
            sizes[name] = total
            return total

        def table(blocks: list[Any]) -> int:
            total = 0
            for block in blocks:
                target = block.get("use") if isinstance(block, Mapping) else None
                total += size(target) if isinstance(target, str) else 1
                if total > MAX_TABLE_BLOCKS:
                    return MAX_TABLE_BLOCKS + 1
            return total

        for section in ("commands", "custom_cycles"):
            for name, command in (self.data.get(section) or {}).items():
                blocks = command.get("blocks") or []
                if table(blocks) <= MAX_TABLE_BLOCKS:
                    continue
                index = max(range(len(blocks)), key=lambda i: size(blocks[i]["use"]) if
                            "use" in blocks[i] else 1)
                self.problems.append(Problem(
                    (section, name, "blocks", index, "use"),
                    f"'use: {blocks[index].get('use')}' makes table '{name}' expand to more "
                    f"than {MAX_TABLE_BLOCKS:,} blocks (structures using structures multiply)"))

    def _finite(self, node: Any, path: PathKey) -> None:
        """.nan and .inf are YAML numbers the schema lets through; no post means them."""
        if isinstance(node, float) and not math.isfinite(node):
            text = ".nan" if node != node else (".inf" if node > 0 else "-.inf")
            where = "/".join(str(p) for p in path)
            self.problems.append(Problem(path, f"{where}: {text} is not a finite number"))
        elif isinstance(node, Mapping):
            for key, value in node.items():
                self._finite(value, path + (key,))
        elif isinstance(node, list):
            for index, value in enumerate(node):
                self._finite(value, path + (index,))

    def _machine(self) -> None:
        """Ranges the machine checks every posted value against must be ranges."""
        machine = self.data.get("machine") or {}
        ranges = [(("machine", "travel", axis), r)
                  for axis, r in (machine.get("travel") or {}).items()]
        if machine.get("spindle") is not None:
            ranges.append((("machine", "spindle"), machine["spindle"]))
        if ("control" in machine) != ("resolution" in machine):
            given, missing = ("control", "resolution") if "control" in machine \
                else ("resolution", "control")
            self.problems.append(Problem(("machine", given), f"machine/{given} needs "
                                         f"machine/{missing}: postdsl verify replays the "
                                         f"program with the control model at that resolution",
                                         key=True))
        if machine.get("min_feed") is not None and machine.get("max_feed") is not None:
            ranges.append((("machine", "min_feed"), (machine["min_feed"], machine["max_feed"])))
        for path, (low, high) in ranges:
            if low > high:
                where = "/".join(str(p) for p in path)
                self.problems.append(Problem(path, f"{where}: the minimum {low} is above the "
                                                   f"maximum {high}"))

    def _formats(self) -> None:
        for name, spec in (self.data.get("formats") or {}).items():
            try:
                # every word of a post gets a width a control takes, unless it names one
                self.formats[name] = NumberFormat.from_mapping(
                    {"max_digits": DEFAULT_MAX_DIGITS, **spec})
            except FormatSpecError as exc:
                path = ("formats", name) + ((exc.key,) if exc.key and exc.key in spec else ())
                self.problems.append(Problem(path, f"format '{name}': {exc.message}",
                                             key=bool(exc.key)))

    def _block_numbers(self) -> None:
        numbers = (self.data.get("output") or {}).get("block_numbers") or {}
        for key in ("prefix", "suffix"):
            if key in numbers:
                self._plain_text(("output", "block_numbers", key), numbers[key],
                                 f"block number {key}")
        if "format" in numbers:
            self._format_ref(("output", "block_numbers", "format"), numbers["format"])
        start, maximum = numbers.get("start", 10), numbers.get("maximum", 99999)
        increment = numbers.get("increment", 10)
        number_format = self.formats.get(str(numbers.get("format", "")))
        allowed = number_format.max_digits if number_format is not None else None
        if maximum < start:
            self.problems.append(Problem(("output", "block_numbers", "maximum"),
                                         f"maximum {maximum} is below start {start}"))
        elif allowed is not None and len(str(maximum)) > allowed:
            self.problems.append(Problem(("output", "block_numbers", "maximum"),
                                         f"maximum {maximum} has more digits than the "
                                         f"{allowed} its format '{numbers['format']}' writes "
                                         f"(max_digits)"))
        elif start + increment > maximum:
            # the second block would have no number: every program would stop (or wrap
            # onto the first number at once)
            key = "increment" if "increment" in numbers else "maximum"
            self.problems.append(Problem(("output", "block_numbers", key),
                                         f"increment {increment} leaves no second block number "
                                         f"between start {start} and maximum {maximum}"))

    def _format_ref(self, path: PathKey, name: str) -> None:
        if name not in self.formats and name not in (self.data.get("formats") or {}):
            self.problems.append(Problem(
                path, f"unknown format '{name}'{_hint(name, self.data.get('formats') or {})}"))

    def _expr(self, path: PathKey, source: str, names: frozenset[str]) -> None:
        try:
            compile_expr(source, names, self.formats)
        except ExprError as exc:
            self.problems.append(Problem(path, f"bad expression: {exc.message}",
                                         offset=exc.column))

    def _command(self, path: PathKey, name: str, command: Mapping[str, Any],
                 names: frozenset[str], commands: Mapping[str, Any], custom: bool = False) -> None:
        if not custom and name not in COMMANDS:
            self.problems.append(Problem(path, f"unknown CL command '{name}'"
                                         f"{_hint(name, COMMANDS)}", key=True))
            return
        target = command.get("redirect")
        if target is not None:
            seen = [name]
            while target is not None:
                if target not in COMMANDS:
                    self.problems.append(Problem(path + ("redirect",),
                                                 f"unknown CL command '{target}'"
                                                 f"{_hint(target, COMMANDS)}"))
                    break
                if target in seen:
                    self.problems.append(Problem(path + ("redirect",),
                                                 "redirect loop: " + " -> ".join(seen + [target])))
                    break
                if target not in commands:
                    self.problems.append(Problem(path + ("redirect",),
                                                 f"redirect to '{target}', which has no table"))
                    break
                seen.append(target)
                target = commands[target].get("redirect")
        if name == "arc_move" and not custom:
            self._arc_chords(path, command, commands)
        elif "tolerance" in command:
            self.problems.append(Problem(path + ("tolerance",),
                                         "tolerance applies to arc_move with expand: true only",
                                         key=True))
        if command.get("expand") and not (name == "arc_move" and not custom):
            if name not in DRILL_SETUPS:
                self.problems.append(Problem(path + ("expand",),
                                             "only drilling setups and arc_move can be "
                                             "expanded into moves"))
            elif "tapping" in name:
                self.problems.append(Problem(
                    path + ("expand",),
                    "tapping cannot be expanded into moves (the spindle must reverse in "
                    "step with the feed); give it a table or redirect it"))
        if "new_cycle_if" in command:
            if name != "cycle_hole":
                self.problems.append(Problem(path + ("new_cycle_if",),
                                             "new_cycle_if applies to cycle_hole only"))
            self._expr(path + ("new_cycle_if",), command["new_cycle_if"], names)
        if name == "tool_change" and not custom:
            self._tool_change_forgets(path, command)
        for index, rule in enumerate(command.get("reject") or []):
            self._expr(path + ("reject", index, "if"), rule["if"], names)
        for key, source in (command.get("assume") or {}).items():
            self._expr(path + ("assume", key), source, names)
        for pname in (command.get("preview") or {}):
            if pname not in names:
                self.problems.append(Problem(path + ("preview", pname),
                                             f"unknown parameter '{pname}'{_hint(pname, names)}",
                                             key=True))
        if "blocks" in command:
            self._blocks(path + ("blocks",), command["blocks"], names, seen=())

    def _arc_chords(self, path: PathKey, command: Mapping[str, Any],
                    commands: Mapping[str, Any]) -> None:
        """``arc_move: {expand: true, tolerance: t}``: arcs as chords through linear_move."""
        if not command.get("expand"):
            if "tolerance" in command:
                self.problems.append(Problem(path + ("tolerance",), "tolerance applies to "
                                             "arc_move with expand: true only", key=True))
            return
        if "tolerance" not in command:
            self.problems.append(Problem(path + ("expand",), "an expanded arc_move needs a "
                                         "tolerance: how far (mm) a chord may stray from the "
                                         "arc, e.g. tolerance: 0.01"))
        if "linear_move" not in commands:
            self.problems.append(Problem(path + ("expand",), "an expanded arc_move is written "
                                         "as chords through linear_move, and the post has no "
                                         "table for linear_move"))

    def _tool_change_forgets(self, path: PathKey, command: Mapping[str, Any]) -> None:
        """After a tool change the control's axes and feed are unknown: the post must say so.

        A tool change moves the spindle to the changer (G30/G28, a macro behind M6), so
        the axis positions and the feed the registers remember are no longer what the
        control holds; the next move must write its Z and F again, as the real
        programs do after every M6.  The table states it with ``reset:`` (or ``assume:``
        where the post knows what the control holds): every register an item writing
        x, y, z or the feed uses.
        """
        if "redirect" in command:
            return
        stated = set(command.get("reset") or ()) | set(command.get("assume") or {})
        missing = sorted(_motion_registers(self.data) - stated)
        if missing:
            self.problems.append(Problem(
                path, "tool_change: after a tool change the control's axes and feed are "
                f"unknown; add reset: [{', '.join(missing)}] (the registers of the X, Y, Z "
                "and feed words), or assume: what the control holds", key=True))

    def _blocks(self, path: PathKey, blocks: list[Any], names: frozenset[str],
                seen: tuple[str, ...]) -> None:
        for index, block in enumerate(blocks):
            here = path + (index,)
            if "use" in block:
                target = block["use"]
                if target not in self.structures:
                    self.problems.append(Problem(here + ("use",),
                                                 f"unknown structure '{target}'"
                                                 f"{_hint(target, self.structures)}"))
                elif target in seen:
                    self.problems.append(Problem(here + ("use",),
                                                 "structure uses itself: "
                                                 + " -> ".join(seen + (target,))))
                continue
            if "if" in block:
                self._expr(here + ("if",), block["if"], names)
            for position, item in enumerate(block["items"]):
                if isinstance(item, str):
                    self._plain_text(here + ("items", position), item, "fixed text")
                    continue
                self._item(here + ("items", position), item, names)

    def _all_cycle_params(self) -> frozenset[str]:
        params: set[str] = set()
        for cycle in (self.data.get("custom_cycles") or {}).values():
            params |= set(cycle.get("parameters") or {})
        return frozenset(params)

    def _plain_text(self, path: PathKey, text: Any, what: str) -> None:
        """Text the post writes into blocks must not break them.

        A carriage return, line feed or other control character in a post's own text
        passes every other check and ends the block where it stands: the rest becomes a
        block of its own, one the control executes but nobody sees in the table.
        """
        if not isinstance(text, str) or text.isprintable():
            return
        bad = next(c for c in text if not c.isprintable())
        self.problems.append(Problem(path, f"control character {bad!r} (U+{ord(bad):04X}) in "
                                           f"the {what}: it would break the NC block"))

    def _item(self, path: PathKey, item: Mapping[str, Any], names: frozenset[str]) -> None:
        for key in ("text", "prefix", "suffix"):
            if key in item:
                self._plain_text(path + (key,), item[key], key if key != "text" else
                                 "fixed text")
        for old, new in (item.get("replace") or {}).items():
            self._plain_text(path + ("replace", old), old, "replace table")
            self._plain_text(path + ("replace", old), new, "replace table")
        mode = item.get("mode", "always")
        if "param" in item:
            pname = item["param"]
            if pname not in names:
                self.problems.append(Problem(path + ("param",), f"unknown parameter '{pname}'"
                                             f"{_hint(pname, names)}"))
            elif _kind(pname, self.data, names) == "list":
                self.problems.append(Problem(
                    path + ("param",), f"parameter '{pname}' is a list of values, which a block "
                    f"cannot write (test it in a condition, e.g. 'z' in given)"))
            elif "format" in item and _kind(pname, self.data, names) == "text":
                self.problems.append(Problem(
                    path + ("format",), f"'{pname}' is text: a number format does not apply to "
                    f"it (leave the format out)"))
            elif "format" not in item and _is_number(pname, self.data) and \
                    "default" not in self.formats:
                self.problems.append(Problem(
                    path + ("param",),
                    f"number parameter '{pname}' needs a format (or define a format "
                    f"named 'default')"))
        if "expr" in item:
            self._expr(path + ("expr",), item["expr"], names)
        for key in ("if", "force_if"):
            if key in item:
                self._expr(path + (key,), item[key], names)
        if "format" in item:
            self._format_ref(path + ("format",), item["format"])
        if mode != "always" and "text" in item and "modal" not in item:
            self.problems.append(Problem(
                path + ("mode",),
                f"a text item in mode '{mode}' needs 'modal: <register>' naming what it "
                f"compares with (e.g. modal: motion for G0/G1)"))
        if mode != "always" and "expr" in item and "modal" not in item:
            self.problems.append(Problem(
                path + ("mode",), f"a computed item in mode '{mode}' needs 'modal: <register>'"))
        if "replace" in item and "text" in item:
            self.problems.append(Problem(path + ("replace",),
                                         "replace applies to parameter and computed values; "
                                         "write fixed text as it should appear"))
        if "force_if" in item and mode != "changed":
            self.problems.append(Problem(path + ("force_if",),
                                         "force_if only applies to items in mode 'changed'"))


def _motion_registers(data: Mapping[str, Any]) -> set[str]:
    """The registers of every item that writes X, Y, Z or the feed (directly or computed)."""
    registers: set[str] = set()
    tables = [c.get("blocks") or [] for c in (data.get("commands") or {}).values()]
    tables += list((data.get("structures") or {}).values())
    tables += [c.get("blocks") or [] for c in (data.get("custom_cycles") or {}).values()]
    for blocks in tables:
        for block in blocks:
            for item in block.get("items") or ():
                if isinstance(item, str):
                    continue
                if "param" in item and item["param"] in ("x", "y", "z", "feed"):
                    registers.add(str(item.get("modal", item["param"])))
                elif "expr" in item and "modal" in item and \
                        re.search(r"\bfeed\b", str(item["expr"])):
                    registers.add(str(item["modal"]))
    return registers


def _kind(name: str, data: Mapping[str, Any], names: frozenset[str]) -> str:
    """"number", "text" or "list" for a parameter or variable; "" when only the CL can tell."""
    info = PARAMETERS.get(name)
    if info is not None:
        return info.kind
    variables = data.get("variables") or {}
    if name in variables:
        return "text" if isinstance(variables[name], str) else "number"
    return ""  # a custom cycle's parameter: the CL may give a number or text


def _is_number(name: str, data: Mapping[str, Any]) -> bool:
    info = PARAMETERS.get(name)
    if info is not None:
        return info.kind == "number"
    value = (data.get("variables") or {}).get(name)
    return isinstance(value, (int, float)) and not isinstance(value, bool)

