"""Keep the compiled code of generated post modules between runs.

Compiling the generated text is most of what turning a post into functions costs,
and a shop posts many programs with one post.  The entry's name is a hash of the
generated text itself (with :func:`environment`: postdsl's code and Python's version),
not of the post file: a post that ``extends`` another, or takes options, generates
other text when anything it depends on changes, so a stale entry can never be found.  An entry
holds the hash again and is checked before use; an unreadable or corrupt entry is
compiled again and rewritten, and a cache directory that cannot be written is simply
not used.  The render functions of number formats (:mod:`postdsl.lang.format_codegen`) are
kept the same way, as ``KEY.format`` entries: a post compiles its formats on every run.

Code entries are executed, so an entry is trusted the way Python trusts its own
bytecode cache, and no further: the folder is created private to the user (0700),
entries are written 0600, and an entry is read only when it is a regular file owned
by the user and writable by nobody else (anyone who could write it could change every
coordinate of every later program).  Anything else at an entry's name -- a FIFO, a
link to ``/dev/zero``, a device, another user's file, a file larger than
:data:`ENTRY_LIMIT` -- is ignored without being read and replaced by the next write
(a rename).  The key (:func:`environment`) covers everything an entry's content
depends on: a digest of postdsl's own source (``__version__`` stays the same through
every change), the versions of the libraries a checked post depends on, and Python's.

The folder has a budget (:data:`CACHE_LIMIT`): a write that takes it past the budget
removes the entries used longest ago (reading an entry marks it used).  Every edit of
a post generates other text, so the editor's previews, a post being tuned, and each
new version of postdsl write new entries; without a budget the folder would only grow.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import marshal
import os
import re
import stat
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from types import CodeType

#: overrides the cache directory; an empty value switches the cache off
CACHE_VARIABLE = "POSTDSL_CACHE_DIR"

#: the folder's budget in bytes; a write past it removes the entries used longest ago,
#: down to three quarters of it (a few hundred posts' entries)
CACHE_LIMIT = 64 * 1024 * 1024
#: an entry larger than this is never read (a post's entries are a few hundred KB): a
#: file that only grows, or claims to, cannot make postdsl hold it in memory
ENTRY_LIMIT = CACHE_LIMIT // 4
#: the names of the entries written here, by postdsl.compile.postcache,
#: postdsl.compile.classcode and the review's result cache (a SHA-256 key and the kind):
#: nothing else is ever removed
ENTRY_NAME = re.compile(r"[0-9a-f]{64}\.(?:code|format|post|classes|review)")
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


#: the libraries whose version can change what a checked post is (postdsl.compile.postcache):
#: the YAML reader and the schema validator with the packages holding its meta-schemas
LIBRARIES = ("ruamel.yaml", "jsonschema", "referencing", "jsonschema-specifications")


def source_key(source: str) -> str:
    """The entry name of a generated module's text."""
    digest = hashlib.sha256()
    for part in (environment(), source):
        digest.update(part.encode("utf-8", "surrogatepass"))
        digest.update(b"\0")
    return digest.hexdigest()


@functools.cache
def environment() -> str:
    """What every entry depends on besides its own input: postdsl's code (a digest of
    its source, :func:`code_digest`), the versions of :data:`LIBRARIES`, and Python's.

    Computed once a process: 2-3 ms of CPU, mostly reading postdsl's ~70 modules (~1 MB;
    SHA-256 of them is 0.5 ms); the library versions come from one listing of each site
    folder, not ``importlib.metadata`` (whose import alone costs 50-100 ms).
    """
    package = Path(__file__).resolve().parent
    return "\n".join((code_digest(package), library_versions(), sys.version,
                      sys.implementation.cache_tag or ""))


def code_digest(package: Path) -> str:
    """SHA-256 of every ``.py`` file of ``package`` (names and contents, sorted).

    The content, not sizes and times: a checkout switched to another commit, or a file
    restored with its old time, is other code.  The packaged data (``_data``) and the
    bytecode caches are not code; the post's own inputs are keyed where they are read.
    """
    digest = hashlib.sha256()
    for folder, subfolders, files in os.walk(package):
        subfolders[:] = sorted(d for d in subfolders if d not in ("__pycache__", "_data"))
        for name in sorted(files):
            if not name.endswith(".py"):
                continue
            path = os.path.join(folder, name)
            try:
                with open(path, "rb") as stream:
                    data = stream.read()
            except OSError:
                data = b"?"
            digest.update(os.path.relpath(path, package).encode("utf-8", "surrogateescape"))
            digest.update(len(data).to_bytes(8, "little"))
            digest.update(data)
    return digest.hexdigest()


def _project(name: str) -> str:
    """A distribution's name as its metadata folder spells it, normalised (PEP 503)."""
    return re.sub(r"[-_.]+", "_", name).lower()


def library_versions(path: list[str] | None = None) -> str:
    """The metadata folders (``NAME-VERSION.dist-info``, ``.egg-info``) of
    :data:`LIBRARIES` in every site folder of ``path`` (default ``sys.path``), in order.

    Only folders named ``site-packages`` or ``dist-packages`` are listed: ``sys.path``
    may start with the current folder, which can hold thousands of files.
    """
    wanted = {_project(name) for name in LIBRARIES}
    found: list[str] = []
    for folder in sys.path if path is None else path:
        if os.path.basename(folder.rstrip("/\\")) not in ("site-packages", "dist-packages"):
            continue
        try:
            names = sorted(os.listdir(folder))
        except OSError:
            continue
        for name in names:
            stem, _, kind = name.rpartition(".")
            if kind in ("dist-info", "egg-info") and _project(stem.partition("-")[0]) in wanted:
                found.append(os.path.join(folder, name))
    return "\n".join(found)


def compiled_code(source: str) -> CodeType:
    """The code of ``source``: from the cache when a sound entry is there, else compiled."""
    return cached_code(source, "code", lambda: compile(source, _FILENAME, "exec"))


def cached_code(source: str, kind: str, make: Callable[[], CodeType]) -> CodeType:
    """The code ``make()`` compiles from ``source``: from the entry ``KEY.kind`` when a
    sound one is there, else made and kept.  One ``kind`` per file name the code is
    compiled under (``code``: a post's module; ``format``: a number format's function,
    see :mod:`postdsl.lang.format_codegen`), so an entry always holds the code ``make`` would."""
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
        value: object = marshal.loads(payload)
        return value
    except (ValueError, EOFError, TypeError):
        return None


def _write(entry: Path, key: str, code: CodeType) -> None:
    write_entry(entry, _MAGIC, key, marshal.dumps(code))


# --- entries: shared with postdsl.compile.postcache (the loaded posts) ---------------------


def trusted(info: os.stat_result) -> bool:
    """Whether a file of this status may be read as an entry: a regular file of this
    user's, writable by no one else, no larger than :data:`ENTRY_LIMIT`."""
    if not stat.S_ISREG(info.st_mode) or info.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
        return False
    if hasattr(os, "getuid") and info.st_uid != os.getuid():
        return False
    return info.st_size <= ENTRY_LIMIT


def _read_trusted(entry: Path) -> bytes | None:
    """The bytes of ``entry`` if it is :func:`trusted`, else None; never blocks.

    The name is looked at first (``lstat``: a FIFO or device is never opened), then
    opened without following a link and without waiting (the name may have been
    replaced since), and the open file is checked again: that check is the one that
    counts.  At most the size it gives is read.
    """
    try:
        if not trusted(os.lstat(entry)):
            return None
        handle = os.open(entry, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0)
                         | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError:
        return None
    try:
        info = os.fstat(handle)
        if not trusted(info):
            return None
        chunks: list[bytes] = []
        left = info.st_size
        while left > 0:
            chunk = os.read(handle, left)
            if not chunk:
                break
            chunks.append(chunk)
            left -= len(chunk)
        # used now: the budget removes the entries used longest ago (a folder we may
        # read but not write keeps its times, and the entry is still good)
        with contextlib.suppress(OSError, NotImplementedError):
            os.utime(handle if os.utime in os.supports_fd else entry)
        return b"".join(chunks)
    except OSError:
        return None
    finally:
        os.close(handle)


def read_entry(entry: Path, magic: bytes, key: str) -> bytes | None:
    """The payload of a sound entry, else None (missing, unreadable, not
    :func:`trusted`, another kind or key, torn or altered: the header holds the key and
    the payload's hash)."""
    data = _read_trusted(entry)
    if data is None:
        return None
    header = magic + key.encode("ascii") + b"\n"
    if not data.startswith(header):
        return None
    check, _, payload = data[len(header):].partition(b"\n")
    if check != hashlib.sha256(payload).hexdigest().encode("ascii"):
        return None  # a torn or altered entry
    return payload


def write_entry(entry: Path, magic: bytes, key: str, payload: bytes) -> None:
    """Write atomically (temporary file, rename); give up quietly if the folder is not ours.

    The rename replaces whatever is at the entry's name (a FIFO, a link, a file not
    :func:`trusted`), never writing through it; the folder is made private to the user
    (0700) and the entry is 0600, as ``mkstemp`` creates it.  An entry too large to be
    read back (:data:`ENTRY_LIMIT`) is not written.
    """
    if len(payload) > ENTRY_LIMIT - 4096:
        return
    try:
        entry.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
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
