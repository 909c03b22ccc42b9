"""Issue 27: an editor action changes exactly the nodes it names, nothing else.

Each test here drove the editor as a technologist did when the post was changed
behind their back: these are the reproductions, kept so the bugs stay fixed.
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

from textual.pilot import Pilot
from textual.widgets import Input

from tests.conftest import MACHINES
from tests.tui.conftest import run
from tui.app import EditorApp
from tui.settings_editor import SettingsEditor


def copy(tmp_path: Path, name: str) -> Path:
    target = tmp_path / f"{name}.yaml"
    shutil.copyfile(MACHINES / f"{name}.yaml", target)
    return target


def test_f4_tabbing_through_the_form_and_setting_an_option_changes_nothing(
        tmp_path: Path) -> None:
    """The issue's keys: F4, Tab×21 (Increment), 5, Enter, Esc, ctrl+s.  Only
    ``increment`` changes; ``suffix: ""`` (an empty string the field shows as empty)
    stays, and so does every other byte."""
    post = copy(tmp_path, "emco")
    before = post.read_text(encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f4")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, SettingsEditor)
        for _ in range(21):
            await pilot.press("tab")
        await pilot.pause()
        assert app.focused is editor.query_one("#f-n_increment", Input)
        await pilot.press("ctrl+a", "ctrl+k", "5", "enter")
        await pilot.pause()
        await pilot.press("escape")
        await pilot.pause()
        await pilot.press("ctrl+s")
        await pilot.pause()

    run(EditorApp(post), scenario)
    after = post.read_text(encoding="utf-8")
    assert after == before.replace("    increment: 10\n", "    increment: 5\n", 1)


def test_setting_an_option_writes_nothing(tmp_path: Path) -> None:
    """Tabbing to an option field passes every setting: none of them may be written,
    and the option's value (the preview's) is not part of the post."""
    post = copy(tmp_path, "emco")
    before = post.read_text(encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f4")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, SettingsEditor)
        fields = [w for w in editor.query("#settings-form Input, #settings-form Select")]
        for _ in range(len(fields) - 1):  # through every field: focus and blur each
            await pilot.press("tab")
        await pilot.pause()
        await pilot.press("escape")
        await pilot.pause()
        assert not app.doc.dirty, app.doc.text
        await pilot.press("ctrl+s")
        await pilot.pause()

    run(EditorApp(post), scenario)
    assert post.read_text(encoding="utf-8") == before
