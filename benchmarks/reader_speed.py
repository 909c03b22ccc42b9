"""How fast the APT and FreeCAD G-code readers read, against a hand-written loop.

Generates a 3D raster (feed moves with varying X Y Z, feed changes, rapids between
passes, arcs) as APT, as the G-code a FreeCAD post writes and as FreeCAD's dump of its
internal path, then reads each with
postdsl's reader and with a minimal hand-written loop that turns the same lines into
the same CL records (split, ``float``, the record's constructor; no checks, no error
messages).  Optionally the readers of another commit are timed in the same run
(``--before COMMIT``: its reader modules are loaded from git beside the current ones),
so before/after figures are measured side by side.  Prints the median of interleaved
runs, the time per move and the ratio to the hand loop:

    .venv/bin/python benchmarks/reader_speed.py [--moves 100000] [--runs 5] [--before REF]
"""

from __future__ import annotations

import argparse
import importlib.util
import io
import math
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from types import ModuleType

from postdsl.cl.apt import read_apt
from postdsl.cl.freecad import read_freecad
from postdsl.cl.model import ArcMove, CLCommand, LinearMove, RapidMove

ROOT = Path(__file__).resolve().parent.parent


def raster(moves: int) -> Iterator[tuple[str, tuple[float, ...]]]:
    """("rapid"|"feed"|"arc", values): passes of 200 feed moves, an arc at each pass end."""
    y = 0.0
    n = 0
    while n < moves:
        yield "rapid", (0.0, y, 5.0)
        for i in range(200):
            x = i * 0.5
            z = -1.0 - 0.3 * math.sin(x * 0.1 + y * 0.05)
            feed = 800.0 if i % 50 else 1200.0
            yield "feed", (round(x, 4), round(y, 4), round(z, 4), feed)
            n += 1
        # a half circle up to the next pass, about its centre
        yield "arc", (99.5, y + 1.0, round(z, 4), 99.5, y + 0.5)
        n += 1
        y += 1.0


def apt_program(moves: int) -> str:
    out = io.StringIO()
    out.write("PARTNO/RASTER\nUNITS/MM\nLOADTL/1\nSPINDL/RPM,3000,CLW\n")
    feed = None
    for kind, v in raster(moves):
        if kind == "rapid":
            out.write(f"RAPID\nGOTO/{v[0]:.4f},{v[1]:.4f},{v[2]:.4f}\n")
        elif kind == "feed":
            if v[3] != feed:
                feed = v[3]
                out.write(f"FEDRAT/{feed:.1f},MMPM\n")
            out.write(f"GOTO/{v[0]:.4f},{v[1]:.4f},{v[2]:.4f}\n")
        else:
            out.write(f"CIRCLE/{v[3]:.4f},{v[4]:.4f},{v[2]:.4f},0,0,1,0.5\n"
                      f"GOTO/{v[0]:.4f},{v[1]:.4f},{v[2]:.4f}\n")
    out.write("END\nFINI\n")
    return out.getvalue()


def gcode_program(moves: int) -> str:
    """G-code as FreeCAD's linuxcnc post writes it (mm/min, modal G words left out)."""
    out = io.StringIO()
    out.write("(Exported by FreeCAD)\n(Post Processor: linuxcnc_post)\nG17 G54 G40 G49 G80 G90\n"
              "G21\nM6 T1\nG43 H1\nM3 S3000\n")
    feed = None
    prev = (None, None, None)
    for kind, v in raster(moves):
        if kind == "rapid":
            out.write(f"G0 X{v[0]:.3f} Y{v[1]:.3f} Z{v[2]:.3f}\n")
            prev = v
        elif kind == "feed":
            words = ["G1"]
            for letter, value, old in zip("XYZ", v[:3], prev, strict=True):
                if value != old:
                    words.append(f"{letter}{value:.3f}")
            if v[3] != feed:
                feed = v[3]
                words.append(f"F{feed:.3f}")
            out.write(" ".join(words) + "\n")
            prev = v[:3]
        else:
            out.write(f"G3 X{v[0]:.3f} Y{v[1]:.3f} I0.000 J0.500\n")
            prev = v[:3]
    out.write("M5\nM2\n")
    return out.getvalue()


def dump_program(moves: int) -> str:
    """The same path as FreeCAD's dump post lists its internal path (feeds in mm/s)."""
    out = io.StringIO()
    out.write("(Path: Raster)\nCommand M6 [ T:1 ]\nCommand M3 [ S:3000 ]\n")
    for kind, v in raster(moves):
        if kind == "rapid":
            out.write(f"Command G0 [ X:{v[0]:.4f} Y:{v[1]:.4f} Z:{v[2]:.4f} ]\n")
        elif kind == "feed":
            out.write(f"Command G1 [ F:{v[3] / 60:.4f} X:{v[0]:.4f} Y:{v[1]:.4f} "
                      f"Z:{v[2]:.4f} ]\n")
        else:
            out.write(f"Command G3 [ I:0.0000 J:0.5000 X:{v[0]:.4f} Y:{v[1]:.4f} ]\n")
    return out.getvalue()


# --- the hand-written loops: the floor CPython sets for turning these lines into records --


def hand_apt(text: str) -> list[CLCommand]:
    out: list[CLCommand] = []
    feed = None
    rapid = False
    pos = (0.0, 0.0, 0.0)
    pending: tuple[tuple[float, ...], tuple[float, ...], float] | None = None
    for line in text.splitlines():
        word, _, rest = line.partition("/")
        if word == "GOTO":
            x, y, z = (float(v) for v in rest.split(","))
            if pending is not None:
                (cx, cy, _), axis, _ = pending
                out.append(ArcMove(x=x, y=y, z=z, cx=cx, cy=cy, feed=feed,
                                   arc_direction="ccw" if axis[2] > 0 else "cw"))
                pending = None
            elif rapid:
                out.append(RapidMove(x=x, y=y, z=z))
            else:
                out.append(LinearMove(x=x, y=y, z=z, feed=feed))
            rapid = False
            pos = (x, y, z)
        elif word == "FEDRAT":
            feed = float(rest.split(",")[0])
        elif word == "RAPID":
            rapid = True
        elif word == "CIRCLE":
            circle = rest.split(",")
            centre = (float(circle[0]), float(circle[1]), float(circle[2]))
            axis = (float(circle[3]), float(circle[4]), float(circle[5]))
            pending = (centre, axis, float(circle[6]))
    del pos
    return out


def hand_gcode(text: str) -> list[CLCommand]:
    out: list[CLCommand] = []
    feed = None
    for line in text.splitlines():
        words = line.split()
        code = words[0]
        if code not in ("G0", "G1", "G3"):
            continue
        values = {w[0]: float(w[1:]) for w in words[1:]}
        if "F" in values:
            feed = values["F"]
        if code == "G0":
            out.append(RapidMove(x=values.get("X"), y=values.get("Y"), z=values.get("Z")))
        elif code == "G1":
            out.append(LinearMove(x=values.get("X"), y=values.get("Y"), z=values.get("Z"),
                                  feed=feed))
        else:
            out.append(ArcMove(x=values.get("X"), y=values.get("Y"), feed=feed,
                               arc_direction="ccw"))
    return out


def hand_dump(text: str) -> list[CLCommand]:
    out: list[CLCommand] = []
    feed = None
    for line in text.splitlines():
        if not line.startswith("Command G"):
            continue
        words = line[8:-2].split()
        values = {w[0]: float(w[2:]) for w in words[2:]}
        code = words[0]
        if "F" in values:
            feed = values["F"] * 60
        if code == "G0":
            out.append(RapidMove(x=values.get("X"), y=values.get("Y"), z=values.get("Z")))
        elif code == "G1":
            out.append(LinearMove(x=values.get("X"), y=values.get("Y"), z=values.get("Z"),
                                  feed=feed))
        else:
            out.append(ArcMove(x=values.get("X"), y=values.get("Y"), feed=feed,
                               arc_direction="ccw"))
    return out


# --- the readers of another commit, for before/after in one run -----------------------------


def module_at(ref: str, path: str, name: str, into: Path) -> ModuleType:
    """The module ``path`` as it is at ``ref``, imported from a copy under ``into``."""
    source = subprocess.run(["git", "-C", str(ROOT), "show", f"{ref}:{path}"], check=True,
                            capture_output=True, text=True).stdout
    copy = into / f"{name}.py"
    copy.write_text(source, encoding="utf-8")
    spec = importlib.util.spec_from_file_location(name, copy)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def timed(read: Callable[[], object]) -> float:
    start = time.perf_counter()
    read()
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--moves", type=int, default=100_000)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--before", help="a commit whose readers are timed beside these")
    options = parser.parse_args()
    apt, gcode = apt_program(options.moves), gcode_program(options.moves)
    dump = dump_program(options.moves)
    apt_lines, gcode_lines, dump_lines = apt.splitlines(), gcode.splitlines(), dump.splitlines()
    cases: dict[str, Callable[[], object]] = {
        "APT: hand loop": lambda: hand_apt(apt),
        "APT: postdsl": lambda: list(read_apt(apt_lines, "raster.apt")),
        "FreeCAD G-code: hand loop": lambda: hand_gcode(gcode),
        "FreeCAD G-code: postdsl": lambda: list(read_freecad(gcode_lines, "raster.nc")),
        "FreeCAD dump: hand loop": lambda: hand_dump(dump),
        "FreeCAD dump: postdsl": lambda: list(read_freecad(dump_lines, "raster.txt")),
    }
    if options.before:
        into = Path(tempfile.mkdtemp(prefix="reader-speed-"))
        old_apt = module_at(options.before, "postdsl/cl/apt.py", "_before_apt", into)
        old_freecad = module_at(options.before, "postdsl/cl/freecad.py", "_before_freecad",
                                into)
        cases["APT: postdsl before"] = lambda: list(old_apt.read_apt(apt_lines, "raster.apt"))
        cases["FreeCAD G-code: postdsl before"] = lambda: list(
            old_freecad.read_freecad(gcode_lines, "raster.nc"))
        cases["FreeCAD dump: postdsl before"] = lambda: list(
            old_freecad.read_freecad(dump_lines, "raster.txt"))
    hand = {"APT": hand_apt(apt), "FreeCAD G-code": hand_gcode(gcode),
            "FreeCAD dump": hand_dump(dump)}
    counts = {name: len(hand[name.split(":")[0]]) for name in cases}
    times: dict[str, list[float]] = {name: [] for name in cases}
    for _ in range(options.runs):  # interleaved, so that load on the machine hits all alike
        for name, read in cases.items():
            times[name].append(timed(read))
    print(f"{options.moves} moves, median of {options.runs} interleaved runs "
          f"(Python {sys.version.split()[0]})")
    floor = {family: statistics.median(times[f"{family}: hand loop"]) for family in hand}
    for name, values in times.items():
        median = statistics.median(values)
        family = name.split(":")[0]
        print(f"  {name:32s} {median:7.3f} s  {median / counts[name] * 1e6:6.2f} us/move  "
              f"{median / floor[family]:5.2f}x the hand loop")


if __name__ == "__main__":
    main()
