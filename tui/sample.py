"""The sample program the previews post: read, posted and indexed off the UI thread.

A technologist's finishing program has hundreds of thousands of moves; posting it
takes seconds.  The editor posts it in a worker and shows the previous program
until the new one arrives, so everything here is plain data a thread can build:
no widgets, no app.  The index answers what the screen asks on every cursor move
(where does table T, block B first write, how many lines are T's) without a pass
over the whole program on the UI thread.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from postdsl import api

#: a program of at most this many CL commands is posted at once, with the keystroke:
#: it takes a few milliseconds, and a "posting…" flash on every edit would only distract
INLINE_COMMANDS = 3000
#: a CL file larger than this is read in the worker too (200 000 moves are ~15 MB)
INLINE_BYTES = 300_000


@dataclass
class Sample:
    """A CL program read for the previews, or why it could not be."""

    path: Path | None
    commands: list[api.CLCommand] = field(default_factory=list)
    error: str | None = None
    #: too large to read with a keystroke: never read here, the posting process reads it
    pending: bool = False
    #: the names the program uses, as the posting process found them (pending samples)
    used_names: frozenset[str] | None = None

    @property
    def name(self) -> str:
        return self.path.name if self.path is not None else "no sample program"

    @property
    def used(self) -> frozenset[str]:
        """CL command (and custom cycle) names the program uses."""
        if self.used_names is not None:
            return self.used_names
        names = set()
        for command in self.commands:
            names.add(command.name)
            cycle = getattr(command, "cycle", None)
            if command.name == "custom_cycle" and cycle:
                names.add(cycle)
        return frozenset(names)

    @property
    def small(self) -> bool:
        return not self.pending and len(self.commands) <= INLINE_COMMANDS


def sample_for(path: Path | None) -> Sample:
    """A short CL program read now; a long one left ``pending`` for a worker to read."""
    try:
        large = path is not None and path.stat().st_size > INLINE_BYTES
    except OSError:
        large = False
    return Sample(path, pending=True) if large else read_sample(path)


def read_sample(path: Path | None) -> Sample:
    """Read a CL program; an unreadable one becomes a message, never an exception."""
    if path is None:
        return Sample(None, error="no sample program: start the editor with --cl FILE")
    try:
        return Sample(path, list(api.read_cl(path)))
    except api.CLError as exc:
        return Sample(path, error=str(exc))
    except OSError as exc:
        return Sample(path, error=f"cannot read the sample program: {exc}")


#: a run of posted lines as columns: (texts, commands, tables, blocks)
Chunk = tuple[list[str], list[str], list[str], list[int]]


@dataclass
class Program:
    """A posted sample program, kept as columns, and its index.

    Columns, not one NCLine per line: 200 000 small objects make every full garbage
    collection walk them, and such a pause on the UI thread is a frozen keystroke; a
    list of strings is walked as one object.
    """

    texts: list[str] = field(default_factory=list)
    commands: list[str] = field(default_factory=list)
    tables: list[str] = field(default_factory=list)
    blocks: list[int] = field(default_factory=list)
    error: str | None = None
    #: (table, block), table and ("command", name) -> index of its first line
    first: dict[object, int] = field(default_factory=dict)
    #: table, and ("command", name) -> how many lines it wrote
    count: Counter[object] = field(default_factory=Counter)

    def __len__(self) -> int:
        return len(self.texts)

    def extend(self, chunk: Chunk) -> None:
        texts, commands, tables, blocks = chunk
        self.texts += texts
        self.commands += commands
        self.tables += tables
        self.blocks += blocks


class Indexer:
    """Builds a program's columns and index as its lines are posted (here or in the
    posting process)."""

    def __init__(self) -> None:
        self.program = Program()
        self._index = 0

    def add(self, line: api.NCLine) -> None:
        program, index = self.program, self._index
        program.texts.append(line.text)
        program.commands.append(line.command)
        program.tables.append(line.table)
        program.blocks.append(line.block)
        first, count = program.first, program.count
        first.setdefault((line.table, line.block), index)
        first.setdefault(line.table, index)
        first.setdefault(("command", line.command), index)
        count[line.table] += 1
        count[("command", line.command)] += 1
        self._index += 1


def post_sample(post: api.CompiledPost | None, problems: int, sample: Sample) -> Program:
    """Post a short sample with the post, or say why not."""
    if post is None:
        return Program(error=f"the post has {problems} problem{'s' if problems != 1 else ''}: "
                             f"the program cannot be posted")
    if sample.error:
        return Program(error=sample.error)
    indexer = Indexer()
    try:
        for line in api.iter_post(post, sample.commands, cl_file=sample.name):
            indexer.add(line)
    except (api.CLError, api.PostError) as exc:
        indexer.program.error = str(exc)
    except Exception as exc:  # an engine bug: say so, keep the editor (and the work)
        indexer.program.error = f"internal error while posting: {type(exc).__name__}: {exc}"
    return indexer.program


def shown_path(path: Path) -> str:
    """A program's path as corpus.yaml writes it (relative to the repository), else whole."""
    root = api.machines_root()
    try:
        return path.resolve().relative_to(root.resolve()).as_posix()
    except ValueError:
        return str(path)
