"""The review screen (f5): what the unsaved edits do to the NC programs, before saving.

``postdsl review`` shows a post change by its effect on a corpus of programs,
but only once the change is in the working tree.  This screen shows the same
thing one step earlier: the machine's corpus programs (those corpus.yaml
lists for it; else the editor's sample program) posted with the file as it
is saved and with the document as it is now, compared by
:func:`postdsl.review.review_texts` — the same verdicts (with the first motion
difference located), unified diffs with
block numbers kept and renumbering-only detection as the command line.

Posting a corpus takes a noticeable fraction of a second, so it runs in a
worker thread behind a loading indicator, and again after every edit, undo
or redo while the screen is open; a result is shown only if the texts it was
posted from are still the saved and the current ones, so a slow, stale run
can never overwrite a newer one.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

from rich.segment import Segment
from rich.style import Style
from rich.text import Text
from textual import on, work
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Vertical, VerticalScroll
from textual.events import Resize
from textual.geometry import Size
from textual.screen import Screen
from textual.scroll_view import ScrollView
from textual.strip import Strip
from textual.widgets import DataTable, Footer, Header, Static
from textual.worker import Worker, WorkerState

from postdsl import api, review
from postdsl.review import Program, ProgramDiff, results
from tui.dialogs import focus_now
from tui.document import PostDocument
from tui.messages import DocumentView
from tui.model import problem_text
from tui.tables import fill

#: verdict -> its style in the program list: what moves differently stands out, what
#: only changed its text is calm, what is the same is dim
VERDICT_STYLES: dict[str, str] = {
    review.MOTION: "bold yellow",
    review.NEWLY_REFUSED: "bold red",
    review.NEWLY_POSTING: "green",
    review.FORMAT_ONLY: "cyan",
    results.RENUMBERING: "cyan",
    results.SAME: "dim",
    results.REFUSED_BY_BOTH: "red",
    results.NOT_REPLAYED: "bold yellow",
    results.FAILED: "bold red",
}

NO_UNSAVED_CHANGES = "no unsaved changes"
NO_OUTPUT_CHANGES = "no output changes"


@dataclass(frozen=True)
class Corpus:
    """The programs to post, and where they come from (said in the screen's title)."""

    programs: list[Program]
    source: str
    warning: str | None = None


@dataclass
class Outcome:
    """One posting of the corpus: the texts it compared, and the diffs or why not."""

    saved: str
    unsaved: str
    corpus: Corpus
    diffs: list[ProgramDiff] = field(default_factory=list)
    error: str | None = None


def corpus_of(doc: PostDocument, sample: Path | None) -> Corpus:
    """The machine's corpus programs, else the editor's sample program.

    Reads corpus.yaml (and may ask git where the repository is), so it runs in
    the worker, not on the UI thread.
    """
    machine = doc.path.stem
    warning = None
    try:
        programs = review.corpus_for_machine(doc.path)
    except review.ReviewError as exc:
        programs, warning = [], f"corpus.yaml cannot be used: {exc}"
    if programs:
        count = len(programs)
        return Corpus(programs, f"the {count} program{'s' if count != 1 else ''} corpus.yaml "
                                f"lists for {machine}", warning)
    if sample is not None:
        return Corpus([Program(sample.name, sample)],
                      f"the sample program {sample.name} (corpus.yaml lists no programs for "
                      f"{machine})", warning)
    return Corpus([], f"no programs: corpus.yaml lists none for {machine} and the editor has "
                      f"no sample program (start it with --cl FILE)", warning)


def verdict_of(diff: ProgramDiff) -> str:
    """The program's verdict, as ``postdsl review`` says it: whether anything that moves
    changed (``motion changed``) or only the text (``format only``, ``renumbering
    only``) is what a post's author needs to know first, more than that lines differ."""
    return diff.verdict or results.verdict_of(diff.status)


def label_of(diff: ProgramDiff) -> Text:
    """The verdict of a program in the list."""
    verdict = verdict_of(diff)
    return Text(verdict, style=VERDICT_STYLES.get(verdict, "bold"))


def counts_of(diff: ProgramDiff) -> str:
    """The size of a program's change, for the list: ``+3 -3`` or ``23 numbers``."""
    if diff.status == review.RENUMBERED:
        return f"{diff.renumbered} numbers"
    if diff.added or diff.removed:
        return f"+{diff.added} -{diff.removed}"
    return ""


def summary_of(diffs: Sequence[ProgramDiff]) -> str:
    """One line over every program, from the review's own counts."""
    counts = review.ReviewResult("saved", "", list(diffs)).summary()
    programs = f"{counts['programs']} program{'s' if counts['programs'] != 1 else ''}"
    changed = counts["changed_programs"] - counts[review.RENUMBERED]
    if not counts["changed_programs"] and not counts[review.UNPOSTABLE]:
        return f"{NO_OUTPUT_CHANGES} · {programs} unchanged"
    parts = []
    if changed:
        parts.append(f"{changed} changed (+{counts['added_lines']} -{counts['removed_lines']} "
                     f"lines)")
    if counts[review.RENUMBERED]:
        parts.append(f"{counts[review.RENUMBERED]} renumbering only")
    if counts[review.NOW_FAILS]:
        parts.append(f"{counts[review.NOW_FAILS]} cannot be posted any more")
    if counts[review.UNPOSTABLE]:
        parts.append(f"{counts[review.UNPOSTABLE]} cannot be posted by either version")
    if counts[review.UNCHANGED]:
        parts.append(f"{counts[review.UNCHANGED]} unchanged")
    return f"{programs}: " + ", ".join(parts)


class DiffView(ScrollView, can_focus=True):
    """A unified diff, coloured by line kind; a Line API widget, so long diffs scroll fast."""

    COMPONENT_CLASSES: ClassVar[set[str]] = {"diff--added", "diff--removed", "diff--hunk",
                                             "diff--file"}

    def __init__(self, id: str | None = None) -> None:
        super().__init__(id=id)
        self.lines: list[str] = []

    def show(self, lines: Sequence[str]) -> None:
        """A new diff, scrolled to its top."""
        self.lines = list(lines)
        self.virtual_size = Size(max((len(line) for line in self.lines), default=0),
                                 len(self.lines))
        self.scroll_to(0, 0, animate=False)
        self.refresh()

    def _style(self, line: str) -> Style:
        if line.startswith(("---", "+++")):
            return self.get_component_rich_style("diff--file")
        if line.startswith("@@"):
            return self.get_component_rich_style("diff--hunk")
        if line.startswith("+"):
            return self.get_component_rich_style("diff--added")
        if line.startswith("-"):
            return self.get_component_rich_style("diff--removed")
        return Style()

    def render_line(self, y: int) -> Strip:
        scroll_x, scroll_y = self.scroll_offset
        index = y + scroll_y
        width = self.scrollable_content_region.width
        if index >= len(self.lines):
            return Strip.blank(width, self.rich_style)
        text = self.lines[index]
        strip = Strip([Segment(text, self._style(text))]).crop_extend(
            scroll_x, scroll_x + width, None)
        return strip.apply_style(self.rich_style)


class ReviewScreen(DocumentView, Screen[None]):
    """The corpus posted with the saved file and with the unsaved document, diffed."""

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("escape", "close", "Close"),
        Binding("n", "next_change", "Next change"),
        Binding("tab", "app.focus_next", "Pane"),
        Binding("f5", "close", "Close", show=False),  # f5 opens it, f5 closes it again
    ]

    def __init__(self, doc: PostDocument, sample: Path | None) -> None:
        super().__init__()
        self.doc = doc
        #: the editor's sample program: reviewed when corpus.yaml lists none for the machine
        self.sample = sample
        self.corpus: Corpus | None = None
        self.outcome: Outcome | None = None
        self.selected: str | None = None

    def compose(self) -> ComposeResult:
        yield Header()
        yield Static("", id="review-title")
        with Vertical(id="review-body"):  # one loading indicator over all of it
            yield DataTable(id="review-programs", cursor_type="row", zebra_stripes=False)
            yield Static("", id="review-detail")
            yield DiffView(id="review-diff")
            with VerticalScroll(id="review-note"):
                yield Static("", id="review-note-text")
        yield Static("", id="review-summary")
        yield Footer(compact=True)

    def on_mount(self) -> None:
        self.query_one("#review-programs", DataTable).border_title = "Programs"
        self.document_changed()
        focus_now(self.query_one("#review-programs", DataTable))

    def on_resize(self, event: Resize) -> None:
        self.set_class(event.size.width < 100, "-narrow")

    # --- what to show ------------------------------------------------------------------------

    @property
    def _texts(self) -> tuple[str, str]:
        doc = self.doc
        return doc.saved_text, doc.text

    def document_changed(self) -> None:
        """The document changed (edit, undo, redo) or was saved: review it again."""
        doc = self.doc
        self._title()
        if not doc.dirty:
            self.workers.cancel_group(self, "review")
            self._loading(False)
            self.outcome = None
            self._show_message(
                NO_UNSAVED_CHANGES,
                f"{NO_UNSAVED_CHANGES}: the post is as saved in {doc.path.name}.\n"
                f"Edit it, then come back here (f5) to see which NC lines of which programs "
                f"the edits change — before saving them.")
            return
        if doc.post is None:
            self.workers.cancel_group(self, "review")
            self._loading(False)
            self.outcome = None
            count = len(doc.problems)
            problems = "\n".join(problem_text(p) for p in doc.problems[:8])
            self._show_message(
                f"the unsaved post has {count} problem{'s' if count != 1 else ''}: "
                f"it cannot be posted",
                f"The unsaved post has {count} problem{'s' if count != 1 else ''}, so it cannot "
                f"post anything; fix {'them' if count != 1 else 'it'} to review the change."
                f"\n\n{problems}")
            return
        self._loading(True)
        self.query_one("#review-summary", Static).update(Text("posting…", style="dim italic"))
        saved, unsaved = self._texts
        self._post(saved, unsaved)

    def document_saved(self) -> None:
        """Saved while open: the saved file is now the document, so nothing is unsaved."""
        self.document_changed()

    def _title(self) -> None:
        doc = self.doc
        text = Text()
        text.append("Review unsaved changes", style="bold")
        text.append(f" · {doc.path.name}: the saved file → the unsaved edits", style="")
        if self.corpus is not None:
            text.append(f"\nposted with both: {self.corpus.source}", style="dim")
            if self.corpus.warning:
                text.append(f"\n{self.corpus.warning}", style="yellow")
        self.query_one("#review-title", Static).update(text)

    def _loading(self, loading: bool) -> None:
        self.query_one("#review-body").loading = loading

    @property
    def note(self) -> str:
        """What the screen says where a diff would be (empty when it shows a diff)."""
        if not self.query_one("#review-note").display:
            return ""
        return str(self.query_one("#review-note-text", Static).render())

    def _show_note(self, text: str) -> None:
        """Words where the diff would be: an empty state, or why a program has no diff."""
        view = self.query_one(DiffView)
        view.show([])
        view.display = False
        self.query_one("#review-note").display = True
        self.query_one("#review-note-text", Static).update(Text(text, style="italic"))

    def _show_diff(self, lines: Sequence[str]) -> None:
        self.query_one("#review-note").display = False
        view = self.query_one(DiffView)
        view.display = True
        view.show(lines)

    def _show_message(self, summary: str, message: str) -> None:
        """An empty state: no program list, a message where the diff would be."""
        table = self.query_one("#review-programs", DataTable)
        fill(table, [("verdict", "verdict"), ("program", "program"), ("lines", "lines")], [])
        table.display = False
        self.query_one("#review-detail", Static).display = False
        self._show_note(message)
        self.query_one("#review-summary", Static).update(Text(summary, style="bold"))
        self.refresh_bindings()

    # --- posting (in a worker thread) ------------------------------------------------------

    @work(thread=True, exclusive=True, group="review", exit_on_error=False)
    def _post(self, saved: str, unsaved: str) -> Outcome:
        """Post the corpus with both texts; never raises (errors become the outcome's)."""
        corpus = self.corpus or corpus_of(self.doc, self.sample)
        outcome = Outcome(saved, unsaved, corpus)
        doc = self.doc
        try:
            outcome.diffs = review.review_texts(saved, unsaved, corpus.programs,
                                                machine=doc.path.stem, file=doc.file,
                                                path=doc.path)
        except api.PostError as exc:
            outcome.error = f"the saved file is not a valid post, so there is nothing to " \
                            f"compare with:\n{exc.report()}"
        except api.CLError as exc:
            outcome.error = f"a program cannot be read:\n{exc}"
        except Exception as exc:  # a bug in postdsl must not take the editor (and the work)
            outcome.error = f"internal error while posting: {type(exc).__name__}: {exc}"
        return outcome

    def on_worker_state_changed(self, event: Worker.StateChanged) -> None:
        if event.worker.group != "review" or event.state != WorkerState.SUCCESS:
            return
        outcome = event.worker.result
        if not isinstance(outcome, Outcome) or (outcome.saved, outcome.unsaved) != self._texts:
            return  # posted from texts that are no longer the saved and current ones
        self.corpus = outcome.corpus
        self.outcome = outcome
        self._loading(False)
        self._title()
        self._show(outcome)

    # --- showing -----------------------------------------------------------------------------

    def _show(self, outcome: Outcome) -> None:
        if outcome.error is not None:
            self._show_message("the change cannot be reviewed", outcome.error)
            return
        if not outcome.diffs:
            self._show_message("nothing to post", outcome.corpus.source)
            return
        table = self.query_one("#review-programs", DataTable)
        table.display = True
        fill(table, [("verdict", "verdict"), ("program", "program"), ("lines", "lines")],
             [((label_of(d), d.program, counts_of(d)), d.program) for d in outcome.diffs])
        names = [d.program for d in outcome.diffs]
        if self.selected not in names:
            first = next((d for d in outcome.diffs if d.status != review.UNCHANGED), None)
            self.selected = (first or outcome.diffs[0]).program
        table.move_cursor(row=names.index(self.selected or names[0]), animate=False)
        if self.focused is None or self.focused.id == "review-note":
            table.focus()  # the list was hidden (an empty state) and took the focus with it
        self._show_program()
        summary = summary_of(outcome.diffs)
        style = "bold" if summary.startswith(NO_OUTPUT_CHANGES) else ""
        self.query_one("#review-summary", Static).update(Text(summary, style=style))
        self.refresh_bindings()

    def _show_program(self) -> None:
        """The selected program's headline above its diff."""
        if self.outcome is None:
            return
        diff = next((d for d in self.outcome.diffs if d.program == self.selected), None)
        if diff is None:
            return
        detail = Text()
        detail.append(diff.program, style="bold")
        detail.append(": ")
        detail.append(review.headline(diff), style=label_of(diff).style)
        if diff.motion_at is not None:
            # where the toolpath first differs: the line to read before any other
            detail.append("\nfirst motion difference: ", style="bold")
            detail.append(diff.motion_at.describe())
        self.query_one("#review-detail", Static).update(detail)
        self.query_one("#review-detail", Static).display = True
        self.query_one(DiffView).border_title = f"Diff · {diff.program}"
        if diff.diff:
            self._show_diff(diff.diff)
        elif all(d.status == review.UNCHANGED for d in self.outcome.diffs):
            count = len(self.outcome.diffs)
            self._show_note(f"{NO_OUTPUT_CHANGES}: the unsaved edits change the NC output of "
                            f"none of the {count} program{'s' if count != 1 else ''}.")
        elif diff.status == review.RENUMBERED:
            self._show_note("Only block numbers differ: every line is the same once its block "
                            "number is ignored.")
        elif diff.status == review.UNCHANGED:
            self._show_note("This program's NC output is the same with the saved file and "
                            "with the unsaved edits.")
        else:
            self._show_note(review.headline(diff))

    @on(DataTable.RowHighlighted, "#review-programs")
    def _highlighted(self, event: DataTable.RowHighlighted) -> None:
        event.stop()
        name = event.row_key.value if event.row_key is not None else None
        if name is not None and name != self.selected:
            self.selected = name
            self._show_program()

    # --- actions -----------------------------------------------------------------------------

    def check_action(self, action: str, parameters: tuple[object, ...]) -> bool | None:
        """'Next change' is greyed out while there is no list of programs to move in."""
        if action == "next_change":
            return True if self.outcome is not None and self.outcome.diffs else None
        return True

    def action_next_change(self) -> None:
        """Move to the next program whose output changes (wrapping around)."""
        if self.outcome is None or not self.outcome.diffs:
            return
        names = [d.program for d in self.outcome.diffs]
        start = names.index(self.selected) if self.selected in names else -1
        for step in range(1, len(names) + 1):
            diff = self.outcome.diffs[(start + step) % len(names)]
            if diff.status != review.UNCHANGED:
                self.query_one("#review-programs", DataTable).move_cursor(
                    row=(start + step) % len(names), animate=False)
                return
        self.notify(NO_OUTPUT_CHANGES)

    def action_close(self) -> None:
        self.dismiss(None)
