"""A first peck unlike the later ones (SolidWorks CAM's CYCLE/DEEP2 1STPECK/SUBPECK).

The CL carries it as ``first_peck``; a post writes it, expands the hole into moves
(each peck at its depth), or the hole is refused -- a table that writes one peck depth
never drills it at that depth throughout.
"""

from __future__ import annotations

import re

import pytest

from postdsl import api
from postdsl.cl.model import CycleEnd, CycleStart, DeepDrill, RapidMove, SpindleOn, ToolChange
from postdsl.errors import CLError
from tests.test_engine import MOVES, make_post, post

CYCLE = """
cycle_start: {blocks: []}
cycle_end: {blocks: []}
cycle_hole: {blocks: []}
"""
ONE_PECK = """
deep_drill:
  blocks: [{items: [" G83", {param: bottom, prefix: " Z", format: c},
                    {param: peck, prefix: " Q", format: c}]}]
"""
FIRST_AND_LATER = """
deep_drill:
  blocks: [{items: [" CYCLE83", {param: bottom, prefix: " Z", format: c},
                    {param: first_peck, prefix: " FDPR=", format: c},
                    {param: peck, prefix: " P=", format: c}]}]
"""


def hole(**values: float) -> list:
    return [RapidMove(x=0, y=0, z=10), CycleStart(),
            DeepDrill(x=0, y=0, top=0, depth=7, clearance=2, feed=50, line=3, **values),
            CycleEnd()]


def test_an_expanded_hole_drills_its_first_peck_then_the_later_ones() -> None:
    p = make_post(MOVES + CYCLE + "deep_drill: {expand: true}\n")
    lines = post(p, *hole(peck=2, first_peck=5))
    # down 5 to Z-5, back to the approach plane, to 1 mm above, then pecks of 2 to the bottom
    assert lines[1:] == ["N20 Z2.", "N30 G1 Z-5. F50", "N40 G0 Z2.", "N50 Z-4.",
                         "N60 G1 Z-7.", "N70 G0 Z2.", "N80 M30"]


def test_a_first_peck_equal_to_the_peck_changes_nothing() -> None:
    p = make_post(MOVES + CYCLE + "deep_drill: {expand: true}\n")
    assert post(p, *hole(peck=3, first_peck=3)) == post(p, *hole(peck=3))


def test_a_table_writing_one_peck_depth_refuses_a_different_first_peck() -> None:
    p = make_post(MOVES + CYCLE + ONE_PECK)
    assert post(p, *hole(peck=2))[1] == "N20 G83 Z-7. Q2."
    with pytest.raises(CLError) as caught:
        post(p, *hole(peck=2, first_peck=5))
    assert caught.value.location is not None and caught.value.location.line == 3
    assert caught.value.message == (
        "deep_drill: a first peck of 5 and later pecks of 2, but the post's table "
        "'deep_drill' writes one peck depth (not first_peck): the control would drill every "
        "peck at it (write first_peck, or expand the hole into moves: expand_if: "
        "\"first_peck != peck\")")


def test_a_table_writing_the_first_peck_posts_it_and_sees_the_peck_without_one() -> None:
    p = make_post(MOVES + CYCLE + FIRST_AND_LATER)
    assert post(p, *hole(peck=2, first_peck=5))[1] == "N20 CYCLE83 Z-7. FDPR=5. P=2."
    # omitted, the first peck is the peck: a post reads one value either way
    assert post(p, *hole(peck=2))[1] == "N20 CYCLE83 Z-7. FDPR=2. P=2."


@pytest.mark.parametrize(("values", "message"), [
    ({"peck": 2, "first_peck": -1}, "first peck -1 must not be negative"),
    ({"peck": 0, "first_peck": 4}, "a first peck of 4 needs the later pecks' depth"),
    ({"peck": 2, "first_peck": 0}, "first peck 0 must be greater than 0"),
])
def test_a_first_peck_no_machine_can_drill_is_refused(values: dict, message: str) -> None:
    p = make_post(MOVES + CYCLE + "deep_drill: {expand: true}\n")
    with pytest.raises(CLError) as caught:
        post(p, *hole(**values))
    assert message in caught.value.message


@pytest.mark.parametrize("machine", ["feeler", "fanuc", "vmc500", "emco", "linuxcnc"])
def test_no_bundled_post_drops_a_first_peck(machine: str) -> None:
    """The bundled posts' peck cycles write one peck depth: their ``expand_if`` drills such a
    hole as moves -- a feed to 5 below the top, then pecks of 2 to the bottom -- which
    ``postdsl verify`` finds right."""
    program = [ToolChange(tool_number=1, tool_diameter=6), SpindleOn(spindle_speed=1000),
               RapidMove(x=10, y=10, z=50),
               DeepDrill(x=10, y=10, top=0, depth=12, clearance=2, retract=2, peck=2,
                         first_peck=5, feed=100, line=7)]
    post_ = api.load_post(machine)
    lines = api.post_commands(post_, program)
    feeds = [line.text for line in lines if line.cl_line == 7 and line.command == "linear_move"]
    depths = [float(re.search(r"Z(-?[\d.]+)", text).group(1))  # type: ignore[union-attr]
              for text in feeds]
    assert depths == [-5, -7, -9, -11, -12]
    assert api.verify_commands(post_, program).ok
