"""Review a post change by its effect: which NC lines of which programs change.

A post edit is reviewed like code, but the YAML diff alone does not say what
reaches the machine: one changed format touches every coordinate of every
program.  This module posts a corpus of CL programs with each machine file
as it is at a git revision (read with ``git cat-file``, no checkout) and as
it is in the working tree, and diffs the NC outputs line by line — the
answer to PPU's separate PostComparer tool, kept in git.

Design points:

* Programs are compared on their lines *without block numbers* (see
  :func:`postdsl.api.without_block_number`), then shown with them.  A new
  start or increment, or one more numbered block near the top, is reported
  as "renumbering", not as hundreds of changed lines.
* Posting uses one fixed time (``SOURCE_DATE_EPOCH`` when set), so the date
  in a program header never shows up as a change.
* Each (machine, program) pair is posted in a worker process; nothing but
  post texts and file paths crosses the process boundary, since compiled
  posts are closures and cannot be pickled.
* A program one machine cannot post (an unknown command, a move outside the
  travel) is a finding about that pair, not a failure of the review; only
  what stops the review from being trustworthy — a bad revision, an invalid
  post, an unreadable CL file — is an error (exit status 2).

Only :mod:`postdsl.api` is used for posting, like every other tool.
"""

from __future__ import annotations

import contextlib
import difflib
import json
import os
import re
import subprocess
import sys
import tempfile
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any
from urllib.parse import quote

from ruamel.yaml import YAML
from ruamel.yaml.error import YAMLError

from postdsl import api
from postdsl.errors import Location, PostdslError, printable
from postdsl.review_plots import MotionPlots, PlotFiles, compare_motion

__all__ = [
    "CHANGE_STATUSES", "FORMATS", "Program", "ProgramDiff", "ReviewError", "ReviewResult",
    "compare_outputs", "corpus_for_machine", "headline", "render", "render_json",
    "render_markdown", "render_text", "review", "review_texts", "review_time",
    "terminal_progress",
]

#: the posting time when SOURCE_DATE_EPOCH is not set; any constant will do
FIXED_TIME = datetime(2000, 1, 1, tzinfo=UTC)

#: what the machine file is called on the working-tree side of a diff
WORKING_TREE = "working tree"

# The statuses of a (machine, program) pair.
UNCHANGED = "unchanged"    # the same NC text (or the machine file is the same)
CHANGED = "changed"        # lines differ once block numbers are ignored
RENUMBERED = "renumbered"  # only block numbers differ
ADDED = "added"            # the machine file does not exist at the revision
REMOVED = "removed"        # the machine file no longer exists in the working tree
NOW_FAILS = "now_fails"    # posted before, the new post cannot post it
NOW_POSTS = "now_posts"    # could not be posted before, now it can
UNPOSTABLE = "unpostable"  # neither version can post it: reported, not a change
ERROR = "error"            # the CL file cannot be read (or postdsl failed): exit status 2

#: statuses that make ``postdsl review`` exit with 1
CHANGE_STATUSES = frozenset({CHANGED, RENUMBERED, ADDED, REMOVED, NOW_FAILS, NOW_POSTS})

FORMATS = ("text", "markdown", "json")

#: files in a --corpus folder that are documentation or posts, not CL programs
_NOT_CL = frozenset({".md", ".rst", ".yaml", ".yml"})


class ReviewError(PostdslError):
    """The review itself cannot run (bad revision, not a repository, bad corpus): exit 2."""

    exit_code = 2


# --- data model ------------------------------------------------------------------------------


@dataclass(frozen=True)
class Program:
    """A CL program of the corpus: how it is shown, and where it is read from."""

    name: str
    path: Path


@dataclass
class ProgramDiff:
    """What a post change does to one program posted with one machine."""

    machine: str
    program: str
    status: str
    #: the NC lines as posted by the old and the new post (empty when not posted)
    old_lines: list[str] = field(default_factory=list)
    new_lines: list[str] = field(default_factory=list)
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
    #: with plots asked for, a changed program replayed on both sides (review_plots)
    motion: MotionPlots | None = None

    @property
    def changed(self) -> bool:
        """Whether the NC output differs (exit status 1)."""
        return self.status in CHANGE_STATUSES

    @property
    def renumbering_only(self) -> bool:
        return self.status == RENUMBERED

    def to_json(self) -> dict[str, Any]:
        return {
            "machine": self.machine, "program": self.program, "status": self.status,
            "changed": self.changed, "renumbering_only": self.renumbering_only,
            "added": self.added, "removed": self.removed, "renumbered": self.renumbered,
            "renumber_example": list(self.renumber_example) if self.renumber_example else None,
            "posted": self.posted, "old_error": self.old_error, "new_error": self.new_error,
            "notes": self.notes, "diff": self.diff,
        }


@dataclass
class ReviewResult:
    """Every pair's diff plus what went wrong; ``exit_status`` is the CLI's."""

    against: str
    commit: str
    programs: list[ProgramDiff] = field(default_factory=list)
    #: located messages that make the review untrustworthy (exit status 2)
    errors: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    new_label: str = WORKING_TREE

    @property
    def changed(self) -> list[ProgramDiff]:
        return [p for p in self.programs if p.changed]

    @property
    def exit_status(self) -> int:
        if self.errors:
            return 2
        return 1 if self.changed else 0

    def summary(self) -> dict[str, int]:
        counts = {status: 0 for status in (UNCHANGED, CHANGED, RENUMBERED, ADDED, REMOVED,
                                           NOW_FAILS, NOW_POSTS, UNPOSTABLE, ERROR)}
        for program in self.programs:
            counts[program.status] += 1
        return {
            "programs": len(self.programs),
            "machines": len({p.machine for p in self.programs}),
            "changed_programs": len(self.changed),
            "added_lines": sum(p.added for p in self.programs),
            "removed_lines": sum(p.removed for p in self.programs),
            **counts,
            "errors": len(self.errors),
        }


# --- comparing two outputs -------------------------------------------------------------------


@dataclass
class _Output:
    """One side of a comparison: the posted lines and their number-free keys, or why not."""

    lines: list[str] = field(default_factory=list)
    keys: list[str] = field(default_factory=list)
    text: str = ""
    error: str | None = None
    missing: bool = False
    #: the posted lines with their origins, for replaying the motion
    nc: list[api.NCLine] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.error is None and not self.missing


def compare_outputs(machine: str, program: str, old: _Output, new: _Output, *,
                    old_label: str, new_label: str, context: int = 3) -> ProgramDiff:
    """Classify and diff two postings of one program.

    The diff is computed on the lines without block numbers, so that
    renumbered lines match, and printed with the real lines: removed lines
    as they were, added and context lines as they are now.
    """
    result = ProgramDiff(machine, program, UNCHANGED, old.lines, new.lines,
                         old_error=old.error, new_error=new.error)
    if old.error is not None and new.error is not None:
        result.status = UNPOSTABLE
        return result
    if old.ok and new.ok and old.text == new.text:
        return result
    header = (f"--- {machine} @ {old_label}: {program}", f"+++ {machine} @ {new_label}: {program}")
    diff, added, removed, renumbered, example = _unified(
        old.lines, new.lines, _numbered_keys(old), _numbered_keys(new), context)
    result.added, result.removed, result.renumbered = added, removed, renumbered
    result.renumber_example = example
    if diff:
        result.diff = [*header, *diff]
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
    return result


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


def _numbered_keys(output: _Output) -> list[str]:
    """The keys, marked where the line carries a block number.

    A number that changed is renumbering; a number added to or removed from a line is
    text the control receives differently (a block it can jump to, or not): a change.
    """
    return [key if key == line else "\N{NUMBER SIGN}" + key
            for line, key in zip(output.lines, output.keys, strict=True)]


def _unified(old: Sequence[str], new: Sequence[str], old_keys: Sequence[str],
             new_keys: Sequence[str], context: int
             ) -> tuple[list[str], int, int, int, tuple[str, str] | None]:
    """A unified diff of ``old`` -> ``new`` matched on the keys, and its counts."""
    matcher = difflib.SequenceMatcher(None, old_keys, new_keys, autojunk=False)
    added = removed = renumbered = 0
    example: tuple[str, str] | None = None
    for tag, i1, i2, j1, j2 in matcher.get_opcodes():
        if tag == "equal":
            for i, j in zip(range(i1, i2), range(j1, j2), strict=True):
                if old[i] != new[j]:
                    renumbered += 1
                    if example is None:
                        example = (old[i], new[j])
        else:
            removed += i2 - i1
            added += j2 - j1
    lines: list[str] = []
    if added or removed:
        for group in matcher.get_grouped_opcodes(context):
            first, last = group[0], group[-1]
            lines.append(f"@@ -{_range(first[1], last[2])} +{_range(first[3], last[4])} @@")
            for op, i1, i2, j1, j2 in group:
                if op == "equal":
                    lines.extend(" " + line for line in new[j1:j2])
                    continue
                lines.extend("-" + line for line in old[i1:i2])
                lines.extend("+" + line for line in new[j1:j2])
    return lines, added, removed, renumbered, example


def _range(start: int, stop: int) -> str:
    """A hunk range as ``diff -u`` writes it (1-based start, length when not 1)."""
    length = stop - start
    begin = start + 1
    if length == 1:
        return str(begin)
    if not length:
        begin -= 1
    return f"{begin},{length}"


# --- posting (in worker processes) ----------------------------------------------------------


def review_time() -> datetime:
    """The posting time of a review: SOURCE_DATE_EPOCH when set, else a constant."""
    if os.environ.get("SOURCE_DATE_EPOCH"):
        return api.posting_time()
    return FIXED_TIME


@dataclass(frozen=True)
class _MachineSides:
    """A machine file's two versions, as text (None: the file does not exist there).

    A post that ``extends:`` another is read from a path, so its base is found as
    ``postdsl post`` finds it (relative to the post's folder): ``old_path`` is a copy
    of the old side's chain at the revision, ``new_path`` the working-tree file.  The
    bases' texts are part of each side: a base that changed changes every child.
    """

    old_text: str | None
    new_text: str | None
    old_file: str
    new_file: str
    old_path: Path | None = None
    new_path: Path | None = None
    old_bases: tuple[str, ...] = ()
    new_bases: tuple[str, ...] = ()

    @property
    def same(self) -> bool:
        """Both sides are the same post, bases included: nothing to post."""
        return self.old_text == self.new_text and self.old_bases == self.new_bases


def load_side(text: str, file: str, path: Path | None) -> api.CompiledPost:
    """A post's text compiled as read from ``path`` (its ``extends:`` found from there)."""
    from postdsl.lang.loader import PostSource, parse_yaml

    if path is None:
        return api.load_post_text(text, file)
    return api.compile_source(PostSource(file, parse_yaml(text, file), text, path))


class _Poster:
    """Posts (machine, program) pairs; one per process, caching compiled posts and CL."""

    def __init__(self, machines: Mapping[str, _MachineSides], now: datetime,
                 labels: tuple[str, str], context: int, plots: bool = False) -> None:
        self.machines = machines
        self.now = now
        self.labels = labels
        self.context = context
        self.plots = plots
        self._posts: dict[tuple[str, bool], api.CompiledPost] = {}
        self._cl: tuple[Path, list[api.CLCommand]] | None = None

    def _post(self, machine: str, new: bool) -> api.CompiledPost:
        key = (machine, new)
        post = self._posts.get(key)
        if post is None:
            sides = self.machines[machine]
            text = sides.new_text if new else sides.old_text
            assert text is not None
            post = load_side(text, sides.new_file if new else sides.old_file,
                             sides.new_path if new else sides.old_path)
            self._posts[key] = post
        return post

    def _commands(self, program: Program) -> list[api.CLCommand]:
        if self._cl is not None and self._cl[0] == program.path:
            return self._cl[1]
        commands = api.read_cl(program.path)
        self._cl = (program.path, commands)
        return commands

    def _output(self, machine: str, new: bool, program: Program,
                commands: list[api.CLCommand]) -> _Output:
        sides = self.machines[machine]
        if (sides.new_text if new else sides.old_text) is None:
            return _Output(missing=True)
        post = self._post(machine, new)
        refused: str | None = None
        try:
            lines = self._posted(post, commands, program)
        except api.CLError as exc:
            return _Output(error=str(exc))
        except api.VerifyError as exc:
            # the program postdsl post would refuse: shown as refused, with the lines that
            # make it wrong in the diff (and its toolpath), never as a plain change
            refused = str(exc)
            lines = api.post_commands(post, commands, cl_file=program.name, now=self.now)
        texts = [line.text for line in lines]
        return _Output(texts, [renumber_key(post, line) for line in lines],
                       api.post_text(post, lines), error=refused,
                       nc=lines if self.plots else [])

    def _posted(self, post: api.CompiledPost, commands: list[api.CLCommand],
                program: Program) -> list[api.NCLine]:
        """The program as ``postdsl post`` writes it: verified where the post has a control
        model, so a post change that makes wrong NC is a refusal here too (VerifyError),
        never a diff a reviewer might approve."""
        if post.machine.control is None or post.machine.resolution is None:
            return api.post_commands(post, commands, cl_file=program.name, now=self.now)
        lines: list[api.NCLine] = []
        verdict = api.verify_commands(post, commands, cl_file=program.name, now=self.now,
                                      written=lines)
        if verdict.divergence is not None:
            raise api.VerifyError(f"{verdict.divergence} (the NC program does not do what "
                                  f"the CL says)")
        return lines

    def __call__(self, pair: tuple[str, Program]) -> ProgramDiff:
        machine, program = pair
        sides = self.machines[machine]
        if sides.same:
            return ProgramDiff(machine, program.name, UNCHANGED, posted=False)
        try:
            commands = self._commands(program)
            old = self._output(machine, False, program, commands)
            new = self._output(machine, True, program, commands)
        except PostdslError as exc:
            return ProgramDiff(machine, program.name, ERROR, old_error=str(exc),
                               new_error=str(exc))
        except Exception as exc:  # a bug in postdsl: one pair must not hide the whole review
            message = (f"{program.name}: postdsl failed posting it with {machine} (a bug, "
                       f"please report it): {type(exc).__name__}: {exc}")
            return ProgramDiff(machine, program.name, ERROR, old_error=message,
                               new_error=message)
        diff = compare_outputs(machine, program.name, old, new, old_label=self.labels[0],
                               new_label=self.labels[1], context=self.context)
        if self.plots and (diff.status == CHANGED or (diff.status == NOW_FAILS and new.nc)):
            try:
                diff.motion = compare_motion(self._post(machine, False), old.nc,
                                             self._post(machine, True), new.nc,
                                             f"{machine}: {program.name}")
            except PostdslError as exc:
                diff.notes.append(f"the motion cannot be compared: {exc}")
        return diff


_WORKER: _Poster | None = None


def _init_worker(machines: Mapping[str, _MachineSides], now: datetime,
                 labels: tuple[str, str], context: int, plots: bool) -> None:
    global _WORKER
    _WORKER = _Poster(machines, now, labels, context, plots)


def _work(pair: tuple[str, Program]) -> ProgramDiff:
    assert _WORKER is not None
    return _WORKER(pair)


Progress = Callable[[int, int], None]


def _post_pairs(machines: Mapping[str, _MachineSides], pairs: Sequence[tuple[str, Program]],
                *, jobs: int, now: datetime, labels: tuple[str, str], context: int,
                progress: Progress | None, plots: bool = False) -> list[ProgramDiff]:
    """Post every pair, over ``jobs`` processes (in this process when 1); results in order."""
    total = len(pairs)
    results: list[ProgramDiff] = []
    if progress is not None:
        progress(0, total)
    jobs = max(1, min(jobs, total))
    if jobs == 1:
        poster = _Poster(machines, now, labels, context, plots)
        outputs: Iterator[ProgramDiff] | map[ProgramDiff] = map(poster, pairs)
        return _collect(outputs, total, progress, results)
    # Chunks keep the pairs of one program together (its CL is read once per worker)
    # while still giving each worker several chunks to balance uneven programs.
    chunksize = max(1, total // (jobs * 8))
    with ProcessPoolExecutor(max_workers=jobs, initializer=_init_worker,
                             initargs=(machines, now, labels, context, plots)) as pool:
        return _collect(pool.map(_work, pairs, chunksize=chunksize), total, progress, results)


def _collect(outputs: Iterable[ProgramDiff], total: int, progress: Progress | None,
             results: list[ProgramDiff]) -> list[ProgramDiff]:
    for result in outputs:
        results.append(result)
        if progress is not None:
            progress(len(results), total)
    return results


# --- git -------------------------------------------------------------------------------------


def _git(root: Path, *args: str) -> subprocess.CompletedProcess[bytes]:
    try:
        return subprocess.run(["git", *args], cwd=root, capture_output=True, check=False)
    except OSError as exc:
        raise ReviewError(f"cannot run git: {exc}") from None


def repo_root(start: Path) -> Path:
    """The top of the git working tree containing ``start``."""
    done = _git(start, "rev-parse", "--show-toplevel")
    if done.returncode != 0:
        raise ReviewError(f"{start}: not inside a git repository "
                          f"({_git_message(done)})")
    return Path(done.stdout.decode().strip())


def resolve_commit(root: Path, rev: str) -> str:
    """``rev`` -> the full commit id, or a ReviewError naming the revision."""
    if not rev or rev.startswith("-"):
        raise ReviewError(f"'{rev}' is not a revision")
    done = _git(root, "rev-parse", "--verify", "--quiet", f"{rev}^{{commit}}")
    if done.returncode != 0:
        raise ReviewError(f"unknown revision '{rev}' (a commit, branch or tag of "
                          f"{root})")
    return done.stdout.decode().strip()


def _file_at(root: Path, commit: str, relpath: str) -> bytes | None:
    """A file's content at a commit, or None when it does not exist there."""
    spec = f"{commit}:{relpath}"
    if _git(root, "cat-file", "-e", spec).returncode != 0:
        return None
    done = _git(root, "cat-file", "blob", spec)
    if done.returncode != 0:
        raise ReviewError(f"cannot read {relpath} at {commit[:12]}: {_git_message(done)}")
    return done.stdout


def _files_at(root: Path, commit: str, folder: str) -> list[str]:
    done = _git(root, "ls-tree", "--name-only", f"{commit}", "--", f"{folder}/")
    if done.returncode != 0:
        raise ReviewError(f"cannot list {folder}/ at {commit[:12]}: {_git_message(done)}")
    return done.stdout.decode("utf-8", "replace").splitlines()


def _git_message(done: subprocess.CompletedProcess[bytes]) -> str:
    return done.stderr.decode("utf-8", "replace").strip() or f"git exit {done.returncode}"


# --- corpus ----------------------------------------------------------------------------------


def _display(path: Path, root: Path) -> str:
    try:
        return path.resolve().relative_to(root.resolve()).as_posix()
    except ValueError:
        return str(path)


def load_corpus_file(corpus_file: Path, root: Path) -> dict[str, list[Program]]:
    """corpus.yaml: machine name -> its CL programs (paths relative to the file)."""
    try:
        text = corpus_file.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ReviewError(f"cannot read the corpus: {exc}", Location(str(corpus_file))) \
            from None
    try:
        data = YAML(typ="rt").load(text)
    except YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = Location(str(corpus_file), mark.line + 1, mark.column + 1) if mark else \
            Location(str(corpus_file))
        raise ReviewError(f"not valid YAML: {getattr(exc, 'problem', None) or exc}",
                          where) from None
    if data is None:
        return {}
    if not isinstance(data, Mapping):
        raise ReviewError("the corpus must map machine names to lists of CL files",
                          Location(str(corpus_file), 1))
    corpus: dict[str, list[Program]] = {}
    for machine, paths in data.items():
        line = data.lc.key(machine)[0] + 1 if hasattr(data, "lc") else None
        if not isinstance(machine, str) or not _MACHINE_NAME.fullmatch(machine):
            raise ReviewError("a corpus key must be a machine's name (letters, digits, '.', "
                              "'_', '-')", Location(str(corpus_file), line))
        if not isinstance(paths, list) or not all(isinstance(p, str) for p in paths):
            raise ReviewError(f"'{machine}': expected a list of CL file paths",
                              Location(str(corpus_file), line))
        programs = []
        for index, given in enumerate(paths):
            where = Location(str(corpus_file), _item_line(paths, index, line))
            path = _inside(corpus_file.parent, given, root, where)
            programs.append(Program(_display(path, root), path))
        corpus[machine] = programs
    return corpus


#: what a corpus key may be: the stem of a file in machines/
_MACHINE_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]*")


def _item_line(items: Any, index: int, fallback: int | None) -> int | None:
    try:
        return int(items.lc.item(index)[0]) + 1
    except (AttributeError, KeyError, TypeError):
        return fallback


def _inside(folder: Path, given: str, root: Path, where: Location) -> Path:
    """A corpus path, refused unless it names a file inside the repository.

    corpus.yaml comes with a pull request, and the review runs in CI with whatever
    that machine can read: an absolute path, ``..`` or a symbolic link out of the
    repository would post (and quote) files that are none of the pull request's.
    """
    if not given.isprintable() or not given.strip():
        raise ReviewError("a corpus path must be printable text", where)
    relative = Path(given)
    if relative.is_absolute() or ".." in relative.parts:
        raise ReviewError("corpus paths are relative to corpus.yaml and stay inside the "
                          "repository (no absolute paths, no '..')", where)
    path = folder / relative
    try:
        path.resolve().relative_to(root.resolve())
    except ValueError:
        raise ReviewError("the corpus path is a symbolic link (or lies in a linked folder) "
                          "leading outside the repository", where) from None
    return path


def corpus_for_machine(machine: str | Path, root: Path | None = None) -> list[Program]:
    """The programs corpus.yaml lists for ``machine`` (a name or a post path), for editors.

    corpus.yaml is looked for in ``root``, else in the folders above the post
    file, else at the top of the current git repository; no corpus found
    means no programs (an installed postdsl has none), not an error.
    """
    candidates: list[Path] = []
    if root is not None:
        candidates.append(root)
    else:
        given = Path(machine)
        if given.suffix in (".yaml", ".yml") and given.exists():
            candidates += given.resolve().parents
        with contextlib.suppress(ReviewError):  # not in a repository: no corpus there
            candidates.append(repo_root(Path.cwd()))
    for folder in candidates:
        corpus_file = folder / "corpus.yaml"
        if corpus_file.is_file():
            return load_corpus_file(corpus_file, folder).get(Path(machine).stem, [])
    return []


def corpus_from_paths(paths: Iterable[str | Path], root: Path) -> list[Program]:
    """Every CL file in the given folders (recursively; hidden, docs and YAML skipped)."""
    programs: list[Program] = []
    for given in paths:
        path = Path(given)
        if path.is_file():
            files = [path]
        elif path.is_dir():
            files = sorted(
                p for p in path.rglob("*")
                if p.is_file() and p.suffix.lower() not in _NOT_CL
                and not any(part.startswith(".") for part in p.relative_to(path).parts))
            for file in files:
                try:
                    file.resolve().relative_to(path.resolve())
                except ValueError:
                    raise ReviewError(f"a symbolic link leading outside {given}: the review "
                                      f"reads only the folder's own files",
                                      Location(str(file))) from None
        else:
            raise ReviewError("no such CL file or folder", Location(str(given)))
        programs += [Program(_display(p, root), p) for p in files]
    return programs


# --- machines --------------------------------------------------------------------------------


def _machine_file(root: Path, machine: str, commit: str) -> tuple[str, str]:
    """A --machine argument -> (its display name, its path relative to the repository)."""
    given = Path(machine)
    if given.suffix in (".yaml", ".yml") or os.sep in machine or "/" in machine:
        absolute = given if given.is_absolute() else Path.cwd() / given
        try:
            relative = absolute.resolve().relative_to(root.resolve()).as_posix()
        except ValueError:
            raise ReviewError("the machine file is outside the repository, so git has no "
                              "old version of it", Location(machine)) from None
        return given.stem, relative
    for suffix in (".yaml", ".yml"):
        relative = f"machines/{machine}{suffix}"
        if (root / relative).is_file() or _file_at(root, commit, relative) is not None:
            return machine, relative
    raise ReviewError(f"unknown machine '{machine}': no machines/{machine}.yaml in the "
                      f"working tree or at {commit[:12]}")


def _all_machines(root: Path, commit: str) -> list[str]:
    names = {p.stem for p in (root / "machines").glob("*.y*ml")}
    names |= {Path(p).stem for p in _files_at(root, commit, "machines")
              if p.endswith((".yaml", ".yml"))}
    return sorted(names)


def _read_sides(root: Path, commit: str, against: str, relpath: str,
                old_copy: Path | None = None) -> tuple[_MachineSides, list[str]]:
    """Both versions of a machine file, and the errors that make them unusable.

    A post that ``extends:`` another is read as ``postdsl post`` reads it: the working
    tree's from its own path, the revision's from a copy of its chain at the revision
    under ``old_copy`` (same paths relative to the repository), so its base is found
    the same way on both sides, from whatever folder the review runs in.
    """
    errors: list[str] = []
    old_bytes = _file_at(root, commit, relpath)
    old_text = new_text = None
    if old_bytes is not None:
        try:
            old_text = old_bytes.decode("utf-8")
        except UnicodeDecodeError as exc:
            errors.append(f"{against}:{relpath}: not UTF-8 text ({exc.reason})")
    new_path = root / relpath
    if new_path.exists():
        try:
            new_text = new_path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            errors.append(f"{relpath}: cannot read the post: {exc}")
    if old_bytes is None and not new_path.exists():
        errors.append(f"{relpath}: no such machine file in the working tree or at {against}")
    old_path: Path | None = None
    old_bases: tuple[str, ...] = ()
    if old_text is not None and old_copy is not None:
        old_path, old_bases = _chain_at(root, commit, relpath, old_text, old_copy)
    new_bases = _bases_now(new_path, new_text) if new_text is not None else ()
    sides = _MachineSides(old_text, new_text, f"{against}:{relpath}", relpath,
                          old_path, new_path if new_text is not None else None,
                          old_bases, new_bases)
    for text, file, path in ((old_text, sides.old_file, sides.old_path),
                             (new_text, sides.new_file, sides.new_path)):
        if text is None or sides.same:
            continue
        try:
            load_side(text, file, path)
        except api.PostError as exc:
            errors.append(exc.report())
    return sides, errors


def _extends_name(text: str, file: str) -> str | None:
    from postdsl.lang.loader import parse_yaml
    from postdsl.lang.post.extends import extends_of

    try:
        return extends_of(parse_yaml(text, file))
    except PostdslError:
        return None  # the post itself is broken: loading it says where


def _bases_now(path: Path, text: str) -> tuple[str, ...]:
    """The texts of the working-tree post's bases, nearest first."""
    from postdsl.lang.loader import parse_yaml, read_source
    from postdsl.lang.post.extends import ExtendsError, chain_of
    from postdsl.resources import machines_dir

    if _extends_name(text, str(path)) is None:
        return ()
    try:
        chain = chain_of(path, str(path), parse_yaml(text, str(path)), read_source,
                         machines_dir())
    except (ExtendsError, PostdslError):
        return ()  # loading the post reports it, located
    return tuple(source.text for source in chain)


def _chain_at(root: Path, commit: str, relpath: str, text: str, copy: Path
              ) -> tuple[Path, tuple[str, ...]]:
    """Write the post at ``relpath`` and the bases it names by path, as they are at
    ``commit``, under ``copy``; its path there and the bases' texts.  A base named as a
    bundled post (``extends: BASE``) is the installed one, on both sides."""
    from postdsl.lang.post.extends import base_file
    from postdsl.resources import machines_dir

    target = copy / relpath
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(text, encoding="utf-8")
    bases: list[str] = []
    current, current_text, seen = relpath, text, {relpath}
    while (name := _extends_name(current_text, current)) is not None and len(seen) < 32:
        pathlike = Path(name).suffix in (".yaml", ".yml") or "/" in name or "\\" in name
        if not pathlike or Path(name).is_absolute():
            found = base_file(name, copy / current, machines_dir())
            if found is None:
                break
            bases.append(found.read_text(encoding="utf-8", errors="replace"))
            current, current_text = found.as_posix(), bases[-1]
            if not pathlike:
                break  # the installed post's own bases are the installed ones
            continue
        relative = os.path.normpath(os.path.join(os.path.dirname(current), name))
        relative = Path(relative).as_posix()
        data = _file_at(root, commit, relative) if not relative.startswith("..") else None
        if data is None or relative in seen:
            break  # loading the copy reports the missing base (or the loop), located
        seen.add(relative)
        current, current_text = relative, data.decode("utf-8", errors="replace")
        (copy / relative).parent.mkdir(parents=True, exist_ok=True)
        (copy / relative).write_text(current_text, encoding="utf-8")
        bases.append(current_text)
    return target, tuple(bases)


# --- the review ------------------------------------------------------------------------------


def review(start: Path | None = None, *, against: str = "HEAD",
           machines: Sequence[str] = (), corpora: Sequence[str | Path] = (),
           jobs: int | None = None, context: int = 3,
           progress: Progress | None = None, plots: bool = False) -> ReviewResult:
    """Post the corpus with each machine file at ``against`` and in the working tree.

    ``start`` is any folder inside the repository (default: the current one).
    Without ``corpora`` the programs are those corpus.yaml lists for each
    machine; with them, every machine posts every CL file found there.  With
    ``plots`` each changed program is also replayed through the control model on
    both sides (``ProgramDiff.motion``, see review_plots).  Raises ReviewError
    when the review cannot run at all; problems of single machines or programs
    are collected in the result.
    """
    root = repo_root(start or Path.cwd())
    commit = resolve_commit(root, against)
    result = ReviewResult(against, commit)
    now = review_time()
    if corpora:
        programs = corpus_from_paths(corpora, root)
        names = list(machines) or _all_machines(root, commit)
        plan = {name: programs for name in names}
    else:
        corpus_file = root / "corpus.yaml"
        if not corpus_file.is_file():
            raise ReviewError("no corpus.yaml at the top of the repository; name the CL "
                              "programs with --corpus DIR", Location(str(corpus_file)))
        corpus = load_corpus_file(corpus_file, root)
        if machines:
            plan = {}
            for name in machines:
                _machine_file(root, name, commit)  # an unknown machine is that, first
                key = Path(name).stem
                if key not in corpus:
                    raise ReviewError(f"corpus.yaml lists no programs for '{key}' (add them "
                                      f"there, or give --corpus DIR)",
                                      Location(str(corpus_file)))
                plan[name] = corpus[key]
        else:
            plan = dict(corpus)
            unlisted = sorted(set(_all_machines(root, commit)) - set(corpus))
            result.warnings += [f"machines/{name}: corpus.yaml lists no programs for it; "
                                f"not reviewed" for name in unlisted]
    with tempfile.TemporaryDirectory(prefix="postdsl-review-") as old_copy:
        sides: dict[str, _MachineSides] = {}
        pairs: list[tuple[str, Program]] = []
        for name, programs in plan.items():
            display, relpath = _machine_file(root, name, commit)
            machine_sides, errors = _read_sides(root, commit, against, relpath,
                                                Path(old_copy))
            if errors:
                result.errors += errors
                continue
            sides[display] = machine_sides
            pairs += [(display, program) for program in programs]
        pairs.sort(key=lambda pair: (pair[1].name, pair[0]))
        diffs = _post_pairs(sides, pairs, jobs=jobs or os.cpu_count() or 1, now=now,
                            labels=(against, WORKING_TREE), context=context,
                            progress=progress, plots=plots)
    result.programs = sorted(diffs, key=lambda d: (d.machine, d.program))
    for diff in result.programs:
        if diff.status == ERROR:
            result.errors.append(diff.old_error or f"{diff.program}: cannot be read")
    result.errors = list(dict.fromkeys(result.errors))
    return result


def review_texts(saved: str, unsaved: str, corpus: Sequence[Program | str | Path], *,
                 machine: str = "post", file: str = "<post>", jobs: int = 1,
                 context: int = 3, saved_label: str = "saved",
                 unsaved_label: str = "unsaved", path: Path | None = None
                 ) -> list[ProgramDiff]:
    """The NC diffs an editor's unsaved changes cause, before anything is saved.

    ``saved`` and ``unsaved`` are the post's YAML texts; ``corpus`` the CL
    programs (see :func:`corpus_for_machine`).  Raises PostError when either
    text is not a valid post, CLError when a CL file cannot be read.  One
    process by default: an editor reviews a machine's few programs, and
    forking a process that runs a UI thread is best avoided.
    """
    programs = [p if isinstance(p, Program) else Program(str(p), Path(p)) for p in corpus]
    # ``path``: where the post is read from, so an ``extends:`` finds its base (the same
    # base on both sides: the editor changes this file only)
    sides = _MachineSides(saved, unsaved, f"{file} ({saved_label})", file, path, path)
    for text, name in ((saved, sides.old_file), (unsaved, sides.new_file)):
        load_side(text, name, path)
    diffs = _post_pairs({machine: sides}, [(machine, p) for p in programs], jobs=jobs,
                        now=review_time(), labels=(saved_label, unsaved_label),
                        context=context, progress=None)
    for diff in diffs:
        if diff.status == ERROR:
            raise api.CLError(diff.old_error or f"{diff.program}: cannot be read")
    return diffs


# --- output ----------------------------------------------------------------------------------


def _counts(program: ProgramDiff) -> str:
    return f"+{program.added} -{program.removed}"


def headline(program: ProgramDiff) -> str:
    """One line saying what happened to a program: "+3 -3 lines", "renumbering only (…)"."""
    status = program.status
    if status == RENUMBERED:
        text = f"renumbering only ({program.renumbered} block numbers"
        if program.renumber_example:
            old, new = program.renumber_example
            text += f"; first: '{old}' -> '{new}'"
        return text + ")"
    if status == UNPOSTABLE:
        if program.old_error == program.new_error:
            return f"cannot be posted by either version: {program.new_error}"
        return (f"cannot be posted by either version: before: {program.old_error}; "
                f"now: {program.new_error}")
    if status == ERROR:
        return f"error: {program.old_error}"
    if status == NOW_FAILS:
        return f"cannot be posted any more: {program.new_error}"
    if status == NOW_POSTS:
        return f"can be posted now ({program.added} lines; before: {program.old_error})"
    if status == ADDED:
        if program.new_error:
            return f"new machine file, which cannot post it: {program.new_error}"
        return f"new machine file: {program.added} lines added"
    if status == REMOVED:
        if program.old_error:
            return f"machine file removed (it could not post this: {program.old_error})"
        return f"machine file removed: {program.removed} lines removed"
    if status == CHANGED:
        text = f"{_counts(program)} lines"
        if program.renumbered:
            text += f"; block numbers also changed on {program.renumbered} other lines"
        return "; ".join([text, *program.notes])
    return "unchanged"


def _summary_line(result: ReviewResult) -> str:
    s = result.summary()
    parts = [f"{s['changed_programs'] - s[RENUMBERED]} changed (+{s['added_lines']} "
             f"-{s['removed_lines']} lines)"]
    if s[RENUMBERED]:
        parts.append(f"{s[RENUMBERED]} renumbering only")
    parts.append(f"{s[UNCHANGED]} unchanged")
    if s[UNPOSTABLE]:
        parts.append(f"{s[UNPOSTABLE]} cannot be posted by either version")
    if s["errors"]:
        parts.append(_plural(s["errors"], "error"))
    return (f"postdsl review against {result.against} ({result.commit[:12]}): "
            f"{_plural(s['programs'], 'program')} on {_plural(s['machines'], 'machine')}: "
            + ", ".join(parts))


def _plural(count: int, noun: str) -> str:
    return f"{count} {noun}" if count == 1 else f"{count} {noun}s"


def _noteworthy(result: ReviewResult) -> list[ProgramDiff]:
    return [p for p in result.programs if p.status != UNCHANGED]


def render_text(result: ReviewResult) -> str:
    """For a terminal: each changed program's headline and diff, then the summary.

    Errors are only counted: print ``result.errors`` to stderr beside it.
    """
    out: list[str] = []
    for program in _noteworthy(result):
        # names and messages come from files: escaped, no terminal escape sequence runs
        out.append(printable(f"{program.machine}  {program.program}: {headline(program)}"))
        out.extend(printable(line) for line in program.diff)
        if program.diff:
            out.append("")
    # errors are not repeated here: the CLI writes them to stderr, where CI logs show them
    out.extend(printable(f"warning: {w}") for w in result.warnings)
    out.append(printable(_summary_line(result)))
    return "\n".join(out) + "\n"


# Markdown meant for a pull-request comment shows names (machines, paths) that come with
# the pull request, so none of them may turn into a link, a mention, an image, HTML or
# formatting; and no error message is quoted there, only where it is and what kind it is:
# messages quote the input (a CL record), which may hold anything, secrets included.

#: characters that mean something in Markdown: written with a backslash
_MD_PUNCTUATION = re.compile(r"([\\`*_\[\]()!|~])")
#: where an autolink, a mention or an issue reference would start
_MD_TRIGGERS = re.compile(r"(@|#|://|www\.)", re.IGNORECASE)
#: ``file:line:`` or ``file:line:column:`` at the start of a located message
_SITE = re.compile(r"^(?P<at>[^\n]*?:\d+(?::\d+)?): ")


def _md_cell(text: str) -> str:
    """Plain text in a Markdown table cell (or line): shown as it is, never interpreted."""
    return _untriggered(_MD_PUNCTUATION.sub(r"\\\1", _entities(text)))


def _html(text: str) -> str:
    """Text inside HTML (a ``<summary>``): entities for markup, nothing that links."""
    return _untriggered(_entities(text))


def _entities(text: str) -> str:
    text = "".join(c if c.isprintable() else " " for c in text)
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def _untriggered(text: str) -> str:
    # a zero-width space keeps @team, #12, http:// and www. from becoming mentions or links
    return _MD_TRIGGERS.sub(lambda m: m.group(1)[0] + "\u200b" + m.group(1)[1:], text)


def _md_code(text: str) -> str:
    """Text as a code span in a table cell: literal, whatever backticks it holds.

    A table splits its cells before it reads code spans, and takes a backslash before a
    pipe as an escape even there, so a name with a pipe is written as escaped text.
    """
    if "|" in text:
        return _md_cell(text)
    text = "".join(c if c.isprintable() else " " for c in text)
    fence = "`" * (max((len(run) for run in re.findall("`+", text)), default=0) + 1)
    padded = f" {text} " if text.startswith("`") or text.endswith("`") else text
    return f"{fence}{padded}{fence}"


def _md_error(message: str | None, kind: str) -> str:
    """An error for Markdown: its kind and where it is, never the message itself."""
    match = _SITE.match(message or "")
    if match is None:
        return f"{kind} (run postdsl review for the message)"
    return f"{kind} at {match.group('at')} (run postdsl review for the message)"


def _md_headline(program: ProgramDiff) -> str:
    """:func:`headline`, with every error message replaced by where and what it is."""
    status = program.status
    if status == ERROR:
        return _md_error(program.old_error, "error: the CL program cannot be read or posted")
    if status == UNPOSTABLE:
        return _md_error(program.new_error, "cannot be posted by either version")
    if status == NOW_FAILS:
        return _md_error(program.new_error, "cannot be posted any more")
    if status == NOW_POSTS:
        return f"can be posted now ({program.added} lines; before: " + \
            _md_error(program.old_error, "error") + ")"
    if status == ADDED and program.new_error:
        return _md_error(program.new_error, "new machine file, which cannot post it")
    if status == REMOVED and program.old_error:
        return _md_error(program.old_error, "machine file removed (it could not post this)")
    return headline(program)


def _fence(lines: Sequence[str]) -> str:
    longest = 0
    for line in lines:
        run = 0
        for char in line:
            run = run + 1 if char == "`" else 0
            longest = max(longest, run)
    return "`" * max(3, longest + 1)


def render_markdown(result: ReviewResult, max_diff_lines: int = 400,
                    plots: Mapping[tuple[str, str], PlotFiles] | None = None) -> str:
    """For a pull-request comment: a table of changed programs and folded diffs.

    Each diff is cut after ``max_diff_lines`` lines (hosts limit comment
    size); the counts in the table stay exact.  ``plots`` links each program
    whose motion changed to its before/after pictures (``review_plots``).
    """
    s = result.summary()
    out = [f"### postdsl review: {s['changed_programs']} of {s['programs']} programs change "
           f"(+{s['added_lines']} −{s['removed_lines']} lines)", "",
           f"Posted with each machine file at {_md_code(result.against)} "
           f"(`{result.commit[:12]}`) and in the {_md_cell(result.new_label)}.", ""]
    noteworthy = _noteworthy(result)
    if noteworthy:
        out += ["| machine | program | change |", "|---|---|---|"]
        out += [f"| {_md_cell(p.machine)} | {_md_code(p.program)} | "
                f"{_md_cell(_md_headline(p))} |" for p in noteworthy]
        out.append("")
    for program in noteworthy:
        if not program.diff:
            continue
        shown = program.diff[:max_diff_lines]
        fence = _fence(shown)
        out += [f"<details><summary>{_html(program.machine)} · "
                f"{_html(program.program)} ({_counts(program)})</summary>", "",
                *_md_motion(program, plots), f"{fence}diff", *shown, fence]
        if len(program.diff) > len(shown):
            out.append(f"… {len(program.diff) - len(shown)} more diff lines "
                       f"(run `postdsl review` locally)")
        out += ["", "</details>", ""]
    for warning in result.warnings:
        out.append(f"> warning: {_md_cell(warning)}")
    for error in result.errors:
        for line in error.splitlines():
            out.append(f"> **error:** {_md_cell(_md_error(line, 'error'))}")
    if result.warnings or result.errors:
        out.append("")
    out.append(_md_cell(_summary_line(result)))
    return "\n".join(out) + "\n"




def _md_motion(program: ProgramDiff,
               plots: Mapping[tuple[str, str], PlotFiles] | None) -> list[str]:
    """The toolpath before and after, or that the moves stay the same (when replayed)."""
    if program.motion is None:
        return []
    if not program.motion.changed:
        return ["The toolpath is unchanged: the control model replays the same moves.", ""]
    files = (plots or {}).get((program.machine, program.program))
    if files is None:
        return ["**The toolpath changes.**", ""]
    return ["**The toolpath changes:**", "",
            "| before | after |", "|---|---|",
            f"| ![before]({quote(files.before)}) | ![after]({quote(files.after)}) |", ""]


def motion_pictures(result: ReviewResult) -> list[tuple[str, str, str, str]]:
    """(machine, program, before SVG, after SVG) of every program whose motion changed."""
    return [(p.machine, p.program, p.motion.before, p.motion.after) for p in result.programs
            if p.motion is not None and p.motion.changed and p.motion.before is not None
            and p.motion.after is not None]


def render_json(result: ReviewResult) -> str:
    """For scripts: every pair (unchanged ones too), the summary and the errors."""
    document = {
        "against": result.against, "commit": result.commit, "new": result.new_label,
        "exit_status": result.exit_status, "summary": result.summary(),
        "programs": [p.to_json() for p in result.programs],
        "errors": result.errors, "warnings": result.warnings,
    }
    return json.dumps(document, indent=2, ensure_ascii=False) + "\n"


def render(result: ReviewResult, fmt: str = "text") -> str:
    renderers: dict[str, Callable[[ReviewResult], str]] = {
        "text": render_text, "markdown": render_markdown, "json": render_json}
    return renderers[fmt](result)


def terminal_progress(label: str = "posting") -> tuple[Progress | None, Callable[[], None]]:
    """A progress callback drawing a bar on stderr, when stderr is a terminal (else None).

    Returns the callback and a function that finishes the bar; CI logs and
    pipes get neither, so they stay clean.
    """
    if not sys.stderr.isatty():
        return None, lambda: None
    import click

    state: dict[str, Any] = {}

    def update(done: int, total: int) -> None:
        bar = state.get("bar")
        if bar is None:
            bar = click.progressbar(length=total, label=label, file=sys.stderr,
                                    show_pos=True)
            bar.__enter__()
            state["bar"] = bar
            state["done"] = 0
        bar.update(done - state["done"])
        state["done"] = done

    def finish() -> None:
        bar = state.pop("bar", None)
        if bar is not None:
            bar.__exit__(None, None, None)

    return update, finish
