"""The floor a Python post can reach: a minimal hand-written loop over native CL.

``json.loads`` per line, three modal coordinates (X Y Z written when their text
changes), F when the feed changes, G0/G1/G2/G3 with I J, and a write per block.
``--rounding exact`` rounds half away from zero on the decimal text of the float
(as postdsl's formats do); ``--rounding fstring`` uses ``f"{v:.3f}"`` (rounds the
binary float, half to even).  No checks of any kind: what ``benchmarks/scale.py``
compares postdsl with.

    python benchmarks/hand_loop.py program.jsonl out.nc --rounding exact
"""

from __future__ import annotations

import argparse
import json
from decimal import ROUND_HALF_UP, Decimal
from typing import Any

_QUANTUM = Decimal("0.001")


def exact(value: float) -> str:
    text = str(Decimal(repr(value)).quantize(_QUANTUM, ROUND_HALF_UP))
    return "0.000" if text == "-0.000" else text


def fstring(value: float) -> str:
    text = f"{value:.3f}"
    return "0.000" if text == "-0.000" else text


def run(source: str, target: str, fmt: Any) -> None:
    last: dict[str, str] = {}
    x = y = 0.0
    codes = {"rapid_move": "G0", "linear_move": "G1"}
    with open(source, encoding="utf-8") as cl, open(target, "w", encoding="utf-8") as out:
        write = out.write
        for line in cl:
            record = json.loads(line)
            cmd = record["cmd"]
            if cmd == "arc_move":
                words = ["G2" if record["arc_direction"] == "cw" else "G3"]
                nx, ny = record.get("x", x), record.get("y", y)
                words += [f"X{fmt(nx)}", f"Y{fmt(ny)}", f"I{fmt(record['cx'] - x)}",
                          f"J{fmt(record['cy'] - y)}"]
                last["X"], last["Y"] = words[1][1:], words[2][1:]
                x, y = nx, ny
            elif cmd in codes:
                words = [codes[cmd]]
                for axis in ("x", "y", "z"):
                    if axis in record:
                        text = fmt(record[axis])
                        letter = axis.upper()
                        if last.get(letter) != text:
                            last[letter] = text
                            words.append(letter + text)
                x, y = record.get("x", x), record.get("y", y)
            else:
                continue
            feed = record.get("feed")
            if feed is not None:
                text = fmt(feed)
                if last.get("F") != text:
                    last["F"] = text
                    words.append("F" + text)
            write(" ".join(words) + "\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("source")
    parser.add_argument("target")
    parser.add_argument("--rounding", choices=("exact", "fstring"), default="exact")
    args = parser.parse_args()
    run(args.source, args.target, exact if args.rounding == "exact" else fstring)


if __name__ == "__main__":
    main()
