"""work_offset: read from G-code and FreeCAD (G54-G59) and native CL, written in each
control's words or refused, and compared by verify at every cut like the tool."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from postdsl import api
from postdsl.check.controls import control_model
from postdsl.check.controls.base import ControlError
from postdsl.cl.model import WorkOffset
from postdsl.errors import CLError
from tests.conftest import ROOT, THESIS_TIME
from tests.test_rs274_oracle import TOOL_TABLE, needs_rs274, rs274_process

OFFSETS = ROOT / "examples" / "work_offsets.jsonl"
ROUTER = ROOT / "examples" / "work_offsets_router.jsonl"


def offsets(commands) -> list[tuple[int, int]]:
    return [(c.work_offset_index, c.line) for c in commands if isinstance(c, WorkOffset)]


@pytest.mark.parametrize("fmt", ["gcode", "freecad"])
def test_g54_to_g59_are_read_where_the_offset_changes(fmt: str) -> None:
    """G54 first is the CL's own default (no record); G55 twice is one change."""
    text = "G54\nG0 X0 Y0 Z5\nG55\nG0 X1\nG55\nG59\nG54\nM2\n"
    assert offsets(api.read_cl_text(text, "o.ngc", fmt)) == [(2, 3), (6, 6), (1, 7)]


#: what each post writes for the example's work offsets 2 (CL line 9), 8 (22), 1 (28)
WRITTEN = {
    "fanuc": (["G55"], ["G54.1 P2"], ["G54"]),
    "emco": (["G55"], ["G508"], ["G54"]),
    "linuxcnc": (["G55"], ["G59.2"], ["G54"]),
    "heidenhain": (["CYCL DEF 247 DATUM SETTING ~", "Q339=+2 ;DATUM NUMBER"],
                   ["CYCL DEF 247 DATUM SETTING ~", "Q339=+8 ;DATUM NUMBER"],
                   ["CYCL DEF 247 DATUM SETTING ~", "Q339=+1 ;DATUM NUMBER"]),
}


@pytest.mark.parametrize("machine", sorted(WRITTEN))
def test_each_post_writes_its_controls_offset_word(machine: str) -> None:
    lines = list(api.post_commands(api.load_post(machine), api.read_cl(OFFSETS),
                                   cl_file=OFFSETS.name, now=THESIS_TIME))

    def words(cl_line: int) -> list[str]:
        return [re.sub(r"^(N\d+|\d+)\s+", "", line.text).strip() for line in lines
                if line.cl_line == cl_line]

    assert (words(9), words(22), words(28)) == WRITTEN[machine]
    verdict = api.verify_commands(api.load_post(machine), api.read_cl(OFFSETS),
                                  cl_file=OFFSETS.name)
    assert verdict.divergence is None, verdict.divergence


def test_the_fanuc_tool_change_states_the_offset_in_force() -> None:
    lines = [line.text for line in api.post_commands(api.load_post("fanuc"),
                                                     api.read_cl(OFFSETS))]
    assert "N200 G55 G90 G17 G94" in lines  # T2 runs in G55, as the CL says


@pytest.mark.parametrize(("machine", "cl", "line", "reason"), [
    ("feeler", OFFSETS, 22, "G54.1 P (the additional workpiece coordinate systems option) "
                            "is not known to be on this machine"),
    ("grbl", OFFSETS, 22, "GRBL 1.1 has the work offsets G54-G59 (1-6) only"),
    ("vmc500", OFFSETS, 9, "knows no fixture-offset word of the Acramatic 2100"),
    ("hmcnc", ROUTER, 9, "hmCNC has no work offsets"),
])
def test_a_post_refuses_an_offset_its_control_lacks(machine: str, cl: Path, line: int,
                                                    reason: str) -> None:
    with pytest.raises(CLError) as caught:
        list(api.post_commands(api.load_post(machine), api.read_cl(cl), cl_file=cl.name))
    assert caught.value.location is not None and caught.value.location.line == line
    assert reason in caught.value.message


@pytest.mark.parametrize(("machine", "old", "new"), [
    ("fanuc", "53 + work_offset_index", "54 + work_offset_index"),
    ("linuxcnc", '"work_offset_index - 6", prefix: "G59."',
     '"work_offset_index - 5", prefix: "G59."'),
    ("heidenhain", 'value: "work_offset_index"', 'value: "work_offset_index + 1"'),
])
def test_verify_sees_a_wrong_offset_number(machine: str, old: str, new: str) -> None:
    """The offset's value is on the machine; its number is compared at every cut."""
    text = (ROOT / "machines" / f"{machine}.yaml").read_text(encoding="utf-8")
    assert old in text
    wrong = api.load_post_text(text.replace(old, new), f"{machine}.yaml")
    verdict = api.verify_commands(wrong, api.read_cl(OFFSETS), cl_file=OFFSETS.name)
    assert verdict.divergence is not None
    assert re.search(r"in work offset \d+, CL says \d+", verdict.divergence.message)


@pytest.mark.parametrize(("model", "text", "message"), [
    ("fanuc-0i", "G54.1 P49", "G54.1 needs P1 to P48"),
    ("fanuc-0i", "G55 G54.1 P1", "two work offsets in one block"),
    ("sinumerik-828d", "G58", "G58 is not a code"),
])
def test_the_models_refuse_what_their_control_does_not_read(model: str, text: str,
                                                           message: str) -> None:
    with pytest.raises(ControlError, match=re.escape(message)):
        list(control_model(model).replay(text.split("\n")))


@needs_rs274
def test_rs274_selects_the_offsets_of_the_linuxcnc_program(tmp_path: Path) -> None:
    lines = list(api.post_commands(api.load_post("linuxcnc"), api.read_cl(OFFSETS),
                                   cl_file=OFFSETS.name, now=THESIS_TIME))
    ngc, table = tmp_path / "p.ngc", tmp_path / "t.tbl"
    ngc.write_text("\n".join(f"N{i} {line.text}" for i, line in enumerate(lines, start=1))
                   + "\n", encoding="utf-8")
    table.write_text(TOOL_TABLE, encoding="utf-8")
    out = rs274_process(table, ngc).stdout
    # rs274 names the coordinate system it selects (1 = G54 ... 8 = G59.2)
    selected = [(int(system), lines[int(n) - 1].cl_line) for n, system in
                re.findall(r"N(\d+)\s+SET_G5X_OFFSET\((\d+),", out)]
    assert [s for s in selected if s[1] in (9, 22, 28)] == [(2, 9), (8, 22), (1, 28)]
