"""The command line as a user meets it: exit codes, messages, files."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from postdsl import api
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
    cl.write_text('{"cmd": "tool_change", "tool_number": 1}\n'
                  '{"cmd": "rapid_move", "x": 40, "y": 20, "z": 80}\n'
                  '{"cmd": "rapid_move", "x": 4000}\n{"cmd": "program_end"}\n',
                  encoding="utf-8")
    result = run("post", "vmc500", str(cl), "-o", str(out))
    assert result.returncode == 2
    assert result.stderr.strip() == (f"{cl}:3: X 4000 is outside the travel of VMC 500 "
                                     f"(-500 to 500)")
    assert out.read_text(encoding="utf-8") == "previous program\n"


def test_unmapped_command_names_the_command_and_cl_line(tmp_path: Path) -> None:
    post = tmp_path / "small.yaml"
    post.write_text("postdsl: 1\nmachine: {name: Small}\ncommands:\n"
                    "  program_start: {blocks: []}\n  program_end: {blocks: []}\n",
                    encoding="utf-8")
    cl = tmp_path / "p.jsonl"
    cl.write_text('{"cmd": "program_start"}\n{"cmd": "dwell", "dwell": 1}\n'
                  '{"cmd": "program_end"}\n', encoding="utf-8")
    result = run("post", str(post), str(cl))
    assert result.returncode == 2
    # the post has no control model: post says once that it posts unverified, then the error
    notice, error = result.stderr.splitlines()
    assert notice == f"{post}: {api.NO_CONTROL_MODEL}"
    assert error.startswith(f"{cl}:2: the post {post} has no table for CL command 'dwell'")


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
        (("preview", "vmc500", "input_modes"), 1, "the post has no table for 'input_modes'"),
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


# --- what a new user meets first --------------------------------------------------------------


def test_output_into_a_missing_folder_says_so(tmp_path: Path) -> None:
    out = tmp_path / "nc" / "prog.nc"
    result = run("post", "vmc500", str(EXAMPLES / "vmc500_cycles.jsonl"), "-o", str(out))
    assert result.returncode == 2
    assert result.stderr.strip() == (f"{out}: cannot write the NC program: the folder "
                                     f"{out.parent} does not exist")
    assert not (tmp_path / "nc").exists()


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0,
                    reason="needs file permissions that apply (not root)")
def test_output_into_a_read_only_folder_says_so(tmp_path: Path) -> None:
    folder = tmp_path / "locked"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        out = folder / "prog.nc"
        result = run("post", "vmc500", str(EXAMPLES / "vmc500_cycles.jsonl"), "-o", str(out))
        assert result.returncode == 2
        assert result.stderr.strip() == (f"{out}: cannot write the NC program: Permission "
                                         f"denied")
        assert list(folder.iterdir()) == []
    finally:
        folder.chmod(0o755)


def test_a_write_error_does_not_name_the_temporary_file(tmp_path: Path, monkeypatch) -> None:
    """Whatever the OS refuses (a read-only file system, a full disk), the message names the
    program the user asked for, not the temporary file it is written through."""
    from postdsl import api
    from postdsl.run import writer

    def refuse(*args: object, **kwargs: object) -> None:
        raise OSError(30, "Read-only file system", str(tmp_path / ".prog.nc.x1y2.tmp"))

    monkeypatch.setattr(writer.tempfile, "mkstemp", refuse)
    out = tmp_path / "prog.nc"
    with pytest.raises(api.CLError) as info:
        api.post_file("vmc500", EXAMPLES / "vmc500_cycles.jsonl", out)
    assert str(info.value) == f"{out}: cannot write the NC program: Read-only file system"


def test_every_bundled_machine_previews_every_table() -> None:
    """`postdsl preview` is the first thing a post author tries: no table may fail on the
    post's own sample values."""
    from postdsl import api

    for machine in run("machines", "--names").stdout.split():
        post = api.load_post(machine)
        tables: dict[str, Any] = {}  # a post built on another (extends:) has the base's too
        for base in post.source.bases.values():
            tables.update(base.data.get("commands") or {})
        tables.update(post.source.data.get("commands") or {})
        for command in [*post.commands, *post.custom_cycles]:
            result = api.preview_command(post, command)
            # a table that exists to refuse its command (a library post's "GRBL has no
            # tapping cycle": no blocks, a rule that always fires) previews as that refusal
            table = tables.get(command) or {}
            table = tables.get(table.get("redirect")) or table  # a redirect refuses alike
            refusals = [f"{command}: {rule['message']}" for rule in table.get("reject") or ()
                        if rule.get("if") == "true"]
            if refusals and not table.get("blocks"):
                assert result.error == refusals[0], (machine, command, result.error)
                continue
            assert result.error is None, (machine, command, result.error)


@pytest.mark.parametrize(
    ("setting", "message"),
    [
        ("x=abc", "preview of rapid_move: rapid_move: 'x' must be a number, not \"abc\""),
        ("spindle=sideways",
         "preview of spindle_on: spindle_on: 'spindle' must be one of cw, ccw, not \"sideways\""),
        ("tool_number=1.5",
         "preview of tool_change: tool_change: 'tool_number' must be a whole number, not 1.5"),
        ("feeed=100", "preview of rapid_move: unknown parameter 'feeed' (did you mean 'feed'?)"),
    ],
)
def test_preview_values_are_checked_like_cl_values(setting: str, message: str) -> None:
    command = {"spindle": "spindle_on", "tool_number": "tool_change"}.get(
        setting.split("=")[0], "rapid_move")
    result = run("preview", "vmc500", command, "--set", setting)
    assert result.returncode == 2
    assert result.stdout == ""
    assert result.stderr.strip() == f"{ROOT / 'machines' / 'vmc500.yaml'}: {message}"


@pytest.mark.parametrize(
    ("fmt", "example", "message"),
    [
        ("native", "feeler_milling.apt", "feeler_milling.apt:1:1: not a JSON record"),
        ("apt", "emco_pocket.gcode", "emco_pocket.gcode:1: (EMCO"),
        ("freecad", "vmc500_cycles.jsonl", "vmc500_cycles.jsonl:1:1: cannot read"),
    ],
)
def test_a_format_that_does_not_match_the_content_is_a_located_error(
        fmt: str, example: str, message: str) -> None:
    result = run("post", "vmc500", str(EXAMPLES / example), "--format", fmt)
    assert result.returncode == 2
    assert result.stderr.startswith(str(EXAMPLES / message))


@pytest.mark.skipif(os.name != "posix", reason="symbolic links")
def test_output_through_a_symbolic_link_writes_the_file_it_points_to(tmp_path: Path) -> None:
    """A link to the machine's share must stay a link: the program goes where it points."""
    share = tmp_path / "share"
    share.mkdir()
    target = share / "prog.nc"
    target.write_text("old\n", encoding="utf-8")
    link = tmp_path / "prog.nc"
    link.symlink_to(target)
    result = run("post", "vmc500", str(EXAMPLES / "vmc500_cycles.jsonl"), "-o", str(link))
    assert result.returncode == 0, result.stderr
    assert link.is_symlink()
    assert target.read_text(encoding="utf-8") == (DATA / "vmc500_thesis.nc").read_text("utf-8")
    assert sorted(p.name for p in share.iterdir()) == ["prog.nc"]
