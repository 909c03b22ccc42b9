"""Where each NC word came from: the CL record, table, block and item that wrote it.

A technologist reads the NC program and thinks in its words (``G83``, ``R70.0``);
a post is edited by table cell.  This module links the two without slowing the
engine: :class:`TracingEngine` runs the *traced* flavour of the post's generated
code (:func:`postdsl.compile.codegen.generate` with ``traced=True``), whose block functions
hand each line's words and the items that wrote them to :meth:`TracingEngine.
_trace_block`.  It is the same generated code as ``postdsl post`` runs, so what is
traced is what is posted; the plain :class:`~postdsl.run.engine.Engine` runs the
untraced flavour, and only an explain or an editor's "where does this come from"
pays for the bookkeeping.

It also answers the reverse question statically, from the post document:
which cells can write a given word (:func:`word_writers`).
"""

from __future__ import annotations

import re
from collections import deque
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from datetime import datetime
from typing import Any, NamedTuple

from postdsl.cl.model import CLCommand, command_fields
from postdsl.compile.compiler import CompiledBlock, CompiledItem, CompiledPost
from postdsl.compile.runtime import NCLine
from postdsl.lang.post.nodes import (
    Block,
    BlockEntry,
    ExprItem,
    Item,
    ParamItem,
    PlainText,
    Post,
    TextItem,
)
from postdsl.run.engine import Engine

PathKey = tuple[Any, ...]


@dataclass(frozen=True)
class WordOrigin:
    """One stretch of an NC line and the post item that wrote it (``path`` None: the
    block number, written by the post's numbering)."""

    start: int
    end: int
    text: str
    path: PathKey | None


@dataclass(frozen=True)
class TracedLine:
    """An NC line with everything that made it."""

    #: 1-based number of the line in the posted program
    number: int
    line: NCLine
    #: the CL record being posted (a generated move when the engine expanded a hole)
    record: CLCommand
    #: where the block is defined in the post (inside a structure after ``use:``)
    block_path: PathKey
    words: tuple[WordOrigin, ...]
    #: (path, source) of the block's condition and of every written item's condition
    conditions: tuple[tuple[PathKey, str], ...]
    #: the registers (what the control holds) right after the line
    registers: Mapping[str, Any] = field(default_factory=dict)


class _Origin(NamedTuple):
    """What made one written line, as its block function handed it on: the words are
    found in the line only for a line that is asked for (:func:`_traced`)."""

    record: CLCommand
    block: CompiledBlock
    text: str
    #: the words the block wrote, each put by the item at the same place in ``items``
    parts: list[str]
    items: list[CompiledItem]
    registers: dict[str, Any]


class TracingEngine(Engine):
    """An engine that knows, for each line it yields, which item wrote which characters.

    Every line it writes leaves its origin in :attr:`pending`, in the order the
    lines are yielded (a table may be written whole before its first line is).
    """

    traced = True

    def __init__(self, post: CompiledPost, *, now: datetime, cl_file: str = "<cl>") -> None:
        #: the record being posted (the traced lanes of the moves set it too)
        self.record: CLCommand | None = None
        super().__init__(post, now=now, cl_file=cl_file)
        #: the origin of every written line not yet yielded, in order: the engine may
        #: write a whole table before it yields its first line
        self.pending: deque[_Origin] = deque()
        #: copy the registers for this line only (1-based), or for every line when None
        self.wanted: int | None = None
        self._written = 0

    def post_command(self, command: CLCommand) -> Iterable[NCLine]:
        outer = self.record
        self.record = command  # the innermost command: an expanded hole's moves
        try:
            return super().post_command(command)
        finally:
            self.record = outer

    def _trace_block(self, block: CompiledBlock, text: str, parts: list[str],
                     items: list[CompiledItem]) -> None:
        """Called by each traced block function with the line it wrote and its words."""
        self._written += 1
        registers = dict(self.registers) if self.wanted in (None, self._written) else {}
        assert self.record is not None
        self.pending.append(_Origin(self.record, block, text, parts, items, registers))


def _traced(number: int, line: NCLine, origin: _Origin, separator: str) -> TracedLine:
    """The traced line of ``origin``: its words found in the line from its end, before
    them the block number, if any (a line whose trailing spaces were trimmed keeps no
    words); the conditions of the block and of every item that wrote."""
    record, block, text, parts, items, registers = origin
    written = [(item, part) for item, part in zip(items, parts, strict=True) if part]
    body = separator.join(part for _item, part in written)  # between written words only
    words: list[WordOrigin] = []
    start = len(text) - len(body) if text.endswith(body) else None
    if start is not None:
        if start:
            words.append(WordOrigin(0, start, text[:start], None))
        for item, part in written:
            words.append(WordOrigin(start, start + len(part), part, item.path))
            start += len(part) + len(separator)
    conditions = [(block.path + ("if",), block.condition.source)] \
        if block.condition is not None else []
    conditions += [(item.path + ("if",), item.condition.source)
                   for item in items if item.condition is not None]
    return TracedLine(number, line, record, block.path, tuple(words), tuple(conditions),
                      registers)


def trace_lines(post: CompiledPost, commands: Iterable[CLCommand], *, now: datetime,
                cl_file: str = "<cl>", wanted: int | None = None) -> Iterator[TracedLine]:
    """Post ``commands`` and trace every line (or only line ``wanted``, 1-based, and stop).

    The registers are copied for the lines returned only, so tracing one line of
    a long program costs little more than posting up to it.
    """
    engine = TracingEngine(post, now=now, cl_file=cl_file)
    engine.wanted = wanted
    separator = post.word_separator
    pending = engine.pending
    for number, line in enumerate(engine.run(commands), start=1):
        origin = pending.popleft()
        if wanted is not None and number != wanted:
            continue
        yield _traced(number, line, origin, separator)
        if wanted is not None:
            return


# --- describing -------------------------------------------------------------------------------


def place(path: PathKey) -> str:
    """A post path in the editor's words: ``deep_drill, block 2, item 3``."""
    if len(path) < 2:
        return "the post" if not path else str(path[0])
    kind = {"custom_cycles": "custom cycle ", "structures": "structure "}.get(str(path[0]), "")
    rest = path[2:] if path[0] == "structures" else path[3:]
    text = f"{kind}{path[1]}"
    if rest and isinstance(rest[0], int):
        text += f", block {rest[0] + 1}"
        if len(rest) >= 3 and rest[1] == "items" and isinstance(rest[2], int):
            text += f", item {rest[2] + 1}"
    return text


def item_words(item: Item | None) -> str:
    """An item of the post as a short phrase: ``fixed text ' G83'``, ``x (prefix ' X',
    format coord, changed)``."""
    if isinstance(item, PlainText):
        return f"fixed text {item.text!r}"
    if isinstance(item, TextItem):
        head = f"text {item.text!r}"
    elif isinstance(item, ParamItem):
        head = f"parameter {item.param}"
    elif isinstance(item, ExprItem) and item.expr is not None:
        head = f"expression {item.expr.source}"
    else:
        return "an item"
    details = [f"prefix {item.prefix!r}"] if item.prefix else []
    details += [f"format {item.format}"] if item.format else []
    details += [f"mode {item.mode}"] if item.mode else []
    details += [f"register {item.modal}"] if item.modal else []
    return head + (f" ({', '.join(details)})" if details else "")


def record_words(record: CLCommand) -> str:
    """A CL record as ``single_peck x=40 y=20 top=70``: only the values it carries."""
    values = []
    for spec in command_fields(type(record)):
        value = getattr(record, spec.name, None)
        if value is None or spec.name == "line":
            continue
        values.append(f"{spec.name}={value_words(value)}")
    return " ".join([record.name, *values])


def value_words(value: Any) -> str:
    """A value as a technologist writes it: ``70``, ``'cw'``, ``x, y`` — not Python's repr
    of a tuple."""
    if isinstance(value, float):
        return f"{value:g}" if abs(value) < 1e15 else repr(value)
    if isinstance(value, (tuple, list)):
        return ", ".join(value_words(v) for v in value) if value else "(none)"
    if isinstance(value, str):
        return repr(value)
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{k}: {value_words(v)}" for k, v in value.items()) + "}"
    return str(value)


def explain(traced: TracedLine, post: Post, cl_file: str = "<cl>") -> list[str]:
    """The lines ``postdsl explain`` prints (and the editor's trace pane shows)."""
    line = traced.line
    out = [f"NC line {traced.number}: {line.text}"]
    where = f"{cl_file}:{line.cl_line}" if line.cl_line else f"{cl_file} (added by the engine)"
    out.append(f"CL record  {where}: {record_words(traced.record)}")
    if traced.record.name != line.command:
        out.append(f"           (a move the engine wrote for the hole of {line.command})")
    table = f"table {line.table}" + (f" (redirected from {line.command})"
                                     if line.table != line.command else "")
    out.append(f"written by {table}, {place(traced.block_path).split(', ', 1)[-1]}"
               if traced.block_path[0] != "structures" else
               f"written by {table} through {place(traced.block_path)}")
    out.append("words:")
    for word in traced.words:
        if word.path is None:
            out.append(f"  {word.text.strip()!s:<14} block number")
            continue
        spec = post.item_at(word.path)
        index = word.path[-1] + 1 if isinstance(word.path[-1], int) else "?"
        out.append(f"  {word.text.strip()!s:<14} item {index}: {item_words(spec)}")
    if traced.conditions:
        out.append("conditions that fired:")
        for path, source in traced.conditions:
            out.append(f"  {source}    ({place(path[:-1])})")
    # registers hold the text the control received: show it as written, unquoted
    registers = ", ".join(f"{name}={value if isinstance(value, str) else value_words(value)}"
                          for name, value in sorted(traced.registers.items()))
    out.append(f"registers after the line: {registers or '(none)'}")
    return out


# --- from a word to the cells that write it ---------------------------------------------------


@dataclass(frozen=True)
class WordWriter:
    """A cell of the post that writes a word: as fixed text, or as the prefix of a value."""

    #: "command", "cycle" or "structure", and the table's name
    kind: str
    name: str
    block: int
    item: int
    #: True when the word is the item's prefix (``X`` of every X coordinate)
    prefix: bool

    @property
    def path(self) -> PathKey:
        section = {"command": "commands", "cycle": "custom_cycles"}.get(self.kind)
        if section is None:
            return ("structures", self.name, self.block, "items", self.item)
        return (section, self.name, "blocks", self.block, "items", self.item)

    def sentence(self, word: str) -> str:
        what = {"command": "", "cycle": "custom cycle ", "structure": "structure "}[self.kind]
        how = " (as the prefix of a value)" if self.prefix else ""
        return f"{word} is written by {what}{self.name}, block {self.block + 1}, " \
               f"item {self.item + 1}{how}"


_WORD = re.compile(r"^[A-Za-z]{1,8}[-+]?[0-9]*\.?[0-9]*$")


def looks_like_word(text: str) -> bool:
    """``G83``, ``g83``, ``M6``, ``X``, ``MCALL``: something to look for in the NC, not a
    command name (those are lower case words joined by ``_``, such as ``arc_move``)."""
    text = text.strip()
    return bool(_WORD.match(text)) and (text.isupper() or any(c.isdigit() for c in text))


def word_writers(post: Post, word: str) -> list[WordWriter]:
    """Every item of the post whose fixed text or prefix writes ``word``.

    A word matches as a whole NC word: ``G8`` does not find ``G83``, ``G83`` does
    not find ``G838``; letters are compared without case.
    """
    word = word.strip()
    if not word:
        return []
    pattern = re.compile(r"(?<![A-Za-z0-9.])" + re.escape(word) + r"(?![0-9.])", re.IGNORECASE)
    letters = re.compile(r"(?<![A-Za-z0-9.])" + re.escape(word) + r"$", re.IGNORECASE)
    found: list[WordWriter] = []
    kinds = {"commands": "command", "custom_cycles": "cycle", "structures": "structure"}
    for section, table in post.tables():
        found += _writers(kinds[section], table.name, table.blocks or (), pattern, letters)
    head = re.match(r"[A-Za-z]+", word)
    if not found and head is not None and head.group() != word:
        # X12.5: no item writes that text, but every value with the prefix X can
        return [w for w in word_writers(post, head.group()) if w.prefix]
    return found


#: the ISO drilling cycles in words, by the CL command each G word stands for
_SAID = {"single_peck": "drilling", "deep_drill": "deep drilling",
         "break_chip": "chip-breaking drilling", "tapping": "tapping",
         "tapping_ccw": "left-hand tapping", "boring": "boring",
         "boring_spindle_stop": "boring with a spindle stop"}


def iso_meaning(word: str) -> str | None:
    """The CL command an ISO drilling word stands for (``G83`` -> ``deep_drill``), as the
    FreeCAD reader reads it; None for any other word."""
    from postdsl.cl.freecad import _DRILLS  # the one table of what the G words mean

    cycle = _DRILLS.get(word.strip().upper())
    return cycle.name if cycle is not None else None


@dataclass(frozen=True)
class WordMeaning:
    """What an NC word that the post does not write means here: the CL command it stands
    for on ISO controls (``G83``: ``deep_drill``) and the post's table for it."""

    word: str
    #: the CL command the word stands for, and the table that writes it here (the
    #: command's own, or the one it redirects to); "command" or "cycle"
    command: str
    table: str
    kind: str
    #: the first fixed text of that table (``MCALL CYCLE83``), "" when it has none
    writes: str

    @property
    def said(self) -> str:
        return _SAID.get(self.command, self.command.replace("_", " "))

    def sentence(self) -> str:
        """``G83: deep drilling on ISO controls, written here by deep_drill as MCALL
        CYCLE83`` (``... by break_chip through deep_drill ...`` for a redirect)."""
        through = f" through {self.table}" if self.table != self.command else ""
        writes = f" as {self.writes}" if self.writes else ""
        return f"{self.word}: {self.said} on ISO controls, written here by " \
               f"{self.command}{through}{writes}"


def word_meaning(post: Post, word: str) -> WordMeaning | None:
    """The table of ``post`` for what ``word`` means on ISO controls, when no item of the
    post writes the word as fixed text (a post of another control writes G83's deep
    drilling as a cycle call: ``CYCLE83``, ``CYCL DEF 200``).  A cell that writes only the word's
    letter before a computed number (a work offset's ``G`` of G54 + n) may not mean it:
    the meaning is the better answer then.  None: the post writes the word itself, the
    word means no CL command, or the post has no table for it."""
    if not looks_like_word(word) or any(not w.prefix for w in word_writers(post, word)):
        return None
    command = iso_meaning(word)
    if command is None:
        return None
    table = command
    seen: set[str] = set()
    while table in post.commands and table not in seen:
        seen.add(table)
        target = post.commands[table].redirect
        if target is None or target not in post.commands:
            break
        table = target
    if table in post.commands:
        return WordMeaning(word.strip().upper(), command, table, "command",
                           _first_text(post.commands[table].blocks or ()))
    if command in post.custom_cycles:
        return WordMeaning(word.strip().upper(), command, command, "cycle",
                           _first_text(post.custom_cycles[command].blocks or ()))
    return None


def _first_text(blocks: Iterable[BlockEntry]) -> str:
    """The first fixed text of a table's own blocks, without the punctuation around it."""
    for block in blocks:
        for item in block.items if isinstance(block, Block) else ():
            if isinstance(item, PlainText | TextItem):
                text = item.text.strip().rstrip("(~,").strip()
                if any(c.isalnum() for c in text):
                    return text
    return ""


def _writers(kind: str, name: str, blocks: Iterable[BlockEntry], pattern: re.Pattern[str],
             letters: re.Pattern[str]) -> Iterator[WordWriter]:
    for block_index, block in enumerate(blocks):
        items = block.items if isinstance(block, Block) else ()
        for item_index, item in enumerate(items):
            if isinstance(item, PlainText):
                written, prefix = item.text, ""
            else:
                prefix = item.prefix or ""
                written = prefix + item.text if isinstance(item, TextItem) else ""
            if written and pattern.search(written):
                yield WordWriter(kind, name, block_index, item_index, False)
            elif prefix and not written and letters.search(prefix):
                yield WordWriter(kind, name, block_index, item_index, True)
