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

import dataclasses
import datetime
import functools
import io
import json
import re
import sys
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from postdsl.errors import Location, PostError
from postdsl.lang.formats import NumberFormat
from postdsl.lang.post import Post, build_post
from postdsl.resources import machines_dir, schema_path
from postdsl.textfile import TextFileError, read_text

if TYPE_CHECKING:
    import jsonschema
    from ruamel.yaml import YAML
    from ruamel.yaml.comments import CommentedMap

    from postdsl.lang.post.checks import Problem

PathKey = tuple[Any, ...]


def make_yaml() -> YAML:
    """The one YAML configuration used to read and write posts (round-trip, quotes kept)."""
    from ruamel.yaml import YAML  # a post from the cache is never parsed: ruamel loads late

    yaml = YAML()
    yaml.preserve_quotes = True
    # keep ["; ", {param: x}] as written (ruamel would drop the braces on dump)
    yaml.brace_single_entry_mapping_in_flow_sequence = True
    yaml.width = 4096
    yaml.indent(mapping=2, sequence=4, offset=2)
    return yaml


@functools.lru_cache(maxsize=1)
def post_schema() -> dict[str, Any]:
    schema: dict[str, Any] = json.loads(
        schema_path("post.schema.json").read_text(encoding="utf-8"))
    return schema


@functools.lru_cache(maxsize=1)
def _validator() -> jsonschema.protocols.Validator:
    import jsonschema  # only a post that is not in the cache is validated

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
        """The file position of the node at ``path`` (a key's own position when ``key``),
        with ``path`` itself: the position may fall back to a parent (a node edited in
        memory has none), the path stays the node's."""
        return Location(self.file, *locate(self.data, path, key=key, offset=offset),
                        path=tuple(path))


@dataclass
class CheckedPost:
    """A post that passed every check; what the compiler consumes."""

    source: PostSource
    known_names: frozenset[str]
    formats: dict[str, NumberFormat] = field(default_factory=dict)
    #: the typed model every reader of the post reads (never the document's keys)
    model: Post = field(default_factory=lambda: Post(""))
    #: the posts it extends, by file name (``model.origin_of`` names the file of a node)
    bases: dict[str, PostSource] = field(default_factory=dict)

    def locate(self, path: PathKey, *, key: bool = False, offset: int = 0) -> Location:
        """Where the node at ``path`` of the model is written: in the post or a base (the
        location's path is then the node's path in that base's document)."""
        file, where = self.model.origin_of(path)
        owner = self.bases.get(file, self.source) if file is not None else self.source
        return owner.locate(where, key=key, offset=offset)

    @property
    def data(self) -> CommentedMap:
        return self.source.data


def parse_yaml(text: str, file: str) -> CommentedMap:
    """YAML text -> round-trip document; syntax errors become located PostErrors."""
    # ruamel is imported here, not at the top: a post from the cache is never parsed
    from ruamel.yaml.comments import CommentedMap
    from ruamel.yaml.error import MarkedYAMLError
    from ruamel.yaml.reader import ReaderError

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
                        Location(file, 1, 1, path=()))
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
                        Location(file, *locate(data, path, key=True), path=path))


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
    """Validate a post (and the bases it extends); raise one PostError listing every
    problem, the post's own first, each file's in file order."""
    # the checks are imported here: a post from the cache (postdsl.compile.postcache) skips them
    from postdsl.lang.post.checks import Problem, Semantics, finite_problems
    from postdsl.lang.post.extends import ExtendsError, chain_of, extends_of

    sources = {source.file: source}
    found: list[tuple[PostSource, Problem]] = \
        [(source, p) for p in _schema_problems(source.data)]
    bases: list[PostSource] = []
    if not found and extends_of(source.data) is not None:
        try:
            bases = chain_of(source.path, source.file, source.data, read_source,
                             machines_dir())
        except ExtendsError as exc:
            owner = sources.get(exc.file) or read_source(exc.file)
            raise PostError(exc.message, owner.locate(("extends",))) from None
        for base in bases:
            sources[base.file] = base
            found += [(base, p) for p in _schema_problems(base.data, partial=True)]
    formats: dict[str, NumberFormat] = {}
    known: frozenset[str] = frozenset()
    model = Post(source.file)
    if not found:
        model, merge_problems = _model(source, bases)
        found += merge_problems
        for each in (source, *bases):
            found += [(each, p) for p in finite_problems(each.data)]
        if model.machine is None:
            found.append((source, Problem((), "the post has no machine: neither it nor the "
                                              "posts it extends declare machine: (name, …)")))
        if not found:
            checker = Semantics(model)
            for problem in checker.run():
                file, path = model.origin_of(problem.path)
                owner = sources.get(file, source) if file is not None else source
                found.append((owner, dataclasses.replace(problem, path=path)))
            formats, known = checker.formats, checker.known_names
    if found:
        errors = [PostError(p.message, owner.locate(p.path, key=p.key, offset=p.offset))
                  for owner, p in found]
        # every error here was made with owner.locate(): its location is not None
        errors.sort(key=lambda e: (e.location.file != source.file,  # type: ignore[union-attr]
                                   e.location.file,  # type: ignore[union-attr]  # (as above)
                                   e.location.line or 0,  # type: ignore[union-attr]  # (as above)
                                   e.location.column or 0))  # type: ignore[union-attr]  # (as above)
        first = errors[0]
        raise PostError(first.message, first.location, errors)
    return CheckedPost(source, known, formats, model,
                       {base.file: base for base in bases})


def _model(source: PostSource, bases: list[PostSource]) \
        -> tuple[Post, list[tuple[PostSource, Problem]]]:
    """The post's model with its bases merged under it (the farthest base first)."""
    from postdsl.lang.post.build import _Builder  # checking only, as in check()
    from postdsl.lang.post.extends import chain_names, merge, overrides_of

    if not bases:
        return build_post(source.data, source.file), []
    names = chain_names([source.data, *(base.data for base in bases)])
    problems: list[tuple[PostSource, Problem]] = []
    chain = [*reversed(bases), source]
    model = build_post(chain[0].data, chain[0].file, origin=chain[0].file, names=names)
    for each in chain[1:]:
        origin = None if each is source else each.file
        builder = _Builder(each.file, origin, names)
        # str(x, 'name') may name a format of any base: the merged post has them all
        builder.formats = {name: NumberFormat() for name in model.formats}
        child = builder.post(each.data)
        # a base in the middle keeps its file name: what the next post inherits from it
        model, merged = merge(model, child, overrides_of(each.data), builder)
        problems += [(each, p) for p in merged]
    return model, problems


def load(path: str | Path) -> CheckedPost:
    return check(read_source(path))


# --- positions ------------------------------------------------------------------------------


def locate(data: Any, path: PathKey, *, key: bool = False, offset: int = 0) -> tuple[int, int]:
    """1-based (line, column) of the node at ``path``, falling back to its nearest parent."""
    from ruamel.yaml.comments import CommentedMap, CommentedSeq  # positions: errors only

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
    """Within oneOf/anyOf, the sub-error that explains most (deepest path).

    A setting that may also be ``{option: NAME}`` fails both ways when it is wrong; the
    option form explains nothing about a plain value, so its error is left out then.
    """
    if error.context:
        context = [e for e in error.context if not (_is_option_ref(e.schema) and
                                                    not isinstance(e.instance, Mapping))]
        return _best_error(max(context or error.context,
                               key=lambda e: (len(e.absolute_path), -len(e.message))))
    return error


def _is_option_ref(schema: Any) -> bool:
    return isinstance(schema, Mapping) and schema.get("required") == ["option"]


def _schema_problems(data: CommentedMap, partial: bool = False) -> Iterator[Problem]:
    """The schema's complaints; a ``partial`` post (a base of another) may lack the
    top-level keys a post must have."""
    from postdsl.lang.post.checks import Problem, hint  # checking only, as in check()

    for error in _validator().iter_errors(data):
        best = _best_error(error) if error.validator in ("oneOf", "anyOf") else error
        path = tuple(best.absolute_path)
        if partial and best.validator == "required" and not path:
            continue
        message = best.message
        if best.validator == "additionalProperties" and isinstance(best.instance, Mapping):
            # the post schema's subschemas are objects, never the booleans the stubs allow
            allowed = list(best.schema.get("properties", {}))  # type: ignore[union-attr]
            extras = [k for k in best.instance if k not in allowed]
            for extra in extras:
                suggestion = hint(str(extra), allowed)
                yield Problem(path + (extra,), f"unknown key '{extra}'{suggestion}", key=True)
            continue
        where = "/".join(str(p) for p in path) or "top level"
        if best.validator == "type":
            # jsonschema's message is the value's repr: a whole list, or "TaggedScalar(…)"
            wanted: str | list[str] = best.validator_value  # type: ignore[assignment]  # a type's name(s)
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


