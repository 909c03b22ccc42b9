"""Review's verdicts, its aligned diff, its result cache and its Dask executor.

The repositories are those of tests/test_review.py (the VMC500 post and three small CL
programs); the expected verdicts are reasoned from what each post change does to the
machine, never copied from a review's output.
"""

from __future__ import annotations

import random
import time
from pathlib import Path

import pytest

from postdsl import review
from postdsl.review import compare
from tests.test_review import COORD_3, COORD_4, _clean_git_env, edit_post, repo, run

__all__ = ["_clean_git_env", "repo"]  # fixtures, used by name

#: the rapid move as one block, and split: Z first, then X and Y (another path)
RAPID = ("          - {param: x, prefix: \" X\", format: coord, mode: changed}\n"
         "          - {param: y, prefix: \" Y\", format: coord, mode: changed}\n"
         "          - {param: z, prefix: \" Z\", format: coord, mode: changed}\n"
         "          - {text: \" M9\", if: \"coolant == 'off'\", modal: coolant, mode: changed}\n")
RAPID_Z_FIRST = (
    "          - {param: z, prefix: \" Z\", format: coord, mode: changed}\n"
    "          - {text: \" M9\", if: \"coolant == 'off'\", modal: coolant, mode: changed}\n"
    "      - only_with_values: true\n"
    "        items:\n"
    "          - {text: \" G0\", modal: motion}\n"
    "          - {param: x, prefix: \" X\", format: coord, mode: changed}\n"
    "          - {param: y, prefix: \" Y\", format: coord, mode: changed}\n")


@pytest.fixture(autouse=True)
def _no_cache(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """Each test its own result cache: one test's results are never another's."""
    monkeypatch.setenv("POSTDSL_CACHE_DIR", str(tmp_path / "cache"))


def test_a_fourth_decimal_below_the_resolution_is_format_only(repo: Path) -> None:
    edit_post(repo, COORD_3, COORD_4)
    result = review.review(repo, jobs=1)
    verdicts = {p.program: p.verdict for p in result.programs}
    assert verdicts == {"cl/mill.jsonl": "format only", "cl/drill.jsonl": "format only",
                        "cl/plain.jsonl": "unchanged"}
    assert result.exit_status == review.EXIT_FORMAT_ONLY == 4


def test_a_rapid_split_z_first_is_a_motion_change_located_on_both_sides(repo: Path) -> None:
    """After the tool change the position is unknown; one rapid to X10 Y10 Z50 becomes
    Z50 first, then X10 Y10: the tool takes another path.  Verify accepts both (a rapid
    is positioning), review must not call it a format change."""
    edit_post(repo, RAPID, RAPID_Z_FIRST)
    result = review.review(repo, jobs=1)
    mill = next(p for p in result.programs if p.program == "cl/mill.jsonl")
    assert mill.verdict == review.MOTION
    assert mill.motion_at is not None
    assert mill.motion_at.cl_line == 4  # {"cmd": "rapid_move", "x": 10, "y": 10, "z": 50}
    assert mill.motion_at.old is not None and mill.motion_at.new is not None
    assert "X10. Y10. Z50." in mill.motion_at.old[1]
    assert mill.motion_at.new[1].endswith("G0 Z50.") or "Z50." in mill.motion_at.new[1]
    assert "X" not in mill.motion_at.new[1].split("G0", 1)[1]
    assert result.exit_status == review.EXIT_MOTION == 1
    status, text = run("--jobs", "1")
    assert status == 1
    first = text.splitlines()[0]
    assert first.startswith("verdicts: ") and "motion changed" in first
    assert "motion changed: vmc500  cl/mill.jsonl — at CL line 4" in text


def test_only_renumbering_or_format_exits_4_and_nothing_exits_0(repo: Path) -> None:
    assert run("--jobs", "1")[0] == 0
    edit_post(repo, "    start: 10\n", "    start: 100\n")
    assert run("--jobs", "1")[0] == 4


def _apply(opcodes: list[compare.Opcode], old: list[str], new: list[str]) -> list[str]:
    out: list[str] = []
    for tag, i1, i2, j1, j2 in opcodes:
        out += old[i1:i2] if tag == "equal" else new[j1:j2]
    return out


@pytest.mark.parametrize("seed", range(20))
def test_the_aligned_diff_turns_old_into_new_and_pairs_only_lines_of_one_record(
        seed: int) -> None:
    rng = random.Random(seed)
    old: list[str] = []
    new: list[str] = []
    old_records: list[int] = []
    new_records: list[int] = []
    for record in range(1, rng.randint(2, 40)):
        lines = [f"G1 X{rng.randint(0, 9)}" for _ in range(rng.randint(0, 4))]
        changed = [line if rng.random() < 0.6 else line + "1" for line in lines]
        if rng.random() < 0.2:
            changed.append("G4 P1")
        old += lines
        old_records += [record] * len(lines)
        new += changed
        new_records += [record] * len(changed)
    opcodes = compare.aligned_opcodes(old, new, old_records, new_records)
    assert _apply(opcodes, old, new) == new
    for tag, i1, i2, j1, j2 in opcodes:
        assert i1 <= i2 and j1 <= j2
        if tag == "equal":
            assert old[i1:i2] == new[j1:j2]
        if tag == "replace":  # a replaced line is replaced by one of its own record
            assert set(old_records[i1:i2]) == set(new_records[j1:j2])


def test_a_fully_changed_long_program_diffs_in_linear_time() -> None:
    """Every line changed, one record a line: 20 000 lines take about ten times what
    2 000 take (difflib over the whole program took a hundred times)."""
    def timed(count: int) -> float:
        old = [f"N{i} G1 X{i}.000" for i in range(count)]
        new = [f"N{i} G1 X{i}.0001" for i in range(count)]
        records = list(range(1, count + 1))
        start = time.perf_counter()
        opcodes = compare.aligned_opcodes(old, new, records, records)
        list(compare.unified(opcodes, old, new, 3))
        return time.perf_counter() - start

    small = min(timed(2000) for _ in range(3))
    large = min(timed(20000) for _ in range(3))
    assert large < small * 25, (small, large)


def test_the_result_cache_reposts_only_what_changed(repo: Path) -> None:
    edit_post(repo, COORD_3, COORD_4)
    first = review.review(repo, jobs=1)
    assert not any(p.cached for p in first.programs)
    again = review.review(repo, jobs=1)
    assert all(p.cached for p in again.programs if p.posted)
    assert again.programs == first.programs
    # one CL program changed: only it is posted again
    mill = repo / "cl" / "mill.jsonl"
    mill.write_text(mill.read_text().replace('"x": 20}', '"x": 21}'), encoding="utf-8")
    third = review.review(repo, jobs=1)
    posted = {p.program for p in third.programs if not p.cached}
    assert posted == {"cl/mill.jsonl"}
    assert review.review(repo, jobs=1, use_cache=False).programs == third.programs


def test_a_forged_cache_entry_is_not_read(repo: Path, tmp_path: Path) -> None:
    edit_post(repo, COORD_3, COORD_4)
    review.review(repo, jobs=1)
    entries = list((tmp_path / "cache" / "review").glob("*.review"))
    assert entries
    for entry in entries:  # a verdict changed without its hash: a forged entry
        entry.write_bytes(entry.read_bytes().replace(b"format only", b"unchanged!!"))
    again = review.review(repo, jobs=1)
    assert not any(p.cached for p in again.programs if p.verdict == "format only")
    assert {p.verdict for p in again.programs} == {"format only", "unchanged"}


@pytest.mark.slow
def test_the_dask_executor_finds_what_the_local_pool_finds(repo: Path) -> None:
    """Two worker processes of a LocalCluster; the posts and the CL programs' bytes are
    sent to them (nothing read from this repository by path on the workers' side)."""
    distributed = pytest.importorskip("distributed")
    edit_post(repo, RAPID, RAPID_Z_FIRST)
    local = review.review(repo, jobs=1, use_cache=False)
    calls: list[tuple[int, int]] = []
    with distributed.LocalCluster(processes=True, n_workers=2, threads_per_worker=1,
                                  dashboard_address=None) as cluster:
        remote = review.review(repo, executor="dask", scheduler=cluster.scheduler_address,
                               use_cache=False,
                               progress=lambda done, total: calls.append((done, total)))
        assert remote.programs == local.programs
        assert remote.exit_status == local.exit_status == 1
        assert calls == [(done, 3) for done in range(4)]
        # and a format-only change on top: the same verdicts, through the same cluster
        edit_post(repo, COORD_3, COORD_4)
        local = review.review(repo, jobs=2, use_cache=False)
        remote = review.review(repo, executor="dask", scheduler=cluster.scheduler_address,
                               use_cache=False)
        assert remote.programs == local.programs
        assert [p.verdict for p in remote.programs] == [p.verdict for p in local.programs]


def test_the_dask_executor_needs_a_scheduler(repo: Path) -> None:
    pytest.importorskip("distributed")
    edit_post(repo, COORD_3, COORD_4)
    with pytest.raises(review.ReviewError, match="--scheduler"):
        review.review(repo, executor="dask")


@pytest.mark.slow
def test_an_unreachable_scheduler_is_a_located_error_not_a_traceback(repo: Path) -> None:
    pytest.importorskip("distributed")
    edit_post(repo, COORD_3, COORD_4)
    status, output = run("--executor", "dask", "--scheduler", "tcp://127.0.0.1:1")
    assert status == 2
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:1" in output


def test_a_posting_kept_from_before_spares_the_old_post(repo: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    """The post changed again (a comment): no pair is cached, but a program whose new
    posting has the text its old posting had is unchanged without running the old post."""
    from postdsl.review import posting

    edit_post(repo, COORD_3, COORD_4)
    first = review.review(repo, jobs=1)
    edit_post(repo, COORD_4, COORD_4 + "  # four decimals: the CAM's tolerance\n")
    old_postings: list[str] = []
    output = posting.Poster._output

    def counted(self: posting.Poster, machine: str, new: bool, job: posting.Job,
                commands: list) -> tuple:
        if not new:
            old_postings.append(job.program)
        return output(self, machine, new, job, commands)

    monkeypatch.setattr(posting.Poster, "_output", counted)
    again = review.review(repo, jobs=1)
    assert sorted(old_postings) == ["cl/drill.jsonl", "cl/mill.jsonl"]  # not plain.jsonl
    assert [(p.program, p.verdict) for p in again.programs] == \
        [(p.program, p.verdict) for p in first.programs]
    assert again.programs == first.programs


def test_the_streamed_report_is_the_rendered_one(repo: Path) -> None:
    """The CLI writes the report as it renders it (a whole archive's report is never one
    string); what it writes is exactly what render gives, diffs spooled or not."""
    edit_post(repo, RAPID, RAPID_Z_FIRST)
    kept = review.review(repo, jobs=1)
    spooled = review.review(repo, jobs=1, spool=True)
    assert all(not p.diff for p in spooled.programs)  # in the temporary file
    for fmt in review.FORMATS:
        written: list[str] = []
        review.write_report(spooled, fmt, written.append)
        assert "".join(written) == review.render(kept, fmt)
