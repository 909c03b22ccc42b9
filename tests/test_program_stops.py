"""program_stop and optional_stop (M0/M1): read from every CL form, written or refused by
every library post, replayed by the control models, and where rs274 stops."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from postdsl import api
from postdsl.cl.model import OptionalStop, ProgramStop
from postdsl.errors import CLError
from tests.conftest import ROOT, THESIS_TIME
from tests.test_rs274_oracle import TOOL_TABLE, for_rs274, needs_rs274, rs274_process

STOPS = ROOT / "examples" / "program_stops.jsonl"
ROUTER = ROOT / "examples" / "program_stops_router.jsonl"


def stops(commands) -> list[tuple[str, int]]:
    return [(c.name, c.line) for c in commands if isinstance(c, (ProgramStop, OptionalStop))]


# --- readers ------------------------------------------------------------------------------------


def test_plain_gcode_stops_after_the_motion_of_their_block() -> None:
    """RS274's order of execution: the stop (M0, M1) is the last thing a block does."""
    text = "G21 G90\nT1 M6\nS1000 M3\nG0 X10 Y10 M0\nG0 Z5\nM01\nM5\nM30\n"
    commands = api.read_cl_text(text, "s.ngc", "gcode")
    names = [(c.name, c.line) for c in commands if c.line in (4, 6)]
    assert names == [("rapid_move", 4), ("program_stop", 4), ("optional_stop", 6)]


def test_freecad_path_stop_objects_are_read() -> None:
    """FreeCAD's Path Stop writes M0 (mandatory) or M1 (optional) on a line of its own."""
    text = "(Stop)\nM0\n(Stop001)\nM1\nM2\n"
    assert stops(api.read_cl_text(text, "s.gcode", "freecad")) == [
        ("program_stop", 2), ("optional_stop", 4)]


def test_native_and_apt_stops() -> None:
    native = ('{"cmd": "program_start"}\n{"cmd": "optional_stop"}\n'
              '{"cmd": "program_stop"}\n{"cmd": "program_end"}\n')
    assert stops(api.read_cl_text(native, "s.jsonl", "native")) == [
        ("optional_stop", 2), ("program_stop", 3)]
    apt = "PARTNO/1\nOPSTOP\nSTOP\nFINI\n"
    assert stops(api.read_cl_text(apt, "s.apt", "apt")) == [
        ("optional_stop", 2), ("program_stop", 3)]


# --- posts --------------------------------------------------------------------------------------

#: the block each post writes for the example's optional stop (CL line 10) and program stop
#: (CL line 17), without its block number
WRITTEN = {
    "fanuc": (["M1", "S2000 M3", "M8"], ["M0"]),
    "feeler": (["M1"], ["M0"]),
    "emco": (["M1"], ["M0"]),
    "vmc500": (["M1"], ["M5", "M9", "M0"]),
    "linuxcnc": (["M1"], ["M0"]),
    "heidenhain": (["M1", "M3", "M8"], ["M0"]),
}


@pytest.mark.parametrize("machine", sorted(WRITTEN))
def test_each_post_writes_its_controls_stop_words(machine: str) -> None:
    post = api.load_post(machine)
    lines = list(api.post_commands(post, api.read_cl(STOPS), cl_file=STOPS.name,
                                   now=THESIS_TIME))

    def words(cl_line: int) -> list[str]:
        return [re.sub(r"^(N\d+|\d+)\s+", "", line.text).strip() for line in lines
                if line.cl_line == cl_line]

    assert (words(10), words(17)) == WRITTEN[machine]


@pytest.mark.parametrize("machine", sorted(WRITTEN))
def test_each_post_stops_verify(machine: str) -> None:
    verdict = api.verify_commands(api.load_post(machine), api.read_cl(STOPS),
                                  cl_file=STOPS.name, now=THESIS_TIME)
    assert verdict.divergence is None, verdict.divergence


@pytest.mark.parametrize(("machine", "cl", "line", "reason"), [
    ("grbl", STOPS, 10, "GRBL 1.1 reads M1 and ignores it"),
    ("hmcnc", ROUTER, 9, "hmCNC has no optional stop"),
])
def test_a_control_without_the_stop_refuses_it_at_the_cl_line(machine: str, cl: Path,
                                                              line: int, reason: str) -> None:
    with pytest.raises(CLError) as caught:
        list(api.post_commands(api.load_post(machine), api.read_cl(cl), cl_file=cl.name))
    assert caught.value.location is not None and caught.value.location.line == line
    assert reason in caught.value.message


def test_grbl_pauses_at_m0_and_hmcnc_refuses_it() -> None:
    text = ('{"cmd": "program_start"}\n{"cmd": "program_stop"}\n{"cmd": "program_end"}\n')
    grbl = api.load_post("grbl")
    assert "M0" in [line.text for line in api.post_commands(
        grbl, api.read_cl_text(text, "s.jsonl", "native"))]
    with pytest.raises(CLError, match="hmCNC has no program stop"):
        list(api.post_commands(api.load_post("hmcnc"),
                               api.read_cl_text(text, "s.jsonl", "native")))


def test_the_tnc_model_knows_m0_stops_the_spindle() -> None:
    """TNC 640 M0/M1 stop the spindle: a post that does not switch it on again is caught."""
    text = (ROOT / "machines" / "heidenhain.yaml").read_text(encoding="utf-8")
    careless = api.load_post_text(text.replace("      - use: restate_spindle\n", ""),
                                  "heidenhain.yaml")
    verdict = api.verify_commands(careless, api.read_cl(STOPS), cl_file=STOPS.name)
    assert verdict.divergence is not None
    assert "spindle stopped" in verdict.divergence.message
    assert verdict.divergence.cl is not None and verdict.divergence.cl.line == 12


# --- rs274 --------------------------------------------------------------------------------------


@needs_rs274
@pytest.mark.parametrize("machine", ["fanuc", "feeler", "linuxcnc"])
def test_rs274_stops_where_the_cl_stops(machine: str, tmp_path: Path) -> None:
    """rs274 reads the posted program and names its stops: at the CL's stops, in order."""
    lines = list(api.post_commands(api.load_post(machine), api.read_cl(STOPS),
                                   cl_file=STOPS.name, now=THESIS_TIME))
    # every line numbered by its index (a post's own N word replaced), '%' left bare
    numbered = [line.text if line.text.strip() == "%" else
                f"N{index} {re.sub(r'^N[0-9]+', '', line.text).strip()}"
                for index, line in enumerate(for_rs274_lines(machine, lines), start=1)]
    ngc, table = tmp_path / "p.ngc", tmp_path / "t.tbl"
    ngc.write_text("\n".join(numbered) + "\n", encoding="utf-8")
    table.write_text(TOOL_TABLE, encoding="utf-8")
    out = rs274_process(table, ngc).stdout
    found = re.findall(r"N(\d+)\s+(OPTIONAL_PROGRAM_STOP|PROGRAM_STOP)\(\)", out)
    cl_of = {index: line.cl_line for index, line in enumerate(lines, start=1)}
    assert [(name, cl_of[int(n)]) for n, name in found] == [
        ("OPTIONAL_PROGRAM_STOP", 10), ("PROGRAM_STOP", 17)]


def for_rs274_lines(machine: str, lines: list) -> list:
    """The posted lines as rs274 reads them: Fanuc's rewritten, LinuxCNC's as they are;
    their number stays (one rewritten line per posted line)."""
    if machine == "linuxcnc":
        return lines
    texts = for_rs274([line.text for line in lines])
    assert len(texts) == len(lines)
    return [line._replace(text=text) for line, text in zip(lines, texts, strict=True)]
