"""The repository a review reads: git run in a subprocess, files read at a commit.

Machine files are read with ``git cat-file`` at the revision, never checked out, so
the working tree the reviewer edits is left alone.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

from postdsl.review.results import ReviewError


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
                          f"({git_message(done)})")
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


def file_at(root: Path, commit: str, relpath: str) -> bytes | None:
    """A file's content at a commit, or None when it does not exist there."""
    spec = f"{commit}:{relpath}"
    if _git(root, "cat-file", "-e", spec).returncode != 0:
        return None
    done = _git(root, "cat-file", "blob", spec)
    if done.returncode != 0:
        raise ReviewError(f"cannot read {relpath} at {commit[:12]}: {git_message(done)}")
    return done.stdout


def files_at(root: Path, commit: str, folder: str) -> list[str]:
    done = _git(root, "ls-tree", "--name-only", f"{commit}", "--", f"{folder}/")
    if done.returncode != 0:
        raise ReviewError(f"cannot list {folder}/ at {commit[:12]}: {git_message(done)}")
    return done.stdout.decode("utf-8", "replace").splitlines()


def git_message(done: subprocess.CompletedProcess[bytes]) -> str:
    return done.stderr.decode("utf-8", "replace").strip() or f"git exit {done.returncode}"

