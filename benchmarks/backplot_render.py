"""How long a 200 000-move toolpath takes to replay, rasterise in braille and draw as SVG.

Posts a generated milling program (lines and arcs, from post_throughput.py)
with the bundled VMC500 post (block numbers wrapping), replays it through the control model into
segments (``api.toolpath``), rasterises the segments for a 120 × 40 cell
backplot in each view (what the widget's worker does), draws every row
(what the widget does on the UI thread per refresh), and renders the SVG:

    .venv/bin/python benchmarks/backplot_render.py [MOVES]
"""

from __future__ import annotations

import sys
import time
from datetime import UTC, datetime
from pathlib import Path

from post_throughput import milling_program  # beside this file: run as a script

from postdsl import api
from postdsl.check.svgplot import render_svg
from postdsl.cl.model import SpindleOn, ToolChange
from tui.braille import Frame, rasterise


def timed(label: str, func, *args):
    start = time.perf_counter()
    result = func(*args)
    print(f"{label:<44} {time.perf_counter() - start:8.3f} s")
    return result


def main() -> None:
    moves = int(sys.argv[1]) if len(sys.argv) > 1 else 200_000
    program = milling_program(moves)
    program[1:1] = [ToolChange(tool_number=1, tool_type="end_mill", tool_diameter=6),
                    SpindleOn(spindle_speed=3000, spindle="cw")]
    # 200 000 blocks outrun the VMC500's five-digit block numbers: let them wrap
    text = Path(api.load_post("vmc500").file).read_text()
    post = api.load_post_text(text.replace("    maximum: 99999\n",
                                           "    maximum: 99999\n    wrap: true\n"))
    now = datetime(2021, 1, 22, tzinfo=UTC)
    lines = timed(f"post {moves} moves",
                  lambda: api.post_commands(post, program, cl_file="bench", now=now))
    path = timed("replay through the control model", api.toolpath_of_lines, post, lines)
    print(f"{len(path.segments)} segments, {sum(len(s.points) for s in path.segments)} points")
    for view in ("xy", "xz", "yz"):
        frame = Frame.fitting(path.segments, view, 120, 40)
        raster = timed(f"rasterise {view} at 120x40 (worker thread)", rasterise, path.segments,
                       frame)
        timed("draw its 40 rows (UI thread)", lambda r=raster: [r.row_text(y)
                                                                 for y in range(40)])
    highlight = {s.nc_line for s in path.segments[:500]}
    frame = Frame.fitting(path.segments, "xy", 120, 40)
    timed("rasterise a 500-move highlight", rasterise,
          [s for s in path.segments if s.nc_line in highlight], frame)
    svg = timed("render the SVG (3 views)", render_svg, path)
    print(f"SVG: {len(svg) / 1e6:.1f} MB")


if __name__ == "__main__":
    main()
