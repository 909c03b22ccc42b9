"""SVG screenshots of the editor's screens, locked with syrupy.

Review a changed screenshot by looking at it (any browser opens the .svg),
then accept it with ``pytest tests/tui --snapshot-update``.  The posting time
is pinned (SOURCE_DATE_EPOCH, see conftest) so the previews are stable.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from syrupy.extensions.image import SVGImageSnapshotExtension
from textual.pilot import Pilot
from textual.widgets import Input

from tests.tui.conftest import choose, run
from tui.app import EditorApp
from tui.command_table import ITEM_COLUMN, CommandTable
from tui.formats_editor import FormatsEditor
from tui.item_editor import ItemEditor


@pytest.fixture
def svg_snapshot(snapshot: Any) -> Any:
    return snapshot.use_extension(SVGImageSnapshotExtension)


async def steady(app: EditorApp, pilot: Pilot[Any]) -> None:
    """No blinking cursor and no pending layout before the picture."""
    for field in app.screen.query(Input):
        field.cursor_blink = False
    await pilot.wait_for_scheduled_animations()
    for _ in range(3):  # tables size their columns when idle
        await pilot.pause(0.05)


async def break_chip_j11(app: EditorApp, pilot: Pilot[Any]) -> None:
    await choose(pilot, "break_chip")
    table = app.main.query_one(CommandTable)
    table.move_cursor(row=2, column=ITEM_COLUMN + 6)
    await pilot.pause()


@pytest.mark.parametrize("size", [(120, 40), (80, 24)], ids=["120x40", "80x24"])
def test_main_screen(vmc500: Path, svg_snapshot: Any, size: tuple[int, int]) -> None:
    pictures: list[str] = []

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await break_chip_j11(app, pilot)
        await steady(app, pilot)
        pictures.append(app.export_screenshot(title="postdsl edit"))

    run(EditorApp(vmc500), scenario, size=size)
    assert pictures[0] == svg_snapshot


def test_item_editor(vmc500: Path, svg_snapshot: Any) -> None:
    pictures: list[str] = []

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "break_chip")
        app.main.query_one(CommandTable).move_cursor(row=2, column=ITEM_COLUMN + 1)
        await pilot.pause()
        await pilot.press("enter")
        await pilot.pause()
        assert isinstance(app.screen, ItemEditor)
        app.screen.query_one("#condition", Input).focus()
        await pilot.press(*"x >")
        await steady(app, pilot)
        pictures.append(app.export_screenshot(title="postdsl edit"))

    run(EditorApp(vmc500), scenario)
    assert pictures[0] == svg_snapshot


def test_formats_editor(vmc500: Path, svg_snapshot: Any) -> None:
    pictures: list[str] = []

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f2")
        await pilot.pause()
        assert isinstance(app.screen, FormatsEditor)
        await pilot.press("down")  # the cycle format
        await steady(app, pilot)
        pictures.append(app.export_screenshot(title="postdsl edit"))

    run(EditorApp(vmc500), scenario)
    assert pictures[0] == svg_snapshot
