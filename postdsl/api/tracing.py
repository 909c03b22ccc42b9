"""Tracing: which CL record, table and item wrote an NC line or a word
(``postdsl explain``, the editor's cell trace and word lookup).

Apart from posting because tracing runs the traced flavour of the generated code
(:mod:`postdsl.run.trace`), which ``postdsl post`` never loads.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from datetime import datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

from postdsl.api.loading import Options, _model, load_post
from postdsl.api.posting import post_commands, posting_time
from postdsl.cl.model import CLCommand
from postdsl.cl.readers import read_cl
from postdsl.compile.compiler import CompiledPost
from postdsl.errors import CLError, Location
from postdsl.lang.post import Post

if TYPE_CHECKING:
    from postdsl.run.trace import TracedLine, WordMeaning, WordWriter


def trace_line(post: CompiledPost, commands: Iterable[CLCommand], number: int, *,
               cl_file: str = "<cl>", now: datetime | None = None) -> TracedLine | None:
    """NC line ``number`` (1-based) of the program ``commands`` posts, with the CL record,
    table, block and item that wrote each of its words, the conditions that fired and the
    registers after it; None when the program is shorter.  Posts up to that line only."""
    if number < 1:
        return None
    from postdsl.run.trace import trace_lines  # tracing only, not posting

    return next(trace_lines(post, commands, now=now or posting_time(), cl_file=cl_file,
                            wanted=number), None)


def explain_text(post: CompiledPost, traced: TracedLine, cl_file: str = "<cl>") -> list[str]:
    """A traced line in words, as ``postdsl explain`` prints it."""
    from postdsl.run.trace import explain  # tracing only, not posting

    return explain(traced, post.source.model, cl_file)


def explain_line(machine: str | Path, cl_path: str | Path, number: int,
                 fmt: str | None = None, options: Options | None = None) -> list[str]:
    """``postdsl explain``: where NC line ``number`` of a posted CL file comes from."""
    post = load_post(machine, options)
    commands = list(read_cl(cl_path, fmt))
    traced = trace_line(post, commands, number, cl_file=str(cl_path))
    if traced is None:
        count = len(post_commands(post, commands, cl_file=str(cl_path)))
        raise CLError(f"the program has {count} NC line{'s' if count != 1 else ''}, "
                      f"no line {number}", Location(str(cl_path)))
    return explain_text(post, traced, str(cl_path))


def word_writers(post: Post | Mapping[str, Any], word: str) -> list[WordWriter]:
    """Every item of the post (its model, or a document) whose fixed text or prefix writes
    ``word``, as a whole NC word."""
    from postdsl.run.trace import word_writers as _word_writers  # the editor's and preview's

    return _word_writers(_model(post), word)


def word_meaning(post: Post | Mapping[str, Any], word: str) -> WordMeaning | None:
    """The table of the post (its model, or a document) for what ``word`` means on ISO
    controls (``G83``: deep drilling, which another control's post writes as a cycle
    call), when the post does not write the word itself; None otherwise."""
    from postdsl.run.trace import word_meaning as _word_meaning  # preview and palette only

    return _word_meaning(_model(post), word)
