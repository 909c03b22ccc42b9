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


# --- the editor's dialogs ------------------------------------------------------------------

import shutil  # noqa: E402
from typing import Any  # noqa: E402

from textual.pilot import Pilot  # noqa: E402
from textual.widgets import Input, Label, Select, Static  # noqa: E402

from tests.conftest import MACHINES  # noqa: E402
from tests.tui.conftest import run  # noqa: E402
from tui.app import EditorApp  # noqa: E402
from tui.formats_editor import FormatsEditor  # noqa: E402
from tui.settings_editor import SettingsEditor  # noqa: E402
from tui.variables_editor import VariablesEditor  # noqa: E402


def copy(tmp_path: Path, name: str) -> Path:
    target = tmp_path / f"{name}.yaml"
    shutil.copyfile(MACHINES / f"{name}.yaml", target)
    return target


def test_a_dialog_field_has_the_focus_as_the_dialog_opens(tmp_path: Path) -> None:
    """enter opens the value prompt; keys in the same burst reach its field (the field
    is focused on mount, not after the pending messages).  ``Pilot.press`` waits after
    each key: the order of a real terminal's burst is
    ``test_editing_keys_in_a_burst_apply_in_the_order_typed``."""
    post = copy(tmp_path, "fanuc")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f3")
        await pilot.pause()
        assert isinstance(app.screen, VariablesEditor)
        await pilot.press("enter", "ctrl+a", "ctrl+k", "4", "2")  # one burst, no pause
        await pilot.pause()
        assert app.screen.query_one(Input).value == "42"

    run(EditorApp(post), scenario)


def test_the_formats_dialog_says_enter_applies(tmp_path: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f2")
        await pilot.pause()
        assert isinstance(app.screen, FormatsEditor)
        hint = str(app.screen.query_one(".dialog-hint", Static).render())
        assert "enter: apply" in hint

    run(EditorApp(copy(tmp_path, "fanuc")), scenario)


def test_the_options_are_one_key_away_and_their_labels_stand_apart(tmp_path: Path) -> None:
    """The f4 option was the 26th field (25 tabs); its label ran into its value
    (``prestage_next_todefault``)."""
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f4")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, SettingsEditor)
        await pilot.press("ctrl+o")
        await pilot.pause()
        # ctrl+o lands on the first option (fanuc.yaml's options: cutter_compensation)
        assert app.focused is editor.query_one("#f-option-cutter_compensation", Select)
        select = editor.query_one("#f-option-prestage_next_tool", Select)
        label = select.parent.query_one(Label)
        assert "prestage_next_tool" in str(label.render())
        assert label.region.right < select.region.x  # a gap between label and value
        assert label.region.width >= len("prestage_next_tool")
        assert "ctrl+o: options" in str(editor.query_one(".dialog-hint", Static).render())

    run(EditorApp(copy(tmp_path, "fanuc")), scenario)


def test_the_quit_dialog_counts_the_edits_from_the_saved_text(tmp_path: Path) -> None:
    """After an edit, a save and an undo it said "0 unsaved edits"."""
    post = copy(tmp_path, "fanuc")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        assert app.doc.edit("x", lambda data: data["machine"].__setitem__("max_feed", 9000))
        await pilot.press("ctrl+s")
        await pilot.pause()
        await pilot.press("ctrl+z")
        await pilot.pause()
        assert app.doc.dirty
        await pilot.press("ctrl+q")
        await pilot.pause()
        message = str(app.screen.query_one(".dialog-message", Static).render())
        assert "fanuc.yaml has 1 unsaved edit." in message
        await pilot.press("escape")
        await pilot.pause()
        await pilot.press("ctrl+y")  # back to the saved text: nothing to ask
        await pilot.pause()
        assert not app.doc.dirty

    run(EditorApp(post), scenario)


def test_preview_by_an_iso_word_finds_the_cells_that_mean_it() -> None:
    """``postdsl preview emco G83`` found nothing: Sinumerik writes deep drilling as
    CYCLE83.  G83 -> deep drilling -> the CL command deep_drill -> the post's table."""
    result = CliRunner().invoke(main, ["preview", "emco", "G83"])
    assert result.exit_code == 0, result.output
    assert "on ISO controls G83 is deep drill (the CL command deep_drill)" in result.output
    assert "MCALL CYCLE83(" in result.output
    heidenhain = CliRunner().invoke(main, ["preview", "heidenhain", "g83"])
    assert heidenhain.exit_code == 0 and "CYCL DEF 20" in heidenhain.output
    # a word the post writes itself is still answered with its cells
    fanuc = CliRunner().invoke(main, ["preview", "fanuc", "G83"])
    assert "G83 is written by deep_drill" in fanuc.output
    # a word no cell writes and no CL command means (G99 would be matched by the work
    # offset's "G" before a computed number, G505-G599)
    nothing = CliRunner().invoke(main, ["preview", "emco", "M99"])
    assert nothing.exit_code == 1


def _burst(app: EditorApp, *keys: str) -> None:
    """Keys as one burst from a terminal: the driver posts every key of a read to the
    app before the app handles any (``Pilot.press`` waits for idle after each key and
    so never shows the order the editor gets from a real terminal)."""
    from textual import events
    from textual.keys import _character_to_key

    driver = app._driver
    assert driver is not None
    for key in keys:
        character = key if len(key) == 1 else None
        event = events.Key(key if len(key) > 1 or key.isalnum() else _character_to_key(key),
                           character)
        event.set_sender(app)
        driver.send_message(event)


def test_editing_keys_in_a_burst_apply_in_the_order_typed(tmp_path: Path) -> None:
    """``tmux send-keys C-a C-k 4 2`` left the field empty, ``End BSpace 9 8`` gave
    ``9``: the editing keys, bindings checked only once the key had bubbled up to the
    app, ran after the printable keys of the same burst, inserted by the field at once."""
    post = copy(tmp_path, "fanuc")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f3")
        await pilot.pause()
        assert isinstance(app.screen, VariablesEditor)
        await pilot.press("enter")
        await pilot.pause()
        field = app.screen.query_one(Input)
        assert app.focused is field and field.value
        _burst(app, "ctrl+a", "ctrl+k", "4", "2")
        await pilot.pause()
        assert field.value == "42"
        _burst(app, "end", "backspace", "9", "8")
        await pilot.pause()
        assert field.value == "498"
        _burst(app, "home", "delete", "7", "left", "1")
        await pilot.pause()
        assert field.value == "1798"
        # the settings form's fields (f4) too
        await pilot.press("escape", "escape")
        await pilot.pause()
        await pilot.press("f4")
        await pilot.pause()
        assert isinstance(app.screen, SettingsEditor)
        name = app.screen.query_one("#f-name", Input)
        assert app.focused is name
        _burst(app, "ctrl+a", "ctrl+k", "V", "M", "C", "backspace", "X")
        await pilot.pause()
        assert name.value == "VMX"

    run(EditorApp(post), scenario)


def test_the_palette_finds_a_word_by_its_meaning(tmp_path: Path) -> None:
    """Typing ``G83`` on the EMCO post (Sinumerik: deep drilling is CYCLE83) found only
    the "G" before a computed work offset; the palette offers the deep_drill table and
    says why, as ``postdsl preview emco G83`` does."""
    from textual.widgets import OptionList

    from tui.command_table import CommandTable
    from tui.model import TableRef

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("ctrl+p")
        await pilot.pause()
        await pilot.press(*"G83")
        await pilot.pause(0.3)
        hits = app.screen.query_one(OptionList)
        said, help = str(hits.get_option_at_index(0).prompt).splitlines()
        assert said == ("G83: deep drilling on ISO controls, written here by deep_drill "
                        "as MCALL CYCLE83")
        assert help == ("go to the deep_drill table: what G83 means on ISO controls, "
                        "as this post writes it")
        await pilot.press("enter")
        await pilot.pause()
        assert app.main.current == TableRef("command", "deep_drill")
        assert app.focused is app.main.query_one(CommandTable)

    run(EditorApp(copy(tmp_path, "emco")), scenario)
