"""The report is written as it is rendered: JSON one program at a time, and a text or
Markdown report a failure cuts short says so in its last line (issue 30)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from postdsl import review
from postdsl.cli import main
from postdsl.review import report
from tests.test_review import COORD_3, COORD_4, _clean_git_env, edit_post, repo

__all__ = ["_clean_git_env", "repo"]  # fixtures, used by name


def _changed(repo: Path) -> review.ReviewResult:
    edit_post(repo, COORD_3, COORD_4)
    return review.review(repo, jobs=1, use_cache=False, spool=True)


def test_streamed_json_is_the_document_json_dumps_writes(repo: Path) -> None:
    """Scripts parsing the report see the same document, byte for byte, as when it was
    built whole: the same keys in the same order, each program with its diff."""
    result = _changed(repo)
    assert len(result.programs) == 3
    chunks: list[str] = []
    review.write_report(result, "json", chunks.append)
    text = "".join(chunks)
    document = json.loads(text)
    assert text == json.dumps(document, indent=2, ensure_ascii=False) + "\n"
    assert list(document) == ["against", "commit", "new", "exit_status", "verdicts",
                              "changes", "summary", "programs", "errors", "warnings"]
    assert [p["program"] for p in document["programs"]] == [p.program
                                                             for p in result.programs]
    assert all(p["diff"] == result.diff_of(q)
               for p, q in zip(document["programs"], result.programs, strict=True))
    assert document["verdicts"] == {"format only": 2, "unchanged": 1}


def test_json_is_written_program_by_program(repo: Path, monkeypatch: pytest.MonkeyPatch
                                            ) -> None:
    """No program's diff is read before the programs before it are rendered: the
    document is never one string in memory."""
    result = _changed(repo)
    rendered: list[str] = []
    diff_of = result.diff_of

    def spy(program: review.ProgramDiff) -> list[str]:
        rendered.append(program.program)
        return diff_of(program)

    monkeypatch.setattr(result, "diff_of", spy)
    chunks = list(report.json_chunks(result))
    programs_at = next(i for i, c in enumerate(chunks) if c.startswith('  "programs"'))
    items = chunks[programs_at + 1:programs_at + 1 + len(result.programs)]
    assert len(rendered) == 3 and all(item.startswith("    {") for item in items)
    assert json.loads("".join(chunks))["programs"][2]["program"] == rendered[2]


def test_json_of_no_programs_is_still_the_same_document(repo: Path) -> None:
    result = review.review(repo, jobs=1, use_cache=False)
    result.programs.clear()
    text = review.render_json(result)
    assert text == json.dumps(json.loads(text), indent=2, ensure_ascii=False) + "\n"


@pytest.mark.parametrize("fmt", ["text", "markdown"])
def test_a_report_cut_short_by_a_failure_ends_saying_so(repo: Path, fmt: str,
                                                         monkeypatch: pytest.MonkeyPatch
                                                         ) -> None:
    result = _changed(repo)
    real = report.headline if fmt == "text" else report._md_headline
    seen: list[str] = []

    def failing(program: review.ProgramDiff) -> str:
        seen.append(program.program)
        if len(seen) == 2:
            raise RuntimeError("secret CL record text")
        return real(program)

    monkeypatch.setattr(report, "headline" if fmt == "text" else "_md_headline", failing)
    written: list[str] = []
    with pytest.raises(RuntimeError):
        review.write_report(result, fmt, written.append)
    text = "".join(written)
    last = text.rstrip("\n").splitlines()[-1]
    assert report.INCOMPLETE in last and "RuntimeError" in last and "missing" in last
    assert text.count(report.INCOMPLETE) == 1
    # Markdown quotes no message (it may quote a CL record), the terminal report does
    assert ("secret CL record text" in last) == (fmt == "text")
    if fmt == "text":  # what was rendered before the failure is there
        assert f"{result.programs[0].program}" in text


def test_cli_exit_3_with_a_partial_report_ends_with_the_incomplete_line(
        repo: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    edit_post(repo, COORD_3, COORD_4)
    calls: list[str] = []
    real = report.headline

    def failing(program: review.ProgramDiff) -> str:
        calls.append(program.program)
        if len(calls) == 2:
            raise RuntimeError("boom")
        return real(program)

    monkeypatch.setattr(report, "headline", failing)
    result = CliRunner().invoke(main, ["review", "--jobs", "1"])
    assert result.exit_code == 3
    lines = result.stdout.rstrip("\n").splitlines()
    assert lines[0] == "verdicts: 2 format only, 1 unchanged"
    assert lines[-1].startswith(report.INCOMPLETE) and "RuntimeError: boom" in lines[-1]
    assert "internal error: RuntimeError: boom" in result.stderr


def test_an_interrupted_report_says_interrupted(repo: Path, monkeypatch: pytest.MonkeyPatch
                                                ) -> None:
    result = _changed(repo)

    def interrupted(program: review.ProgramDiff) -> str:
        raise KeyboardInterrupt

    monkeypatch.setattr(report, "headline", interrupted)
    written: list[str] = []
    with pytest.raises(KeyboardInterrupt):
        review.write_report(result, "text", written.append)
    assert "".join(written).rstrip("\n").endswith(
        f"{report.INCOMPLETE}interrupted; the programs after this point are missing")
