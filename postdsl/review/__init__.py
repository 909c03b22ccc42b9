"""Review a post change by its effect: per program, does anything that moves change?

A post edit is reviewed like code, but the YAML diff alone does not say what reaches
the machine: one changed format touches every coordinate of every program.  A review
posts a corpus of CL programs with each machine file as it is at a git revision (read
with ``git cat-file``, no checkout) and as it is in the working tree, and gives each
program a verdict — ``unchanged``, ``renumbering only``, ``format only`` (the text
changed, the control model replays the same motion), ``motion changed`` (located),
``newly refused``, ``newly posting`` — with the NC diff behind it.

The package, top to bottom (every import points down): ``runner`` (a review from
start to end) · ``report`` (the reports) · ``executors`` (this process, a process
pool, a Dask cluster) · ``posting`` (the per-program function) · ``cache`` (results
between runs), ``verdicts`` (both postings replayed), ``compare`` (the diff, aligned by
CL record), ``plots`` (before/after pictures) · ``machines`` (both versions of each
post), ``corpus`` (the CL programs) · ``gitrepo`` · ``results`` (what a review finds).
Posting goes through :mod:`postdsl.api` only, like every other tool.
"""

from postdsl.review.compare import Output as _Output
from postdsl.review.compare import compare_outputs, renumber_key
from postdsl.review.corpus import (
    Program,
    corpus_for_machine,
    corpus_from_paths,
    load_corpus_file,
)
from postdsl.review.gitrepo import repo_root, resolve_commit
from postdsl.review.machines import load_side
from postdsl.review.posting import FIXED_TIME, review_time
from postdsl.review.report import (
    FORMATS,
    headline,
    motion_pictures,
    render,
    render_json,
    render_markdown,
    render_text,
    terminal_progress,
    write_report,
)
from postdsl.review.results import (
    ADDED,
    CHANGE_STATUSES,
    CHANGED,
    ERROR,
    EXIT_ERROR,
    EXIT_FORMAT_ONLY,
    EXIT_MOTION,
    EXIT_UNCHANGED,
    FORMAT_ONLY,
    MOTION,
    NEWLY_POSTING,
    NEWLY_REFUSED,
    NOW_FAILS,
    NOW_POSTS,
    REMOVED,
    RENUMBERED,
    RENUMBERING,
    UNCHANGED,
    UNPOSTABLE,
    VERDICTS,
    WORKING_TREE,
    MotionDifference,
    ProgramDiff,
    ReviewError,
    ReviewResult,
)
from postdsl.review.runner import review, review_texts

__all__ = [
    "ADDED", "CHANGED", "CHANGE_STATUSES", "ERROR", "EXIT_ERROR", "EXIT_FORMAT_ONLY",
    "EXIT_MOTION", "EXIT_UNCHANGED", "FIXED_TIME", "FORMATS", "FORMAT_ONLY", "MOTION",
    "NEWLY_POSTING", "NEWLY_REFUSED", "NOW_FAILS", "NOW_POSTS", "REMOVED", "RENUMBERED",
    "RENUMBERING", "UNCHANGED", "UNPOSTABLE", "VERDICTS", "WORKING_TREE", "MotionDifference",
    "Program", "ProgramDiff", "ReviewError", "ReviewResult", "_Output", "compare_outputs",
    "corpus_for_machine", "corpus_from_paths", "headline", "load_corpus_file", "load_side",
    "motion_pictures", "render", "render_json", "render_markdown", "render_text",
    "renumber_key", "repo_root", "resolve_commit", "review", "review_texts", "review_time",
    "terminal_progress", "write_report",
]
