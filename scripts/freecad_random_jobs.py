"""Random FreeCAD jobs and FreeCAD 0.20's linuxcnc_post output of them, for tests/test_linuxcnc.py.

Run with FreeCAD's command-line interpreter (Debian package freecad-python3)::

    freecadcmd scripts/freecad_random_jobs.py

It writes, under tests/data/freecad/random/, for seeds 0 to RAND_N - 1 (default 6):
``rN.dump.txt`` (the job's dump) and ``rN.SET.ngc`` (linuxcnc_post's output) for the
option sets of SETS -- the modal ones, where FreeCAD compares each word with the last
value given.  A job is an operation of 40 random steps from a fixed seed: straight cuts
whose coordinates move by whole and by tiny amounts (0.0003: a value written again
although its text is the same), arcs, rapids, and groups of drilling holes (G81, G82,
G83, G98 or G99), some with G0 moves to each hole and some one cycle after the other.
Coordinates keep at most five significant digits, as in scripts/freecad_reference.py
(the dump's precision), and none rounds to zero but zero itself (see q).  Arc radii
are not on a decimal tie at three decimals (1.2345): the CL keeps an arc's absolute
centre, so its I comes back as centre - start, which can fall on the other side of the
tie than FreeCAD's own I.

Each export runs in a process of its own (FreeCAD's posts keep state between exports).
"""

import importlib.util
import os
import random
import subprocess
from pathlib import Path as FP

spec = importlib.util.spec_from_file_location(
    "freecad_reference_jobs", FP(__file__).resolve().parent / "freecad_reference.py"
)
ref = importlib.util.module_from_spec(spec)
spec.loader.exec_module(ref)
C = ref.C
OUT = FP(__file__).resolve().parent.parent / "tests" / "data" / "freecad" / "random"


def q(v):
    """At most 5 significant digits; none between -0.0005 and 0.0005 but 0: FreeCAD writes
    a negative value that rounds to zero as -0.000, postdsl's formats as 0.000 (a
    difference no control reads)."""
    return 0.0 if abs(v) < 0.0005 else float(f"{v:.5g}")


def job(seed):
    rnd = random.Random(seed)
    tc = ref._ToolController(rnd.choice([300.0, 600.0, 900.0]), rnd.choice([120.0, 300.0]))
    body = [C("G0", Z=15.0), C("G0", X=0.0, Y=0.0), C("G0", Z=2.0)]
    x, y, z = 0.0, 0.0, 2.0
    for _ in range(40):
        kind = rnd.random()
        if kind < 0.45:
            x = q(x + rnd.choice([0, 0, 5, -5, 2.5, 0.00031, -0.0004, 1.1834]))
            y = q(y + rnd.choice([0, 0, 5, -5, 0.0003, 3.3333]))
            z = q(rnd.choice([z, z, -1.1834, -1.1831, -1.1828, -2.0, -0.5, z + 0.0002]))
            body.append(C("G1", X=x, Y=y, Z=z))
        elif kind < 0.6:
            r = rnd.choice([2.0, 2.5, 1.25])
            nx = q(x + 2 * r)
            body.append(C(rnd.choice(["G2", "G3"]), I=r, J=0.0, K=0.0, X=nx, Y=y, Z=z))
            x = nx
        elif kind < 0.7:
            x = q(x + rnd.choice([0, 3, -3]))
            y = q(y + rnd.choice([0, 4, 1.0001]))
            body.append(C("G0", X=x, Y=y))
        elif kind < 0.8:
            z = q(rnd.choice([2.0, 5.0, z]))
            body.append(C("G0", Z=z))
        else:
            cyc = rnd.choice(["G81", "G82", "G83"])
            body.append(C("G0", Z=5.0))
            z = 5.0
            body.append(C(rnd.choice(["G98", "G99"])))
            bottom = rnd.choice([-8.0, -8.0002, -5.0])
            for k in range(rnd.randint(1, 4)):
                hx, hy = q(10.0 + 10 * k), q(rnd.choice([10.0, 20.0]))
                if rnd.random() < 0.4:
                    body += [C("G0", X=hx, Y=hy), C("G0", Z=3.0)]
                args = dict(X=hx, Y=hy, Z=bottom, R=1.0)
                if cyc == "G82":
                    args["P"] = 0.5
                if cyc == "G83":
                    args["Q"] = rnd.choice([2.0, 2.5])
                body.append(C(cyc, **args))
                x, y = hx, hy
            body.append(C("G80"))
            body.append(C("G0", Z=5.0))
            z = 5.0
    return [
        ref.fixture(),
        ref.tool(1, "TC: Endmill 6mm", 5000.0),
        ref.operation(f"Op{seed}", body, tc, 15.0),
    ]


#: option set name -> linuxcnc_post arguments (as in scripts/freecad_reference.py)
SETS = {
    "modal": "--no-show-editor --no-header --modal",
    "axis_modal": "--no-show-editor --no-header --axis-modal",
    "modal_axis_modal": "--no-show-editor --no-header --modal --axis-modal",
    "default": "--no-show-editor --no-header",
}

req = os.environ.get("RAND_EXPORT")
if req:
    seed, s = req.split(":")
    from PathScripts.PathPostProcessor import PostProcessor

    PostProcessor.load("linuxcnc").export(job(int(seed)), str(OUT / f"r{seed}.{s}.ngc"), SETS[s])
else:
    OUT.mkdir(parents=True, exist_ok=True)
    for seed in range(int(os.environ.get("RAND_N", "6"))):
        objs = job(seed)
        dump = []
        for o in objs:
            dump.append(f"(Path: {o.Label})")
            dump += [str(c) for c in o.Path.Commands]
        (OUT / f"r{seed}.dump.txt").write_text("\n".join(dump) + "\n")
        for s in SETS:
            subprocess.run(
                ["freecadcmd", __file__],
                env=dict(os.environ, RAND_EXPORT=f"{seed}:{s}"),
                check=True,
                stdout=subprocess.DEVNULL,
            )
