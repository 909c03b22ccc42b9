"""The backplot widget: braille dots of a known path, views, highlight, a large path off the UI."""

from __future__ import annotations

import asyncio
import itertools
import time
from typing import Any

import pytest
from textual.app import App, ComposeResult
from textual.pilot import Pilot

from postdsl.api import Segment, Toolpath
from tui.backplot import BACKPLOT_TCSS, Backplot
from tui.braille import Frame, Stopped, rasterise

SQUARE_CORNERS = [(0.0, 0.0, -1.0), (10.0, 0.0, -1.0), (10.0, 10.0, -1.0), (0.0, 10.0, -1.0),
                  (0.0, 0.0, -1.0)]

#: the square's outline in 8 × 4 cells (16 × 16 dots): every border dot set
SQUARE_XY = ["⡏⠉⠉⠉⠉⠉⠉⢹",
             "⡇⠀⠀⠀⠀⠀⠀⢸",
             "⡇⠀⠀⠀⠀⠀⠀⢸",
             "⣇⣀⣀⣀⣀⣀⣀⣸"]


def square() -> Toolpath:
    """Four sides, NC lines 10 to 13, written by linear_move; the first by a 'contour' table."""
    sides = [Segment("feed", (a, b), 10 + n, "linear_move", "contour" if n == 0 else "linear_move",
                     n + 1)
             for n, (a, b) in enumerate(itertools.pairwise(SQUARE_CORNERS))]
    return Toolpath(sides)


class PlotApp(App[None]):
    """A tiny app that mounts only the backplot, the way a screen would."""

    CSS_PATH = BACKPLOT_TCSS
    CSS = "#plot { border: none; width: 8; height: 4; }"

    def compose(self) -> ComposeResult:
        yield Backplot(id="plot")


async def settled(app: App[Any], pilot: Pilot[Any]) -> None:
    """Until every drawing worker has finished (a cancelled one counts as finished)."""
    deadline = time.monotonic() + 30
    while any(not w.is_finished for w in app.workers) and time.monotonic() < deadline:
        await pilot.pause(0.01)
    await pilot.pause()


def rows(plot: Backplot) -> list[str]:
    return [plot.render_line(y).text for y in range(plot.size.height)]


def styles(plot: Backplot, y: int) -> list[tuple[str, Any]]:
    return [(s.text, s.style) for s in plot.render_line(y)]


def run(scenario: Any, size: tuple[int, int] = (20, 8)) -> None:
    async def main() -> None:
        app = PlotApp()
        async with app.run_test(size=size) as pilot:
            await scenario(app, pilot, app.query_one(Backplot))
    asyncio.run(main())


def test_the_square_from_above_is_its_outline() -> None:
    async def scenario(app: PlotApp, pilot: Pilot[Any], plot: Backplot) -> None:
        assert rows(plot)[0] == "no motion to draw"[:8]
        plot.show_path(square())
        await settled(app, pilot)
        assert rows(plot) == SQUARE_XY
    run(scenario)


def test_v_switches_to_the_front_and_side_views() -> None:
    async def scenario(app: PlotApp, pilot: Pilot[Any], plot: Backplot) -> None:
        path = square()
        plunge = Segment("feed", ((0.0, 0.0, 9.0), (0.0, 0.0, -1.0)), 9, "linear_move",
                         "linear_move", 1)
        plot.show_path(Toolpath([plunge, *path.segments]))
        await settled(app, pilot)
        plot.focus()
        await pilot.press("v")
        await settled(app, pilot)
        assert plot.view == "xz"
        assert "XZ front" in str(plot.border_title)
        # from the front: the plunge down the left edge, the square a line along the bottom
        assert rows(plot) == ["⡇⠀⠀⠀⠀⠀⠀⠀",
                              "⡇⠀⠀⠀⠀⠀⠀⠀",
                              "⡇⠀⠀⠀⠀⠀⠀⠀",
                              "⣇⣀⣀⣀⣀⣀⣀⣀"]
        await pilot.press("v")
        await settled(app, pilot)
        assert plot.view == "yz" and rows(plot)[3] == "⣇⣀⣀⣀⣀⣀⣀⣀"
        await pilot.press("v")
        assert plot.view == "xy"
    run(scenario)


def test_rapids_are_drawn_every_other_dot() -> None:
    points = ((0.0, 0.0, 0.0), (15.0, 0.0, 0.0))
    frame = Frame.fitting([Segment("rapid", points, 1)], "xy", 8, 4)
    # 15 mm over 16 dots, centred in the 16 dot rows: dots 0 … 15 of dot row 8
    rapid = rasterise([Segment("rapid", points, 1)], frame)
    assert [rapid.row_text(row) for row in range(4)] == ["⠀" * 8, "⠀" * 8, "⠁" * 8, "⠀" * 8]
    solid = rasterise([Segment("feed", points, 1)], frame)
    assert solid.row_text(2) == "⠉" * 8


def test_a_tilted_tool_axis_is_drawn_dotted_as_a_direction() -> None:
    """A 3+2 program's tool axis (kind ``axis``) is drawn, every other dot, not as a cut."""
    points = ((0.0, 0.0, 0.0), (15.0, 0.0, 0.0))
    frame = Frame.fitting([Segment("axis", points, 1)], "xy", 8, 4)
    axis = rasterise([Segment("axis", points, 1)], frame)
    assert [axis.row_text(row) for row in range(4)] == ["⠀" * 8, "⠀" * 8, "⠁" * 8, "⠀" * 8]


def test_a_commands_moves_are_highlighted() -> None:
    async def scenario(app: PlotApp, pilot: Pilot[Any], plot: Backplot) -> None:
        plot.show_path(square())
        await settled(app, pilot)
        lit = plot.get_component_rich_style("backplot--highlight")
        feed = plot.get_component_rich_style("backplot--feed")
        assert lit != feed
        assert all(style == feed for _, style in styles(plot, 3))
        plot.highlight_table("contour")  # the first side: the bottom edge, Y0
        assert plot.highlight == frozenset({10})
        await settled(app, pilot)
        bottom = styles(plot, 3)
        assert "".join(t for t, _ in bottom) == SQUARE_XY[3]
        assert all(style == lit for _, style in bottom)
        assert all(style == feed for _, style in styles(plot, 0))  # the top edge stays
        plot.highlight = frozenset()
        await settled(app, pilot)
        assert all(style == feed for _, style in styles(plot, 3))
    run(scenario)


@pytest.mark.slow  # a 100 ms wall-clock bound while drawing a large path
def test_a_large_path_is_drawn_off_the_ui_thread() -> None:
    """200 000 segments: keys are handled while the worker rasterises them."""
    count = 200_000
    segments = [Segment("feed" if i % 3 else "rapid",
                        ((i % 500 * 0.2, i // 500 * 0.5, 0.0),
                         ((i + 1) % 500 * 0.2, (i + 1) // 500 * 0.5, -1.0)), i + 1)
                for i in range(count)]

    async def scenario(app: PlotApp, pilot: Pilot[Any], plot: Backplot) -> None:
        plot.styles.width = 100
        plot.styles.height = 40
        await pilot.pause()
        plot.focus()
        started = time.perf_counter()
        plot.show_path(Toolpath(segments))
        returned = time.perf_counter() - started
        assert plot.drawing
        assert returned < 0.1  # the UI thread only starts the worker
        changed: list[float] = []
        plot.watch(plot, "view", lambda _: changed.append(time.perf_counter()), init=False)
        pressed = time.perf_counter()
        await pilot.press("v")  # handled while drawing: the view changes at once
        print(f"key handled in {changed[0] - pressed:.3f} s while drawing; press returned "
              f"after {time.perf_counter() - pressed:.3f} s")
        assert plot.view == "xz"
        assert changed[0] - pressed < 0.1  # issue 14: no keystroke blocked for 100 ms
        await settled(app, pilot)
        assert not plot.drawing
        assert any(row.strip("⠀") for row in rows(plot))
    run(scenario, size=(110, 45))


def test_a_picture_no_longer_wanted_stops_rasterising() -> None:
    segments = square().segments * 2000
    frame = Frame.fitting(segments, "xy", 8, 4)
    asked: list[int] = []

    def stop() -> bool:
        asked.append(1)
        return len(asked) > 1

    with pytest.raises(Stopped):
        rasterise(segments, frame, stop)
    assert len(asked) == 2  # asked at the start and once more, a few thousand segments on
    assert rasterise(segments, frame, lambda: False).row_text(0) == SQUARE_XY[0]
