"""The review screen (f5): the NC diff of the unsaved edits, seen before saving.

The post is a copy of vmc500.yaml with a corpus.yaml beside it listing copies
of three example programs, so the screen posts exactly those (and shows short,
stable program names).  Edits go through the editor's own dialogs, as a
technologist would make them; nothing is saved unless a test says so.
"""

from __future__ import annotations

import re
import shutil
import threading
from pathlib import Path
from typing import Any

import pytest
from syrupy.extensions.image import SVGImageSnapshotExtension
from textual.pilot import Pilot
from textual.widgets import DataTable, Input, Static

from postdsl import review
from tests.conftest import EXAMPLES, MACHINES
from tests.tui.conftest import go_to, run
from tests.tui.test_editors import type_into
from tests.tui.test_technologist import edit_text_item
from tui.app import EditorApp
from tui.formats_editor import FormatsEditor
from tui.review_screen import DiffView, ReviewScreen
from tui.settings_editor import SettingsEditor

PROGRAMS = ("vmc500_cycles.jsonl", "feeler_milling.apt", "emco_drilling.jsonl")

# The thesis program's two G83 blocks (section 7.1); the cycle format writes their depth.
N70 = "N70 G83 X40. Y20. Z53.0043 R70.0 F200.0 J13 K10.0"
N100 = "N100 G83 X60. Y20. Z53.0043 R70.0 F200.0 J11 K10.0"


@pytest.fixture
def corpus(vmc500: Path) -> Path:
    """corpus.yaml beside the copied post, listing copies of three example programs."""
    folder = vmc500.parent / "examples"
    folder.mkdir()
    for name in PROGRAMS:
        shutil.copyfile(EXAMPLES / name, folder / name)
    # the VMC500 refuses what its cycles cannot write (a retract plane above R, a dwell
    # on G83 or G84.1): the drilling program without those values is posted
    drilling = folder / "emco_drilling.jsonl"
    drilling.write_text(re.sub(r'"retract": [\d.]+, |"dwell": 0\.[12], ', "",
                               drilling.read_text(encoding="utf-8")), encoding="utf-8")
    (vmc500.parent / "corpus.yaml").write_text(
        "vmc500:\n" + "".join(f"  - examples/{name}\n" for name in PROGRAMS), encoding="utf-8")
    return vmc500


@pytest.fixture
def svg_snapshot(snapshot: Any) -> Any:
    return snapshot.use_extension(SVGImageSnapshotExtension)


async def open_review(pilot: Pilot[Any]) -> ReviewScreen:
    """f5, then wait for the posting worker and the screen it fills."""
    await pilot.press("f5")
    await settle(pilot)
    screen = pilot.app.screen
    assert isinstance(screen, ReviewScreen)
    return screen


async def settle(pilot: Pilot[Any]) -> None:
    await pilot.pause()
    await pilot.app.workers.wait_for_complete()
    await pilot.pause()


def rows(screen: ReviewScreen) -> dict[str, tuple[str, str]]:
    """program -> (verdict, line counts) as the list shows them."""
    table = screen.query_one("#review-programs", DataTable)
    if not table.display:
        return {}
    result = {}
    for key in table.rows:
        status, program, counts = (str(cell) for cell in table.get_row(key))
        result[program] = (status, counts)
    return result


def shown(screen: ReviewScreen, widget: str) -> str:
    return str(screen.query_one(widget, Static).render())


def changed_lines(screen: ReviewScreen) -> tuple[list[str], list[str]]:
    """The removed and the added NC lines of the selected program's diff."""
    lines = screen.query_one(DiffView).lines
    removed = [line[1:] for line in lines if line.startswith("-") and
               not line.startswith("---")]
    added = [line[1:] for line in lines if line.startswith("+") and not line.startswith("+++")]
    return removed, added


async def set_cycle_decimals(pilot: Pilot[Any], decimals: str) -> None:
    """Through the formats editor: the cycle format's decimals, committed with enter."""
    await pilot.press("f2")
    await pilot.pause()
    editor = pilot.app.screen
    assert isinstance(editor, FormatsEditor)
    await pilot.press("down")
    await pilot.pause()
    assert editor.current == "cycle"
    await type_into(pilot, editor.query_one("#f-decimals", Input), decimals)
    await pilot.press("enter", "escape")
    await pilot.pause()


def test_format_change_is_reviewed_before_saving(corpus: Path) -> None:
    original = corpus.read_text(encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        # 4 -> 3: Z53.0043 -> Z53.004, the same hole at the machine's 0.001 mm
        await set_cycle_decimals(pilot, "3")
        assert app.doc.get(("formats", "cycle", "decimals")) == 3 and app.doc.dirty
        screen = await open_review(pilot)
        listed = rows(screen)
        assert list(listed) == [f"examples/{name}" for name in PROGRAMS]
        assert listed["examples/vmc500_cycles.jsonl"] == ("format only", "+2 -2")
        assert listed["examples/feeler_milling.apt"] == ("unchanged", "")  # no cycles
        assert listed["examples/emco_drilling.jsonl"] == ("unchanged", "")  # depths fit in 2
        # the first changed program is selected: exactly its two G83 lines change
        assert screen.selected == "examples/vmc500_cycles.jsonl"
        assert app.focused is screen.query_one("#review-programs")  # ↑↓ choose at once
        assert changed_lines(screen) == (
            [N70, N100], [N70.replace("53.0043", "53.004"), N100.replace("53.0043", "53.004")])
        diff = screen.query_one(DiffView).lines
        assert diff[:2] == ["--- vmc500 @ saved: examples/vmc500_cycles.jsonl",
                            "+++ vmc500 @ unsaved: examples/vmc500_cycles.jsonl"]
        assert " N80 G80" in diff  # context lines keep their block numbers
        assert "examples/vmc500_cycles.jsonl: +2 -2 lines" in shown(screen, "#review-detail")
        assert shown(screen, "#review-summary") == \
            "3 programs: 1 changed (+2 -2 lines), 2 unchanged"
        assert "posted with both: the 3 programs corpus.yaml lists for vmc500" in \
            shown(screen, "#review-title")

        await pilot.press("down")  # an unchanged program: no diff, and the screen says so
        await pilot.pause()
        assert screen.selected == "examples/feeler_milling.apt"
        assert screen.query_one(DiffView).lines == []
        assert "the same with the saved file" in screen.note
        await pilot.press("n")  # the next changed program (wrapping around)
        await pilot.pause()
        assert screen.selected == "examples/vmc500_cycles.jsonl"
        await pilot.press("down")

        # undo while the screen is open: nothing is unsaved any more; redo: changed again
        await pilot.press("ctrl+z")
        await settle(pilot)
        assert app.screen is screen
        assert shown(screen, "#review-summary") == "no unsaved changes"
        assert rows(screen) == {}
        await pilot.press("ctrl+y")
        await settle(pilot)
        assert rows(screen)["examples/vmc500_cycles.jsonl"] == ("format only", "+2 -2")
        assert screen.selected == "examples/feeler_milling.apt"  # the selection is kept
        assert app.focused is screen.query_one("#review-programs")

        await pilot.press("escape")
        await pilot.pause()
        assert app.screen is app.main
        await open_review(pilot)
        await pilot.press("f5")  # the key that opens it closes it
        await pilot.pause()
        assert app.screen is app.main

    run(EditorApp(corpus), scenario)
    assert corpus.read_text(encoding="utf-8") == original  # reviewed, never saved


def test_unchanged_document_has_no_unsaved_changes(corpus: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        screen = await open_review(pilot)
        assert rows(screen) == {}
        assert shown(screen, "#review-summary") == "no unsaved changes"
        assert screen.note.startswith(
            "no unsaved changes: the post is as saved in vmc500.yaml")

    run(EditorApp(corpus), scenario)


def test_block_number_start_is_renumbering_only(corpus: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await pilot.press("f4")
        await pilot.pause()
        editor = app.screen
        assert isinstance(editor, SettingsEditor)
        await type_into(pilot, editor.query_one("#f-n_start", Input), "20")
        await pilot.press("enter", "escape")
        await pilot.pause()
        assert app.doc.get(("output", "block_numbers", "start")) == 20
        screen = await open_review(pilot)
        listed = rows(screen)
        assert [status for status, _ in listed.values()] == ["renumbering only"] * 3
        assert listed["examples/vmc500_cycles.jsonl"] == ("renumbering only", "23 numbers")
        assert "renumbering only (23 block numbers; first: 'N10  T1 M6' -> 'N20  T1 M6')" \
            in shown(screen, "#review-detail")
        assert screen.query_one(DiffView).lines == []  # not hundreds of changed lines
        assert "Only block numbers differ" in screen.note
        assert shown(screen, "#review-summary") == "3 programs: 3 renumbering only"

    run(EditorApp(corpus), scenario)


def test_without_a_corpus_entry_the_sample_program_is_reviewed(tmp_path: Path) -> None:
    """A post corpus.yaml does not know (here 'mill') is reviewed with the editor's --cl."""
    post = tmp_path / "mill.yaml"
    shutil.copyfile(MACHINES / "vmc500.yaml", post)

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await go_to(pilot, "Break Chip")
        await edit_text_item(pilot, row=2, item=6, old="J11", new="J1")
        screen = await open_review(pilot)
        # J1 is another Acramatic G83 than the CL's chip breaking: post would refuse it
        assert rows(screen) == {"vmc500_cycles.jsonl": ("newly refused", "+1 -1")}
        assert changed_lines(screen) == ([N100], [N100.replace("J11", "J1")])
        assert "the sample program vmc500_cycles.jsonl (corpus.yaml lists no programs for " \
               "mill)" in shown(screen, "#review-title")

    run(EditorApp(post, cl=EXAMPLES / "vmc500_cycles.jsonl"), scenario)


def test_post_with_problems_is_not_posted(corpus: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        screen = await open_review(pilot)
        await set_cycle_decimals(pilot, "3")  # edits under the open screen refresh it
        await settle(pilot)
        assert rows(screen)["examples/vmc500_cycles.jsonl"][0] == "format only"
        # min_decimals 1 > decimals 0: the post has a problem, so nothing can be posted
        await set_cycle_decimals(pilot, "0")
        await settle(pilot)
        assert app.doc.post is None
        assert rows(screen) == {}
        assert "the unsaved post has 1 problem" in shown(screen, "#review-summary")
        assert "min_decimals" in screen.note

    run(EditorApp(corpus), scenario)


def test_saved_file_with_problems_is_named(corpus: Path) -> None:
    """Saved anyway with a problem, then fixed: the saved side cannot be posted, and says so."""
    text = corpus.read_text(encoding="utf-8")
    corpus.write_text(text.replace("    decimals: 4\n", "    decimals: 0\n", 1), encoding="utf-8")

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        assert app.doc.problems
        await set_cycle_decimals(pilot, "4")
        assert app.doc.post is not None
        screen = await open_review(pilot)
        assert rows(screen) == {}
        assert shown(screen, "#review-summary") == "the change cannot be reviewed"
        assert screen.note.startswith("the saved file is not a valid post")
        assert "vmc500.yaml (saved):" in screen.note and "min_decimals" in screen.note

    run(EditorApp(corpus), scenario)


def test_posting_runs_in_a_worker_and_stale_results_are_dropped(
        corpus: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    release = threading.Event()
    real = review.review_texts

    def slow(*args: Any, **kwargs: Any) -> list[review.ProgramDiff]:
        assert release.wait(10)
        return real(*args, **kwargs)

    monkeypatch.setattr(review, "review_texts", slow)

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await set_cycle_decimals(pilot, "3")
        await pilot.press("f5")
        await pilot.pause()
        screen = app.screen
        assert isinstance(screen, ReviewScreen)
        assert screen.query_one("#review-body").loading  # posting: a loading indicator
        assert shown(screen, "#review-summary") == "posting…"
        # the UI still answers keys while the worker posts: undo, then redo
        await pilot.press("ctrl+z")
        await pilot.pause()
        assert shown(screen, "#review-summary") == "no unsaved changes"
        assert not screen.query_one("#review-body").loading
        release.set()
        await settle(pilot)
        # the blocked worker posted texts that are no longer current: not shown
        assert shown(screen, "#review-summary") == "no unsaved changes"
        await pilot.press("ctrl+y")
        await settle(pilot)
        assert rows(screen)["examples/vmc500_cycles.jsonl"] == ("format only", "+2 -2")

    run(EditorApp(corpus), scenario)


def test_saving_while_open_leaves_nothing_unsaved(corpus: Path) -> None:
    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await set_cycle_decimals(pilot, "3")
        screen = await open_review(pilot)
        assert rows(screen)
        await pilot.press("ctrl+s")
        await settle(pilot)
        assert not app.doc.dirty
        assert shown(screen, "#review-summary") == "no unsaved changes"

    run(EditorApp(corpus), scenario)
    assert "decimals: 3" in corpus.read_text(encoding="utf-8")


def test_review_screen_snapshot(corpus: Path, svg_snapshot: Any) -> None:
    pictures: list[str] = []

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await go_to(pilot, "Break Chip")
        await edit_text_item(pilot, row=2, item=6, old="J11", new="J1")
        await open_review(pilot)
        await pilot.wait_for_scheduled_animations()
        for _ in range(3):  # tables size their columns when idle
            await pilot.pause(0.05)
        pictures.append(app.export_screenshot(title="postdsl edit"))

    run(EditorApp(corpus), scenario, size=(120, 40))
    assert pictures[0] == svg_snapshot


def test_a_motion_change_shows_its_verdict_and_where_the_motion_first_differs(
        corpus: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The list says which programs move differently, not only that lines changed; the
    detail locates the first motion difference (CL line, the NC line on both sides).

    The unsaved text also writes the X Y Z rapid as two blocks, Z first (the benchmark's
    motion change, which no dialog makes in one step): a rapid moving all three axes
    together now takes another path."""
    from benchmarks.review_scale import RAPID, RAPID_Z_FIRST

    real = review.review_texts

    def z_first(saved: str, unsaved: str, *args: Any, **kwargs: Any
                ) -> list[review.ProgramDiff]:
        assert unsaved.count(RAPID) == 1
        return real(saved, unsaved.replace(RAPID, RAPID_Z_FIRST), *args, **kwargs)

    monkeypatch.setattr(review, "review_texts", z_first)

    async def scenario(app: EditorApp, pilot: Pilot[Any]) -> None:
        await set_cycle_decimals(pilot, "3")
        screen = await open_review(pilot)
        listed = rows(screen)
        verdicts = {verdict for verdict, _ in listed.values()}
        assert review.MOTION in verdicts, listed
        moved = next(name for name, (verdict, _) in listed.items() if verdict == review.MOTION)
        table = screen.query_one("#review-programs", DataTable)
        table.move_cursor(row=list(listed).index(moved), animate=False)
        await pilot.pause()
        assert screen.selected == moved
        detail = shown(screen, "#review-detail")
        diff = next(d for d in screen.outcome.diffs if d.program == moved)
        assert diff.motion_at is not None
        assert f"first motion difference: CL line {diff.motion_at.cl_line}" in detail
        assert "before NC line" in detail and "after NC line" in detail

    run(EditorApp(corpus), scenario)
