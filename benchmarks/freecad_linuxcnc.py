"""FreeCAD 0.20's linuxcnc_post on a program in Path.toGCode form, run by ``freecadcmd``.

``benchmarks/scale.py`` runs it as one process per export, the way a user or a
script exports a job: the G-code text becomes a FreeCAD ``Path`` (parsed in C++)
on one operation object, and ``linuxcnc_post.export`` writes the NC file.  The
input and output are given in the environment (``freecadcmd`` passes no arguments
to a script): BENCH_GCODE, BENCH_OUT.
"""

import os

# FreeCAD's own modules, importable only inside freecadcmd
import Path
from PathScripts.post import linuxcnc_post


class Operation:
    """What linuxcnc_post reads of a job's operation: a label and a Path."""

    Label = "raster"
    Name = "raster"

    def __init__(self, path: object) -> None:
        self.Path = path


path = Path.Path()
with open(os.environ["BENCH_GCODE"], encoding="utf-8") as source:
    path.setFromGCode(source.read())
linuxcnc_post.export([Operation(path)], os.environ["BENCH_OUT"], "--no-show-editor")
