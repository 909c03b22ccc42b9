"""``extends:``: a post built on another, with overrides by command, block and item.

A machine family shares most of its post: the child names its base and states only
what differs.  Resolution, in the order a reader expects:

- everything of the base is inherited (its own base first, recursively);
- ``machine:`` and ``output:`` (and ``output.block_numbers``) merge key by key;
- a format, variable, option, structure, command or custom cycle the child names
  replaces the base's of that name as a whole;
- ``override:`` replaces single nodes, addressed by their path in the post:
  ``commands/NAME/blocks/N`` or ``structures/NAME/N`` for a block, followed by
  ``/items/N`` for an item, or ``/if`` (``/number``, ``/renumber``, ``/for_each``,
  ``/only_with_values``) for one property of the block (N from 0, as the editor's
  rows); ``formats/NAME/KEY`` for one key of a format (the base's other keys stay);
  ``commands/NAME/set`` (``assume``, ``reject``, ``new_cycle_if``, ``expand_if``) for
  a table's, whole or one entry at a time (``…/set/FLAG``, ``…/reject/N``).  So a
  child states exactly the field it changes, and keeps everything else the base gives.

The merged :class:`~nodes.Post` records in ``sources`` where each inherited or
overriding node is written, so every message points into the right file.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from postdsl.lang.post import nodes as n
from postdsl.lang.post.build import _Builder, known_names
from postdsl.lang.post.checks import Problem

PathKey = tuple[Any, ...]

#: the named sections of a post a child replaces entry by entry
SECTIONS = ("formats", "variables", "flags", "options", "structures", "commands",
            "custom_cycles")
#: most posts in one extends: chain (a chain this long is a mistake, not a family)
MAX_DEPTH = 16


class ExtendsError(Exception):
    """A base that cannot be found or read, or a loop; located at the ``extends:`` value."""

    def __init__(self, message: str, file: str) -> None:
        super().__init__(message)
        self.message = message
        #: the file whose ``extends:`` is at fault
        self.file = file


def extends_of(data: Mapping[str, Any]) -> str | None:
    """The ``extends:`` of a post document, when it has one."""
    value = data.get("extends") if isinstance(data, Mapping) else None
    return value if isinstance(value, str) else None


def base_file(name: str, child: Path | None, machines: Path) -> Path | None:
    """Where ``extends: name`` points: a path relative to the child's folder, an absolute
    path, or a bundled post's or base's name (``machines/NAME.yaml``,
    ``machines/bases/NAME.yaml``); None when nothing is there."""
    candidate = Path(name)
    if candidate.suffix in (".yaml", ".yml") or "/" in name or "\\" in name:
        if not candidate.is_absolute():
            candidate = (child.parent if child is not None else Path.cwd()) / candidate
        return candidate if candidate.is_file() else None
    for folder in (machines / "bases", machines):
        bundled = folder / f"{name}.yaml"
        if bundled.is_file():
            return bundled
    return None


def chain_of(child_path: Path | None, child_file: str, data: Mapping[str, Any],
             read: Callable[[Path], Any], machines: Path) -> list[Any]:
    """The sources of a post's bases, nearest first, each read with ``read``.

    Raises ExtendsError for a base that is not there and for a loop.
    """
    chain: list[Any] = []
    seen = [child_path.resolve() if child_path is not None else child_file]
    path, file = child_path, child_file
    while (name := extends_of(data)) is not None:
        found = base_file(name, path, machines)
        if found is None:
            raise ExtendsError(f"extends: no post '{name}' (a path relative to this file, "
                               f"an absolute path, or a bundled post's or base's name)", file)
        if found.resolve() in seen:
            names = [Path(str(s)).name for s in seen] + [found.name]
            raise ExtendsError("extends loop: " + " -> ".join(names), file)
        if len(seen) > MAX_DEPTH:
            raise ExtendsError(f"extends: more than {MAX_DEPTH} posts in one chain", file)
        seen.append(found.resolve())
        source = read(found)
        chain.append(source)
        path, file, data = found, str(found), source.data
    return chain


def overrides_of(data: Mapping[str, Any]) -> Mapping[str, Any]:
    """The ``override:`` mapping of a post document (empty when it has none)."""
    value = data.get("override") if isinstance(data, Mapping) else None
    return value if isinstance(value, Mapping) else {}


def chain_names(documents: list[Mapping[str, Any]]) -> frozenset[str]:
    """Every name an expression anywhere in the chain may read."""
    names: frozenset[str] = frozenset()
    for data in documents:
        names |= known_names(data)
    return names


def merge(base: n.Post, child: n.Post, overrides: Mapping[str, Any],
          builder: _Builder) -> tuple[n.Post, list[Problem]]:
    """``child`` on top of ``base``; ``overrides`` is the child's ``override:`` mapping.

    Nodes of ``base`` keep (or gain) their file in ``sources``; the problems are
    overrides that address no block or item of the merged post.
    """
    sources: dict[PathKey, tuple[str | None, PathKey]] = {}

    def inherit(path: PathKey) -> None:
        file, where = base.origin_of(path)
        sources[path] = (file if file is not None else base.file, where)
        for prefix, (file, where) in base.sources.items():
            if prefix[:len(path)] == path:  # an override of the base: in the base's file
                sources[prefix] = (file if file is not None else base.file, where)

    # Any: each section is a differently typed field of n.Post, passed by name
    sections: dict[str, Any] = {}
    for section in SECTIONS:
        merged = dict(getattr(base, section))
        for name in merged:
            inherit((section, name))
        for name, node in getattr(child, section).items():
            merged[name] = node
            for prefix in [p for p in sources if p[:2] == (section, name)]:
                del sources[prefix]
        sections[section] = merged
    machine = _merge_fields(base.machine, child.machine, ("machine",), inherit)
    output = _merge_fields(base.output, child.output, ("output",), inherit)
    if base.output is not None and child.output is not None:
        numbers = _merge_fields(base.output.block_numbers, child.output.block_numbers,
                                ("output", "block_numbers"), inherit)
        output = dataclasses.replace(output, block_numbers=numbers)
    post = n.Post(file=child.file, version=child.version, extends=child.extends,
                  machine=machine, output=output, sources=sources, **sections)
    return _apply_overrides(post, overrides, builder)


def _merge_fields(base: Any, child: Any, path: PathKey,
                  inherit: Callable[[PathKey], None]) -> Any:
    """A machine or output node: the child's keys over the base's."""
    if child is None:
        if base is not None:
            inherit(path)
        return base
    if base is None:
        return child
    given: dict[str, Any] = {}
    for spec in dataclasses.fields(child):
        if spec.name in ("path", "file", "block_numbers"):
            continue
        value = getattr(child, spec.name)
        if value is None or value == {}:
            value = getattr(base, spec.name)
            if value is not None and value != {}:
                inherit(path + (spec.name,))
        given[spec.name] = value
    return dataclasses.replace(child, **given)


def override_path(key: str) -> PathKey:
    """``commands/drill/blocks/2/items/0`` -> ``("commands", "drill", "blocks", 2, "items", 0)``."""
    return tuple(int(part) if part.isdigit() else part for part in key.split("/"))


#: the keys of a table ``override:`` may replace (``commands/NAME/KEY``), each with the
#: keys below it it may address one by one (``set/FLAG``, ``assume/REGISTER``, ``reject/N``)
TABLE_KEYS = ("set", "assume", "reject", "new_cycle_if", "expand_if")
#: the properties of a block ``override:`` may replace one by one (``…/blocks/N/number``)
BLOCK_FIELDS = ("if", "number", "renumber", "for_each", "only_with_values")


def override_kind(target: PathKey) -> str:
    """What an ``override:`` path addresses: ``format`` (one key of a format), ``table``
    (``set:``, ``assume:``, ``reject:`` or a condition of a table, or one entry of them),
    ``condition`` (one property of a block: ``if``, ``number``…), ``item`` or ``block``."""
    if target[:1] == ("formats",):
        return "format"
    if target[:1] in (("commands",), ("custom_cycles",)) and len(target) >= 3 \
            and target[2] in TABLE_KEYS:
        return "table"
    if target[-1:] and target[-1] in BLOCK_FIELDS:
        return "condition"
    return "item" if "items" in target else "block"


def _apply_overrides(post: n.Post, overrides: Mapping[str, Any],
                     builder: _Builder) -> tuple[n.Post, list[Problem]]:
    problems: list[Problem] = []
    sources = dict(post.sources)
    for key, value in overrides.items():
        target = override_path(str(key))
        where = ("override", key)
        kind = override_kind(target)
        if kind == "format":
            found = _override_format(post, target, value, builder)
            if isinstance(found, str):
                problems.append(Problem(where, f"override '{key}': {found}", key=True))
                continue
            post = found
        elif kind == "table":
            found = _override_table(post, target, value, builder)
            if isinstance(found, str):
                problems.append(Problem(where, f"override '{key}': {found}", key=True))
                continue
            post = found
        else:
            replaced = _override_block(post, target, kind, value, builder)
            if isinstance(replaced, str):
                problems.append(Problem(where, f"override '{key}': {replaced}", key=True))
                continue
            post = replaced
        for prefix in [p for p in sources if p[:len(target)] == target]:
            del sources[prefix]
        sources[target] = (None, where)
    return dataclasses.replace(post, sources=sources), problems


def _override_block(post: n.Post, target: PathKey, kind: str, value: Any,
                    builder: _Builder) -> n.Post | str:
    """A block, one of its items or its ``if:`` replaced; a message when there is none."""
    block_path = target[:target.index("items")] if kind == "item" else \
        target[:-1] if kind == "condition" else target
    table = post.table_at(target)
    block = post.block_at(block_path)
    if table is None:
        return f"the post has no {_kind(target)} '{target[1]}'"
    if block is None:
        return (f"{_kind(target)} '{target[1]}' has no block {block_path[-1] + 1} "
                f"(blocks count from 0 in the path)")
    names = builder.names | known_names({}) | frozenset(
        getattr(table, "parameters", None) or {})
    if kind == "item":
        if not isinstance(block, n.Block) or not 0 <= target[-1] < len(block.items):
            return f"block {block_path[-1] + 1} has no item {target[-1] + 1}"
        items = list(block.items)
        items[target[-1]] = builder.item(target, value, names)
        replacement: n.BlockEntry = dataclasses.replace(block, items=tuple(items))
    elif kind == "condition":
        field = str(target[-1])
        if field == "if":
            condition = builder.expr(target, value, names) if value is not None else None
            replacement = dataclasses.replace(block, condition=condition)
        elif not isinstance(block, n.Block):
            return f"block {block_path[-1] + 1} inserts a structure: it has no {field}"
        else:
            properties: dict[str, Any] = {field: value}  # one of BLOCK_FIELDS
            replacement = dataclasses.replace(block, **properties)
    else:
        replacement = builder.block(target, value, names)
    return _replace_block(post, block_path, replacement)


def _override_format(post: n.Post, target: PathKey, value: Any,
                     builder: _Builder) -> n.Post | str:
    """``formats/NAME/KEY``: one key of an inherited format (None removes it); the
    format's other keys stay the base's."""
    if len(target) != 3:
        return "a format is overridden key by key: formats/NAME/KEY"
    name, key = str(target[1]), str(target[2])
    spec = post.formats.get(name)
    if spec is None:
        return f"the post has no format '{name}'"
    values = dict(spec.values)
    if value is None:
        values.pop(key, None)
    else:
        values[key] = builder.setting(target, value)
    return dataclasses.replace(post, formats={**post.formats, name: dataclasses.replace(
        spec, values=values)})


def _override_table(post: n.Post, target: PathKey, value: Any,
                    builder: _Builder) -> n.Post | str:
    """``set:``, ``assume:``, ``reject:``, ``new_cycle_if`` or ``expand_if`` of an
    inherited table, whole (``commands/NAME/set``) or one entry (``…/set/FLAG``,
    ``…/reject/N``; N one past the last adds a rule).  None removes it."""
    table = post.table_at(target)
    if table is None:
        return f"the post has no {_kind(target)} '{target[1]}'"
    # override_kind sends only commands/ and custom_cycles/ here: never a structure
    assert isinstance(table, n.Table)
    names = builder.names | known_names({}) | frozenset(
        getattr(table, "parameters", None) or {})
    field, rest = str(target[2]), target[3:]
    if field in ("new_cycle_if", "expand_if"):
        if rest or not isinstance(table, n.Command):
            return f"{field} is a condition of a command, overridden whole"
        condition = builder.expr(target, value, names) if value is not None else None
        conditions: dict[str, Any] = {field: condition}  # new_cycle_if or expand_if
        return _replace_table(post, target, dataclasses.replace(table, **conditions))
    if field == "reject":
        rules = list(table.reject or ())
        if not rest:
            rules = list(builder.table_fields(target[:2], str(target[1]),
                                              {"reject": value or []}, names)["reject"])
        else:
            index = rest[0]
            if len(rest) != 1 or not isinstance(index, int) or not 0 <= index <= len(rules):
                return f"reject has no rule {rest[0]} (rules count from 0; one past the " \
                       f"last adds one)"
            if value is None:
                if index < len(rules):
                    del rules[index]
            else:
                rule = n.Reject(target, builder.expr(target + ("if",), value["if"], names),
                                str(value["message"]))
                if index == len(rules):
                    rules.append(rule)
                else:
                    rules[index] = rule
        return _replace_table(post, target, dataclasses.replace(
            table, reject=tuple(rules) if rules or table.reject is not None else None))
    attribute = "sets" if field == "set" else "assume"
    entries = dict(getattr(table, attribute) or {})
    if not rest:
        entries = {str(k): builder.expr(target + (k,), v, names)
                   for k, v in (value or {}).items()}
    elif len(rest) == 1:
        if value is None:
            entries.pop(str(rest[0]), None)
        else:
            entries[str(rest[0])] = builder.expr(target, value, names)
    else:
        return f"{field} is overridden whole or one entry at a time: {field}/NAME"
    changes: dict[str, Any] = {
        attribute: entries if entries or getattr(table, attribute) is not None else None}
    return _replace_table(post, target, dataclasses.replace(table, **changes))


def _replace_table(post: n.Post, path: PathKey, table: Any) -> n.Post:
    section, name = str(path[0]), path[1]
    changes: dict[str, Any] = {section: {**getattr(post, section), name: table}}
    return dataclasses.replace(post, **changes)


def _kind(path: PathKey) -> str:
    return {"commands": "command", "custom_cycles": "custom cycle",
            "structures": "structure"}[str(path[0])]


def _replace_block(post: n.Post, path: PathKey, block: n.BlockEntry) -> n.Post:
    section, name = str(path[0]), path[1]
    table = getattr(post, section)[name]
    index = path[-1]
    blocks = list(table.blocks or ())
    blocks[index] = block
    changes: dict[str, Any] = {
        section: {**getattr(post, section), name: dataclasses.replace(table, blocks=tuple(blocks))}}
    return dataclasses.replace(post, **changes)
