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
from tests.test_snapshots import NCSnapshot


@pytest.fixture
def nc_snapshot(snapshot):
    return snapshot.use_extension(NCSnapshot)


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
    if "fine_boring" in program:
        pytest.skip("rs274 has no fine boring: LinuxCNC's G76 is threading (the Fanuc model "
                    "verifies G76 Q, test_boring.py)")
    moves, holes = check_program(str(ROOT / program), tmp_path, api.load_post("fanuc"),
                                 drill_per_rev=False)
    assert moves + holes > 0



def _fanuc_prestaging() -> api.CompiledPost:
    return api.load_post("fanuc", {"prestage_next_tool": "true"})


def test_fanuc_prestages_the_next_tool_when_asked() -> None:
    """T<next> right after M6, none after the last tool; off by default."""
    cl = api.read_cl(ROOT / "examples/feeler_drilling.apt")
    lines = [line.text for line in api.post_commands(_fanuc_prestaging(), cl)]
    changes = [i for i, line in enumerate(lines) if line.endswith(" M6")]
    assert [lines[i] for i in changes] == ["N30 T2 M6", "N260 T3 M6", "N410 T4 M6"]
    assert [lines[i + 1] for i in changes] == ["N40 T3", "N270 T4", "N420 G54 G90 G17 G94"]
    assert api.verify_commands(_fanuc_prestaging(), cl).ok
    for off in (api.load_post("fanuc"), api.load_post("fanuc", {"prestage_next_tool": False})):
        plain = [line.text for line in api.post_commands(off, cl)]
        assert "N40 T3" not in plain and plain[plain.index("N30 T2 M6") + 1] == \
            "N40 G54 G90 G17 G94"
        assert [line for line in plain if line[:1] == "N" and " T" in line] == \
            ["N30 T2 M6", "N250 T3 M6", "N390 T4 M6"]   # no T but the changes'


@pytest.mark.parametrize("prestage", ["true", "false"])
def test_fanuc_prestaging_option_snapshot(prestage: str, nc_snapshot) -> None:
    """The drilling program (four tools) with and without pre-staging, read as a whole."""
    post = api.load_post("fanuc", {"prestage_next_tool": prestage})
    cl = ROOT / "examples/feeler_drilling.apt"
    lines = list(api.post_commands(post, api.read_cl(cl), cl_file=cl.name, now=THESIS_TIME))
    assert api.verify_commands(post, api.read_cl(cl), now=THESIS_TIME).ok
    assert api.post_text(post, lines) == nc_snapshot


@needs_rs274
@pytest.mark.parametrize("prestage", [True, False])
def test_fanuc_prestaging_moves_to_the_cl_points_in_rs274(prestage: bool,
                                                           tmp_path: Path) -> None:
    post = api.load_post("fanuc", {"prestage_next_tool": prestage})
    moves, holes = check_program(str(ROOT / "examples/feeler_drilling.apt"), tmp_path,
                                 post, drill_per_rev=False)
    assert (moves, holes) == (7, 13)   # the rapids and the 13 holes of the program

# --- grbl.yaml --------------------------------------------------------------------------------

def _model_cuts(lines: list[str]) -> list[tuple[str, tuple[float, ...], tuple[float, ...]]]:
    """(kind, end, centre) of every cut the GRBL control model reads in a program."""
    from postdsl.check.controls import control_model
    from postdsl.check.controls.events import ArcMove, FeedMove

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
    from postdsl.check.controls import control_model

    return list(control_model("grbl-1.1").replay(program.strip().splitlines()))


@pytest.mark.parametrize(("program", "message"), [
    ("G21 G90\nT2 M6", "M6 is not a GRBL 1.1 command"),
    ("G21 G90\nG0 X0 Y0 Z5\nG81 X0 Y0 Z-5 R2 F100", "G81 is not a code"),
    ("G21 G90\nG0 Z5\nG43 H1 Z5", "'H1' is not a word"),
    ("G21 G90\nG0 Z5\nG43 Z5", "G43 is not a code"),
    ("G21 G90\nG0 X0 Y0 Z0\nS1000 M3\nG2 X2.01 Y0 I1 J0 F100", "end is not on its circle"),
])
def test_the_grbl_model_refuses_what_grbl_refuses(program: str, message: str) -> None:
    from postdsl.check.controls import ControlError

    with pytest.raises(ControlError, match=message):
        _grbl_events(program)


def test_the_grbl_model_takes_an_arc_within_grbl_arc_check() -> None:
    """0.004 mm off the circle is below GRBL's 0.005 mm: GRBL runs it, so does the model."""
    from postdsl.check.controls.events import ArcMove

    events = _grbl_events("G21 G90\nG0 X0 Y0 Z0\nS1000 M3\nG2 X2.004 Y0 I1 J0 F100")
    assert [type(e) for e in events if isinstance(e, ArcMove)] == [ArcMove]


def test_the_grbl_model_changes_the_tool_at_the_pause_after_a_t_word() -> None:
    """T names the tool, M0 is where the operator changes it and touches it off."""
    from postdsl.check.controls.events import LengthOffsetChanged, ToolLoaded

    events = _grbl_events("G21 G90\nG0 X5 Y5 Z10\nT3 M0\nG0 Z10\nM0")
    loaded = [e for e in events if isinstance(e, (ToolLoaded, LengthOffsetChanged))]
    assert [(type(e).__name__, e.origin.line) for e in loaded] == [
        ("ToolLoaded", 3), ("LengthOffsetChanged", 3)]   # the second M0 changes nothing


# --- hmcnc.yaml and the hmcnc control model ----------------------------------------------------

def test_hmcnc_writes_the_seed_command_format() -> None:
    """One command a line, values before their letters, integer steps, T first, S last."""
    import re

    lines = post("hmcnc", "examples/hmcnc_sign.jsonl")
    commands = [line for line in lines if not line.startswith("//")]
    assert commands[:3] == ["T", "P", "E"] and commands[-2:] == ["Q", "S"]
    assert all(re.fullmatch(r"L-?\d+X-?\d+Y-?\d+Z|V-?\d+V|W\d+W|[TPERQS]", c)
               for c in commands), [c for c in commands if " " in c]
    # 400 steps/mm: X20 Y10 Z10 is L8000X4000Y4000Z; the board's top is V at Z10
    assert "V4000V" in commands and "L8000X4000Y4000Z" in commands
    assert "W500W" in commands   # the dwell of 0.5 s, in ms
    assert commands.index("R") < commands.index("L8000X4000Y-400Z")  # spindle on, then cut


SIGN = ROOT / "examples/hmcnc_sign.jsonl"


def _hm_posted(options: dict[str, object], cl: Path | str = SIGN) -> list[str]:
    cl_commands = api.read_cl(cl) if isinstance(cl, Path) else api.read_cl_text(cl, "<cl>",
                                                                                "native")
    return [line.text for line in api.post_commands(api.load_post("hmcnc", options),
                                                    cl_commands, now=THESIS_TIME)]


def _steps(lines: list[str]) -> list[tuple[int, int, int]]:
    import re

    found = [re.fullmatch(r"L(-?\d+)X(-?\d+)Y(-?\d+)Z", line) for line in lines]
    return [(int(m[1]), int(m[2]), int(m[3])) for m in found if m]


@pytest.mark.parametrize("steps", [200, 800])
def test_hmcnc_steps_per_mm_are_options_and_the_program_verifies_at_them(steps: int) -> None:
    """The same program at 200 or 800 steps/mm: each integer scaled from the 400 default
    (within the rounding of each), the setting comment the control reads, verified."""
    options = {f"steps_per_mm_{axis}": str(steps) for axis in "xyz"}
    lines = _hm_posted(options)
    default = _hm_posted({})
    assert f"//steps/mm {steps}X{steps}Y{steps}Z" in lines
    assert "//steps/mm 400X400Y400Z" in default
    # X20 Y10 Z10, the first move of the frame: 20 mm is 20 x steps
    assert f"L{20 * steps}X{10 * steps}Y{10 * steps}Z" in lines
    moves, at_400 = _steps(lines), _steps(default)
    assert len(moves) == len(at_400) > 100
    # the same mm within the half step each rounds to
    assert all(abs(value / steps - base / 400) <= 0.5 / steps + 0.5 / 400 + 1e-9
               for move, base_move in zip(moves, at_400, strict=True)
               for value, base in zip(move, base_move, strict=True))
    verdict = api.verify_commands(api.load_post("hmcnc", options), api.read_cl(SIGN))
    assert verdict.ok, verdict.divergence


def test_hmcnc_steps_differ_per_axis_and_verify_at_a_coarse_step() -> None:
    """80 steps/mm (a belt drive) in X, 26.666667 in Y, 100 in Z (a screw): verify
    compares within one step of each axis (the 0.0025 mm of the machine's resolution is
    a step at 400 steps/mm, finer than the half step these round to)."""
    options = {"steps_per_mm_x": "80", "steps_per_mm_y": "26.666667",
               "steps_per_mm_z": "100"}
    lines = _hm_posted(options)
    assert "//steps/mm 80X26.666667Y100Z" in lines
    assert "L1600X267Y1000Z" in lines   # X20 Y10 Z10
    verdict = api.verify_commands(api.load_post("hmcnc", options), api.read_cl(SIGN))
    assert verdict.ok, verdict.divergence


def test_verify_of_hmcnc_still_finds_a_coordinate_scaled_by_another_axis() -> None:
    """A post that scales X by Y's steps: equal steps hide it, different steps do not."""
    text = (ROOT / "machines" / "hmcnc.yaml").read_text(encoding="utf-8")
    first = '{expr: "x * steps_per_mm_x", format: steps, suffix: "X"}'
    wrong_text = text.replace(first, first.replace("_x", "_y"), 1)
    assert wrong_text != text
    cl = api.read_cl(SIGN)
    assert api.verify_commands(api.load_post_text(wrong_text, "hmcnc_xy.yaml"), cl).ok
    wrong = api.load_post_text(wrong_text, "hmcnc_xy.yaml", {"steps_per_mm_y": "401"})
    verdict = api.verify_commands(wrong, cl)
    assert not verdict.ok and "CL says X20.000" in str(verdict.divergence)


def test_the_hmcnc_model_compares_within_one_step_of_each_axis() -> None:
    """One step off passes, two steps off do not; the step is the axis's own."""
    from postdsl.check.controls import control_model
    from postdsl.check.motion import cl_events
    from postdsl.check.verify import verify_events

    cl = api.read_cl_text('{"cmd": "tool_change", "tool_number": 1}\n'
                          '{"cmd": "spindle_on", "spindle_speed": 20000}\n'
                          '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 5}\n'
                          '{"cmd": "linear_move", "z": -1, "feed": 600}\n'
                          '{"cmd": "linear_move", "x": 10, "y": 10}\n'
                          '{"cmd": "program_end"}\n', "<cl>", "native")

    def verdict(x_steps: int, y_steps: int = 10000) -> str | None:
        model = control_model("hmcnc")
        nc = ("T\n//steps/mm 100X1000Y100Z\n//feed 600mm/min\n//spindle 20000rpm\n"
              f"//tool 1\nR\nL0X0Y500Z\nL0X0Y-100Z\nL{x_steps}X{y_steps}Y-100Z\nE\nS")
        found = verify_events(model.replay(nc.splitlines()), cl_events(cl, "<cl>"),
                              0.0025, axis_steps=model.axis_steps).divergence
        return None if found is None else str(found)

    assert verdict(1000) is None and verdict(1001) is None   # X: one step is 0.01 mm
    assert "feed move ends at X10.020" in str(verdict(1002))
    # Y: a step is 0.001 mm; two of them are within the machine's 0.0025 but not a step
    assert verdict(1000, 10001) is None
    assert "feed move ends at X10.000 Y10.002" in str(verdict(1000, 10002))


@pytest.mark.parametrize(("option", "value", "message"), [
    ("steps_per_mm_z", "0", "steps per mm (options steps_per_mm_x, _y, _z) must be greater"),
    ("machine_feed", "-600", "option machine_feed) must be greater than 0"),
    ("spindle_speed_rpm", "0", "option spindle_speed_rpm) must be greater than 0"),
    ("steps_per_mm_x", "many", "option 'steps_per_mm_x' is a number, not 'many'"),
])
def test_hmcnc_refuses_settings_no_router_has(option: str, value: str, message: str) -> None:
    with pytest.raises((api.CLError, api.PostError), match=message.replace("(", r"\(")
                       .replace(")", r"\)")):
        _hm_posted({option: value})


def test_hmcnc_speed_and_spindle_speed_are_options() -> None:
    """A router set to 900 mm/min and 18000 rpm posts a CL written for those, and only those."""
    cl = ('{"cmd": "tool_change", "tool_number": 1}\n'
          '{"cmd": "spindle_on", "spindle_speed": 18000, "spindle": "cw"}\n'
          '{"cmd": "rapid_move", "x": 10, "y": 10, "z": 5}\n'
          '{"cmd": "linear_move", "z": -1, "feed": 900}\n'
          '{"cmd": "linear_move", "x": 20, "feed": 900}\n{"cmd": "program_end"}\n')
    options = {"machine_feed": "900", "spindle_speed_rpm": "18000"}
    lines = _hm_posted(options, cl)
    assert "//feed 900mm/min" in lines and "//spindle 18000rpm" in lines
    # the control moves at that one speed, rapids too: the time estimate's rapid rate
    assert api.load_post("hmcnc", options).machine.rapid_rate == 900.0
    assert api.load_post("hmcnc").machine.rapid_rate == 600.0
    assert api.verify_commands(api.load_post("hmcnc", options),
                               api.read_cl_text(cl, "<cl>", "native")).ok
    with pytest.raises(api.CLError, match="spindle_speed_rpm"):
        _hm_posted({}, cl)
    with pytest.raises(api.CLError, match="machine_feed"):
        _hm_posted({"spindle_speed_rpm": "18000"}, cl)


@pytest.mark.parametrize(("change", "message"), [
    ('{"cmd": "linear_move", "x": 100}', "a cut in Z and X/Y at once"),
    ('{"cmd": "spindle_on", "spindle_speed": 18000, "spindle": "cw"}', "spindle_speed_rpm"),
    ('{"cmd": "coolant_on", "coolant": "flood"}', "no coolant"),
])
def test_hmcnc_refuses_what_the_router_cannot_do(change: str, message: str) -> None:
    text = (ROOT / "examples/hmcnc_sign.jsonl").read_text(encoding="utf-8")
    old = {"linear": '{"cmd": "linear_move", "x": 100}',
           "spindle": '{"cmd": "spindle_on", "spindle_speed": 20000, "spindle": "cw"}',
           "coolant": '{"cmd": "spindle_on", "spindle_speed": 20000, "spindle": "cw"}'}
    if "coolant" in change:
        wrong = text.replace(old["coolant"], old["coolant"] + "\n" + change)
    elif "spindle" in change:
        wrong = text.replace(old["spindle"], change)
    else:  # a ramp: the frame's first side going down as it goes along
        wrong = text.replace(old["linear"], '{"cmd": "linear_move", "x": 100, "z": -1.5}')
    assert wrong != text
    with pytest.raises(api.CLError, match=message):
        list(api.post_commands(api.load_post("hmcnc"), api.read_cl_text(wrong, "<cl>",
                                                                       "native")))


def test_hmcnc_splits_a_rapid_down_and_sideways_sideways_first() -> None:
    """The router moves Z first: the post writes the sideways part at the old height."""
    cl = api.read_cl_text(
        '{"cmd": "tool_change", "tool_number": 1}\n'
        '{"cmd": "spindle_on", "spindle_speed": 20000}\n'
        '{"cmd": "rapid_move", "x": 10, "y": 10, "z": 20}\n'
        '{"cmd": "rapid_move", "x": 50, "y": 10, "z": 2}\n'
        '{"cmd": "linear_move", "z": -1, "feed": 600}\n{"cmd": "program_end"}\n',
        "<cl>", "native")
    lines = [line.text for line in api.post_commands(api.load_post("hmcnc"), cl)]
    assert lines[lines.index("L4000X4000Y8000Z"):][:4] == [
        "L4000X4000Y8000Z", "L20000X4000Y8000Z", "L20000X4000Y800Z", "L20000X4000Y-400Z"]
    assert api.verify_commands(api.load_post("hmcnc"), cl).ok


def test_verify_catches_an_hmcnc_post_that_leaves_out_a_move_to_where_the_tool_is() -> None:
    """A post that skips "unchanged" moves drops the expanded hole's move over the next
    hole (the engine's x is already the hole's): the router would then go down first and
    move sideways at the feed level.  The model replays Z first, and verify says so."""
    text = (ROOT / "machines" / "hmcnc.yaml").read_text(encoding="utf-8")
    wrong_text = text.replace("  move_to_here:\n    - items:", "  move_to_here:\n    - if: \""
                              "x != prev_x or y != prev_y or z != prev_z\"\n      items:")
    assert wrong_text != text
    wrong = api.load_post_text(wrong_text, "hmcnc_skips.yaml")
    cl = api.read_cl(ROOT / "examples/hmcnc_sign.jsonl")
    assert api.verify_commands(api.load_post("hmcnc"), cl).ok
    verdict = api.verify_commands(wrong, cl)
    assert not verdict.ok and "a rapid sideways at Z2.000, below the CL's Z10.000" in str(
        verdict.divergence)


def _hmcnc(program: str) -> list:
    from postdsl.check.controls import control_model

    return list(control_model("hmcnc").replay(program.strip().splitlines()))


HM_START = "T\n//steps/mm 400X200Y100Z\n//feed 600mm/min\n//spindle 20000rpm\n//tool 2\n"


def test_the_hmcnc_model_reads_values_before_letters_and_moves_z_first() -> None:
    from postdsl.check.controls.events import FeedMove

    events = _hmcnc(HM_START + "V1000V\nR\nL4000X2000Y1000Z\nL8000X2000Y-100Z\nE\nS")
    moves = [(e.start, e.end) for e in events if isinstance(e, FeedMove)]
    # X 4000/400 = 10, Y 2000/200 = 10, Z 1000/100 = 10; then Z down to -1 first, then X
    assert moves == [((10.0, 10.0, 10.0), (10.0, 10.0, -1.0)),
                     ((10.0, 10.0, -1.0), (20.0, 10.0, -1.0))]
    assert all(e.feed == 600 and e.tooling.tool == 2 and e.tooling.speed == 20000
               for e in events if isinstance(e, FeedMove))


@pytest.mark.parametrize(("program", "message"), [
    ("P\nS", "must start with T"),
    ("T\nP", "does not end with S"),
    ("T\nS\nP", "after S"),
    ("T\nL1X 2Y3Z\nS", "with a space"),
    ("T\nL1X2Y3Z\nS", "before the program states its steps per mm"),
    (HM_START + "L1X2Z3Y\nS", "is not an hmCNC command"),
    (HM_START + "A\nS", "sets the position to zero"),
])
def test_the_hmcnc_model_refuses_what_breaks_the_rules(program: str, message: str) -> None:
    from postdsl.check.controls import ControlError

    with pytest.raises(ControlError, match=message):
        _hmcnc(program)
