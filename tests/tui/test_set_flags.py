"""Flags in the editor: a table's ``set:`` (``s`` on the grid) and the post's ``flags:``
declarations (the variables editor, f3), each edit checked with the post's own checks,
written through the round-trip document and seen in the program."""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

from textual.pilot import Pilot
from textual.widgets import Input, Static
from textual.widgets._footer import FooterKey

from tests.conftest import EXAMPLES, MACHINES
from tests.tui.conftest import choose, notifications, program_lines, run
from tui.app import EditorApp
from tui.dialogs import PromptDialog
from tui.flags_section import FlagsTable
from tui.footer import EditorFooter
from tui.palette import ACTIONS
from tui.set_editor import SetEditor
from tui.variables_editor import VariablesEditor

SAMPLE = str(EXAMPLES / "vmc500_cycles.jsonl")
RAPID_M9 = "          - {text: \" M9\", if: \"coolant == 'off'\", modal: coolant, mode: changed}\n"
#: a rapid after coolant_on says so, until coolant_off clears the flag
MARK = "          - {text: \" (CD)\", if: coolant_due}\n"
FLAGS = "flags:\n  coolant_due: false   # coolant came on: mark the next rapids\n\n"
COOLANT_OFF = "  coolant_off:\n"


def flagged_post(target: Path) -> str:
    """The VMC500 post with a declared flag that rapid_move reads and coolant_off sets."""
    text = (MACHINES / "vmc500.yaml").read_text(encoding="utf-8")
    assert RAPID_M9 in text and "\nstructures:\n" in text and COOLANT_OFF in text
    text = text.replace(RAPID_M9, RAPID_M9 + MARK)
    text = text.replace("\nstructures:\n", "\n" + FLAGS + "structures:\n", 1)
    text = text.replace(COOLANT_OFF, COOLANT_OFF + "    set: {coolant_due: \"false\"}\n", 1)
    target.write_text(text, encoding="utf-8")
    return text


async def type_into(pilot: Pilot[Any], text: str) -> None:
    """Clear the focused field and type ``text`` key by key, as a user does."""
    field = pilot.app.screen.query_one(Input)
    await pilot.press("end", *["backspace"] * len(field.value))
    await pilot.press(*[{" ": "space"}.get(c, c) for c in text])
    await pilot.pause()


def prompt_error(app: EditorApp) -> str:
    return str(app.screen.query_one("#prompt-error", Static).render())


async def open_sets(pilot: Pilot[Any], command: str) -> SetEditor:
    await choose(pilot, command)
    await pilot.press("s")
    await pilot.pause()
    editor = pilot.app.screen
    assert isinstance(editor, SetEditor)
    return editor


def test_s_is_a_key_of_the_grid_shown_in_footer_help_and_palette(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        footer = app.main.query_one(EditorFooter)
        shown = {(key.key_display, key.description) for key in footer.query(FooterKey)}
        assert ("s", "Set flags") in shown  # when the terminal is wide enough
        await pilot.press("f1")
        await pilot.pause()
        assert "Set flags" in str(app.screen.query_one("#help-text", Static).render())
        await pilot.press("escape")
        await pilot.pause()
        await pilot.press("ctrl+p")
        await pilot.pause()
        await pilot.press(*"Set flags")
        await pilot.pause(0.3)
        await pilot.press("enter")  # from the palette, on the selected table
        await pilot.pause()
        assert isinstance(app.screen, SetEditor)
        assert app.screen.ref.name == app.main.current.name

    assert any(action == "edit_sets" for _t, action, _h in ACTIONS)
    run(EditorApp(vmc500, SAMPLE), scenario, size=(220, 40))


def test_add_a_set_entry_checked_as_typed(tmp_path: Path) -> None:
    post = tmp_path / "vmc500.yaml"
    original = flagged_post(post)

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        assert app.doc.problems == []
        assert not any("(CD)" in line for line in program_lines(app))
        editor = await open_sets(pilot, "coolant_on")
        assert "sets no flags" in str(editor.query_one("#set-message", Static).render())
        await pilot.press("a")
        await pilot.pause()
        assert isinstance(app.screen, PromptDialog)
        await type_into(pilot, "coolant_dew")  # not declared: refused, the name kept
        await pilot.press("enter")
        await pilot.pause()
        assert isinstance(app.screen, PromptDialog)
        assert "'coolant_dew' is not a flag" in prompt_error(app)
        assert "declared: coolant_due" in prompt_error(app)
        assert app.screen.query_one(Input).value == "coolant_dew"
        await type_into(pilot, "coolant_due")
        await pilot.press("enter")
        await pilot.pause()
        assert isinstance(app.screen, PromptDialog)  # now the expression
        await type_into(pilot, "spindle_sped > 0")  # an unknown name: kept, with the message
        await pilot.press("enter")
        await pilot.pause()
        assert isinstance(app.screen, PromptDialog)
        assert "spindle_sped" in prompt_error(app)
        assert app.screen.query_one(Input).value == "spindle_sped > 0"
        await type_into(pilot, "true and")  # a syntax error: kept, with the message
        await pilot.press("enter")
        await pilot.pause()
        assert isinstance(app.screen, PromptDialog) and prompt_error(app)
        assert app.screen.query_one(Input).value == "true and"
        assert app.doc.text == original  # nothing written while it is wrong
        await type_into(pilot, "true")
        await pilot.press("enter")
        await pilot.pause()
        assert app.screen is editor
        assert app.doc.problems == []
        assert app.doc.model.commands["coolant_on"].sets["coolant_due"].source == "true"
        await pilot.press("escape")
        await pilot.pause()
        # the rapids after coolant_on carry the mark, and none before the first M8
        lines = program_lines(app)
        marked = [i for i, line in enumerate(lines) if "(CD)" in line]
        first_m8 = next(i for i, line in enumerate(lines) if "M8" in line)
        assert marked and marked[0] > first_m8
        await pilot.press("ctrl+s")
        await pilot.pause()

    run(EditorApp(post, SAMPLE), scenario)
    assert post.read_text(encoding="utf-8") == original.replace(
        "  coolant_on:\n", "  coolant_on:\n    set: {coolant_due: \"true\"}\n", 1)


def test_change_and_remove_a_set_entry(tmp_path: Path) -> None:
    post = tmp_path / "vmc500.yaml"
    original = flagged_post(post)

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        editor = await open_sets(pilot, "coolant_off")
        assert editor.current == "coolant_due"
        await pilot.press("enter")
        await pilot.pause()
        assert isinstance(app.screen, PromptDialog)
        assert app.screen.query_one(Input).value == "false"
        await type_into(pilot, "coolant_due and false")
        await pilot.press("enter")
        await pilot.pause()
        assert app.screen is editor and app.doc.problems == []
        assert app.doc.text == original.replace(
            'set: {coolant_due: "false"}', 'set: {coolant_due: "coolant_due and false"}')
        await pilot.press("x")
        await pilot.pause()
        assert app.doc.text == original.replace('    set: {coolant_due: "false"}\n', "")
        assert "sets no flags" in str(editor.query_one("#set-message", Static).render())
        await pilot.press("ctrl+z")  # undo brings the entry back, in the dialog too
        await pilot.pause()
        assert editor.current == "coolant_due"
        await pilot.press("escape")
        await pilot.pause()
        await pilot.press("ctrl+s")
        await pilot.pause()

    run(EditorApp(post, SAMPLE), scenario)
    assert post.read_text(encoding="utf-8") == original.replace(
        'set: {coolant_due: "false"}', 'set: {coolant_due: "coolant_due and false"}')


def test_a_table_without_blocks_of_its_own_says_why(tmp_path: Path) -> None:
    post = tmp_path / "vmc500.yaml"
    flagged_post(post)

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "gage_height", kind="structure")
        await pilot.press("s")
        await pilot.pause()
        assert not isinstance(app.screen, SetEditor)
        assert "set: belongs to the table of a command" in notifications(app)

    run(EditorApp(post, SAMPLE), scenario)


def test_set_of_an_inherited_table_is_edited_as_overrides_of_its_entries(
        tmp_path: Path) -> None:
    """Issue 27: ``override:`` can replace a ``set:`` entry of the base's table, so the
    dialog edits it, writing exactly the entry changed."""
    base = tmp_path / "base.yaml"
    base_text = flagged_post(base)
    child = tmp_path / "child.yaml"
    child_text = "postdsl: 1\nextends: base.yaml\nmachine:\n  name: VMC 500 child\n"
    child.write_text(child_text, encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        assert app.doc.problems == []
        editor = await open_sets(pilot, "coolant_off")
        assert editor.current == "coolant_due"
        message = str(editor.query_one("#set-message", Static).render())
        assert "comes from the base post" in message
        await pilot.press("enter")
        await pilot.pause()
        assert isinstance(app.screen, PromptDialog)
        field = app.screen.query_one(Input)
        field.value = "true"
        await pilot.press("enter")
        await pilot.pause()
        assert app.doc.problems == []
        assert app.doc.text == child_text + \
            'override:\n  commands/coolant_off/set/coolant_due: "true"\n'
        table = app.doc.model.commands["coolant_off"]
        assert table.sets is not None and table.sets["coolant_due"].source == "true"
        await pilot.press("x")
        await pilot.pause()
        assert app.doc.text == child_text + \
            "override:\n  commands/coolant_off/set/coolant_due:\n"
        assert app.doc.problems == []
        assert not app.doc.model.commands["coolant_off"].sets

    run(EditorApp(child, SAMPLE), scenario)
    assert base.read_text(encoding="utf-8") == base_text


async def open_flags(pilot: Pilot[Any]) -> VariablesEditor:
    await pilot.press("f3")
    await pilot.pause()
    editor = pilot.app.screen
    assert isinstance(editor, VariablesEditor)
    await pilot.press("tab")
    await pilot.pause()
    assert isinstance(editor.focused, FlagsTable)
    return editor


def test_declare_change_and_remove_flags(tmp_path: Path) -> None:
    post = tmp_path / "vmc500.yaml"
    original = flagged_post(post)

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        editor = await open_flags(pilot)
        assert editor.current_flag == "coolant_due"
        await pilot.press("a")
        await pilot.pause()
        for name, error in (("x", "is a CL parameter"), ("post_name", "is a variable"),
                            ("coolant_due", "already a flag"), ("2nd", "is a word")):
            await type_into(pilot, name)
            await pilot.press("enter")
            await pilot.pause()
            assert isinstance(app.screen, PromptDialog), name
            assert error in prompt_error(app), name
        await type_into(pilot, "pending")
        await pilot.press("enter")
        await pilot.pause()
        await type_into(pilot, "'open")  # an unclosed quote: refused, kept
        await pilot.press("enter")
        await pilot.pause()
        assert "closing quote" in prompt_error(app)
        await type_into(pilot, "false")
        await pilot.press("enter")
        await pilot.pause()
        assert app.screen is editor and app.doc.problems == []
        assert app.doc.model.flags["pending"].value is False
        assert app.doc.text == original.replace(FLAGS, FLAGS[:-1] + "  pending: false\n\n")
        assert editor.current_flag == "pending"

        # the start value: true from the start marks the rapids until coolant_off clears it
        assert not any("(CD)" in line for line in program_lines(app))
        editor.query_one(FlagsTable).move_cursor(row=0)
        await pilot.pause()
        assert editor.current_flag == "coolant_due"
        await pilot.press("enter")
        await pilot.pause()
        await type_into(pilot, "true")
        await pilot.press("enter")
        await pilot.pause()
        assert app.doc.model.flags["coolant_due"].value is True
        # the comment stays in its column
        assert "  coolant_due: true    # coolant came on: mark the next rapids\n" in app.doc.text
        lines = program_lines(app)
        assert "N30  G0 X40. Y20. Z80. (CD)" in lines and "N190  G0 X100." in lines

        # removing a flag still read or set is refused, naming the tables
        await pilot.press("x")
        await pilot.pause()
        said = notifications(app)
        assert "flag 'coolant_due' cannot be removed" in said
        assert "coolant_off" in said and "rapid_move" in said
        assert "coolant_due:" in app.doc.text
        # an unused one goes
        editor.query_one(FlagsTable).move_cursor(row=1)
        await pilot.pause()
        assert editor.current_flag == "pending"
        await pilot.press("x")
        await pilot.pause()
        assert "pending" not in app.doc.text
        await pilot.press("escape")
        await pilot.pause()
        await pilot.press("ctrl+s")
        await pilot.pause()

    run(EditorApp(post, SAMPLE), scenario)
    assert post.read_text(encoding="utf-8") == original.replace(
        "  coolant_due: false   #", "  coolant_due: true    #")


def test_a_flag_that_shadows_an_option_is_refused(tmp_path: Path) -> None:
    post = tmp_path / "vmc500.yaml"
    text = flagged_post(post)
    text = text.replace(FLAGS, FLAGS + "options:\n  probe: {type: bool, default: false}\n\n")
    post.write_text(text, encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        assert app.doc.problems == []
        await open_flags(pilot)
        await pilot.press("a")
        await pilot.pause()
        await type_into(pilot, "probe")
        await pilot.press("enter")
        await pilot.pause()
        assert isinstance(app.screen, PromptDialog)
        assert "'probe' is an option" in prompt_error(app)

    run(EditorApp(post, SAMPLE), scenario)


def test_variables_editor_still_edits_variables_with_flags_below(vmc500: Path) -> None:
    shutil.copyfile(MACHINES / "vmc500.yaml", vmc500)

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f3")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, VariablesEditor)
        assert editor.current_flag is None  # the VMC500 declares none
        await pilot.press("tab")
        await pilot.pause()
        await pilot.press("x")  # nothing to delete: nothing happens
        await pilot.pause()
        assert not app.doc.dirty

    run(EditorApp(vmc500, SAMPLE), scenario)
