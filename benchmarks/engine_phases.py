"""Where a native post's time goes, phase by phase, and against another revision.

Reads one native CL program and times, in this process, in CPU seconds (best of
``--runs``, so the other processes on a shared machine weigh less than in wall time):
the reading pass, the summary pass (the first pass of ``write_program``: reading,
checking and folding the summary), and the engine alone on records already read.
With ``--baseline SRC`` (a tree holding another revision's ``postdsl``, e.g.
``git archive main postdsl machines schemas | tar -x -C SRC``) the same phases run
in a child process on that revision, in turns with this one.

    .venv/bin/python benchmarks/engine_phases.py PROGRAM.jsonl [--machine vmc500]
        [--runs 3] [--rounds 2] [--baseline /tmp/base]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def phases(program: str, machine: str, runs: int) -> dict[str, float]:
    """Best CPU seconds of each phase over ``runs`` runs, in this process."""
    from postdsl.api import load_post, posting_time
    from postdsl.cl.readers import read_cl
    from postdsl.cl.source import CLSource
    from postdsl.run.engine import Engine
    from postdsl.run.program import summarize

    try:  # the first pass as write_program runs it, on the revision being measured
        from postdsl.run.program import summarize_source as first_pass
    except ImportError:  # a revision from before summarize_source folded the commands
        def first_pass(source: CLSource, rapid_rate: float) -> object:
            return summarize(source.commands(), rapid_rate)

    post = load_post(machine)
    best = {"read": 1e9, "read + summary": 1e9, "engine": 1e9}
    commands = read_cl(program)
    summary = summarize(commands, post.machine.rapid_rate)
    for _ in range(runs):
        start = time.process_time()
        with CLSource(program) as source:
            for _command in source.commands():
                pass
        best["read"] = min(best["read"], time.process_time() - start)
        start = time.process_time()
        with CLSource(program) as source:
            first_pass(source, post.machine.rapid_rate)
        best["read + summary"] = min(best["read + summary"], time.process_time() - start)
        engine = Engine(post, now=posting_time())
        start = time.process_time()
        for _line in engine.run(commands, summary):
            pass
        best["engine"] = min(best["engine"], time.process_time() - start)
    return best


def child(src: Path, program: str, machine: str, runs: int) -> dict[str, float]:
    """:func:`phases` in a child process running the postdsl found in ``src``."""
    env = {**os.environ, "PYTHONPATH": str(src), "PYTHONDONTWRITEBYTECODE": "1"}
    code = (f"import json, sys; sys.path.insert(0, {str(Path(__file__).parent)!r}); "
            f"import engine_phases as e; "
            f"print(json.dumps(e.phases({program!r}, {machine!r}, {runs!r})))")
    done = subprocess.run([sys.executable, "-c", code], env=env, cwd=src, check=True,
                          capture_output=True, text=True)
    return json.loads(done.stdout.splitlines()[-1])  # type: ignore[no-any-return]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("program")
    parser.add_argument("--machine", default="vmc500")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--baseline", type=Path)
    args = parser.parse_args()
    program = str(Path(args.program).resolve())
    results: dict[str, list[dict[str, float]]] = {"this tree": [], "baseline": []}
    for _ in range(args.rounds):
        results["this tree"].append(child(ROOT, program, args.machine, args.runs))
        if args.baseline:
            results["baseline"].append(child(args.baseline.resolve(), program, args.machine,
                                             args.runs))
    print("| CPU s (best) | " + " | ".join(results["this tree"][0]) + " |")
    print("|---|" + "---:|" * len(results["this tree"][0]))
    for name, rows in results.items():
        if rows:
            best = {k: min(r[k] for r in rows) for k in rows[0]}
            print(f"| {name} | " + " | ".join(f"{v:.2f}" for v in best.values()) + " |")
    if args.baseline:
        new = {k: min(r[k] for r in results["this tree"]) for k in results["this tree"][0]}
        old = {k: min(r[k] for r in results["baseline"]) for k in results["baseline"][0]}
        print("| baseline ÷ this tree | " + " | ".join(f"{old[k] / new[k]:.2f}×" for k in new)
              + " |")


if __name__ == "__main__":
    main()
