"""Benchmark: ``postdsl review`` of a 200-program corpus on 1 and on 2 processes.

    python benchmarks/review_parallel.py [--programs 200] [--seed 1]

Builds a throw-away git repository holding the VMC500 post and a generated
corpus (milling programs with lines and arcs, drilling programs with cycles;
a few hundred to a few thousand NC lines each), commits it, changes the
``coord`` format from 3 to 4 decimals in the working tree — a change that
touches most lines, so diffing is measured too — and reviews it with
``--jobs 1`` and ``--jobs 2`` (alternately, best of ``--repeat`` runs each).
Prints both times and the speed-up; exits
with 1 when two processes are not faster although two CPUs are available,
or when the two reviews disagree.

The corpus generator is also used by tests/test_review.py to check that a
parallel review finds exactly what a serial one finds.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # run as a script from a source checkout
    sys.path.insert(0, str(ROOT))

from postdsl import review  # noqa: E402

#: the VMC500 travel, kept well inside: X 0..500, Y 0..400
_X = (20.0, 480.0)
_Y = (20.0, 380.0)


def _r(value: float) -> float:
    """CAM-like coordinates: 5 decimals, so a 3 -> 4 decimals change shows."""
    return round(value, 5)


def _milling(rng: random.Random, lines: int) -> list[dict]:
    """A pocketing program: zig-zag passes at several depths, arcs at the ends."""
    out: list[dict] = [
        {"cmd": "tool_change", "tool_number": rng.randint(1, 20), "tool_type": "end mill",
         "tool_diameter": rng.choice([6, 8, 10, 12, 16])},
        {"cmd": "coolant_on", "coolant": "flood"},
        {"cmd": "spindle_on", "spindle_speed": rng.randint(20, 80) * 100, "spindle": "cw"},
    ]
    # passes stay inside the travel: X up to 240 + 200, Y up to 130 + 40 * 6
    x0, y0 = rng.uniform(20.0, 240.0), rng.uniform(20.0, 130.0)
    width = rng.uniform(60.0, 200.0)
    step = rng.uniform(2.0, 6.0)
    out.append({"cmd": "rapid_move", "x": _r(x0), "y": _r(y0), "z": 100})
    z = 50.0
    while len(out) < lines:
        z = max(z - rng.uniform(0.5, 2.0), 5.0)
        out.append({"cmd": "rapid_move", "z": _r(z + 5)})
        out.append({"cmd": "linear_move", "x": _r(x0), "y": _r(y0), "z": _r(z),
                    "feed": rng.choice([300, 500, 800])})
        y = y0
        forward = True
        for _ in range(rng.randint(10, 40)):
            x_end = x0 + width if forward else x0
            out.append({"cmd": "linear_move", "x": _r(x_end), "y": _r(y),
                        "feed": rng.choice([800, 1200, 1500])})
            # a half circle to the next pass: start and end on one circle about the centre
            radius = step / 2
            centre_y = y + radius
            y += step
            out.append({"cmd": "arc_move", "x": _r(x_end), "y": _r(y), "cx": _r(x_end),
                        "cy": _r(centre_y), "arc_direction": "ccw" if forward else "cw"})
            forward = not forward
            if len(out) >= lines:
                break
        out.append({"cmd": "rapid_move", "z": 100})
    out.append({"cmd": "coolant_off"})
    out.append({"cmd": "spindle_off"})
    return out


_CYCLES = ("single_peck", "deep_drill", "break_chip", "tapping", "rigid_tapping")


def _drilling(rng: random.Random, lines: int) -> list[dict]:
    """A hole-pattern program: several tools, each a cycle over a grid of holes."""
    out: list[dict] = []
    tool = 0
    while len(out) < lines:
        tool += 1
        cycle = rng.choice(_CYCLES)
        out += [
            {"cmd": "tool_change", "tool_number": (tool - 1) % 20 + 1,
             "tool_type": "tap" if "tapping" in cycle else "drill",
             "tool_diameter": rng.choice([3.3, 5, 6.8, 8.5, 10.2])},
            {"cmd": "coolant_on", "coolant": "flood"},
            {"cmd": "spindle_on", "spindle_speed": rng.randint(3, 30) * 100, "spindle": "cw"},
        ]
        top = _r(rng.uniform(20.0, 70.0))
        holes = [(_r(rng.uniform(*_X)), _r(rng.uniform(*_Y)))
                 for _ in range(rng.randint(20, 120))]
        out.append({"cmd": "rapid_move", "x": holes[0][0], "y": holes[0][1], "z": top + 30})
        out.append({"cmd": "cycle_start"})
        setup = {"cmd": cycle, "x": holes[0][0], "y": holes[0][1], "top": top,
                 "depth": _r(rng.uniform(5.0, 18.0)), "clearance": 5,
                 "feed": rng.choice([80, 120, 200])}
        if cycle in ("deep_drill", "break_chip", "rigid_tapping"):
            setup["peck"] = _r(rng.uniform(1.0, 4.0))
        if cycle in ("single_peck", "tapping"):
            setup["dwell"] = 0.5
        out.append(setup)
        out += [{"cmd": "cycle_hole", "x": x, "y": y} for x, y in holes[1:]]
        out.append({"cmd": "cycle_end"})
        out.append({"cmd": "rapid_move", "z": 100})
        out.append({"cmd": "spindle_off"})
    return out


def make_program(rng: random.Random, index: int) -> list[dict]:
    """One CL program of 200 to 3000 commands (a few hundred to a few thousand NC lines)."""
    size = int(math.exp(rng.uniform(math.log(200), math.log(3000))))
    body = _milling(rng, size) if index % 3 else _drilling(rng, size)
    start = {"cmd": "program_start", "program_name": f"P{index:04d}", "project": "BENCH",
             "author": "benchmark"}
    return [start, *body, {"cmd": "program_end"}]


def make_corpus(folder: Path, programs: int, seed: int = 1) -> list[Path]:
    """Write ``programs`` native CL files into ``folder``; the same files for the same seed."""
    rng = random.Random(seed)
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for index in range(programs):
        path = folder / f"p{index:04d}.jsonl"
        path.write_text("".join(json.dumps(c) + "\n" for c in make_program(rng, index)),
                        encoding="utf-8")
        paths.append(path)
    return paths


def _git(root: Path, *args: str) -> None:
    env = {k: v for k, v in os.environ.items() if not k.startswith("GIT_")}
    subprocess.run(["git", "-c", "commit.gpgsign=false", *args], cwd=root, check=True,
                   capture_output=True, env=env)


def make_repository(root: Path, programs: int, seed: int = 1) -> Path:
    """A git repository with the VMC500 post and a corpus, committed, then the post changed.

    Returns the corpus folder.
    """
    (root / "machines").mkdir(parents=True)
    shutil.copy(ROOT / "machines" / "vmc500.yaml", root / "machines" / "vmc500.yaml")
    corpus = root / "cl"
    make_corpus(corpus, programs, seed)
    _git(root, "init", "-q")
    _git(root, "config", "user.name", "benchmark")
    _git(root, "config", "user.email", "benchmark@example.invalid")
    _git(root, "add", "-A")
    _git(root, "commit", "-q", "-m", "corpus")
    post = root / "machines" / "vmc500.yaml"
    text = post.read_text(encoding="utf-8")
    changed = text.replace("  coord:               # 40. / 16.996 : point always, trailing "
                           "zeros trimmed\n    decimals: 3",
                           "  coord:               # 40. / 16.996 : point always, trailing "
                           "zeros trimmed\n    decimals: 4")
    if changed == text:
        raise SystemExit("benchmark: machines/vmc500.yaml has no 'coord' format with 3 decimals "
                         "any more; update make_repository")
    post.write_text(changed, encoding="utf-8")
    return corpus


def timed_review(root: Path, corpus: Path, jobs: int) -> tuple[float, review.ReviewResult]:
    start = time.perf_counter()
    result = review.review(root, corpora=[corpus], machines=["vmc500"], jobs=jobs)
    return time.perf_counter() - start, result


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--programs", type=int, default=200)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--repeat", type=int, default=3,
                        help="runs of each; the best counts (other load only slows a run)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="postdsl-review-bench-") as temporary:
        root = Path(temporary)
        corpus = make_repository(root, args.programs, args.seed)
        cl_lines = sum(len(p.read_text().splitlines()) for p in corpus.glob("*.jsonl"))
        serial = parallel = math.inf
        for _ in range(max(1, args.repeat)):  # alternate, so load changes hit both alike
            seconds, one = timed_review(root, corpus, 1)
            serial = min(serial, seconds)
            seconds, two = timed_review(root, corpus, 2)
            parallel = min(parallel, seconds)
    nc_lines = sum(p.new_count for p in one.programs)
    summary = one.summary()
    print(f"corpus: {args.programs} programs, {cl_lines} CL commands, {nc_lines} NC lines "
          f"(min {min(p.new_count for p in one.programs)}, "
          f"max {max(p.new_count for p in one.programs)} per program)")
    print(f"change: coord 3 -> 4 decimals: {summary['changed_programs']} programs changed, "
          f"+{summary['added_lines']} -{summary['removed_lines']} lines")
    best = f"best of {max(1, args.repeat)}"
    print(f"review --jobs 1: {serial:.2f} s ({best})")
    print(f"review --jobs 2: {parallel:.2f} s ({best})")
    print(f"speed-up: {serial / parallel:.2f}x  (os.cpu_count() = {os.cpu_count()})")
    if one.programs != two.programs or one.errors != two.errors:
        print("FAIL: the serial and the parallel review differ", file=sys.stderr)
        return 1
    if (os.cpu_count() or 1) >= 2 and parallel >= serial:
        print("FAIL: 2 processes were not faster than 1", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
