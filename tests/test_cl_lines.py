"""Reading a CL file as a stream of bounded lines (postdsl/cl/lines.py)."""

from __future__ import annotations

import io

import pytest

from postdsl.cl.lines import MAX_LINE, SourceLines, binary_blocks, text_blocks
from postdsl.errors import CLError

BLOCK = 1 << 16


def lines_of(data: bytes) -> tuple[list[str], bool]:
    source = SourceLines(binary_blocks(io.BytesIO(data)), "f")
    lines = list(source)
    return lines, source.final_newline


@pytest.mark.parametrize("end", ["\n", "\r\n", "\r"])
def test_line_ends_split_between_two_blocks_count_once(end: str) -> None:
    first = "a" * (4 + BLOCK - 1)  # 4 bytes are read first, then a block: the CR ends it
    text = first + end + "b\n"
    assert lines_of(text.encode()) == ([first, "b"], True)
    assert list(SourceLines(text_blocks("x" * (BLOCK - 1) + end + "y"), "f")) == [
        "x" * (BLOCK - 1), "y"]


def test_the_last_line_end_is_remembered() -> None:
    assert lines_of(b"G0 X1\nG0 X30") == (["G0 X1", "G0 X30"], False)
    assert lines_of(b"G0 X1\nG0 X30\n") == (["G0 X1", "G0 X30"], True)
    assert lines_of(b"G0 X1\r") == (["G0 X1"], True)
    assert lines_of(b"") == ([], True)


def test_peeked_lines_are_still_read() -> None:
    source = SourceLines(text_blocks("1\n2\n3\n"), "f")
    assert source.peek(2) == ["1", "2"]
    assert list(source) == ["1", "2", "3"]


def test_a_line_at_the_bound_reads_and_one_beyond_is_refused() -> None:
    assert lines_of(b"x" * MAX_LINE + b"\n")[0] == ["x" * MAX_LINE]
    with pytest.raises(CLError) as caught:
        lines_of(b"ok\n" + b"x" * (MAX_LINE + 1))
    assert str(caught.value) == ("f:2: line 2 is longer than 1,000,000 characters: this is not "
                                 "a CL file, or a damaged one")


def test_a_nul_byte_is_located_in_its_line_and_column() -> None:
    with pytest.raises(CLError) as caught:
        lines_of(b"G0 X1\n" + b"y" * (BLOCK + 10) + b"\x00\n")
    assert (caught.value.location.line, caught.value.location.column) == (2, BLOCK + 11)


def test_a_bad_byte_in_a_later_block_names_its_line_and_column() -> None:
    with pytest.raises(CLError) as caught:
        lines_of(b"a\n" * 40000 + b"bc\xe9\n")
    assert str(caught.value) == "f:40001:3: not UTF-8 text (byte 0xe9 here); save the file as UTF-8"
