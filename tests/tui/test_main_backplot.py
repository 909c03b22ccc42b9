"""The toolpath on the main screen: the sample replayed, the selected command lit, p and V."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import pytest
from textual.pilot import Pilot

from postdsl import api
from tests.tui.conftest import choose, run
from tests.tui.test_responsive import long_program, posted
from tui.app import EditorApp
from tui.backplot import Backplot
from tui.preview_pane import PreviewPane
from tui.program_view import ProgramView


async def drawn(app: EditorApp, pilot: Pilot[Any], timeout: float = 120) -> Backplot:
    """Until no worker (posting, replaying, rasterising) is under way."""
    deadline = time.monotonic() + timeout
    while app.main.posting or any(not w.is_finished for w in app.workers):
        assert time.monotonic() < deadline, "the toolpath was never drawn"
        await pilot.pause(0.02)
    await pilot.pause()
    return app.main.query_one(Backplot)


def hole_points(plot: Backplot, table: str) -> set[tuple[float, float]]:
    """(X, Y) of the holes a table drilled, as the backplot has them."""
    return {segment.points[0][:2] for segment in plot.segments
            if segment.table == table and segment.kind == "hole"}


def test_the_backplot_replays_the_sample_and_lights_the_selected_command(
        vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        plot = await drawn(app, pilot)
        assert plot.display and plot.size.width >= 30  # beside the program at 120 columns
        # the same path `postdsl plot` draws: the sample posted and replayed by the control model
        post = api.load_post(vmc500)
        sample = app.main.sample
        _, expected = api.toolpath(post, sample.commands, cl_file=sample.name)
        assert list(plot.segments) == expected.segments and expected.segments
        await choose(pilot, "break_chip")
        await drawn(app, pilot)
        lines = app.main.query_one(ProgramView).lines
        lit = plot.highlight
        assert lit and all("G83" in lines[number - 1] for number in lit)
        assert lit == {s.nc_line for s in plot.segments if s.table == "break_chip"}
        assert any(style == plot.get_component_rich_style("backplot--highlight")
                   for y in range(plot.size.height) for _, style, _ in plot.render_line(y))
        await choose(pilot, "rapid_move")
        assert plot.highlight and plot.highlight.isdisjoint(lit)
        assert all(" G0" in lines[number - 1] or lines[number - 1].startswith("G0")
                   for number in plot.highlight)
        await choose(pilot, "gage_height", kind="structure")
        assert plot.highlight == frozenset()  # a structure is no command of the program

    run(EditorApp(vmc500), scenario)


def test_an_edit_replays_the_program_again(vmc500: Path) -> None:
    """Break Chip writing Y with the X value moves its hole: the picture follows the post."""
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        plot = await drawn(app, pilot)
        assert hole_points(plot, "break_chip") == {(60.0, 20.0)}
        app.main.change("Y from x", lambda data: data["commands"]["break_chip"]["blocks"][2][
            "items"][2].__setitem__("param", "x"))
        plot = await drawn(app, pilot)
        assert hole_points(plot, "break_chip") == {(60.0, 60.0)}
        assert app.main.plotted is not None and app.main.plotted.post_text == app.doc.text
        # a post with problems has no path: the pane says why instead of an old picture
        app.main.change("broken", lambda data: data["commands"]["break_chip"]["blocks"][2][
            "items"][2].__setitem__("format", "no_such_format"))
        plot = await drawn(app, pilot)
        assert not plot.segments and "problems" in plot.note
        assert "problems" in plot.render_line(0).text
        await pilot.press("ctrl+z")
        plot = await drawn(app, pilot)
        assert hole_points(plot, "break_chip") == {(60.0, 60.0)} and not plot.note

    run(EditorApp(vmc500), scenario)


def test_p_and_V_from_the_grid_at_80_columns(vmc500: Path) -> None:
    """At 80×24 the toolpath waits for p, then takes the command preview's room; V turns
    it from anywhere; p again gives the preview back."""
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await choose(pilot, "break_chip")  # enter: the keyboard is in the grid
        plot = await drawn(app, pilot)
        preview = app.main.query_one(PreviewPane)
        assert not plot.display and preview.display
        await pilot.press("p")
        await drawn(app, pilot)
        assert plot.display and not preview.display
        assert plot.size.width >= 25 and plot.size.height >= 8
        assert any(plot.render_line(y).text.strip("⠀ ") for y in range(plot.size.height))
        await pilot.press("V")
        assert plot.view == "xz" and "XZ front" in str(plot.border_title)
        await pilot.press("V", "V")
        assert plot.view == "xy"
        await pilot.press("p")
        assert not plot.display and preview.display

    run(EditorApp(vmc500), scenario, size=(80, 24))


def test_V_shows_a_hidden_toolpath_at_120_columns(vmc500: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        plot = await drawn(app, pilot)
        assert plot.display
        await pilot.press("p")
        assert not plot.display
        await pilot.press("V")
        assert plot.display and plot.view == "xz"

    run(EditorApp(vmc500), scenario)


@pytest.mark.slow  # posts a long sample program in the editor's process
def test_a_long_samples_toolpath_comes_from_the_posting_process(vmc500: Path,
                                                                 tmp_path: Path) -> None:
    moves = 20_000
    sample = long_program(tmp_path / "long.jsonl", moves=moves)

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        assert not app.main.sample.small
        await posted(app, pilot)
        plot = await drawn(app, pilot)
        _, expected = api.toolpath(api.load_post(vmc500), api.read_cl(sample),
                                   cl_file=sample.name)
        assert list(plot.segments) == expected.segments  # none lost on the way
        feeds = [s for s in plot.segments if s.kind == "feed"]
        # every linear move but the first, which starts where the rapid left the tool
        assert len(feeds) == moves - 3 - 1
        await choose(pilot, "linear_move")
        assert len(plot.highlight) == len(feeds)

    run(EditorApp(vmc500, sample), scenario)


def test_a_post_without_a_control_model_says_why_there_is_no_picture(tmp_path: Path) -> None:
    post = tmp_path / "tiny.yaml"
    post.write_text("postdsl: 1\nmachine: {name: Tiny, tool_changer: false}\n"
                    "formats: {c: {decimals: 3}}\n"
                    "commands:\n  program_start: {blocks: []}\n"
                    "  program_end: {blocks: [{items: [M30]}]}\n"
                    "  rapid_move: {blocks: [{items: [G0, {param: x, prefix: ' X', "
                    "format: c}]}]}\n", encoding="utf-8")
    sample = tmp_path / "one.jsonl"
    sample.write_text('{"cmd": "rapid_move", "x": 5, "y": 0, "z": 0}\n'
                      '{"cmd": "program_end"}\n', encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        assert app.doc.post is not None and app.doc.post.machine.control is None
        assert app.main.query_one(ProgramView).lines == ["N10 G0 X5.000", "N20 M30"]
        plot = await drawn(app, pilot)
        assert not plot.segments
        assert "declares no machine/control" in plot.note
        shown = " ".join(plot.render_line(y).text.strip() for y in range(plot.size.height))
        assert "the post declares no machine/control" in shown

    run(EditorApp(post, sample), scenario)
