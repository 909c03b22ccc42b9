"""How fast the engine posts, compared with a hand-written Python post.

Generates a milling program (linear moves and arcs, as a CAM's finishing
pass writes them), posts it with the bundled VMC500 post, and posts the same
moves with a minimal hand-written post (f-strings, modal X/Y/Z/F) that
produces the same G0/G1/G2/G3 blocks.  Prints blocks per second of both and
the ratio, measured in one run:

    .venv/bin/python benchmarks/post_throughput.py [MOVES]
"""

from __future__ import annotations

import math
import sys
import time
from datetime import UTC, datetime

from postdsl import api
from postdsl.cl.model import ArcMove, CLCommand, LinearMove, ProgramEnd, ProgramStart, RapidMove


def milling_program(moves: int) -> list[CLCommand]:
    commands: list[CLCommand] = [ProgramStart(), RapidMove(x=50, y=50, z=100)]
    x, y = 50.0, 50.0
    for n in range(moves):
        if n % 4 == 3:
            # a quarter arc about a centre 5 mm to the left
            cx, cy = x - 5, y
            angle = math.pi / 2
            ex, ey = cx + 5 * math.cos(angle), cy + 5 * math.sin(angle)
            commands.append(ArcMove(x=ex, y=ey, cx=cx, cy=cy, arc_direction="ccw", feed=800))
            x, y = ex, ey
        else:
            x = 50 + 40 * math.sin(n * 0.01)
            y = 50 + 40 * math.cos(n * 0.013)
            commands.append(LinearMove(x=x, y=y, z=20 + (n % 7) * 0.01, feed=1200))
    commands.append(ProgramEnd())
    return commands


def hand_written(commands: list[CLCommand]) -> list[str]:
    """What a small Python post would do for the same blocks."""
    out: list[str] = []
    last: dict[str, str] = {}
    n = 10
    px = py = pz = 0.0

    def word(letter: str, value: float) -> str:
        text = f"{value:.3f}".rstrip("0")
        if last.get(letter) == text:
            return ""
        last[letter] = text
        return f" {letter}{text}"

    for c in commands:
        if isinstance(c, RapidMove):
            out.append(f"N{n}  G0{word('X', c.x)}{word('Y', c.y)}{word('Z', c.z)}")
            px, py, pz = c.x, c.y, c.z
        elif isinstance(c, LinearMove):
            out.append(f"N{n}  G1{word('X', c.x)}{word('Y', c.y)}{word('Z', c.z)}"
                       f"{word('F', c.feed)}")
            px, py, pz = c.x, c.y, c.z
        elif isinstance(c, ArcMove):
            g = " G2" if c.arc_direction == "cw" else " G3"
            out.append(f"N{n} {g} X{c.x:.3f} Y{c.y:.3f}{word('Z', pz)} I{c.cx - px:.3f} "
                       f"J{c.cy - py:.3f}{word('F', c.feed)}")
            px, py = c.x, c.y
        else:
            continue
        n += 10
    return out


def best_of(runs: int, func, *args):
    best = math.inf
    result = None
    for _ in range(runs):
        start = time.perf_counter()
        result = func(*args)
        best = min(best, time.perf_counter() - start)
    return best, result


def main() -> None:
    moves = int(sys.argv[1]) if len(sys.argv) > 1 else 50_000
    commands = milling_program(moves)
    now = datetime(2024, 1, 1, tzinfo=UTC)
    compile_time, post = best_of(3, api.load_post, "vmc500")
    engine_time, lines = best_of(3, lambda: api.post_commands(post, commands, now=now))
    hand_time, hand = best_of(3, hand_written, commands)
    blocks = len(lines)
    print(f"moves: {moves}, blocks written: {blocks} (hand-written post: {len(hand)})")
    print(f"load + check + compile the post: {compile_time * 1000:.1f} ms")
    print(f"postdsl engine:     {engine_time:.3f} s  {blocks / engine_time:10.0f} blocks/s")
    print(f"hand-written post:  {hand_time:.3f} s  {len(hand) / hand_time:10.0f} blocks/s")
    print(f"ratio engine / hand-written: {engine_time / hand_time:.2f}")


if __name__ == "__main__":
    main()
