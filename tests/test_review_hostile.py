"""`postdsl review` on hostile corpora: nothing read from outside, nothing leaked, exit 2.

The review runs in CI on a pull request's corpus.yaml and CL files and posts Markdown
for people to read, so a corpus must not reach files outside the repository, and what
reaches the comment must be shown as text, never interpreted, and never quote the input.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from postdsl import review
from postdsl.review import report
from tests.test_review import COORD_3, COORD_4, _clean_git_env, edit_post, repo, run

__all__ = ["_clean_git_env", "repo"]  # fixtures, used by name


def write_corpus(repo: Path, text: str) -> None:
    (repo / "corpus.yaml").write_text(text, encoding="utf-8")


@pytest.mark.parametrize(("corpus", "line"), [
    ('vmc500:\n  - cl/mill.jsonl\n"vm\\0c": [cl/mill.jsonl]\n', 3),
    ('vmc500:\n  - cl/mill.jsonl\n  - "cl/mi\\0ll.jsonl"\n', 3),
    ("vmc500:\n  - cl/mill.jsonl\n../etc: [cl/mill.jsonl]\n", 3),
])
def test_a_bad_corpus_key_or_path_is_a_located_error_exit_2(repo: Path, corpus: str,
                                                             line: int) -> None:
    write_corpus(repo, corpus)
    status, output = run("--jobs", "1")
    assert status == 2
    assert output.startswith(f"{repo / 'corpus.yaml'}:{line}: ")
    assert "Traceback" not in output


@pytest.mark.parametrize("path", ["/etc/hostname", "../outside.jsonl", "cl/../../outside.jsonl"])
def test_corpus_paths_cannot_leave_the_repository(repo: Path, path: str) -> None:
    (repo.parent / "outside.jsonl").write_text('{"cmd": "program_start"}\n', encoding="utf-8")
    write_corpus(repo, f"vmc500:\n  - cl/mill.jsonl\n  - {path}\n")
    status, output = run("--jobs", "1")
    assert status == 2
    assert output.startswith(f"{repo / 'corpus.yaml'}:3: corpus paths are relative")


@pytest.mark.skipif(os.name != "posix", reason="symbolic links")
def test_a_corpus_symlink_out_of_the_repository_is_refused(repo: Path) -> None:
    secret = repo.parent / "secret.jsonl"
    secret.write_text("PASSWORD/hunter2\n", encoding="utf-8")
    (repo / "cl" / "link.jsonl").symlink_to(secret)
    write_corpus(repo, "vmc500:\n  - cl/mill.jsonl\n  - cl/link.jsonl\n")
    edit_post(repo, COORD_3, COORD_4)
    status, output = run("--jobs", "1", "--format", "markdown")
    assert status == 2
    assert output.startswith(f"{repo / 'corpus.yaml'}:3: the corpus path is a symbolic link")
    assert "hunter2" not in output


@pytest.mark.skipif(os.name != "posix", reason="symbolic links")
def test_a_symlink_out_of_a_corpus_folder_is_refused(repo: Path) -> None:
    secret = repo.parent / "secret.jsonl"
    secret.write_text("PASSWORD/hunter2\n", encoding="utf-8")
    (repo / "cl" / "link.jsonl").symlink_to(secret)
    edit_post(repo, COORD_3, COORD_4)
    status, output = run("--jobs", "1", "--corpus", "cl", "--format", "markdown")
    assert status == 2
    assert "symbolic link leading outside cl" in output and "hunter2" not in output


def test_a_symlink_inside_the_repository_is_fine(repo: Path) -> None:
    (repo / "cl" / "again.jsonl").symlink_to(repo / "cl" / "mill.jsonl")
    write_corpus(repo, "vmc500:\n  - cl/again.jsonl\n")
    edit_post(repo, COORD_3, COORD_4)
    status, _ = run("--jobs", "1")
    assert status == 4  # format only


def test_markdown_never_quotes_the_input_of_an_error(repo: Path) -> None:
    (repo / "cl" / "bad.jsonl").write_text(
        '{"cmd": "program_start"}\n{"cmd": "PASSWORD/hunter2 @team [x](http://evil)"}\n',
        encoding="utf-8")
    write_corpus(repo, "vmc500:\n  - cl/mill.jsonl\n  - cl/bad.jsonl\n")
    edit_post(repo, COORD_3, COORD_4)
    status, _ = run("--jobs", "1", "--format", "markdown")
    assert status == 2
    markdown = review.render_markdown(review.review(jobs=1))
    assert "hunter2" not in markdown and "PASSWORD" not in markdown
    assert "cl/bad.jsonl:2" in markdown
    # the located message itself still reaches stderr and the JSON, for whoever runs it
    status, output = run("--jobs", "1", "--format", "json")
    document = json.loads(output[output.index("{"):output.rindex("}") + 1])
    assert any("hunter2" in error for error in document["errors"])


def test_markdown_shows_names_as_text(repo: Path) -> None:
    name = "cl/@team [x](evil.example) <img src=x> `tick` #12 www.evil.example.jsonl"
    (repo / name).write_bytes((repo / "cl" / "mill.jsonl").read_bytes())
    write_corpus(repo, f"vmc500:\n  - '{name}'\n")
    edit_post(repo, COORD_3, COORD_4)
    status, text = run("--jobs", "1", "--format", "markdown")
    assert status == 4  # format only
    row = next(line for line in text.splitlines() if line.startswith("| format only |"))
    cell = row.split(" | ")[2]
    # a code span: literal, and longer than any backtick run inside it
    assert cell.startswith("``") and cell.endswith("``") and "<img src=x>" in cell
    summary = next(line for line in text.splitlines() if line.startswith("<details>"))
    assert "<img" not in summary and "&lt;img src=x&gt;" in summary
    assert "@team" not in summary and "www.evil" not in summary and "#12" not in summary


def test_md_cell_escapes_markdown_html_mentions_and_links() -> None:
    cell = report._md_cell("[a](http://x) @bob <b>*c*</b> `d` | e\nf #3 www.x.org")
    assert "[a](" not in cell and "\\[a\\]\\(" in cell
    assert "@bob" not in cell and "@\u200bbob" in cell
    assert "<b>" not in cell and "&lt;b&gt;" in cell
    assert "\\*c\\*" in cell and "\\`d\\`" in cell and "\\|" in cell and "\n" not in cell
    assert "http://" not in cell and "#3" not in cell and "www." not in cell


def test_an_internal_error_in_review_is_exit_3_never_1(repo: Path, monkeypatch) -> None:
    def broken(**kwargs: object) -> None:
        raise RuntimeError("boom")

    monkeypatch.setattr(review, "review", broken)
    status, output = run("--jobs", "1")
    assert status == 3
    assert "internal error: RuntimeError: boom" in output


def test_the_terminal_report_escapes_control_characters_in_names(repo: Path) -> None:
    name = "cl/\x1b[2Jclear.jsonl"
    (repo / name).write_bytes((repo / "cl" / "mill.jsonl").read_bytes())
    edit_post(repo, COORD_3, COORD_4)
    status, text = run("--jobs", "1", "--corpus", "cl")
    assert status == 4  # format only
    assert "\x1b" not in text and "cl/\\x1b[2Jclear.jsonl" in text
