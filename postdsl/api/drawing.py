"""Drawing: a program's motion as a toolpath (the control model's replay as segments),
an SVG picture of it, and the comparison review makes of two.

Apart from posting and verifying because drawing is the one task that needs the toolpath
and its pictures (imported when drawn): ``postdsl plot``, the editor's backplot, review.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from datetime import datetime
from pathlib import Path
from typing import TYPE_CHECKING

from postdsl.api.files import _input_file, _write_output
from postdsl.api.loading import Options, load_post
from postdsl.api.posting import post_commands
from postdsl.api.verifying import _nc_input
from postdsl.cl.model import CLCommand, ToolChange
from postdsl.cl.readers import read_cl
from postdsl.compile.compiler import CompiledPost
from postdsl.compile.runtime import NCLine
from postdsl.errors import Location, PostError

if TYPE_CHECKING:
    from postdsl.check.toolpath import LineSource, Toolpath


def toolpath_of_lines(post: CompiledPost, lines: Sequence[NCLine],
                      tolerance: float | None = None,
                      tool_diameters: Mapping[int, float] | None = None) -> Toolpath:
    """Replay posted lines through the post's control model into drawable segments.

    Each segment names its NC line and the CL command and table that wrote it
    (see :mod:`postdsl.check.toolpath`).  A line the control model refuses ends the
    path: ``stopped`` says which and why, the segments before it are kept.
    A post without ``machine.control`` is a PostError.  ``tolerance`` (mm) is how far
    the chords drawn for an arc may stray from it (default ``toolpath.ARC_TOLERANCE``).
    ``tool_diameters`` (the CL's) let a post in the cutter_compensation mode ``control``
    draw the tool centre the control makes of the contour; without them, or in the other
    modes, the radius registers count as 0 (the programmed path).
    """
    # the toolpath and the control models are not needed to post: imported when drawn
    from postdsl.check.controls import control_model
    from postdsl.check.toolpath import ARC_TOLERANCE, LineSource
    from postdsl.check.toolpath import collect as collect_toolpath

    control = post.machine.control
    if control is None:
        raise PostError("the post declares no machine/control: a toolpath is the program "
                        "replayed through the control model", Location(post.file))
    model = control_model(control, calculator_input=post.machine.calculator_input)
    if post.machine.cutter_compensation == "control" and tool_diameters:
        model.configure_compensation("control", dict(tool_diameters))
    model.set_kinematics(post.machine.kinematics)

    def source(number: int) -> LineSource | None:
        if not 1 <= number <= len(lines):
            return None
        line = lines[number - 1]
        return LineSource(line.command, line.table, line.cl_line)

    inputs = (_nc_input(post, number, line) for number, line in enumerate(lines, start=1))
    # a rapid carries no tooling: the plane in force is the model's while it yields it
    return collect_toolpath(model.replay(inputs), source,
                            ARC_TOLERANCE if tolerance is None else tolerance,
                            lambda: model.frame)


def toolpath(post: CompiledPost, commands: Iterable[CLCommand], *, cl_file: str = "<cl>",
             now: datetime | None = None) -> tuple[list[NCLine], Toolpath]:
    """Post CL commands and replay the program: (the NC lines, their toolpath)."""
    commands = commands if isinstance(commands, Sequence) else list(commands)
    lines = post_commands(post, commands, cl_file=cl_file, now=now)
    diameters = {c.tool_number: c.tool_diameter for c in commands
                 if isinstance(c, ToolChange)}
    return lines, toolpath_of_lines(post, lines, tool_diameters=diameters)


def toolpath_file(machine: str | Path, cl_path: str | Path, fmt: str | None = None,
                  feed_units: str | None = None, options: Options | None = None) \
        -> tuple[CompiledPost, Toolpath]:
    """Post a CL file with a machine and replay it: (the post, the toolpath)."""
    post = load_post(machine, options)
    _, path = toolpath(post, read_cl(cl_path, fmt, feed_units), cl_file=str(cl_path))
    return post, path


def plot_file(machine: str | Path, cl_path: str | Path, output: str | Path,
              views: Sequence[str] | None = None, fmt: str | None = None,
              feed_units: str | None = None, options: Options | None = None) -> Toolpath:
    """Draw a CL file's toolpath as SVG (``views``: xy, xz, yz, iso) into ``output``, atomically.

    Returns the toolpath; when the control model refused a line (``stopped``)
    the picture shows the path up to it and says so.  ``views`` default to all four.
    """
    from postdsl.check.svgplot import ALL_VIEWS, render_svg  # drawing only, not posting

    views = ALL_VIEWS if views is None else views
    post, path = toolpath_file(machine, cl_path, fmt, feed_units, options)
    title = f"{post.machine.name or Path(str(machine)).stem}: {Path(cl_path).name}"
    _write_output(output, render_svg(path, views, title), "the picture",
                  keep=((_input_file(cl_path), "the CL program being drawn"),
                        (post.file, "the post")))
    return path


def same_motion(post: CompiledPost, old: Toolpath, new: Toolpath) -> bool:
    """Whether two toolpaths move the tool alike, within the machine's resolution."""
    from postdsl.check.toolpath import motion_key  # comparing toolpaths (review) only

    resolution = post.machine.resolution or 0.001
    return (old.stopped is None) == (new.stopped is None) and \
        motion_key(old.segments, resolution) == motion_key(new.segments, resolution)
