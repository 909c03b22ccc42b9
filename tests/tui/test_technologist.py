"""The flow of a technologist: open vmc500, change two values of Break Chip, save.

The saved file must differ from the original in exactly those two values:
comments, quoting and layout everywhere else stay byte-identical.
"""

from __future__ import annotations

import difflib
from pathlib import Path
from typing import Any

from textual.pilot import Pilot
from textual.widgets import Input

from tests.tui.conftest import (
    go_to,
    highlighted_program_lines,
    preview_text,
    program_lines,
    run,
)
from tui.app import EditorApp
from tui.command_table import ITEM_COLUMN, CommandTable
from tui.item_editor import ItemEditor
from tui.model import TableRef


async def edit_text_item(pilot: Pilot[Any], row: int, item: int, old: str, new: str) -> None:
    """Put the cursor on a cell, open the item editor, retype the end of its text, OK."""
    app = pilot.app
    table = app.main.query_one(CommandTable)
    table.focus()
    await pilot.pause()
    table.move_cursor(row=0, column=ITEM_COLUMN)
    await pilot.pause()
    await pilot.press(*["down"] * row, *["right"] * item)
    await pilot.pause()
    await pilot.press("enter")
    await pilot.pause()
    editor = app.screen
    assert isinstance(editor, ItemEditor)
    field = editor.query_one("#text", Input)
    assert field.value.endswith(old)
    await pilot.press("end", *["backspace"] * len(old), *new)
    await pilot.pause()
    assert field.value.endswith(new)
    await pilot.press("enter")  # OK
    await pilot.pause()
    assert not isinstance(app.screen, ItemEditor)


def test_change_break_chip_and_save(vmc500: Path) -> None:
    original = vmc500.read_text(encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await go_to(pilot, "Break Chip")
        assert app.main.current == TableRef("command", "break_chip")
        assert app.focused is app.main.query_one(CommandTable)
        # the program preview scrolled to and highlights the lines Break Chip wrote
        assert "N100 G83 X60. Y20. Z53.0043 R70.0 F200.0 J11 K10.0" in \
            highlighted_program_lines(app)

        # block 2: [$CYCLE_PARAMS(2)G83_RET_DIST] = 1.0 -> 1.5
        await edit_text_item(pilot, row=1, item=0, old="1.0", new="1.5")
        assert "[$CYCLE_PARAMS(2)G83_RET_DIST] = 1.5" in preview_text(app)
        assert "[$CYCLE_PARAMS(2)G83_RET_DIST] = 1.5" in program_lines(app)

        # block 3, item 7: " J11" -> " J1"
        await edit_text_item(pilot, row=2, item=6, old="J11", new="J1")
        preview = preview_text(app)
        assert "G83 X60. Y20. Z53.0043 R70.0 F200.0 J1 K10.0" in preview
        assert "[$CYCLE_PARAMS(2)G83_RET_DIST] = 1.5" in preview
        highlighted = highlighted_program_lines(app)
        assert "N100 G83 X60. Y20. Z53.0043 R70.0 F200.0 J1 K10.0" in highlighted
        assert "[$CYCLE_PARAMS(2)G83_RET_DIST] = 1.5" in highlighted
        # the deep drill's J13 is another table: untouched
        assert "N70 G83 X40. Y20. Z53.0043 R70.0 F200.0 J13 K10.0" in program_lines(app)

        assert app.doc.dirty and "modified" in app.sub_title
        await pilot.press("ctrl+s")
        await pilot.pause()
        assert not app.doc.dirty and "modified" not in app.sub_title

    run(EditorApp(vmc500), scenario)

    saved = vmc500.read_text(encoding="utf-8")
    diff = [line for line in difflib.unified_diff(original.splitlines(keepends=True),
                                                  saved.splitlines(keepends=True), n=0)
            if not line.startswith(("---", "+++", "@@"))]
    assert diff == [
        '-        items: ["[$CYCLE_PARAMS(2)G83_RET_DIST] = 1.0"]\n',
        '+        items: ["[$CYCLE_PARAMS(2)G83_RET_DIST] = 1.5"]\n',
        '-          - " J11"\n',
        '+          - " J1"\n',
    ]
    # everything else, comments included, byte for byte
    before, after = original.splitlines(keepends=True), saved.splitlines(keepends=True)
    assert len(before) == len(after)
    changed = [i for i, (a, b) in enumerate(zip(before, after, strict=True)) if a != b]
    assert len(changed) == 2
    assert "".join(b for i, b in enumerate(after) if i not in changed) == \
        "".join(a for i, a in enumerate(before) if i not in changed)
