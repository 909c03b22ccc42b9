"""G95 in plain G-code: F per revolution is the CL's feed per minute at the spindle speed
in force, converted again when S changes; without a speed the cutting move is refused at
its line; G93 (inverse time) is refused with its reason.  rs274 runs the G95 program
itself (SET_FEED_MODE 1: F times the speed) and the posts' G94 programs cut alike."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from postdsl import api
from postdsl.cl.model import LinearMove
from postdsl.errors import CLError
from tests.conftest import THESIS_TIME
from tests.test_reader_gcode import compare_cuts, rs274_cuts
from tests.test_rs274_oracle import for_rs274, needs_rs274, rs274_process

PROGRAM = ("G21 G90 G17\nT1 M6\nG95 F0.1 S1200 M3\nG0 X0 Y0 Z5\nG1 Z-1\nX10\nS1500\nX20\n"
           "G2 X30 Y0 I5 J0\nG94\nG1 X40 F300\nG95 G1 Y10 F0.05\nG0 Z5\nM5\nM30\n")


def read(text: str) -> list:
    return api.read_cl_text(text, "p.ngc", "gcode")


def feeds(text: str) -> list[tuple[int, float | None]]:
    return [(c.line, c.feed) for c in read(text) if hasattr(c, "feed")
            and c.name in ("linear_move", "arc_move")]


def test_feed_per_revolution_is_the_feed_per_minute_at_the_speed_in_force() -> None:
    """0.1 mm/rev at 1200 rpm is 120 mm/min (line 5; line 6 keeps it), at 1500 rpm 150
    (the S alone on line 7 changes it for the next move); G94 F300 is per minute; back in
    G95, 0.05 mm/rev at 1500 rpm is 75 -- products of the decimals written, rounded once."""
    assert feeds(PROGRAM) == [(5, 120.0), (6, None), (8, 150.0), (9, None), (11, 300.0),
                              (12, 75.0)]


def test_an_inch_feed_per_revolution_is_converted_exactly() -> None:
    moves = [c for c in read("G20 G90\nT1 M6\nS1000 M3\nG95 G1 X1 Z0 F0.004\nM30\n")
             if isinstance(c, LinearMove)]
    assert [(m.x, m.feed) for m in moves] == [(25.4, 101.6)]


@pytest.mark.parametrize(("program", "line", "reason"), [
    ("T1 M6\nG95 F0.1\nG0 X0 Y0 Z5\nG1 Z-1\nM30\n", 4,
     "a cutting move at F0.1 per revolution (G95) with no spindle speed S in force"),
    ("T1 M6\nG0 X0 Y0 Z5\nG95 G1 Z-1 F0.1\nM30\n", 3, "no spindle speed S in force"),
    ("T1 M6\nS1000 M3\nG1 X1 F100\nG95\nG1 X2\nM30\n", 5,
     "G1 is a cutting move but no feed F was given before it"),
    ("T1 M6\nG93\nG1 X1 F2\nM30\n", 2, "inverse-time feed (G93) is not read: its F is one "
                                       "over the move's time"),
    ("G94 G95\nM30\n", 1, "G94 and G95 in one block"),
])
def test_what_cannot_be_converted_is_refused_at_its_line(program: str, line: int,
                                                         reason: str) -> None:
    with pytest.raises(CLError) as caught:
        read(program)
    assert caught.value.location is not None and caught.value.location.line == line
    assert reason in caught.value.message


def _rs274_per_minute(program: str, tmp_path: Path) -> list[float]:
    """rs274's own reading of the G95 program: each STRAIGHT_FEED / ARC_FEED's feed per
    minute (SET_FEED_MODE(0, 1): the feed rate times SET_SPINDLE_SPEED)."""
    ngc, table = tmp_path / "g95.ngc", tmp_path / "g95.tbl"
    ngc.write_text(program, encoding="utf-8")
    table.write_text("T1 P1 Z0 D0\n", encoding="utf-8")
    result = rs274_process(table, ngc)
    assert result.returncode == 0, result.stderr
    mode, rate, speed, out = 0, 0.0, 0.0, []
    for raw in result.stdout.splitlines():
        call = re.search(r"([A-Z_]+)\((.*)\)", raw)
        if call is None:
            continue
        name, args = call.groups()
        values = [float(v) for v in re.findall(r"-?\d+\.\d+|-?\d+", args)]
        if name == "SET_FEED_MODE":
            mode = int(values[-1])
        elif name == "SET_FEED_RATE":
            rate = values[0]
        elif name == "SET_SPINDLE_SPEED":
            speed = values[-1]
        elif name in ("STRAIGHT_FEED", "ARC_FEED"):
            out.append(rate * speed if mode == 1 else rate)
    return out


@needs_rs274
@pytest.mark.parametrize("machine", ["fanuc", "linuxcnc"])
def test_rs274_cuts_the_posted_program_as_the_g95_program(machine: str,
                                                         tmp_path: Path) -> None:
    expected = _rs274_per_minute(PROGRAM, tmp_path)
    assert expected == [120.0, 120.0, 150.0, 150.0, 300.0, 75.0]
    post = api.load_post(machine)
    commands = read(PROGRAM)
    verdict = api.verify_commands(post, commands)
    assert verdict.ok, verdict.divergence
    lines = [line.text for line in api.post_commands(post, commands, cl_file="p.ngc",
                                                     now=THESIS_TIME)]
    posted = rs274_cuts(for_rs274(lines) if machine == "fanuc" else lines, tmp_path)
    assert [cut.feed for cut in posted] == pytest.approx(expected, abs=0.5)
    original = rs274_cuts(PROGRAM.replace("G95 F0.1", "F120").replace("S1500\n", "S1500 F150\n")
                          .replace("G95 G1 Y10 F0.05", "G1 Y10 F75").splitlines(), tmp_path)
    assert compare_cuts(posted, original, 0.001) == 6


def test_a_drilling_cycle_in_g95_feeds_per_minute_at_its_speed() -> None:
    """G81 F0.1 at 1000 rpm drills (single_peck) at 100 mm/min; after S2000 (which ends the
    cycle) the next cycle block is a new setup at 200."""
    records = read("T1 M6\nS1000 M3\nG0 X0 Y0 Z5\nG95 G99 G81 X1 Y1 Z-3 R2 F0.1\nS2000\n"
                   "G81 X5 Y1 Z-3 R2\nG80\nM30\n")
    assert [(c.line, c.feed) for c in records if c.name == "single_peck"] == [(4, 100.0),
                                                                          (6, 200.0)]


def test_freecad_g_code_reads_g95_as_the_g_code_reader_does() -> None:
    """A FreeCAD post's G-code (mm/min) with G95: F0.1 at S1000 is 100 mm/min; G94 drops
    it, F200 is per minute again.  In FreeCAD's internal path (mm/s) G95 is refused."""
    text = ("(Exported by FreeCAD)\nG21\nM6 T1\nM3 S1000\nG0 X0 Y0 Z5\nG95\nG1 X1 F0.1\n"
            "G1 X2\nG94\nG1 X3 F200\nM2\n")
    moves = [(c.line, c.feed) for c in api.read_cl_text(text, "p.ngc")
             if isinstance(c, LinearMove)]
    assert moves == [(7, 100.0), (8, None), (10, 200.0)]
    with pytest.raises(CLError) as caught:
        api.read_cl_text("M6 T1\nM3 S1000\nG0 X0 Y0 Z5\nG95\nG1 X1 F0.1\nM2\n", "p.ngc",
                         "freecad", feed_units="mm/s")
    assert caught.value.location is not None and caught.value.location.line == 4
    assert "G95 (feed per revolution) in a file whose feeds are mm/s" in caught.value.message
