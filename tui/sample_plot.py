"""The sample program's toolpath on the main screen: built off the UI thread, highlighted.

A mixin of :class:`~tui.main_screen.MainScreen`.  The path is the posted program
replayed through the machine's control model (``api.toolpath``), the picture
``postdsl plot`` draws, so the backplot shows what the text makes the machine do.
A short sample is replayed in a thread worker (a few milliseconds of work); a long
one in the posting process (:mod:`tui.posting`), after its lines have arrived, so
the two never compete for the core the keys need.  The newest edit wins: a path
built for an older post or sample is dropped.

The moves of the table (or, for a redirected command, the command) selected in
the grid are drawn in the highlight colour; which NC lines those are is indexed
once per path in the worker, so following the grid costs a dictionary look-up.
"""

from __future__ import annotations

import gc
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from textual import work
from textual.worker import get_current_worker

from postdsl import api
from tui.backplot import Backplot
from tui.model import TableRef, redirect_of
from tui.posting import Job, Outcome, run_job
from tui.sample import Sample

if TYPE_CHECKING:
    from tui.document import PostDocument
    from tui.screen_host import ScreenHost as _Host
else:
    # at run time the mixin adds its methods only: MainScreen brings the Screen
    _Host = object


@dataclass
class PlottedPath:
    """A toolpath and, per table and per CL command, the NC lines of its moves."""

    path: api.Toolpath
    post_text: str
    sample: Path | None
    by_table: dict[str, frozenset[int]] = field(default_factory=dict)
    by_command: dict[str, frozenset[int]] = field(default_factory=dict)


def index_path(path: api.Toolpath, post_text: str, sample: Path | None) -> PlottedPath:
    """The path with its highlight index (run in a worker: one pass over every segment)."""
    tables: dict[str, set[int]] = defaultdict(set)
    commands: dict[str, set[int]] = defaultdict(set)
    for segment in path.segments:
        tables[segment.table].add(segment.nc_line)
        commands[segment.command].add(segment.nc_line)
    return PlottedPath(path, post_text, sample,
                       {name: frozenset(lines) for name, lines in tables.items()},
                       {name: frozenset(lines) for name, lines in commands.items()})


class SamplePlot(_Host):
    """The main screen's backplot: the sample program's toolpath, the selection lit."""

    # the main screen's state this part reads
    doc: PostDocument
    current: TableRef
    sample: Sample
    plotted: PlottedPath | None

    def replot(self) -> None:
        """Build the sample's toolpath again (after the program was posted)."""
        self.workers.cancel_group(self, "toolpath")
        plot = self.query_one(Backplot)
        post = self.doc.post
        if post is None:
            plot.show_note("the post has problems: nothing to replay")
            return
        if post.machine.control is None:
            plot.show_note("the post declares no machine/control: a toolpath is the program "
                           "replayed through the control model")
            return
        if self.sample.path is None or self.sample.error:
            plot.show_note(self.sample.error or "no sample program")
            return
        if self.sample.small:
            self._plot_in_thread(post, self.sample.commands, self.doc.text, self.sample)
        else:
            if plot.segments or plot.note:
                plot.show_note("replaying the program…")
            self._plot_in_child(Job(self.doc.text, self.doc.file, self.sample.path,
                                    self.sample.name, api.posting_time(), toolpath=True))

    @work(exclusive=True, thread=True, group="toolpath", exit_on_error=False,
          description="replaying the sample program")
    def _plot_in_thread(self, post: api.CompiledPost, commands: list[api.CLCommand],
                        post_text: str, sample: Sample) -> None:
        worker = get_current_worker()
        try:
            _, path = api.toolpath(post, commands, cl_file=sample.name)
        except (api.CLError, api.PostError) as exc:
            reason = str(exc)
        except Exception as exc:  # an engine bug: say so in the pane, keep the editor
            reason = f"internal error while replaying: {type(exc).__name__}: {exc}"
        else:
            plotted = index_path(path, post_text, sample.path)
            if not worker.is_cancelled:
                self.app.call_from_thread(self._plotted, plotted)
            return
        if not worker.is_cancelled:
            self.app.call_from_thread(self._not_plotted, post_text, sample.path, reason)

    @work(exclusive=True, thread=True, group="toolpath", exit_on_error=False,
          description="replaying the sample program in the posting process")
    def _plot_in_child(self, job: Job) -> None:
        worker = get_current_worker()
        segments: list[api.Segment] = []
        outcome: Outcome | None = None
        # a million small objects (segments, their points) arrive: the collector's passes
        # over them would hold the interpreter lock for a quarter of a second at a time, so
        # it waits, and the path, which holds no cycles, is kept out of its later passes
        gc.disable()
        try:
            for message in run_job(job, lambda: worker.is_cancelled):
                if isinstance(message, Outcome):
                    outcome = message
                    break
                segments.extend(message)  # type: ignore[arg-type]  # a plot job's child sends segments
        finally:
            gc.freeze()
            gc.enable()
        if outcome is None or worker.is_cancelled:
            return
        if outcome.error:
            self.app.call_from_thread(self._not_plotted, job.post_text, job.sample,
                                      outcome.error)
            return
        plotted = index_path(api.Toolpath(segments, outcome.stopped), job.post_text,
                             job.sample)
        self.app.call_from_thread(self._plotted, plotted)

    def _current(self, post_text: str, sample: Path | None) -> bool:
        return post_text == self.doc.text and sample == self.sample.path

    def _not_plotted(self, post_text: str, sample: Path | None, reason: str) -> None:
        if self._current(post_text, sample):
            self.plotted = None
            self.query_one(Backplot).show_note(reason)

    def _plotted(self, plotted: PlottedPath) -> None:
        if not self._current(plotted.post_text, plotted.sample):
            return  # a newer edit or sample is being replayed
        self.plotted = plotted
        plot = self.query_one(Backplot)
        plot.highlight = self._plot_highlight()
        plot.show_path(plotted.path)

    def _plot_highlight(self) -> frozenset[int]:
        """The NC lines of the selected table's moves (a redirected command's own)."""
        plotted = self.plotted
        ref = self.current
        if plotted is None or ref.kind == "structure":
            return frozenset()
        if redirect_of(self.doc.model, ref):
            return plotted.by_command.get(ref.name, frozenset())
        return plotted.by_table.get(ref.name, frozenset())

    def show_plot_highlight(self) -> None:
        """Light the selected table's moves in the backplot."""
        self.query_one(Backplot).highlight = self._plot_highlight()

