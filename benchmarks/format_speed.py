"""Per-number cost of each bundled format: generic closure, generated function, hand code.

Side by side, in one run, for every format of every bundled post
(``machines/*.yaml``; formats with equal options are timed once) and a few
others (multipliers, half_even, an implied point):

* ``generic`` — :func:`postdsl.lang.format_render.compile_fast`, one closure for
  every format (what ``render`` was before issue 11's generated functions, and
  their fallback now);
* ``generated`` — ``NumberFormat.render``, the function written for the
  format's options (:mod:`postdsl.lang.format_codegen`);
* ``Decimal`` — the hand-written ``str(Decimal(repr(v)).quantize(q, ROUND_HALF_UP))``
  (rounding only: no trimming, sign or multiplier);
* ``f-string`` — ``f'{v:.Nf}'``, the floor any Python post pays for a number.

The values are a mix of raster coordinates as a CAM writes them (15-17
significant digits), a person's numbers, whole numbers and zeros; the columns
after it are the generated function on each kind alone (``int``: whole numbers
as a JSON CL file gives them).  A person's 12.35 is a tie for a 1-decimal
format and takes the exact path.  CPU time (``time.process_time``), best of
``--rounds`` interleaved rounds, in ns per number:

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
from postdsl.lang.format_render import compile_decimal, compile_fast
from postdsl.lang.formats import DEFAULT_MAX_DIGITS, NumberFormat
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


def sample_values(count: int) -> dict[str, list[Any]]:
    """Values by kind: a CAM's coordinates (16-17 digits, either sign), a person's
    (two decimals), whole numbers, zeros, and ints as JSON gives them."""
    cam = [(50 + 40 * math.sin(n * 0.0137)) * (1 if n % 4 else -1) for n in range(count)]
    short = [round(-25 + (n % 997) * 0.05, 2) for n in range(count)]
    whole = [float(n % 500 - 100) for n in range(count)]
    zeros = [(0.0, -0.0)[n % 2] for n in range(count)]
    ints = [n % 500 - 100 for n in range(count)]
    return {"cam": cam, "short": short, "whole": whole, "zero": zeros, "int": ints}


def mix(kinds: dict[str, list[Any]]) -> list[Any]:
    """Six CAM coordinates in ten, two short numbers, a whole number and a zero."""
    count = len(kinds["cam"])
    take = {"cam": 6, "short": 2, "whole": 1, "zero": 1}
    values: list[Any] = []
    for n in range(0, count, 10):
        for kind, many in take.items():
            values += kinds[kind][n:n + many]
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
    parser.add_argument("--values", type=int, default=10_000)
    parser.add_argument("--rounds", type=int, default=7)
    args = parser.parse_args()
    kinds = sample_values(args.values)
    values = mix(kinds)
    headline(args.rounds)
    print(f"{len(values)} mixed values, best of {args.rounds} interleaved rounds, "
          f"CPU ns per number; then the generated function by kind of value")
    print(f"{'format':30} {'generic':>7} {'generated':>9} {'Decimal':>7} {'f-string':>8} "
          f"{'speedup':>7} | {' '.join(f'{kind:>5}' for kind in kinds)}")
    ratios: list[float] = []
    for group in bundled_formats().values():
        fmt = group[0][1]
        generic, generated = compile_fast(fmt), fmt.render
        reference = compile_decimal(fmt)
        for sample in kinds.values():
            assert [generated(v) for v in sample] == [reference(v) for v in sample], group
        hand, floor = hand_decimal(fmt.decimals), f_string(fmt.decimals)
        mixed = {"generic": generic, "generated": generated, "Decimal": hand, "f-string": floor}
        best = dict.fromkeys([*mixed, *kinds], math.inf)
        for _ in range(args.rounds):  # interleaved: the machine's load hits all alike
            for name, render in mixed.items():
                best[name] = min(best[name], best_time(render, values, 1))
            for kind, sample in kinds.items():
                best[kind] = min(best[kind], best_time(generated, sample, 1))
        ratios.append(best["generic"] / best["generated"])
        for index, (label, _) in enumerate(group):
            if index:
                print(f"  {label:28} (same options)")
                continue
            print(f"{label:30} {best['generic']:7.0f} {best['generated']:9.0f} "
                  f"{best['Decimal']:7.0f} {best['f-string']:8.0f} "
                  f"{best['generic'] / best['generated']:6.2f}x | "
                  f"{' '.join(f'{best[kind]:5.0f}' for kind in kinds)}")
    print(f"{'geometric mean speedup':30} {'':7} {'':9} {'':7} {'':8} "
          f"{math.prod(ratios) ** (1 / len(ratios)):6.2f}x")


if __name__ == "__main__":
    main()
