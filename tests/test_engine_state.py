"""Engine.in_state: the state a preview renders one command in, built by the engine."""

from __future__ import annotations

from postdsl.cl.model import LinearMove, RapidMove, SpindleOn, ToolChange
from postdsl.run.engine import Engine
from postdsl.run.program import ProgramSummary
from tests.test_engine import MOVES, NOW, make_post


def summary() -> ProgramSummary:
    return ProgramSummary(tools=[3], tool_records={3: ToolChange(tool_number=3,
                                                                  tool_diameter=6)},
                          machining_time=60.0, extents={})


def test_kept_values_come_from_the_commands_and_nothing_is_written() -> None:
    post = make_post(MOVES)
    engine = Engine.in_state(post, [RapidMove(x=1, y=2, z=3), LinearMove(x=4, feed=100)],
                             summary(), now=NOW)
    assert (engine.values["x"], engine.values["y"], engine.values["z"]) == (4, 2, 3)
    assert engine.values["feed"] == 100
    # nothing was written, so no register holds a word: the next move writes every word
    assert engine.registers == {}
    assert engine.number == post.numbering.start
    lines = [line.text for line in engine.post_command(LinearMove(x=4, feed=100))]
    assert lines == ["N10 G1 X4. Y2. Z3. F100"]


def test_commands_without_a_table_still_set_their_values() -> None:
    post = make_post(MOVES)  # no tool_change or spindle_on table
    engine = Engine.in_state(post, [ToolChange(tool_number=3, tool_diameter=6),
                                    SpindleOn(spindle_speed=2000, spindle="cw")],
                             summary(), now=NOW)
    assert engine.values["tool_number"] == 3
    assert engine.values["spindle_speed"] == 2000
    assert engine.values["spindle"] == "cw"
    assert engine.summary.tools == [3]
