"""Post a reference job through FreeCAD's own post mechanism, for tests/test_freecad_post.py.

Run with FreeCAD's command-line interpreter; ``freecadcmd`` passes no arguments to a
script, so the request is in the environment: ``POSTDSL_REQUESTS`` names a JSON file of
exports, each ``{"job", "post", "args", "nc", "dump"}``:

* ``job``: a job of ``scripts/freecad_reference.py`` (``pocket``, ``helix``, …), or
  ``refused_feed`` (the pocket with no feed on its tool controller) or ``refused_tool``
  (the pocket with tool 1000);
* ``post``: the post's name in FreeCAD's list (``postdsl``);
* ``args``: the post's argument string, as a Job's PostProcessorArgs;
* ``nc``: the NC file to write;
* ``dump``: where to write the job's dump (``str(Path.Command)``), the form
  ``postdsl post`` is compared on.

The post is loaded as FreeCAD's Post Process command loads it
(``PathPostProcessor.PostProcessor.load``: the post search path, the user's macro folder
first) and called as that command calls it (``processor.export(objects, filename,
args)``), with the object list PathPost builds for a Job (fixture, tool controller,
operations).  Each result is printed as ``RESULT <nc> <'text' or 'none'>``.
"""

import importlib.util
import json
import os
from pathlib import Path as FilePath

import Path
from PathScripts.PathPostProcessor import PostProcessor

_spec = importlib.util.spec_from_file_location(
    "freecad_reference_jobs", FilePath(__file__).resolve().parent / "freecad_reference.py")
jobs = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(jobs)


def refused_feed() -> list:
    """A pocket whose tool controller has no feed: F 0 on a cutting move."""
    objects = jobs.pocket_job()
    operation = objects[-1]
    commands = [Path.Command(c.Name, {**c.Parameters, "F": 0.0}) if c.Name == "G1" else c
                for c in operation.Path.Commands]
    operation.Path = Path.Path(commands)
    return objects


def refused_tool() -> list:
    """A pocket whose tool controller has tool number 1000."""
    objects = jobs.pocket_job()
    objects[1] = jobs.tool(1000, "TC: Endmill 6mm", 5000.0)
    return objects


BUILDERS = {**jobs.JOBS, "refused_feed": refused_feed, "refused_tool": refused_tool}

for request in json.loads(FilePath(os.environ["POSTDSL_REQUESTS"]).read_text()):
    objects = BUILDERS[request["job"]]()
    dump = []
    for obj in objects:
        dump.append(f"(Path: {obj.Label})")
        dump += [str(command) for command in obj.Path.Commands]
    FilePath(request["dump"]).write_text("\n".join(dump) + "\n")
    processor = PostProcessor.load(request["post"])
    result = processor.export(objects, request["nc"], request["args"])
    print("RESULT", request["nc"], "text" if isinstance(result, str) else "none", flush=True)
