"""What the editor shows, computed from the post document alone (no Textual here).

Tables, items and their compact cell text, the names a table reads (for the
sample-value table) and which compiled blocks a YAML block became (to
highlight the program lines a block wrote).  Kept free of widgets so it can be
tested and reused by other screens.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from postdsl import api
from postdsl.api import (
    Block,
    Command,
    Expr,
    ExprItem,
    Item,
    ParamItem,
    PlainText,
    Post,
    Structure,
    Table,
    TextItem,
    Use,
    resolve_option,
)

#: keys of an item mapping, in the order posts write them
ITEM_KEYS = ("text", "param", "expr", "prefix", "suffix", "format", "mode", "modal", "if",
             "force_if")
#: keys of a block mapping, in the order posts write them
BLOCK_KEYS = ("use", "if", "number", "renumber", "for_each", "only_with_values", "items")
MODES = ("always", "changed", "changed_value", "forced")
#: top-level keys of a post, in the order posts write them
TOP_KEYS = ("postdsl", "extends", "machine", "output", "formats", "variables", "options",
            "flags", "structures", "commands", "custom_cycles", "override")
MACHINE_KEYS = ("name", "controller", "control", "resolution", "calculator_input", "units",
                "travel", "spindle",
                "min_feed", "max_feed", "rapid_rate", "tool_changer", "tools")
OUTPUT_KEYS = ("extension", "line_ending", "final_newline", "word_separator", "motion_register",
               "block_numbers")
NUMBER_KEYS = ("prefix", "suffix", "start", "increment", "maximum", "format", "default")
#: keys of a command's or custom cycle's table, in the order posts write them
TABLE_KEYS = ("doc", "redirect", "parameters", "preview", "set", "assume", "reset", "reject",
              "verify", "new_cycle_if", "expand", "expand_if", "tolerance", "blocks")
FORMAT_KEYS = ("decimals", "trailing_zeros", "min_decimals", "point", "leading_zeros", "width",
               "sign", "multiplier", "integer", "rounding", "zero_sign")


def key_order(parent: tuple[Any, ...]) -> tuple[str, ...]:
    """The usual order of the keys of the mapping at ``parent`` (new keys go in place)."""
    if parent[:1] == ("formats",) and len(parent) == 2:
        return FORMAT_KEYS
    if parent[:1] in (("commands",), ("custom_cycles",)) and len(parent) == 2:
        return TABLE_KEYS
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
    def of(cls, node: Item | Any) -> ItemSpec:
        """The spec of a model item (a raw YAML item, e.g. from the clipboard, is read
        into the model first)."""
        if not isinstance(node, Item):
            node = api.item_model(node)
        if isinstance(node, PlainText):
            return cls("text", node.text)
        if isinstance(node, TextItem):
            kind, value = "text", node.text
        elif isinstance(node, ParamItem):
            kind, value = "param", node.param
        else:
            kind = "expr"
            value = node.expr.source if isinstance(node, ExprItem) and node.expr else ""
        extra = {"replace": dict(node.replace)} if node.replace is not None else {}
        return cls(kind=kind, value=value, prefix=node.prefix or "", suffix=node.suffix or "",
                   format=node.format or "", mode=node.mode or "always",
                   modal=node.modal or "", condition=_source(node.condition),
                   force_if=_source(node.force_if), extra=extra)

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


def _source(expr: Expr | None) -> str:
    return expr.source if expr is not None else ""


def item_cell(node: Item) -> str:
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
    marks = ("?" if spec.condition else "") + \
        {"changed": "~", "changed_value": "~", "forced": "!"}.get(spec.mode, "")
    return body + marks


def item_summary(node: Item) -> str:
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
    items: list[Item] = field(default_factory=list)
    use: str | None = None
    condition: str = ""
    numbered: bool = True
    explicit_number: bool = False
    renumber: bool = False
    for_each: str = ""
    only_with_values: bool = False
    #: written in the post this one extends: an edit writes an override of it
    inherited: bool = False


def numbered_by_default(post: Post) -> bool:
    """Whether blocks are numbered unless they say (an option's default when it is one)."""
    default = resolve_option(post.block_numbers.default, option_defaults(post))
    return bool(default) if default is not None else True


def blocks_of(post: Post, ref: TableRef) -> list[BlockView]:
    """The rows of a table, read from the post's model."""
    table = table_node(post, ref)
    if table is None:
        return []
    default = numbered_by_default(post)
    views = []
    for index, block in enumerate(table.blocks or ()):
        inherited = post.inherited(block.path)
        if isinstance(block, Use):
            views.append(BlockView(index, use=block.use, inherited=inherited))
            continue
        views.append(BlockView(
            index, list(block.items), condition=_source(block.condition),
            numbered=bool(block.number if block.number is not None else default),
            explicit_number=block.number is not None, renumber=bool(block.renumber),
            for_each=block.for_each or "", only_with_values=bool(block.only_with_values),
            inherited=inherited))
    return views


def table_node(post: Post, ref: TableRef) -> Table | Structure | None:
    """The table (a command's, a custom cycle's or a structure), None when absent."""
    return post.table_at(ref.path)


def redirect_of(post: Post, ref: TableRef) -> str | None:
    """The command whose table a redirected command uses, else None."""
    table = table_node(post, ref)
    return table.redirect if isinstance(table, Command) else None


def resolved_table(post: Post, name: str) -> str:
    """The command whose table ``name`` is written with (following redirects)."""
    seen = {name}
    while (command := post.commands.get(name)) is not None and command.redirect is not None:
        name = command.redirect
        if name in seen:
            break
        seen.add(name)
    return name


def compiled_blocks(post: Post, ref: TableRef) -> list[range]:
    """For each YAML block, the indices of the compiled blocks it became (``use:`` inlines)."""
    table = table_node(post, ref)
    ranges, position = [], 0
    for block in (table.blocks or ()) if table is not None else ():
        size = len(post.resolved((block,)))
        ranges.append(range(position, position + size))
        position += size
    return ranges


def names_read(post: Post, ref: TableRef) -> list[str]:
    """Parameters a table prints or tests, preview samples first (the sample-value rows)."""
    table = table_node(post, ref)
    names: list[str] = []
    if isinstance(table, Table):
        names += list(table.preview or {})
    blocks = table.blocks if table is not None else ()
    for resolved in post.resolved(blocks, (ref.name,) if ref.kind == "structure" else ()):
        block = resolved.block
        names += _names(block.condition)
        for item in block.items:
            if isinstance(item, ParamItem):
                names.append(item.param)
            for expr in (item.expr if isinstance(item, ExprItem) else None, item.condition,
                         item.force_if):
                names += _names(expr)
    return list(dict.fromkeys(names))


def _names(expr: Expr | None) -> list[str]:
    """The names an expression reads, sorted (none when it does not compile)."""
    if expr is None or expr.compiled is None:
        return []
    return sorted(expr.compiled.names)


def format_names(post: Post) -> list[str]:
    """Names of the post's formats, in file order."""
    return list(post.formats)


def option_defaults(post: Post) -> dict[str, Any]:
    return {name: option.default for name, option in post.options.items()}


def format_spec(post: Post, name: str) -> dict[str, Any] | None:
    """A format's keys as the editor renders examples with them (an option's value is
    its default), None when the post has no format of that name."""
    spec = post.formats.get(name)
    if spec is None:
        return None
    defaults = option_defaults(post)
    return {key: resolve_option(value, defaults) for key, value in spec.values.items()}


def setting_at(post: Post, path: tuple[Any, ...]) -> Any:
    """The value of a machine or output setting of the model by its YAML path
    (``("machine", "travel", "x", 0)``); None when the post leaves it out.  An option's
    value (``{option: NAME}``) is its default."""
    node: Any = post
    for part in path:
        if node is None:
            return None
        if isinstance(part, int):
            node = node[part] if isinstance(node, tuple) and part < len(node) else None
        elif isinstance(node, Mapping):
            node = node.get(part)
        else:
            node = getattr(node, str(part), None)
    return resolve_option(node, option_defaults(post))


def variable_names(post: Post) -> list[str]:
    """Names of the post's variables, in file order."""
    return list(post.variables)


def uses_of(post: Post, key: str, name: str) -> list[tuple[Any, ...]]:
    """Paths of every item whose ``key`` (``format``, ``param``) is ``name``."""
    found: list[tuple[Any, ...]] = []
    for _, table in post.tables():
        for block in table.blocks or ():
            for item in block.items if isinstance(block, Block) else ():
                value = item.format if key == "format" else \
                    item.param if key == "param" and isinstance(item, ParamItem) else None
                if value == name:
                    found.append(item.path)
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
        message: str = problem.message
        return message
    return f"{api.place_in_post(path)}: {problem.message}"
