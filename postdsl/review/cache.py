"""The result cache: a program's review, kept by what it depends on, between runs.

Re-running a review after a small change posts only the pairs the change reaches: an
entry's name is a hash of both versions of the post (bases included), the CL program's
bytes, the review's settings and postdsl's own code (``codecache.environment``), so an
entry is found only for exactly the same inputs and can never be stale.  It holds the
verdict, the counts and the diff lines a report shows.  Each posting is kept too, by
one version of the post and the CL program, as the digest of its NC text: after a
change of the working tree's post, a program whose new posting has the digest the old
posting had is unchanged, and the old post is not run again.

Entries are data, not code, but a forged entry could hide a motion change, so they are
kept and trusted as the code cache's are (``postdsl.codecache``): a folder private to
the user under the user's cache directory (``$POSTDSL_CACHE_DIR``, empty: no cache),
entries written 0600 and read only when they are the user's regular files, writable by
no one else, with their key and a hash of their content checked.
"""

from __future__ import annotations

import functools
import json
from pathlib import Path

from postdsl import codecache
from postdsl.review.results import ProgramDiff

_MAGIC = b"postdsl-review-1\n"


@functools.cache
def _version() -> str:
    return codecache.environment()




def folder() -> Path | None:
    base = codecache.cache_dir()
    return None if base is None else base / "review"


def _entry(key: str) -> Path | None:
    base = folder()
    return None if base is None else base / f"{key}.review"


def key_prefix() -> str:
    """What every key starts from: the entry format and postdsl's code."""
    return f"review-1:{_version()}"


def read(key: str) -> ProgramDiff | None:
    """The cached result for ``key``, or None (missing, untrusted, torn, another format)."""
    entry = _entry(key)
    if entry is None:
        return None
    payload = codecache.read_entry(entry, _MAGIC, key)
    if payload is None:
        return None
    try:
        found = ProgramDiff.from_json(json.loads(payload))
    except (ValueError, KeyError, TypeError, IndexError):
        return None
    found.cached = True
    return found


def write(key: str, result: ProgramDiff) -> None:
    """Keep ``result`` under ``key``; quietly nothing when the folder cannot be written."""
    entry = _entry(key)
    if entry is not None:
        codecache.write_entry(entry, _MAGIC, key,
                              json.dumps(result.to_json(), ensure_ascii=False).encode("utf-8"))


# --- one side: (post version x CL program) -> the NC text's digest --------------------------


def read_side(key: str) -> tuple[str, str | None] | None:
    """(digest of the NC text, the refusal or None) of one posting, or None."""
    entry = _entry(key)
    if entry is None:
        return None
    payload = codecache.read_entry(entry, _SIDE_MAGIC, key)
    if payload is None:
        return None
    try:
        digest, error = json.loads(payload)
    except (ValueError, TypeError):
        return None
    if not isinstance(digest, str) or not (error is None or isinstance(error, str)):
        return None
    return digest, error


def write_side(key: str, digest: str, error: str | None) -> None:
    entry = _entry(key)
    if entry is not None:
        codecache.write_entry(entry, _SIDE_MAGIC, key, json.dumps([digest, error]).encode())


_SIDE_MAGIC = b"postdsl-review-side-1\n"
