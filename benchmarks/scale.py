"""How postdsl scales: whole-process time and peak memory, beside the floor and a peer.

In one run, for each program size, the contestants below run in turns (round
robin, ``--runs`` rounds), each as its own process on the same machine, so a
busy moment slows all of them alike; the table gives each one's median wall
time, its ratio to the exact-rounding hand loop, the time per move and the
largest peak RSS of its runs (the process's own ``ru_maxrss``, from ``wait4``):

- ``postdsl post MACHINE PROGRAM -o OUT`` for each bundled machine with native
  CL, and with APT and FreeCAD G-code (``--all-formats``: every machine with
  every format; otherwise the first machine only for APT and FreeCAD); ``post``
  verifies what it writes, ``--no-verify`` measures posting alone (what verifying
  costs: ``benchmarks/verify_cost.py``);
- the hand loop (``benchmarks/hand_loop.py``): json.loads per line, three modal
  coordinates, exact decimal rounding, write; and the same with f-string rounding;
- FreeCAD 0.20's ``linuxcnc_post`` (``benchmarks/freecad_linuxcnc.py`` under
  ``freecadcmd``) on the same path, when ``freecadcmd`` is on PATH (up to
  ``--peer-max`` moves: it holds the whole program as text).

The programs come from ``benchmarks/make_program.py`` (a 3D raster: X Y Z change
on every move, feed changes, arcs, rapids between passes), cached in ``--work``.

Before the rounds, each contestant runs once, untimed, on a program of
:data:`WARM_UP` moves: postdsl's first run of a post compiles it into the user's
cache (once per post file and version, see ``postdsl.compile.postcache``), and every
contestant's own files are then read from the page cache alike.  The rounds
measure the steady state a shop posting program after program sees.

    .venv/bin/python benchmarks/scale.py --quick          # 100 000 moves, 5 rounds
    .venv/bin/python benchmarks/scale.py --full           # 1 000 000 and 10 000 000 moves
    .venv/bin/python benchmarks/scale.py --sizes 200000 --runs 3
"""

from __future__ import annotations

import argparse
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))

import make_program  # noqa: E402 (a sibling script, found through the path set above)

#: the contestant every ratio is taken to
FLOOR = "hand loop, exact rounding"
#: the moves of the program each contestant runs once before the timed rounds
WARM_UP = 1000


@dataclass
class Contestant:
    name: str
    fmt: str  # the program format it reads
    command: list[str]  # with {program} and {out} to fill in
    env: dict[str, str] = field(default_factory=dict)
    cwd: Path = ROOT
    times: list[float] = field(default_factory=list)
    peaks: list[int] = field(default_factory=list)  # KB
    failed: str = ""


def run_once(contestant: Contestant, program: Path, out: Path) -> None:
    """Run one contestant as its own process; its wall time and peak RSS."""
    command = [part.format(program=program, out=out) for part in contestant.command]
    env = {**os.environ, **{k: v.format(program=program, out=out)
                            for k, v in contestant.env.items()}}
    start = time.perf_counter()
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                               env=env, cwd=contestant.cwd)
    assert process.stderr is not None
    errors = process.stderr.read()
    _, status, usage = os.wait4(process.pid, 0)
    elapsed = time.perf_counter() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode != 0 or not out.exists():
        contestant.failed = errors.decode("utf-8", "replace").strip()[-300:] or \
            f"exit {process.returncode}"
        return
    contestant.times.append(elapsed)
    contestant.peaks.append(usage.ru_maxrss)
    out.unlink()


#: post options a machine needs to post the benchmark's program: the hobby router's spindle
#: runs at the one speed set on it, and the post refuses a CL speed that differs
MACHINE_OPTIONS = {"hmcnc": ["--option", f"spindle_speed_rpm={make_program.SPEED}"]}


def contestants(machines: list[str], formats: list[str], all_formats: bool, freecad: bool,
                baseline: Path | None, no_verify: bool = False) -> list[Contestant]:
    python = sys.executable
    postdsl = [python, "-m", "postdsl.cli", "post", *(["--no-verify"] if no_verify else [])]
    found = [Contestant(FLOOR, "native", [python, str(HERE / "hand_loop.py"), "{program}",
                                          "{out}", "--rounding", "exact"]),
             Contestant("hand loop, f-string rounding", "native",
                        [python, str(HERE / "hand_loop.py"), "{program}", "{out}",
                         "--rounding", "fstring"])]
    for index, machine in enumerate(machines):
        for fmt in formats:
            if fmt != "native" and index > 0 and not all_formats:
                continue
            options = MACHINE_OPTIONS.get(machine, [])
            found.append(Contestant(f"postdsl post {machine}, {fmt}", fmt,
                                    [*postdsl, machine, "{program}", "-o", "{out}", *options]))
            if baseline is not None and index == 0 and fmt == "native":
                found.append(Contestant(f"postdsl post {machine}, {fmt} ({baseline.name})",
                                        fmt, [python, "-m", "postdsl.cli", "post", machine,
                                              "{program}", "-o", "{out}"],
                                        {"PYTHONPATH": str(baseline),
                                         "PYTHONDONTWRITEBYTECODE": "1"}, cwd=baseline))
    if freecad:
        found.append(Contestant("FreeCAD 0.20 linuxcnc_post", "freecad",
                                ["freecadcmd", str(HERE / "freecad_linuxcnc.py")],
                                {"BENCH_GCODE": "{program}", "BENCH_OUT": "{out}"}))
    return found


def program_file(work: Path, moves: int, fmt: str) -> Path:
    path = work / f"raster-{moves}{make_program.SUFFIX[fmt]}"
    if not path.exists():
        partial = path.with_suffix(".partial")
        with partial.open("w", encoding="utf-8", newline="\n") as out:
            make_program.WRITERS[fmt](moves, out)
        partial.replace(path)
    return path


def machine_line() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text(encoding="utf-8").splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return (f"{cpu}, {os.cpu_count()} cores, load {load:.1f} at start; Python "
            f"{platform.python_version()}; {platform.system()} {platform.release()}")


def measure(moves: int, runs: int, work: Path, machines: list[str], args: argparse.Namespace,
            ) -> list[Contestant]:
    peers = moves <= args.peer_max
    freecad = shutil.which("freecadcmd") is not None and peers
    field = contestants(machines, args.formats, args.all_formats, freecad,
                        args.baseline if peers else None, args.no_verify)
    programs = {fmt: program_file(work, moves, fmt) for fmt in {c.fmt for c in field}}
    out = work / "out.nc"
    for contestant in field:
        run_once(contestant, program_file(work, WARM_UP, contestant.fmt), out)
        contestant.times.clear()  # untimed: only a failure is kept
        contestant.peaks.clear()
    for round_number in range(runs):
        for contestant in field:
            if contestant.failed:
                continue
            run_once(contestant, programs[contestant.fmt], out)
            done = bool(contestant.times) and not contestant.failed
            print(f"  round {round_number + 1}/{runs}: {contestant.name}: "
                  f"{contestant.times[-1] if done else float('nan'):.2f} s, peak "
                  f"{contestant.peaks[-1] / 1024 if done else float('nan'):.0f} MB",
                  file=sys.stderr, flush=True)
    return field


def table(moves: int, field: list[Contestant]) -> str:
    floor = next((statistics.median(c.times) for c in field if c.name == FLOOR and c.times),
                 None)
    rows = [f"| {moves:,} moves | median wall | × hand loop (exact) | µs per move | "
            f"peak RSS |", "|---|---:|---:|---:|---:|"]
    for c in field:
        if c.failed or not c.times:
            rows.append(f"| {c.name} | failed: {c.failed.splitlines()[-1] if c.failed else ''}"
                        f" | | | |")
            continue
        median = statistics.median(c.times)
        ratio = f"{median / floor:.2f}×" if floor else "–"
        rows.append(f"| {c.name} | {median:.2f} s | {ratio} | {median / moves * 1e6:.1f} | "
                    f"{max(c.peaks) / 1024:.0f} MB |")
    return "\n".join(rows)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--quick", action="store_true", help="100 000 moves (the default)")
    mode.add_argument("--full", action="store_true", help="1 000 000 and 10 000 000 moves")
    mode.add_argument("--sizes", type=int, nargs="+", metavar="MOVES")
    parser.add_argument("--runs", type=int, help="rounds (default: 5 quick, 3 full)")
    parser.add_argument("--machines", nargs="+", help="bundled machines (default: all)")
    parser.add_argument("--all-formats", action="store_true",
                        help="APT and FreeCAD input on every machine, not only the first")
    parser.add_argument("--formats", nargs="+", choices=make_program.FORMATS,
                        default=list(make_program.FORMATS), help="CL formats postdsl reads")
    parser.add_argument("--baseline", type=Path, metavar="SRC",
                        help="also post with the postdsl package found in SRC, e.g. "
                             "`git archive REV postdsl machines schemas | tar -x -C SRC` "
                             "(first machine, native CL)")
    parser.add_argument("--no-verify", action="store_true",
                        help="post with --no-verify: posting alone, as the figures before "
                             "post verified by default")
    parser.add_argument("--peer-max", type=int, default=1_000_000, metavar="MOVES",
                        help="largest program FreeCAD's post and the baseline are run on "
                             "(both hold the whole program)")
    parser.add_argument("--work", type=Path, help="folder for the generated programs "
                        "(default: a temporary folder, removed afterwards)")
    args = parser.parse_args(argv)
    sizes = args.sizes or ([1_000_000, 10_000_000] if args.full else [100_000])
    runs = args.runs or (3 if args.full else 5)
    if args.machines:
        machines = args.machines
    else:
        sys.path.insert(0, str(ROOT))
        from postdsl.resources import bundled_machines

        machines = list(bundled_machines())
    work = args.work or Path(tempfile.mkdtemp(prefix="postdsl-scale-"))
    work.mkdir(parents=True, exist_ok=True)
    try:
        print(f"machine: {machine_line()}")
        print(f"command: {' '.join([Path(sys.executable).name, *sys.argv])}\n")
        for moves in sizes:
            field = measure(moves, runs, work, machines, args)
            print(table(moves, field) + f"\n\n(median of {runs} interleaved runs)\n",
                  flush=True)
    finally:
        if args.work is None:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
