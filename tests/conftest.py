"""Shared fixtures: the repository's folders and a fixed posting time."""

from __future__ import annotations

import atexit
import functools
import os
import shutil
import tempfile
from collections.abc import Mapping
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

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
# Under pytest-xdist this runs in the controller first, and the workers it starts inherit
# the variable: all of them share one folder (each compiled every post and format again
# in a folder of its own), and only the controller, which outlives them, removes it.
if "POSTDSL_CACHE_DIR" not in os.environ:
    _CACHE = tempfile.mkdtemp(prefix="postdsl-test-cache-")
    os.environ["POSTDSL_CACHE_DIR"] = _CACHE
    # registered before postdsl's own exit handler: runs after it (last in, first out)
    atexit.register(shutil.rmtree, _CACHE, True)

# imported only now that POSTDSL_CACHE_DIR is set; bound here, so a test may route
# api.load_post itself through compiled_post (monkeypatch) without recursion
from postdsl.api import load_post as _load_post  # noqa: E402

#: the editor's tests: each drives the whole Textual app in real time through a pilot
#: (5-18 s a test, mostly waiting on its event loop); 82 of them took 5 min 45 s of a
#: -n 2 run, two thirds of the README's test command.  They are "slow": CI's second step.
EDITOR_TESTS = ROOT / "tests" / "tui"


@pytest.hookimpl(tryfirst=True)  # before -m deselects by marker
def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    slow = pytest.mark.slow
    for item in items:
        if EDITOR_TESTS in item.path.parents:
            item.add_marker(slow)


@pytest.fixture
def thesis_time() -> datetime:
    return THESIS_TIME


def compiled_post(machine: str | Path, options: Mapping[str, Any] | None = None) -> Any:
    """``api.load_post(machine, options)``, compiled once per test process (session-scoped).

    Loading a post (the cached check, then generating and compiling its module) takes
    20-300 ms, heidenhain's the most; parametrized tests loaded the same post for every
    case, some 1 400 times a run -- minutes of the suite.  Only for tests that use the
    post as it is: a test of loading, of the caches, or of a post it changes loads its
    own.  A compiled post is not changed by posting (each run has its own Engine).
    """
    frozen = tuple(sorted((options or {}).items(), key=lambda item: item[0]))
    return _compiled_post(str(machine), frozen)


@functools.cache
def _compiled_post(machine: str, options: tuple[tuple[str, Any], ...]) -> Any:
    return _load_post(machine, dict(options) or None)



# Hypothesis profiles, chosen by the environment variable HYPOTHESIS_PROFILE (or pytest's
# --hypothesis-profile):
#   ci       the default, and what .ci/run uses: a fixed seed and hypothesis's usual 100
#            examples a test, so the run is repeatable and takes minutes, not tens of them;
#   nightly  random seeds and 20x the examples, for a scheduled or hand run of everything
#            (-m "" lifts the default "not slow and not fuzz"):
#            HYPOTHESIS_PROFILE=nightly .venv/bin/python -m pytest -n auto -m ""
# Tests give no example counts of their own: a test slower per example than most takes a
# share of the profile's budget (examples(0.5)), so both profiles scale every test alike.
HYPOTHESIS_PROFILES = ("ci", "nightly")
settings.register_profile("ci", max_examples=100, derandomize=True, deadline=None,
                          database=None, suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("nightly", max_examples=2_000, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE") or "ci")


def examples(share: float) -> int:
    """A share of the active profile's examples a test (at least 10), for a test whose
    every example is slow (a whole program posted, a file written): a number of its own
    would not grow with the nightly profile, nor shrink with ci."""
    return max(10, round(settings.default.max_examples * share))
