"""The derived parameter ``first_move``: true only while the first motion after a tool change posts.

Posts for controls with tool length offsets write that move differently (XY
first, then the offset with Z); the engine, not the post, knows which move it is.
"""

from __future__ import annotations

from postdsl import api
from postdsl.cl.model import PARAMETERS

POST = """\
postdsl: 1
machine: {name: test, tool_changer: false}   # the first moves come before any tool change
formats: {default: {decimals: 1}, int: {integer: true}}
output: {block_numbers: {default: false}}
commands:
  program_start: {blocks: []}
  program_end: {blocks: []}
  tool_change:
    blocks: [{items: ["T", {param: tool_number, format: int}]}]
  spindle_on:
    blocks: [{items: ["S", {text: " first", if: "first_move"}]}]
  rapid_move:
    blocks:
      - {if: "first_move", items: ["G0 XY first"]}
      - {if: "not first_move", items: ["G0"]}
  linear_move:
    blocks: [{items: ["G1", {text: " first", if: "first_move"}]}]
  single_peck:
    blocks: [{items: ["G81", {text: " first", if: "first_move"}]}]
  cycle_hole:
    blocks: [{items: ["HOLE", {text: " first", if: "first_move"}]}]
  cycle_end: {blocks: [{items: ["G80"]}]}
"""

CL = """\
{"cmd": "rapid_move", "x": 0, "y": 0, "z": 5}
{"cmd": "rapid_move", "z": 1}
{"cmd": "tool_change", "tool_number": 1}
{"cmd": "spindle_on", "spindle_speed": 100}
{"cmd": "rapid_move", "x": 1}
{"cmd": "linear_move", "x": 2, "feed": 10}
{"cmd": "tool_change", "tool_number": 2}
{"cmd": "linear_move", "x": 3, "feed": 10}
{"cmd": "tool_change", "tool_number": 3}
{"cmd": "spindle_on", "spindle_speed": 100}
{"cmd": "single_peck", "x": 1, "y": 1, "depth": 1, "feed": 10}
{"cmd": "cycle_hole", "x": 2}
{"cmd": "cycle_end"}
{"cmd": "rapid_move", "z": 9}
{"cmd": "program_end"}
"""


def test_first_move_after_each_tool_change() -> None:
    post = api.load_post_text(POST, "first.yaml")
    lines = [line.text for line in api.post_commands(post, api.read_cl_text(CL, "t.jsonl"))]
    assert lines == [
        "G0 XY first",  # the program's first move counts too
        "G0",
        "T1", "S", "G0 XY first", "G1",
        "T2", "G1 first",
        "T3", "S", "G81 first", "HOLE", "G80", "G0",
    ]


def test_first_move_is_a_documented_parameter() -> None:
    info = PARAMETERS["first_move"]
    assert info.source == "derived" and "tool change" in info.doc
