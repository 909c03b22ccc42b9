"""Issue 27's smaller items, each seen by a technologist: the commands around the editor
and the editor's dialogs."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from click.testing import CliRunner

from postdsl.cli import main

BIN = Path(sys.executable).parent


def test_machines_shows_control_and_description() -> None:
    result = CliRunner().invoke(main, ["machines"])
    assert result.exit_code == 0
    rows = {line.split()[0]: line for line in result.output.splitlines()}
    assert "Siemens Sinumerik 828D (sinumerik-828d)" in rows["emco"]
    assert "EMCO Concept Mill 105 vertical mill" in rows["emco"]
    assert "HEIDENHAIN TNC 640" in rows["heidenhain"]
    names = CliRunner().invoke(main, ["machines", "--names"]).output.split()
    assert names == sorted(rows)


def test_preview_conditions_says_when_there_are_none() -> None:
    result = CliRunner().invoke(main, ["preview", "emco", "program_end", "--conditions"])
    assert result.exit_code == 0
    assert "no conditions: no block or item of program_end has an if:" in result.output


def test_edit_without_a_terminal_says_so_instead_of_hanging() -> None:
    done = subprocess.run([str(BIN / "postdsl"), "edit", "emco"], stdin=subprocess.DEVNULL,
                          capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 2
    assert "postdsl edit needs a terminal" in done.stderr
