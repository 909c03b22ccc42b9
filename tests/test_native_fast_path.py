"""The native reader's fast path reads a record exactly as the full reading does, or not at all.

A record the fast path takes must give the command the full reading gives; every
other record (wrong, unusual, or with a key given twice) must be left to the full
reading, whose errors are pinned in tests/test_native.py.
"""

from __future__ import annotations

import json

from hypothesis import given
from hypothesis import strategies as st

from postdsl.cl.model import COMMANDS, command_fields
from postdsl.cl.native import _fast_record, record_to_command
from postdsl.errors import CLError, Location
from tests.conftest import EXAMPLES

NAMES = sorted(COMMANDS)
VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True), st.integers(-2**60, 2**60),
    st.booleans(), st.none(), st.text(max_size=6),
    st.sampled_from(["cw", "ccw", "xy", "zx", "yz", "flood", "mm", "drill"]),
    st.dictionaries(st.text(max_size=3), st.integers(), max_size=2),
)


def full_reading(text: str, number: int) -> object:
    try:
        return record_to_command(json.loads(text), Location("f", number))
    except CLError as exc:
        return exc.message


@st.composite
def records(draw: st.DrawFn) -> str:
    name = draw(st.sampled_from(NAMES))
    fields = [f.name for f in command_fields(COMMANDS[name])] + ["line", "bogus"]
    keys = draw(st.lists(st.sampled_from(fields), max_size=5))
    items = [f'"cmd": {json.dumps(name)}'] + [
        f"{json.dumps(key)}: {json.dumps(draw(VALUES))}" for key in keys]  # keys may repeat
    return "{" + ", ".join(items) + "}"


@given(records())
def test_a_record_the_fast_path_takes_reads_as_the_full_reading_reads_it(text: str) -> None:
    fast = _fast_record(text, 7)
    if fast is None:
        return
    full = full_reading(text, 7)
    assert fast == full and fast.line == 7, text  # type: ignore[union-attr]
    assert len(json.loads(text, object_pairs_hook=list)) == len(set(
        key for key, _ in json.loads(text, object_pairs_hook=list)))


def test_the_common_records_take_the_fast_path() -> None:
    for line in (EXAMPLES / "emco_drilling.jsonl").read_text(encoding="utf-8").splitlines():
        if line.startswith("{"):
            command = _fast_record(line, 3)
            assert command is not None, line
            assert command == full_reading(line, 3)
    assert _fast_record('{"cmd": "linear_move", "x": 1.5, "y": -2, "z": 0.25, "feed": 900}',
                        1) is not None


def test_unusual_or_wrong_records_are_left_to_the_full_reading() -> None:
    for text in ('{"cmd": "linear_move", "x": 1, "x": 2}',   # a key twice
                 '{"cmd": "linear_move", "x": NaN}',
                 '{"cmd": "linear_move", "x": Infinity}',
                 '{"cmd": "linear_move", "x": true}',
                 '{"cmd": "linear_move", "x": 9007199254740993}',
                 '{"cmd": "tool_change", "tool_number": 1.0}',
                 '{"cmd": "arc_move", "arc_direction": "left"}',
                 '{"cmd": "comment", "text": "\\u00e9"}',
                 '{"cmd": "linear_move", "x": 1} trailing',
                 '{"cmd": ["linear_move"]}',
                 '{"x": 1}',
                 '{"cmd": "custom_cycle", "cycle": "c", "params": {}}'):
        assert _fast_record(text, 1) is None, text
