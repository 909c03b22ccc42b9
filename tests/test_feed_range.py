"""The feed range every bundled machine declares: a feed outside it is refused like travel."""

from __future__ import annotations

import pytest

from postdsl import api
from postdsl.errors import PostError

PROGRAM = ('{"cmd": "tool_change", "tool_number": 1}\n'
           '{"cmd": "spindle_on", "spindle_speed": 1000}\n'
           '{"cmd": "rapid_move", "x": 0, "y": 0, "z": 5}\n'
           '{"cmd": "linear_move", "z": 0, "feed": FEED}\n'
           '{"cmd": "program_end"}\n')


def post(machine: str, feed: float) -> str:
    loaded = api.load_post(machine)
    commands = api.read_cl_text(PROGRAM.replace("FEED", repr(feed)), "f.jsonl")
    return api.post_text(loaded, api.post_commands(loaded, commands, cl_file="f.jsonl"))


@pytest.mark.parametrize(("machine", "low", "high", "name"), [
    ("feeler", 1, 10000, "Feeler VMP-45A"), ("emco", 1, 3000, "EMCO Concept Mill 105"),
    ("vmc500", 1, 10000, "VMC 500")])
def test_each_bundled_machine_refuses_a_feed_outside_its_range(machine: str, low: float,
                                                              high: float, name: str) -> None:
    post(machine, low)
    post(machine, high)
    with pytest.raises(api.CLError) as caught:
        post(machine, low / 2)
    assert str(caught.value) == (f"f.jsonl:4: feed {low / 2:g} mm/min is below the minimum "
                                 f"feed of {name} ({low} mm/min)")
    with pytest.raises(api.CLError) as caught:
        post(machine, high * 2)
    assert str(caught.value) == (f"f.jsonl:4: feed {high * 2} mm/min exceeds the maximum "
                                 f"feed of {name} ({high} mm/min)")


def test_a_minimum_feed_above_the_maximum_is_a_located_post_error() -> None:
    text = ("postdsl: 1\nmachine: {name: M, min_feed: 500, max_feed: 100}\n"
            "commands: {program_start: {blocks: []}, program_end: {blocks: []}}\n")
    with pytest.raises(PostError) as caught:
        api.load_post_text(text, "m.yaml")
    assert "machine/min_feed: the minimum 500 is above the maximum 100" in caught.value.report()
