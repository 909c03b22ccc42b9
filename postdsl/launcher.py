"""The ``postdsl`` command's entry point: the CLI, with dataclass methods from the cache.

The methods ``dataclasses`` writes for postdsl's classes are a third of a short
run's start-up (:mod:`postdsl.compile.classcode`).  Routing them through the cache touches
the ``dataclasses`` module, so only the command line's own process does it, here,
before :mod:`postdsl.cli` imports the modules that define the classes; a program
that imports postdsl as a library is left alone.
"""

from __future__ import annotations


def main() -> None:
    """Run the command line (the console script ``postdsl``)."""
    from postdsl.compile import classcode

    classcode.install()
    from postdsl.cli import main as cli_main

    cli_main()
