"""A long sample program is posted off the UI thread: keys never wait for it."""

from __future__ import annotations

import asyncio
import json
import resource
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from textual import events
from textual.pilot import Pilot
from textual.widgets import Static

from tests.tui.conftest import run
from tui.app import EditorApp
from tui.commands_pane import CommandsPane
from tui.program_view import ProgramView
from tui.trace_pane import TracePane

# 200 000-line programs posted while keys are timed: CI runs these in the slow step
pytestmark = pytest.mark.slow

LINES = 200_000


def long_program(path: Path, moves: int = LINES) -> Path:
    """A finishing-like program: one tool, then ``moves`` feed moves zig-zagging in X."""
    head = [{"cmd": "tool_change", "tool_number": 1, "tool_type": "drill", "tool_diameter": 8},
            {"cmd": "spindle_on", "spindle_speed": 3000, "spindle": "cw"},
            {"cmd": "rapid_move", "x": 10, "y": 10, "z": 50}]
    with path.open("w", encoding="utf-8") as out:
        for record in head:
            out.write(json.dumps(record) + "\n")
        for index in range(moves - len(head)):
            move = {"cmd": "linear_move", "x": 10 + (index % 200) * 0.5,
                    "y": 10 + (index // 200) * 0.05, "feed": 800}
            out.write(json.dumps(move) + "\n")
        out.write('{"cmd": "program_end"}\n')
    return path


def children_cpu() -> float:
    """CPU seconds of the editor's ended child processes (the posting processes)."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


async def posted(app: EditorApp, pilot: Pilot[Any], timeout: float = 120) -> None:
    """Wait until no posting is under way (a replaced worker is cancelled, not completed)."""
    end = time.monotonic() + timeout
    while app.main.posting:
        assert time.monotonic() < end, "the sample program was never posted"
        await pilot.pause(0.1)
    await pilot.pause()


#: UI-thread CPU seconds spent calibrating (not the editor's work)
CALIBRATION: list[float] = []


def calibrate(rounds: int = 1) -> float:
    """UI-thread CPU seconds of a fixed piece of pure-Python work (the best of ``rounds``).

    CPU time is not lengthened by waiting for a core, but a core shared with other busy
    processes (a hyperthread sibling, a thrashed cache) runs slower: the same work costs
    more CPU time.  Timing this fixed work next to each key tells how much slower the
    core was at that moment than at its best, so a key's cost can be stated at the
    machine's undisturbed speed.
    """
    best = float("inf")
    began = time.thread_time()
    for _ in range(rounds):
        start = time.thread_time()
        words: dict[str, int] = {}
        for index in range(4_000):
            key = f"N{index % 500} G1 X{index * 0.5:.3f}"
            words[key] = words.get(key, 0) + len(key.split())
        best = min(best, time.thread_time() - start)
    CALIBRATION.append(time.thread_time() - began)
    return best


@dataclass(frozen=True)
class ShownKey:
    """A key's cost until the screen showed its effect, on the UI thread."""

    #: UI-thread CPU seconds from the key reaching the app to the screen update showing it
    ui: float
    #: the same at the core's undisturbed speed (``ui`` divided by the slowdown)
    normalised: float
    #: wall-clock seconds, for the report only (a loaded machine lengthens them)
    wall: float


async def key_to_screen(app: EditorApp, key: str, shown: Callable[[], bool],
                        best: float, timeout: float = 30) -> ShownKey:
    """Send ``key`` as the terminal driver does; measure until a screen update is painted
    while ``shown()`` holds (the compositor's output, headless or not, goes through
    ``App._display``).  Waiting is on an event set from that hook: no polling loop runs
    on the UI thread to inflate its CPU time."""
    painted = asyncio.Event()
    stamp: list[tuple[float, float]] = []
    display = app._display

    def watching(screen: Any, renderable: Any) -> None:
        display(screen, renderable)
        if renderable is not None and not painted.is_set() and shown():
            stamp.append((time.thread_time(), time.perf_counter()))
            painted.set()

    slowdown = max(1.0, calibrate() / best)
    event = events.Key(key, None)
    event.set_sender(app)
    app._display = watching  # type: ignore[method-assign]
    try:
        ui, wall = time.thread_time(), time.perf_counter()
        assert app._driver is not None
        app._driver.send_message(event)
        await asyncio.wait_for(painted.wait(), timeout)
    finally:
        del app._display  # the class's method again
    slowdown = max(slowdown, calibrate() / best)
    cpu = stamp[0][0] - ui
    return ShownKey(cpu, cpu / slowdown, stamp[0][1] - wall)


def test_a_keystroke_reaches_the_screen_within_100_ms_while_a_long_program_posts(
        vmc500: Path, tmp_path: Path) -> None:
    """Keys down the command list, each shown on screen, while 200 000 lines post, and
    up again right after they arrived, while the toolpath is replayed.

    What is measured is the UI thread's CPU time from the key reaching the app to the
    painted screen update that shows it: the key's handling, the previews it refreshes,
    the collector passes it triggers and the compositor's repaint.  Wall-clock time would
    measure the machine's load instead (other test runs on both cores hold the editor
    off a core for 100-300 ms now and then), but CPU time is not lengthened by waiting.
    A busy sibling on the same core still slows the core itself, so each key is
    bracketed by a fixed calibration workload: its CPU cost compared with the best of
    30 runs at the start gives the slowdown, and the key's CPU time divided by it is
    what the key costs at the machine's undisturbed speed; that must stay ≤ 100 ms.
    Posting on the UI thread (5 s of CPU) could not pass.  A worker thread of the
    editor holding the interpreter lock shows in the process's CPU time instead, and
    over the whole posting the editor must spend clearly less CPU than the posting
    process spent.
    """
    sample = long_program(tmp_path / "long.jsonl")
    times: list[ShownKey] = []
    spent: list[float] = []

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        editor, children = time.process_time(), children_cpu()
        CALIBRATION.clear()
        best = calibrate(30)
        main = app.main
        view = main.query_one(ProgramView)
        assert main.posting and "posting…" in str(view.border_title)
        pane = main.query_one(CommandsPane)
        shown = {main.current}
        pane.move_cursor(pane.get_node_at_line(0))
        pane.focus()
        await pilot.pause()
        for _ in range(8):
            line = pane.cursor_line
            node = pane.get_node_at_line(line + 1)

            def moved(line: int = line, node: Any = node) -> bool:
                # the cursor moved, and the command under it is the one shown
                return pane.cursor_line == line + 1 and (
                    node is None or node.data is None or main.current == node.data)

            times.append(await key_to_screen(app, "down", moved, best))
            assert main.posting  # …while the program was still being posted
            shown.add(main.current)
            await asyncio.sleep(0.1)
        assert len(shown) >= 4
        await posted(app, pilot)
        # right after the program arrives: the toolpath is replayed and received now
        assert any(w.group == "toolpath" and not w.is_finished for w in app.workers)
        for _ in range(4):
            line = pane.cursor_line
            times.append(await key_to_screen(
                app, "up", lambda line=line: pane.cursor_line == line - 1, best))
            await asyncio.sleep(0.1)
        while any(w.group == "program" and not w.is_finished for w in app.workers):
            await pilot.pause(0.01)  # until the posting process has ended and been waited for
        spent.extend((time.process_time() - editor - sum(CALIBRATION),
                      children_cpu() - children))
        assert len(view.lines) >= LINES
        assert "posting…" not in str(view.border_title)

    run(EditorApp(vmc500, sample), scenario)
    figures = [f"{t.normalised * 1000:.0f} ms ({t.ui * 1000:.0f} ms UI CPU, "
               f"{t.wall * 1000:.0f} ms on the clock)" for t in times]
    print("keystroke to screen:", figures)
    assert all(t.normalised <= 0.1 for t in times), figures
    editor_cpu, posting_cpu = spent
    print(f"CPU while posting: editor {editor_cpu:.2f} s, posting process {posting_cpu:.2f} s")
    assert posting_cpu > 1.0  # the 200 000 lines were posted by another process…
    # …not by the editor's: posting in any of its threads would cost it at least as much
    # CPU as the posting process spends (the same work); receiving and indexing the lines,
    # repainting the growing program and the keys cost it a part (0.7-2 s, depending on
    # the machine's load, as the posting process's 6-7.5 s do)
    assert editor_cpu < posting_cpu / 2


def test_the_newest_edit_wins(vmc500: Path, tmp_path: Path) -> None:
    """Two edits while a long program posts: the program shown is the one of the last."""
    sample = long_program(tmp_path / "long.jsonl", moves=20_000)

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        main = app.main
        app.doc.edit("first", lambda data: data["commands"]["linear_move"]["blocks"][0][
            "items"].insert(0, " (A)"))
        main.repost()
        app.doc.edit("second", lambda data: data["commands"]["linear_move"]["blocks"][0][
            "items"].__setitem__(0, " (B)"))
        main.repost()
        await posted(app, pilot)
        lines = main.query_one(ProgramView).lines
        moves = [line for line in lines if "G1" in line]
        assert moves and all("(B)" in line for line in moves)
        assert not any("(A)" in line for line in lines)

    run(EditorApp(vmc500, sample), scenario)


def test_a_line_of_a_long_program_is_traced_off_the_ui_thread(vmc500: Path,
                                                              tmp_path: Path) -> None:
    sample = long_program(tmp_path / "long.jsonl", moves=20_000)

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        main = app.main
        await posted(app, pilot)
        view = main.query_one(ProgramView)
        view.focus()
        await pilot.pause()
        view.cursor = 15_000
        await pilot.pause()
        pane = main.query_one(TracePane)
        assert "tracing line 15001…" in str(pane.query_one("#trace-text", Static).render())
        end = time.monotonic() + 120
        while pane.traced is None or pane.traced.number != 15_001:
            assert time.monotonic() < end, "the line was never traced"
            await pilot.pause(0.1)
        assert pane.traced.line.text == view.lines[15_000]
        assert pane.traced.record.name == "linear_move"
        await pilot.press("right", "enter")
        assert main.current.name == "linear_move"

    run(EditorApp(vmc500, sample), scenario)
