"""The code base stays ruff clean: the linter is part of the test run."""

from __future__ import annotations

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
