"""``expand_if:``: a drilling table that writes its cycle, except for the setups it cannot.

A canned cycle with one peck depth cannot drill a CAM's unequal pecks; one that leaves
the tool at R cannot reach a higher retract plane.  The table's condition decides, per
drilling setup, whether its holes are written as moves instead (the engine's
``expand: true`` path), and ``postdsl verify`` expects moves exactly where the engine
wrote them.
"""

from __future__ import annotations

import re

import pytest

from postdsl import api
from postdsl.cl.model import (
    CycleEnd,
    CycleHole,
    CycleStart,
    DeepDrill,
    RapidMove,
    SpindleOn,
    ToolChange,
)
from postdsl.errors import PostError
from tests.conftest import ROOT, THESIS_TIME
from tests.test_engine import MOVES, make_post, post

CYCLE = """
cycle_start: {blocks: []}
cycle_end: {blocks: []}
cycle_hole:
  blocks: [{items: [{param: x, prefix: " X", format: c}]}]
"""
ONE_PECK = """
deep_drill:
  expand_if: "first_peck != peck"
  reject:
    - {if: "dwell > 0", message: "G83 has no dwell"}
  blocks: [{items: [" G83", {param: bottom, prefix: " Z", format: c},
                    {param: peck, prefix: " Q", format: c}]}]
"""
DWELL = """
dwell:
  blocks: [{items: [" G4", {param: dwell, prefix: " P", format: c}]}]
"""


def holes(**values: float) -> list:
    return [RapidMove(x=0, y=0, z=10), CycleStart(),
            DeepDrill(x=0, y=0, top=0, depth=7, clearance=2, feed=50, line=3, **values),
            CycleHole(x=5, y=0, line=4), CycleEnd()]


def test_the_cycle_is_written_while_the_condition_is_false() -> None:
    lines = post(make_post(MOVES + CYCLE + ONE_PECK), *holes(peck=2))
    assert lines[1:3] == ["N20 G83 Z-7. Q2.", "N30 X5."]


def test_the_setup_and_its_holes_are_moves_when_it_holds() -> None:
    lines = post(make_post(MOVES + CYCLE + ONE_PECK), *holes(peck=2, first_peck=5))
    # each hole: down to R, 5 to Z-5, back to R, to 1 mm above, a peck of 2 to the bottom
    assert lines == ["N10 G0 X0. Y0. Z10.", "N20 Z2.", "N30 G1 Z-5. F50", "N40 G0 Z2.",
                     "N50 Z-4.", "N60 G1 Z-7.", "N70 G0 Z2.",
                     "N80 X5.", "N90 G1 Z-5.", "N100 G0 Z2.", "N110 Z-4.", "N120 G1 Z-7.",
                     "N130 G0 Z2.", "N140 M30"]


def test_the_rules_of_the_unwritten_cycle_do_not_apply_to_the_moves() -> None:
    """G83 cannot dwell, so the table refuses a dwell -- but moves can: G4 at the bottom."""
    p = make_post(MOVES + CYCLE + ONE_PECK + DWELL)
    with pytest.raises(api.CLError, match="G83 has no dwell"):
        post(p, *holes(peck=2, dwell=0.5))
    lines = post(p, *holes(peck=2, first_peck=5, dwell=0.5))
    assert lines[5:8] == ["N60 G1 Z-7.", "N70 G4 P0.5", "N80 G0 Z2."]


def test_the_decision_is_made_per_setup() -> None:
    p = make_post(MOVES + CYCLE + ONE_PECK)
    program = holes(peck=2, first_peck=5)[:-1] + holes(peck=2)[1:]
    lines = post(p, *program)
    assert sum("G83" in line for line in lines) == 1


@pytest.mark.parametrize(("table", "message"), [
    ('tapping:\n  expand_if: "true"\n  blocks: [{items: [" G84"]}]\n',
     "tapping cannot be expanded into moves"),
    ('deep_drill:\n  expand: true\n  expand_if: "peck > 0"\n', "should not be valid"),
    ('linear_move:\n  expand_if: "true"\n  blocks: [{items: [" G1"]}]\n',
     "expand_if applies to drilling setups only"),
    ('deep_drill:\n  expand_if: "peck > nonsense"\n  blocks: [{items: [" G83"]}]\n',
     "nonsense"),
])
def test_a_misplaced_expand_if_is_refused_at_its_key(table: str, message: str) -> None:
    commands = MOVES + CYCLE + table if not table.startswith("linear_move") else \
        MOVES.split("linear_move:")[0] + CYCLE + table
    with pytest.raises(PostError) as caught:
        make_post(commands)
    assert message in str(caught.value)


def test_verify_expects_moves_exactly_where_the_engine_wrote_them() -> None:
    """The Feeler drills equal pecks with G83 and unequal ones as moves, in one program."""
    feeler = api.load_post("feeler")
    program = [ToolChange(tool_number=1, line=1),
               SpindleOn(spindle_speed=1000, line=2),
               RapidMove(x=0, y=0, z=10, line=3), CycleStart(line=4),
               DeepDrill(x=0, y=0, top=0, depth=7, clearance=2, feed=50, peck=2,
                         first_peck=5, line=5),
               CycleHole(x=5, y=0, line=6), CycleEnd(line=7), CycleStart(line=8),
               DeepDrill(x=10, y=0, top=0, depth=7, clearance=2, feed=50, peck=2, line=9),
               CycleHole(x=15, y=0, line=10), CycleEnd(line=11)]
    written: list = []
    verdict = api.verify_commands(feeler, program, now=THESIS_TIME, written=written)
    assert verdict.ok, str(verdict.divergence)
    assert sum(" G83" in line.text for line in written) == 1
    assert verdict.holes == 2  # the cycle's two holes; the expanded ones are feed moves
    assert verdict.cuts == 2 * 2 + 2


def test_the_readme_example_is_the_feelers_table() -> None:
    readme = (ROOT / "docs" / "reference" / "post-language.md").read_text(encoding="utf-8")
    start = readme.index("**Holes as moves when the cycle cannot write them.**")
    example = re.search(r'expand_if: "([^"]+)"', readme[start:])
    assert example is not None
    feeler = (ROOT / "machines" / "feeler.yaml").read_text(encoding="utf-8")
    deep_drill = feeler[feeler.index("\n  deep_drill:"):feeler.index("\n  break_chip:")]
    assert f'expand_if: "{example.group(1)}"' in deep_drill
