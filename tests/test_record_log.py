"""The second pass replays the records a native first pass kept, without the file.

``CLSource.fold`` keeps every record of a native file on disk, a plain rapid or
linear move as its fields (:mod:`postdsl.cl.record_log`); ``CLSource.records`` then
hands exactly the records the reading would hand -- ints as ints, left-out fields as
None, in batches, across every other kind of line -- without opening the file, so
what is posted is what the first pass read and summed up.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from postdsl.cl import native, record_log
from postdsl.cl.model import LinearMove, RapidMove, plain_command
from postdsl.cl.source import CLSource
from postdsl.errors import CLError
from postdsl.run.program import SummaryFolder
from tests.conftest import DATA, EXAMPLES, ROOT, examples

RAPID_RATE = 5000.0

numbers = st.one_of(st.none(), st.integers(-500, 500),
                    st.floats(-500, 500, allow_nan=False).map(lambda v: round(v, 4)))


@st.composite
def lines(draw: st.DrawFn) -> str:
    """A line of a native program: mostly plain moves, and the other kinds between."""
    kind = draw(st.sampled_from(["linear_move"] * 4 + ["rapid_move"] * 2 + [
        "arc", "comment", "blank", "feed_text", "odd_order", "tool_change"]))
    if kind in ("linear_move", "rapid_move"):
        record: dict[str, object] = {"cmd": kind}
        for axis in ("x", "y", "z") + (("feed",) if kind == "linear_move" else ()):
            value = draw(numbers)
            if value is not None or draw(st.booleans()):  # null: a field left out
                record[axis] = value if axis != "feed" or value is None else abs(value) + 1
        return json.dumps(record)
    return {
        "arc": '{"cmd": "arc_move", "x": 1, "y": 0, "cx": 0, "cy": 0, "arc_direction": "cw"}',
        "comment": "# a comment",
        "blank": "",
        "feed_text": '{"cmd":"linear_move","x":1.5,  "feed":600}',
        "odd_order": '{"feed": 900, "z": -1, "cmd": "linear_move"}',
        "tool_change": '{"cmd": "tool_change", "tool_number": 2}',
    }[kind]


def program(body: list[str]) -> str:
    return "\n".join(['{"cmd": "program_start"}', '{"cmd": "tool_change", "tool_number": 1}',
                      *body, '{"cmd": "program_end"}']) + "\n"


def read_without_log(path: Path) -> list[object]:
    """The records as a second pass reads them when no first pass kept anything."""
    with CLSource(path) as source:
        return list(source.records())


def read_after_fold(path: Path) -> list[object]:
    with CLSource(path) as source:
        source.fold(SummaryFolder(RAPID_RATE))
        return list(source.records())


@settings(max_examples=examples(0.6), deadline=None)
@given(st.lists(lines(), max_size=80))
def test_the_replayed_moves_are_the_moves_the_reading_reads(
        tmp_path_factory: pytest.TempPathFactory, body: list[str]) -> None:
    path = tmp_path_factory.mktemp("log") / "job.jsonl"
    path.write_text(program(body), encoding="utf-8")
    replayed = read_after_fold(path)
    assert replayed == read_without_log(path)
    # types too: an int stays an int, a field left out stays None
    assert [tuple(map(type, r)) if isinstance(r, tuple) else type(r) for r in replayed] == \
        [tuple(map(type, r)) if isinstance(r, tuple) else type(r)
         for r in read_without_log(path)]


def test_records_over_many_batches_are_replayed_in_order_without_the_file(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    count = 3 * record_log.BATCH + 5
    body = []
    for n in range(count):
        body.append(json.dumps({"cmd": "linear_move", "x": n * 0.5, "y": n, "feed": 600})
                    if n % 7 else json.dumps({"cmd": "rapid_move", "z": n}))
        if n % 1000 == 0:
            body.append('{"cmd": "arc_move", "x": 0, "y": 0, "cx": 1, "cy": 0}')
            body.append("# a comment, not a record")
    path = tmp_path / "long.jsonl"
    path.write_text(program(body), encoding="utf-8")
    expected = read_without_log(path)
    with CLSource(path) as source:
        source.fold(SummaryFolder(RAPID_RATE))
        parsed: list[int] = []
        real = native.plain_move

        def counting(text: str, number: int) -> object:
            parsed.append(number)
            return real(text, number)

        def no_file() -> None:
            raise AssertionError("the second pass opened the file")

        monkeypatch.setattr(native, "plain_move", counting)
        monkeypatch.setattr(source, "_open", no_file)
        records = list(source.records())
    assert records == expected
    moves = [r for r in records if isinstance(r, tuple)]
    assert len(moves) == count
    # line 3: the first rapid, line 4: an arc (read as a command), line 5: a comment,
    # line 6: a linear move
    assert moves[1] == (LinearMove, 6, 0.5, 1, None, 600)
    assert moves[7] == (RapidMove, 12, None, None, 7)
    assert [type(m[3]) for m in moves if m[0] is LinearMove][:3] == [int, int, int]
    assert [r.name for r in records if not isinstance(r, tuple)][:3] == \
        ["program_start", "tool_change", "arc_move"]
    assert parsed == []  # no move of the second pass went through the JSON again


def test_the_replay_reports_progress_up_to_the_bytes_the_first_pass_read(
        tmp_path: Path) -> None:
    path = tmp_path / "job.jsonl"
    path.write_text(program([json.dumps({"cmd": "linear_move", "x": n, "feed": 600})
                             for n in range(2 * record_log.BATCH)]), encoding="utf-8")
    reports: list[int] = []
    with CLSource(path) as source:
        source.fold(SummaryFolder(RAPID_RATE))
        for _ in source.records(reports.append):
            pass
    assert len(reports) >= 2 and reports == sorted(reports)
    assert reports[-1] == path.stat().st_size


def test_what_is_posted_is_what_the_first_pass_read_though_the_file_changed_after_it(
        tmp_path: Path) -> None:
    """The header describes the program the first pass read: the second pass posts that
    program, not what the file holds by then."""
    path = tmp_path / "job.jsonl"
    path.write_text(program([json.dumps({"cmd": "linear_move", "x": n, "feed": 600})
                             for n in range(100)]), encoding="utf-8")
    expected = read_without_log(path)
    with CLSource(path) as source:
        source.fold(SummaryFolder(RAPID_RATE))
        path.write_text(program([json.dumps({"cmd": "linear_move", "x": -n, "feed": 600})
                                 for n in range(100)]), encoding="utf-8")
        assert list(source.records()) == expected
        with pytest.raises(CLError, match="changed while it was being posted"):
            list(source.commands())  # a pass that reads the file again still refuses it


def test_a_first_pass_that_fails_leaves_nothing_to_replay(tmp_path: Path) -> None:
    path = tmp_path / "job.jsonl"
    path.write_text(program(['{"cmd": "rapid_move", "z": 5}']).replace(
        '{"cmd": "program_end"}\n', ""), encoding="utf-8")
    with CLSource(path) as source:
        with pytest.raises(CLError, match="without a program_end"):
            source.fold(SummaryFolder(RAPID_RATE))
        with pytest.raises(CLError, match="without a program_end"):
            list(source.records())  # read from the file again, and refused again


def test_the_kept_records_go_with_the_source(tmp_path: Path) -> None:
    path = tmp_path / "job.jsonl"
    path.write_text(program(['{"cmd": "rapid_move", "z": 5}']), encoding="utf-8")
    source = CLSource(path)
    source.fold(SummaryFolder(RAPID_RATE))
    kept = source._log
    assert kept is not None
    source.close()
    assert source._log is None
    with pytest.raises(ValueError):  # the temporary file is closed (and so removed)
        next(kept.batches())


# --- every CL file of the repository, every format ---------------------------------------

CL_FILES = sorted(path for folder in (EXAMPLES, DATA) for path in folder.rglob("*")
                  if path.suffix in {".jsonl", ".apt", ".gcode", ".ncl"}
                  or path.name.endswith(".dump.txt"))


def as_commands(records: list[object]) -> list[object]:
    """Each record as its command, with its line (which command equality leaves out)."""
    commands = [plain_command(r) if isinstance(r, tuple) else r for r in records]
    return [(c, c.line) for c in commands]  # type: ignore[attr-defined]


def outcome(read: object) -> object:
    """What a reading gives: its records as commands, or the error it stops at."""
    try:
        return as_commands(read())  # type: ignore[operator]
    except CLError as exc:
        return ("refused", str(exc))


@pytest.mark.parametrize("path", CL_FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_cl_file_replays_as_its_second_pass_reads_it(path: Path,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    """APT and G-code records depend on the ones before them: their first pass keeps the
    commands themselves, in the order the reading hands them on between the moves."""
    expected = outcome(lambda: read_without_log(path))

    def replayed() -> list[object]:
        with CLSource(path) as source:
            source.fold(SummaryFolder(RAPID_RATE))
            monkeypatch.setattr(source, "_open", lambda: pytest.fail("the file was read again"))
            return list(source.records())

    assert outcome(replayed) == expected
    if not isinstance(expected, tuple):
        assert expected  # a program, not only refusals
