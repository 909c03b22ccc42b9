"""The code base stays ruff and mypy clean: both linters are part of the test run."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import ROOT


def test_ruff_is_clean() -> None:
    # the ruff installed with the project (pinned by pyproject), not whatever is on PATH
    beside = Path(sys.executable).with_name("ruff")
    ruff = str(beside) if beside.exists() else (shutil.which("ruff") or str(beside))
    if not Path(ruff).exists():
        pytest.skip("ruff is not installed (pip install -e '.[test]' installs it)")
    result = subprocess.run([ruff, "check", "postdsl", "tui", "tests", "benchmarks"],
                            cwd=ROOT, capture_output=True, text=True, check=False)
    assert result.returncode == 0, result.stdout + result.stderr


def test_mypy_is_clean() -> None:
    """mypy --strict reports nothing on postdsl/ and tui/ (``[tool.mypy]`` in pyproject).

    Run here, beside ruff, so the README's test command and CI enforce it: a type error
    or a ``# type: ignore`` that no longer silences anything (``warn_unused_ignores``,
    part of strict) or names no error code fails the suite, not a later reader.
    """
    # the mypy installed with the project (pinned by pyproject), not whatever is on PATH
    beside = Path(sys.executable).with_name("mypy")
    mypy = str(beside) if beside.exists() else (shutil.which("mypy") or str(beside))
    if not Path(mypy).exists():
        pytest.skip("mypy is not installed (pip install -e '.[test]' installs it)")
    # the files and the strictness come from pyproject.toml; the cache stays in the
    # checkout (.mypy_cache), so a rerun checks only what changed
    result = subprocess.run([mypy], cwd=ROOT, capture_output=True, text=True, check=False)
    assert result.returncode == 0, result.stdout + result.stderr


def test_every_type_ignore_says_why() -> None:
    """A ``# type: ignore[code]`` is a claim mypy cannot check (a value is not None here,
    a tuple is a PlainMove there): it names its error code (mypy's ignore-without-code
    enforces that) and says why, after it on its line or on the comment line above it."""
    ignore = re.compile(r"#\s*type:\s*ignore(\[[^\]]*\])?")
    unexplained = []
    for path in sorted([*(ROOT / "postdsl").rglob("*.py"), *(ROOT / "tui").rglob("*.py")]):
        lines = path.read_text(encoding="utf-8").splitlines()
        for number, line in enumerate(lines, start=1):
            found = ignore.search(line)
            if found is None:
                continue
            after = line[found.end():].strip()
            above = lines[number - 2].strip() if number > 1 else ""
            if not found.group(1) or not ((after.startswith("#") and after.strip("# "))
                                          or above.startswith("#")):
                unexplained.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert not unexplained, "type: ignore without a code or a reason:\n" + "\n".join(unexplained)
