"""Facts of the input a post may read (issue 12): G90/G91, G17-G19, G98/G99, G80.

The readers carry them as CL values; the CL itself does not depend on them, so a post
that ignores them posts the same program, and one that wants them tests them in
conditions.
"""

from __future__ import annotations

import pytest

from postdsl import api
from tests.test_engine import MOVES, make_post, post

GCODE = """\
(Exported by FreeCAD)
G90
G17
M6 T1
M3 S1000
G0 X0 Y0 Z20
G99
G81 X1 Y1 Z-5 R2 F100
G81 X2 Y2
G83 X3 Y3 Z-5 R2 Q1 F100
G80
G0 Z20
M2
"""

FACTS = """
cycle_start: {blocks: []}
cycle_hole: {blocks: [{items: [{param: x, prefix: " X", format: c}]}]}
tool_change: {reset: [feed, x, y, z], blocks: []}
comment: {blocks: []}
spindle_on: {blocks: []}
input_modes:
  blocks:
    - items: [{text: " G90", if: "'distance_mode' in given and distance_mode == 'absolute'"},
              {text: " G17", if: "'active_plane' in given and active_plane == 'xy'"},
              {text: " G99", if: "'cycle_return' in given and cycle_return == 'r_plane'"}]
single_peck:
  blocks: [{items: [" G81", {text: " G99", if: "cycle_return == 'r_plane'"},
                    {param: x, prefix: " X", format: c}]}]
deep_drill:
  blocks: [{items: [" G83", {text: " G99", if: "cycle_return == 'r_plane'"},
                    {param: first_peck, prefix: " Q", format: c}]}]
cycle_end:
  blocks: [{items: [{text: " G80", if: "ended_by == 'cancel'"},
                    {text: " (next cycle)", if: "ended_by == 'next_cycle'"}]}]
"""


def test_a_post_reads_the_facts_of_freecad_gcode_in_conditions() -> None:
    commands = api.read_cl_text(GCODE, "job.nc")
    lines = post(make_post(MOVES + FACTS), *commands)
    # a record gives the mode its line set: each word where the input wrote it
    assert lines == ["N10 G90", "N20 G17", "N30 G0 X0. Y0. Z20.", "N40 G99",
                     "N50 G81 G99 X1.", "N60 X2.", "N70 (next cycle)", "N80 G83 G99 Q1.",
                     "N90 G80", "N100 G0 X3. Y3. Z20.", "N110 M30"]


def test_a_post_without_a_table_for_the_facts_writes_nothing_for_them() -> None:
    start, rest = FACTS.split("input_modes:")
    without = make_post(MOVES + start + "single_peck:" + rest.split("single_peck:")[1])
    assert "input_modes" not in without.commands
    lines = post(without, *api.read_cl_text(GCODE, "job.nc"))
    assert lines[:2] == ["N10 G0 X0. Y0. Z20.", "N20 G81 G99 X1."]


def test_native_cl_carries_the_facts_and_a_cycle_end_is_a_cancel_unless_it_says_otherwise(
) -> None:
    from postdsl.cl.model import CycleEnd, InputModes, SinglePeck

    text = "\n".join([
        '{"cmd": "input_modes", "distance_mode": "incremental", "active_plane": "zx"}',
        '{"cmd": "single_peck", "x": 1, "y": 1, "top": 0, "depth": 5, "cycle_return": '
        '"initial", "feed": 100}',
        '{"cmd": "cycle_end", "ended_by": "next_cycle"}',
        '{"cmd": "cycle_end"}',
        '{"cmd": "program_end"}', ""])
    modes, hole, ended, cancelled, _end = api.read_cl_text(text, "facts.jsonl", "native")
    assert modes == InputModes(distance_mode="incremental", active_plane="zx")
    assert isinstance(hole, SinglePeck) and hole.cycle_return == "initial"
    assert (ended, cancelled) == (CycleEnd(ended_by="next_cycle"), CycleEnd(ended_by="cancel"))
    bad = text.replace('"next_cycle"', '"G80"')
    with pytest.raises(api.CLError) as caught:
        api.read_cl_text(bad, "facts.jsonl", "native")
    assert caught.value.location is not None and caught.value.location.line == 3
