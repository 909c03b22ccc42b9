"""The cache folder stays within its budget: the entries used longest ago go first.

Every edit of a post generates another module, so the editor's previews, a post
being tuned and each new postdsl version write new entries; the budget
(``codecache.CACHE_LIMIT``) is what keeps the folder from only growing.  Reading an
entry marks it used; nothing but postdsl's own entries (and temporary files a dead
write left) is ever removed.
"""

from __future__ import annotations

import hashlib
import os
from datetime import datetime
from pathlib import Path

import pytest

from postdsl import api, codecache
from postdsl.run.engine import Engine

MAGIC = b"postdsl-test-1\n"


@pytest.fixture()
def folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    cache = tmp_path / "cache"
    monkeypatch.setenv(codecache.CACHE_VARIABLE, str(cache))
    monkeypatch.setattr(codecache, "_CHECK_EVERY", 1)  # every write checks the budget
    return cache


def _key(number: int) -> str:
    return hashlib.sha256(str(number).encode()).hexdigest()


def _write(folder: Path, number: int, used: float) -> Path:
    """An entry of 1 000 bytes of payload, last used at ``used`` (seconds)."""
    entry = folder / f"{_key(number)}.code"
    codecache.write_entry(entry, MAGIC, _key(number), bytes(1000))
    os.utime(entry, (used, used))
    return entry


def _kept(folder: Path) -> set[int]:
    names = {path.name for path in folder.iterdir()}
    return {number for number in range(100) if f"{_key(number)}.code" in names}


def test_a_write_past_the_budget_removes_the_entries_used_longest_ago(
        folder: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    entries = [_write(folder, number, 1_000_000 + number) for number in range(10)]
    size = entries[0].stat().st_size
    monkeypatch.setattr(codecache, "CACHE_LIMIT", 10 * size)
    assert _kept(folder) == set(range(10))  # within the budget: nothing goes
    # reading the oldest entry marks it used now
    assert codecache.read_entry(entries[0], MAGIC, _key(0)) == bytes(1000)
    _write(folder, 10, 2_000_000_000)
    # eleven entries: down to three quarters of ten, the least recently used first
    assert _kept(folder) == {0, 5, 6, 7, 8, 9, 10}


def test_nothing_but_entries_is_removed(folder: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    folder.mkdir()
    others = [folder / "notes.txt", folder / "abc.code", folder / f"{_key(1).upper()}.code",
              folder / f"{_key(2)}.code.bak"]
    for other in others:
        other.write_bytes(bytes(5000))
        os.utime(other, (1, 1))
    (folder / f"{_key(3)}.post").mkdir()  # a folder with an entry's name
    monkeypatch.setattr(codecache, "CACHE_LIMIT", 1)  # less than any entry
    _write(folder, 4, 1_000_000)
    _write(folder, 5, 2_000_000)
    assert _kept(folder) == {5}  # the older entry went; the one just written stays
    assert all(other.exists() for other in others)
    assert (folder / f"{_key(3)}.post").is_dir()


def test_a_dead_writes_temporary_file_goes_once_it_is_a_day_old(folder: Path) -> None:
    folder.mkdir()
    old, fresh = folder / ".tmp-old", folder / ".tmp-fresh"
    for temporary in (old, fresh):
        temporary.write_bytes(b"half an entry")
    os.utime(old, (1, 1))
    _write(folder, 1, 1_000_000)
    assert not old.exists() and fresh.exists() and _kept(folder) == {1}


def test_entries_another_process_removed_meanwhile_are_skipped(
        folder: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    for number in range(6):
        _write(folder, number, 1_000_000 + number)
    real = os.unlink
    gone: list[str] = []

    def racing(path: str) -> None:
        real(path)
        if not gone:  # the first removal finds it already gone
            gone.append(path)
            raise FileNotFoundError(path)

    monkeypatch.setattr(codecache.os, "unlink", racing)
    monkeypatch.setattr(codecache, "CACHE_LIMIT", 4 * 1100)
    _write(folder, 6, 2_000_000_000)
    assert gone and len(_kept(folder)) <= 3 and 6 in _kept(folder)


POST = """\
postdsl: 1
machine: {{name: budget}}
output: {{block_numbers: {{default: false}}}}
formats:
  coord: {{decimals: 3}}
commands:
  program_end:
    blocks: [{{items: [" M{end}"]}}]
  rapid_move:
    blocks:
      - items: [{{text: G0, modal: motion, mode: changed}},
                {{param: x, prefix: " X", format: coord, mode: changed}}]
"""


def test_an_editing_session_keeps_the_folder_within_the_budget(
        folder: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The editor previews each version of the post it edits: each is a new module."""
    def preview(end: int) -> None:
        post = api.load_post_text(POST.format(end=end), "budget.yaml")
        Engine(post, now=datetime(2026, 1, 1))  # compiles the post's module

    preview(0)
    size = sum(path.stat().st_size for path in folder.iterdir())
    budget = 5 * size
    monkeypatch.setattr(codecache, "CACHE_LIMIT", budget)
    for end in range(1, 40):
        preview(end)
        assert sum(path.stat().st_size for path in folder.iterdir()) <= budget
    assert len(list(folder.glob("*.code"))) >= 2  # the latest versions are kept


def test_a_long_session_lists_the_folder_once_every_so_many_writes(
        folder: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The editor or a test run writes thousands of entries: listing the folder at each
    write made the writes quadratic in the folder's size."""
    monkeypatch.setattr(codecache, "_CHECK_EVERY", 8)
    monkeypatch.setattr(codecache, "_writes", 0)
    listed: list[Path] = []
    real = codecache.keep_within_budget

    def counting(where: Path, keep: str = "") -> None:
        listed.append(where)
        real(where, keep)

    monkeypatch.setattr(codecache, "keep_within_budget", counting)
    for number in range(20):
        _write(folder, number, 1_000_000 + number)
    assert len(listed) == 3  # the first write, the 9th and the 17th
