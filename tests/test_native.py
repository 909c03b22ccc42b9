"""The native CL format: JSON Lines records checked against the CL vocabulary."""

from __future__ import annotations

import json

import jsonschema
import pytest

from postdsl.cl.model import COMMANDS, DeepDrill, ProgramEnd, RapidMove
from postdsl.cl.native import command_to_record, read_native, write_native
from postdsl.cl.readers import read_cl, read_cl_text
from postdsl.cl.schema import render_reference, render_schema
from postdsl.errors import CLError
from tests.conftest import EXAMPLES, ROOT


def read(text: str) -> list:
    """The commands of a native text, which is given the program_end a whole file ends
    with (and which is not returned)."""
    commands = list(read_native((text + '\n{"cmd": "program_end"}').splitlines(),
                                "prog.jsonl"))
    assert commands.pop() == ProgramEnd()
    return commands


def test_records_become_typed_commands_with_their_line() -> None:
    commands = read('# a comment\n\n{"cmd": "rapid_move", "x": 1, "z": 2.5}\n'
                    '{"cmd": "deep_drill", "x": 1, "y": 2, "top": 0, "depth": 5, "peck": 2}\n')
    assert commands == [RapidMove(x=1, z=2.5), DeepDrill(x=1, y=2, top=0, depth=5, peck=2)]
    assert [c.line for c in commands] == [3, 4]


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ('{"cmd": "rapid_move", "x": 1',
         "prog.jsonl:1:29: not a JSON record (Expecting ',' delimiter)"),
        ('["rapid_move"]', "prog.jsonl:1: a CL record must be a JSON object"),
        ('{"x": 1}', "prog.jsonl:1: the record has no \"cmd\""),
        ('{"cmd": "rapid_mvoe"}', "prog.jsonl:1: unknown CL command 'rapid_mvoe' "
                                  "(did you mean 'rapid_move'?)"),
        ('{"cmd": "rapid_move", "f": 1}', "prog.jsonl:1: rapid_move has no field 'f'"),
        ('{"cmd": "rapid_move", "x": "1"}', "prog.jsonl:1: rapid_move: 'x' must be a number"),
        ('{"cmd": "rapid_move", "x": true}', "prog.jsonl:1: rapid_move: 'x' must be a number"),
        ('{"cmd": "tool_change", "tool_number": 1.5}', "must be a whole number"),
        ('{"cmd": "spindle_on", "spindle": "left"}', "'spindle' must be one of cw, ccw"),
        ('{"cmd": "tool_change", "tool_number": null}', "'tool_number' must not be null"),
        ('{"cmd": "custom_cycle", "params": {"a": [1]}}', "'params.a' must be a number or text"),
    ],
)
def test_malformed_records_are_located_errors(line: str, message: str) -> None:
    with pytest.raises(CLError) as info:
        read(line)
    assert message in str(info.value)


def test_errors_name_the_right_line() -> None:
    with pytest.raises(CLError) as info:
        read('{"cmd": "rapid_move"}\n\n{"cmd": "nope"}\n')
    assert str(info.value).startswith("prog.jsonl:3: unknown CL command 'nope'")


def test_write_then_read_round_trips_every_command_example() -> None:
    commands = [COMMANDS[name](**{k: v for k, v in cls.example.items() if k != "cmd"})
                for name, cls in COMMANDS.items() if name != "program_end"]
    again = read("".join(write_native(commands)))
    assert again == commands


def test_a_whole_program_ends_with_program_end() -> None:
    """Cut between two lines, JSON Lines is still valid: only program_end proves the end."""
    with pytest.raises(CLError) as info:
        list(read_native(['{"cmd": "rapid_move", "x": 1}', "", "# note"], "cut.jsonl"))
    assert str(info.value).startswith("cut.jsonl:1: the CL file ends without a program_end "
                                      "record")
    with pytest.raises(CLError) as info:
        list(read_native(['{"cmd": "program_end"}', '{"cmd": "rapid_move"}'], "late.jsonl"))
    assert str(info.value).startswith("late.jsonl:2: a record after program_end (line 1)")


@pytest.mark.parametrize("field", ["x", "tool_number", "feed", "dwell", "spindle_speed"])
def test_a_number_of_309_digits_is_refused_not_a_crash(field: str) -> None:
    record = f'{{"cmd": "rapid_move", "{field}": 1{"0" * 320}}}'
    with pytest.raises(CLError, match=f"'{field}' is too large a number \\(321 digits\\)"):
        list(read_native([record.replace("rapid_move", _COMMAND_OF[field])], "big.jsonl"))


_COMMAND_OF = {"x": "rapid_move", "tool_number": "tool_change", "feed": "linear_move",
               "dwell": "dwell", "spindle_speed": "spindle_on"}


def test_the_committed_schema_and_reference_are_generated_from_the_model() -> None:
    committed = (ROOT / "schemas" / "cl.schema.json").read_text(encoding="utf-8")
    assert committed == render_schema(), "run: python -m postdsl.cl.schema"
    reference = (ROOT / "docs" / "cl-format.md").read_text(encoding="utf-8")
    assert reference == render_reference(), "run: python -m postdsl.cl.schema"
    for name in COMMANDS:
        assert f"### `{name}`" in reference


def test_every_example_record_and_every_native_example_file_validates_against_the_schema(
) -> None:
    schema = json.loads(render_schema())
    validator = jsonschema.Draft202012Validator(schema)
    for cls in COMMANDS.values():
        validator.validate(cls.example)
    for path in sorted(EXAMPLES.glob("*.jsonl")):
        for command in read_cl_text(path.read_text(encoding="utf-8"), str(path), "native"):
            validator.validate(command_to_record(command))


def test_the_schema_rejects_what_the_reader_rejects() -> None:
    validator = jsonschema.Draft202012Validator(json.loads(render_schema()))
    for bad in ({"cmd": "rapid_move", "f": 1}, {"cmd": "spindle_on", "spindle": "left"},
                {"cmd": "tool_change", "tool_number": 1.5}, {"cmd": "nope"}):
        assert not validator.is_valid(bad)
        with pytest.raises(CLError):
            read(json.dumps(bad))


# --- hostile input: whatever the file holds, a located error, never a traceback -------------


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ('{"cmd": "comment", "comment": ' + "[" * 100_000 + "]" * 100_000 + "}",
         "prog.jsonl:1: not a JSON record (nested too deeply)"),
        ('{"cmd": "tool_change", "tool_number": ' + "9" * 5000 + "}",
         "prog.jsonl:1: not a JSON record (a number of more than 4300 digits)"),
        ('{"cmd": "comment", "comment": "\\ud800"}',
         "prog.jsonl:1: comment: 'comment' is not valid Unicode text (a lone surrogate \\ud800)"),
        ('{"cmd": "custom_cycle", "cycle": "p", "params": {"a": "\\udc00"}}',
         "prog.jsonl:1: custom_cycle: 'params.a' is not valid Unicode text"),
    ],
)
def test_hostile_records_are_located_errors(line: str, message: str) -> None:
    with pytest.raises(CLError) as info:
        read(line)
    assert str(info.value).startswith(message)


def test_a_utf8_byte_order_mark_is_accepted(tmp_path) -> None:
    """Windows editors write one; it is not part of the first record."""
    end = '{"cmd": "program_end"}\n'
    assert read_cl_text('\ufeff{"cmd": "rapid_move", "x": 1}\n' + end) == [RapidMove(x=1),
                                                                           ProgramEnd()]
    path = tmp_path / "bom.jsonl"
    path.write_bytes(b'\xef\xbb\xbf{"cmd": "rapid_move", "x": 1}\r\n{"cmd": "rapid_move"}\r\n'
                     + end.encode())
    assert read_cl(path) == [RapidMove(x=1), RapidMove(), ProgramEnd()]


def test_utf16_and_utf32_with_a_byte_order_mark_are_read(tmp_path) -> None:
    """PowerShell's '>' writes UTF-16: the byte order mark says so unambiguously."""
    text = '# ž\n{"cmd": "rapid_move", "x": 1}\n{"cmd": "program_end"}\n'
    for encoding in ("utf-16", "utf-32"):
        path = tmp_path / f"{encoding}.jsonl"
        path.write_bytes(text.encode(encoding))
        assert read_cl(path) == [RapidMove(x=1), ProgramEnd()]


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (b'{"cmd": "rapid_move"}\n{"cmd": "comment", "comment": "caf\xe9"}\n',
         "bad.jsonl:2:35: not UTF-8 text (byte 0xe9 here)"),
        ('{"cmd": "rapid_move"}\n'.encode("utf-16-le"), "bad.jsonl:1:2: the file contains a NUL"),
        # the first bad byte is the NUL that starts it (the file is read in order)
        (bytes(range(256)), "bad.jsonl:1:1: the file contains a NUL byte"),
        (b'{"cmd": "rapid_move"}\n' + bytes(range(1, 256)),
         "bad.jsonl:4:115: not UTF-8 text (byte 0x80 here)"),  # LF and CR end lines 2 and 3
    ],
)
def test_a_file_that_is_not_text_names_the_line_and_column(tmp_path, data: bytes,
                                                           message: str) -> None:
    path = tmp_path / "bad.jsonl"
    path.write_bytes(data)
    with pytest.raises(CLError) as info:
        read_cl(path)
    assert str(info.value).startswith(str(tmp_path / message))


def test_a_field_given_twice_is_refused() -> None:
    """json.loads keeps the last of two "x": the CAM system wrote one of them by mistake."""
    with pytest.raises(CLError) as info:
        read('{"cmd": "rapid_move", "x": 1, "y": 0, "x": 2}')
    assert str(info.value) == "prog.jsonl:1: the record gives 'x' twice"
    with pytest.raises(CLError, match="the record gives 'a' twice"):
        read('{"cmd": "custom_cycle", "cycle": "p", "params": {"a": 1, "a": 2}}')


def test_lines_are_counted_as_editors_count_them() -> None:
    """Only LF, CRLF and CR end a line: a raw U+2028 or U+0085 inside a JSON string (valid
    JSON) must neither split a record nor shift the line numbers of later errors."""
    text = ('{"cmd": "comment", "comment": "a\u2028b"}\n{"cmd": "comment", "comment": "c\x85d"}'
            '\r\n{"cmd": "nope"}\n')
    with pytest.raises(CLError) as info:
        read_cl_text(text, "prog.jsonl")
    assert str(info.value).startswith("prog.jsonl:3: unknown CL command 'nope'")
