"""`postdsl review --format markdown --plots DIR`: before/after pictures of changed toolpaths."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from postdsl import review
from tests.test_review import COORD_3, COORD_4, _clean_git_env, edit_post, repo, run

__all__ = ["_clean_git_env", "repo"]  # the fixtures of test_review, used here

SVG = "{http://www.w3.org/2000/svg}"


def test_a_changed_toolpath_is_linked_before_and_after(repo: Path) -> None:
    # whole millimetres: X12.346 becomes X12., the tool no longer goes where the CL says
    edit_post(repo, COORD_3, COORD_3.replace("decimals: 3", "decimals: 0"))
    status, text = run("--format", "markdown", "--jobs", "1", "--plots", "plots")
    assert status == 1
    block = text.split("<summary>vmc500 · cl/mill.jsonl")[1].split("</details>")[0]
    assert "**The toolpath changes:**" in block
    assert ("| ![before](plots/vmc500-cl-mill-jsonl-before.svg) | "
            "![after](plots/vmc500-cl-mill-jsonl-after.svg) |") in block
    before = ET.parse(repo / "plots" / "vmc500-cl-mill-jsonl-before.svg").getroot()
    after = ET.parse(repo / "plots" / "vmc500-cl-mill-jsonl-after.svg").getroot()
    assert before.find(f"{SVG}title").text == "vmc500: cl/mill.jsonl (before)"  # type: ignore[union-attr]
    feeds = [[p.get("d") for p in root.iter(f"{SVG}path") if p.get("class") == "feed"]
             for root in (before, after)]
    assert feeds[0] and feeds[1] and feeds[0] != feeds[1]
    # a picture for every program whose moves differ, none for the others
    changed = {p.program for p in _motion_changed(repo)}
    assert len(list((repo / "plots").glob("*.svg"))) == 2 * len(changed)
    assert "cl/mill.jsonl" in changed


def _motion_changed(repo: Path) -> list[review.ProgramDiff]:
    result = review.review(repo, jobs=1, plots=True)
    return [p for p in result.programs if p.motion is not None and p.motion.changed]


def test_a_text_change_that_moves_nothing_says_so(repo: Path) -> None:
    # a fourth decimal: the lines change, the control (resolution 0.001 mm) moves the same
    edit_post(repo, COORD_3, COORD_4)
    status, text = run("--format", "markdown", "--jobs", "1", "--plots", "plots")
    assert status == 4  # format only
    block = text.split("<summary>vmc500 · cl/mill.jsonl")[1].split("</details>")[0]
    assert "The toolpath is unchanged: the control model replays the same moves." in block
    assert not list((repo / "plots").glob("*.svg"))


def test_the_motion_is_compared_on_every_process(repo: Path) -> None:
    edit_post(repo, COORD_3, COORD_3.replace("decimals: 3", "decimals: 0"))
    serial = review.review(repo, jobs=1, plots=True)
    parallel = review.review(repo, jobs=2, plots=True)
    assert [(p.program, p.motion) for p in serial.programs] == \
        [(p.program, p.motion) for p in parallel.programs]


def test_plots_go_with_markdown_only(repo: Path) -> None:
    status, output = run("--format", "text", "--plots", "plots")
    assert status == 2 and "--plots goes with --format markdown" in output


def test_without_plots_nothing_is_replayed(repo: Path) -> None:
    edit_post(repo, COORD_3, COORD_3.replace("decimals: 3", "decimals: 0"))
    result = review.review(repo, jobs=1)
    assert all(p.motion is None for p in result.programs)
    status, text = run("--format", "markdown", "--jobs", "1")
    assert status == 1 and "toolpath" not in text
