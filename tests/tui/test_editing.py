"""Editing flows: a conditional block, an invalid condition, undo/redo, quitting."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from textual.pilot import Pilot
from textual.widgets import Input, Select, Static

from tests.tui.conftest import choose, preview_text, program_lines, run
from tui.app import EditorApp
from tui.command_table import ITEM_COLUMN, CommandTable
from tui.dialogs import ConfirmDialog, PromptDialog
from tui.item_editor import ItemEditor
from tui.preview_pane import SampleTable


async def open_cell(pilot: Pilot[Any], row: int, column: int) -> None:
    table = pilot.app.main.query_one(CommandTable)
    table.focus()
    table.move_cursor(row=row, column=column)
    await pilot.pause()


def test_conditional_block_follows_the_sample_value(vmc500: Path) -> None:
    """Add a block writing G4 only when clearance > 6; clearance 5 -> 7 in the samples shows it.

    (Not dwell: the post refuses a dwell on break chip, the Acramatic's G83 has none.)
    """

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "break_chip")
        await open_cell(pilot, 2, ITEM_COLUMN)  # the G83 block
        await pilot.press("b")  # a new, empty block after it
        await pilot.pause()
        assert len(app.main.blocks()) == 5 and app.main.block == 3
        await pilot.press("a")  # its first item
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, ItemEditor)
        editor.query_one("#kind", Select).value = "param"
        await pilot.pause()
        editor.query_one("#param", Select).value = "clearance"
        await pilot.pause()
        editor.query_one("#format", Select).value = "cycle"
        editor.query_one("#prefix", Input).value = "G4 F"
        condition = editor.query_one("#condition", Input)
        condition.focus()
        await pilot.press(*"clearance > 6")
        await pilot.pause()
        assert not editor.query_one("#condition-error").has_class("-shown")
        await pilot.press("enter")
        await pilot.pause()
        assert not isinstance(app.screen, ItemEditor)
        assert app.doc.get(("commands", "break_chip", "blocks", 3, "items", 0)) == \
            {"param": "clearance", "prefix": "G4 F", "format": "cycle",
             "if": "clearance > 6"}

        # Break Chip's sample clearance is 5: the condition does not fire
        assert "G4" not in preview_text(app)
        assert "✗ clearance > 6" in preview_text(app)
        samples = app.main.query_one(SampleTable)
        assert "clearance" in samples.names
        samples.focus()
        samples.move_cursor(row=samples.names.index("clearance"))
        await pilot.pause()
        await pilot.press("enter")
        await pilot.pause()
        prompt = app.screen
        assert isinstance(prompt, PromptDialog)
        assert prompt.query_one(Input).value == "5"
        prompt.query_one(Input).value = "7"
        await pilot.press("enter")
        await pilot.pause()
        assert "N20 G4 F7.0" in preview_text(app)
        assert "✓ clearance > 6" in preview_text(app)
        # back to 5 (r resets the sample): the block disappears again
        samples.focus()
        await pilot.press("r")
        await pilot.pause()
        assert "G4" not in preview_text(app)
        # the sample program's break-chip clearance is 5 too
        assert not any("G4" in line for line in program_lines(app))

    run(EditorApp(vmc500), scenario)


def test_invalid_condition_is_shown_and_not_saved_silently(vmc500: Path) -> None:
    original = vmc500.read_bytes()

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "break_chip")
        await open_cell(pilot, 2, ITEM_COLUMN + 1)  # the X item of the G83 block
        await pilot.press("enter")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, ItemEditor)
        editor.query_one("#condition", Input).focus()
        await pilot.press(*"x >")
        await pilot.pause()
        error = editor.query_one("#condition-error", Static)
        assert error.has_class("-shown") and error.display
        assert "unexpected end of expression" in str(error.render())
        assert "^" in str(error.render())  # points at the place
        assert editor.query_one("#condition", Input).has_class("-invalid")
        # fixing it clears the error as you type
        await pilot.press("backspace", "backspace", "backspace", *"x > 1")
        await pilot.pause()
        assert not error.has_class("-shown")
        await pilot.press(*" and")
        await pilot.pause()
        assert error.has_class("-shown")
        await pilot.press("enter")  # keep it anyway: the post now has a problem
        await pilot.pause()

        assert app.doc.post is None
        assert [p.path for p in app.doc.problems] == \
            [("commands", "break_chip", "blocks", 2, "items", 1, "if")]
        assert "problem" in app.sub_title
        assert "cannot render" in preview_text(app)
        assert "unexpected end of expression" in preview_text(app)
        table = app.main.query_one(CommandTable)
        cell = table.get_cell_at(table.cursor_coordinate)
        assert any("on red" in str(span.style) for span in cell.spans)  # the cell is marked

        await pilot.press("ctrl+s")
        await pilot.pause()
        assert isinstance(app.screen, ConfirmDialog) and app.screen.id == "save-dialog"
        await pilot.press("escape")
        await pilot.pause()
        assert not isinstance(app.screen, ConfirmDialog)
        assert app.doc.dirty

    run(EditorApp(vmc500), scenario)
    assert vmc500.read_bytes() == original


def test_a_problem_marks_the_cell_its_check_found_it_at(vmc500: Path) -> None:
    """The editor marks the cell from the problem's own path, not from its position.

    An unknown key written first in a block-style item starts where the item starts:
    found back from the line and column, the problem was the item's, not its key's.
    """
    text = vmc500.read_text(encoding="utf-8")
    item = '          - {param: x, prefix: " X", format: coord}\n'
    start = text.index("  break_chip:")
    at = text.index(item, start)
    vmc500.write_text(text[:at] + '          - prefx: " X"\n            param: x\n'
                      '            format: coord\n' + text[at + len(item):], encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        item_path = ("commands", "break_chip", "blocks", 2, "items", 1)
        assert [p.path for p in app.doc.problems] == [item_path + ("prefx",)]
        assert "problem" in app.sub_title
        await choose(pilot, "break_chip")
        await open_cell(pilot, 2, ITEM_COLUMN + 1)
        table = app.main.query_one(CommandTable)
        cell = table.get_cell_at(table.cursor_coordinate)
        assert any("on red" in str(span.style) for span in cell.spans)  # the cell is marked
        inspector = str(app.main.query_one("#inspector", Static).render())
        assert "unknown key 'prefx'" in inspector
        await open_cell(pilot, 2, ITEM_COLUMN)  # the G83 beside it has no problem
        cell = table.get_cell_at(table.cursor_coordinate)
        assert not any("on red" in str(span.style) for span in cell.spans)
        assert "prefx" not in str(app.main.query_one("#inspector", Static).render())

    run(EditorApp(vmc500), scenario)


def test_undo_and_redo(vmc500: Path) -> None:
    original = vmc500.read_text(encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "tool_change")
        await open_cell(pilot, 0, ITEM_COLUMN)
        assert app.main.blocks()[0].numbered
        await pilot.press("n")  # do not number the tool change block
        await pilot.pause()
        assert not app.main.blocks()[0].numbered
        assert " T1 M6" in program_lines(app)
        await pilot.press("x")  # and delete its first item (T1)
        await pilot.pause()
        assert " M6" in program_lines(app)
        edited = app.doc.text
        assert len(app.doc.undo_stack) == 2

        await pilot.press("ctrl+z")
        await pilot.pause()
        assert " T1 M6" in program_lines(app)
        await pilot.press("ctrl+z")
        await pilot.pause()
        assert app.doc.text == original and not app.doc.dirty
        assert app.main.blocks()[0].numbered
        assert "N10  T1 M6" in program_lines(app)
        await pilot.press("ctrl+z")  # nothing more to undo: no change
        await pilot.pause()
        assert app.doc.text == original

        await pilot.press("ctrl+y", "ctrl+y")
        await pilot.pause()
        assert app.doc.text == edited
        assert " M6" in program_lines(app)
        await pilot.press("ctrl+z")
        await pilot.pause()
        await pilot.press("n")  # a new edit clears what could be redone
        await pilot.pause()
        assert app.doc.redo_stack == []

    run(EditorApp(vmc500), scenario)
    assert vmc500.read_text(encoding="utf-8") == original  # never saved


def test_quit_with_unsaved_changes_asks(vmc500: Path) -> None:
    original = vmc500.read_bytes()

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "tool_change")
        await open_cell(pilot, 0, ITEM_COLUMN)
        await pilot.press("n")
        await pilot.pause()
        assert app.doc.dirty

        await pilot.press("ctrl+q")
        await pilot.pause()
        assert isinstance(app.screen, ConfirmDialog) and app.screen.id == "quit-dialog"
        await pilot.press("escape")  # cancel: stay
        await pilot.pause()
        assert not isinstance(app.screen, ConfirmDialog) and app.is_running
        assert app.doc.dirty

        await pilot.press("ctrl+q")
        await pilot.pause()
        assert app.screen.id == "quit-dialog"
        await pilot.press("ctrl+q")  # confirm
        await pilot.pause()
        assert not app.is_running

    run(EditorApp(vmc500), scenario)
    assert vmc500.read_bytes() == original


def test_quit_dialog_choices(vmc500: Path) -> None:
    async def quit_without_saving(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "tool_change")
        await open_cell(pilot, 0, ITEM_COLUMN)
        await pilot.press("n", "ctrl+q")
        await pilot.pause()
        await pilot.press("q")
        await pilot.pause()
        assert not app.is_running

    original = vmc500.read_bytes()
    run(EditorApp(vmc500), quit_without_saving)
    assert vmc500.read_bytes() == original

    async def save_and_quit(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "tool_change")
        await open_cell(pilot, 0, ITEM_COLUMN)
        await pilot.press("n", "ctrl+q")
        await pilot.pause()
        await pilot.press("s")
        await pilot.pause()
        assert not app.is_running

    run(EditorApp(vmc500), save_and_quit)
    assert vmc500.read_bytes() != original
    assert b"number: false" in vmc500.read_bytes().split(b"tool_change:")[1][:80]


def test_quit_without_changes_does_not_ask(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("ctrl+q")
        await pilot.pause()
        assert not app.is_running

    run(EditorApp(vmc500), scenario)
