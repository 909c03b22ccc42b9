"""The per-program function: post one CL program with both versions of a post, compare.

Every executor (the local process pool, a Dask cluster) runs this same function on
(machine, program) jobs.  What crosses to a worker is text — both versions of each
post and, for a cluster, the CL program's bytes — since compiled posts are closures
and cannot be pickled; what comes back is a :class:`ProgramDiff`: the verdict, the
counts and the diff lines a report shows, never whole programs.

A program one machine cannot post (an unknown command, a move outside the travel) is
a finding about that pair, not a failure of the review; only what stops the review
from being trustworthy — an unreadable CL file, a bug — is an ``error`` (exit 2).
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Mapping
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path

from postdsl import api
from postdsl.errors import PostdslError
from postdsl.review import cache
from postdsl.review.compare import DIFF_LIMIT, Output, compare_outputs, renumber_key
from postdsl.review.machines import MachineSides, load_side
from postdsl.review.plots import compare_motion
from postdsl.review.results import (
    CHANGED,
    ERROR,
    FORMAT_ONLY,
    MOTION,
    NOT_REPLAYED,
    NOW_FAILS,
    UNCHANGED,
    ProgramDiff,
)
from postdsl.review.verdicts import first_motion_difference

#: the posting time when SOURCE_DATE_EPOCH is not set; any constant will do
FIXED_TIME = datetime(2000, 1, 1, tzinfo=UTC)


def review_time() -> datetime:
    """The posting time of a review: SOURCE_DATE_EPOCH when set, else a constant."""
    if os.environ.get("SOURCE_DATE_EPOCH"):
        return api.posting_time()
    return FIXED_TIME


@dataclass(frozen=True)
class Settings:
    """What every job of a review shares besides the posts."""

    now: datetime
    labels: tuple[str, str]
    context: int = 3
    plots: bool = False
    #: the diff lines sent back per program (None: all)
    limit: int | None = DIFF_LIMIT
    #: look results up in (and write them to) the result cache
    use_cache: bool = True

    def signature(self) -> str:
        return repr((self.now.isoformat(), self.labels, self.context, self.limit))


@dataclass(frozen=True)
class Job:
    """One (machine, program) pair: the program by path, or by content (a cluster)."""

    machine: str
    program: str
    path: Path | None = None
    content: bytes | None = None


class Poster:
    """Runs jobs; one per worker process, keeping the compiled posts of both sides."""

    def __init__(self, machines: Mapping[str, MachineSides], settings: Settings) -> None:
        self.machines = machines
        self.settings = settings
        self._posts: dict[tuple[str, bool], api.CompiledPost] = {}

    def post(self, machine: str, new: bool) -> api.CompiledPost:
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

    def _commands(self, job: Job, content: bytes | None) -> list[api.CLCommand]:
        if content is not None:
            try:
                return api.read_cl_text(content.decode("utf-8"), job.program)
            except UnicodeDecodeError:
                pass  # read as postdsl post reads a file (its own decoding rules)
        if job.path is None:
            raise api.CLError("not UTF-8 text", api.Location(job.program))
        return api.read_cl(job.path)

    def _output(self, machine: str, new: bool, job: Job, commands: list[api.CLCommand]
                ) -> tuple[Output, list[api.NCLine]]:
        sides = self.machines[machine]
        if (sides.new_text if new else sides.old_text) is None:
            return Output(missing=True), []
        post = self.post(machine, new)
        refused: str | None = None
        try:
            lines = self._posted(post, commands, job.program)
        except api.CLError as exc:
            return Output(error=str(exc)), []
        except api.VerifyError as exc:
            # the program postdsl post would refuse: shown as refused, with the lines that
            # make it wrong in the diff (and its toolpath), never as a plain change
            refused = str(exc)
            lines = api.post_commands(post, commands, cl_file=job.program,
                                      now=self.settings.now)
        return Output([line.text for line in lines], [renumber_key(post, line) for line in lines],
                      api.post_text(post, lines), error=refused,
                      records=[line.cl_line for line in lines]), lines

    def _posted(self, post: api.CompiledPost, commands: list[api.CLCommand],
                program: str) -> list[api.NCLine]:
        """The program as ``postdsl post`` writes it: verified where the post has a control
        model, so a post change that makes wrong NC is a refusal here too (VerifyError),
        never a diff a reviewer might approve."""
        now = self.settings.now
        if post.machine.control is None or post.machine.resolution is None:
            return api.post_commands(post, commands, cl_file=program, now=now)
        lines: list[api.NCLine] = []
        verdict = api.verify_commands(post, commands, cl_file=program, now=now, written=lines)
        if verdict.divergence is not None:
            raise api.VerifyError(f"{verdict.divergence} (the NC program does not do what "
                                  f"the CL says)")
        return lines

    def _cache_key(self, job: Job, content: bytes, side: bool | None = None) -> str:
        """The pair's key, or with ``side`` one posting's (False: the old post's)."""
        sides = self.machines[job.machine]
        parts = (sides.digest(False), sides.digest(True), sides.old_file, sides.new_file) \
            if side is None else ("side", sides.digest(side),
                                  sides.new_file if side else sides.old_file)
        digest = hashlib.sha256()
        for part in (cache.key_prefix(), *parts, job.machine, job.program,
                     self.settings.signature()):
            digest.update(part.encode("utf-8", "surrogatepass") + b"\0")
        digest.update(hashlib.sha256(content).digest())
        return digest.hexdigest()

    def _unchanged_by_digest(self, job: Job, content: bytes | None, new: Output) -> bool:
        """Whether the old posting, as kept, had the new one's text (so it need not run);
        the new posting is kept for the next review either way."""
        if not self.settings.use_cache or content is None or new.missing:
            return False
        digest = hashlib.sha256(new.text.encode("utf-8", "surrogatepass")).hexdigest()
        cache.write_side(self._cache_key(job, content, True), digest, new.error)
        old = cache.read_side(self._cache_key(job, content, False))
        return old is not None and new.error is None and old == (digest, None)

    def _keep_old(self, job: Job, content: bytes | None, old: Output) -> None:
        if self.settings.use_cache and content is not None and not old.missing:
            digest = hashlib.sha256(old.text.encode("utf-8", "surrogatepass")).hexdigest()
            cache.write_side(self._cache_key(job, content, False), digest, old.error)

    def __call__(self, job: Job) -> ProgramDiff:
        machine = job.machine
        sides = self.machines[machine]
        if sides.same:
            return ProgramDiff(machine, job.program, UNCHANGED, posted=False)
        try:
            content = job.content
            if content is None and job.path is not None:
                content = job.path.read_bytes()
        except OSError as exc:
            return _error(job, f"{job.program}: cannot read CL file: {exc.strerror or exc}")
        key = None
        if self.settings.use_cache and not self.settings.plots and content is not None:
            key = self._cache_key(job, content)
            found = cache.read(key)
            if found is not None:
                return found
        try:
            result = self._compare(job, content)
        except PostdslError as exc:
            return _error(job, str(exc))
        except Exception as exc:  # a bug in postdsl: one pair must not hide the whole review
            return _error(job, f"{job.program}: postdsl failed posting it with {machine} (a "
                               f"bug, please report it): {type(exc).__name__}: {exc}")
        if key is not None and result.status != ERROR:
            cache.write(key, result)
        return result

    def _compare(self, job: Job, content: bytes | None) -> ProgramDiff:
        machine = job.machine
        commands = self._commands(job, content)
        new, new_lines = self._output(machine, True, job, commands)
        if self._unchanged_by_digest(job, content, new):
            return ProgramDiff(machine, job.program, UNCHANGED, old_count=len(new.lines),
                               new_count=len(new.lines))
        old, old_lines = self._output(machine, False, job, commands)
        self._keep_old(job, content, old)
        settings = self.settings
        diff = compare_outputs(machine, job.program, old, new, old_label=settings.labels[0],
                               new_label=settings.labels[1], context=settings.context,
                               limit=settings.limit)
        del old, new
        if diff.status == CHANGED and not diff.notes:
            old_post, new_post = self.post(machine, False), self.post(machine, True)
            if old_post.machine.control is None or new_post.machine.control is None:
                diff.verdict = NOT_REPLAYED
            else:
                diff.motion_at = first_motion_difference(old_post, old_lines, new_post,
                                                         new_lines)
                diff.verdict = MOTION if diff.motion_at is not None else FORMAT_ONLY
        elif diff.status == CHANGED:
            diff.verdict = FORMAT_ONLY  # the same lines: a line ending or final newline
        if settings.plots and (diff.verdict == MOTION or (diff.status == NOW_FAILS
                               and new_lines)):
            try:
                diff.motion = compare_motion(self.post(machine, False), old_lines,
                                             self.post(machine, True), new_lines,
                                             f"{machine}: {job.program}")
            except PostdslError as exc:
                diff.notes.append(f"the motion cannot be compared: {exc}")
        return diff


def _error(job: Job, message: str) -> ProgramDiff:
    return ProgramDiff(job.machine, job.program, ERROR, old_error=message, new_error=message)
