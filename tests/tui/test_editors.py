"""The other editors and tools: formats, variables, machine settings, blocks, clipboard,
new tables, structures, the command palette and the CLI entry point."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path
from typing import Any

from click.testing import CliRunner
from textual.pilot import Pilot
from textual.widgets import DataTable, Input, Select, Static

from postdsl.cli import main
from tests.conftest import EXAMPLES, ROOT
from tests.tui.conftest import choose, notifications, preview_text, program_lines, run
from tests.tui.test_responsive import posted
from tui.app import EditorApp
from tui.block_editor import BlockEditor
from tui.command_table import ITEM_COLUMN, CommandTable
from tui.dialogs import PromptDialog
from tui.fields import FieldForm
from tui.formats_editor import FormatsEditor
from tui.item_editor import ItemEditor
from tui.main_screen import MainScreen
from tui.model import TableRef
from tui.palette import ACTIONS, EditorCommands
from tui.program_view import ProgramView
from tui.settings_editor import SettingsEditor
from tui.variables_editor import VariablesEditor

TINY = """\
postdsl: 1
machine: {name: Tiny}
formats:
  f: {decimals: 3, trailing_zeros: false}   # short coordinates
commands:
  program_start: {blocks: []}
  rapid_move:
    blocks:
      - items: [" G0", {param: x, prefix: " X", format: f}]
"""


async def open_cell(pilot: Pilot[Any], row: int, column: int) -> None:
    table = pilot.app.main.query_one(CommandTable)
    table.focus()
    table.move_cursor(row=row, column=column)
    await pilot.pause()


async def type_into(pilot: Pilot[Any], field: Input, text: str) -> None:
    field.focus()
    field.value = ""
    await pilot.press(*text)
    await pilot.pause()


def test_formats_editor_live_example_commit_and_undo(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f2")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, FormatsEditor)
        await pilot.press("down")  # cycle: decimals 4, min_decimals 1, no trailing zeros
        await pilot.pause()
        assert editor.current == "cycle"
        decimals = editor.query_one("#f-decimals", Input)
        assert decimals.value == "4"
        await type_into(pilot, decimals, "2")
        example = str(editor.query_one("#format-example").render())
        assert "53.0043 → 53.0" in example  # live, before anything is committed
        assert app.doc.get(("formats", "cycle", "decimals")) == 4
        await pilot.press("enter")  # commit
        await pilot.pause()
        assert app.doc.get(("formats", "cycle", "decimals")) == 2
        assert "N70 G83 X40. Y20. Z53.0 R70.0 F200.0 J13 K10.0" in program_lines(app)
        table = editor.query_one("#formats-table", DataTable)
        assert "53.0" in [str(c) for c in table.get_row("cycle")]

        # an impossible combination is named under its field and marks the post
        min_decimals = editor.query_one("#f-min_decimals", Input)
        await type_into(pilot, min_decimals, "3")
        form = editor.query_one(FieldForm)
        assert form.query_one("#e-min_decimals").has_class("-shown")
        assert "min_decimals must be at most decimals" in \
            str(form.query_one("#e-min_decimals").render())

        await pilot.press("escape")  # leaving without enter: the typed value is not kept
        await pilot.pause()
        assert app.doc.get(("formats", "cycle", "min_decimals")) == 1
        await pilot.press("ctrl+z")
        await pilot.pause()
        assert app.doc.text == vmc500.read_text(encoding="utf-8")

    run(EditorApp(vmc500), scenario)


def test_formats_add_and_delete(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f2")
        await pilot.pause()
        await pilot.press("a")
        await pilot.pause()
        assert isinstance(app.screen, PromptDialog)
        await pilot.press(*"coord")  # taken
        await pilot.pause()
        assert "already a format" in str(app.screen.query_one("#prompt-error").render())
        await pilot.press(*"2", "enter")
        await pilot.pause()
        assert app.doc.get(("formats", "coord2")) == {"decimals": 3}
        assert "  coord2:\n    decimals: 3\n" in app.doc.text
        editor = app.screen
        assert isinstance(editor, FormatsEditor) and editor.current == "coord2"
        await pilot.press("x")  # unused: deleted at once
        await pilot.pause()
        assert app.doc.get(("formats", "coord2")) is None
        assert app.doc.text == vmc500.read_text(encoding="utf-8")

    run(EditorApp(vmc500), scenario)


def test_variables_editor(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f3")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, VariablesEditor)
        table = editor.query_one(DataTable)
        table.move_cursor(row=list(app.doc.get(("variables",))).index("g83_relief"))
        await pilot.pause()
        assert editor.current == "g83_relief"
        assert "[$CYCLE_PARAMS(2)G83_RELIEF] = 1.0" in \
            str(editor.query_one("#variable-example-text").render())
        await pilot.press("enter")
        await pilot.pause()
        assert isinstance(app.screen, PromptDialog)
        app.screen.query_one(Input).value = "2.5"
        await pilot.press("enter")
        await pilot.pause()
        assert app.doc.get(("variables", "g83_relief")) == 2.5
        line = next(x for x in app.doc.text.splitlines() if "g83_relief:" in x)
        before = next(x for x in vmc500.read_text(encoding="utf-8").splitlines()
                      if "g83_relief:" in x)
        assert line == before.replace("1.0", "2.5")  # the comment stays where it was
        assert "[$CYCLE_PARAMS(2)G83_RELIEF] = 2.5" in \
            str(editor.query_one("#variable-example-text").render())
        assert "[$CYCLE_PARAMS(2)G83_RELIEF] = 2.5" in program_lines(app)

    run(EditorApp(vmc500), scenario)


def test_settings_editor_limits_and_numbering(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f4")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, SettingsEditor)
        low, high = app.doc.get(("machine", "travel", "x"))
        assert editor.query_one("#f-x_max", Input).value == str(high)
        await type_into(pilot, editor.query_one("#f-x_max", Input), "50")
        await pilot.press("enter")
        await pilot.pause()
        assert app.doc.get(("machine", "travel", "x")) == [low, 50]
        assert f"x: [{low}, 50]" in app.doc.text
        assert "outside the travel" in (app.main.program_error or "")
        assert "outside the travel" in str(editor.query_one("#settings-example").render())
        await pilot.press("ctrl+z")
        await pilot.pause()
        assert editor.query_one("#f-x_max", Input).value == str(high)  # the form follows undo
        await type_into(pilot, editor.query_one("#f-n_increment", Input), "5")
        await pilot.press("enter")
        await pilot.pause()
        assert "N15  M3 S500 M8" in str(editor.query_one("#settings-example").render())
        editor.query_one("#f-line_ending", Select).value = "crlf"
        await pilot.pause()
        assert app.doc.get(("output", "line_ending")) == "crlf"
        assert "CR↵" in str(editor.query_one("#settings-example").render())

    run(EditorApp(vmc500), scenario)


def test_block_editor(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "break_chip")
        await open_cell(pilot, 2, 0)  # the # column of the G83 block
        await pilot.press("enter")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, BlockEditor)
        await pilot.press(*"spindle ==")
        await pilot.pause()
        assert editor.query_one("#condition-error").has_class("-shown")
        await pilot.press(*" 'cw'")
        await pilot.pause()
        assert not editor.query_one("#condition-error").has_class("-shown")
        editor.query_one("#number", Select).value = False
        await pilot.press("enter")
        await pilot.pause()
        block = app.doc.get(("commands", "break_chip", "blocks", 2))
        assert block["if"] == "spindle == 'cw'" and block["number"] is False
        assert list(block)[:2] == ["if", "number"]  # written where posts write them
        assert "G83 X60. Y20. Z53.0043 R70.0 F200.0 J11 K10.0" in preview_text(app)
        assert "N10 G83" not in preview_text(app)
        assert "✓ spindle == 'cw'" in preview_text(app)

    run(EditorApp(vmc500), scenario)


def test_copy_paste_and_move_items_and_blocks(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "break_chip")
        await open_cell(pilot, 2, ITEM_COLUMN + 6)  # " J11"
        await pilot.press("c", "right", "v")
        await pilot.pause()
        items = app.doc.get(("commands", "break_chip", "blocks", 2, "items"))
        assert list(items[6:]) == [" J11", {"param": "peck", "prefix": " K",
                                            "format": "cycle"}, " J11"]
        assert app.main.column == ITEM_COLUMN + 8
        await pilot.press("shift+left")  # move the copy before K
        await pilot.pause()
        assert "J11 J11 K10.0" in preview_text(app)
        await pilot.press("x")
        await pilot.pause()
        assert "J11 K10.0" in preview_text(app)
        await open_cell(pilot, 1, 0)  # copy block 2, paste it after block 3
        await pilot.press("c", "down", "v")
        await pilot.pause()
        assert len(app.main.blocks()) == 5
        assert preview_text(app).count("G83_RET_DIST") == 2
        await pilot.press("shift+up")
        await pilot.pause()
        assert app.main.block == 2
        await pilot.press("X")
        await pilot.pause()
        assert len(app.main.blocks()) == 4
        assert app.doc.text == vmc500.read_text(encoding="utf-8")

    run(EditorApp(vmc500), scenario)


def test_a_new_table_for_a_command_without_one(tmp_path: Path) -> None:
    post = tmp_path / "tiny.yaml"
    post.write_text(TINY, encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        # the sample program needs tables the post lacks: the program view says so
        assert "no table for CL command 'tool_change'" in (app.main.program_error or "")
        assert app.main.query_one(ProgramView).message == app.main.program_error
        await choose(pilot, "linear_move")
        title = str(app.main.query_one("#table-title", Static).render())
        assert "no table — press t to add one" in title
        assert "no table" in preview_text(app)
        app.main.query_one(CommandTable).focus()
        await pilot.press("b")  # not yet: no table
        await pilot.pause()
        assert app.doc.get(("commands", "linear_move")) is None
        await pilot.press("t")  # where the title says: the grid has the keyboard
        await pilot.pause()
        assert app.doc.get(("commands", "linear_move")) == {"blocks": []}
        await pilot.press("t")
        await pilot.pause()
        assert "Linear Move already has a table" in notifications(app)
        await pilot.press("b", "a")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, ItemEditor)
        editor.query_one("#text", Input).value = " G1"
        await pilot.press("enter")
        await pilot.pause()
        assert app.doc.get(("commands", "linear_move")) == {"blocks": [{"items": [" G1"]}]}
        assert "N10  G1" in preview_text(app)
        assert "f: {decimals: 3, trailing_zeros: false}   # short coordinates" in app.doc.text

    run(EditorApp(post, cl=EXAMPLES / "vmc500_cycles.jsonl"), scenario)


def test_structures_are_tables_too(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "break_chip")
        await open_cell(pilot, 0, ITEM_COLUMN)  # "⇢ gage_height": enter opens it
        await pilot.press("enter")
        await pilot.pause()
        assert app.main.current == TableRef("structure", "gage_height")
        assert "Single Peck" in preview_text(app)  # who uses it
        await open_cell(pilot, 0, ITEM_COLUMN)
        await pilot.press("enter")
        await pilot.pause()
        assert isinstance(app.screen, ItemEditor)
        app.screen.query_one("#text", Input).value = "[$CYCLE_PARAMS(2)GAGE_HEIGHT] = "
        await pilot.press("enter")
        await pilot.pause()
        assert sum("GAGE_HEIGHT] = 5.0" in line for line in program_lines(app)) == 5

    run(EditorApp(vmc500), scenario)


def test_palette_lists_every_action_screen_and_table(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        commands = list(EditorCommands(app.screen)._commands())
        titles = [title for title, _key, _, _ in commands]
        for title, action, _ in ACTIONS:
            name = re.match(r"\w+", action.removeprefix("app.")).group()  # type: ignore[union-attr]
            owner = app if action.startswith("app.") else app.main
            assert hasattr(owner, f"action_{name}"), action
            assert title in titles
        assert {"Open Formats", "Open Variables", "Open Machine settings",
                "Go to Break Chip", "Go to Gage Height"} <= set(titles)
        # the keys of the main screen are all reachable from the palette too, with their key
        keys = {title: key for title, key, _, _ in commands}
        actions = {a.split("(")[0] for _, a, _ in ACTIONS}
        for binding in MainScreen.BINDINGS:
            action = binding.action.split("(")[0]  # type: ignore[union-attr]
            assert action in actions, action
        assert keys["Save"] == "^s" and keys["Add item"] == "a" and keys["Undo"] == "^z"
        assert keys["Open Formats"] == "f2" and keys["Choose the sample program"] == "f6"
        await pilot.press("ctrl+p")
        await pilot.pause()
        await pilot.press(*"variables")
        await pilot.pause(0.3)
        await pilot.press("enter")
        await pilot.pause()
        assert isinstance(app.screen, VariablesEditor)

    run(EditorApp(vmc500), scenario)


def test_edit_command_line(tmp_path: Path) -> None:
    runner = CliRunner()
    result = runner.invoke(main, ["edit", "--help"])
    assert result.exit_code == 0 and "--cl" in result.output
    result = runner.invoke(main, ["edit", "no_such_machine"])
    assert result.exit_code == 1 and "unknown machine" in result.output
    broken = tmp_path / "broken.yaml"
    broken.write_text("postdsl: 1\nmachine: [\n", encoding="utf-8")
    result = runner.invoke(main, ["edit", str(broken)])
    assert result.exit_code == 1 and "broken.yaml:" in result.output


def test_posting_does_not_load_textual() -> None:
    code = "import sys, postdsl.cli; print('textual' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, check=True).stdout
    assert out.strip() == "False"


def test_settings_editor_sets_the_options_the_preview_posts_with(vmc500: Path) -> None:
    text = vmc500.read_text(encoding="utf-8")
    text = text.replace("    default: true\n\nformats:", "    default: {option: numbered}\n\n"
                        "formats:", 1)
    text = text.replace("formats:\n", "options:\n  numbered: {type: bool, default: true, "
                        "description: write block numbers}\n  speed_factor: {type: int, "
                        "default: 1, choices: [1, 2]}\nformats:\n", 1)
    vmc500.write_text(text, encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        assert app.doc.problems == []
        await posted(app, pilot)
        assert any(line.startswith("N") for line in program_lines(app))
        await pilot.press("f4")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, SettingsEditor)
        numbered = editor.query_one("#f-option-numbered", Select)
        assert numbered.value == Select.NULL  # the default: not set
        numbered.value = False
        await pilot.pause()
        await posted(app, pilot)
        assert app.doc.options == {"numbered": False}
        assert app.doc.text == text  # an option is not saved in the post
        assert not any(line.startswith("N") for line in program_lines(app))
        assert not any(line.startswith("N") for line in
                       str(editor.query_one("#settings-example").render()).splitlines()[1:4])
        choice = editor.query_one("#f-option-speed_factor", Select)
        choice.value = "2"
        await pilot.pause()
        assert app.doc.options == {"numbered": False, "speed_factor": "2"}
        assert app.doc.problems == []
        numbered.value = Select.NULL  # back to the default
        await pilot.pause()
        await posted(app, pilot)
        assert app.doc.options == {"speed_factor": "2"}
        assert any(line.startswith("N") for line in program_lines(app))

    run(EditorApp(vmc500), scenario)
