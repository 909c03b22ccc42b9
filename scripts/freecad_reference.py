"""Reference outputs of FreeCAD 0.20's own linuxcnc_post, for tests/test_linuxcnc.py.

Run with FreeCAD's command-line interpreter (Debian package freecad-python3)::

    freecadcmd scripts/freecad_reference.py

It builds several FreeCAD jobs headless and writes, under tests/data/freecad/:

* ``JOB.dump.txt``: the job's objects in the FreeCAD dump form (``(Path: label)`` and
  ``str(Path.Command)`` for every command, as FreeCAD's dump post printed it);
* ``JOB.gcode``: the same objects' ``Path.toGCode()`` one after the other;
* ``JOB.OPTIONSET.ngc``: what linuxcnc_post writes for the job with that option set.

**How the jobs are built.**  Path operations need a document with a model, tool bits
and (for the 3D surface) OpenCamLib, which the headless install does not give, so the
toolpaths are built as the operations build them, without the operation objects:
FreeCAD's own generators where 0.20 has them (``toolchange_generator`` for the tool
controllers, ``helix_generator`` for the helix, ``drill_generator`` for G81/G82/G83,
``PathFeedRate.setFeedRate`` for the feeds of every move), and Path.Command lists in
the shape the pocket and 3D-surface operations write for the rest (the operation's
label comment first, ``G0 Z`` clearance last, ``F`` on every move).  The list of objects
handed to the post is PathPost's for a job ordered by fixture: the fixture object
(``G54``, ``G0 Z`` clearance), then each tool controller before the first operation
using it, then the operations.

Coordinates are chosen with at most five significant digits, because the dump form
prints five (``str(Path.Command)``): a longer value would reach postdsl rounded and be
posted differently from the double FreeCAD posts.  Feeds are whole mm/min (FreeCAD keeps
mm/s: 600 mm/min is 10 mm/s, exact in both forms).  Operations have no coolant mode,
which neither form carries.

FreeCAD 0.20's posts keep state between exports (line numbers, options), so every
export runs in a process of its own: the driver starts ``freecadcmd`` again with
``FREECAD_REFERENCE_EXPORT=JOB:OPTIONSET`` in the environment.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path as FilePath

import FreeCAD
import Part
import Path
import PathFeedRate
from Generators import drill_generator, helix_generator, toolchange_generator

OUT = FilePath(__file__).resolve().parent.parent / "tests" / "data" / "freecad"

#: option set name -> linuxcnc_post arguments
OPTION_SETS: dict[str, str] = {
    "default": "--no-show-editor",
    "no_header": "--no-show-editor --no-header",
    "no_comments": "--no-show-editor --no-comments",
    "line_numbers": "--no-show-editor --line-numbers",
    "precision4": "--no-show-editor --precision=4",
    "modal": "--no-show-editor --no-header --modal",
    "axis_modal": "--no-show-editor --no-header --axis-modal",
    "modal_axis_modal": "--no-show-editor --no-header --modal --axis-modal",
    "preamble": "--no-show-editor --no-header --preamble='G17 G90 G64 P0.01' "
                "--postamble='M5 M2'",
}


class _Object:
    """What a post reads of a path object: Name, Label, Path (PathPost's _TempObject)."""

    def __init__(self, label: str, commands: list) -> None:
        self.Name = label
        self.Label = label
        self.Path = Path.Path(commands)


class _Rate:
    def __init__(self, mm_per_min: float) -> None:
        self.Value = mm_per_min / 60.0


class _ToolController:
    """The feeds of a tool controller, as PathFeedRate reads them (mm/s inside FreeCAD)."""

    def __init__(self, horiz: float, vert: float) -> None:
        self.HorizFeed = _Rate(horiz)
        self.VertFeed = _Rate(vert)
        self.HorizRapid = _Rate(0.0)
        self.VertRapid = _Rate(0.0)


def C(name: str, **params: float) -> Path.Command:
    return Path.Command(name, params)


def fixture() -> _Object:
    return _Object("G54", [C("G54"), C("G0", Z=15.0)])


def tool(number: int, label: str, speed: float) -> _Object:
    commands = toolchange_generator.generate(
        number, label, speed, toolchange_generator.SpindleDirection.CW)
    return _Object(label, commands)


def operation(label: str, body: list, tc: _ToolController, clearance: float) -> _Object:
    commands = [C(f"({label})"), *body, C("G0", Z=clearance)]
    PathFeedRate.setFeedRate(commands, tc)
    return _Object(label, commands)


def pocket_job() -> list:
    tc = _ToolController(600.0, 300.0)
    body = [
        C("G0", Z=15.0), C("G0", X=10.0, Y=10.0), C("G0", Z=5.0),
        C("G1", X=10.0, Y=10.0, Z=-2.0),
        C("G1", X=50.0, Y=10.0, Z=-2.0),
        C("G3", I=0.0, J=5.0, K=0.0, X=55.0, Y=15.0, Z=-2.0),
        C("G1", X=55.0, Y=35.0, Z=-2.0),
        C("G3", I=-5.0, J=0.0, K=0.0, X=50.0, Y=40.0, Z=-2.0),
        C("G1", X=10.0, Y=40.0, Z=-2.0),
        C("G1", X=10.0, Y=10.0, Z=-2.0),
        C("G0", Z=5.0),
        # a value on a rounding tie: Python's format rounds the double (-4.375)
        C("G0", X=20.0, Y=-4.3755), C("G1", X=20.0, Y=-4.3755, Z=-1.0),
        C("G2", I=0.0, J=4.3755, K=0.0, X=20.0, Y=4.3755, Z=-1.0),
        C("G2", I=0.0, J=-4.3755, K=0.0, X=20.0, Y=-4.3755, Z=-1.0),
        C("G1", X=30.125, Y=-4.3755, Z=-1.0),
    ]
    return [fixture(), tool(1, "TC: Endmill 6mm", 5000.0),
            operation("Pocket", body, tc, 15.0)]


def helix_job() -> list:
    tc = _ToolController(450.0, 120.0)
    start = FreeCAD.Vector(30.0, 20.0, 0.0)
    edge = Part.makeLine(start, FreeCAD.Vector(30.0, 20.0, -3.0))
    body = [C("(helix cut operation)"), C("G0", Z=10.0), C("G0", Z=10.0),
            C("G0", X=30.0, Y=20.0, Z=10.0), C("G0", X=30.0, Y=20.0, Z=0.0)]
    body += helix_generator.generate(edge, 5.0, 1.0, 0.5, 4.0, 0.0, "CW", "Outside")
    return [fixture(), tool(2, "TC: Endmill 4mm", 8000.0),
            operation("Helix", body, tc, 10.0)]


def drill_op(label: str, holes: list, return_level: str, dwell: float, peck: float,
             tc: _ToolController) -> _Object:
    """What PathDrilling.circularHoleExecute writes (FreeCAD 0.20) for these holes."""
    body = [C("(Begin Drilling)"), C("G0", Z=10.0), C("G90"), C(return_level)]
    for x, y in holes:
        body += [C("G0", X=x, Y=y), C("G0", Z=3.0)]
        edge = Part.makeLine(FreeCAD.Vector(x, y, 0.0), FreeCAD.Vector(x, y, -8.0))
        body += drill_generator.generate(edge, dwell, peck, 1, 1.0)
    body += [C("G80"), C("G0", Z=5.0)]
    return operation(label, body, tc, 10.0)


def drilling_job() -> list:
    tc = _ToolController(300.0, 90.0)
    holes = [(10.0, 10.0), (40.0, 10.0), (40.0, 30.0)]
    return [fixture(), tool(3, "TC: Drill 5mm", 2000.0),
            drill_op("Drilling", holes, "G99", 0.0, 0.0, tc),
            drill_op("Drilling001", holes, "G98", 0.5, 0.0, tc),
            drill_op("Drilling002", holes, "G98", 0.0, 2.5, tc)]


def raster_job() -> list:
    """A 3D surface's zigzag raster: X lines, Z following a dome, 2 mm step over."""
    tc = _ToolController(900.0, 300.0)
    body = [C("G0", Z=15.0), C("G0", X=0.0, Y=0.0), C("G0", Z=5.0),
            C("G1", X=0.0, Y=0.0, Z=0.0)]
    for row in range(6):
        y = 2.0 * row
        xs = [2.5 * k for k in range(9)]
        if row % 2:
            xs.reverse()
        if row:
            body.append(C("G1", X=xs[0], Y=y, Z=0.0))
        for x in xs:
            z = round(-0.02 * ((x - 10.0) ** 2 + (y - 5.0) ** 2) / 4.0 + 0.5, 3)
            z = min(z, 0.0)
            body.append(C("G1", X=x, Y=y, Z=z))
    return [fixture(), tool(5, "TC: Ball 3mm", 12000.0),
            operation("Surface", body, tc, 15.0)]


def planes_job() -> list:
    """Arcs in G17, G18 and G19, each plane selected just before its arcs."""
    tc = _ToolController(600.0, 300.0)
    body = [
        C("G0", Z=15.0), C("G0", X=0.0, Y=0.0), C("G0", Z=2.0),
        C("G1", X=0.0, Y=0.0, Z=0.0),
        C("G2", I=5.0, J=0.0, K=0.0, X=10.0, Y=0.0, Z=0.0),
        C("G18"),
        C("G2", I=0.0, K=5.0, X=15.0, Y=0.0, Z=5.0),
        C("G3", I=-5.0, K=0.0, X=10.0, Y=0.0, Z=0.0),
        C("G19"),
        C("G2", J=0.0, K=5.0, X=10.0, Y=5.0, Z=5.0),
        C("G3", J=-5.0, K=0.0, X=10.0, Y=0.0, Z=0.0),
        C("G17"),
        C("G3", I=-5.0, J=0.0, K=0.0, X=0.0, Y=0.0, Z=0.0),
    ]
    return [fixture(), tool(1, "TC: Endmill 6mm", 5000.0),
            operation("Arcs", body, tc, 15.0)]


def modal_job() -> list:
    """What FreeCAD's --modal --axis-modal compares as it does: depths that differ by less
    than the precision (written again: the raw doubles differ), drilling cycles one after
    the other with no move between (the next hole is its X or Y alone), the same feed and
    arc centre offsets again, a Z of -1 (FreeCAD's first location per object)."""
    tc = _ToolController(600.0, 300.0)
    body = [
        C("G0", Z=15.0), C("G0", X=5.0, Y=5.0), C("G0", Z=2.0),
        C("G1", X=5.0, Y=5.0, Z=-1.1834),
        C("G1", X=25.0, Y=5.0, Z=-1.1831),
        C("G1", X=25.0, Y=25.0, Z=-1.1831),
        C("G1", X=5.0, Y=25.0, Z=-1.1828),
        C("G2", I=0.0, J=-5.0, K=0.0, X=5.0, Y=15.0, Z=-1.1828),
        C("G2", I=0.0, J=-5.0, K=0.0, X=5.0, Y=5.0, Z=-1.1828),
        C("G0", Z=5.0),
        C("G98"),
        C("G81", X=10.0, Y=10.0, Z=-8.0, R=1.0, F=1.5),
        C("G81", X=30.0, Y=10.0, Z=-8.0, R=1.0, F=1.5),
        C("G81", X=30.0, Y=20.0, Z=-8.0, R=1.0, F=1.5),
        C("G83", X=10.0, Y=20.0, Z=-9.0, Q=2.0, R=1.0, F=1.5),
        C("G83", X=20.0, Y=20.0, Z=-9.0, Q=2.0, R=1.0, F=1.5),
        C("G80"),
    ]
    return [fixture(), tool(1, "TC: Endmill 6mm", 5000.0), operation("Modal", body, tc, 15.0)]


JOBS = {"pocket": pocket_job, "helix": helix_job, "drilling": drilling_job,
        "raster": raster_job, "planes": planes_job, "modal": modal_job}


def write_forms(name: str, objects: list) -> None:
    dump = []
    gcode = []
    for obj in objects:
        dump.append(f"(Path: {obj.Label})")
        dump += [str(command) for command in obj.Path.Commands]
        gcode.append(obj.Path.toGCode())
    (OUT / f"{name}.dump.txt").write_text("\n".join(dump) + "\n")
    (OUT / f"{name}.gcode").write_text("".join(gcode))


def export(name: str, option_set: str) -> None:
    from PathScripts.PathPostProcessor import PostProcessor

    processor = PostProcessor.load("linuxcnc")
    processor.export(JOBS[name](), str(OUT / f"{name}.{option_set}.ngc"),
                     OPTION_SETS[option_set])


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    chosen = os.environ.get("FREECAD_REFERENCE_JOBS")  # e.g. "modal": those jobs alone
    for name, job in JOBS.items():
        if chosen and name not in chosen.split(","):
            continue
        write_forms(name, job())
        for option_set in OPTION_SETS:
            env = dict(os.environ, FREECAD_REFERENCE_EXPORT=f"{name}:{option_set}")
            subprocess.run(["freecadcmd", __file__], env=env, check=True,
                           stdout=subprocess.DEVNULL)
            if not (OUT / f"{name}.{option_set}.ngc").exists():
                sys.exit(f"linuxcnc_post wrote no {name}.{option_set}.ngc")


# freecadcmd names a script's module after its file; scripts/freecad_post_job.py loads
# this one under another name for its jobs alone
_request = os.environ.get("FREECAD_REFERENCE_EXPORT")
if _request:
    export(*_request.split(":"))
elif __name__ == FilePath(__file__).stem:
    main()
