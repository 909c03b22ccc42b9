"""The typed model of a machine post: what a post file means, once it has been read.

A post's YAML document is read in one place, :mod:`postdsl.lang.post.build`, into these
frozen nodes; the semantic checks, the compiler, the editor's model, preview and review
read the nodes, never the document's keys.  So a key the language gains is added to the
schema, the builder and a node, and every reader sees it — or the type checker and the
schema test say where it is missing.

Every node carries ``path``, the YAML path of its value in the document (for
:meth:`postdsl.lang.loader.PostSource.locate` and for the editor, which writes changes
back by path), and ``file``: the file it was written in when that is another post's
(it came through ``extends:``), or ``None`` when it is the post's own.

An optional key the file leaves out is ``None`` in its node, so a check can still tell
"not given" from "given as the default"; the properties give the value that applies.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from postdsl.lang.expr import ExprError, Expression

PathKey = tuple[Any, ...]


@dataclass(frozen=True, slots=True)
class Expr:
    """An expression of the post language, compiled once when the model is built."""

    path: PathKey
    source: str
    #: the compiled expression, or None when ``error`` says why it is not one
    compiled: Expression | None
    error: ExprError | None = None
    file: str | None = None


@dataclass(frozen=True, slots=True)
class OptionRef:
    """A setting whose value is an option's: ``{option: precision}``, resolved at compile."""

    path: PathKey
    option: str
    file: str | None = None


@dataclass(frozen=True, slots=True)
class Option:
    """A value the user sets when posting (``--option NAME=VALUE``), read like a variable."""

    path: PathKey
    name: str
    type: str  # bool, int, number, string
    default: Any
    choices: tuple[Any, ...] | None = None
    description: str = ""
    file: str | None = None


@dataclass(frozen=True, slots=True)
class Variable:
    """A value the post names once and reads in expressions (``variables:``)."""

    path: PathKey
    name: str
    value: Any
    file: str | None = None


@dataclass(frozen=True, slots=True)
class Flag:
    """State the post keeps itself: a value at the start of the program, changed by a
    table's ``set:`` and read by name in every condition and expression."""

    path: PathKey
    name: str
    value: Any
    file: str | None = None


@dataclass(frozen=True, slots=True)
class FormatSpec:
    """A named number format as the file states it (``NumberFormat`` is what it means).

    ``values`` are the keys as written; a value may be an :class:`OptionRef`.
    """

    path: PathKey
    name: str
    values: Mapping[str, Any]
    file: str | None = None


@dataclass(frozen=True, slots=True)
class Tools:
    """The machine's tool limits, which the engine checks each tool change against."""

    path: PathKey
    min_number: int | None = None
    max_number: int | None = None
    max_diameter: float | None = None


@dataclass(frozen=True, slots=True)
class MachineSpec:
    """The ``machine:`` section as written; the compiler applies its defaults."""

    path: PathKey
    name: str
    controller: str | None = None
    control: str | None = None
    resolution: float | None = None
    #: the control reads a number without a decimal point in mm (calculator input)
    calculator_input: bool | None = None
    units: str | None = None
    #: axis -> (minimum, maximum), in file order
    travel: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    spindle: tuple[float, float] | None = None
    min_feed: float | None = None
    max_feed: float | None = None
    #: a number, or an :class:`OptionRef` (the speed is an option of the post)
    rapid_rate: float | OptionRef | None = None
    tool_changer: bool | None = None
    tools: Tools | None = None
    #: what a CL's cutter_compensation means: off, wear or control, or an
    #: :class:`OptionRef` (a post option overrides the machine's setting)
    cutter_compensation: str | OptionRef | None = None
    file: str | None = None
    #: the convention of the control's tilted-plane angles (postdsl.frames), None: 3-axis
    tilted_plane: str | None = None


@dataclass(frozen=True, slots=True)
class BlockNumbers:
    """``output.block_numbers``; ``default`` and the others may be an :class:`OptionRef`."""

    path: PathKey
    prefix: str | None = None
    suffix: str | None = None
    start: int | None = None
    increment: int | None = None
    maximum: int | None = None
    wrap: bool | None = None
    format: str | None = None
    default: bool | OptionRef | None = None

    @property
    def given(self) -> frozenset[str]:
        """The keys the file states."""
        return frozenset(name for name in _NUMBER_KEYS if getattr(self, name) is not None)


_NUMBER_KEYS = ("prefix", "suffix", "start", "increment", "maximum", "wrap", "format",
                "default")


@dataclass(frozen=True, slots=True)
class Output:
    """The ``output:`` section: how the program's text is laid out."""

    path: PathKey
    extension: str | None = None
    line_ending: str | None = None
    final_newline: bool | None = None
    motion_register: str | None = None
    block_numbers: BlockNumbers | None = None
    #: put between the written words of a block (None: nothing, the prefixes space them)
    word_separator: str | None = None
    #: trailing spaces removed from every written line (a base whose items end in a space
    #: extended for a control, or an emulation of a post, that strips them)
    trim_line_ends: bool | None = None


@dataclass(frozen=True, slots=True)
class Item:
    """One item of a block: the options every kind of item may have.

    The kind is the subclass: :class:`PlainText` (a bare string), :class:`TextItem`,
    :class:`ParamItem`, :class:`ExprItem`.
    """

    path: PathKey
    prefix: str | None = None
    suffix: str | None = None
    format: str | None = None
    mode: str | None = None
    modal: str | None = None
    condition: Expr | None = None  # if:
    force_if: Expr | None = None
    #: (old, new) pairs of ``replace:``, in order; None when not given
    replace: tuple[tuple[str, str], ...] | None = None
    file: str | None = None

    @property
    def output_mode(self) -> str:
        return self.mode or "always"


@dataclass(frozen=True, slots=True)
class PlainText(Item):
    """A bare string in a block's items: written as it is, with no other option."""

    text: str = ""


@dataclass(frozen=True, slots=True)
class TextItem(Item):
    """Fixed text with item options (prefix, condition, mode…)."""

    text: str = ""


@dataclass(frozen=True, slots=True)
class ParamItem(Item):
    """A CL parameter's value, formatted and written by its output mode."""

    param: str = ""


@dataclass(frozen=True, slots=True)
class ExprItem(Item):
    """A computed value: an expression's result, written like a parameter."""

    expr: Expr | None = None


@dataclass(frozen=True, slots=True)
class Block:
    """One NC block of a table: its items in order and when it is written."""

    path: PathKey
    items: tuple[Item, ...]
    condition: Expr | None = None  # if:
    number: bool | None = None
    renumber: bool | None = None
    for_each: str | None = None
    only_with_values: bool | None = None
    file: str | None = None


@dataclass(frozen=True, slots=True)
class Use:
    """``{use: structure}`` in a table: the structure's blocks stand in its place.

    ``condition`` (``if:``) applies to every block of the structure; ``bindings``
    (``with:``) give the structure's parameters, each an expression in the names of the
    block that uses it (see :mod:`postdsl.lang.post.structures`).
    """

    path: PathKey
    use: str
    file: str | None = None
    condition: Expr | None = None
    bindings: Mapping[str, Expr] | None = None


BlockEntry = Block | Use


@dataclass(frozen=True, slots=True)
class Reject:
    """CL values the machine must not be given: the run stops with the message."""

    path: PathKey
    condition: Expr
    message: str


@dataclass(frozen=True, slots=True)
class Verify:
    """What ``postdsl verify`` is told of a table: its motion word and the words it writes."""

    path: PathKey
    motion: str | None = None
    words: tuple[str, ...] | None = None


@dataclass(frozen=True, slots=True)
class CycleParameter:
    """A named parameter of a custom cycle, with its default and help text."""

    path: PathKey
    name: str
    default: Any = None
    doc: str | None = None


@dataclass(frozen=True, slots=True)
class Table:
    """A command's or a custom cycle's table: its blocks and what it tells the engine.

    ``blocks`` are the entries as written (``use:`` included); :meth:`Post.resolved`
    gives the blocks with every ``use:`` replaced by the structure's blocks.
    """

    path: PathKey
    name: str
    blocks: tuple[BlockEntry, ...] | None = None
    doc: str | None = None
    preview: Mapping[str, Any] | None = None
    #: register -> expression
    assume: Mapping[str, Expr] | None = None
    reset: tuple[str, ...] | None = None
    reject: tuple[Reject, ...] | None = None
    verify: Verify | None = None
    file: str | None = None
    #: ``set:``: flag -> its new value, given after the table's blocks, in order
    sets: Mapping[str, Expr] | None = None


@dataclass(frozen=True, slots=True)
class Command(Table):
    """A CL command's table, with what only commands have (redirect, expand…)."""

    redirect: str | None = None
    new_cycle_if: Expr | None = None
    expand: bool | None = None
    #: a drilling setup: when this holds for the setup's values, its holes are written as
    #: moves (as with ``expand: true``) instead of through the table -- the cycle cannot
    #: write what the CL asks (unequal pecks, a retract plane the control cannot reach)
    expand_if: Expr | None = None
    #: arc_move with ``expand``: the furthest (mm) a chord may stray from the arc
    tolerance: float | None = None


@dataclass(frozen=True, slots=True)
class CustomCycle(Table):
    """A custom cycle's table, with the parameters it takes."""

    parameters: Mapping[str, CycleParameter] | None = None


@dataclass(frozen=True, slots=True)
class Structure:
    """Blocks shared between tables, included with ``use:``."""

    path: PathKey
    name: str
    blocks: tuple[BlockEntry, ...]
    file: str | None = None


@dataclass(frozen=True, slots=True)
class ResolvedBlock:
    """A block of a table with ``use:`` resolved: the block, and the structure chain it
    came through (empty when the table states it itself)."""

    block: Block
    via: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class Post:
    """A whole post: the root of the model."""

    file: str
    version: int | None = None
    extends: str | None = None
    machine: MachineSpec | None = None
    output: Output | None = None
    formats: Mapping[str, FormatSpec] = field(default_factory=dict)
    variables: Mapping[str, Variable] = field(default_factory=dict)
    flags: Mapping[str, Flag] = field(default_factory=dict)
    options: Mapping[str, Option] = field(default_factory=dict)
    structures: Mapping[str, Structure] = field(default_factory=dict)
    commands: Mapping[str, Command] = field(default_factory=dict)
    custom_cycles: Mapping[str, CustomCycle] = field(default_factory=dict)
    path: PathKey = ()
    #: where nodes not written at their own path in this file come from: a path prefix
    #: -> (file, or None for this file; the YAML path there).  Inherited nodes (extends:)
    #: map to their base's file, ``override:`` entries to their own key.
    sources: Mapping[PathKey, tuple[str | None, PathKey]] = field(default_factory=dict)

    def origin_of(self, path: PathKey) -> tuple[str | None, PathKey]:
        """The file (None: the post's own) and YAML path where the node at ``path`` is
        written: what a message about it must point at."""
        for length in range(len(path), 0, -1):
            found = self.sources.get(path[:length])
            if found is not None:
                return found[0], found[1] + path[length:]
        return None, path

    def inherited(self, path: PathKey) -> bool:
        """Whether the node at ``path`` comes from a base post (``extends:``)."""
        return self.origin_of(path)[0] is not None

    @property
    def block_numbers(self) -> BlockNumbers:
        numbers = self.output.block_numbers if self.output is not None else None
        return numbers if numbers is not None else BlockNumbers(("output", "block_numbers"))

    @property
    def motion_register(self) -> str:
        """The register of the motion word, as the post names it (``motion`` by default)."""
        output = self.output
        return output.motion_register if output is not None and output.motion_register \
            else "motion"

    def tables(self) -> list[tuple[str, Table | Structure]]:
        """Every table with blocks, as (section, table): commands, cycles, structures."""
        found: list[tuple[str, Table | Structure]] = []
        found += [("commands", c) for c in self.commands.values()]
        found += [("custom_cycles", c) for c in self.custom_cycles.values()]
        found += [("structures", s) for s in self.structures.values()]
        return found

    def resolved(self, blocks: tuple[BlockEntry, ...] | None,
                 via: tuple[str, ...] = ()) -> list[ResolvedBlock]:
        """``blocks`` with every ``use:`` replaced by its structure's blocks, recursively.

        Unknown structures and loops are skipped here (the checks report them; the
        compiler refuses a loop with its location).
        """
        resolved: list[ResolvedBlock] = []
        for entry in blocks or ():
            if isinstance(entry, Use):
                target = self.structures.get(entry.use)
                if target is None or entry.use in via:
                    continue
                resolved += self.resolved(target.blocks, via + (entry.use,))
            else:
                resolved.append(ResolvedBlock(entry, via))
        return resolved

    # --- finding nodes by path -------------------------------------------------------------

    def table_at(self, path: PathKey) -> Table | Structure | None:
        """The command, custom cycle or structure a path points into, or None."""
        if len(path) < 2:
            return None
        section = {"commands": self.commands, "custom_cycles": self.custom_cycles,
                   "structures": self.structures}.get(str(path[0]))
        return section.get(path[1]) if section is not None else None  # type: ignore[return-value]  # the dict of the section path[0] names

    def block_at(self, path: PathKey) -> BlockEntry | None:
        """The block entry (a block or a ``use:``) a path points into, or None."""
        table = self.table_at(path)
        rest = path[2:] if path[:1] == ("structures",) else path[3:]
        if table is None or not rest or not isinstance(rest[0], int):
            return None
        blocks = table.blocks or ()
        return blocks[rest[0]] if 0 <= rest[0] < len(blocks) else None

    def item_at(self, path: PathKey) -> Item | None:
        """The item at ``(…, block, "items", index)``, or None."""
        block = self.block_at(path)
        if not isinstance(block, Block) or len(path) < 2 or path[-2] != "items" or \
                not isinstance(path[-1], int):
            return None
        return block.items[path[-1]] if 0 <= path[-1] < len(block.items) else None
