"""Cache entries are trusted as Python trusts its bytecode cache, and no further (issue 25).

Code entries are executed: whoever can put a file at an entry's name could shift every
coordinate of every later program.  So an entry is read only when it is a regular file
of the user's that no one else may write; anything else at its name is ignored without
blocking or reading without bound, and replaced by a rename.  The key changes with
postdsl's code (``__version__`` never did) and with the libraries a checked post depends
on.
"""

from __future__ import annotations

import contextlib
import hashlib
import marshal
import os
import signal
import stat
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from postdsl import api, codecache
from postdsl.compile import postcache
from tests.conftest import EXAMPLES

posix = pytest.mark.skipif(os.name != "posix", reason="FIFOs, owners and modes")

#: the generated text every test compiles; an attacker's entry holds other code for it
SOURCE = "value = 1\n"


@pytest.fixture()
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    folder = tmp_path / "home" / "cache"
    monkeypatch.setenv(codecache.CACHE_VARIABLE, str(folder))
    return folder


class Blocked(Exception):
    """Not an OSError (TimeoutError is one): the cache must not take it for a bad read."""


@contextlib.contextmanager
def within(seconds: int) -> Iterator[None]:
    """Fail, instead of hanging the run, if the block blocks (a FIFO opened for reading)."""
    def expired(signum: int, frame: object) -> None:
        raise Blocked(f"blocked for {seconds} s")

    previous = signal.signal(signal.SIGALRM, expired)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def entry_of(cache: Path) -> Path:
    return cache / f"{codecache.source_key(SOURCE)}.code"


def forged(cache: Path) -> Path:
    """A well-formed entry for SOURCE holding other code (``value = 666``): what someone
    who can write the folder would put there; the header's SHA-256 is right."""
    payload = marshal.dumps(compile("value = 666\n", "<postdsl generated post>", "exec"))
    key = codecache.source_key(SOURCE)
    entry = entry_of(cache)
    entry.parent.mkdir(parents=True, exist_ok=True)
    entry.write_bytes(b"postdsl-code-1\n" + key.encode() + b"\n"
                      + hashlib.sha256(payload).hexdigest().encode() + b"\n" + payload)
    return entry


def value_of(code: object) -> object:
    namespace: dict[str, object] = {}
    exec(code, namespace)  # the test's own SOURCE, or the forged entry's
    return namespace["value"]


def assert_rewritten(entry: Path) -> None:
    """The entry is now a regular file of ours, private, holding SOURCE's code."""
    info = entry.lstat()
    assert stat.S_ISREG(info.st_mode)
    assert stat.S_IMODE(info.st_mode) == 0o600
    assert value_of(codecache.compiled_code(SOURCE)) == 1


@posix
def test_the_folder_is_created_private_to_the_user(cache: Path) -> None:
    codecache.compiled_code(SOURCE)
    assert stat.S_IMODE(cache.stat().st_mode) == 0o700
    assert stat.S_IMODE(entry_of(cache).stat().st_mode) == 0o600


@posix
def test_an_own_private_entry_is_used(cache: Path) -> None:
    """The control for the tests below: a sound entry of the user's is what runs."""
    entry = forged(cache)
    entry.chmod(0o600)
    assert value_of(codecache.compiled_code(SOURCE)) == 666


@posix
@pytest.mark.parametrize("mode", [0o620, 0o602, 0o666], ids=oct)
def test_an_entry_others_may_write_is_ignored_and_rewritten(cache: Path, mode: int) -> None:
    entry = forged(cache)
    entry.chmod(mode)
    assert value_of(codecache.compiled_code(SOURCE)) == 1
    assert_rewritten(entry)


@posix
def test_an_entry_of_another_user_is_ignored_and_rewritten(
        cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    entry = forged(cache)
    entry.chmod(0o600)
    if os.geteuid() == 0:  # root can give the file away; else postdsl runs as another user
        os.chown(entry, 4242, 4242)
    else:
        monkeypatch.setattr(os, "getuid", lambda: os.stat(entry).st_uid + 1)
    assert value_of(codecache.compiled_code(SOURCE)) == 1
    monkeypatch.undo()
    monkeypatch.setenv(codecache.CACHE_VARIABLE, str(cache))
    assert entry.lstat().st_uid == os.getuid()
    assert_rewritten(entry)


@posix
def test_a_fifo_at_an_entry_name_neither_blocks_nor_stays(cache: Path) -> None:
    cache.mkdir(parents=True)
    entry = entry_of(cache)
    os.mkfifo(entry)
    with within(10):
        assert value_of(codecache.compiled_code(SOURCE)) == 1
    assert_rewritten(entry)


@posix
def test_an_entry_linked_to_dev_zero_is_not_read(cache: Path) -> None:
    cache.mkdir(parents=True)
    entry = entry_of(cache)
    entry.symlink_to("/dev/zero")
    with within(10):
        assert value_of(codecache.compiled_code(SOURCE)) == 1
    assert_rewritten(entry)
    assert Path("/dev/zero").is_char_device()  # the link was replaced, not written through


@posix
def test_an_entry_linked_to_an_own_sound_entry_is_not_followed(cache: Path) -> None:
    """A link can point anywhere, e.g. at a file the user wrote elsewhere: never followed."""
    target = forged(cache).rename(cache.parent / "elsewhere.code")
    target.chmod(0o600)
    entry_of(cache).symlink_to(target)
    assert value_of(codecache.compiled_code(SOURCE)) == 1
    assert_rewritten(entry_of(cache))


@posix
def test_an_entry_larger_than_the_limit_is_not_read(cache: Path) -> None:
    entry = forged(cache)
    entry.chmod(0o600)
    with entry.open("r+b") as stream:  # sparse: no disk, but a size past the limit
        stream.truncate(codecache.ENTRY_LIMIT + 1)
    with within(10):
        assert value_of(codecache.compiled_code(SOURCE)) == 1
    assert_rewritten(entry)


@posix
def test_a_post_entry_others_may_write_is_read_again(cache: Path) -> None:
    """The checked-post entries share the reading (and unpickle only postdsl's model)."""
    post = EXAMPLES.parent / "machines" / "vmc500.yaml"
    api.load_post(post)
    entries = list(cache.glob("*.post"))
    assert len(entries) == 1
    entries[0].chmod(0o646)
    before = entries[0].stat().st_mtime_ns
    assert postcache.load_checked(post).source.text == post.read_text(encoding="utf-8")
    assert stat.S_IMODE(entries[0].stat().st_mode) == 0o600  # rewritten by rename
    assert entries[0].stat().st_mtime_ns >= before


def test_the_key_changes_with_the_code_not_with_version_strings(tmp_path: Path) -> None:
    """A digest of the content: an edit that keeps the size and the time is other code."""
    package = tmp_path / "package"
    (package / "sub").mkdir(parents=True)
    (package / "__init__.py").write_text("__version__ = '0.1.0'\n")
    module = package / "sub" / "engine.py"
    module.write_text("SHIFT = 0.0\n")
    (package / "__pycache__").mkdir()
    before = codecache.code_digest(package)
    (package / "__pycache__" / "engine.cpython-311.pyc").write_bytes(b"not code")
    (package / "notes.txt").write_text("not code either")
    assert codecache.code_digest(package) == before
    info = module.stat()
    module.write_text("SHIFT = 0.1\n")  # same size
    os.utime(module, ns=(info.st_atime_ns, info.st_mtime_ns))  # same time
    assert codecache.code_digest(package) != before


def test_the_key_holds_the_code_the_libraries_and_python() -> None:
    from importlib.metadata import version

    environment = codecache.environment()
    assert codecache.code_digest(Path(codecache.__file__).resolve().parent) in environment
    found = codecache.library_versions()
    for name, spelled in (("ruamel.yaml", "ruamel_yaml-"), ("jsonschema", "jsonschema-")):
        assert f"{spelled}{version(name)}." in found.replace("ruamel.yaml-", "ruamel_yaml-")
    assert found in environment
    assert sys.version in environment


def test_library_versions_read_the_metadata_folders(tmp_path: Path) -> None:
    site = tmp_path / "lib" / "site-packages"
    site.mkdir(parents=True)
    for name in ("ruamel.yaml-0.18.6.dist-info", "jsonschema-4.20.0.dist-info",
                 "ruamel.yaml.clib-0.2.8.dist-info", "click-8.1.7.dist-info",
                 "referencing-0.35.1.dist-info", "jsonschema_specifications-2023.12.1.dist-info"):
        (site / name).mkdir()
    listed = codecache.library_versions([str(site), str(tmp_path)])
    assert [Path(line).name for line in listed.splitlines()] == [
        "jsonschema-4.20.0.dist-info", "jsonschema_specifications-2023.12.1.dist-info",
        "referencing-0.35.1.dist-info", "ruamel.yaml-0.18.6.dist-info"]
    (site / "jsonschema-4.20.0.dist-info").rename(site / "jsonschema-4.21.0.dist-info")
    assert codecache.library_versions([str(site)]) != listed
