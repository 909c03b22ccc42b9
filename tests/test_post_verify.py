"""``postdsl post`` verifies what it writes, by default, through the fast paths of verify.

Every line is replayed through the control model as it is written and compared with
the CL's records: a program that does not do what the CL says is not written (exit
4, the CL line and the NC line), ``--no-verify`` posts without it and says so, a post
without a control model is posted with a notice.  The fast paths (the control models'
reading of the common G0/G1 line, the plain feed moves compared as tuples, the lines'
sources from ``Engine.sourced_texts``) must give what the general path gives: the
same events, the same verdicts, the same messages.
"""

from __future__ import annotations

import io
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from postdsl import api
from postdsl.check.controls import CONTROLS, ControlError, control_model
from postdsl.check.controls.base import feed_event
from postdsl.check.controls.fanuc import FanucControl
from postdsl.cl.model import LinearMove, RapidMove, plain_move_of
from postdsl.errors import VerifyError
from postdsl.run.engine import Engine, NCLine
from postdsl.run.program import summarize
from tests.conftest import MACHINES, ROOT, THESIS_TIME


def _make_program() -> Any:
    """The benchmark's raster writer (``benchmarks/make_program.py``)."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        import make_program
    finally:
        sys.path.remove(str(ROOT / "benchmarks"))
    return make_program


make_program = _make_program()
LINUXCNC = (MACHINES / "linuxcnc.yaml").read_text(encoding="utf-8")
Y_ITEM = '{param: y, prefix: "Y", suffix: " ", format: coord, mode: changed'


def wrong_y_post(tmp_path: Path) -> Path:
    """LinuxCNC's post writing X's value in the Y word of a feed move: plain G1 lines that
    read well and cut in the wrong place."""
    start = LINUXCNC.index("  linear_move:")
    at = LINUXCNC.index(Y_ITEM, start)
    text = LINUXCNC[:at] + Y_ITEM.replace("param: y", "param: x") + LINUXCNC[at + len(Y_ITEM):]
    path = tmp_path / "wrong.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def raster(tmp_path: Path, moves: int = 300, fmt: str = "native") -> Path:
    path = tmp_path / f"raster{make_program.SUFFIX[fmt]}"
    with path.open("w", encoding="utf-8") as out:
        make_program.WRITERS[fmt](moves, out)
    return path


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "postdsl.cli", *args], capture_output=True,
                          text=True, check=False, cwd=ROOT)


# --- the command line ----------------------------------------------------------------------


def test_post_verifies_by_default_and_writes_nothing_when_the_program_is_wrong(
        tmp_path: Path) -> None:
    post, cl, out = wrong_y_post(tmp_path), raster(tmp_path), tmp_path / "part.nc"
    to_file = run("post", str(post), str(cl), "-o", str(out))
    assert to_file.returncode == 4, to_file.stderr
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == \
        ["raster.jsonl", "wrong.yaml"]  # no temporary file left either
    # one located line: the CL line, the NC line and what differs; no traceback
    message = to_file.stderr.strip()
    assert message.startswith(f"{cl}:") and "\n" not in message
    assert ": NC line " in message and "G1 " in message and "CL says" in message
    to_stdout = run("post", str(post), str(cl))
    assert to_stdout.returncode == 4 and to_stdout.stdout == ""
    assert to_stdout.stderr == to_file.stderr


def test_no_verify_posts_the_program_and_says_so_once(tmp_path: Path) -> None:
    post, cl, out = wrong_y_post(tmp_path), raster(tmp_path), tmp_path / "part.nc"
    result = run("post", "--no-verify", str(post), str(cl), "-o", str(out))
    assert result.returncode == 0, result.stderr
    assert out.read_text(encoding="utf-8").count("G1 ") > 100
    assert len(result.stderr.splitlines()) == 1 and "without verifying" in result.stderr


def test_a_right_program_is_the_same_verified_or_not_and_verify_is_still_accepted(
        tmp_path: Path) -> None:
    cl = raster(tmp_path)
    outputs = []
    for flag in ((), ("--verify",), ("--no-verify",)):
        result = run("post", *flag, "linuxcnc", str(cl), "--option", "header=false")
        assert result.returncode == 0, result.stderr
        outputs.append(result.stdout)
        assert ("without verifying" in result.stderr) == (flag == ("--no-verify",))
    assert outputs[0] == outputs[1] == outputs[2] and outputs[0].count("G1 ") > 100


def test_a_post_without_a_control_model_is_posted_with_one_notice(tmp_path: Path) -> None:
    post = tmp_path / "small.yaml"
    post.write_text("postdsl: 1\nmachine: {name: Small}\ncommands:\n"
                    "  program_start: {blocks: [{items: [{text: 'BEGIN'}]}]}\n"
                    "  program_end: {blocks: [{items: [{text: 'END'}]}]}\n", encoding="utf-8")
    cl = tmp_path / "p.jsonl"
    cl.write_text('{"cmd": "program_start"}\n{"cmd": "program_end"}\n', encoding="utf-8")
    result = run("post", str(post), str(cl))
    assert result.returncode == 0, result.stderr
    assert result.stdout == "N10 BEGIN\nN20 END\n"
    assert result.stderr.splitlines() == [f"{post}: {api.NO_CONTROL_MODEL}"]


# --- the API ---------------------------------------------------------------------------------


def test_the_api_verifies_by_default_and_verify_false_posts_unverified(tmp_path: Path) -> None:
    post, cl, out = wrong_y_post(tmp_path), raster(tmp_path), tmp_path / "part.nc"
    with pytest.raises(VerifyError) as caught:
        api.write_program(post, cl, out)
    assert not out.exists()
    with pytest.raises(VerifyError):
        api.post_file(post, cl)
    stdout = io.BytesIO()
    with pytest.raises(VerifyError):
        api.write_program(post, cl, stdout=stdout)
    assert stdout.getvalue() == b""
    assert api.write_program(post, cl, out, verify=False) > 300 and out.exists()
    # the same message as the general path gives (verify_commands: no fast path at all)
    general = api.verify_commands(api.load_post(post), api.read_cl(cl), cl_file=str(cl),
                                  now=THESIS_TIME)
    assert str(caught.value) == str(general.divergence)


@pytest.mark.parametrize("fmt", ["native", "apt", "freecad"])
@pytest.mark.parametrize("machine", ["vmc500", "linuxcnc", "fanuc", "emco", "grbl"])
def test_a_raster_verifies_in_every_format_with_the_same_counts_as_the_general_path(
        machine: str, fmt: str, tmp_path: Path) -> None:
    cl = raster(tmp_path, 400, fmt)
    options = {"spindle_speed_rpm": str(make_program.SPEED)} if machine == "hmcnc" else None
    fast = api.verify_file(machine, cl, options=options)
    post = api.load_post(machine, options)
    general = api.verify_commands(post, api.read_cl(cl), cl_file=str(cl), now=THESIS_TIME)
    assert general.ok and fast.ok
    assert (fast.cuts, fast.holes, fast.rapids) == (general.cuts, general.holes, general.rapids)
    assert fast.cuts > 300


# --- the control models' fast path ----------------------------------------------------------


def corpus() -> list[tuple[str, Path]]:
    from ruamel.yaml import YAML

    listed = YAML(typ="safe").load((ROOT / "corpus.yaml").read_text(encoding="utf-8"))
    return [(machine, ROOT / path) for machine, paths in listed.items() for path in paths]


def replayed(post: api.CompiledPost, lines: list[NCLine], plain: bool) -> list[object]:
    """The events of posted lines, the model's fast path on or off (tuples made events)."""
    model = control_model(post.machine.control)  # type: ignore[arg-type]
    model.plain_feeds = plain
    notes = api._LineNotes(post)
    inputs = [line.text if (note := notes.of(line)) is None
              else notes.input(number, line.text, note)
              for number, line in enumerate(lines, start=1)]
    return [feed_event(event) if event.__class__ is tuple else event  # type: ignore[arg-type]
            for event in model.replay(inputs)]


@pytest.mark.parametrize(("machine", "cl_path"), corpus(),
                         ids=[f"{m}-{p.name.split('.')[0]}" for m, p in corpus()])
def test_the_fast_path_gives_the_general_paths_events_on_every_snapshot(
        machine: str, cl_path: Path) -> None:
    post = api.load_post(MACHINES / f"{machine}.yaml")
    try:
        lines = api.post_commands(post, api.read_cl(cl_path), cl_file=cl_path.name,
                                  now=THESIS_TIME)
    except api.CLError:
        return  # the machine refuses the program: no NC to replay
    try:
        general = replayed(post, lines, plain=False)
    except ControlError as exc:  # pragma: no cover - the snapshot suite verifies them
        pytest.fail(str(exc))
    assert replayed(post, lines, plain=True) == general


def test_the_fast_path_reads_most_lines_of_a_raster(tmp_path: Path) -> None:
    for machine in ("vmc500", "linuxcnc", "fanuc"):
        post = api.load_post(machine)
        lines = api.post_commands(post, api.read_cl(raster(tmp_path)), now=THESIS_TIME)
        model = control_model(post.machine.control)  # type: ignore[arg-type]
        model.plain_feeds = True
        events = list(model.replay([line.text for line in lines]))
        plain = sum(event.__class__ is tuple for event in events)
        assert plain > 0.9 * len(events), machine


@pytest.mark.parametrize("text", [
    "G1 X1. (a comment) Y2.", "G1 X1. ; LinuxCNC's comment", "G1 X1. Y2.;", "%", "G1 X1 %",
    "G1 X1. S100", "G1 X1. M8", "G1 X1. H1", "G1 X1. R2", "G2 X1. I1.", "G1 X1. A10",
    "g1 x1.", " G1 X1.", "G1\tX1.", "G1 X1. X2.", "G1 Y1. X2.", "G1 X#1", "O100",
    "G1 F500", "G17 G1 X1.", "G91 G1 X1.", "N10 G1 X1. N20", "G1 X1.0.0", "G33.1 Z-5 K1",
    "MCALL CYCLE81(10,0,2,-5)", "G1 X1. CR=5",
])
def test_the_fast_path_leaves_every_other_line_to_the_general_reader(text: str) -> None:
    for cls in CONTROLS.values():
        if not cls.fast_path:
            continue
        model = cls()
        model.motion, model.pos = "1", [0.0, 0.0, 0.0]
        before = dict(vars(model))
        assert model.plain_move(1, text) is None, (cls.name, text)
        assert vars(model) == before  # and nothing changed on the way


def test_the_fast_path_waits_for_the_state_the_general_reader_needs() -> None:
    model = FanucControl()
    assert model.plain_move(1, "G1 X1.") is None  # no motion mode yet: G1 from nowhere
    model.motion, model.pos = "81", [0.0, 0.0, 5.0]
    assert model.plain_move(1, "X1. Y2.") is None  # another hole of the cycle
    model.motion = "1"
    model.absolute = False
    assert model.plain_move(1, "X1.") is None  # G91
    model.absolute, model.rigid = True, True
    assert model.plain_move(1, "G1 X1.") is None  # G1 ends M29's rigid mode
    model.rigid = False
    model.pos = [None, None, None]
    assert model.plain_move(1, "G1 X1.") is None  # after a tool change: refused at its line
    assert model.plain_move(1, "G0 X1.") is not None  # a rapid may go there


def test_a_number_rule_of_the_model_holds_on_the_fast_path_too() -> None:
    """number is the one reading of a number: a control that reads a coordinate
    without a decimal point in 0.001 mm reads it so on both paths."""

    class Increments(FanucControl):
        def number(self, letter: str, text: str) -> float:
            return float(text) / 1000 if letter in "XYZ" and "." not in text else float(text)

    program = ["T1 M6", "S1000 M3", "G0 X0. Y0. Z0.", "G1 X10 Y20. Z-3 F100."]
    for plain in (False, True):
        model = Increments()
        model.plain_feeds = plain
        last = list(model.replay(program))[-1]
        end = last[3] if last.__class__ is tuple else last.end  # type: ignore[union-attr]
        assert end == (0.01, 20.0, -0.003), plain


# --- the lines' sources ------------------------------------------------------------------------


@pytest.mark.parametrize("fmt", ["native", "apt"])
def test_sourced_texts_are_the_texts_and_name_each_lines_table_and_cl_line(
        fmt: str, tmp_path: Path) -> None:
    cl = raster(tmp_path, 3000, fmt)
    post = api.load_post("linuxcnc")
    commands = api.read_cl(cl)
    summary = summarize(commands, post.machine.rapid_rate)
    full = list(Engine(post, now=THESIS_TIME).run(commands, summary))
    records = [plain_move_of(c) if c.__class__ in (LinearMove, RapidMove) else c
               for c in commands] if fmt == "native" else commands
    texts = [text for batch in Engine(post, now=THESIS_TIME).texts(records, summary)
             for text in batch]
    sourced = [(text, source) for batch, sources in
               Engine(post, now=THESIS_TIME).sourced_texts(records, summary)
               for text, source in zip(batch, sources, strict=True)]
    assert [text for text, _ in sourced] == texts == [line.text for line in full]
    for (_, source), line in zip(sourced, full, strict=True):
        if source.__class__ is tuple:  # a lane's line: its move's class and CL line
            assert (source[0].name, source[1]) == (line.table, line.cl_line)
        else:
            assert source == line
    assert sum(source.__class__ is tuple for _, source in sourced) > 2000


# --- the plain comparison ------------------------------------------------------------------


def test_plain_feeds_agree_exactly_when_the_general_comparison_finds_nothing() -> None:
    """Each field of two plain feed moves moved just within and just beyond its tolerance:
    the in-line comparison passes them exactly when :meth:`_Comparison.cut` does."""
    from postdsl.check.controls.events import Tooling
    from postdsl.check.verify import FEED_TOLERANCE, _Comparison, _Tolerance

    compare = _Comparison(_Tolerance(0.001, None))
    nc_tool, cl_tool = Tooling(1, 1, "cw", 1000.0), Tooling(1, 1, "cw", 1000.0)
    base = (7, "G1 X1. Y2. Z3.", (0.0, 0.0, 0.0), (1.0, 2.0, 3.0), 500.0, nc_tool)
    cases = []
    for field, axis in [(2, 0), (2, 1), (2, 2), (3, 0), (3, 1), (3, 2)]:
        for step in (0.001 - 1e-10, 0.001 + 1e-8, -0.001 - 1e-8):
            point = list(base[field])  # type: ignore[arg-type]
            point[axis] += step
            cases.append(base[:field] + (tuple(point),) + base[field + 1:])
    for feed in (500.0 + FEED_TOLERANCE, 500.0 + FEED_TOLERANCE + 1e-6, None, 0.0):
        cases.append(base[:4] + (feed,) + base[5:])
    for tooling in (Tooling(2, 2, "cw", 1000.0), Tooling(1, None, "cw", 1000.0),
                    Tooling(1, 1, "ccw", 1000.0), Tooling(1, 1, "cw", 1001.0),
                    Tooling(1, 1, "off", 1000.0), Tooling(1, 1, "cw", 1000.0)):
        cases.append(base[:5] + (tooling,))
    cl = base[:5] + (cl_tool,)
    outcomes = []
    for nc in [base, *cases]:
        general = compare.cut(feed_event(nc), feed_event(cl, "p.jsonl"), 1)  # type: ignore
        assert compare.plain_feeds(nc, cl) == (general is None), (nc, general)  # type: ignore
        outcomes.append(general is None)
    # the base, a step within each axis's tolerance, a feed 0.5 off, an equal tooling
    assert outcomes.count(True) == 9 and outcomes.count(False) == len(outcomes) - 9


def test_plot_draws_the_program_and_says_where_it_departs_from_the_cl(tmp_path: Path) -> None:
    post, cl, svg = wrong_y_post(tmp_path), raster(tmp_path, 60), tmp_path / "p.svg"
    result = run("plot", str(post), str(cl), "-o", str(svg))
    assert result.returncode == 4, result.stderr
    assert "<svg" in svg.read_text(encoding="utf-8")
    message, note = result.stderr.splitlines()[-2:]
    assert message.startswith(f"{cl}:") and ": NC line " in message
    assert note == f"{svg} shows what the NC program does, not what the CL says"
    good = run("plot", "linuxcnc", str(cl), "-o", str(svg))
    assert good.returncode == 0 and "moves drawn" in good.stderr


COORD_3 = "  coord:               # 40. / 16.996 : point always, trailing zeros trimmed\n" \
          "    decimals: 3\n"


@pytest.mark.parametrize("decimals", ["3", "0"])
def test_post_verified_hands_on_the_whole_program_and_the_verdict(decimals: str) -> None:
    """``api.post_verified`` (the editor's preview) posts once: every line post writes, to
    the program's end even past a divergence, and the verdict verify_commands gives."""
    text = (MACHINES / "vmc500.yaml").read_text(encoding="utf-8")
    assert COORD_3 in text
    post = api.load_post_text(text.replace(COORD_3, COORD_3.replace("3", decimals)),
                              str(MACHINES / "vmc500.yaml"))
    commands = list(api.read_cl(ROOT / "examples" / "emco_pocket.gcode"))
    shown: list[NCLine] = []
    verdict = api.post_verified(post, commands, shown.append, cl_file="p", now=THESIS_TIME)
    assert shown == api.post_commands(post, commands, cl_file="p", now=THESIS_TIME)
    again = api.verify_commands(post, commands, cl_file="p", now=THESIS_TIME)
    assert verdict.divergence == again.divergence
    # decimals 0 rounds the coordinates to whole mm: verify finds where the NC leaves the
    # CL, and the whole program is shown all the same (compared above)
    assert (verdict.divergence is None) == (decimals == "3")
