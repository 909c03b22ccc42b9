"""Per-number cost of the fast render path against the Decimal reference path.

Both paths are compiled from the same formats (those of the bundled posts and
the new rounding options) and render the same values — raster coordinates
with 15-17 significant digits, as a CAM writes them, and short ones, as a
person writes them.  Rounds alternate between the two paths so that the noise
of a shared machine hits both alike; the ratio of medians is printed per format:

    .venv/bin/python benchmarks/format_speed.py [--values N] [--rounds R]
"""

from __future__ import annotations

import argparse
import math
import statistics
import time
from collections.abc import Callable
from typing import Any

from postdsl.format_render import compile_decimal, compile_fast
from postdsl.formats import DEFAULT_MAX_DIGITS, NumberFormat

FORMATS: dict[str, NumberFormat] = {
    "vmc500 coord (3, trim, point always)": NumberFormat(
        decimals=3, trailing_zeros=False, point="always", max_digits=DEFAULT_MAX_DIGITS),
    "emco coord (3, zeros kept)": NumberFormat(decimals=3, max_digits=DEFAULT_MAX_DIGITS),
    "cycle (4, trim, min 1)": NumberFormat(decimals=4, trailing_zeros=False, min_decimals=1),
    "feed (integer)": NumberFormat(integer=True, max_digits=DEFAULT_MAX_DIGITS),
    "feed mm/s (integer x60)": NumberFormat(integer=True, multiplier=60),
    "implied point (3, never)": NumberFormat(decimals=3, point="never"),
    "inch (4, x1/25.4)": NumberFormat(decimals=4, multiplier=1 / 25.4),
    "half_even (3)": NumberFormat(decimals=3, rounding="half_even"),
    "binary (3, printf)": NumberFormat(decimals=3, rounding="binary"),
    "heidenhain (3, sign always, +0)": NumberFormat(
        decimals=3, trailing_zeros=False, sign="always", zero_sign="plus"),
}


def sample_values(count: int) -> list[float]:
    """Raster-like coordinates: most with full float digits, some short, some zeros."""
    values: list[float] = []
    for n in range(count):
        kind = n % 10
        if kind < 6:
            values.append(50 + 40 * math.sin(n * 0.0137))  # 16-17 digits
        elif kind < 8:
            values.append(round(-25 + (n % 997) * 0.05, 2))  # a person's numbers
        elif kind == 8:
            values.append(float(n % 500))  # whole numbers
        else:
            values.append(-0.0)
    return values


def time_once(render: Callable[[Any], str], values: list[float]) -> float:
    start = time.perf_counter()
    for value in values:
        render(value)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--values", type=int, default=20_000)
    parser.add_argument("--rounds", type=int, default=7)
    args = parser.parse_args()
    values = sample_values(args.values)
    print(f"{args.values} values per round, {args.rounds} interleaved rounds, median ns/number")
    print(f"{'format':40} {'Decimal':>9} {'fast':>9} {'speedup':>8}")
    ratios: list[float] = []
    for name, fmt in FORMATS.items():
        fast, slow = compile_fast(fmt), compile_decimal(fmt)
        assert [fast(v) for v in values] == [slow(v) for v in values], name
        fast_times: list[float] = []
        slow_times: list[float] = []
        for _ in range(args.rounds):
            slow_times.append(time_once(slow, values))
            fast_times.append(time_once(fast, values))
        slow_ns = statistics.median(slow_times) / len(values) * 1e9
        fast_ns = statistics.median(fast_times) / len(values) * 1e9
        ratios.append(slow_ns / fast_ns)
        print(f"{name:40} {slow_ns:9.0f} {fast_ns:9.0f} {slow_ns / fast_ns:7.2f}x")
    print(f"{'geometric mean speedup':40} {'':9} {'':9} "
          f"{statistics.geometric_mean(ratios):7.2f}x")


if __name__ == "__main__":
    main()
