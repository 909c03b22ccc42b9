"""A post that extends another: the editor shows the inherited tables, and an edit of an
inherited cell writes an override into the child only."""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

from textual.pilot import Pilot
from textual.widgets import Input

from postdsl import api
from tests.conftest import EXAMPLES, MACHINES
from tests.tui.conftest import choose, run
from tui.app import EditorApp
from tui.command_table import ITEM_COLUMN, CommandTable
from tui.item_editor import ItemEditor

CHILD = "postdsl: 1\nextends: base.yaml\nmachine:\n  name: VMC 500 child\n"


def family(tmp_path: Path) -> tuple[Path, Path]:
    base = tmp_path / "base.yaml"
    shutil.copyfile(MACHINES / "vmc500.yaml", base)
    child = tmp_path / "child.yaml"
    child.write_text(CHILD, encoding="utf-8")
    return base, child


def test_an_inherited_item_edit_becomes_an_item_override(tmp_path: Path) -> None:
    base, child = family(tmp_path)
    base_text = base.read_text(encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        assert app.doc.problems == []
        await choose(pilot, "break_chip")
        blocks = app.main.blocks()
        assert blocks and all(b.inherited for b in blocks)
        table = app.main.query_one(CommandTable)
        table.focus()
        table.move_cursor(row=2, column=ITEM_COLUMN + 1)  # {param: x, prefix: " X", …}
        await pilot.pause()
        await pilot.press("enter")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, ItemEditor)
        editor.query_one("#prefix", Input).value = " X"
        editor.query_one("#condition", Input).value = "x > 0"
        await pilot.pause()
        await pilot.press("ctrl+o")
        await pilot.pause()
        assert not isinstance(app.screen, ItemEditor)
        assert app.doc.problems == []
        assert app.doc.text == CHILD + (
            "override:\n"
            "  commands/break_chip/blocks/2/items/1: {param: x, prefix: \" X\", format: coord, "
            "if: \"x > 0\"}\n")
        item = app.doc.model.item_at(("commands", "break_chip", "blocks", 2, "items", 1))
        assert item is not None and item.condition is not None
        assert item.condition.source == "x > 0"

        # a block property of an inherited block: an override of that property only
        # (issue 27: the whole block was copied, its items no longer following the base)
        table.focus()
        table.move_cursor(row=2, column=1)
        await pilot.pause()
        await pilot.press("n")
        await pilot.pause()
        assert app.doc.problems == []
        assert app.doc.text.endswith(
            "  commands/break_chip/blocks/2/items/1: {param: x, prefix: \" X\", format: coord, "
            "if: \"x > 0\"}\n  commands/break_chip/blocks/2/number: false\n")
        block = app.doc.model.block_at(("commands", "break_chip", "blocks", 2))
        assert block is not None and block.number is False
        assert block.items[1].condition is not None
        assert app.doc.model.origin_of(("commands", "break_chip", "blocks", 2, "number"))[0] \
            is None

    run(EditorApp(child, str(EXAMPLES / "vmc500_cycles.jsonl")), scenario)
    assert base.read_text(encoding="utf-8") == base_text


def fanuc_child(tmp_path: Path) -> Path:
    """``postdsl new m2 --from fanuc --extends``, in a folder of its own."""
    shutil.copyfile(MACHINES / "fanuc.yaml", tmp_path / "fanuc.yaml")
    child = tmp_path / "m2.yaml"
    child.write_text("postdsl: 1\nextends: fanuc.yaml\n\nmachine:\n  name: m2\n",
                     encoding="utf-8")
    return child


def test_a_format_edit_on_an_extends_post_overrides_that_key_only(tmp_path: Path) -> None:
    """Issue 27: f2 on an ``extends:`` post wrote ``formats: {coord: {decimals: 2}}``,
    replacing the base's format whole (``X-10.00``: the point and trailing-zero rules were
    gone).  The edit is now an override of that one key."""
    from tui.fields import FieldForm
    from tui.formats_editor import FormatsEditor

    child = fanuc_child(tmp_path)
    text = child.read_text(encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f2")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, FormatsEditor)
        assert editor.current == "coord"
        field = editor.query_one(FieldForm).query_one("#f-decimals", Input)
        field.focus()
        await pilot.press("ctrl+a", "ctrl+k", "2", "enter")
        await pilot.pause()
        assert app.doc.problems == []
        assert app.doc.text == text + "override:\n  formats/coord/decimals: 2\n"
        spec = app.doc.model.formats["coord"].values
        assert {k: v for k, v in spec.items() if k != "multiplier"} == {
            "decimals": 2, "trailing_zeros": False, "point": "always"}
        post = app.doc.post
        assert post is not None
        nc = api.post_text(post, api.post_commands(post, api.read_cl(
            EXAMPLES / "feeler_milling.apt")))
        assert " X-10. " in nc or " X-10.\n" in nc
        assert "X-10.00" not in nc
        await pilot.press("ctrl+z")
        await pilot.pause()
        assert app.doc.text == text

    run(EditorApp(child, str(EXAMPLES / "feeler_milling.apt")), scenario)
