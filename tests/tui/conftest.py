"""Fixtures of the editor tests: a private copy of a post, a fixed posting time, a runner."""

from __future__ import annotations

import asyncio
import shutil
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

import pytest
from textual.pilot import Pilot
from textual.widgets import Static

from tests.conftest import MACHINES, THESIS_EPOCH
from tui.app import EditorApp
from tui.commands_pane import CommandsPane
from tui.model import TableRef
from tui.preview_pane import CommandPreview
from tui.program_view import PLAIN, ProgramView


@pytest.fixture(autouse=True)
def fixed_time(monkeypatch: pytest.MonkeyPatch) -> None:
    """Previews print the posting date: pin it so screens and snapshots are stable."""
    monkeypatch.setenv("SOURCE_DATE_EPOCH", str(THESIS_EPOCH))


@pytest.fixture
def vmc500(tmp_path: Path) -> Path:
    """A copy of the VMC500 post; named like the original, so its bundled example is found."""
    target = tmp_path / "vmc500.yaml"
    shutil.copyfile(MACHINES / "vmc500.yaml", target)
    return target


Scenario = Callable[[EditorApp, Pilot[Any]], Awaitable[None]]


def run(app: EditorApp, scenario: Scenario, size: tuple[int, int] = (120, 40)) -> None:
    """Drive ``app`` headless through ``scenario`` (no pytest-asyncio needed)."""

    async def main() -> None:
        async with app.run_test(size=size) as pilot:
            await pilot.pause()
            await scenario(app, pilot)

    asyncio.run(main())


def preview_text(app: EditorApp) -> str:
    """What the command preview shows (lines, errors, conditions)."""
    static = app.main.query_one(CommandPreview).query_one("#preview-text", Static)
    return str(static.render())


def program_lines(app: EditorApp) -> list[str]:
    return app.main.query_one(ProgramView).lines


def highlighted_program_lines(app: EditorApp) -> list[str]:
    view = app.main.query_one(ProgramView)
    return [line for line, mark in zip(view.lines, view.marks, strict=True) if mark != PLAIN]


async def go_to(pilot: Pilot[Any], title: str) -> None:
    """Open a table through the command palette, as a user would."""
    await pilot.press("ctrl+p")
    await pilot.pause()
    await pilot.press(*title)  # fuzzy: matches "Go to <title>" first
    await pilot.pause(0.2)
    await pilot.press("enter")
    await pilot.pause()


async def choose(pilot: Pilot[Any], name: str, kind: str = "command") -> None:
    """Open a table from the commands pane: cursor on it, enter."""
    pane = pilot.app.main.query_one(CommandsPane)
    pane.focus()
    node = pane.node_for(TableRef(kind, name))
    assert node is not None, name
    pane.move_cursor(node)
    await pilot.pause()
    await pilot.press("enter")
    await pilot.pause()


def notifications(app: EditorApp) -> str:
    """Every notification the app has shown and not yet cleared, one a line."""
    return "\n".join(str(n.message) for n in app._notifications)
