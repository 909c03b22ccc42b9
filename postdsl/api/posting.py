"""Posting CL commands in memory: the NC lines of a program, each with its origin.

What the editor, review and the tests call when the program fits in memory and the
caller wants the lines themselves (a file is streamed by :mod:`postdsl.api.files`).
It imports neither the control models nor tracing: posting needs neither.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Iterator
from datetime import UTC, datetime

from postdsl.cl.model import CLCommand
from postdsl.compile.compiler import CompiledPost
from postdsl.compile.runtime import NCLine
from postdsl.errors import CLError
from postdsl.run.engine import Engine
from postdsl.run.writer import join_lines


def posting_time() -> datetime:
    """Now, or ``SOURCE_DATE_EPOCH`` (UTC) when set, so posted programs are reproducible."""
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch:
        try:
            return datetime.fromtimestamp(int(epoch), tz=UTC)
        except (ValueError, OverflowError):
            raise CLError(f"SOURCE_DATE_EPOCH must be whole seconds, not '{epoch}'") from None
    return datetime.now().astimezone()


def post_commands(post: CompiledPost, commands: Iterable[CLCommand], *,
                  cl_file: str = "<cl>", now: datetime | None = None) -> list[NCLine]:
    """Post CL commands; every line with its origin.  Raises CLError on bad input."""
    engine = Engine(post, now=now or posting_time(), cl_file=cl_file)
    return list(engine.run(commands))


def iter_post(post: CompiledPost, commands: Iterable[CLCommand], *, cl_file: str = "<cl>",
              now: datetime | None = None) -> Iterator[NCLine]:
    """Post CL commands line by line, so a caller can stop early or report progress."""
    engine = Engine(post, now=now or posting_time(), cl_file=cl_file)
    return engine.run(commands)


def post_text(post: CompiledPost, lines: Iterable[NCLine]) -> str:
    """NC lines -> the program text with the post's line ending."""
    return join_lines((line.text for line in lines), post.line_ending, post.final_newline)


def without_block_number(post: CompiledPost, line: NCLine) -> str:
    """``line``'s text without its block-number word (``N120 G1 X5.`` -> ``G1 X5.``).

    A review compares programs on these keys, so a new start, increment or one
    more numbered block near the top shows up as renumbering, not as a change
    of every line.  Only lines the post numbered lose anything: the line's
    table block says whether it was numbered, so a comment that happens to
    start with ``N12`` keeps it.
    """
    table = (post.custom_cycles.get(line.table) if line.command == "custom_cycle"
             else post.commands.get(line.table))
    if table is None or not 0 <= line.block < len(table.blocks) \
            or not table.blocks[line.block].numbered:
        return line.text
    numbering = post.numbering
    text = line.text
    if not text.startswith(numbering.prefix):
        return text
    match = _BLOCK_NUMBER.match(text, len(numbering.prefix))
    if match is None or not text.startswith(numbering.suffix, match.end()):
        return text
    return text[match.end() + len(numbering.suffix):]


#: the number of a block-number word, however its format pads or points it
_BLOCK_NUMBER = re.compile(r" *[-+]?[0-9]+(?:\.[0-9]*)?")
