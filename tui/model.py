"""What the editor shows, computed from the post document alone (no Textual here).

Tables, items and their compact cell text, the names a table reads (for the
sample-value table) and which compiled blocks a YAML block became (to
highlight the program lines a block wrote).  Kept free of widgets so it can be
tested and reused by other screens.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

from postdsl import api

#: keys of an item mapping, in the order posts write them
ITEM_KEYS = ("text", "param", "expr", "prefix", "suffix", "format", "mode", "modal", "if",
             "force_if")
#: keys of a block mapping, in the order posts write them
BLOCK_KEYS = ("use", "if", "number", "renumber", "for_each", "only_with_values", "items")
MODES = ("always", "changed", "forced")
#: top-level keys of a post, in the order posts write them
TOP_KEYS = ("postdsl", "machine", "output", "formats", "variables", "flags", "structures",
            "commands", "custom_cycles")
MACHINE_KEYS = ("name", "controller", "control", "resolution", "units", "travel", "spindle",
                "min_feed", "max_feed", "rapid_rate", "tool_changer", "tools")
OUTPUT_KEYS = ("extension", "line_ending", "final_newline", "motion_register", "block_numbers")
NUMBER_KEYS = ("prefix", "suffix", "start", "increment", "maximum", "format", "default")
FORMAT_KEYS = ("decimals", "trailing_zeros", "min_decimals", "point", "leading_zeros", "width",
               "sign", "multiplier", "integer", "rounding", "zero_sign")


def key_order(parent: tuple[Any, ...]) -> tuple[str, ...]:
    """The usual order of the keys of the mapping at ``parent`` (new keys go in place)."""
    if parent[:1] == ("formats",) and len(parent) == 2:
        return FORMAT_KEYS
    return {(): TOP_KEYS, ("machine",): MACHINE_KEYS, ("machine", "travel"): ("x", "y", "z"),
            ("machine", "tools"): ("min_number", "max_number", "max_diameter"),
            ("output",): OUTPUT_KEYS,
            ("output", "block_numbers"): NUMBER_KEYS}.get(parent, ())
SPACE = "␣"


def title_of(name: str) -> str:
    """``break_chip`` -> ``Break Chip`` (PPU's command names)."""
    return " ".join(part.capitalize() for part in name.split("_"))


def visible(text: str) -> str:
    """Text with its spaces shown, so ``" X"`` and ``"X"`` look different in a cell."""
    return text.replace(" ", SPACE)


@dataclass(frozen=True)
class TableRef:
    """A table of blocks: a command's, a custom cycle's or a structure."""

    kind: str  # "command" | "cycle" | "structure"
    name: str

    @property
    def path(self) -> tuple[Any, ...]:
        return {"command": ("commands", self.name), "cycle": ("custom_cycles", self.name),
                "structure": ("structures", self.name)}[self.kind]

    @property
    def blocks_path(self) -> tuple[Any, ...]:
        return self.path if self.kind == "structure" else self.path + ("blocks",)

    @property
    def title(self) -> str:
        return title_of(self.name)

    @property
    def previewable(self) -> bool:
        return self.kind != "structure"


@dataclass
class ItemSpec:
    """An item's properties as the item editor edits them (a flat, typed view)."""

    kind: str = "text"  # "text" | "param" | "expr"
    value: str = ""
    prefix: str = ""
    suffix: str = ""
    format: str = ""
    mode: str = "always"
    modal: str = ""
    condition: str = ""
    force_if: str = ""
    #: keys this editor does not know (a newer post language): kept as they are
    extra: dict[str, Any] = field(default_factory=dict)

    @classmethod
    def of(cls, node: Any) -> ItemSpec:
        if isinstance(node, str):
            return cls("text", str(node))
        node = node if isinstance(node, Mapping) else {}
        kind = next((k for k in ("text", "param", "expr") if k in node), "text")
        return cls(kind=kind, value=str(node.get(kind, "")),
                   prefix=str(node.get("prefix", "")), suffix=str(node.get("suffix", "")),
                   format=str(node.get("format", "")), mode=str(node.get("mode", "always")),
                   modal=str(node.get("modal", "")), condition=str(node.get("if", "")),
                   force_if=str(node.get("force_if", "")),
                   extra={str(k): v for k, v in node.items() if k not in ITEM_KEYS})

    @property
    def plain(self) -> bool:
        """A fixed text with no other property: written as a bare YAML string."""
        return self.kind == "text" and self.as_mapping().keys() == {"text"}

    def as_mapping(self) -> dict[str, Any]:
        """The item's YAML keys in the usual order, leaving out defaults."""
        values = {self.kind: self.value, "prefix": self.prefix, "suffix": self.suffix,
                  "format": self.format, "mode": "" if self.mode == "always" else self.mode,
                  "modal": self.modal, "if": self.condition, "force_if": self.force_if}
        mapping = {k: values[k] for k in ITEM_KEYS
                   if k in values and (values[k] or k == self.kind)}
        return {**mapping, **self.extra}


def item_cell(node: Any) -> str:
    """An item as a compact cell: fixed text as it is, a parameter as ``␣X{x:coord}``.

    Markers: ``?`` a condition, ``~`` written only when changed, ``!`` forced.
    """
    spec = ItemSpec.of(node)
    if spec.kind == "text":
        body = visible(spec.prefix + spec.value + spec.suffix)
    else:
        inner = spec.value if spec.kind == "param" else "=" + spec.value
        if spec.format:
            inner += ":" + spec.format
        body = visible(spec.prefix) + "{" + inner + "}" + visible(spec.suffix)
    marks = ("?" if spec.condition else "") + {"changed": "~", "forced": "!"}.get(spec.mode, "")
    return body + marks


def item_summary(node: Any) -> str:
    """An item in words, for the line under the table (the cell may be cut short)."""
    spec = ItemSpec.of(node)
    what = {"text": f"text {spec.value!r}", "param": f"parameter {spec.value}",
            "expr": f"computed {spec.value}"}[spec.kind]
    parts = [what]
    if spec.prefix:
        parts.append(f"prefix {spec.prefix!r}")
    if spec.suffix:
        parts.append(f"suffix {spec.suffix!r}")
    if spec.format:
        parts.append(f"format {spec.format}")
    if spec.mode != "always":
        parts.append(f"mode {spec.mode}" + (f" ({spec.modal})" if spec.modal else ""))
    if spec.condition:
        parts.append(f"if {spec.condition}")
    return ", ".join(parts)


@dataclass
class BlockView:
    """One row of the command table."""

    index: int
    items: list[Any] = field(default_factory=list)
    use: str | None = None
    condition: str = ""
    numbered: bool = True
    explicit_number: bool = False
    renumber: bool = False
    for_each: str = ""
    only_with_values: bool = False


def blocks_of(data: Mapping[str, Any], ref: TableRef) -> list[BlockView]:
    """The rows of a table, read from the document."""
    node: Any = data
    for part in ref.blocks_path:
        node = node.get(part) if isinstance(node, Mapping) else None
        if node is None:
            return []
    default = bool(((data.get("output") or {}).get("block_numbers") or {}).get("default", True))
    views = []
    for index, block in enumerate(node if isinstance(node, list) else []):
        if not isinstance(block, Mapping):
            views.append(BlockView(index))
            continue
        if "use" in block:
            views.append(BlockView(index, use=str(block["use"])))
            continue
        items = block.get("items")
        views.append(BlockView(
            index, list(items) if isinstance(items, list) else [],
            condition=str(block.get("if", "")),
            numbered=bool(block.get("number", default)), explicit_number="number" in block,
            renumber=bool(block.get("renumber", False)), for_each=str(block.get("for_each", "")),
            only_with_values=bool(block.get("only_with_values", False))))
    return views


def table_node(data: Mapping[str, Any], ref: TableRef) -> Any:
    """The table's mapping (or a structure's block list), None when absent."""
    node: Any = data
    for part in ref.path:
        node = node.get(part) if isinstance(node, Mapping) else None
    return node


def redirect_of(data: Mapping[str, Any], ref: TableRef) -> str | None:
    """The command whose table a redirected command uses, else None."""
    node = table_node(data, ref)
    if ref.kind == "command" and isinstance(node, Mapping) and "redirect" in node:
        return str(node["redirect"])
    return None


def resolved_table(data: Mapping[str, Any], name: str) -> str:
    """The command whose table ``name`` is written with (following redirects)."""
    commands = data.get("commands") or {}
    seen = {name}
    while isinstance(commands.get(name), Mapping) and "redirect" in commands[name]:
        name = str(commands[name]["redirect"])
        if name in seen:
            break
        seen.add(name)
    return name


def compiled_blocks(data: Mapping[str, Any], ref: TableRef) -> list[range]:
    """For each YAML block, the indices of the compiled blocks it became (``use:`` inlines)."""
    structures = data.get("structures") or {}

    def count(blocks: Any, seen: tuple[str, ...]) -> int:
        total = 0
        for block in blocks if isinstance(blocks, list) else []:
            target = block.get("use") if isinstance(block, Mapping) else None
            if target is None:
                total += 1
            elif target in structures and target not in seen:
                total += count(structures[target], seen + (target,))
        return total

    ranges, position = [], 0
    for view in blocks_of(data, ref):
        size = 1 if view.use is None else count([{"use": view.use}], ())
        ranges.append(range(position, position + size))
        position += size
    return ranges


def _expressions(node: Mapping[str, Any], keys: tuple[str, ...]) -> Iterator[str]:
    for key in keys:
        if isinstance(node.get(key), str):
            yield node[key]


def names_read(data: Mapping[str, Any], ref: TableRef) -> list[str]:
    """Parameters a table prints or tests, preview samples first (the sample-value rows)."""
    names: list[str] = []
    extra: list[str] = []
    table = table_node(data, ref)
    if ref.kind == "cycle" and isinstance(table, Mapping):
        extra = list(table.get("parameters") or {})
    if isinstance(table, Mapping):
        names += [str(k) for k in (table.get("preview") or {})]
    structures = data.get("structures") or {}

    def walk(blocks: Any, seen: tuple[str, ...]) -> None:
        for block in blocks if isinstance(blocks, list) else []:
            if not isinstance(block, Mapping):
                continue
            if "use" in block:
                target = block["use"]
                if target in structures and target not in seen:
                    walk(structures[target], seen + (target,))
                continue
            for source in _expressions(block, ("if",)):
                names.extend(sorted(api.check_expression(source, data, extra).names))
            for item in block.get("items") or []:
                if not isinstance(item, Mapping):
                    continue
                if isinstance(item.get("param"), str):
                    names.append(item["param"])
                for source in _expressions(item, ("expr", "if", "force_if")):
                    names.extend(sorted(api.check_expression(source, data, extra).names))

    node: Any = data
    for part in ref.blocks_path:
        node = node.get(part) if isinstance(node, Mapping) else None
    walk(node, (ref.name,) if ref.kind == "structure" else ())
    return list(dict.fromkeys(names))


def format_names(data: Mapping[str, Any]) -> list[str]:
    """Names of the post's formats, in file order."""
    return [str(name) for name in (data.get("formats") or {})]


def variable_names(data: Mapping[str, Any]) -> list[str]:
    """Names of the post's variables, in file order."""
    return [str(name) for name in (data.get("variables") or {})]


def uses_of(data: Mapping[str, Any], key: str, name: str) -> list[tuple[Any, ...]]:
    """Paths of every item whose ``key`` (``format``, ``param``) is ``name``."""
    found: list[tuple[Any, ...]] = []

    def walk(node: Any, path: tuple[Any, ...]) -> None:
        if isinstance(node, Mapping):
            if node.get(key) == name and path[-2:-1] == ("items",):
                found.append(path)
            for k, v in node.items():
                walk(v, path + (k,))
        elif isinstance(node, list):
            for i, v in enumerate(node):
                walk(v, path + (i,))

    for section in ("commands", "custom_cycles", "structures"):
        walk(data.get(section) or {}, (section,))
    return found


def parse_value(text: str) -> Any:
    """A typed sample or variable value: numbers, true/false, none, else text."""
    stripped = text.strip()
    lowered = stripped.lower()
    if lowered in ("true", "false"):
        return lowered == "true"
    if lowered in ("none", "null", ""):
        return None
    for kind in (int, float):
        try:
            return kind(stripped)
        except ValueError:
            pass
    return text


def show_value(value: Any) -> str:
    """A value as a technologist types it (none, true/false, 0.5)."""
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (tuple, list)):  # given, tools: a list, as a post writes one
        return ", ".join(show_value(v) for v in value) if value else "(none)"
    return str(value)


def problem_text(problem: Any) -> str:
    """``deep_drill, block 2, item 3: message``: where in the post, in the editor's words.

    The line number of the YAML file is no help while editing: unsaved edits moved
    the lines, and the editor shows tables, not the file.
    """
    path = tuple(getattr(problem, "path", ()) or ())
    if not path:
        return problem.message
    return f"{api.place_in_post(path)}: {problem.message}"
