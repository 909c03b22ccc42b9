"""The VMC500 / Acramatic 2100 program of the thesis, reproduced line for line.

The expected listing (tests/data/vmc500_thesis.nc) is section 7.1 of the
thesis as normalised in the reference digest: the real output of the
original PowerMill post.  Every line matches; there are no known
differences.  Its quirks — two spaces after block numbers of non-cycle
blocks, ``R70.0J1``, no F on G84.1 — come from item properties in
machines/vmc500.yaml (prefixes, modal F), as they did in PPU.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys

from postdsl import api
from tests.conftest import DATA, EXAMPLES, ROOT, THESIS_EPOCH

EXPECTED = (DATA / "vmc500_thesis.nc").read_text(encoding="utf-8")


def run_cli(*args: str, epoch: int | None = THESIS_EPOCH) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k != "SOURCE_DATE_EPOCH"}
    if epoch is not None:
        env["SOURCE_DATE_EPOCH"] = str(epoch)
    return subprocess.run([sys.executable, "-m", "postdsl.cli", *args], capture_output=True,
                          text=True, env=env, cwd=ROOT, check=False)


def test_postdsl_post_prints_the_thesis_program_line_for_line() -> None:
    result = run_cli("post", "vmc500", "examples/vmc500_cycles.jsonl")
    assert result.returncode == 0, result.stderr
    assert result.stderr == ""
    got, want = result.stdout.splitlines(), EXPECTED.splitlines()
    for number, (line, expected) in enumerate(zip(got, want, strict=True), start=1):
        assert line == expected, f"line {number}"


def test_the_header_date_comes_from_source_date_epoch() -> None:
    result = run_cli("post", "vmc500", "examples/vmc500_cycles.jsonl", epoch=0)
    assert "; vytvoreno: 01.01.1970 v 0:00:00" in result.stdout.splitlines()


def test_the_header_extents_are_computed_from_the_cl() -> None:
    # the CL carries no extents: they come from the moves and hole bottoms (70 - 53.0043)
    post = api.load_post("vmc500")
    commands = api.read_cl(EXAMPLES / "vmc500_cycles.jsonl")
    lines = [line.text for line in api.post_commands(post, commands)]
    assert "; pohyb nastroje (XxYxZ): (40.;100.) x (20.;20.) x (16.996;150.)" in lines


def test_the_estimate_is_computed_when_the_cam_gives_none() -> None:
    post = api.load_post("vmc500")
    commands = api.read_cl(EXAMPLES / "vmc500_cycles.jsonl")
    from dataclasses import replace

    commands[0] = replace(commands[0], machining_time=None)
    lines = [line.text for line in api.post_commands(post, commands)]
    [estimate] = [line for line in lines if line.startswith("; vypocitany cas:")]
    # the time model: rapids at the machine's 15 m/min, each hole down from the approach
    # plane (top + 5) and back up at the cycle feed, plus dwells
    rapids = (5 + 20 + 25 + 20 + 20 + 20 + 75) / 15000 * 60
    holes = (2 * 55 / 200 * 60 + 0.5            # single peck, 75 -> 20, dwell 0.5
             + 2 * 2 * (75 - 16.9957) / 200 * 60  # deep drill and break chip
             + 2 * 40 / 100 * 60 + 0.5          # tapping, dwell 0.5
             + 2 * 40 / 100 * 60 + 0.5)         # rigid tapping, dwell 0.5 (counted once)
    seconds = round(rapids + holes)
    assert seconds == 201
    assert estimate == f"; vypocitany cas: 0 hod {seconds // 60} min {seconds % 60} sek"


def test_the_engine_names_no_machine() -> None:
    """No machine anywhere in the code; a control family only in its model
    (postdsl/check/controls/).

    A control model holds what a control does with a word, from its manual: it
    names the control, once, and never a machine built with it.
    """
    machines = re.compile(r"vmc|emco|feeler", re.IGNORECASE)
    controls = re.compile(r"acramatic|sinumerik|fanuc|siemens", re.IGNORECASE)
    for path in sorted((ROOT / "postdsl").rglob("*.py")):
        # the control models, and the one table of the controls' reading facts they share
        # with the compiler (comment syntax, numbers without a point)
        in_models = path.parent == ROOT / "postdsl" / "check" / "controls" \
            or path == ROOT / "postdsl" / "lang" / "control_syntax.py"
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            assert not machines.search(line), f"{path.relative_to(ROOT)}:{number}: {line}"
            assert in_models or not controls.search(line), \
                f"{path.relative_to(ROOT)}:{number}: {line}"


def test_preview_shows_a_commands_blocks_for_sample_values() -> None:
    result = run_cli("preview", "vmc500", "break_chip", "--set", "peck=5")
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == [
        "[$CYCLE_PARAMS(2)GAGE_HT_MM] = 5.0",
        "[$CYCLE_PARAMS(2)G83_RET_DIST] = 1.0",
        "N10 G83 X60. Y20. Z53.0043 R70.0 F200.0 J11 K5.0",
        "; " + "*" * 74,
    ]
