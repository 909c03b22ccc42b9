"""Hostile-input fuzzing: every entry point raises only postdsl's located errors, in time."""

from __future__ import annotations

from hypothesis import settings


def share(fraction: float) -> settings:
    """A fraction of the active profile's example budget, for the slower fuzz targets.

    The "ci" profile keeps all fuzz files to a few seconds each; "nightly" (20 times the
    examples, tests/conftest.py) scales every target alike.
    """
    return settings(max_examples=max(10, int(settings.default.max_examples * fraction)))
