"""Shared fixtures: the repository's folders and a fixed posting time."""

from __future__ import annotations

from datetime import UTC, datetime
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
EXAMPLES = ROOT / "examples"
MACHINES = ROOT / "machines"

#: the posting time of the VMC500 thesis program (22.01.2021 4:57:30 UTC)
THESIS_EPOCH = 1611291450
THESIS_TIME = datetime.fromtimestamp(THESIS_EPOCH, tz=UTC)


@pytest.fixture
def thesis_time() -> datetime:
    return THESIS_TIME
