"""What a newcomer meets: every key findable and working, any NC word traced to its cell,
the machine's own samples, texts that say what they mean."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from textual.pilot import Pilot
from textual.widgets import Button, Input, OptionList, Static
from textual.widgets._footer import FooterKey

from tests.conftest import MACHINES
from tests.tui.conftest import choose, notifications, run
from tui.app import EditorApp
from tui.block_editor import BlockEditor
from tui.command_table import ITEM_COLUMN, CommandTable
from tui.commands_pane import CommandsPane
from tui.dialogs import ConfirmDialog
from tui.formats_editor import FormatsEditor
from tui.help_screen import HelpScreen
from tui.item_editor import ItemEditor, set_by
from tui.model import TableRef, problem_text, show_value
from tui.preview_pane import SampleTable
from tui.program_view import ProgramView
from tui.sample_picker import SamplePicker
from tui.trace_pane import TracePane


async def program_line(pilot: Pilot[Any], text: str) -> None:
    """Put the program's cursor on the first line starting with ``text`` (the keyboard in
    the program, as after tab)."""
    view = pilot.app.main.query_one(ProgramView)
    view.focus()
    await pilot.pause()
    view.cursor = next(i for i, line in enumerate(view.lines) if line.startswith(text))
    await pilot.pause()


def test_from_a_program_line_to_the_cell_that_wrote_a_word_in_two_keys(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        main = app.main
        await program_line(pilot, "N100 G83")  # Break Chip's cycle block
        trace = str(main.query_one(TracePane).query_one("#trace-text", Static).render())
        assert "written by table break_chip, block 3" in trace
        assert "G83            item 1: fixed text 'G83'" in trace
        await pilot.press("right")  # the word G83: the trace marks where it comes from
        trace = str(main.query_one(TracePane).query_one("#trace-text", Static).render())
        assert "▶ G83            item 1: fixed text 'G83'" in trace
        await pilot.press("enter")  # and to its cell: two keys
        assert main.current == TableRef("command", "break_chip")
        assert (main.block, main.column) == (2, ITEM_COLUMN)
        table = main.query_one(CommandTable)
        assert app.focused is table and table.cursor_coordinate == (2, ITEM_COLUMN)
        # a value's word goes to its parameter's cell: K10.0 is the peck
        await program_line(pilot, "N100 G83")
        await pilot.press(*["right"] * 8, "enter")
        assert (main.block, main.column) == (2, ITEM_COLUMN + 7)
        assert "parameter peck" in str(main.query_one("#inspector", Static).render())

    run(EditorApp(vmc500), scenario)


def test_a_structure_line_goes_to_the_structure(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await program_line(pilot, "[$CYCLE_PARAMS(2)G83_RET_DIST]")
        await pilot.press("enter")
        assert app.main.current.kind in ("structure", "command")
        trace = str(app.main.query_one(TracePane).query_one("#trace-text", Static).render())
        assert "written by table break_chip" in trace

    run(EditorApp(vmc500), scenario)


def test_the_palette_finds_the_cells_that_write_g83(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("ctrl+p")
        await pilot.pause()
        await pilot.press(*"G83")
        await pilot.pause(0.3)
        hits = app.screen.query_one(OptionList)
        first = str(hits.get_option_at_index(0).prompt)
        assert first.startswith("G83 is written by deep_drill, block 2, item 1")
        await pilot.press("enter")
        await pilot.pause()
        main = app.main
        assert main.current == TableRef("command", "deep_drill")
        assert (main.block, main.column) == (1, ITEM_COLUMN)
        assert app.focused is main.query_one(CommandTable)

    run(EditorApp(vmc500), scenario)


def footer_keys(app: EditorApp) -> list[tuple[str, str]]:
    return [(key.key, key.description) for key in app.main.query(FooterKey)
            if "-command-palette" not in key.classes]


@pytest.mark.parametrize("size", [(80, 24), (120, 40)], ids=["80x24", "120x40"])
def test_every_footer_key_works_from_the_grid(vmc500: Path, size: tuple[int, int]) -> None:
    """Each key shown opens its screen, changes the post, or says why it cannot act."""
    seen: list[str] = []

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        main = app.main
        await choose(pilot, "break_chip")
        table = main.query_one(CommandTable)
        assert app.focused is table
        keys = footer_keys(app)
        names = {key for key, _ in keys}
        # the main keys are there at both sizes, shortened at 80 columns
        assert {"f1", "ctrl+s", "ctrl+z", "ctrl+y", "f2", "f3", "f4", "f5", "f6",
                "ctrl+q"} <= names
        descriptions = dict(keys)
        assert descriptions["f2"] == ("Fmt" if size[0] < 100 else "Formats")
        for key, _description in keys:
            if key == "ctrl+q":
                continue  # last: it ends the app
            table.focus()
            table.move_cursor(row=2, column=ITEM_COLUMN + 1)
            await pilot.pause()
            before = (len(app.screen_stack), len(app._notifications), app.doc.text)
            await pilot.press(key)
            await pilot.pause()
            after = (len(app.screen_stack), len(app._notifications), app.doc.text)
            assert after != before, f"{key} did nothing"
            seen.append(key)
            while len(app.screen_stack) > 1:  # close what it opened
                await pilot.press("escape")
                await pilot.pause()
            if app.doc.dirty:
                await pilot.press("ctrl+z")
                await pilot.pause()
        await pilot.press("ctrl+q")
        await pilot.pause()
        assert not app.is_running

    run(EditorApp(vmc500), scenario, size=size)
    assert "f1" in seen and "f6" in seen


def test_keys_that_cannot_act_say_why(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        main = app.main
        await choose(pilot, "deep_drill")
        table = main.query_one(CommandTable)
        structure_row = next(b.index for b in main.blocks() if b.use is not None)
        table.move_cursor(row=structure_row, column=0)
        await pilot.pause()
        for key in ("i", "n", "a"):
            await pilot.press(key)
            await pilot.pause()
            assert f"block {structure_row + 1} inserts the structure" in notifications(app)
            app.clear_notifications()
        row = next(b.index for b in main.blocks() if b.use is None and b.items)
        table.move_cursor(row=row, column=ITEM_COLUMN)
        await pilot.pause()
        await pilot.press("shift+left")
        await pilot.pause()
        assert "item 1 is already the first of the block" in notifications(app)
        await pilot.press("v")
        await pilot.pause()
        assert "nothing copied yet (c copies)" in notifications(app)
        await choose(pilot, "tool_change")
        await pilot.press("t")
        await pilot.pause()
        assert "Tool Change already has a table" in notifications(app)
        assert isinstance(app.screen, type(main))

    run(EditorApp(vmc500), scenario)


def test_press_t_works_where_the_title_says_it(tmp_path: Path) -> None:
    post = tmp_path / "tiny.yaml"
    post.write_text("postdsl: 1\nmachine: {name: Tiny}\ncommands:\n  program_start: "
                    "{blocks: []}\n", encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "dwell")
        assert "press t to add one" in str(app.main.query_one("#table-title", Static).render())
        for widget in (CommandsPane, CommandTable, ProgramView):  # from any pane
            app.main.query_one(widget).focus()
            await pilot.pause()
            await pilot.press("t")
            await pilot.pause()
            assert app.doc.get(("commands", "dwell")) == {"blocks": []}, widget
            await pilot.press("ctrl+z")
            await pilot.pause()
            assert app.doc.get(("commands", "dwell")) is None

    run(EditorApp(post), scenario)


def test_help_lists_the_keys_and_explains_every_mark(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f1")
        await pilot.pause()
        assert isinstance(app.screen, HelpScreen)
        text = str(app.screen.query_one("#help-text", Static).render())
        for mark in ("?", "~", "!", "⇢", "·", "●", "✗", "→"):
            assert f"\n  {mark} " in text, mark
        for key in ("^s", "^z", "^y", "f2", "f5", "f6", "a ", "shift+←"):
            assert key in text, key
        # the toolpath: its keys and what each kind of line means
        assert "\n  p " in text and "\n  V " in text
        for meaning in ("a rapid move", "a cutting move", "hole", "the command selected"):
            assert meaning in text.split("The toolpath (the sample replayed")[1], meaning
        await pilot.press("f1")
        await pilot.pause()
        assert not isinstance(app.screen, HelpScreen)

    run(EditorApp(vmc500), scenario)


def test_tab_from_the_grid_lands_where_keys_act(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "break_chip")
        app.main.query_one(CommandTable).move_cursor(row=2, column=ITEM_COLUMN + 1)
        await pilot.pause()
        await pilot.press("tab")
        await pilot.pause()
        assert app.focused is not None and app.focused.id == "samples"
        await pilot.press("tab")
        await pilot.pause()
        assert isinstance(app.focused, ProgramView)
        await pilot.press("a")  # the grid's keys act from here too
        await pilot.pause()
        assert isinstance(app.screen, ItemEditor)

    run(EditorApp(vmc500), scenario)


def test_the_first_tab_in_the_formats_editor_keeps_a_typed_value(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f2")
        await pilot.pause()
        assert isinstance(app.screen, FormatsEditor)
        await pilot.press("tab")
        await pilot.pause()
        field = app.focused
        assert isinstance(field, Input) and field.id == "f-decimals"
        await pilot.press("end", *["backspace"] * len(field.value), "2", "tab")
        await pilot.pause()
        name = app.screen.current
        assert app.doc.get(("formats", name, "decimals")) == 2

    run(EditorApp(vmc500), scenario)


def test_arrow_keys_move_between_dialog_buttons(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        app.doc.edit("x", lambda data: data["variables"].__setitem__("g83_relief", 2.0))
        await pilot.press("ctrl+q")
        await pilot.pause()
        assert isinstance(app.screen, ConfirmDialog)
        assert app.focused is not None and app.focused.id == "choice-cancel"
        await pilot.press("left")
        assert app.focused.id == "choice-quit"
        await pilot.press("left")
        assert app.focused.id == "choice-save"
        await pilot.press("right", "right", "right")
        assert app.focused.id == "choice-save"  # round the row
        await pilot.press("escape")
        await pilot.pause()
        await choose(pilot, "break_chip")
        app.main.query_one(CommandTable).move_cursor(row=2, column=0)
        await pilot.press("i")
        await pilot.pause()
        assert isinstance(app.screen, BlockEditor)
        app.screen.query_one("#ok", Button).focus()
        await pilot.press("right")
        assert app.focused is not None and app.focused.id == "cancel"

    run(EditorApp(vmc500), scenario)


def test_the_showcase_opens_and_the_samples_switch_inside_the_editor(tmp_path: Path) -> None:
    post = tmp_path / "feeler.yaml"
    post.write_text((MACHINES / "feeler.yaml").read_text(encoding="utf-8"), encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        main = app.main
        view = main.query_one(ProgramView)
        assert "feeler_probe_x.jsonl" in str(view.border_title)
        # its probing cycle is marked as used (the drilling program did not use it)
        pane = main.query_one(CommandsPane)
        assert str(pane.node_for(TableRef("cycle", "probe_x")).label).startswith("● ")
        await pilot.press("f6")
        await pilot.pause()
        assert isinstance(app.screen, SamplePicker)
        options = app.screen.query_one(OptionList)
        prompts = [str(options.get_option_at_index(i).prompt)
                   for i in range(options.option_count)]
        assert prompts[0].startswith("● examples/feeler_probe_x.jsonl")
        assert "the machine's showcase" in prompts[0]
        assert any("examples/feeler_drilling.apt" in p for p in prompts)
        drilling = next(i for i, p in enumerate(prompts) if "feeler_drilling.apt" in p)
        options.highlighted = drilling
        await pilot.press("enter")
        await pilot.pause()
        assert "feeler_drilling.apt" in str(view.border_title)
        assert any(line.startswith("N") and " G83 " in line for line in view.lines)
        label = str(main.query_one(CommandsPane).node_for(TableRef("command", "deep_drill"))
                    .label)
        assert label.startswith("● ")

    run(EditorApp(post), scenario)


def test_small_texts_say_what_they_mean() -> None:
    assert set_by("peck", "single_peck", "break_chip") == " · set by this command (break_chip)"
    assert "single_peck" not in set_by("peck", "single_peck", "break_chip")
    assert show_value(("x", "z")) == "x, z" and show_value(()) == "(none)"

    class Problem:
        path = ("commands", "deep_drill", "blocks", 1, "items", 2)
        message = "unknown format 'cord'"
        location = None

    assert problem_text(Problem()) == "deep_drill, block 2, item 3: unknown format 'cord'"


def test_the_block_editor_labels_fit_their_column(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "break_chip")
        app.main.query_one(CommandTable).move_cursor(row=2, column=0)
        await pilot.press("i")
        await pilot.pause()
        labels = [str(label.render()) for label in app.screen.query(".field-label")]
        assert labels and all(len(text) < 16 for text in labels), labels

    run(EditorApp(vmc500), scenario, size=(80, 24))


def test_at_80_columns_the_command_preview_is_not_cut(vmc500: Path) -> None:
    """Break Chip's longest NC block (49 characters) fits, whichever pane has the keyboard
    (the program's pane shows the trace in the preview's place)."""

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        main = app.main
        await choose(pilot, "break_chip")
        blocks = [line.text for line in main.preview.lines if not line.text.startswith(";")]
        longest = max(len(line) for line in blocks)
        assert longest >= 45
        for pane in (CommandsPane, CommandTable, SampleTable):
            main.query_one(pane).focus()
            await pilot.pause()
            preview = main.query_one("#command-preview")
            assert preview.content_region.width >= longest, pane

    run(EditorApp(vmc500), scenario, size=(80, 24))
