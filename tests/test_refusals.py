"""Issue 25: the ways posting still wrote NC a control runs wrongly, or crashed.

Each test posts what a machinist or an attacker would give a bundled post and reads
the NC text (or the refusal) as the control would: CL text that closes a comment and
writes words, program names the control refuses to load, values no control can cut,
and inputs that ended in a traceback (exit 3) instead of a located error.
"""

from __future__ import annotations

import functools
import json
import re
from datetime import UTC, datetime
from pathlib import Path

import pytest
from click.testing import CliRunner

from postdsl import api
from postdsl.cli import main
from postdsl.errors import CLError, PostError
from postdsl.run.trace import trace_lines
from tests.conftest import ROOT
from tests.test_rs274_oracle import TOOL_TABLE, needs_rs274, rs274_process, run_rs274

NOW = datetime(2024, 3, 5, 7, 8, 9, tzinfo=UTC)

#: the bundled machines that write CL comments into ( ... )
PARENTHESES = ("linuxcnc", "fanuc", "feeler", "grbl")
INJECTION = "end of roughing) M30 (finish follows"
LABEL = "Pocket) G0 Z-99 (x"


@functools.cache
def bundled(machine: str) -> api.CompiledPost:
    return api.load_post(machine)


def jsonl(*records: dict) -> str:
    if not records or records[-1] != {"cmd": "program_end"}:
        records = (*records, {"cmd": "program_end"})
    return "".join(json.dumps(record) + "\n" for record in records)


START = ({"cmd": "program_start", "program_name": "P1"},
         {"cmd": "tool_change", "tool_number": 1, "tool_type": "drill", "tool_diameter": 8},
         {"cmd": "spindle_on", "spindle_speed": 500, "spindle": "cw"},
         {"cmd": "rapid_move", "x": 10, "y": 0, "z": 5},
         {"cmd": "linear_move", "z": 0, "feed": 100})


def nc(machine: str | api.CompiledPost, text: str) -> list[str]:
    post = bundled(machine) if isinstance(machine, str) else machine
    return [line.text for line in
            api.post_commands(post, api.read_cl_text(text, "job.jsonl"), cl_file="job.jsonl",
                              now=NOW)]


def refusal(machine: str, text: str) -> str:
    with pytest.raises(CLError) as caught:
        nc(machine, text)
    return str(caught.value)


def cli_post(machine: str, text: str, tmp_path: Path, *options: str) -> tuple[int, str, Path]:
    cl = tmp_path / "job.jsonl"
    cl.write_text(text, encoding="utf-8")
    out = tmp_path / "out.nc"
    result = CliRunner().invoke(main, ["post", machine, str(cl), "-o", str(out), *options])
    return result.exit_code, result.output, out


# --- 1. CL text into comments, by the control's rule ------------------------------------


def comment_program() -> str:
    return jsonl(*START, {"cmd": "comment", "comment": INJECTION},
                 {"cmd": "comment", "comment": "50% done; ok"},  # ';' is text inside ( )
                 {"cmd": "operation", "operation": LABEL},
                 {"cmd": "linear_move", "x": 20, "feed": 100}, {"cmd": "spindle_off"})


def outside_comments(line: str) -> str:
    """The NC words of a line as RS274 reads them: ( ... ) removed, ';' to the end."""
    line = re.sub(r"\([^)]*\)", "", line)
    return line.split(";")[0].strip()


@pytest.mark.parametrize("machine", PARENTHESES)
def test_cl_text_cannot_close_a_parenthesis_comment(machine: str) -> None:
    post = api.load_post(machine)
    lines = nc(post, comment_program())
    texts = [line for line in lines if "roughing" in line or "Pocket" in line]
    assert texts, lines
    for line in texts:
        # was "(end of roughing) M30 (finish follows)": M30 ended the program there
        assert outside_comments(line) in ("", re.sub(r"\(.*", "", line).strip()), line
        assert "M30" not in outside_comments(line) and "G0" not in outside_comments(line)
    assert any("end of roughing] M30 [finish follows" in line for line in texts)


@needs_rs274
def test_the_linuxcnc_comment_reads_as_one_comment_to_rs274(tmp_path: Path) -> None:
    """LinuxCNC's own interpreter runs every cut of the program, and no M30 or Z-99."""
    lines = nc("linuxcnc", comment_program())
    numbered = [f"N{index}{line}" for index, line in enumerate(lines, start=1)]
    trace = run_rs274(numbered, tmp_path)
    ends = [move.end for move in trace.moves]
    assert all(end[2] > -1 for end in ends), ends  # no plunge to Z-99
    # the cut after the comment and the label runs: a feed to X20 (an M30 read in the
    # comment would have ended the program before it)
    assert any(move.kind == "feed" and abs(move.end[0] - 20) < 1e-6 for move in trace.moves)


def test_percent_does_not_reach_a_fanuc_comment() -> None:
    text = jsonl(*START, {"cmd": "comment", "comment": "50% done"}, {"cmd": "spindle_off"})
    lines = nc("fanuc", text)
    body = lines[1:-1]  # the tape's own % lines are first and last
    assert not any("%" in line for line in body), body
    assert "(50pct done)" in lines


def test_normal_comments_are_written_unchanged() -> None:
    text = jsonl(*START, {"cmd": "comment", "comment": "ROUGH [A] 50% ; x"},
                 {"cmd": "spindle_off"})
    assert "(ROUGH [A] 50% ; x) " in nc("linuxcnc", text)
    assert "; ROUGH [A] 50% ; x" in nc("vmc500", text)


def test_a_heidenhain_program_name_the_tnc_refuses_is_refused_at_the_cl_line() -> None:
    text = jsonl({"cmd": "program_start", "program_name": "P;1(x)%"}, *START[1:],
                 {"cmd": "spindle_off"})
    message = refusal("heidenhain", text)
    assert message.startswith("job.jsonl:1: program_start"), message
    assert "'%' '(' ')' ';'" in message and "TNC 640" in message
    # the post's own replace (space -> _) comes first: a space is no error
    ok = jsonl({"cmd": "program_start", "program_name": "MY PART-2"}, *START[1:],
               {"cmd": "spindle_off"})
    assert nc("heidenhain", ok)[0] == "0 BEGIN PGM MY_PART-2 MM"


# --- 4. crashes become located errors ---------------------------------------------------


@pytest.mark.parametrize("machine", ["emco", "fanuc", "feeler", "grbl", "linuxcnc", "vmc500"])
def test_a_spindle_speed_of_1e20_is_a_located_error(machine: str) -> None:
    text = jsonl(*START[:2], {"cmd": "spindle_on", "spindle_speed": 1e20, "spindle": "cw"})
    message = refusal(machine, text)
    assert message.startswith("job.jsonl:3: spindle speed 1e+20 rpm is outside"), message


@pytest.mark.parametrize("machine", ["grbl", "vmc500"])
def test_a_subnormal_peck_on_an_expanded_hole_is_a_located_error(machine: str) -> None:
    text = jsonl(*START, {"cmd": "rapid_move", "z": 20}, {"cmd": "cycle_start"},
                 {"cmd": "deep_drill", "x": 40, "y": 20, "top": 0, "depth": 10,
                  "clearance": 5, "retract": 20, "peck": 1e-320, "feed": 200},
                 {"cmd": "cycle_end"})
    message = refusal(machine, text)
    assert message.startswith("job.jsonl:8: deep_drill: peck"), message
    assert "more than 10^308 pecks" in message


def test_a_header_the_cl_leaves_out_is_located_at_the_first_record() -> None:
    """No program_start record, and a machining time too long for the header's format:
    the refusal names a CL line (it had none)."""
    records = [*START[1:], {"cmd": "dwell", "dwell": 1e300}, {"cmd": "spindle_off"}]
    message = refusal("vmc500", jsonl(*records))
    assert message.startswith("job.jsonl:1: program_start (the CL has none"), message
    assert "machining_time" in message


def test_the_cli_exits_2_not_3_for_these(tmp_path: Path) -> None:
    text = jsonl(*START[:2], {"cmd": "spindle_on", "spindle_speed": 1e20, "spindle": "cw"})
    code, output, out = cli_post("fanuc", text, tmp_path)
    assert code == 2, output
    assert "internal error" not in output and not out.exists()


# --- 2. the EMCO's floating tap takes its directions from the spindle -------------------


def tap(cycle: str, spindle: str) -> str:
    return jsonl(START[0], {"cmd": "tool_change", "tool_number": 2, "tool_type": "tap",
                            "tool_diameter": 8},
                 {"cmd": "spindle_on", "spindle_speed": 500, "spindle": spindle},
                 {"cmd": "rapid_move", "x": 10, "y": 0, "z": 20}, {"cmd": "cycle_start"},
                 {"cmd": cycle, "x": 40, "y": 20, "top": 0, "depth": 10, "clearance": 5,
                  "retract": 20, "feed": 500},
                 {"cmd": "cycle_end"}, {"cmd": "spindle_off"})


def cycle840(machine_lines: list[str]) -> list[str]:
    """SDR and SDAC of the CYCLE840 call: its 7th and 8th arguments."""
    call = next(line for line in machine_lines if "CYCLE840(" in line)
    return [a.strip() for a in call.split("CYCLE840(")[1].rstrip(")").split(",")][6:8]


def test_a_left_hand_floating_tap_under_m4_retracts_under_m3_and_ends_under_m4() -> None:
    # Siemens CYCLE840: SDR the direction of retraction, SDAC the direction after it
    assert cycle840(nc("emco", tap("tapping_ccw", "ccw"))) == ["3", "4"]
    assert cycle840(nc("emco", tap("tapping", "cw"))) == ["4", "3"]


@pytest.mark.parametrize(("cycle", "spindle"), [("tapping", "ccw"), ("tapping_ccw", "cw")])
def test_a_floating_tap_against_the_spindle_is_refused(cycle: str, spindle: str) -> None:
    """Was: 'tapping' under M4 written as a right-hand MCALL CYCLE840(... 4, 4 ...)."""
    message = refusal("emco", tap(cycle, spindle))
    assert message.startswith(f"job.jsonl:6: {cycle}: a "), message
    assert "the way the spindle turns" in message


# --- 3. what no control can cut, refused at the CL line ---------------------------------

MACHINES = ("emco", "fanuc", "feeler", "grbl", "heidenhain", "linuxcnc", "vmc500")


@pytest.mark.parametrize("machine", MACHINES)
@pytest.mark.parametrize("end_x", [10.0008, 10.0])  # a short arc, and a full circle
def test_an_arc_whose_radius_rounds_below_the_resolution_is_refused(machine: str,
                                                                    end_x: float) -> None:
    """Was 'G3 X10.001 Y0. I0. J0.': a radius 0 arc, an alarm on every control."""
    text = jsonl(*START, {"cmd": "arc_move", "x": end_x, "y": 0, "cx": 10.0004, "cy": 0,
                          "arc_direction": "ccw", "feed": 100})
    message = refusal(machine, text)
    assert message.startswith("job.jsonl:6: arc_move: radius 0.0004 rounds below the output "
                              "resolution 0.001"), message


@pytest.mark.parametrize("machine", MACHINES)
def test_an_arc_of_one_increment_radius_is_still_written(machine: str) -> None:
    text = jsonl(*START, {"cmd": "arc_move", "x": 10, "y": 0, "cx": 10.001, "cy": 0,
                          "arc_direction": "ccw", "feed": 100}, {"cmd": "spindle_off"})
    assert nc(machine, text)


def drill(peck: float, cycle: str = "deep_drill") -> str:
    return jsonl(*START, {"cmd": "rapid_move", "z": 20}, {"cmd": "cycle_start"},
                 {"cmd": cycle, "x": 40, "y": 20, "top": 0, "depth": 10, "clearance": 5,
                  "retract": 20, "peck": peck, "feed": 200},
                 {"cmd": "cycle_end"}, {"cmd": "spindle_off"})


@pytest.mark.parametrize(("machine", "peck", "written"), [
    ("fanuc", 0.0001, "'0.'"), ("feeler", 0.0001, "'0.'"), ("emco", 0.0001, "'0.000'"),
    ("linuxcnc", 0.0001, "'0.000'"), ("heidenhain", 0.00004, "'+0'")])
def test_a_peck_that_rounds_to_zero_is_refused(machine: str, peck: float, written: str) -> None:
    """Was 'Q0.', 'Q202=+0': read as no pecking, or (Fanuc) the last Q given."""
    message = refusal(machine, drill(peck))
    assert message.startswith(f"job.jsonl:8: deep_drill: peck {peck:g} is written {written}"), \
        message


def test_a_peck_that_rounds_to_zero_in_inches_is_refused() -> None:
    """A TNC Q line written through an expression (the inch conversion of a length) is
    checked on the value it writes: 0.001 mm is Q202=+0.001 in a mm program, and +0 in an
    inch one (0.0000394 in at 4 decimals) -- written as no pecking while the check, which
    saw only the peck itself, passed it."""
    assert any("Q202=+0.001" in line for line in nc("heidenhain", drill(0.001)))
    inch = api.load_post("heidenhain", {"program_units": "inch"})
    with pytest.raises(CLError) as caught:
        nc(inch, drill(0.001))
    assert str(caught.value).startswith("job.jsonl:8: deep_drill: peck 0.001 is written '+0'")


@pytest.mark.parametrize("machine", MACHINES)
def test_a_peck_of_exactly_zero_is_no_pecking_and_stays_valid(machine: str) -> None:
    lines = nc(machine, drill(0))
    assert not any(re.search(r"\bQ0\.|K0\.0|Q20[25]=\+0\b", line) for line in lines), lines


def test_every_library_machine_declares_its_tools() -> None:
    for machine in (*MACHINES, "hmcnc"):
        assert bundled(machine).machine.max_tool_number is not None, machine


@pytest.mark.parametrize("machine", (*MACHINES, "hmcnc"))
def test_a_tool_beyond_the_machine_is_refused(machine: str) -> None:
    """Was: T9999 written by six posts."""
    number = bundled(machine).machine.max_tool_number + 1
    records = [{**record, "tool_number": number} if record["cmd"] == "tool_change" else record
               for record in START if machine != "hmcnc" or record["cmd"] != "spindle_on"]
    message = refusal(machine, jsonl(*records))
    assert message.startswith(f"job.jsonl:2: tool {number} does not exist on "), message


# --- the post's side: postdsl check -----------------------------------------------------

POST = """
postdsl: 1
machine: {{name: T, control: {control}, resolution: 0.001, tool_changer: false,
          tools: {{max_number: 9}}}}
formats:
  c: {{decimals: 3}}
{structures}
commands:
  program_start: {{blocks: []}}
  program_end: {{blocks: [{{items: ["M30"]}}]}}
{commands}
"""


WORD = """structures:
  word:
    - items: ["(Q", {expr: "v"}, ")"]"""


def post_problem(commands: str, control: str = "fanuc-0i", structures: str = "") -> str:
    with pytest.raises(PostError) as caught:
        api.load_post_text(POST.format(control=control, commands=commands,
                                       structures=structures), "p.yaml")
    return caught.value.report()


def test_a_computed_number_without_a_format_is_a_located_post_error() -> None:
    """Was '(Q-3.3333333333333335)': Python's repr in the program."""
    report = post_problem("""
  linear_move:
    blocks:
      - items: ["G1", {param: x, prefix: " X", format: c}, " (Q", {expr: "x / 3"}, ")"]
""")
    assert report.startswith("p.yaml:14:75: "), report
    assert "the computed item 'x / 3' may write a number, and it has no format" in report
    # through a structure's use: the table's expression is the one checked
    report = post_problem("""
  linear_move:
    blocks:
      - items: ["G1", {param: x, prefix: " X", format: c}]
      - {use: word, with: {v: "x / 3"}}
""", structures=WORD)
    assert report.startswith("p.yaml:9:") and "may write a number" in report, report


def test_texts_and_flags_need_no_format() -> None:
    api.load_post_text(POST.format(control="fanuc-0i", structures="", commands="""
  linear_move:
    blocks:
      - items: [{expr: "'G' + str(1, 'c')"}, {expr: "x > 1"}, {param: x, format: c}]
"""), "p.yaml")


def test_cl_text_outside_a_comment_is_reported() -> None:
    report = post_problem("""
  comment:
    blocks:
      - items: [{param: comment, prefix: "M0 "}]
      - items: ["(", {param: comment}, ")"]
""")
    assert report.startswith("p.yaml:14:17: ") and "CL text (comment) written outside a " \
        "comment" in report, report
    assert report.count("\n") == 0, report  # the second block is a comment: no problem


def test_a_replace_that_maps_to_a_breaking_character_is_reported() -> None:
    report = post_problem("""
  comment:
    blocks:
      - items: ["(", {param: comment, replace: {"[": "("}}, ")"]
""")
    assert "replace maps '[' to '(' inside a comment, but '(' breaks out" in report, report


def test_text_after_a_line_comment_opener_is_in_the_comment() -> None:
    post = api.load_post_text(POST.format(control="linuxcnc", structures="", commands="""
  comment:
    blocks:
      - items: ["; ", {param: comment}]
"""), "p.yaml")
    assert next(line.text for line in api.post_commands(
        post, api.read_cl_text(jsonl({"cmd": "comment", "comment": "a (b) c"}), "j.jsonl"),
        now=NOW)).endswith("; a [b] c")


def test_a_move_lane_escapes_its_comment_text_too(tmp_path: Path) -> None:
    """The generated lanes of rapid and linear moves (the one returning lines, its traced
    flavour, and the one writing text to a file) escape CL text through the same closure."""
    source = POST.format(control="linuxcnc", structures="", commands="""
  tool_change: {reset: [x], blocks: []}
  linear_move:
    blocks:
      - items: ["G1", {param: x, prefix: " X", format: c}, " (", {param: tool_name}, ")"]
""")
    text = jsonl({"cmd": "tool_change", "tool_number": 1, "tool_name": "a) M30 (b"},
                 {"cmd": "linear_move", "x": 1, "feed": 100},
                 {"cmd": "linear_move", "x": 2, "feed": 100})
    want = ["N10 G1 X1.000 (a] M30 [b)", "N20 G1 X2.000 (a] M30 [b)"]
    post = api.load_post_text(source, "p.yaml")
    lines = [line.text for line in api.post_commands(post, api.read_cl_text(text, "j.jsonl"),
                                                      now=NOW)]
    assert lines[:2] == want
    traced = [t.line.text for t in trace_lines(post, api.read_cl_text(text, "j.jsonl"),
                                               now=NOW)]
    assert traced == lines
    (tmp_path / "p.yaml").write_text(source, encoding="utf-8")
    # --no-verify: the lane that writes text straight to the file (a verified post reads
    # each line's source too); the test's toy program states no start position to verify
    code, output, out = cli_post(str(tmp_path / "p.yaml"), text, tmp_path, "--no-verify")
    assert code == 0, output
    assert out.read_text(encoding="utf-8").splitlines()[:2] == want


# --- comments that are commands to the control ------------------------------------------

#: CL comments that a LinuxCNC would run as commands: an abort, a log file, a message
ACTIVE = (" abort, stop here", "LOGOPEN,/tmp/postdsl-pwned.txt", "msg,operator look",
          "DEBUG,#<x>", "PRINT,y", "py,import os")


@pytest.mark.parametrize("comment", ACTIVE)
def test_a_cl_comment_never_becomes_a_linuxcnc_command(comment: str) -> None:
    lines = nc("linuxcnc", jsonl(*START, {"cmd": "comment", "comment": comment},
                                 {"cmd": "linear_move", "x": 20, "feed": 100}))
    [line] = [line for line in lines if comment.strip()[:3] in line]
    written = line[line.index("(") + 1:line.index(")")]
    assert not ACTIVE_WORD.match(written), line
    assert written.endswith(comment.replace("(", "[").replace(")", "]")), line


ACTIVE_WORD = re.compile(r"\s*(MSG|DEBUG|PRINT|LOG\w*|PROBE\w*|ABORT|PY)\b", re.I)


@needs_rs274
def test_rs274_runs_the_escaped_active_comments_as_comments(tmp_path: Path) -> None:
    """LinuxCNC's interpreter: no LOGOPEN, no MESSAGE, no abort; the cut after them runs."""
    records = [{"cmd": "comment", "comment": comment} for comment in ACTIVE]
    lines = nc("linuxcnc", jsonl(*START, *records, {"cmd": "linear_move", "x": 20,
                                                    "feed": 100}))
    ngc = tmp_path / "program.ngc"
    ngc.write_text("\n".join(lines) + "\n", encoding="utf-8")
    table = tmp_path / "tools.tbl"
    table.write_text(TOOL_TABLE, encoding="utf-8")
    done = rs274_process(table, ngc)
    calls = done.stdout
    run = re.findall(r"^\s*\d+ N\.+ (\w+)\(", calls, re.MULTILINE)
    assert run and not {"LOGOPEN", "LOG", "MESSAGE", "PROBEOPEN"} & set(run), run
    assert run.count("COMMENT") >= len(ACTIVE), run
    assert "STRAIGHT_FEED(20.0000" in calls, calls
    assert not Path("/tmp/postdsl-pwned.txt").exists()


def test_verify_refuses_an_active_comment_a_post_writes_itself(tmp_path: Path) -> None:
    """A post whose own text is a LinuxCNC command fails verify: the model does not guess."""
    source = (ROOT / "machines" / "linuxcnc.yaml").read_text(encoding="utf-8")
    mutated = source.replace('items: [{text: " ", if: "line_numbers"}, "(", {param: comment}',
                             'items: [{text: " ", if: "line_numbers"}, "(ABORT,", '
                             '{param: comment}', 1)
    assert mutated != source
    post_file = tmp_path / "linuxcnc.yaml"
    post_file.write_text(mutated, encoding="utf-8")
    cl = tmp_path / "job.jsonl"
    cl.write_text(jsonl(*START, {"cmd": "comment", "comment": "x"},
                        {"cmd": "linear_move", "x": 20, "feed": 100}), encoding="utf-8")
    result = CliRunner().invoke(main, ["verify", str(post_file), str(cl)])
    assert result.exit_code == 4, result.output
    assert "is a command to the linuxcnc control" in result.output


def test_a_heidenhain_comment_never_ends_in_a_continuation_tilde() -> None:
    """'~' ends a TNC block that goes on in the next line: CL text never writes one."""
    lines = nc("heidenhain", jsonl(
        {"cmd": "program_start", "program_name": "P1"},
        {"cmd": "operation", "operation": "rough~"},
        {"cmd": "tool_change", "tool_number": 1, "tool_type": "drill", "tool_diameter": 8,
         "tool_name": "EM~"},
        {"cmd": "comment", "comment": "ends in ~"},
        *START[2:]))
    assert not any(line.rstrip().endswith("~") for line in lines
                   if ";" in line or "* -" in line), lines
    assert any(line.endswith("* - rough-") for line in lines), lines
