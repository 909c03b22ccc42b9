"""Before/after toolpath pictures for a review: has a post change moved the tool?

A review says which NC lines a post change alters and, through its verdicts, whether
the motion changed; for a program whose motion changed, both postings are replayed
through the machine's control model (``api.toolpath_of_lines``) and drawn as two SVG
pictures.

A pull-request comment cannot inline SVG text (hosts strip it), so the pictures are
written as files into a folder and the markdown links them with relative paths:
commit the folder with the comment's source, or upload it as a CI artifact beside it.
"""
from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

from postdsl import api
from postdsl.check.svgplot import render_svg


@dataclass(frozen=True)
class MotionPlots:
    """Whether a changed program moves differently, and its two pictures when it does."""

    changed: bool
    #: SVG text before and after the change (None when the motion is the same)
    before: str | None = None
    after: str | None = None


def compare_motion(old_post: api.CompiledPost, old_lines: Sequence[api.NCLine],
                   new_post: api.CompiledPost, new_lines: Sequence[api.NCLine],
                   title: str) -> MotionPlots | None:
    """Replay both postings; the pictures when the motion differs (None: a side has no control).

    A program the control model refuses on one side only has changed motion.
    """
    if old_post.machine.control is None or new_post.machine.control is None:
        return None
    old = api.toolpath_of_lines(old_post, old_lines)
    new = api.toolpath_of_lines(new_post, new_lines)
    if api.same_motion(new_post, old, new):
        return MotionPlots(False)
    return MotionPlots(True, render_svg(old, title=f"{title} (before)"),
                       render_svg(new, title=f"{title} (after)"))


def _slug(text: str) -> str:
    slug = re.sub(r"[^A-Za-z0-9]+", "-", text).strip("-").lower()
    return slug or "program"


@dataclass(frozen=True)
class PlotFiles:
    """Where a program's pictures were written, as the links the markdown gives."""

    before: str
    after: str


def write_plots(pairs: Iterable[tuple[str, str, str, str]], folder: str | Path
                ) -> Mapping[tuple[str, str], PlotFiles]:
    """Write (machine, program, before SVG, after SVG) pictures into ``folder``, atomically.

    Files are named after the machine and the program (made safe for any file
    system, numbered when two programs give one name).  Each link is
    ``folder`` as given joined with the file name, in POSIX form: relative to
    the folder the markdown is saved in when ``folder`` is given relative to it.
    """
    target = Path(folder)
    try:
        target.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise api.CLError(f"cannot create the plots folder: {exc.strerror or exc}",
                          api.Location(str(folder))) from None
    links: dict[tuple[str, str], PlotFiles] = {}
    used: set[str] = set()
    for machine, program, before, after in pairs:
        stem = f"{_slug(machine)}-{_slug(program)}"
        name, number = stem, 1
        while name in used:
            number += 1
            name = f"{stem}-{number}"
        used.add(name)
        files = []
        for side, text in (("before", before), ("after", after)):
            path = target / f"{name}-{side}.svg"
            try:
                api.write_atomic(path, text)
            except (OSError, ValueError) as exc:
                raise api.CLError(f"cannot write a plot: {exc}", api.Location(str(path))) \
                    from None
            files.append(str(PurePosixPath(*Path(folder).parts) / path.name))
        links[(machine, program)] = PlotFiles(files[0], files[1])
    return links
