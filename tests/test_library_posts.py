"""The library posts (machines/fanuc.yaml, grbl.yaml, hmcnc.yaml): what each writes and refuses.

Their corpus snapshots are locked and verified in tests/test_snapshots.py; here
the Fanuc-family output is read by LinuxCNC's own interpreter (``rs274``) and
compared with the CL point by point, and the rules each post's header promises
are checked on small programs.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from ruamel.yaml import YAML

from postdsl import api
from tests.conftest import ROOT, THESIS_TIME
from tests.test_rs274_oracle import check_program, needs_rs274


def corpus_of(machine: str) -> list[str]:
    corpus = YAML(typ="safe").load((ROOT / "corpus.yaml").read_text(encoding="utf-8"))
    return list(corpus[machine])


def post(machine: str, cl: Path | str) -> list[str]:
    return [line.text for line in api.post_commands(
        api.load_post(machine), api.read_cl(ROOT / cl), now=THESIS_TIME)]


# --- fanuc.yaml -------------------------------------------------------------------------------

def _posts(machine: str, program: str) -> bool:
    try:
        post(machine, program)
    except api.CLError:
        return False
    return True


@needs_rs274
@pytest.mark.parametrize("program", corpus_of("fanuc"))
def test_every_fanuc_program_moves_to_the_cl_points_in_rs274(program: str,
                                                             tmp_path: Path) -> None:
    """rs274 reads each program the generic Fanuc post writes and moves where the CL says."""
    if not _posts("fanuc", program):
        pytest.skip("the post refuses this program (its snapshot locks the refusal)")
    moves, holes = check_program(str(ROOT / program), tmp_path, api.load_post("fanuc"),
                                 drill_per_rev=False)
    assert moves + holes > 0


# --- grbl.yaml --------------------------------------------------------------------------------

def _model_cuts(lines: list[str]) -> list[tuple[str, tuple[float, ...], tuple[float, ...]]]:
    """(kind, end, centre) of every cut the GRBL control model reads in a program."""
    from postdsl.controls import control_model
    from postdsl.controls.events import ArcMove, FeedMove

    cuts = []
    for event in control_model("grbl-1.1").replay(lines):
        if isinstance(event, FeedMove):
            cuts.append(("feed", tuple(event.end), ()))
        elif isinstance(event, ArcMove):
            cuts.append(("arc", tuple(event.end), tuple(event.centre)))
    return cuts  # type: ignore[return-value]


@needs_rs274
@pytest.mark.parametrize("program", corpus_of("grbl"))
def test_every_grbl_program_is_read_by_rs274_as_verify_reads_it(program: str,
                                                               tmp_path: Path) -> None:
    """rs274 takes each GRBL program unchanged (only numbered) and cuts what verify checked.

    ``postdsl verify`` (tests/test_snapshots.py) compares the grbl-1.1 model's reading
    of the program with the CL; here LinuxCNC's interpreter, independent of that model,
    must make the same cuts: every feed move and arc ends at the same point, every arc
    turns about the same centre, at the same feed.
    """
    from tests.test_rs274_oracle import run_rs274

    if not _posts("grbl", program):
        pytest.skip("the post refuses this program (its snapshot locks the refusal)")
    lines = post("grbl", program)
    trace = run_rs274([f"N{n} {line}" for n, line in enumerate(lines, start=1)], tmp_path)
    assert trace.units == {"CANON_UNITS_MM"}
    ours = _model_cuts(lines)
    theirs = [move for move in trace.moves if move.kind != "rapid"]
    assert len(theirs) == len(ours) > 0
    for (kind, end, centre), move in zip(ours, theirs, strict=True):
        where = f"NC line {move.line}: {lines[move.line - 1]}"
        assert move.kind == kind, where
        assert move.end == pytest.approx(end, abs=1e-3), where
        if kind == "arc":
            assert [c for c in move.centre if c is not None] == pytest.approx(
                [c for c, m in zip(centre, move.centre, strict=True) if m is not None],
                abs=1e-3), where
        assert not move.per_rev, where
    dwells = [seconds for _, seconds in trace.dwells]
    assert dwells == [pytest.approx(float(line.split("P")[1])) for line in lines
                      if line.startswith("G4 ")]


def test_grbl_writes_no_word_grbl_lacks() -> None:
    """No canned cycle, no M6, no G43 H, no G95 in any GRBL program of the corpus."""
    import re

    for program in corpus_of("grbl"):
        if not _posts("grbl", program):
            continue
        text = re.sub(r"\([^)]*\)", "", "\n".join(post("grbl", program)))  # not comments
        assert not re.search(r"\bG(7[346]|8[1-9]|9[58]|43)\b|\bM6\b|\bH\d", text), program


def test_grbl_changes_a_tool_at_a_pause_with_its_name() -> None:
    lines = post("grbl", "examples/feeler_milling.apt")
    pause = lines.index("T1 M0")
    assert lines[pause - 1] == "(Change to tool 1 D10, touch off Z, cycle start)"
    # the tool goes up before the pause and straight up again after it
    assert lines[pause - 2] == lines[pause + 1] == "G0 Z50"


@pytest.mark.parametrize("program", ["examples/feeler_drilling.apt",
                                     "examples/vmc500_cycles.jsonl"])
def test_grbl_refuses_a_tap(program: str) -> None:
    with pytest.raises(api.CLError, match="GRBL has no tapping cycle"):
        post("grbl", program)


def test_grbl_refuses_an_arc_its_arc_check_would_stop_on() -> None:
    """With one decimal, a 2 mm arc's written end is 0.2 mm off its written circle."""
    text = (ROOT / "machines" / "grbl.yaml").read_text(encoding="utf-8")
    rough = text.replace("  coord:                 # X10  X-2.5  X12.345 : 3 decimals (0.001 "
                         "mm), no needless zeros\n    decimals: 3",
                         "  coord:\n    decimals: 1").replace(", 3)", ", 1)")
    assert rough != text
    one_decimal = api.load_post_text(rough, "grbl_rough.yaml")
    cl = api.read_cl_text(
        '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 1}\n'
        '{"cmd": "spindle_on", "spindle_speed": 10000}\n'
        '{"cmd": "linear_move", "x": -1.7611, "y": 0.1988, "feed": 100}\n'
        '{"cmd": "arc_move", "x": 1.3752, "y": -1.8587, "cx": 0.1881, "cy": -0.2491, '
        '"arc_direction": "ccw"}\n{"cmd": "program_end"}\n', "<cl>", "native")
    with pytest.raises(api.CLError, match="error 33"):
        list(api.post_commands(one_decimal, cl, now=THESIS_TIME))
    # the library post, with 3 decimals, writes it
    lines = [line.text for line in api.post_commands(api.load_post("grbl"), cl,
                                                      now=THESIS_TIME)]
    assert "G3 X1.375 Y-1.859 I1.949 J-0.448" in lines


# --- the grbl-1.1 control model ----------------------------------------------------------------

def _grbl_events(program: str) -> list:
    from postdsl.controls import control_model

    return list(control_model("grbl-1.1").replay(program.strip().splitlines()))


@pytest.mark.parametrize(("program", "message"), [
    ("G21 G90\nT2 M6", "M6 is not a GRBL 1.1 command"),
    ("G21 G90\nG0 X0 Y0 Z5\nG81 X0 Y0 Z-5 R2 F100", "G81 is not a code"),
    ("G21 G90\nG0 Z5\nG43 H1 Z5", "'H1' is not a word"),
    ("G21 G90\nG0 Z5\nG43 Z5", "G43 is not a code"),
    ("G21 G90\nG0 X0 Y0 Z0\nS1000 M3\nG2 X2.01 Y0 I1 J0 F100", "end is not on its circle"),
])
def test_the_grbl_model_refuses_what_grbl_refuses(program: str, message: str) -> None:
    from postdsl.controls import ControlError

    with pytest.raises(ControlError, match=message):
        _grbl_events(program)


def test_the_grbl_model_takes_an_arc_within_grbl_arc_check() -> None:
    """0.004 mm off the circle is below GRBL's 0.005 mm: GRBL runs it, so does the model."""
    from postdsl.controls.events import ArcMove

    events = _grbl_events("G21 G90\nG0 X0 Y0 Z0\nS1000 M3\nG2 X2.004 Y0 I1 J0 F100")
    assert [type(e) for e in events if isinstance(e, ArcMove)] == [ArcMove]


def test_the_grbl_model_changes_the_tool_at_the_pause_after_a_t_word() -> None:
    """T names the tool, M0 is where the operator changes it and touches it off."""
    from postdsl.controls.events import LengthOffsetChanged, ToolLoaded

    events = _grbl_events("G21 G90\nG0 X5 Y5 Z10\nT3 M0\nG0 Z10\nM0")
    loaded = [e for e in events if isinstance(e, (ToolLoaded, LengthOffsetChanged))]
    assert [(type(e).__name__, e.origin.line) for e in loaded] == [
        ("ToolLoaded", 3), ("LengthOffsetChanged", 3)]   # the second M0 changes nothing
