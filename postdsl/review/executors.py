"""Where the per-program function runs: this process, a local process pool, a Dask cluster.

Each executor takes the same jobs and the same :class:`~postdsl.review.posting.Poster`
inputs (both versions of every post, as text, and the settings) and yields the
:class:`ProgramDiff` of each job as it is done, so the report is written while the
review runs and the caller holds one result at a time.

The Dask executor (``pip install 'postdsl[dask]'``) assumes no shared file system:
the posts' texts are sent to every worker once, each job carries its CL program's
bytes, and no more jobs are in flight than the cluster has threads (times a few), so
the client's memory stays flat however large the archive.
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Iterable, Iterator, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from typing import Any

from postdsl.review.machines import MachineSides
from postdsl.review.posting import Job, Poster, Settings
from postdsl.review.results import ProgramDiff, Progress, ReviewError

EXECUTORS = ("local", "dask")

#: the worker's poster, per review (a process may serve several reviews: a cluster)
_POSTERS: dict[str, Poster] = {}


def _poster(token: str, machines: Mapping[str, MachineSides], settings: Settings) -> Poster:
    poster = _POSTERS.get(token)
    if poster is None:
        _POSTERS.clear()  # one review at a time per worker: the previous posts go
        poster = _POSTERS[token] = Poster(machines, settings)
    return poster


def _token(machines: Mapping[str, MachineSides], settings: Settings) -> str:
    digest = hashlib.sha256(settings.signature().encode())
    for name in sorted(machines):
        sides = machines[name]
        digest.update(f"{name}\0{sides.digest(False)}\0{sides.digest(True)}\0"
                      f"{sides.old_path}\0{sides.new_path}\0".encode("utf-8", "replace"))
    digest.update(repr(settings).encode())
    return digest.hexdigest()


#: how long a review waits for the Dask scheduler to answer (seconds)
_CONNECT_TIMEOUT = 10

_LOCAL: Poster | None = None


def _init_local(machines: Mapping[str, MachineSides], settings: Settings) -> None:
    global _LOCAL
    _LOCAL = Poster(machines, settings)


def _run_local(job: Job) -> ProgramDiff:
    assert _LOCAL is not None
    return _LOCAL(job)


def run_local(machines: Mapping[str, MachineSides], jobs: Sequence[Job], settings: Settings,
              *, workers: int) -> Iterator[ProgramDiff]:
    """The jobs over ``workers`` processes (in this process when 1), in order."""
    workers = max(1, min(workers, len(jobs)))
    if workers == 1:
        yield from map(Poster(machines, settings), jobs)
        return
    # chunks keep the pairs of one program together while still giving each worker
    # several chunks to balance uneven programs
    chunksize = max(1, min(64, len(jobs) // (workers * 8)))
    with ProcessPoolExecutor(max_workers=workers, initializer=_init_local,
                             initargs=(machines, settings)) as pool:
        yield from pool.map(_run_local, jobs, chunksize=chunksize)


def _run_remote(job: Job, machines: Mapping[str, MachineSides], settings: Settings,
                token: str) -> ProgramDiff:
    """The per-program function as a Dask task: the posts arrive once per worker."""
    return _poster(token, machines, settings)(job)


def _with_content(job: Job) -> Job:
    """The job with its CL program's bytes: a worker may see no file of ours."""
    if job.content is not None or job.path is None:
        return job
    try:
        return Job(job.machine, job.program, None, job.path.read_bytes())
    except OSError:
        return job  # the worker reports it, as the local pool does


def run_dask(machines: Mapping[str, MachineSides], jobs: Iterable[Job], settings: Settings,
             *, scheduler: str | None, in_flight: int | None = None) -> Iterator[ProgramDiff]:
    """The jobs on the Dask cluster at ``scheduler`` (``tcp://HOST:8786``), as they finish.

    ``scheduler`` may also be a ``distributed.Client`` or a cluster object (tests use a
    ``LocalCluster``).  The posts (``machines``) are scattered to every worker once.
    """
    try:
        import distributed
    except ImportError:
        raise ReviewError("--executor dask needs Dask's distributed scheduler: pip install "
                          "'postdsl[dask]'") from None
    if scheduler is None:
        raise ReviewError("--executor dask needs --scheduler ADDRESS (the address "
                          "`dask scheduler` prints, e.g. tcp://10.0.0.5:8786)")
    owned = not isinstance(scheduler, distributed.Client)
    try:
        # distributed has no type hints: its objects are Any here
        make: Any = distributed.Client
        client: Any = make(scheduler, set_as_default=False, timeout=_CONNECT_TIMEOUT) \
            if owned else scheduler
    except (OSError, TimeoutError, ValueError) as exc:
        raise ReviewError(f"cannot reach the Dask scheduler at {scheduler}: {exc}") from None
    try:
        token = _token(machines, settings)
        posts = client.scatter(dict(machines), broadcast=True, hash=False)
        threads = sum(client.nthreads().values()) or 1
        limit = in_flight or max(4, threads * 4)
        pending = iter(jobs)

        def submit() -> Any:
            job = next(pending, None)
            if job is None:
                return None
            return client.submit(_run_remote, _with_content(job), posts, settings, token,
                                 pure=False)

        first = [future for future in (submit() for _ in range(limit)) if future is not None]
        if not first:
            return
        completed: Any = distributed.as_completed
        running: Any = completed(first, loop=client.loop)
        for future in running:
            result: ProgramDiff = future.result()
            future.release()
            yield result
            following = submit()
            if following is not None:
                running.add(following)
    finally:
        if owned:
            client.close()


def run(machines: Mapping[str, MachineSides], jobs: Sequence[Job], settings: Settings, *,
        executor: str = "local", workers: int | None = None, scheduler: Any = None,
        progress: Progress | None = None) -> Iterator[ProgramDiff]:
    """Every job's result through ``executor``, calling ``progress(done, total)``."""
    total = len(jobs)
    if progress is not None:
        progress(0, total)
    if executor == "local":
        results = run_local(machines, jobs, settings, workers=workers or os.cpu_count() or 1)
    elif executor == "dask":
        results = run_dask(machines, jobs, settings, scheduler=scheduler)
    else:
        raise ReviewError(f"unknown executor '{executor}' (one of {', '.join(EXECUTORS)})")
    for done, result in enumerate(results, start=1):
        if progress is not None:
            progress(done, total)
        yield result
