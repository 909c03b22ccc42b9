"""Write a large milling program as CL, for the scaling benchmark (``benchmarks/scale.py``).

The program is a 3D raster finish, as a CAM system writes one: rows of feed
moves along X whose Z follows a wavy surface (X, Y and Z all change on every
move), a semicircular arc joining each row to the next (clockwise and
counter-clockwise in turn), a feed change every 50 moves, and every ten rows a
retract with rapids to the start of the next pass.  The same moves are written
in three formats: native JSON Lines, APT CL source, and FreeCAD's internal
path as ``Path.toGCode()`` writes it (feeds in mm/s, six decimals).  The output
is deterministic: the same size gives byte-identical files.

    .venv/bin/python benchmarks/make_program.py --moves 100000 --format native -o p.jsonl

``moves`` counts motion records (feed moves, arcs and rapids).  The part stays
inside the travel of every bundled machine (X -91..91 with the arcs, Y -140..138, Z -3..20).
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from typing import TextIO

FORMATS = ("native", "apt", "freecad")
SUFFIX = {"native": ".jsonl", "apt": ".apt", "freecad": ".gcode"}

#: points per row, rows per pass, row spacing (mm)
ROW_POINTS = 100
PASS_ROWS = 10
STEP = 2.0
X_START, X_END = -90.0, 90.0
Y_START, Y_ROWS = -140.0, 140  # rows before the raster starts again at Y_START
SAFE_Z, APPROACH_Z = 20.0, 2.0
FEEDS = (1200.0, 900.0)  # mm/min, alternated every FEED_EVERY moves
FEED_EVERY = 50
SPEED = 3000


@dataclass(frozen=True)
class Move:
    """One motion record at an absolute position (Z only for the very first rapid).

    ``kind`` is "rapid", "line" or "arc"; ``feed`` is the feed in force (mm/min) and
    ``new_feed`` whether it changes here; arcs have a centre and a direction.
    """

    kind: str
    x: float | None
    y: float | None
    z: float
    feed: float = 0.0
    new_feed: bool = False
    cx: float = 0.0
    cy: float = 0.0
    cw: bool = False


def surface(x: float, y: float) -> float:
    """The finished surface: a gentle wave between Z -3 and Z -1."""
    return round(-2.0 + 0.6 * math.sin(x / 7.0) * math.cos(y / 5.0)
                 + 0.3 * math.sin((x + y) / 13.0), 4)


def moves(count: int) -> Iterator[Move]:
    """``count`` motion records of the raster (the last pass may stop mid-row)."""
    made = 0
    row = 0
    dx = (X_END - X_START) / (ROW_POINTS - 1)
    feed: float | None = None
    x: float | None = None
    y: float | None = None
    z = SAFE_Z

    def cut(kind: str, nx: float, ny: float, nz: float, **arc: float | bool) -> Move:
        nonlocal feed, x, y, z
        wanted = FEEDS[(made // FEED_EVERY) % len(FEEDS)]
        changed = wanted != feed
        feed, x, y, z = wanted, nx, ny, nz
        return Move(kind, nx, ny, nz, wanted, changed, **arc)  # type: ignore[arg-type]

    while made < count:
        y_row = round(Y_START + (row % Y_ROWS) * STEP, 4)
        forward = row % 2 == 0
        x0 = X_START if forward else X_END
        if row % PASS_ROWS == 0:  # a new pass: retract, rapid over, come down, plunge
            steps = [(x, y, SAFE_Z), (x0, y_row, SAFE_Z), (x0, y_row, APPROACH_Z)]
            for nx, ny, nz in steps:
                if made >= count:
                    return
                x, y, z = nx, ny, nz
                yield Move("rapid", nx, ny, nz)
                made += 1
            if made >= count:
                return
            feed = None  # a plunge after rapids states its feed
            yield cut("line", x0, y_row, surface(x0, y_row))
            made += 1
        for i in range(1, ROW_POINTS):
            if made >= count:
                return
            nx = round(X_START + i * dx if forward else X_END - i * dx, 4)
            yield cut("line", nx, y_row, surface(nx, y_row))
            made += 1
        row += 1
        y_next = round(Y_START + (row % Y_ROWS) * STEP, 4)
        if row % PASS_ROWS == 0 or y_next < y_row:
            row += (PASS_ROWS - row % PASS_ROWS) % PASS_ROWS
            continue
        if made >= count:
            return
        # a semicircle at the row's end up to the next row, bulging outwards
        assert x is not None
        yield cut("arc", x, y_next, z, cx=x, cy=round((y_row + y_next) / 2, 4),
                  cw=not forward)
        made += 1


def _num(value: float) -> str:
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def write_native(count: int, out: TextIO) -> None:
    out.write('{"cmd": "program_start", "program_name": "RASTER"}\n'
              '{"cmd": "tool_change", "tool_number": 1, "tool_type": "ball_mill", '
              '"tool_diameter": 6}\n'
              f'{{"cmd": "spindle_on", "spindle_speed": {SPEED}, "spindle": "cw"}}\n'
              '{"cmd": "coolant_on", "coolant": "flood"}\n')
    write = out.write
    for move in moves(count):
        if move.x is None or move.y is None:
            write(f'{{"cmd": "rapid_move", "z": {_num(move.z)}}}\n')
            continue
        axes = f', "x": {_num(move.x)}, "y": {_num(move.y)}, "z": {_num(move.z)}'
        feed = f', "feed": {_num(move.feed)}' if move.new_feed else ""
        if move.kind == "rapid":
            write(f'{{"cmd": "rapid_move"{axes}}}\n')
        elif move.kind == "line":
            write(f'{{"cmd": "linear_move"{axes}{feed}}}\n')
        else:
            direction = "cw" if move.cw else "ccw"
            write(f'{{"cmd": "arc_move"{axes}, "cx": {_num(move.cx)}, "cy": {_num(move.cy)}, '
                  f'"arc_direction": "{direction}"{feed}}}\n')
    out.write('{"cmd": "rapid_move", "z": 20}\n{"cmd": "coolant_off"}\n'
              '{"cmd": "spindle_off"}\n{"cmd": "program_end"}\n')


def write_apt(count: int, out: TextIO) -> None:
    out.write("PARTNO/RASTER\nUNITS/MM\nCUTTER/6,3\nLOADTL/1\n"
              f"SPINDL/{SPEED},RPM,CLW\nCOOLNT/FLOOD\n")
    write = out.write
    x: float | None = None
    y: float | None = None
    for move in moves(count):
        if move.x is None or move.y is None:  # the first rapid: straight up
            write(f"FROM/{_num(X_START)},{_num(Y_START)},{_num(move.z)}\n")
            x, y = X_START, Y_START
            continue
        x, y = move.x, move.y
        if move.kind == "rapid":
            write(f"RAPID\nGOTO/{_num(x)},{_num(y)},{_num(move.z)}\n")
            continue
        if move.new_feed:
            write(f"FEDRAT/{_num(move.feed)},MMPM\n")
        if move.kind == "arc":
            axis = "-1" if move.cw else "1"
            write(f"CIRCLE/{_num(move.cx)},{_num(move.cy)},{_num(move.z)},0,0,{axis},"
                  f"{_num(abs(move.y - move.cy))}\n")
        write(f"GOTO/{_num(x)},{_num(y)},{_num(move.z)}\n")
    out.write(f"RAPID\nGOTO/{_num(x or X_START)},{_num(y or Y_START)},20\n"
              "SPINDL/OFF\nCOOLNT/OFF\nEND\nFINI\n")


def write_freecad(count: int, out: TextIO) -> None:
    """FreeCAD's internal path as ``Path.toGCode()`` writes it: feeds in mm/s, six decimals."""
    out.write("(raster finish: FreeCAD internal path, Path.toGCode form)\nG90\nG17\nG54\n"
              f"M6 T1.000000\nM3 S{SPEED:.6f}\nM8\n")
    write = out.write
    sx = sy = 0.0
    for move in moves(count):
        if move.x is None or move.y is None:
            write(f"G0 Z{move.z:.6f}\n")
            continue
        where = f"X{move.x:.6f} Y{move.y:.6f} Z{move.z:.6f}"
        if move.kind == "rapid":
            write(f"G0 {where}\n")
        elif move.kind == "line":
            write(f"G1 F{move.feed / 60.0:.6f} {where}\n")
        else:
            code = "G2" if move.cw else "G3"
            write(f"{code} F{move.feed / 60.0:.6f} I{move.cx - sx:.6f} J{move.cy - sy:.6f} "
                  f"{where}\n")
        sx, sy = move.x, move.y
    out.write("G0 Z20.000000\nM9\nM5\nM2\n")


WRITERS = {"native": write_native, "apt": write_apt, "freecad": write_freecad}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--moves", type=int, default=100_000)
    parser.add_argument("--format", choices=FORMATS, default="native")
    parser.add_argument("-o", "--output", help="file to write (default: stdout)")
    args = parser.parse_args(argv)
    if args.output:
        with open(args.output, "w", encoding="utf-8", newline="\n") as out:
            WRITERS[args.format](args.moves, out)
    else:
        WRITERS[args.format](args.moves, sys.stdout)


if __name__ == "__main__":
    main()
