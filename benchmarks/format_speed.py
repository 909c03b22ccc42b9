"""Per-number cost of each bundled format: generic closure, generated function, hand code.

Side by side, in one run, for every format of every bundled post
(``machines/*.yaml``; formats with equal options are timed once) and a few
others (multipliers, half_even, an implied point):

* ``generic`` — :func:`postdsl.format_render.compile_fast`, one closure for
  every format (what ``render`` was before issue 11's generated functions, and
  their fallback now);
* ``generated`` — ``NumberFormat.render``, the function written for the
  format's options (:mod:`postdsl.format_codegen`);
* ``Decimal`` — the hand-written ``str(Decimal(repr(v)).quantize(q, ROUND_HALF_UP))``
  (rounding only: no trimming, sign or multiplier);
* ``f-string`` — ``f'{v:.Nf}'``, the floor any Python post pays for a number.

The values are raster coordinates as a CAM writes them (15-17 significant
digits), a person's numbers, whole numbers and zeros; ``ints`` is the generated
function on ints, as a JSON CL file gives whole numbers.  CPU time
(``time.process_time``), best of ``--rounds`` interleaved rounds, in ns per number:

    .venv/bin/python benchmarks/format_speed.py [--values N] [--rounds R]
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable
from decimal import ROUND_HALF_UP, Decimal
from typing import Any

from postdsl.api import load_post
from postdsl.format_render import compile_decimal, compile_fast
from postdsl.formats import DEFAULT_MAX_DIGITS, NumberFormat
from postdsl.resources import bundled_machines

#: formats no bundled post has, whose options take other lines of the generated code
OTHERS: dict[str, NumberFormat] = {
    "(feed mm/s: integer x60)": NumberFormat(integer=True, multiplier=60,
                                             max_digits=DEFAULT_MAX_DIGITS),
    "(inch: 4, x1/25.4)": NumberFormat(decimals=4, multiplier=1 / 25.4,
                                       max_digits=DEFAULT_MAX_DIGITS),
    "(half_even: 3)": NumberFormat(decimals=3, rounding="half_even",
                                   max_digits=DEFAULT_MAX_DIGITS),
    "(implied point: 3, never)": NumberFormat(decimals=3, point="never",
                                              max_digits=DEFAULT_MAX_DIGITS),
}


def bundled_formats() -> dict[str, list[tuple[str, NumberFormat]]]:
    """The formats of the bundled posts and OTHERS, grouped by their options."""
    groups: dict[str, list[tuple[str, NumberFormat]]] = {}
    named = [(f"{machine} {name}", fmt) for machine in bundled_machines()
             for name, fmt in load_post(machine).formats.items()]
    for label, fmt in named + list(OTHERS.items()):
        groups.setdefault(repr(sorted(fmt.to_mapping().items())), []).append((label, fmt))
    return groups


def sample_values(count: int) -> list[float]:
    """Raster-like coordinates: most with full float digits, some short, some zeros."""
    values: list[float] = []
    for n in range(count):
        kind = n % 10
        if kind < 6:
            values.append(50 + 40 * math.sin(n * 0.0137) * (1 if n % 4 else -1))  # 16-17 digits
        elif kind < 8:
            values.append(round(-25 + (n % 997) * 0.05, 2))  # a person's numbers
        elif kind == 8:
            values.append(float(n % 500))  # whole numbers
        else:
            values.append(-0.0)
    return values


def best_time(render: Callable[[Any], Any], values: list[Any], rounds: int) -> float:
    """The least CPU time of ``rounds`` passes over ``values``, in ns per number."""
    best = math.inf
    for _ in range(rounds):
        start = time.process_time()
        for value in values:
            render(value)
        best = min(best, time.process_time() - start)
    return best / len(values) * 1e9


def hand_decimal(decimals: int) -> Callable[[float], str]:
    quantum = Decimal(1).scaleb(-decimals)

    def render(value: float) -> str:
        return str(Decimal(repr(value)).quantize(quantum, ROUND_HALF_UP))

    return render


def f_string(decimals: int) -> Callable[[float], str]:
    spec = f".{decimals}f"

    def render(value: float) -> str:
        return f"{value:{spec}}"

    return render


def headline(rounds: int) -> None:
    """The figure of issue 11: vmc500's coord writing -88.1818, timeit best of ``rounds``."""
    import timeit

    fmt = load_post("vmc500").formats["coord"]
    quantum = Decimal("0.001")
    cases = {
        "generic": (compile_fast(fmt), "render(v)"),
        "generated": (fmt.render, "render(v)"),
        "Decimal": (None, "str(Decimal(repr(v)).quantize(q, ROUND_HALF_UP))"),
        "f-string": (None, "f'{v:.3f}'"),
    }
    parts = []
    for name, (render, statement) in cases.items():
        names = {"render": render, "v": -88.1818, "Decimal": Decimal, "q": quantum,
                 "ROUND_HALF_UP": ROUND_HALF_UP}
        seconds = min(timeit.repeat(statement, globals=names, number=100_000, repeat=rounds,
                                    timer=time.process_time)) / 100_000
        parts.append(f"{name} {seconds * 1e6:.2f} µs")
    print("vmc500 coord, -88.1818: " + ", ".join(parts))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--values", type=int, default=20_000)
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    values = sample_values(args.values)
    ints = [round(v) for v in values]
    headline(args.rounds)
    print(f"{args.values} values, best of {args.rounds} interleaved rounds, CPU ns per number")
    print(f"{'format':34} {'generic':>8} {'generated':>9} {'Decimal':>8} {'f-string':>8} "
          f"{'speedup':>7} {'ints':>6}")
    ratios: list[float] = []
    for group in bundled_formats().values():
        fmt = group[0][1]
        generic, generated = compile_fast(fmt), fmt.render
        reference = compile_decimal(fmt)
        for sample in (values, ints):
            assert [generated(v) for v in sample] == [reference(v) for v in sample], group
        generic_ns = generated_ns = hand_ns = floor_ns = ints_ns = math.inf
        hand, floor = hand_decimal(fmt.decimals), f_string(fmt.decimals)
        for _ in range(args.rounds):  # interleaved: the machine's load hits all alike
            generic_ns = min(generic_ns, best_time(generic, values, 1))
            generated_ns = min(generated_ns, best_time(generated, values, 1))
            hand_ns = min(hand_ns, best_time(hand, values, 1))
            floor_ns = min(floor_ns, best_time(floor, values, 1))
            ints_ns = min(ints_ns, best_time(generated, ints, 1))
        ratios.append(generic_ns / generated_ns)
        for index, (label, _) in enumerate(group):
            if index:
                print(f"  {label:32} (same options)")
                continue
            print(f"{label:34} {generic_ns:8.0f} {generated_ns:9.0f} {hand_ns:8.0f} "
                  f"{floor_ns:8.0f} {generic_ns / generated_ns:6.2f}x {ints_ns:6.0f}")
    print(f"{'geometric mean speedup':34} {'':8} {'':9} {'':8} {'':8} "
          f"{math.prod(ratios) ** (1 / len(ratios)):6.2f}x")


if __name__ == "__main__":
    main()
