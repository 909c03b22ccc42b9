"""Keep the compiled code of generated post modules between runs.

Compiling the generated text is most of what turning a post into functions costs,
and a shop posts many programs with one post.  The entry's name is a hash of the
generated text itself (with the postdsl and Python versions), not of the post file:
a post that ``extends`` another, or takes options, generates other text when
anything it depends on changes, so a stale entry can never be found.  An entry
holds the hash again and is checked before use; an unreadable or corrupt entry is
compiled again and rewritten, and a cache directory that cannot be written is simply
not used.  The render functions of number formats (:mod:`postdsl.format_codegen`) are
kept the same way, as ``KEY.format`` entries: a post compiles its formats on every run.

The folder has a budget (:data:`CACHE_LIMIT`): a write that takes it past the budget
removes the entries used longest ago (reading an entry marks it used).  Every edit of
a post generates other text, so the editor's previews, a post being tuned, and each
new version of postdsl write new entries; without a budget the folder would only grow.
"""

from __future__ import annotations

import contextlib
import hashlib
import marshal
import os
import re
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from types import CodeType

import postdsl

#: overrides the cache directory; an empty value switches the cache off
CACHE_VARIABLE = "POSTDSL_CACHE_DIR"

#: the folder's budget in bytes; a write past it removes the entries used longest ago,
#: down to three quarters of it (a few hundred posts' entries)
CACHE_LIMIT = 64 * 1024 * 1024
#: the names of the entries written here and by postdsl.postcache and postdsl.classcode
#: (a SHA-256 key and the kind): nothing else in the folder is ever removed
ENTRY_NAME = re.compile(r"[0-9a-f]{64}\.(?:code|format|post|classes)")
#: a temporary file left by a write that died is removed once it is this old (seconds)
_STALE_TEMPORARY = 24 * 3600
#: a process checks the budget at its first write and then every this many writes: a
#: command writes a few entries at most, while a long session (the editor previewing
#: each version of a post, a test run with thousands of formats) would otherwise list
#: the folder at every write; it overshoots the budget by this many entries at most
_CHECK_EVERY = 32
_writes = 0

_MAGIC = b"postdsl-code-1\n"
_FILENAME = "<postdsl generated post>"


def cache_dir() -> Path | None:
    """Where entries live: ``$POSTDSL_CACHE_DIR``, else the user's cache directory."""
    override = os.environ.get(CACHE_VARIABLE)
    if override is not None:
        return Path(override) if override.strip() else None
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "postdsl"


def source_key(source: str) -> str:
    """The entry name of a generated module's text."""
    digest = hashlib.sha256()
    for part in (postdsl.__version__, sys.version, source):
        digest.update(part.encode("utf-8", "surrogatepass"))
        digest.update(b"\0")
    return digest.hexdigest()


def compiled_code(source: str) -> CodeType:
    """The code of ``source``: from the cache when a sound entry is there, else compiled."""
    return cached_code(source, "code", lambda: compile(source, _FILENAME, "exec"))


def cached_code(source: str, kind: str, make: Callable[[], CodeType]) -> CodeType:
    """The code ``make()`` compiles from ``source``: from the entry ``KEY.kind`` when a
    sound one is there, else made and kept.  One ``kind`` per file name the code is
    compiled under (``code``: a post's module; ``format``: a number format's function,
    see :mod:`postdsl.format_codegen`), so an entry always holds the code ``make`` would."""
    key = source_key(source)
    folder = cache_dir()
    entry = folder / f"{key}.{kind}" if folder is not None else None
    if entry is not None:
        code = _read(entry, key)
        if code is not None:
            return code
    code = make()
    if entry is not None:
        _write(entry, key, code)
    return code


def _read(entry: Path, key: str) -> CodeType | None:
    code = read_marshalled(entry, _MAGIC, key)
    return code if isinstance(code, CodeType) else None


def read_marshalled(entry: Path, magic: bytes, key: str) -> object | None:
    """The value of a sound entry written with ``marshal``, else None (see
    :func:`read_entry`; a payload ``marshal`` cannot load is no entry either)."""
    payload = read_entry(entry, magic, key)
    if payload is None:
        return None
    try:
        return marshal.loads(payload)
    except (ValueError, EOFError, TypeError):
        return None


def _write(entry: Path, key: str, code: CodeType) -> None:
    write_entry(entry, _MAGIC, key, marshal.dumps(code))


# --- entries: shared with postdsl.postcache (the loaded posts) ---------------------------------


def read_entry(entry: Path, magic: bytes, key: str) -> bytes | None:
    """The payload of a sound entry, else None (missing, unreadable, another kind or key,
    torn or altered: the header holds the key and the payload's hash)."""
    try:
        data = entry.read_bytes()
    except OSError:
        return None
    header = magic + key.encode("ascii") + b"\n"
    if not data.startswith(header):
        return None
    check, _, payload = data[len(header):].partition(b"\n")
    if check != hashlib.sha256(payload).hexdigest().encode("ascii"):
        return None  # a torn or altered entry
    # used now: the budget removes the entries used longest ago (a folder we may read
    # but not write keeps its times, and the entry is still good)
    with contextlib.suppress(OSError):
        os.utime(entry)
    return payload


def write_entry(entry: Path, magic: bytes, key: str, payload: bytes) -> None:
    """Write atomically (temporary file, rename); give up quietly if the folder is not ours."""
    try:
        entry.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=entry.parent, prefix=".tmp-")
        try:
            with os.fdopen(handle, "wb") as stream:
                stream.write(magic + key.encode("ascii") + b"\n" +
                             hashlib.sha256(payload).hexdigest().encode("ascii") + b"\n" +
                             payload)
            os.replace(temporary, entry)
        except BaseException:
            os.unlink(temporary)
            raise
    except OSError:
        return
    global _writes
    if _writes % _CHECK_EVERY == 0:
        keep_within_budget(entry.parent, keep=entry.name)
    _writes += 1


def keep_within_budget(folder: Path, keep: str = "") -> None:
    """Past :data:`CACHE_LIMIT` bytes of entries, remove the entries used longest ago
    down to three quarters of it (never the entry named ``keep``, the one just
    written), and temporary files a dead write left.

    Writes are rare (a post, a format or a version not seen before) and only some of
    them list the folder (:data:`_CHECK_EVERY`), so this costs nothing a run notices.
    Another process may remove the same entries at the same time: whatever is already
    gone is skipped.
    """
    budget = CACHE_LIMIT
    entries: list[tuple[int, int, str]] = []
    total = 0
    stale = time.time() - _STALE_TEMPORARY
    try:
        with os.scandir(folder) as listing:
            items = list(listing)
    except OSError:
        return
    for item in items:
        name = item.name
        temporary = name.startswith(".tmp-")
        if not temporary and ENTRY_NAME.fullmatch(name) is None:
            continue
        try:
            if not item.is_file(follow_symlinks=False):
                continue
            info = item.stat(follow_symlinks=False)
        except OSError:  # gone since the listing
            continue
        if temporary:
            if info.st_mtime < stale:
                _remove(item.path)
            continue
        total += info.st_size
        if name == keep:
            continue
        entries.append((info.st_mtime_ns, info.st_size, item.path))
    if total <= budget:
        return
    entries.sort()  # used longest ago first
    for _used, size, path in entries:
        if total <= budget * 3 // 4:
            break
        if _remove(path):
            total -= size


def _remove(path: str) -> bool:
    """Remove a file; True when it is gone (also when another process removed it)."""
    try:
        os.unlink(path)
    except FileNotFoundError:
        return True
    except OSError:
        return False
    return True
