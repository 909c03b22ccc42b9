"""SVG screenshots of the editor's screens, locked with syrupy.

Review a changed screenshot by looking at it (any browser opens the .svg),
then accept it with ``pytest tests/tui --snapshot-update``.  The posting time
is pinned (SOURCE_DATE_EPOCH, see conftest) so the previews are stable.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import pytest
from syrupy.extensions.image import SVGImageSnapshotExtension
from textual.pilot import Pilot
from textual.widgets import Input

from tests.tui.conftest import choose, run
from tui.app import EditorApp
from tui.backplot import Backplot
from tui.command_table import ITEM_COLUMN, CommandTable
from tui.formats_editor import FormatsEditor
from tui.item_editor import ItemEditor


@pytest.fixture
def svg_snapshot(snapshot: Any) -> Any:
    return snapshot.use_extension(SVGImageSnapshotExtension)


async def steady(app: EditorApp, pilot: Pilot[Any]) -> None:
    """No blinking cursor, no toolpath being drawn and no pending layout before the picture."""
    deadline = time.monotonic() + 30
    while any(not worker.is_finished for worker in app.workers):
        assert time.monotonic() < deadline, "a worker never finished"
        await pilot.pause(0.02)
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


@pytest.mark.parametrize(("size", "keys"), [((120, 40), ()), ((80, 24), ()), ((80, 24), ("p",))],
                         ids=["120x40", "80x24", "80x24-toolpath"])
def test_main_screen(vmc500: Path, svg_snapshot: Any, size: tuple[int, int],
                     keys: tuple[str, ...]) -> None:
    """At 120 columns the toolpath sits beside the program, Break Chip's holes lit; at 80
    it waits for p, then takes the command preview's room."""
    pictures: list[str] = []

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await break_chip_j11(app, pilot)
        await pilot.press(*keys)
        await steady(app, pilot)
        plot = app.main.query_one(Backplot)
        assert plot.display == (size[0] >= 100 or "p" in keys)
        assert plot.highlight  # the sample drills with Break Chip: its holes are lit
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
