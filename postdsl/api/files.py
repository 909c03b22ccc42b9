"""A CL file made into an NC file (or a verdict), streamed in two passes: what the
command line does with ``postdsl post`` and ``postdsl verify``.

Apart from in-memory posting because a file may be longer than memory: the first pass
sums the program up, the second writes each line as it is made, atomically, and a
refusal halfway leaves nothing written.
"""

from __future__ import annotations

import io
import sys
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any, BinaryIO, TextIO

from postdsl.api.loading import Options, load_post
from postdsl.api.posting import posting_time
from postdsl.api.verifying import _control_of, _post_verified
from postdsl.cl.model import CLCommand, PlainMove
from postdsl.cl.source import STDIN, CLSource
from postdsl.compile.compiler import CompiledPost, post_reads
from postdsl.errors import CLError, Location, VerifyError, printable
from postdsl.run.engine import Engine
from postdsl.run.program import MOVE_VALUES, ProgramSummary, summarize_source
from postdsl.run.writer import (
    UnsafeTarget,
    copy_spooled,
    open_atomic,
    spooled,
    write_atomic,
)

if TYPE_CHECKING:
    from postdsl.check.verify import Verdict


def post_file(machine: str | Path, cl_path: str | Path, output: str | Path | None = None,
              fmt: str | None = None, feed_units: str | None = None,
              verify: bool = True, options: Options | None = None,
              notice: Callable[[str], None] | None = None) -> str:
    """Post a CL file with a machine; write ``output`` atomically when given.  Returns the text.

    ``feed_units`` ("mm/min" or "mm/s") says what F means in FreeCAD G-code whose text
    does not tell (see the FreeCAD reader).  The program is verified as it is posted
    (see :func:`write_program`; ``verify=False`` does not): a divergence raises
    VerifyError and nothing is written.
    The text is held to be returned; :func:`write_program` posts a program of any length
    in flat memory.
    """
    collected = io.StringIO()
    write_program(machine, cl_path, output, fmt, feed_units, verify=verify,
                  copy_to=collected, options=options, notice=notice)
    return collected.getvalue()


#: what :func:`write_program` tells ``notice`` of a post it cannot verify
NO_CONTROL_MODEL = ("the post declares no machine/control and machine/resolution: the program "
                    "is posted without verifying it")


def write_program(machine: str | Path, cl_path: str | Path, output: str | Path | None = None,
                  fmt: str | None = None, feed_units: str | None = None, *,
                  verify: bool = True, progress: PassProgress | None = None,
                  stdout: BinaryIO | None = None, copy_to: TextIO | None = None,
                  options: Options | None = None,
                  notice: Callable[[str], None] | None = None) -> int:
    """Post a CL file as a stream, in two passes; returns the number of NC lines.

    The first pass reads the whole file for what headers need (tools, extents,
    time; the moves are folded only for a post that reads an extent or the time)
    and every reader check; the second posts and writes each line as it is
    made, into a temporary file renamed over ``output`` once the program is complete
    (:func:`postdsl.run.writer.open_atomic`), or, without ``output``, copied to
    ``stdout`` once complete: a CL error halfway leaves nothing written.  ``cl_path``
    ``-`` is standard input.  ``progress(pass_name, bytes_read, bytes_total)`` is told
    how far each pass has read (total None when the size is not known up front).
    ``copy_to`` receives the text as well (:func:`post_file` returns it).  ``options``
    are the post's option values (see :func:`load_post`).

    **Verified by default**: every line is replayed through the model of the
    machine's control as it is written, against the CL's own records (the ones the
    posting pass replays; never the engine's values), and a program that does not do
    what the CL says raises VerifyError naming the CL line and the NC line: nothing is
    written, neither ``output`` nor ``stdout`` (``copy_to`` may have received part of
    it).  ``verify=False`` posts without it.  A post without a control model
    (``machine.control`` and ``machine.resolution``) is posted unverified, and
    ``notice`` is told so (:data:`NO_CONTROL_MODEL`), once.
    """
    post = load_post(machine, options)
    if verify and (post.machine.control is None or post.machine.resolution is None):
        verify = False
        if notice is not None:
            notice(NO_CONTROL_MODEL)
    keep = ((_input_file(cl_path), "the CL program being posted"), (post.file, "the post"))
    with CLSource(cl_path, fmt, feed_units) as source:
        summary = summarize_source(source, post.machine.rapid_rate,
                                   _pass(progress, "reading", source.size),
                                   moves=_reads_move_values(post),
                                   kinematics=post.machine.kinematics)
        records = source.records(_pass(progress, "posting", source.size))
        engine = Engine(post, now=posting_time(), cl_file=source.name)
        if output is None:
            with spooled() as stream:
                count = _write_lines(post, engine, records, summary, stream, copy_to,
                                     source.name if verify else None)
                if stdout is not None:
                    copy_spooled(stream, stdout)
                    stdout.flush()
            return count
        try:
            with open_atomic(output, keep) as stream:
                return _write_lines(post, engine, records, summary, stream, copy_to,
                                    source.name if verify else None)
        except UnsafeTarget as exc:
            raise CLError(f"cannot write the NC program: {exc.message}",
                          Location(str(output))) from None
        except OSError as exc:
            raise _unwritable(output, exc, "the NC program") from None


def verify_file(machine: str | Path, cl_path: str | Path, fmt: str | None = None,
                feed_units: str | None = None, options: Options | None = None,
                progress: PassProgress | None = None) -> Verdict:
    """Verify a CL file with a machine; raises VerifyError at the first divergence.

    Streams as :func:`write_program` does, and compares as it does: a first pass for the
    program summary, then the posted lines replayed and compared with the records the
    first pass kept, in step.
    """
    post = load_post(machine, options)
    _control_of(post)
    with CLSource(cl_path, fmt, feed_units) as source:
        summary = summarize_source(source, post.machine.rapid_rate,
                                   _pass(progress, "reading", source.size),
                                   moves=_reads_move_values(post),
                                   kinematics=post.machine.kinematics)
        engine = Engine(post, now=posting_time(), cl_file=source.name)
        records = source.records(_pass(progress, "verifying", source.size))
        verdict = _post_verified(post, engine, records, summary, source.name,
                                 lambda batch: None)
    if verdict.divergence is not None:
        raise VerifyError(str(verdict.divergence))
    return verdict


def _reads_move_values(post: CompiledPost) -> bool:
    """Whether ``post`` may read a summary value only the moves give (an extent, the
    machining time): else its first pass leaves the moves out (see
    :func:`~postdsl.run.program.summarize_source`)."""
    reads = post_reads(post)
    return reads is None or not reads.isdisjoint(MOVE_VALUES)


#: a progress callback: (pass name, bytes read, bytes in the file or None)
PassProgress = Callable[[str, int, "int | None"], None]


def _pass(progress: PassProgress | None, name: str,
          total: int | None) -> Callable[[int], None] | None:
    if progress is None:
        return None
    return lambda done: progress(name, done, total)


def _write_lines(post: CompiledPost, engine: Engine,
                 records: Iterable[CLCommand | PlainMove], summary: ProgramSummary,
                 stream: TextIO, copy_to: TextIO | None, verify_file: str | None) -> int:
    """Post ``records`` into ``stream`` a batch at a time, joined as :func:`post_text` joins.

    With ``verify_file`` (the CL file's name) the lines are replayed through the
    control model as they are written (:func:`_verified_batches`); a divergence raises
    VerifyError (and the caller's atomic output is then not written).
    """
    ending = post.line_ending
    write = stream.write if copy_to is None else _tee(stream.write, copy_to.write)
    count = 0
    last = ""

    def put(batch: list[str]) -> None:  # one write per thousand lines, not one per line
        nonlocal count, last
        write(ending.join(batch) if count == 0 else ending + ending.join(batch))
        count += len(batch)
        last = batch[-1]

    if verify_file is None:
        for batch in engine.texts(records, summary):
            put(batch)
    else:
        verdict = _post_verified(post, engine, records, summary, verify_file, put)
        if verdict.divergence is not None:
            raise VerifyError(str(verdict.divergence))
    if post.final_newline and (count > 1 or last):
        write(ending)
    return count


def _tee(first: Callable[[str], Any], second: Callable[[str], Any]) -> Callable[[str], None]:
    def write(text: str) -> None:
        first(text)
        second(text)
    return write


def _input_file(cl_path: str | Path) -> str | Path | int:
    """The CL file as :func:`~postdsl.run.writer.open_atomic` compares it with the target:
    ``-`` is standard input, by its descriptor (redirected from a file, that file)."""
    if str(cl_path) != STDIN:
        return cl_path
    try:
        return sys.stdin.fileno()
    except (AttributeError, ValueError, OSError):  # no standard input, or not a file
        return cl_path


def _write_output(output: str | Path, text: str, what: str,
                  keep: Iterable[tuple[str | Path | int, str]]) -> None:
    """Write a result atomically; every refusal a CLError naming ``output`` and saying why."""
    try:
        write_atomic(output, text, keep=keep)
    except UnsafeTarget as exc:
        raise CLError(f"cannot write {what}: {exc.message}", Location(str(output))) from None
    except OSError as exc:
        raise _unwritable(output, exc, what) from None


def _unwritable(output: str | Path, exc: OSError, what: str) -> CLError:
    """Why ``output`` cannot be written, in terms of the path the user gave.

    The OS names the temporary file the program is written through.
    """
    folder = Path(output).parent
    reason = (f"the folder {printable(str(folder))} does not exist"
              if not folder.exists() else
              f"{printable(str(folder))} is not a folder" if not folder.is_dir() else
              exc.strerror or str(exc))
    return CLError(f"cannot write {what}: {reason}", Location(str(output)))
