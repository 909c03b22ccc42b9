"""Shared fixtures: the repository's folders and a fixed posting time."""

from __future__ import annotations

import atexit
import os
import shutil
import tempfile
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


# Generated post code and class methods are cached in a folder of this run, not in the
# user's cache.  Set before any test module imports postdsl (the methods of its classes
# are looked up in the cache as they are defined), removed once the run has ended.
if "POSTDSL_CACHE_DIR" not in os.environ:
    _CACHE = tempfile.mkdtemp(prefix="postdsl-test-cache-")
    os.environ["POSTDSL_CACHE_DIR"] = _CACHE
    # registered before postdsl's own exit handler: runs after it (last in, first out)
    atexit.register(shutil.rmtree, _CACHE, True)


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
