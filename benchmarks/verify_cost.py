"""What verifying costs: ``postdsl post`` (verified, the default) beside ``post --no-verify``.

For each machine and CL format, the two commands run in turns, each as its own process
(round robin, ``--runs`` rounds, after one untimed warm-up run of each on a small
program, which also compiles the post into the user's cache), so a busy moment slows
both alike.  The table gives each command's median wall time and CPU time (user +
system, the process's own ``ru_utime + ru_stime`` from ``wait4``), its largest peak RSS
(``ru_maxrss``), and the ratio verified / unverified, taken round by round (the two
runs of a round are neighbours in time) and then the median: issue 25's target is at
most 2× at 1 000 000 moves, with the peak memory flat.

With ``--baseline SRC`` (another revision's package, e.g. ``git archive main postdsl
machines schemas | tar -x -C SRC``) the same table has that revision's ``post`` and
``post --verify`` as well, measured in the same rounds: the before and after of one run.

The programs are ``benchmarks/make_program.py``'s raster (see ``benchmarks/scale.py``).

    .venv/bin/python benchmarks/verify_cost.py                       # 100 000 moves, 5 rounds
    .venv/bin/python benchmarks/verify_cost.py --sizes 1000000 --runs 3 --machines vmc500
    .venv/bin/python benchmarks/verify_cost.py --baseline /tmp/main-src --formats native apt
"""

from __future__ import annotations

import argparse
import os
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
from scale import MACHINE_OPTIONS, WARM_UP, machine_line, program_file  # noqa: E402


@dataclass
class Command:
    """One command line measured: its runs' wall and CPU seconds and peak RSS (KB)."""

    name: str
    argv: list[str]  # with {program} and {out} to fill in
    env: dict[str, str] = field(default_factory=dict)
    cwd: Path = ROOT
    wall: list[float] = field(default_factory=list)
    cpu: list[float] = field(default_factory=list)
    peaks: list[int] = field(default_factory=list)
    failed: str = ""


def run_once(command: Command, program: Path, out: Path) -> None:
    """Run one command as its own process; keep its wall and CPU time and its peak RSS."""
    argv = [part.format(program=program, out=out) for part in command.argv]
    start = time.perf_counter()
    process = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                               env={**os.environ, **command.env}, cwd=command.cwd)
    assert process.stderr is not None
    errors = process.stderr.read()
    _, status, usage = os.wait4(process.pid, 0)
    elapsed = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) != 0 or not out.exists():
        command.failed = errors.decode("utf-8", "replace").strip()[-300:] or "failed"
        return
    command.wall.append(elapsed)
    command.cpu.append(usage.ru_utime + usage.ru_stime)
    command.peaks.append(usage.ru_maxrss)
    out.unlink()


def commands(machine: str, baseline: Path | None) -> list[Command]:
    """The commands of one machine: unverified first (each ratio's denominator)."""
    post = [sys.executable, "-m", "postdsl.cli", "post", machine, "{program}", "-o", "{out}",
            *MACHINE_OPTIONS.get(machine, [])]
    found = [Command("post --no-verify", [*post, "--no-verify"]),
             Command("post (verified)", post)]
    if baseline is not None:
        env = {"PYTHONPATH": str(baseline), "PYTHONDONTWRITEBYTECODE": "1"}
        found += [Command(f"post ({baseline.name})", post, env, baseline),
                  Command(f"post --verify ({baseline.name})", [*post, "--verify"], env,
                          baseline)]
    return found


def ratio(numerators: list[float], denominators: list[float]) -> float:
    """The median of the round-by-round ratios."""
    return statistics.median(a / b for a, b in zip(numerators, denominators, strict=False))


def measure(machine: str, fmt: str, moves: int, runs: int, work: Path,
            baseline: Path | None) -> list[Command]:
    field_ = commands(machine, baseline)
    out = work / "out.nc"
    for command in field_:
        run_once(command, program_file(work, WARM_UP, fmt), out)
        command.wall.clear()
        command.cpu.clear()
        command.peaks.clear()
    program = program_file(work, moves, fmt)
    for round_number in range(runs):
        for command in field_:
            if not command.failed:
                run_once(command, program, out)
        print(f"  {machine} {fmt} {moves}: round {round_number + 1}/{runs}: " + ", ".join(
            f"{c.name} {c.wall[-1]:.2f} s" if c.wall and not c.failed else f"{c.name} failed"
            for c in field_), file=sys.stderr, flush=True)
    return field_


def rows(machine: str, fmt: str, moves: int, field_: list[Command]) -> list[str]:
    """Table rows: each command, and its ratio to the unverified post of the same code."""
    out = []
    pairs = {1: 0, 3: 2}  # verified -> unverified of the same revision
    for index, c in enumerate(field_):
        name = f"`{machine}` {fmt}: {c.name}"
        if c.failed or not c.wall:
            out.append(f"| {name} | failed: {c.failed.splitlines()[-1] if c.failed else ''} "
                       f"| | | | |")
            continue
        base = field_[pairs[index]] if index in pairs else None
        ratios = ("", "")
        if base is not None and base.wall and not base.failed:
            ratios = (f"{ratio(c.wall, base.wall):.2f}×", f"{ratio(c.cpu, base.cpu):.2f}×")
        out.append(f"| {name} | {statistics.median(c.wall):.2f} s | "
                   f"{statistics.median(c.cpu):.2f} s | {ratios[0]} | {ratios[1]} | "
                   f"{statistics.median(c.wall) / moves * 1e6:.1f} | "
                   f"{max(c.peaks) / 1024:.0f} MB |")
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[100_000], metavar="MOVES")
    parser.add_argument("--runs", type=int, default=5, help="rounds (default 5)")
    parser.add_argument("--machines", nargs="+", default=["vmc500", "linuxcnc"])
    parser.add_argument("--formats", nargs="+", choices=make_program.FORMATS,
                        default=["native"], help="CL formats (default native)")
    parser.add_argument("--baseline", type=Path, metavar="SRC",
                        help="also run the postdsl package found in SRC (its `post` and "
                             "`post --verify`), in the same rounds")
    parser.add_argument("--work", type=Path, help="folder for the generated programs "
                        "(default: a temporary folder, removed afterwards)")
    args = parser.parse_args(argv)
    work = args.work or Path(tempfile.mkdtemp(prefix="postdsl-verify-cost-"))
    work.mkdir(parents=True, exist_ok=True)
    try:
        print(f"machine: {machine_line()}")
        print(f"command: {' '.join([Path(sys.executable).name, *sys.argv])}\n")
        for moves in args.sizes:
            table = [f"| {moves:,} moves | median wall | median CPU | verified / unverified, "
                     f"wall | CPU | µs per move | peak RSS |",
                     "|---|---:|---:|---:|---:|---:|---:|"]
            for machine in args.machines:
                for fmt in args.formats:
                    field_ = measure(machine, fmt, moves, args.runs, work, args.baseline)
                    table += rows(machine, fmt, moves, field_)
            print("\n".join(table) + f"\n\n(medians of {args.runs} interleaved rounds)\n",
                  flush=True)
    finally:
        if args.work is None:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
