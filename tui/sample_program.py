"""The sample program on the main screen: read, posted, marked, traced.

A mixin of :class:`~tui.main_screen.MainScreen`, kept apart so each module stays
readable.  A short program is posted at once, with the keystroke; a long one in a
child process (:mod:`tui.posting`) while the previous program stays on screen,
marked "posting…", and the newest edit wins.  The program's marks come from its
index, never from a pass over its lines, so following the grid's cursor costs the
same for 60 lines and for 200 000; tracing a line of a long program runs in the
child process too.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from textual import work
from textual.worker import get_current_worker

from postdsl import api
from tui.command_table import ITEM_COLUMN
from tui.model import TableRef, redirect_of
from tui.posting import Job, Outcome, run_job
from tui.program_view import BLOCK, PLAIN, TABLE, ProgramView
from tui.sample import Chunk, Program, Sample, post_sample, sample_for
from tui.sample_picker import SamplePicker
from tui.trace_pane import TracePane, cell_of

if TYPE_CHECKING:
    from tui.document import PostDocument
    from tui.screen_host import ScreenHost as _Host
else:
    # at run time the mixin adds its methods only: MainScreen brings the Screen
    _Host = object

#: seconds between two "posting… N lines so far" in the program's title
PROGRESS_EVERY = 0.5


class SampleProgram(_Host):
    """The main screen's sample program: posting, marks, trace, the sample picker."""

    # the main screen's state this part reads and changes
    doc: PostDocument
    current: TableRef
    sample: Sample
    program: Program
    sample_path: Path | None
    posting: bool
    overrides: dict[str, dict[str, Any]]

    def _read(self, path: Path | None) -> None:
        self.sample = sample_for(path)

    @property
    def program_lines(self) -> list[str]:
        """The posted sample program's text lines (the settings editor's example)."""
        return self.program.texts

    @property
    def program_error(self) -> str | None:
        return self.program.error

    @property
    def program_view(self) -> ProgramView:
        """The program as shown (the settings editor's example is its start)."""
        return self.query_one(ProgramView)

    def _first_table(self) -> TableRef:
        """Open where the machining starts: the first command of the sample program (after
        its start and comments) that has a table, so the previews show real blocks."""
        commands = self.doc.model.commands
        for command in self.sample.commands:
            if command.name not in ("program_start", "operation", "comment") and \
                    command.name in commands:
                return TableRef("command", command.name)
            cycle = getattr(command, "cycle", None)
            if command.name == "custom_cycle" and cycle in self.doc.model.custom_cycles:
                return TableRef("cycle", str(cycle))
        return TableRef("command", "program_start")

    def _post_now(self) -> Program:
        return post_sample(self.doc.post, len(self.doc.problems), self.sample)

    def repost(self) -> None:
        """Post the sample again: at once when it is short, else in another process."""
        self.workers.cancel_group(self, "program")
        if self.sample.small or self.doc.post is None or self.sample.path is None or \
                self.sample.error:
            self.posting = False
            self.program = self._post_now()  # or why it cannot be posted
            self.show_program()
            self.replot()
            return
        self.posting = True
        self._post_in_worker(Job(self.doc.text, self.doc.file, self.sample.path,
                                 self.sample.name, api.posting_time()))

    @work(exclusive=True, thread=True, group="program")
    def _post_in_worker(self, job: Job) -> None:
        """Stream the program from the posting process; show it as it grows."""
        worker = get_current_worker()
        program = Program()
        shown = time.monotonic()
        for message in run_job(job, lambda: worker.is_cancelled):
            if isinstance(message, Outcome):
                program.error, program.first, program.count = \
                    message.error, message.first, message.count
                if not worker.is_cancelled:
                    self.app.call_from_thread(self._posted, job, program, message.used)
                return
            # a program job's child sends chunks of lines (segments are the plot's)
            program.extend(cast(Chunk, message))
            if not worker.is_cancelled and time.monotonic() - shown > PROGRESS_EVERY:
                shown = time.monotonic()
                self.app.call_from_thread(self._progress, job, len(program))

    def _progress(self, job: Job, count: int) -> None:
        if job.sample == self.sample.path and self.posting:
            self.query_one(ProgramView).border_title = \
                f"Program · {self.sample.name} · posting… {count} lines so far"

    def _posted(self, job: Job, program: Program, used: frozenset[str]) -> None:
        if job.sample != self.sample.path or job.post_text != self.doc.text:
            return  # a newer edit or sample is being posted
        self.sample.used_names = used
        self.program = program
        self.posting = False
        self.show_program(scroll=True)
        self.show_commands()
        self.replot()

    def watch_posting(self) -> None:
        self.show_program_title()

    def watch_sample_path(self, path: Path | None) -> None:
        """Another sample chosen: read it, post it, show where the machining starts."""
        self.workers.cancel_group(self, "program")
        self._read(path)
        self.program = Program()
        self.overrides.clear()
        self.show_commands()
        self.repost()
        self.show_program(scroll=True)
        self.notify(f"sample program: {self.sample.name}"
                    + (f" — {self.sample.error}" if self.sample.error else ""),
                    severity="error" if self.sample.error else "information")

    def _marker(self) -> tuple[Any, int | None, int]:
        """How to mark a program line for the current table and block, the line to scroll
        to and how many lines the table wrote (from the program's index: no pass over it)."""
        ref = self.current
        redirect = redirect_of(self.doc.model, ref)
        highlight = self._block_range()
        program = self.program
        first, count = program.first, program.count
        if ref.kind == "structure":
            return (lambda index: PLAIN), None, 0
        tables, commands, blocks = program.tables, program.commands, program.blocks
        name = ref.name
        if ref.kind == "cycle":
            def ours(index: int) -> bool:
                return commands[index] == "custom_cycle" and tables[index] == name
            total, start = count[name], first.get(name)
        elif redirect:
            def ours(index: int) -> bool:
                return commands[index] == name
            key = ("command", name)
            total, start = count[key], first.get(key)
        else:
            def ours(index: int) -> bool:
                return tables[index] == name
            total, start = count[name], first.get(name)
        if not redirect:
            block_starts = [first[(name, b)] for b in highlight if (name, b) in first]
            if block_starts:
                start = min(block_starts)

        def mark(index: int) -> int:
            if not ours(index):
                return PLAIN
            return BLOCK if blocks[index] in highlight and not redirect else TABLE

        return mark, start, total

    def show_program(self, scroll: bool = False) -> None:
        """The sample program with the current table's (and block's) lines marked."""
        view = self.query_one(ProgramView)
        mark, start, _total = self._marker()
        view.show(self.program.texts, mark, message=self.program.error or "",
                  scroll_to=start if scroll else None)
        self.show_program_title()
        if view.has_focus:
            self.trace(view.cursor)

    def show_program_title(self) -> None:
        view = self.query_one(ProgramView)
        _mark, _start, total = self._marker()
        count = len(self.program)
        title = f"Program · {self.sample.name} · {count} line{'s' if count != 1 else ''}"
        view.border_title = title + (" · posting…" if self.posting else "")
        view.border_subtitle = f"{total} from {self.current.title}" if total else ""

    def on_program_view_cursor_moved(self, event: ProgramView.CursorMoved) -> None:
        self.trace(event.index)

    def on_program_view_word_chosen(self, event: ProgramView.WordChosen) -> None:
        pane = self.query_one(TracePane)
        if pane.traced is not None and pane.traced.number == event.index + 1:
            pane.choose(event.column)

    def on_program_view_cell_wanted(self, event: ProgramView.CellWanted) -> None:
        pane = self.query_one(TracePane)
        traced = pane.traced
        if traced is None or traced.number != event.index + 1:
            self.notify("the line is still being traced: press enter again in a moment",
                        severity="warning")
            return
        cell = cell_of(traced, event.column)
        if cell is None:
            self.notify("no cell wrote that word", severity="warning")
            return
        ref, block, item = cell
        self.go_to_cell(ref, block, ITEM_COLUMN + item if item is not None else 0)

    def trace(self, index: int) -> None:
        """Show where line ``index`` of the program comes from (in another process when the
        program is long: tracing a line posts the program up to it)."""
        pane = self.query_one(TracePane)
        post = self.doc.post
        if post is None or not len(self.program) or self.sample.error:
            pane.show_note(self.program.error or "no program to trace")
            return
        if index >= len(self.program):
            return
        if self.sample.small or self.sample.path is None:
            self._traced(api.trace_line(post, self.sample.commands, index + 1,
                                        cl_file=self.sample.name), post)
            return
        pane.show_note(f"tracing line {index + 1}…")
        self._trace_in_worker(Job(self.doc.text, self.doc.file, self.sample.path,
                                  self.sample.name, api.posting_time(), trace=index + 1), post)

    @work(exclusive=True, thread=True, group="trace")
    def _trace_in_worker(self, job: Job, post: api.CompiledPost) -> None:
        worker = get_current_worker()
        for message in run_job(job, lambda: worker.is_cancelled):
            if isinstance(message, Outcome) and not worker.is_cancelled:
                if message.error:
                    self.app.call_from_thread(self.query_one(TracePane).show_note,
                                              message.error)
                else:
                    self.app.call_from_thread(self._traced, message.traced, post)

    def _traced(self, traced: api.TracedLine | None, post: api.CompiledPost) -> None:
        view = self.query_one(ProgramView)
        if traced is None or traced.number != view.cursor + 1:
            return
        pane = self.query_one(TracePane)
        pane.show_trace(traced, api.explain_text(post, traced, self.sample.name), view.column)
        view.set_words(traced.number - 1, [(w.start, w.end) for w in traced.words])

    def action_choose_sample(self) -> None:
        """The sample picker: the machine's corpus programs, the showcase first."""
        programs = api.corpus_programs(self.doc.path)
        if self.sample_path is not None and self.sample_path not in programs:
            programs.insert(0, self.sample_path)
        if not programs:
            self.notify("no sample programs: corpus.yaml lists none for this machine and "
                        "there is no bundled example (start the editor with --cl FILE)",
                        severity="warning")
            return

        def chosen(path: Path | None) -> None:
            if path is not None and path != self.sample_path:
                self.sample_path = path

        self.app.push_screen(SamplePicker(programs, self.sample_path), chosen)
