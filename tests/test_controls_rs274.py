"""The ISO control models against LinuxCNC's own interpreter ``rs274``, where the dialects meet.

rs274 prints the canonical motion a program means; the Fanuc and LinuxCNC
models yield events for the same text.  Line by line, every feed move and arc
of a model must be rs274's (end point, centre, sense, feed), every hole must be
what rs274's expanded cycle does (X Y, the R level its feed starts from, the
bottom, where the tool is left, the dwell), every dwell rs274's, and rs274 must
cut nothing the model does not.  The Fanuc programs go through the documented
rewrite of tests/test_rs274_oracle.py (P in ms -> s, macro calls as comments).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from postdsl import api
from postdsl.check.controls import NCInput, control_model
from postdsl.check.controls.events import ArcMove, Dwell, FeedMove, Hole, Rapid
from tests.conftest import EXAMPLES, THESIS_TIME
from tests.test_rs274_oracle import Trace, for_rs274, needs_rs274, run_rs274

TOL = 1e-4


def near(a: float | None, b: float) -> bool:
    return a is not None and abs(a - b) <= TOL


def cross_check(events: list, trace: Trace) -> dict[str, int]:
    """Compare a model's events with rs274's calls, NC line by NC line; what was compared."""
    moves: dict[int, list] = {}
    for move in trace.moves:
        moves.setdefault(move.line, []).append(move)
    dwells: dict[int, list[float]] = {}
    for line, seconds in trace.dwells:
        dwells.setdefault(line, []).append(seconds)
    counted = {"feed": 0, "arc": 0, "hole": 0, "dwell": 0, "rapid": 0}
    cut_lines: set[int] = set()
    for event in events:
        line = event.origin.line
        theirs = moves.get(line, [])
        where = f"NC line {line}: {event.origin.text}"
        if isinstance(event, FeedMove):
            feeds = [m for m in theirs if m.kind == "feed"]
            assert len(feeds) == 1 and all(near(a, b) for a, b in zip(event.end, feeds[0].end,
                                                                      strict=True)), where
            rate = feeds[0].feed * (feeds[0].speed if feeds[0].per_rev else 1)
            assert event.feed == pytest.approx(rate, abs=1e-3), where
            counted["feed"] += 1
            cut_lines.add(line)
        elif isinstance(event, ArcMove):
            arcs = [m for m in theirs if m.kind == "arc"]
            assert len(arcs) == 1, where
            arc = arcs[0]
            assert all(near(a, b) for a, b in zip(event.end, arc.end, strict=True)), where
            for axis, value in enumerate(arc.centre):
                if value is not None:
                    assert near(event.centre[axis], value), f"{where}: centre"
            assert (arc.rotation < 0) == event.clockwise, f"{where}: sense"
            counted["arc"] += 1
            cut_lines.add(line)
        elif isinstance(event, Hole):
            feeds = [m for m in theirs if m.kind == "feed"]
            assert feeds, f"{where}: rs274 drills nothing"
            assert all(near(m.end[0], event.x) and near(m.end[1], event.y) for m in theirs[1:])
            assert near(feeds[0].start[2], event.r), f"{where}: R level"
            assert near(min(m.end[2] for m in feeds), event.bottom), f"{where}: bottom"
            assert near(theirs[-1].end[2], event.leave), f"{where}: leaves at"
            assert sum(dwells.get(line, [])) == pytest.approx(event.dwell, abs=1e-6), where
            counted["hole"] += 1
            cut_lines.add(line)
        elif isinstance(event, Dwell):
            assert dwells.get(line) == [pytest.approx(event.seconds)], where
            counted["dwell"] += 1
        elif isinstance(event, Rapid) and None not in event.end and theirs \
                and all(m.kind == "rapid" for m in theirs):
            assert any(all(near(a, b) for a, b in zip(event.end, m.end, strict=True))
                       for m in theirs), f"{where}: rapid to {event.end}"
            counted["rapid"] += 1
    # a feed block without an axis word ("G1 F9144") is a straight feed of no length to
    # rs274 (its canonical STRAIGHT_FEED to where the tool is), nothing to a machine
    extra = sorted(line for line, ms in moves.items()
                   if line not in cut_lines and any(m.kind != "rapid" and not (
                       m.kind == "feed" and m.start == m.end) for m in ms))
    assert not extra, f"rs274 cuts on lines the model does not: {extra}"
    return counted


FEELER_PROGRAMS = ["feeler_milling.apt", "feeler_drilling.apt", "emco_pocket.gcode"]


@needs_rs274
@pytest.mark.parametrize("example", FEELER_PROGRAMS)
def test_the_fanuc_model_moves_as_rs274_on_feeler_programs(example: str, tmp_path: Path) -> None:
    post = api.load_post("feeler")
    lines = [line.text for line in api.post_commands(post, api.read_cl(EXAMPLES / example),
                                                     now=THESIS_TIME)]
    trace = run_rs274(for_rs274(lines), tmp_path)
    counted = cross_check(list(control_model("fanuc-0i").replay(lines)), trace)
    assert counted["feed"] + counted["arc"] + counted["hole"] > 0


LINUXCNC_PROGRAM = """\
%
(a program in the dialect LinuxCNC and Fanuc share, plus LinuxCNC's own comments)
G17 G21 G40 G90 G94
T1 M6
G43 H1
S1200 M3
G0 X0 Y0 Z20 ; over the part
G0 Z2
G1 Z-1 F150
G1 X40 F600
G3 X50 Y10 I0 J10
G2 X60 Y20 R10
G2 X60 Y20 I5 J0
G3 X40 Y0 R-14.142136
G18 G2 X30 Z-1 I-5 K0
G19 G3 Y10 Z-1 J5 K0
G17
G4 P1.5
G0 Z20
G95 F0.1
G1 X10 Y10
G94
G99 G81 X10 Y10 Z-5 R2 F100
X20
G98 G82 X30 Y10 Z-6 R1 P0.5
G99 G83 X40 Y10 Z-12 R2 Q3
G73 X50 Y10 Z-8 R2 Q2.5
G80
G0 Z50
M5
M2
%
"""


@needs_rs274
def test_the_linuxcnc_model_moves_as_rs274(tmp_path: Path) -> None:
    lines = LINUXCNC_PROGRAM.splitlines()
    numbered = [f"N{i} {line}" if line.strip() not in ("%",) else line
                for i, line in enumerate(lines, start=1)]
    # '%' lines stay as they are: rs274 needs them bare; the numbers keep every move's line
    trace = run_rs274(numbered, tmp_path)
    events = list(control_model("linuxcnc").replay(NCInput(i, line) for i, line in
                                                   enumerate(numbered, start=1)))
    counted = cross_check(events, trace)
    assert counted == {"feed": 3, "arc": 6, "hole": 5, "dwell": 1, "rapid": 4}


@needs_rs274
def test_the_cross_check_tells_the_dialects_apart(tmp_path: Path) -> None:
    """Read as Fanuc, LinuxCNC's ``Z20`` is 0.020 mm (no decimal point, parameter 3401#0 = 0)
    and, in calculator input, its G4 P1.5 is 1.5 ms: the comparison with rs274 fails on each."""
    numbered = [f"N{i} {line}" if line.strip() != "%" else line
                for i, line in enumerate(LINUXCNC_PROGRAM.splitlines(), start=1)]
    trace = run_rs274(numbered, tmp_path)
    code = [line.split(";")[0] for line in numbered]
    as_fanuc = list(control_model("fanuc-0i").replay(code))
    with pytest.raises(AssertionError, match=r"NC line 7: N7 G0 X0 Y0 Z20 : rapid to "
                                             r"\(0\.0, 0\.0, 0\.02\)"):
        cross_check(as_fanuc, trace)
    calculator = list(control_model("fanuc-0i", calculator_input=True).replay(code))
    with pytest.raises(AssertionError, match=r"NC line 18: N18 G4 P1\.5"):
        cross_check(calculator, trace)


LINUXCNC_RIGID_TAPS = """\
G17 G21 G90 G94
T1 M6
G43 H1
S500 M3
G0 X10 Y10 Z20
G0 Z3
G33.1 Z-12 K1.25
G0 Z20
G0 X30
G0 Z2
G33.1 Z-9 K1.5
X30 Z-10 K1.5
M4
G0 X50
G33.1 Z-6 K0.8
G0 Z30
M5
M2
"""


@needs_rs274
def test_the_linuxcnc_model_taps_g33_1_as_rs274(tmp_path: Path) -> None:
    """G33.1: rs274's RIGID_TAP goes from the tool to the point at K per revolution and the
    tool is back where it began; the model's hole: R the start, the bottom, the feed K x S,
    the direction, and left at the rapid up that follows it (or at R)."""
    numbered = [f"N{i} {line}" for i, line in enumerate(LINUXCNC_RIGID_TAPS.splitlines(),
                                                        start=1)]
    trace = run_rs274(numbered, tmp_path)
    taps = [m for m in trace.moves if m.kind == "rigid_tap"]
    holes = [e for e in control_model("linuxcnc").replay(
        NCInput(i, line) for i, line in enumerate(numbered, start=1)) if isinstance(e, Hole)]
    assert len(holes) == len(taps) == 4
    for hole, tap in zip(holes, taps, strict=True):
        where = f"NC line {hole.origin.line}"
        assert tap.line == hole.origin.line, where
        assert (near(hole.x, tap.end[0]) and near(hole.y, tap.end[1])
                and near(hole.bottom, tap.end[2])), where
        assert tap.start == (hole.x, hole.y, hole.r), where      # it starts where the tool is
        assert hole.feed == pytest.approx(tap.feed), where
        assert hole.direction == tap.spindle, where
        after = [m for m in trace.moves if m.line > tap.line]
        if hole.leave != hole.r:  # the rapid straight up rs274 makes next
            assert after[0].kind == "rapid" and after[0].start == tap.start, where
            assert after[0].end == (hole.x, hole.y, hole.leave), where
        else:
            assert after[0].start == tap.start, where           # back where it began
    assert [h.leave for h in holes] == [20, 2, 2, 30]
