"""Generated post code against a hand-written loop, and the traced flavour beside it.

Writes a native CL program (a 3D raster: G1 with varying X Y Z, feed changes,
rapids between passes, arcs), then, interleaved in one run so the machine's load
hits all alike, times as whole processes:

* ``postdsl post MACHINE`` (the generated tables, the only executor),
* a minimal hand-written post: ``json.loads`` per line, modal X/Y/Z/F, exact decimal
  rounding (half away from zero on the decimal text), write;

and prints medians and ratios; then, in one process, the engine's lines with their
sources (what previews and review get) against the traced flavour (what ``postdsl
explain`` and the editor's trace run), alternating.  It also times loading a post
with an empty and a warm code cache (what a cache hit saves), and with ``--profile``
prints where the time of the generated path goes (cProfile, in-process).

    .venv/bin/python benchmarks/codegen_speed.py [--moves 100000] [--runs 5]
        [--machine vmc500] [--profile] [--baseline /path/to/another/checkout]
"""

from __future__ import annotations

import argparse
import cProfile
import json
import math
import os
import pstats
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

HAND_LOOP = r'''
import json, sys
from decimal import ROUND_HALF_UP, Decimal
Q = Decimal("0.001")
def exact(v):
    t = str(Decimal(repr(v)).quantize(Q, rounding=ROUND_HALF_UP)).rstrip("0")
    return t
last = {}
n = 10
out = open(sys.argv[2], "w")
for line in open(sys.argv[1]):
    r = json.loads(line)
    cmd = r["cmd"]
    if cmd not in ("rapid_move", "linear_move", "arc_move"):
        continue
    words = [" G0" if cmd == "rapid_move" else " G1"]
    for axis in ("x", "y", "z", "feed"):
        v = r.get(axis)
        if v is None:
            continue
        t = exact(v)
        if last.get(axis) != t:
            last[axis] = t
            words.append(" " + axis[0].upper() + t)
    out.write(f"N{n} " + "".join(words) + "\n")
    n += 10
out.close()
'''


def write_program(path: Path, moves: int) -> None:
    """A raster of ``moves`` records after the tool change and spindle start."""
    records = [{"cmd": "program_start", "program_name": "raster"},
               {"cmd": "tool_change", "tool_number": 1, "tool_diameter": 6.0},
               {"cmd": "spindle_on", "spindle_speed": 6000},
               {"cmd": "rapid_move", "x": 0.0, "y": 0.0, "z": 20.0}]
    x = y = 0.0
    for n in range(moves):
        row, col = divmod(n, 400)
        if col == 0:
            records.append({"cmd": "rapid_move", "z": 5.0})
            records.append({"cmd": "rapid_move", "x": 0.0, "y": row * 0.25})
            continue
        if col % 50 == 49:
            # a quarter arc (a helix-free corner rounding) of radius 0.5
            cx, cy = x, y + 0.5
            records.append({"cmd": "arc_move", "x": round(cx + 0.5, 6), "y": round(cy, 6),
                            "cx": round(cx, 6), "cy": round(cy, 6), "arc_direction": "ccw",
                            "feed": 900.0})
            x, y = cx + 0.5, cy
            continue
        x = col * 0.1
        y = row * 0.25 + 0.02 * math.sin(col * 0.05)
        z = -1.0 - 0.5 * math.sin(col * 0.01) * math.cos(row * 0.02)
        record = {"cmd": "linear_move", "x": round(x, 6), "y": round(y, 6), "z": round(z, 6)}
        if col % 100 == 1:
            record["feed"] = 1200.0 if (col // 100) % 2 else 1000.0
        records.append(record)
    records.append({"cmd": "program_end"})
    with path.open("w", encoding="utf-8") as stream:
        for record in records:
            stream.write(json.dumps(record) + "\n")


def _timeless(path: Path) -> str:
    return re.sub(r"\d+[.:/-]\d+[.:/-]\d+", "#", path.read_text(encoding="utf-8"))


def run(argv: list[str], env: dict[str, str]) -> float:
    start = time.perf_counter()
    subprocess.run(argv, check=True, env=env, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--moves", type=int, default=100_000)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--machine", default="vmc500")
    parser.add_argument("--profile", action="store_true")
    parser.add_argument("--baseline", metavar="TREE",
                        help="also time `postdsl post` of another checkout (e.g. main's)")
    args = parser.parse_args()
    postdsl = str(Path(sys.executable).with_name("postdsl"))
    with tempfile.TemporaryDirectory() as folder:
        work = Path(folder)
        program = work / "raster.jsonl"
        write_program(program, args.moves)
        hand = work / "hand.py"
        hand.write_text(HAND_LOOP, encoding="utf-8")
        env = {**os.environ, "POSTDSL_CACHE_DIR": str(work / "cache")}
        cases = {
            "generated": ([postdsl, "post", args.machine, str(program), "-o",
                           str(work / "gen.nc")], env),
            "hand loop": ([sys.executable, str(hand), str(program), str(work / "hand.nc")],
                          env),
        }
        if args.baseline:
            cases["baseline"] = ([sys.executable, "-c", "from postdsl.cli import main; main()",
                                  "post", args.machine, str(program), "-o",
                                  str(work / "base.nc")],
                                 {**env, "PYTHONPATH": str(Path(args.baseline).resolve())})
        times: dict[str, list[float]] = {name: [] for name in cases}
        for _ in range(args.runs):
            for name, (argv, case_env) in cases.items():
                times[name].append(run(argv, case_env))
        medians = {name: statistics.median(t) for name, t in times.items()}
        print(f"{args.moves} moves, {args.machine}, whole process, median of {args.runs} "
              f"interleaved runs")
        for name, median in medians.items():
            print(f"  {name:12s} {median:7.3f} s   {median / medians['hand loop']:5.2f}x the "
                  f"hand loop")
        if args.baseline:
            print(f"  baseline / generated: {medians['baseline'] / medians['generated']:.2f} "
                  f"(same output: {_timeless(work / 'base.nc') == _timeless(work / 'gen.nc')})")
        engine_only(args.machine, program, work / "cache", args.runs)
        cache_hit(args.machine, work / "cache-timing", args.runs)
        if args.profile:
            profile(args.machine, program, work / "cache")


def engine_only(machine: str, program: Path, cache: Path, runs: int) -> None:
    """The engine alone (the program read once): its lines, and its traced flavour.

    Whole processes on a shared machine drift with its load over a long run; here the
    two alternate every few seconds in one process, and the best of each counts.
    """
    os.environ["POSTDSL_CACHE_DIR"] = str(cache)
    from datetime import UTC, datetime

    from postdsl import api
    from postdsl.run.trace import trace_lines

    commands = list(api.read_cl(program))
    post = api.load_post(machine)
    now = datetime(2024, 1, 1, tzinfo=UTC)
    best = {"lines": math.inf, "traced": math.inf, "one line": math.inf}
    texts = {}
    for _ in range(runs):
        start = time.perf_counter()
        lines = api.post_commands(post, commands, now=now)
        best["lines"] = min(best["lines"], time.perf_counter() - start)
        texts["lines"] = api.post_text(post, lines)
        start = time.perf_counter()
        traced = [t.line for t in trace_lines(post, commands, now=now)]
        best["traced"] = min(best["traced"], time.perf_counter() - start)
        texts["traced"] = api.post_text(post, traced)
        # the last line traced alone: what `postdsl explain` and the editor's trace do
        start = time.perf_counter()
        next(trace_lines(post, commands, now=now, wanted=len(lines)))
        best["one line"] = min(best["one line"], time.perf_counter() - start)
    print(f"  engine only, best of {runs}: lines {best['lines']:.3f} s, every line traced "
          f"{best['traced']:.3f} s ({best['traced'] / best['lines']:.2f}x), the last line "
          f"traced {best['one line']:.3f} s ({best['one line'] / best['lines']:.2f}x; same "
          f"text: {texts['lines'] == texts['traced']})")


def cache_hit(machine: str, folder: Path, runs: int) -> None:
    """Time turning a loaded post into functions with an empty and with a warm cache."""
    os.environ["POSTDSL_CACHE_DIR"] = str(folder)
    from postdsl import api
    from postdsl.compile import codegen

    cold: list[float] = []
    warm: list[float] = []
    for index in range(runs):
        for target in (cold, warm):
            if target is cold:
                for entry in folder.glob("*.code"):
                    entry.unlink()
            post = api.load_post(machine)
            start = time.perf_counter()
            codegen.generated(post)
            target.append(time.perf_counter() - start)
        del index
    print(f"  generated functions of the post: {statistics.median(cold) * 1000:.1f} ms with an "
          f"empty cache, {statistics.median(warm) * 1000:.1f} ms with a warm one")


def profile(machine: str, program: Path, cache: Path) -> None:
    os.environ["POSTDSL_CACHE_DIR"] = str(cache)
    from postdsl import cli

    out = program.with_suffix(".prof.nc")
    profiler = cProfile.Profile()
    profiler.enable()
    try:
        cli.main(["post", machine, str(program), "-o", str(out)], standalone_mode=False)
    finally:
        profiler.disable()
    pstats.Stats(profiler).sort_stats("tottime").print_stats(18)


if __name__ == "__main__":
    main()
