"""The command line as a user meets it: exit codes, messages, files."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import DATA, EXAMPLES, ROOT, THESIS_EPOCH


def run(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "SOURCE_DATE_EPOCH": str(THESIS_EPOCH)}
    return subprocess.run([sys.executable, "-m", "postdsl.cli", *args], capture_output=True,
                          text=True, env=env, cwd=cwd, check=False)


def test_output_file_is_written_whole(tmp_path: Path) -> None:
    out = tmp_path / "prog.nc"
    result = run("post", "vmc500", str(EXAMPLES / "vmc500_cycles.jsonl"), "-o", str(out))
    assert result.returncode == 0, result.stderr
    assert result.stdout == ""
    assert out.read_text(encoding="utf-8") == (DATA / "vmc500_thesis.nc").read_text("utf-8")
    assert [p.name for p in tmp_path.iterdir()] == ["prog.nc"]


def test_bad_cl_exits_2_with_file_and_line_and_leaves_no_file(tmp_path: Path) -> None:
    cl = tmp_path / "bad.jsonl"
    good = (EXAMPLES / "vmc500_cycles.jsonl").read_text(encoding="utf-8").splitlines()
    good.insert(20, '{"cmd": "rapid_move", "x": "forty"}')
    cl.write_text("\n".join(good) + "\n", encoding="utf-8")
    out = tmp_path / "prog.nc"
    result = run("post", "vmc500", str(cl), "-o", str(out))
    assert result.returncode == 2
    assert result.stderr.strip() == f"{cl}:21: rapid_move: 'x' must be a number, not \"forty\""
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir()] == ["bad.jsonl"]


def test_an_error_keeps_the_previous_program_intact(tmp_path: Path) -> None:
    out = tmp_path / "prog.nc"
    out.write_text("previous program\n", encoding="utf-8")
    cl = tmp_path / "far.jsonl"
    cl.write_text('{"cmd": "rapid_move", "x": 40, "y": 20, "z": 80}\n'
                  '{"cmd": "rapid_move", "x": 4000}\n', encoding="utf-8")
    result = run("post", "vmc500", str(cl), "-o", str(out))
    assert result.returncode == 2
    assert result.stderr.strip() == (f"{cl}:2: X 4000 is outside the travel of VMC 500 "
                                     f"(-500 to 500)")
    assert out.read_text(encoding="utf-8") == "previous program\n"


def test_unmapped_command_names_the_command_and_cl_line(tmp_path: Path) -> None:
    post = tmp_path / "small.yaml"
    post.write_text("postdsl: 1\nmachine: {name: Small}\ncommands:\n"
                    "  program_start: {blocks: []}\n  program_end: {blocks: []}\n",
                    encoding="utf-8")
    cl = tmp_path / "p.jsonl"
    cl.write_text('{"cmd": "program_start"}\n{"cmd": "dwell", "dwell": 1}\n', encoding="utf-8")
    result = run("post", str(post), str(cl))
    assert result.returncode == 2
    assert result.stderr.startswith(f"{cl}:2: the post {post} has no table for CL command "
                                    f"'dwell'")


def test_invalid_post_exits_1(tmp_path: Path) -> None:
    post = tmp_path / "bad.yaml"
    post.write_text("postdsl: 1\nmachine: {name: Bad}\ncommands:\n  dwel: {blocks: []}\n",
                    encoding="utf-8")
    result = run("post", str(post), str(EXAMPLES / "vmc500_cycles.jsonl"))
    assert result.returncode == 1
    assert result.stderr.strip() == (f"{post}:4:3: unknown CL command 'dwel' "
                                     f"(did you mean 'dwell'?)")


@pytest.mark.parametrize(
    ("args", "code", "message"),
    [
        (("post", "vmc500", "missing.jsonl"), 2, "missing.jsonl: cannot read CL file"),
        (("post", "nosuch", "examples/vmc500_cycles.jsonl"), 1, "unknown machine 'nosuch'"),
        (("preview", "vmc500", "deep_drill", "--set", "peck"), 2, "'peck' is not NAME=VALUE"),
        (("preview", "vmc500", "boring"), 1, "the post has no table for 'boring'"),
    ],
)
def test_usage_errors_have_clear_messages(args: tuple[str, ...], code: int, message: str) -> None:
    result = run(*args)
    assert result.returncode == code
    assert message in result.stderr
    assert "Traceback" not in result.stderr


def test_machines_lists_the_bundled_posts() -> None:
    result = run("machines")
    assert "vmc500" in result.stdout.split()


def test_installed_entry_point_works() -> None:
    script = Path(sys.executable).with_name("postdsl")
    if not script.exists():
        pytest.skip("postdsl is not installed in this interpreter's environment")
    result = subprocess.run([str(script), "--help"], capture_output=True, text=True, check=False)
    assert result.returncode == 0
    for command in ("post", "check", "preview"):
        assert command in result.stdout


def test_preview_of_a_further_hole_runs_inside_a_sample_cycle() -> None:
    result = run("preview", "vmc500", "cycle_hole", "--set", "x=75")
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == ["N10  X75. Y20."]
