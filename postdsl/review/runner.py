"""A review from start to end: which machines, which programs, run where, collected how.

:func:`review` compares the posts at a git revision with the working tree's, over a
corpus; :func:`review_texts` compares an editor's saved and unsaved texts of one post.
Both hand (machine, program) jobs to an executor and collect what comes back into a
:class:`ReviewResult`, one result at a time: with ``spool=True`` each program's diff
lines wait for the report in a temporary file, so a review of a whole archive holds
only a verdict line per program.
"""

from __future__ import annotations

import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from postdsl import api
from postdsl.errors import Location
from postdsl.review.corpus import Program, corpus_from_paths, load_corpus_file
from postdsl.review.executors import run
from postdsl.review.gitrepo import repo_root, resolve_commit
from postdsl.review.machines import (
    MachineSides,
    all_machines,
    load_side,
    machine_file,
    read_sides,
)
from postdsl.review.posting import Job, Settings, review_time
from postdsl.review.results import (
    ERROR,
    WORKING_TREE,
    DiffStore,
    ProgramDiff,
    Progress,
    ReviewError,
    ReviewResult,
)


def _plan(root: Path, commit: str, machines: Sequence[str], corpora: Sequence[str | Path],
          result: ReviewResult) -> dict[str, list[Program]]:
    """Machine name -> the programs to post with it."""
    if corpora:
        programs = corpus_from_paths(corpora, root)
        names = list(machines) or all_machines(root, commit)
        return {name: programs for name in names}
    corpus_file = root / "corpus.yaml"
    if not corpus_file.is_file():
        raise ReviewError("no corpus.yaml at the top of the repository; name the CL "
                          "programs with --corpus DIR", Location(str(corpus_file)))
    corpus = load_corpus_file(corpus_file, root)
    if machines:
        plan = {}
        for name in machines:
            machine_file(root, name, commit)  # an unknown machine is that, first
            key = Path(name).stem
            if key not in corpus:
                raise ReviewError(f"corpus.yaml lists no programs for '{key}' (add them "
                                  f"there, or give --corpus DIR)", Location(str(corpus_file)))
            plan[name] = corpus[key]
        return plan
    unlisted = sorted(set(all_machines(root, commit)) - set(corpus))
    result.warnings += [f"machines/{name}: corpus.yaml lists no programs for it; "
                        f"not reviewed" for name in unlisted]
    return dict(corpus)


def review(start: Path | None = None, *, against: str = "HEAD",
           machines: Sequence[str] = (), corpora: Sequence[str | Path] = (),
           jobs: int | None = None, context: int = 3,
           progress: Progress | None = None, plots: bool = False,
           executor: str = "local", scheduler: Any = None, spool: bool = False,
           use_cache: bool = True, diff_limit: int | None = None) -> ReviewResult:
    """Post the corpus with each machine file at ``against`` and in the working tree.

    ``start`` is any folder inside the repository (default: the current one).
    Without ``corpora`` the programs are those corpus.yaml lists for each
    machine; with them, every machine posts every CL file found there.  With
    ``plots`` each program whose motion changed is also drawn on both sides
    (``ProgramDiff.motion``, see :mod:`postdsl.review.plots`).  ``executor``:
    ``local`` (a process pool of ``jobs`` processes) or ``dask`` (the cluster at
    ``scheduler``).  ``diff_limit``: the diff lines kept per program (None: all).
    Raises ReviewError when the review cannot run at all; problems of single
    machines or programs are collected in the result.
    """
    root = repo_root(start or Path.cwd())
    commit = resolve_commit(root, against)
    result = ReviewResult(against, commit, store=DiffStore(spool))
    plan = _plan(root, commit, machines, corpora, result)
    settings = Settings(review_time(), (against, WORKING_TREE), context, plots, diff_limit,
                        use_cache)
    with tempfile.TemporaryDirectory(prefix="postdsl-review-") as old_copy:
        sides: dict[str, MachineSides] = {}
        work: list[Job] = []
        for name, programs in plan.items():
            display, relpath = machine_file(root, name, commit)
            machine_sides, errors = read_sides(root, commit, against, relpath, Path(old_copy))
            if errors:
                result.errors += errors
                continue
            sides[display] = machine_sides
            work += [Job(display, program.name, program.path) for program in programs]
        work.sort(key=lambda job: (job.program, job.machine))
        for diff in run(sides, work, settings, executor=executor, workers=jobs,
                        scheduler=scheduler, progress=progress):
            _collect(result, diff)
    result.programs.sort(key=lambda d: (d.machine, d.program))
    result.errors = list(dict.fromkeys(result.errors))
    return result


def _collect(result: ReviewResult, diff: ProgramDiff) -> None:
    if diff.status == ERROR:
        result.errors.append(diff.old_error or f"{diff.program}: cannot be read")
    result.store.put(diff)
    result.programs.append(diff)


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
    sides = MachineSides(saved, unsaved, f"{file} ({saved_label})", file, path, path)
    for text, name in ((saved, sides.old_file), (unsaved, sides.new_file)):
        load_side(text, name, path)
    settings = Settings(review_time(), (saved_label, unsaved_label), context, limit=None,
                        use_cache=False)
    diffs = list(run({machine: sides}, [Job(machine, p.name, p.path) for p in programs],
                     settings, workers=jobs))
    for diff in diffs:
        if diff.status == ERROR:
            raise api.CLError(diff.old_error or f"{diff.program}: cannot be read")
    return diffs
