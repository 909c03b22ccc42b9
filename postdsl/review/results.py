"""What a review finds, per program and in all: the statuses, the verdicts, the exit status.

A status says what happened to the NC text (the editor's review screen shows it); a
verdict says whether anything that reaches the machine moves differently, which is what
a reviewer approves.  The verdicts and the exit status are separate from the text
diff on purpose: CI can ask for a second approval only when the motion changed.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

from postdsl.errors import PostdslError

#: a progress callback: (done, total)
Progress = Callable[[int, int], None]

#: what the machine file is called on the working-tree side of a diff
WORKING_TREE = "working tree"

# The statuses of a (machine, program) pair: what happened to the NC text.
UNCHANGED = "unchanged"    # the same NC text (or the machine file is the same)
CHANGED = "changed"        # lines differ once block numbers are ignored
RENUMBERED = "renumbered"  # only block numbers differ
ADDED = "added"            # the machine file does not exist at the revision
REMOVED = "removed"        # the machine file no longer exists in the working tree
NOW_FAILS = "now_fails"    # posted before, the new post cannot post it
NOW_POSTS = "now_posts"    # could not be posted before, now it can
UNPOSTABLE = "unpostable"  # neither version can post it: reported, not a change
ERROR = "error"            # the CL file cannot be read (or postdsl failed): exit status 2

#: statuses that are a change of the NC output
CHANGE_STATUSES = frozenset({CHANGED, RENUMBERED, ADDED, REMOVED, NOW_FAILS, NOW_POSTS})

# The verdicts: does a change reach the machine?
SAME = "unchanged"
RENUMBERING = "renumbering only"
FORMAT_ONLY = "format only"          # other text; the control model replays the same motion
MOTION = "motion changed"            # a position, feed, spindle or tool state differs
NEWLY_REFUSED = "newly refused"      # posted (and verified) before, refused now
NEWLY_POSTING = "newly posting"      # refused before, posted now
NOT_REPLAYED = "text changed, not replayed"  # no control model: the motion is not known
NEW_MACHINE = "new machine file"
MACHINE_REMOVED = "machine file removed"
REFUSED_BY_BOTH = "refused by both"
FAILED = "error"

#: the order verdicts are listed in: the ones a reviewer must read first
VERDICTS = (MOTION, NEWLY_REFUSED, NEWLY_POSTING, NOT_REPLAYED, NEW_MACHINE, MACHINE_REMOVED,
            FORMAT_ONLY, RENUMBERING, REFUSED_BY_BOTH, FAILED, SAME)
#: verdicts that may change what the machine does: exit status 1
MOTION_VERDICTS = frozenset({MOTION, NEWLY_REFUSED, NEWLY_POSTING, NOT_REPLAYED, NEW_MACHINE,
                             MACHINE_REMOVED})
#: verdicts that change the text only: exit status 4 when nothing else changed
FORMAT_VERDICTS = frozenset({FORMAT_ONLY, RENUMBERING})

#: ``postdsl review``'s exit statuses (documented in docs/how-to/review.md)
EXIT_UNCHANGED = 0
EXIT_MOTION = 1
EXIT_ERROR = 2
EXIT_FORMAT_ONLY = 4

#: a verdict per status, where the status alone decides it
_VERDICT_OF_STATUS = {UNCHANGED: SAME, RENUMBERED: RENUMBERING, ADDED: NEW_MACHINE,
                      REMOVED: MACHINE_REMOVED, NOW_FAILS: NEWLY_REFUSED,
                      NOW_POSTS: NEWLY_POSTING, UNPOSTABLE: REFUSED_BY_BOTH, ERROR: FAILED}


def verdict_of(status: str) -> str:
    """The verdict a status decides alone ("" for ``changed``: the replay decides)."""
    return _VERDICT_OF_STATUS.get(status, "")


class ReviewError(PostdslError):
    """The review itself cannot run (bad revision, not a repository, bad corpus): exit 2."""

    exit_code = 2


@dataclass(frozen=True)
class MotionDifference:
    """Where two postings of a program first move differently, on both sides."""

    #: the CL record whose NC lines move differently (0: a line no record wrote)
    cl_line: int
    #: (1-based NC line number, its text) on each side; None when that side has no line there
    old: tuple[int, str] | None
    new: tuple[int, str] | None
    #: what differs, in words ("the end point", "the feed", ...)
    what: str = ""

    def describe(self) -> str:
        def side(label: str, line: tuple[int, str] | None) -> str:
            return f"{label} NC line {line[0]}: {line[1]}" if line else f"{label}: no line"
        where = f"CL line {self.cl_line}" if self.cl_line else "a line no CL record wrote"
        return (f"{where}{' (' + self.what + ')' if self.what else ''}; "
                f"{side('before', self.old)}; {side('after', self.new)}")

    def to_json(self) -> dict[str, Any]:
        return {"cl_line": self.cl_line, "what": self.what,
                "old": list(self.old) if self.old else None,
                "new": list(self.new) if self.new else None}


@dataclass
class ProgramDiff:
    """What a post change does to one program posted with one machine.

    What a worker sends back: the verdict, the counts and the diff lines that will be
    shown (at most ``diff_limit`` of them, ``diff_total`` counted), never whole programs.
    """

    machine: str
    program: str
    status: str
    #: unified diff, block numbers kept; empty when unchanged or renumbered only
    diff: list[str] = field(default_factory=list)
    added: int = 0
    removed: int = 0
    #: lines whose only change is their block number
    renumbered: int = 0
    #: the first renumbered line, old and new, for the one-line report
    renumber_example: tuple[str, str] | None = None
    old_error: str | None = None
    new_error: str | None = None
    #: changes no line shows (line ending, final newline)
    notes: list[str] = field(default_factory=list)
    #: False when the machine file is the same on both sides, so nothing was posted
    posted: bool = True
    #: the verdict (see VERDICTS); set from the status when the status decides it
    verdict: str = ""
    #: with the verdict ``motion changed``: where the motion first differs
    motion_at: MotionDifference | None = None
    #: the number of diff lines, of which ``diff`` holds the first (the rest not sent)
    diff_total: int = 0
    #: with plots asked for, the motion's pictures (review.plots.MotionPlots)
    motion: Any = None
    #: NC lines on each side (counts only: programs are never sent whole)
    old_count: int = field(default=0, compare=False)
    new_count: int = field(default=0, compare=False)
    #: taken from the result cache rather than posted
    cached: bool = field(default=False, compare=False)

    def __post_init__(self) -> None:
        if not self.verdict:
            self.verdict = verdict_of(self.status)
        if not self.diff_total:
            self.diff_total = len(self.diff)

    @property
    def changed(self) -> bool:
        """Whether the NC output differs."""
        return self.status in CHANGE_STATUSES

    @property
    def renumbering_only(self) -> bool:
        return self.status == RENUMBERED

    @property
    def moves_differently(self) -> bool:
        """Whether the change may reach the machine as other motion (exit status 1)."""
        return self.verdict in MOTION_VERDICTS

    def to_json(self) -> dict[str, Any]:
        return {
            "machine": self.machine, "program": self.program, "verdict": self.verdict,
            "motion_at": self.motion_at.to_json() if self.motion_at else None,
            "status": self.status, "changed": self.changed,
            "renumbering_only": self.renumbering_only,
            "added": self.added, "removed": self.removed, "renumbered": self.renumbered,
            "renumber_example": list(self.renumber_example) if self.renumber_example else None,
            "posted": self.posted, "old_error": self.old_error, "new_error": self.new_error,
            "notes": self.notes, "diff": self.diff, "diff_total": self.diff_total,
        }

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> ProgramDiff:
        """The inverse of :meth:`to_json` (the result cache keeps pairs this way)."""
        motion = data.get("motion_at")
        example = data.get("renumber_example")
        return cls(
            data["machine"], data["program"], data["status"], list(data["diff"]),  # not a post
            data["added"], data["removed"], data["renumbered"],
            (example[0], example[1]) if example else None, data["old_error"],
            data["new_error"], list(data["notes"]), data["posted"], data["verdict"],
            MotionDifference(motion["cl_line"],
                             tuple(motion["old"]) if motion["old"] else None,
                             tuple(motion["new"]) if motion["new"] else None,
                             motion["what"]) if motion else None,
            data["diff_total"])


class DiffStore:
    """Where the diffs of a long review wait for the report: in memory, or in a file.

    The report lists the verdicts first and the diffs after them; a review of a whole
    archive keeps only each program's verdict line in memory and spools its diff lines
    to a temporary file (``spool=True``), so the memory stays flat with the corpus.
    """

    def __init__(self, spool: bool = False) -> None:
        import tempfile

        # open until close(): the diffs wait there for the report
        self._file = (tempfile.TemporaryFile(  # noqa: SIM115
            "w+", encoding="utf-8", newline="\n") if spool else None)
        self._kept: dict[int, list[str]] = {}

    def put(self, program: ProgramDiff) -> None:
        if self._file is None or not program.diff:
            return
        self._file.seek(0, 2)
        start = self._file.tell()
        self._file.write("\n".join(program.diff) + "\n")
        self._kept[id(program)] = [str(start), str(len(program.diff))]
        program.diff = []

    def lines(self, program: ProgramDiff) -> list[str]:
        kept = self._kept.get(id(program))
        if kept is None or self._file is None:
            return program.diff
        self._file.seek(int(kept[0]))
        return [self._file.readline().rstrip("\n") for _ in range(int(kept[1]))]

    def close(self) -> None:
        if self._file is not None:
            self._file.close()


@dataclass
class ReviewResult:
    """Every pair's verdict plus what went wrong; ``exit_status`` is the CLI's."""

    against: str
    commit: str
    programs: list[ProgramDiff] = field(default_factory=list)
    #: located messages that make the review untrustworthy (exit status 2)
    errors: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    new_label: str = WORKING_TREE
    #: where the diffs are kept until the report (a file for a whole archive)
    store: DiffStore = field(default_factory=DiffStore)

    def diff_of(self, program: ProgramDiff) -> list[str]:
        """A program's diff lines, wherever they are kept."""
        return self.store.lines(program)

    @property
    def changed(self) -> list[ProgramDiff]:
        return [p for p in self.programs if p.changed]

    @property
    def exit_status(self) -> int:
        """0 nothing changed; 1 something may move differently; 4 format changes only; 2
        the review could not be trusted."""
        if self.errors:
            return EXIT_ERROR
        if any(p.moves_differently for p in self.programs):
            return EXIT_MOTION
        if any(p.verdict in FORMAT_VERDICTS for p in self.programs):
            return EXIT_FORMAT_ONLY
        return EXIT_UNCHANGED

    def verdicts(self) -> Counter[str]:
        return Counter(p.verdict for p in self.programs)

    def by_verdict(self) -> Iterator[ProgramDiff]:
        """The programs that changed, the verdicts a reviewer must read first."""
        rank = {verdict: index for index, verdict in enumerate(VERDICTS)}
        yield from sorted((p for p in self.programs if p.verdict != SAME),
                          key=lambda p: (rank.get(p.verdict, 0), p.machine, p.program))

    def summary(self) -> dict[str, int]:
        counts = {status: 0 for status in (UNCHANGED, CHANGED, RENUMBERED, ADDED, REMOVED,
                                           NOW_FAILS, NOW_POSTS, UNPOSTABLE, ERROR)}
        for program in self.programs:
            counts[program.status] += 1
        verdicts = self.verdicts()
        return {
            "programs": len(self.programs),
            "machines": len({p.machine for p in self.programs}),
            "changed_programs": len(self.changed),
            "added_lines": sum(p.added for p in self.programs),
            "removed_lines": sum(p.removed for p in self.programs),
            **counts,
            "errors": len(self.errors),
            **{f"verdict:{verdict}": verdicts.get(verdict, 0) for verdict in VERDICTS},
        }
