"""The first pass's summary is the summary the commands give, however it is folded.

``write_program`` folds its first pass with :class:`postdsl.run.program.SummaryFolder`:
a native file's plain moves reach it as fields (``move_taker``), every other record
as a command, while :func:`postdsl.run.program.summarize` feeds it commands only.  Both
must give, field for field and type for type, the summary the fold gave before it
was a folder: :func:`reference_summary` below is that fold as it stood (main at
08640f9), kept as the oracle.  Errors must be those of the full reading, at the
same line.
"""

from __future__ import annotations

import io
import json
import math
import sys
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from postdsl import api
from postdsl.cl.lines import SourceLines, text_blocks
from postdsl.cl.model import (
    DRILL_SETUPS,
    ArcMove,
    CLCommand,
    CycleHole,
    DrillSetup,
    Dwell,
    LinearMove,
    ProgramStart,
    RapidMove,
    SafeRetract,
    SpindleOn,
    ToolChange,
    WorkPlane,
)
from postdsl.cl.native import move_taker, record_to_command
from postdsl.cl.readers import fold_commands, read_cl, read_cl_text
from postdsl.cl.source import CLSource
from postdsl.errors import CLError, Location
from postdsl.kinematics import Kinematics
from postdsl.run.program import (
    MOVE_VALUES,
    ProgramSummary,
    SummaryFolder,
    summarize,
    summarize_source,
)
from tests.conftest import DATA, EXAMPLES, ROOT

RAPID_RATE = 8000.0


def reference_summary(commands: Iterable[CLCommand], rapid_rate: float) -> ProgramSummary:
    """The fold before the folder, unchanged but for its bounds helper inlined, and the
    extents of a move in a tilted plane (work_plane) taken in the part frame."""
    summary = ProgramSummary()
    low: dict[str, float] = {}
    high: dict[str, float] = {}
    # the plane in force: origin and axes X, Y, Z in the part frame (None: the part)
    plane: tuple[tuple[float, ...], ...] | None = None

    def add_point(point: list[float | None]) -> None:
        if plane is None:
            for axis, value in zip("xyz", point, strict=True):
                add(axis, value)
        elif None not in point:
            o, ex, ey, ez = plane
            p = [v or 0.0 for v in point]
            for i, axis in enumerate("xyz"):
                add(axis, o[i] + ex[i] * p[0] + ey[i] * p[1] + ez[i] * p[2])

    def add(axis: str, value: float | None) -> None:
        if value is None:
            return
        if axis not in low or value < low[axis]:
            low[axis] = value
        if axis not in high or value > high[axis]:
            high[axis] = value

    pos: list[float | None] = [None, None, None]
    feed: float | None = None
    given_time: float | None = None
    seconds = 0.0
    cycle: DrillSetup | None = None

    def travel(target: list[float | None], rate: float | None) -> float:
        if rate is None or rate <= 0 or None in pos or None in target:
            return 0.0
        return math.dist(pos, target) / rate * 60.0  # type: ignore[arg-type]

    from postdsl.run.program import arc_length

    for command in commands:
        if isinstance(command, ProgramStart):
            given_time = command.machining_time
        elif isinstance(command, ToolChange):
            summary.tool_records.setdefault(command.tool_number, command)
            summary.tool_sequence.append(command.tool_number)
            summary.tool_speeds.append(None)
            if command.tool_number not in summary.tools:
                summary.tools.append(command.tool_number)
        elif isinstance(command, (RapidMove, LinearMove, ArcMove)):
            target = [command.x if command.x is not None else pos[0],
                      command.y if command.y is not None else pos[1],
                      command.z if command.z is not None else pos[2]]
            if isinstance(command, RapidMove):
                seconds += travel(target, rapid_rate)
            else:
                feed = command.feed if command.feed is not None else feed
                if isinstance(command, ArcMove) and None not in pos and None not in target:
                    centre = (command.cx if command.cx is not None else pos[0],
                              command.cy if command.cy is not None else pos[1],
                              command.cz if command.cz is not None else pos[2])
                    length = arc_length(tuple(pos), tuple(target), centre,  # type: ignore
                                        command.arc_direction == "cw", command.plane)
                    if feed:
                        seconds += length / feed * 60.0
                else:
                    seconds += travel(target, feed)
            pos = target
            add_point(pos)
        elif isinstance(command, WorkPlane):
            # the tool stays where it is: its position restated in the new plane
            part = pos
            if plane is not None and None not in pos:
                o, ex, ey, ez = plane
                p = [v or 0.0 for v in pos]
                part = [o[i] + ex[i] * p[0] + ey[i] * p[1] + ez[i] * p[2] for i in range(3)]
            if command.work_plane == "reset":
                plane = None
            else:
                ex = (command.x_axis_i, command.x_axis_j, command.x_axis_k)
                ez = (command.z_axis_i, command.z_axis_j, command.z_axis_k)
                ey = (ez[1] * ex[2] - ez[2] * ex[1], ez[2] * ex[0] - ez[0] * ex[2],
                      ez[0] * ex[1] - ez[1] * ex[0])
                plane = ((command.origin_x, command.origin_y, command.origin_z), ex, ey, ez)
            if None in part:
                pos = [None, None, None]
            elif plane is None:
                pos = part
            else:
                d = [(part[i] or 0.0) - plane[0][i] for i in range(3)]
                pos = [sum(axis[i] * d[i] for i in range(3)) for axis in plane[1:]]
        elif isinstance(command, SpindleOn):
            if summary.tool_speeds and summary.tool_speeds[-1] is None:
                summary.tool_speeds[-1] = command.spindle_speed
        elif isinstance(command, Dwell):
            seconds += command.dwell
        elif isinstance(command, SafeRetract):
            add("z", command.z)  # a height the tool reaches, not a position
        elif isinstance(command, (DrillSetup, CycleHole)):
            if isinstance(command, DrillSetup):
                cycle = command
            if cycle is None:
                continue
            top = cycle.top if isinstance(command, DrillSetup) or command.top is None \
                else command.top
            x = command.x if command.x is not None else pos[0]
            y = command.y if command.y is not None else pos[1]
            retract = cycle.retract if cycle.retract is not None else top + cycle.clearance
            bottom = top - cycle.depth
            seconds += travel([x, y, pos[2]], rapid_rate)
            cut_feed = cycle.feed if cycle.feed is not None else feed
            if cut_feed:
                seconds += 2 * (top + cycle.clearance - bottom) / cut_feed * 60.0
            seconds += cycle.dwell
            for level in (bottom, retract, top + cycle.clearance):
                add_point([x, y, level])
            pos = [x, y, retract]
    summary.extents = {f"{end}_{axis}": side.get(axis) for axis in "xyz"
                       for end, side in (("min", low), ("max", high))}
    summary.machining_time = given_time if given_time is not None else seconds
    return summary


def typed(value: Any) -> Any:
    """A value with its type, NaN equal to itself: ``-140`` and ``-140.0`` differ here."""
    if isinstance(value, float) and value != value:
        return (float, "nan")
    return (type(value), value)


def facts(summary: ProgramSummary) -> dict[str, Any]:
    """Everything a summary holds, comparable type for type (tool records by their line too)."""
    return {
        "tools": [typed(t) for t in summary.tools],
        "tool_records": [(typed(k), v, v.line) for k, v in summary.tool_records.items()],
        "extents": [(k, typed(v)) for k, v in summary.extents.items()],
        "machining_time": typed(summary.machining_time),
        "tool_sequence": [typed(t) for t in summary.tool_sequence],
        "tool_speeds": [typed(s) for s in summary.tool_speeds],
        "values": [(k, typed(v) if not isinstance(v, list) else v)
                   for k, v in summary.values().items()],
    }


def outcome(fold: Any) -> Any:
    try:
        return ("summary", facts(fold()))
    except CLError as exc:
        return ("error", exc.message, exc.location)


def fold_text(text: str, file: str = "f.jsonl", fmt: str | None = None,
              moves: bool = True) -> ProgramSummary:
    """The first pass as ``CLSource.fold`` runs it, over text in memory."""
    folder = SummaryFolder(RAPID_RATE, moves)
    fold_commands(SourceLines(text_blocks(text), file), folder, fmt)
    return folder.summary()


def without_moves(expected: Any) -> Any:
    """What a first pass that leaves the moves out gives for ``expected``: the same error,
    or the same tools, and none of the values only the moves give."""
    if expected[0] != "summary":
        return expected
    facts = {key: value for key, value in expected[1].items()
             if key not in ("extents", "machining_time")}
    facts["values"] = [(key, value) for key, value in facts["values"]
                       if key not in MOVE_VALUES]
    return ("summary", facts)


def tools_outcome(fold: Any) -> Any:
    """:func:`outcome` of a first pass that leaves the moves out (their values unset)."""
    found = outcome(fold)
    if found[0] == "summary":
        assert found[1]["extents"] == [] and found[1]["machining_time"] == (float, 0.0)
    return without_moves(found)


def assert_same(text: str, file: str = "f.jsonl", fmt: str | None = None) -> Any:
    expected = outcome(lambda: reference_summary(read_cl_text(text, file, fmt), RAPID_RATE))
    assert outcome(lambda: summarize(read_cl_text(text, file, fmt), RAPID_RATE)) == expected
    assert outcome(lambda: fold_text(text, file, fmt)) == expected
    assert tools_outcome(lambda: fold_text(text, file, fmt, moves=False)) == \
        without_moves(expected)
    return expected


# --- generated programs ------------------------------------------------------------------

_FLOAT = st.floats(-1e4, 1e4, allow_nan=False, allow_infinity=False)
_NUMBER = st.one_of(_FLOAT, st.integers(-10_000, 10_000),
                    st.sampled_from([0, 0.0, -0.0, 2**53, -2**53, 1e-7, 1e300, 5e-324]))
#: what a field may hold instead, each refused by the reader or read as left out (null)
_ODD = st.sampled_from([None, True, False, "1", [1], {"a": 1}, 2**53 + 1, 10**400])
_LITERALS = ("NaN", "Infinity", "-Infinity", "1e400")


def _value(draw: st.DrawFn, odd: bool) -> Any:
    if odd and draw(st.integers(0, 30)) == 0:
        return draw(_ODD)
    return draw(_NUMBER)


@st.composite
def move(draw: st.DrawFn, odd: bool) -> dict[str, Any]:
    kind = draw(st.sampled_from(["linear_move", "linear_move", "rapid_move", "arc_move"]))
    axes = ["x", "y", "z"] + (["feed"] if kind != "rapid_move" else [])
    if kind == "arc_move":
        axes += ["cx", "cy", "cz"]
    record: dict[str, Any] = {"cmd": kind}
    for axis in axes:
        if draw(st.integers(0, 4)):  # an axis left out one time in five
            record[axis] = _value(draw, odd)
    if kind == "arc_move":
        for name, choices in (("arc_direction", ["cw", "ccw"]), ("plane", ["xy", "zx", "yz"])):
            if draw(st.booleans()):
                record[name] = draw(st.sampled_from(choices + ([None, "xz", 1]
                                                                if odd else [])))
    return record


@st.composite
def other(draw: st.DrawFn, odd: bool) -> dict[str, Any]:
    kind = draw(st.sampled_from(["tool_change", "spindle_on", "dwell", "drill", "cycle_hole",
                                 "cycle_end", "comment", "program_start", "coolant_on"]))
    if kind == "tool_change":
        return {"cmd": kind, "tool_number": draw(st.integers(1, 6)),
                "tool_diameter": draw(st.sampled_from([3, 6.5, 10]))}
    if kind == "spindle_on":
        return {"cmd": kind, "spindle_speed": draw(st.sampled_from([1000, 2500.5, 0]))}
    if kind == "dwell":
        return {"cmd": kind, "dwell": draw(st.sampled_from([0.5, 2, 0]))}
    if kind == "drill":
        record = {"cmd": draw(st.sampled_from(DRILL_SETUPS)), "x": _value(draw, odd),
                  "y": _value(draw, odd), "top": draw(_FLOAT), "depth": draw(st.integers(0, 30)),
                  "clearance": draw(st.sampled_from([2, 5.5]))}
        for name in ("retract", "feed", "dwell", "peck"):
            if draw(st.booleans()):
                record[name] = abs(draw(_FLOAT))
        return record
    if kind == "cycle_hole":
        record = {"cmd": kind, "x": _value(draw, odd), "y": _value(draw, odd)}
        if draw(st.booleans()):
            record["top"] = draw(_FLOAT)
        return record
    if kind == "comment":
        return {"cmd": kind, "comment": draw(st.sampled_from(["rough", "\\ backslash", "é"]))}
    if kind == "program_start":
        record = {"cmd": kind, "program_name": "P"}
        if draw(st.booleans()):
            record["machining_time"] = draw(st.sampled_from([120, 33.5, 0]))
        return record
    return {"cmd": kind}


def render(record: dict[str, Any], draw: st.DrawFn, odd: bool) -> str:
    """One record as a writer might put it: key order, spacing, a key twice, a literal."""
    items = list(record.items())
    if draw(st.integers(0, 5)) == 0:
        items = draw(st.permutations(items))
    separators = draw(st.sampled_from([(", ", ": "), (",", ":"), (" , ", " :  "),
                                       (",\t", ":")]))
    parts = [json.dumps(k) + separators[1] + json.dumps(v) for k, v in items]
    if odd and len(parts) > 1 and draw(st.integers(0, 30)) == 0:
        parts.append(parts[-1])  # a key given twice
    if odd and len(parts) > 1 and draw(st.integers(0, 30)) == 0:
        key = json.dumps(items[-1][0])
        parts[-1] = key + separators[1] + draw(st.sampled_from(_LITERALS))
    if odd and draw(st.integers(0, 40)) == 0:
        parts.append('"bogus": 1')
    text = "{" + separators[0].join(parts) + "}"
    return text + draw(st.sampled_from(["", "", " ", "\t"]))


@st.composite
def programs(draw: st.DrawFn, odd: bool = False) -> str:
    lines = []
    if draw(st.booleans()):
        lines.append(render({"cmd": "program_start", "program_name": "P",
                             **({"machining_time": 99.5} if draw(st.booleans()) else {})},
                            draw, odd))
    for _ in range(draw(st.integers(0, 40))):
        choice = draw(st.integers(0, 9))
        if choice < 7:
            lines.append(render(draw(move(odd)), draw, odd))
        elif choice < 9:
            lines.append(render(draw(other(odd)), draw, odd))
        else:
            lines.append(draw(st.sampled_from(["", "# a note", "   "])))
    if not odd or draw(st.integers(0, 20)):
        lines.append('{"cmd": "program_end"}')
    if odd and draw(st.integers(0, 20)) == 0:
        lines.append('{"cmd": "linear_move", "x": 1}')  # after the end
    return "\n".join(lines) + "\n"


_SETTINGS = settings(deadline=None,
                     suppress_health_check=[HealthCheck.too_slow])


@_SETTINGS
@given(programs())
@example('{"cmd": "rapid_move", "z": 5}\n{"cmd": "linear_move", "x": 1, "y": 2, "feed": 100}\n'
         '{"cmd": "linear_move", "x": 3, "y": 2, "z": 5}\n{"cmd": "program_end"}\n')
@example('{"cmd": "single_peck", "x": 1, "y": 2, "top": 1e308, "depth": -1e308, '
         '"clearance": 1e308}\n{"cmd": "linear_move", "x": 1, "y": 2, "z": 0, "feed": 5}\n'
         '{"cmd": "program_end"}\n')
@example('{"cmd": "arc_move", "x": 1, "y": 1, "z": 1}\n{"cmd": "arc_move", "x": 0, '
         '"cx": 1, "cy": 0, "plane": "zx", "arc_direction": "cw", "feed": -5}\n'
         '{"cmd": "program_end"}\n')
def test_a_generated_program_folds_to_the_summary_its_commands_give(text: str) -> None:
    assert assert_same(text)[0] == "summary"


@_SETTINGS
@given(programs(odd=True))
@example('{"cmd": "linear_move", "x": 1, "x": 2}\n{"cmd": "program_end"}\n')
@example('{"cmd": "linear_move", "x": true}\n{"cmd": "program_end"}\n')
@example('{"cmd": "linear_move", "x": NaN}\n{"cmd": "program_end"}\n')
@example('{"cmd": "linear_move", "x": 9007199254740993}\n{"cmd": "program_end"}\n')
@example('{"cmd": "arc_move", "plane": null}\n{"cmd": "program_end"}\n')
@example('{"cmd": "linear_move", "x": null, "feed": null}\n{"cmd": "program_end"}\n')
@example('{"cmd": "program_end"}\n{"cmd": "rapid_move", "x": 1}\n')
@example('{"cmd": "rapid_move", "x": 1}\n')
def test_an_odd_program_folds_or_fails_as_the_full_reading_does(text: str) -> None:
    """Nulls, keys given twice, wrong kinds, numbers too large, a missing or early
    program_end: the same summary, or the same error at the same line."""
    assert_same(text)


# --- the records the fast fold takes -------------------------------------------------------


class Recorder:
    """A sink that keeps what it is handed."""

    moves = True

    def __init__(self) -> None:
        self.calls: list[tuple[str, tuple[Any, ...]]] = []

    def rapid(self, *values: Any) -> None:
        self.calls.append(("rapid_move", values))

    def linear(self, *values: Any) -> None:
        self.calls.append(("linear_move", values))

    def arc(self, *values: Any) -> None:
        self.calls.append(("arc_move", values))


def fields(command: CLCommand) -> tuple[Any, ...]:
    """A move command's fields in the order the sink takes them, with their types."""
    if isinstance(command, ArcMove):
        values = (command.x, command.y, command.z, command.cx, command.cy, command.cz,
                  command.arc_direction == "cw", command.plane, command.feed)
    elif isinstance(command, LinearMove):
        values = (command.x, command.y, command.z, command.feed)
    else:
        values = (command.x, command.y, command.z)  # type: ignore[attr-defined]
    return tuple(typed(v) for v in values)


@settings(deadline=None)
@given(st.data())
def test_a_record_the_taker_takes_is_the_move_the_full_reading_reads(data: st.DataObject) -> None:
    record = data.draw(st.one_of(move(odd=True), other(odd=True)))
    text = render(record, data.draw, True)
    sink = Recorder()
    taken = bool(move_taker(sink)(text, 3))
    assert len(sink.calls) == int(taken)
    if not taken:
        return
    command = record_to_command(json.loads(text), Location("f", 3))
    assert sink.calls[0][0] == command.name
    assert tuple(typed(v) for v in sink.calls[0][1]) == fields(command)
    pairs = json.loads(text, object_pairs_hook=list)
    assert len(pairs) == len({key for key, _ in pairs})


def test_the_plain_moves_take_the_fast_fold() -> None:
    """The records a finishing program is made of are taken without a command."""
    sink = Recorder()
    take = move_taker(sink)
    for text in ('{"cmd": "linear_move", "x": -88.1818, "y": -140, "z": -1.6932}',
                 '{"cmd": "linear_move", "x": 1.5, "feed": 1200}',
                 '{"cmd":"rapid_move","z":20}  ',
                 '{"cmd": "arc_move", "x": 90, "y": -138.0, "cx": 90, "cy": -139, '
                 '"arc_direction": "cw", "feed": 900}',
                 '{"cmd": "arc_move", "z": 1, "plane": "yz"}'):
        assert take(text, 1), text
    for text in ('{"cmd": "tool_change", "tool_number": 1}', '{"cmd": "program_end"}',
                 '{"cmd": "linear_move", "x": "1"}', '{"cmd": "linear_move", "x": 1, "x": 2}',
                 '{"cmd": "linear_move", "q": 1}', '{"cmd": "arc_move", "plane": "xz"}',
                 '{"cmd": "linear_move", "x": 1e400}', '[1]', '{"cmd": "linear_move"} x'):
        assert not take(text, 1), text
    assert [name for name, _ in sink.calls] == ["linear_move"] * 2 + ["rapid_move"] + \
        ["arc_move"] * 2


def test_a_native_first_pass_makes_no_command_for_a_plain_move(monkeypatch) -> None:
    """Only the rare records reach the folder as commands."""
    folder = SummaryFolder(RAPID_RATE)
    seen: list[str] = []
    monkeypatch.setattr(folder.__class__, "command",
                        lambda self, command: seen.append(command.name))
    text = (EXAMPLES / "emco_drilling.jsonl").read_text(encoding="utf-8")
    fold_commands(SourceLines(text_blocks(text), "emco_drilling.jsonl"), folder)
    assert seen and not {"rapid_move", "linear_move", "arc_move"} & set(seen)
    assert "tool_change" in seen and seen[-1] == "program_end"


# --- every CL file of the repository ------------------------------------------------------

CL_FILES = sorted(path for folder in (EXAMPLES, DATA) for path in folder.rglob("*")
                  if path.suffix in {".jsonl", ".apt", ".gcode", ".ncl"}
                  or path.name.endswith(".dump.txt"))


def test_the_repository_has_cl_files_of_every_format() -> None:
    suffixes = {path.suffix for path in CL_FILES}
    assert {".jsonl", ".apt", ".gcode", ".ncl", ".txt"} <= suffixes and len(CL_FILES) > 30


@pytest.mark.parametrize("path", CL_FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_cl_file_gives_the_summary_of_its_commands(path: Path) -> None:
    def first_pass(moves: bool = True) -> ProgramSummary:
        with CLSource(path) as source:
            return summarize_source(source, RAPID_RATE, moves=moves)

    expected = outcome(lambda: reference_summary(read_cl(path), RAPID_RATE))
    assert outcome(lambda: summarize(read_cl(path), RAPID_RATE)) == expected
    assert outcome(first_pass) == expected
    assert tools_outcome(lambda: first_pass(moves=False)) == without_moves(expected)


@pytest.mark.parametrize("fmt", ["native", "apt", "freecad"])
def test_a_generated_raster_gives_the_summary_of_its_commands(fmt: str) -> None:
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        import make_program
    finally:
        sys.path.remove(str(ROOT / "benchmarks"))
    out = io.StringIO()
    getattr(make_program, f"write_{fmt}")(3_000, out)
    expected = assert_same(out.getvalue(), f"raster.{fmt}", fmt)
    assert expected[0] == "summary"
    assert dict(expected[1]["extents"])["min_x"][1] < -80


# --- the first pass's guarantees ---------------------------------------------------------


def _raster(count: int) -> list[str]:
    lines = ['{"cmd": "program_start", "program_name": "R"}',
             '{"cmd": "tool_change", "tool_number": 1, "tool_diameter": 6}',
             '{"cmd": "spindle_on", "spindle_speed": 3000}',
             '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 5}']
    lines += [f'{{"cmd": "linear_move", "x": {i % 50}, "y": {i // 50 % 100}, "z": -1, "feed": 500}}'
              for i in range(count)]
    return [*lines, '{"cmd": "program_end"}']


def test_a_bad_move_deep_in_the_file_stops_the_first_pass_at_its_line(tmp_path: Path) -> None:
    lines = _raster(2_000)
    lines.insert(1_500, '{"cmd": "linear_move", "x": 1, "feed": "fast"}')
    cl = tmp_path / "job.jsonl"
    cl.write_text("\n".join(lines) + "\n", encoding="utf-8")
    posted: list[str] = []

    class Watch:
        def write(self, text: str) -> None:
            posted.append(text)

    with pytest.raises(CLError) as caught:
        api.write_program("vmc500", cl, tmp_path / "job.nc", copy_to=Watch())  # type: ignore
    assert caught.value.location == Location(str(cl), 1_501)
    assert caught.value.message == "linear_move: 'feed' must be a number, not \"fast\""
    assert posted == [] and not (tmp_path / "job.nc").exists()


def test_the_first_pass_reports_progress_and_posts_what_a_list_posts(tmp_path: Path,
                                                                     monkeypatch) -> None:
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1611291450")
    cl = tmp_path / "job.jsonl"
    cl.write_text("\n".join(_raster(15_000)) + "\n", encoding="utf-8")
    reports: list[tuple[str, int, int | None]] = []
    out = tmp_path / "job.nc"
    api.write_program("vmc500", cl, out,
                      progress=lambda name, done, total: reports.append((name, done, total)))
    size = cl.stat().st_size
    reading = [done for name, done, total in reports if name == "reading" and total == size]
    assert reading == sorted(reading) and reading[-1] == size and len(reading) > 2
    post = api.load_post("vmc500")
    expected = api.post_text(post, api.post_commands(post, read_cl(cl), cl_file=str(cl)))
    assert out.read_text(encoding="utf-8") == expected


def test_a_file_changed_after_the_first_pass_is_refused(tmp_path: Path) -> None:
    cl = tmp_path / "job.jsonl"
    cl.write_text("\n".join(_raster(100)) + "\n", encoding="utf-8")
    with CLSource(cl) as source:
        summary = summarize_source(source, RAPID_RATE)
        assert summary.tools == [1]
        cl.write_text("\n".join(_raster(101)) + "\n", encoding="utf-8")
        with pytest.raises(CLError, match="changed while it was being posted"):
            list(source.commands())


# --- a first pass folds what the post reads ------------------------------------------------


class _CountingFolder(SummaryFolder):
    """Counts the moves handed to it, as fields or as commands."""

    __slots__ = ("handed",)

    def __init__(self, rapid_rate: float, moves: bool = True,
                 kinematics: Kinematics | None = None) -> None:
        super().__init__(rapid_rate, moves, kinematics)
        self.handed = 0

    def rapid(self, *fields: Any) -> None:
        self.handed += 1
        super().rapid(*fields)

    def linear(self, *fields: Any) -> None:
        self.handed += 1
        super().linear(*fields)

    def arc(self, *fields: Any) -> None:
        self.handed += 1
        super().arc(*fields)


@pytest.mark.parametrize(("machine", "folds"), [("vmc500", True), ("heidenhain", True),
                                                ("grbl", True), ("linuxcnc", False),
                                                ("fanuc", False), ("emco", False)])
def test_the_first_pass_folds_the_moves_only_for_a_post_that_reads_their_values(
        machine: str, folds: bool, tmp_path: Path, monkeypatch) -> None:
    """vmc500 prints the time and the extents, Heidenhain a blank of the extents, GRBL
    lifts to max_z; the others read no value only the moves give, and their first pass
    leaves the moves out -- posting the same program all the same."""
    folders: list[_CountingFolder] = []

    def counting(rapid_rate: float, moves: bool = True,
                 kinematics: Kinematics | None = None) -> _CountingFolder:
        folders.append(_CountingFolder(rapid_rate, moves, kinematics))
        return folders[-1]

    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1611291450")
    monkeypatch.setattr("postdsl.run.program.SummaryFolder", counting)
    cl = tmp_path / "job.jsonl"
    cl.write_text("\n".join(_raster(300)) + "\n", encoding="utf-8")
    out = tmp_path / "job.nc"
    api.write_program(machine, cl, out)
    [folder] = folders
    assert folder.moves is folds and (folder.handed == 301) is folds
    assert folds or folder.handed == 0
    post = api.load_post(machine)
    expected = api.post_text(post, api.post_commands(post, read_cl(cl), cl_file=str(cl)))
    assert out.read_text(encoding="utf-8") == expected


def test_a_post_edited_to_print_the_time_gets_the_moves_folded(tmp_path: Path,
                                                               monkeypatch) -> None:
    """The decision follows what the post reads: a LinuxCNC post whose header prints the
    machining time posts the time of the whole program."""
    source = (ROOT / "machines" / "linuxcnc.yaml").read_text(encoding="utf-8")
    blocks = source.index("    blocks:\n", source.index("\n  program_start:\n"))
    block = '      - items: ["(TIME ", {param: machining_time, format: coord}, " S)"]\n'
    at = blocks + len("    blocks:\n")
    post = tmp_path / "timed.yaml"
    post.write_text(source[:at] + block + source[at:], encoding="utf-8")
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1611291450")
    cl = tmp_path / "job.jsonl"
    cl.write_text("\n".join(_raster(300)) + "\n", encoding="utf-8")
    out = tmp_path / "job.nc"
    api.write_program(post, cl, out)
    seconds = summarize(read_cl(cl), api.load_post(post).machine.rapid_rate).machining_time
    assert seconds > 1
    assert f"(TIME {seconds:.3f} S)" in out.read_text(encoding="utf-8")


def test_the_safe_retract_before_the_first_tool_is_the_programs_highest_z(
        tmp_path: Path) -> None:
    """A program whose only high Z is the CAM's "go safe" before its first tool: a post that
    lifts to max_z at a tool change (GRBL's manual change) must go up to it, not down to
    the highest cut (it went from Z25 down to Z5 with the tool over the part)."""
    program = tmp_path / "safe.gcode"
    program.write_text("G21\nG0 Z25\nT1\nM6\nS5000 M3\nG4 P1\nG0 X0 Y0 Z2\nG1 Z-1 F100\n"
                       "G1 X10\nG0 Z5\nM2\n", encoding="utf-8")
    commands = read_cl(program)
    assert any(command.name == "safe_retract" for command in commands)
    assert summarize(commands, 1000.0).values()["max_z"] == 25
    lines = api.post_file("grbl", program).splitlines()
    change = lines.index("T1 M0")
    assert lines[change + 1] == "G0 Z25"
