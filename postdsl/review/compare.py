"""Two postings of one program, compared line by line in time linear in their length.

Each NC line knows the CL record that wrote it (``NCLine.cl_line``), and both postings
come from the same CL, so the lines are first aligned by record: the runs of lines one
record wrote on each side are paired (the record numbers are unique and ordered, so
pairing them is linear), and only inside a pair whose lines differ does ``difflib``
look for the best match.  A program whose every line changed costs one short
``difflib`` per record instead of one quadratic search over the whole program.

Lines are compared on a key without the block number (see :func:`renumber_key`), so a
new start, increment or one more numbered block near the top is renumbering, not a
change of every line, and printed with the real lines: removed lines as they were,
added and context lines as they are now.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field

from postdsl import api
from postdsl.review.results import (
    ADDED,
    CHANGED,
    NOW_FAILS,
    NOW_POSTS,
    REMOVED,
    RENUMBERED,
    UNCHANGED,
    UNPOSTABLE,
    ProgramDiff,
    verdict_of,
)

#: the diff lines a worker sends back per program, by default: what a report shows
DIFF_LIMIT = 400

Opcode = tuple[str, int, int, int, int]


@dataclass
class Output:
    """One side of a comparison: the posted lines and their number-free keys, or why not."""

    lines: list[str] = field(default_factory=list)
    keys: list[str] = field(default_factory=list)
    text: str = ""
    error: str | None = None
    missing: bool = False
    #: the CL line that wrote each line (empty: one record wrote them all)
    records: list[int] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.error is None and not self.missing


def renumber_key(post: api.CompiledPost, line: api.NCLine) -> str:
    """The line with the number of its block-number word blanked, nothing else.

    Two lines are "renumbered only" when their keys are equal: every byte outside the
    number itself is the same.  The prefix and the suffix stay in the key, so a
    separator lost after the number (``N10 G0`` -> ``N10  G0``) is a change, shown.
    """
    rest = api.without_block_number(post, line)
    text = line.text
    if rest == text:
        return text
    numbering = post.numbering
    return numbering.prefix + "\N{NUMBER SIGN}" + text[len(text) - len(rest)
                                                        - len(numbering.suffix):]


def compare_outputs(machine: str, program: str, old: Output, new: Output, *,
                    old_label: str, new_label: str, context: int = 3,
                    limit: int | None = DIFF_LIMIT) -> ProgramDiff:
    """Classify and diff two postings of one program (at most ``limit`` diff lines kept)."""
    result = ProgramDiff(machine, program, UNCHANGED, old_error=old.error,
                         new_error=new.error, old_count=len(old.lines),
                         new_count=len(new.lines))
    if old.error is not None and new.error is not None:
        result.status = UNPOSTABLE
        result.verdict = verdict_of(UNPOSTABLE)
        return result
    if old.ok and new.ok and old.text == new.text:
        return result
    opcodes = aligned_opcodes(_numbered_keys(old), _numbered_keys(new),
                              old.records or None, new.records or None)
    added, removed, renumbered, example = _counts(opcodes, old.lines, new.lines)
    result.added, result.removed, result.renumbered = added, removed, renumbered
    result.renumber_example = example
    if added or removed:
        header = [f"--- {machine} @ {old_label}: {program}",
                  f"+++ {machine} @ {new_label}: {program}"]
        total = 0
        shown: list[str] = list(header)
        for line in unified(opcodes, old.lines, new.lines, context):
            total += 1
            if limit is None or total <= limit:
                shown.append(line)
        result.diff, result.diff_total = shown, total + len(header)
    if old.missing:
        result.status = ADDED
    elif new.missing:
        result.status = REMOVED
    elif old.error is not None:
        result.status = NOW_POSTS
    elif new.error is not None:
        result.status = NOW_FAILS
    elif added or removed:
        result.status = CHANGED
    elif renumbered:
        result.status = RENUMBERED
    else:
        # same lines, different text: the line ending or the final newline changed
        result.status = CHANGED
        result.notes.append("the lines are the same; the line ending or the final newline "
                            "changed")
    result.verdict = verdict_of(result.status)
    return result


def _numbered_keys(output: Output) -> list[str]:
    """The keys, marked where the line carries a block number.

    A number that changed is renumbering; a number added to or removed from a line is
    text the control receives differently (a block it can jump to, or not): a change.
    """
    return [key if key == line else "\N{NUMBER SIGN}" + key
            for line, key in zip(output.lines, output.keys, strict=True)]


def _runs(records: Sequence[int] | None, length: int) -> list[tuple[int, int, int]]:
    """(record, first line, end) of each run of lines one record wrote."""
    if records is None or not length:
        return [(0, 0, length)] if length else []
    runs: list[tuple[int, int, int]] = []
    start = 0
    current = records[0]
    for index in range(1, length):
        record = records[index]
        if record != current:
            runs.append((current, start, index))
            current, start = record, index
    runs.append((current, start, length))
    return runs


def aligned_opcodes(old: Sequence[str], new: Sequence[str], old_records: Sequence[int] | None,
                    new_records: Sequence[int] | None) -> list[Opcode]:
    """``difflib``-style opcodes turning ``old`` into ``new``, aligned by CL record first.

    The runs are paired by their record (``difflib`` over the record numbers, which are
    unique but for the few lines no record wrote, so it is linear); a pair of runs with
    equal keys is one ``equal`` opcode, other pairs are diffed on their own.
    """
    if old_records is None or new_records is None:
        old_records = new_records = None
    if len(old) == len(new) and old == new:
        return [("equal", 0, len(old), 0, len(new))] if old else []
    old_runs, new_runs = _runs(old_records, len(old)), _runs(new_records, len(new))
    opcodes: list[Opcode] = []
    for i1, i2, j1, j2 in _paired_runs(old_runs, new_runs, len(old), len(new)):
        if i2 - i1 == j2 - j1 and old[i1:i2] == new[j1:j2]:
            _append(opcodes, ("equal", i1, i2, j1, j2))
            continue
        matcher = difflib.SequenceMatcher(None, old[i1:i2], new[j1:j2], autojunk=False)
        for tag, a1, a2, b1, b2 in matcher.get_opcodes():
            _append(opcodes, (tag, i1 + a1, i1 + a2, j1 + b1, j1 + b2))
    return opcodes


def _paired_runs(old_runs: list[tuple[int, int, int]], new_runs: list[tuple[int, int, int]],
                 old_length: int, new_length: int) -> Iterator[tuple[int, int, int, int]]:
    """(old start, old end, new start, new end) of the spans to compare, in order."""
    old_keys = [run[0] for run in old_runs]
    new_keys = [run[0] for run in new_runs]
    if old_keys == new_keys:
        for old_run, new_run in zip(old_runs, new_runs, strict=True):
            yield old_run[1], old_run[2], new_run[1], new_run[2]
        return
    matcher = difflib.SequenceMatcher(None, old_keys, new_keys, autojunk=False)
    for tag, a1, a2, b1, b2 in matcher.get_opcodes():
        if tag == "equal":
            for k in range(a2 - a1):
                old_run, new_run = old_runs[a1 + k], new_runs[b1 + k]
                yield old_run[1], old_run[2], new_run[1], new_run[2]
            continue
        # records written on one side only (or replaced): one span each side
        i1 = old_runs[a1][1] if a1 < a2 else (old_runs[a1][1] if a1 < len(old_runs)
                                             else old_length)
        i2 = old_runs[a2 - 1][2] if a1 < a2 else i1
        j1 = new_runs[b1][1] if b1 < b2 else (new_runs[b1][1] if b1 < len(new_runs)
                                             else new_length)
        j2 = new_runs[b2 - 1][2] if b1 < b2 else j1
        yield i1, i2, j1, j2


def _append(opcodes: list[Opcode], opcode: Opcode) -> None:
    """Add an opcode, joining it to the previous one when both are ``equal``."""
    tag, i1, i2, j1, j2 = opcode
    if i1 == i2 and j1 == j2:
        return
    if opcodes and tag == "equal" and opcodes[-1][0] == "equal":
        last = opcodes[-1]
        opcodes[-1] = ("equal", last[1], i2, last[3], j2)
    else:
        opcodes.append(opcode)


def _counts(opcodes: Sequence[Opcode], old: Sequence[str], new: Sequence[str]
            ) -> tuple[int, int, int, tuple[str, str] | None]:
    """(added, removed, renumbered lines, the first renumbered pair)."""
    added = removed = renumbered = 0
    example: tuple[str, str] | None = None
    for tag, i1, i2, j1, j2 in opcodes:
        if tag == "equal":
            if old[i1:i2] == new[j1:j2]:
                continue
            for i, j in zip(range(i1, i2), range(j1, j2), strict=True):
                if old[i] != new[j]:
                    renumbered += 1
                    if example is None:
                        example = (old[i], new[j])
        else:
            removed += i2 - i1
            added += j2 - j1
    return added, removed, renumbered, example


def _grouped(opcodes: Sequence[Opcode], context: int) -> Iterator[list[Opcode]]:
    """The opcodes in hunks with ``context`` lines around each change (difflib's rule)."""
    codes = list(opcodes) or [("equal", 0, 1, 0, 1)]
    if codes[0][0] == "equal":
        tag, i1, i2, j1, j2 = codes[0]
        codes[0] = tag, max(i1, i2 - context), i2, max(j1, j2 - context), j2
    if codes[-1][0] == "equal":
        tag, i1, i2, j1, j2 = codes[-1]
        codes[-1] = tag, i1, min(i2, i1 + context), j1, min(j2, j1 + context)
    span = context + context
    group: list[Opcode] = []
    for tag, i1, i2, j1, j2 in codes:
        if tag == "equal" and i2 - i1 > span:
            group.append((tag, i1, min(i2, i1 + context), j1, min(j2, j1 + context)))
            yield group
            group = []
            i1, j1 = max(i1, i2 - context), max(j1, j2 - context)
        group.append((tag, i1, i2, j1, j2))
    if group and not (len(group) == 1 and group[0][0] == "equal"):
        yield group


def unified(opcodes: Sequence[Opcode], old: Sequence[str], new: Sequence[str],
            context: int) -> Iterator[str]:
    """The lines of a unified diff (no header), lazily: a caller may stop at its limit."""
    for group in _grouped(opcodes, context):
        first, last = group[0], group[-1]
        yield f"@@ -{_range(first[1], last[2])} +{_range(first[3], last[4])} @@"
        for op, i1, i2, j1, j2 in group:
            if op == "equal":
                yield from (" " + line for line in new[j1:j2])
                continue
            yield from ("-" + line for line in old[i1:i2])
            yield from ("+" + line for line in new[j1:j2])


def _range(start: int, stop: int) -> str:
    """A hunk range as ``diff -u`` writes it (1-based start, length when not 1)."""
    length = stop - start
    begin = start + 1
    if length == 1:
        return str(begin)
    if not length:
        begin -= 1
    return f"{begin},{length}"
