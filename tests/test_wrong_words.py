"""A bundled post mutated to write one wrong word: ``postdsl verify`` exits 4 (issue 25).

Each class of wrong word the control models now read as the control does -- a number
without a decimal point on a Fanuc, a comment that breaks out of its parentheses, M30
inside a comment line, CYCLE840's SDR and SDAC, Heidenhain Q parameters out of order, a
retract higher than the CL's -- is put into a bundled post by editing its YAML text
here; the mutated post fails verify with exit 4 at the line that goes wrong, and the
post as bundled passes.  Where LinuxCNC's ``rs274`` reads the dialect (the LinuxCNC post;
the Fanuc post through the documented rewrite of tests/test_rs274_oracle.py) it is
shown to do what the model says the mutated program does.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from postdsl import api
from postdsl.check.controls import control_model
from postdsl.check.controls.events import ArcMove, FeedMove, Rapid
from tests.conftest import EXAMPLES, MACHINES, ROOT, THESIS_TIME
from tests.test_rs274_oracle import for_rs274, needs_rs274, run_rs274


def mutated(machine: str, after: str, old: str, new: str) -> str:
    """The bundled post's text with the first ``old`` after ``after`` replaced by ``new``."""
    text = (MACHINES / f"{machine}.yaml").read_text(encoding="utf-8")
    at = text.index(old, text.index(after))
    return text[:at] + new + text[at + len(old):]


def verify(post: str | Path, cl: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "postdsl.cli", "verify", str(post), str(cl)],
                          capture_output=True, text=True, cwd=ROOT, check=False)


Q210 = """      - {use: q_line, with: {q: "210", value: "0", label: "'DWELL TIME AT TOP'", \
tail: "' ~'"}}"""
Q203 = """      - {use: q_length, with: {q: "203", value: "top", label: "'SURFACE COORDINATE'", \
tail: "' ~'"}}"""

#: class -> (machine, CL, after, old, new, what verify says)
MUTATIONS = {
    # a safe-Z move written without a point, as the thesis routine's literal "G0 Z50 F5000"
    "decimal point": ("fanuc", EXAMPLES / "feeler_milling.apt", "  home_z:",
                      '" G91 G28 Z0."', '" G90 G0 Z50"',
                      "a rapid down to Z0.050, below the CL's lowest point"),
    # a comment closed early: the rest of the label runs as code (a rapid plunge)
    "comment break": ("linuxcnc", EXAMPLES / "linuxcnc_pocket.dump.txt", "  finish_operation:",
                      '"(finish operation: "', '"(finish operation) G0 Z-99 ("',
                      "a rapid down to Z-99.000"),
    # M30 between two comments: LinuxCNC ends the program there
    "M30 in a comment": ("linuxcnc", EXAMPLES / "linuxcnc_pocket.dump.txt",
                         "  finish_operation:", '"(finish operation: "',
                         '"(end of roughing) M30 (finish operation: "',
                         "(end of roughing) M30 (finish operation: G54): the NC program "
                         "ends, the CL still has"),
    # CYCLE840 under M3 retracting M3: the tap pulled out turning the way it cut
    "SDR": ("emco", EXAMPLES / "emco_drilling.jsonl", "  tapping:",
            """{text: ", 4, 3", if: "spindle == 'cw'"}""",
            """{text: ", 3, 3", if: "spindle == 'cw'"}""",
            "CYCLE840 SDR=3: the tap retracts turning M3, as it went in (cw)"),
    # SDAC 5: the spindle stops after the first hole of the MCALL, the next is tapped so
    "SDAC": ("emco", EXAMPLES / "emco_drilling.jsonl", "  tapping:",
             """{text: ", 4, 3", if: "spindle == 'cw'"}""",
             """{text: ", 4, 5", if: "spindle == 'cw'"}""",
             "CYCLE840 with the spindle off"),
    # Q203 before Q210: not the order of cycle 200's definition
    "Q order": ("heidenhain", EXAMPLES / "heidenhain_cycles.jsonl", "  single_peck:",
                Q210 + "\n" + Q203, Q203 + "\n" + Q210,
                "Q203 where the cycle's definition has Q210"),
    # Q204 written as the absolute retract plane, not above the surface: the tool leaves higher
    "retract Q204": ("heidenhain", EXAMPLES / "heidenhain_cycles.jsonl", "  single_peck:",
                     'q: "204", value: "retract - top"', 'q: "204", value: "retract"',
                     "above the CL's retract"),
    # G98 where the CL's retract is R: the tool returns to the initial level, higher
    "retract G98": ("fanuc", EXAMPLES / "feeler_drilling.apt", "  single_peck:",
                    '{text: " G99", if: "retract <= top + clearance"}',
                    '{text: " G98", if: "retract <= top + clearance"}',
                    "above the CL's retract"),
}


@pytest.mark.parametrize("wrong", list(MUTATIONS))
def test_a_post_writing_a_wrong_word_fails_verify_and_the_bundled_post_passes(
        wrong: str, tmp_path: Path) -> None:
    machine, cl, after, old, new, message = MUTATIONS[wrong]
    good = verify(machine, cl)
    assert good.returncode == 0, good.stderr
    post = tmp_path / f"{machine}.yaml"
    post.write_text(mutated(machine, after, old, new), encoding="utf-8")
    bad = verify(post, cl)
    assert bad.returncode == 4, bad.stderr
    assert message in bad.stderr
    assert "Traceback" not in bad.stderr


def nc(post_text: str, cl: Path) -> list[str]:
    post = api.load_post_text(post_text, "post.yaml")
    return [line.text for line in api.post_commands(post, api.read_cl(cl), now=THESIS_TIME)]


@needs_rs274
@pytest.mark.parametrize("wrong", ["comment break", "M30 in a comment"])
def test_rs274_runs_the_mutated_linuxcnc_program_as_the_model_does(wrong: str,
                                                                   tmp_path: Path) -> None:
    machine, cl, after, old, new, _ = MUTATIONS[wrong]
    lines = nc(mutated(machine, after, old, new), cl)
    trace = run_rs274(lines, tmp_path)
    model = list(control_model("linuxcnc").replay(lines))
    theirs = [m.end for m in trace.moves if m.kind in ("feed", "arc")]
    ours = [e.end for e in model if isinstance(e, (FeedMove, ArcMove))]
    assert theirs == [pytest.approx(end) for end in ours]
    whole = [m for m in run_rs274(nc((MACHINES / "linuxcnc.yaml").read_text(encoding="utf-8"),
                                     cl), tmp_path).moves if m.kind in ("feed", "arc")]
    if wrong == "M30 in a comment":
        assert len(theirs) < len(whole)  # the program ends early: cuts the CL has never run
    else:
        assert any(m.kind == "rapid" and m.end[2] == pytest.approx(-99) for m in trace.moves)
        assert any(isinstance(e, Rapid) and e.end[2] == pytest.approx(-99) for e in model)


@needs_rs274
def test_rs274_leaves_the_g98_hole_at_the_initial_level_as_the_model_does(
        tmp_path: Path) -> None:
    machine, cl, after, old, new, _ = MUTATIONS["retract G98"]
    lines = nc(mutated(machine, after, old, new), cl)
    trace = run_rs274(for_rs274(lines), tmp_path)
    first = next(i for i, line in enumerate(lines, start=1) if " G98 G81" in line)
    # rs274's moves of the first hole's line: down to the bottom, then up to where it leaves
    up = [m for m in trace.moves if m.line == first][-1]
    verdict = api.verify_commands(api.load_post_text(mutated(machine, after, old, new)),
                                  api.read_cl(cl), cl_file=cl.name, now=THESIS_TIME)
    assert verdict.divergence is not None
    assert f"left at Z{up.end[2]:.3f}, above" in verdict.divergence.message


def injection_cl(first: str, second: str) -> str:
    records = [
        {"cmd": "program_start", "program_name": "INJECT"},
        {"cmd": "tool_change", "tool_number": 1, "tool_diameter": 6},
        {"cmd": "spindle_on", "spindle_speed": 1000, "spindle": "cw"},
        {"cmd": "rapid_move", "x": 0, "y": 0, "z": 5},
        {"cmd": "linear_move", "z": -1, "feed": 100},
        {"cmd": "linear_move", "x": 10},
        {"cmd": "comment", "comment": first},
        {"cmd": "linear_move", "y": 10},
        {"cmd": "comment", "comment": second},
        {"cmd": "linear_move", "x": 0},
        {"cmd": "rapid_move", "z": 5},
        {"cmd": "spindle_off"},
        {"cmd": "program_end"},
    ]
    return "".join(json.dumps(record) + "\n" for record in records)


@needs_rs274
def test_the_linuxcnc_comment_injection_never_passes_verify_with_cuts_missing_or_extra(
        tmp_path: Path) -> None:
    """``(end of roughing) M30 (finish follows)`` ended the program on LinuxCNC with exit 0.
    Whatever the post writes for these CL comments (escaped, or as they are), verify passes
    exactly when rs274 runs every cut the CL has and no other move below it."""
    post = api.load_post("linuxcnc")
    plain = injection_cl("end of roughing", "finish follows")
    hostile = injection_cl("end of roughing) M30 (finish follows", "Pocket) G0 Z-99 (x")
    reference = run_rs274(nc_of(post, plain), tmp_path)
    lines = nc_of(post, hostile)
    trace = run_rs274(lines, tmp_path)
    verdict = api.verify_commands(post, api.read_cl_text(hostile, "inject.jsonl"),
                                  cl_file="inject.jsonl", now=THESIS_TIME)
    cuts = [m.end for m in trace.moves if m.kind == "feed"]
    same = cuts == [m.end for m in reference.moves if m.kind == "feed"] and \
        min(m.end[2] for m in trace.moves) >= -1 - 1e-6
    assert verdict.ok == same, (verdict.divergence, lines)
    if not verdict.ok:  # posted as they are: the program ends at the M30
        assert "the NC program ends, the CL still has" in str(verdict.divergence)


def nc_of(post: api.CompiledPost, cl_text: str) -> list[str]:
    return [line.text for line in api.post_commands(post, api.read_cl_text(cl_text, "c.jsonl"),
                                                   now=THESIS_TIME)]
