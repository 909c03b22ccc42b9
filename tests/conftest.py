"""Shared fixtures: the repository's folders and a fixed posting time."""

from __future__ import annotations

import os
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
EXAMPLES = ROOT / "examples"
MACHINES = ROOT / "machines"

#: the posting time of the VMC500 thesis program (22.01.2021 4:57:30 UTC)
THESIS_EPOCH = 1611291450
THESIS_TIME = datetime.fromtimestamp(THESIS_EPOCH, tz=UTC)


@pytest.fixture(autouse=True, scope="session")
def _code_cache(tmp_path_factory: pytest.TempPathFactory) -> Iterator[None]:
    """Generated post code is cached in a folder of this run, not in the user's cache."""
    if "POSTDSL_CACHE_DIR" in os.environ:
        yield
        return
    os.environ["POSTDSL_CACHE_DIR"] = str(tmp_path_factory.mktemp("code-cache"))
    try:
        yield
    finally:
        del os.environ["POSTDSL_CACHE_DIR"]


@pytest.fixture
def thesis_time() -> datetime:
    return THESIS_TIME


# Hypothesis profiles: "ci" (the default) keeps every property and fuzz test to a fixed
# seed and example budget, so the suite is repeatable and fast; "long" is for fuzzing
# runs by hand: `pytest -m fuzz --hypothesis-profile=long`.
settings.register_profile("ci", derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("long", max_examples=20_000, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("ci")
