"""Posting streams: flat memory whatever the program's length, two passes, atomic output."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from postdsl import api
from postdsl.cl.source import CLSource
from postdsl.errors import CLError
from postdsl.progress import ProgressBar
from tests.conftest import EXAMPLES, ROOT, THESIS_EPOCH

posix = pytest.mark.skipif(os.name != "posix", reason="FIFOs")


def raster(path: Path, moves: int) -> Path:
    """A native program of ``moves`` feed moves (X, Y and Z change on every one)."""
    with path.open("w", encoding="utf-8") as out:
        out.write('{"cmd": "program_start", "program_name": "RASTER"}\n'
                  '{"cmd": "tool_change", "tool_number": 1, "tool_diameter": 6}\n'
                  '{"cmd": "spindle_on", "spindle_speed": 3000, "spindle": "cw"}\n'
                  '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 5}\n'
                  '{"cmd": "linear_move", "z": -1, "feed": 900}\n')
        for n in range(moves):
            row, column = divmod(n, 200)
            x = column * 0.5 if row % 2 == 0 else (199 - column) * 0.5
            record = {"cmd": "linear_move", "x": x, "y": row * 0.25,
                      "z": round(-1 - (n % 17) * 0.013, 4)}
            if n % 50 == 0:
                record["feed"] = 1200 if n % 100 else 1000
            out.write(json.dumps(record) + "\n")
        out.write('{"cmd": "rapid_move", "z": 20}\n{"cmd": "program_end"}\n')
    return path


PEAK = """
import resource, sys
from postdsl import api
if sys.argv[1] == "post":
    count = api.write_program("vmc500", sys.argv[2], sys.argv[3])
else:
    count = api.verify_file("feeler", sys.argv[2]).cuts
print(count, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
"""


def peak_kb(action: str, cl: Path, out: Path) -> tuple[int, int]:
    """(NC lines or cuts verified, peak resident memory in KB) of a process posting ``cl``
    into ``out`` or verifying it."""
    env = {**os.environ, "SOURCE_DATE_EPOCH": str(THESIS_EPOCH)}
    done = subprocess.run([sys.executable, "-c", PEAK, action, str(cl), str(out)], cwd=ROOT,
                          env=env, capture_output=True, text=True, check=True, timeout=600)
    count, peak = done.stdout.split()
    return int(count), int(peak)


@pytest.mark.skipif(sys.platform != "linux", reason="ru_maxrss in KB is Linux's unit")
@pytest.mark.parametrize("action", ["post", "verify"])
def test_peak_memory_does_not_grow_with_the_program(tmp_path: Path, action: str) -> None:
    """Twenty times the moves, the same peak memory: nothing holds the whole program.

    Holding it (a list of the commands, a list of the NC lines, the joined text) costs
    well over 300 bytes a move: 16 MB more for the longer program here before posting
    streamed; the bound leaves the interpreter's own noise (a few hundred KB) ample room.
    """
    small_count, small = peak_kb(action, raster(tmp_path / "small.jsonl", 2_000),
                                 tmp_path / "s.nc")
    large_count, large = peak_kb(action, raster(tmp_path / "large.jsonl", 40_000),
                                 tmp_path / "l.nc")
    assert large_count >= 40_000 > small_count
    assert large - small < 3_000, f"peak {small} KB at 2 000 moves, {large} KB at 40 000"


def test_the_streamed_program_is_the_program_posted_from_a_list(tmp_path: Path,
                                                                 monkeypatch) -> None:
    monkeypatch.setenv("SOURCE_DATE_EPOCH", str(THESIS_EPOCH))
    for machine, program in (("vmc500", "vmc500_cycles.jsonl"),
                             ("feeler", "feeler_milling.apt"), ("emco", "emco_pocket.gcode")):
        post = api.load_post(machine)
        cl = EXAMPLES / program
        expected = api.post_text(post, api.post_commands(post, api.read_cl(cl), cl_file=str(cl)))
        out = tmp_path / f"{machine}.nc"
        count = api.write_program(machine, cl, out)
        assert out.read_text(encoding="utf-8") == expected
        assert count == expected.count(post.line_ending)


def test_an_error_halfway_writes_nothing_and_leaves_the_old_program(tmp_path: Path) -> None:
    """The reader's checks run in the first pass; the engine's in the second, whose lines
    go to a temporary file that an error removes."""
    cl = tmp_path / "job.jsonl"
    lines = raster(tmp_path / "ok.jsonl", 3_000).read_text(encoding="utf-8").splitlines()
    lines.insert(2_000, '{"cmd": "linear_move", "x": 9999}')  # beyond the travel
    cl.write_text("\n".join(lines) + "\n", encoding="utf-8")
    out = tmp_path / "job.nc"
    out.write_text("previous program\n", encoding="utf-8")
    with pytest.raises(CLError) as caught:
        api.write_program("vmc500", cl, out)
    assert caught.value.location.line == 2_001
    assert "outside the travel" in caught.value.message
    assert out.read_text(encoding="utf-8") == "previous program\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["job.jsonl", "job.nc", "ok.jsonl"]


def test_a_program_cut_short_is_refused_before_anything_is_posted(tmp_path: Path) -> None:
    cl = tmp_path / "cut.jsonl"
    text = (EXAMPLES / "vmc500_cycles.jsonl").read_text(encoding="utf-8")
    cl.write_text(text[:text.rindex('{"cmd": "program_end"')], encoding="utf-8")
    posted: list[str] = []

    class Watch:
        def write(self, text: str) -> None:
            posted.append(text)

    with pytest.raises(CLError, match="without a program_end"):
        api.write_program("vmc500", cl, tmp_path / "cut.nc", copy_to=Watch())  # type: ignore
    assert posted == []  # the first pass found it: the engine never ran
    assert not (tmp_path / "cut.nc").exists()


def test_a_file_that_changes_between_the_passes_is_refused(tmp_path: Path) -> None:
    cl = tmp_path / "job.jsonl"
    cl.write_bytes((EXAMPLES / "vmc500_cycles.jsonl").read_bytes())
    with CLSource(cl) as source:
        first = list(source.commands())
        with cl.open("a", encoding="utf-8") as more:
            more.write("# a comment added by someone else\n")
        with pytest.raises(CLError, match="changed while it was being posted"):
            list(source.commands())
    assert first


@posix
def test_a_fifo_input_is_read_once_and_posted_from_its_copy(tmp_path: Path) -> None:
    """Standard input or a FIFO cannot be read twice: the first pass copies it."""
    fifo = tmp_path / "cl"
    os.mkfifo(fifo)
    expected = subprocess.run(
        [sys.executable, "-m", "postdsl.cli", "post", "vmc500",
         str(EXAMPLES / "vmc500_cycles.jsonl")],
        capture_output=True, text=True, cwd=ROOT, check=True,
        env={**os.environ, "SOURCE_DATE_EPOCH": str(THESIS_EPOCH)}).stdout.replace(
            str(EXAMPLES / "vmc500_cycles.jsonl"), "CLFILE")
    env = {**os.environ, "SOURCE_DATE_EPOCH": str(THESIS_EPOCH)}
    process = subprocess.Popen([sys.executable, "-m", "postdsl.cli", "post", "vmc500",
                                str(fifo)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               cwd=ROOT, env=env)
    with fifo.open("wb") as pipe:
        pipe.write((EXAMPLES / "vmc500_cycles.jsonl").read_bytes())
    out, err = process.communicate(timeout=120)
    assert process.returncode == 0, err
    assert out.replace(str(fifo), "CLFILE") == expected
    stdin = subprocess.run([sys.executable, "-m", "postdsl.cli", "post", "vmc500", "-"],
                           input=(EXAMPLES / "vmc500_cycles.jsonl").read_text(encoding="utf-8"),
                           capture_output=True, text=True, cwd=ROOT, env=env, check=False)
    assert stdin.returncode == 0, stdin.stderr
    assert stdin.stdout.replace("<stdin>", "CLFILE") == expected
    assert [p.name for p in tmp_path.iterdir()] == ["cl"]


def test_a_bad_stdin_stops_at_its_line_and_prints_no_program() -> None:
    env = {**os.environ, "SOURCE_DATE_EPOCH": str(THESIS_EPOCH)}
    text = (EXAMPLES / "vmc500_cycles.jsonl").read_text(encoding="utf-8")
    text = text.replace('"depth": 50', '"depth": "deep"', 1)
    done = subprocess.run([sys.executable, "-m", "postdsl.cli", "post", "vmc500", "-"],
                          input=text, capture_output=True, text=True, cwd=ROOT, env=env,
                          check=False)
    assert done.returncode == 2
    assert done.stdout == ""
    assert done.stderr.startswith("<stdin>:") and "'depth' must be a number" in done.stderr


def test_verify_streams_and_still_finds_the_first_divergence(tmp_path: Path) -> None:
    cl = raster(tmp_path / "job.jsonl", 1_000)
    verdict = api.verify_file("feeler", cl)
    assert verdict.ok and verdict.cuts == 1_000  # the first move is where the plunge ends
    # a post that rounds coordinates to whole millimetres: caught at the first move it spoils
    text = (ROOT / "machines" / "feeler.yaml").read_text(encoding="utf-8")
    coarse = tmp_path / "coarse.yaml"
    coarse.write_text(text.replace("  coord:               # X-10.  Z0.  X12.345 : point "
                                   "always, 3 decimals (0.001 mm), trimmed\n    decimals: 3",
                                   "  coord:\n    decimals: 0", 1), encoding="utf-8")
    with pytest.raises(api.VerifyError) as caught:
        api.verify_file(coarse, cl)
    assert str(caught.value).startswith(f"{cl}:7: ")
    assert "feed move ends at X1.000" in str(caught.value)


def test_the_progress_bar_shows_only_for_large_files_and_clears_its_line() -> None:
    import io

    stream = io.StringIO()
    bar = ProgressBar(stream, minimum=1_000)
    bar.update("reading", 10, 999)  # small: nothing
    bar.update("reading", 10, None)  # size unknown (stdin): nothing
    assert stream.getvalue() == ""
    bar.update("posting", 500, 2_000)
    assert "posting" in stream.getvalue() and " 25%" in stream.getvalue()
    bar.finish()
    assert stream.getvalue().endswith("\r\x1b[2K")


def test_the_bar_is_drawn_only_on_a_terminal() -> None:
    """Pipes, CI logs and captured output (not a terminal) never get a bar."""
    import io

    from postdsl.progress import terminal_progress

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    update, finish = terminal_progress(io.StringIO())
    assert update is None
    finish()
    terminal = Terminal()
    update, finish = terminal_progress(terminal)
    assert update is not None
    update("reading", 5 << 20, 8 << 20)
    finish()
    assert "reading" in terminal.getvalue()
