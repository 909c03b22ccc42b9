"""Posting a long sample program in another process, line chunks streamed back.

A thread cannot do it: posting is pure Python, and while a thread posts, the UI
thread waits for the interpreter lock at every turn of its event loop — keys
took 300 ms and more with a 200 000-line program.  A child process posts on the
other core; the UI only receives finished lines, a chunk at a time, so the
program grows on screen while it is posted.

The child (``tui.posting.main`` in a new interpreter) is given the post's YAML text and the
sample's path on its stdin (a compiled post holds closures, which cannot be
sent), compiles and reads them itself, and writes pickled chunks to its stdout.
It is a plain subprocess, not ``multiprocessing``: that passes the terminal's
stderr on to the child, which Textual has replaced while the editor runs.
"""

from __future__ import annotations

import contextlib
import os
import pickle
import subprocess
import sys
from collections import Counter
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path
from typing import IO, Any

from postdsl import api
from tui.sample import Chunk, Indexer, Program

#: lines per message from the child: small enough that unpickling one never holds the
#: UI's interpreter lock for more than a few milliseconds
CHUNK = 2000


@dataclass(frozen=True)
class Job:
    """What the child needs: everything as plain, picklable data."""

    post_text: str
    post_file: str
    sample: Path
    cl_file: str
    now: datetime
    #: trace this 1-based line instead of posting the whole program
    trace: int | None = None
    #: replay the program through the control model and send its toolpath's segments
    #: instead of its lines
    toolpath: bool = False


@dataclass
class Outcome:
    """What comes back at the end: the program's index, the names it uses, or an error."""

    error: str | None = None
    used: frozenset[str] = frozenset()
    first: dict[object, int] = field(default_factory=dict)
    count: Counter[object] = field(default_factory=Counter)
    traced: api.TracedLine | None = None
    #: why the control model stopped the toolpath (toolpath jobs)
    stopped: str | None = None


def _chunk(program: Program, start: int) -> Chunk:
    return (program.texts[start:], program.commands[start:], program.tables[start:],
            program.blocks[start:])


def _used(commands: list[api.CLCommand]) -> frozenset[str]:
    names = set()
    for command in commands:
        names.add(command.name)
        cycle = getattr(command, "cycle", None)
        if command.name == "custom_cycle" and cycle:
            names.add(cycle)
    return frozenset(names)


class _Sender:
    def __init__(self, out: IO[bytes]) -> None:
        self.out = out

    def send(self, message: Any) -> None:
        pickle.dump(message, self.out, protocol=pickle.HIGHEST_PROTOCOL)
        self.out.flush()


def _child(connection: Any, job: Job) -> None:
    """The child process: post (or trace) and send chunks, then the outcome."""
    outcome = Outcome()
    try:
        post = api.load_post_text(job.post_text, job.post_file)
        commands = list(api.read_cl(job.sample))
        outcome.used = _used(commands)
        if job.trace is not None:
            outcome.traced = api.trace_line(post, commands, job.trace, cl_file=job.cl_file,
                                            now=job.now)
        elif job.toolpath:
            _, path = api.toolpath(post, commands, cl_file=job.cl_file, now=job.now)
            for start in range(0, len(path.segments), CHUNK):
                connection.send(path.segments[start:start + CHUNK])
            outcome.stopped = path.stopped
        else:
            indexer = Indexer()
            program, sent = indexer.program, [0]

            def add(line: api.NCLine) -> None:
                indexer.add(line)
                if len(program) - sent[0] == CHUNK:
                    connection.send(_chunk(program, sent[0]))
                    sent[0] = len(program)

            divergence = _post_shown(post, commands, job, add)
            if len(program) > sent[0]:
                connection.send(_chunk(program, sent[0]))
            outcome.first, outcome.count = program.first, program.count
            outcome.error = divergence
    except (api.CLError, api.PostError) as exc:
        outcome.error = str(exc)
    except OSError as exc:
        outcome.error = f"cannot read the sample program: {exc}"
    except Exception as exc:  # an engine bug: say so, keep the editor (and the work)
        outcome.error = f"internal error while posting: {type(exc).__name__}: {exc}"
    connection.send(outcome)


def _post_shown(post: api.CompiledPost, commands: list[api.CLCommand], job: Job,
                add: Callable[[api.NCLine], None]) -> str | None:
    """Post the program shown, each line to ``add``; why ``postdsl post`` would refuse it
    (verify), or None.

    The preview shows what ``post`` writes, so it is verified as ``post`` verifies, in
    the same posting (:func:`postdsl.api.post_verified`): the lines stay on screen, and
    the message says where they stop doing what the CL says.  A post without a control
    model is shown unverified, as ``post`` writes it.
    """
    if post.machine.control is None or post.machine.resolution is None:
        for line in api.iter_post(post, commands, cl_file=job.cl_file, now=job.now):
            add(line)
        return None
    verdict = api.post_verified(post, commands, add, cl_file=job.cl_file, now=job.now)
    if verdict.divergence is None:
        return None
    return f"postdsl post refuses this program: {verdict.divergence}"


def run_job(job: Job, cancelled: Callable[[], bool]
            ) -> Iterator[Chunk | list[api.Segment] | Outcome]:
    """Start the child and yield its chunks of lines (or of segments), then its Outcome;
    stops (and ends the child) as soon as ``cancelled()`` — a newer edit replaced this job."""
    # imported, not run as __main__, so what it pickles is tui.posting's Outcome
    child = "from tui.posting import main; main()"
    process = subprocess.Popen([sys.executable, "-c", child], stdin=subprocess.PIPE,
                               stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    assert process.stdin is not None and process.stdout is not None
    try:
        pickle.dump(job, process.stdin, protocol=pickle.HIGHEST_PROTOCOL)
        process.stdin.close()
        while not cancelled():
            try:
                message = pickle.load(process.stdout)
            except (EOFError, pickle.UnpicklingError):
                yield Outcome(error="the posting process ended without a result")
                return
            yield message
            if isinstance(message, Outcome):
                return
    finally:
        if process.poll() is None:
            process.kill()
        process.stdout.close()
        process.wait()


def main() -> None:
    """The child: one job from stdin, its chunks and outcome to stdout.

    It runs at a lower priority than the editor: on a busy machine the keys come first,
    the program a little later."""
    with contextlib.suppress(OSError, AttributeError):
        os.nice(10)
    job = pickle.load(sys.stdin.buffer)
    _child(_Sender(sys.stdout.buffer), job)

