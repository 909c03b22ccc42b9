"""The editor's main screen: commands | table, inspector, previews, program, its trace and
its toolpath.

The screen owns the editing state — the table shown, the grid's cursor, the sample
program and its posting — as reactive attributes, and the actions on that state
(add an item, copy a block, go to a cell).  Widgets report what the user did with
messages; an edit changes the :class:`~tui.document.PostDocument` and posts
:class:`~tui.messages.DocumentChanged`, which comes back to every screen.

The sample program is posted in a worker when it is large: the previous program
stays on screen, marked "posting…", until the new one arrives, and a newer edit
replaces a posting under way.  The toolpath beside the program (``p`` shows or hides
it, ``V`` turns the view) is built after the program, off the UI thread too.
"""

from __future__ import annotations

import gc
from pathlib import Path
from typing import Any, ClassVar

from rich.text import Text
from textual import on
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, Vertical
from textual.events import Resize
from textual.reactive import reactive
from textual.screen import Screen
from textual.widgets import Header, Static

from postdsl import api
from tui.backplot import Backplot
from tui.command_table import ITEM_COLUMN, CommandTable
from tui.commands_pane import CommandsPane, entries
from tui.dialogs import PromptDialog
from tui.document import PostDocument
from tui.footer import EditorFooter
from tui.grid_actions import GridActions
from tui.messages import DocumentChanged, edit_document
from tui.model import (
    BlockView,
    TableRef,
    blocks_of,
    compiled_blocks,
    item_summary,
    names_read,
    parse_value,
    problem_text,
    redirect_of,
    show_value,
    table_node,
    title_of,
)
from tui.preview_pane import CommandPreview, PreviewPane, SampleTable
from tui.program_view import ProgramView
from tui.sample import Program, Sample
from tui.sample_plot import PlottedPath, SamplePlot
from tui.sample_program import SampleProgram
from tui.set_editor import SetEditor
from tui.trace_pane import TracePane


class MainScreen(GridActions, SampleProgram, SamplePlot, Screen[None]):
    """Commands | table, inspector line, preview and sample values, program and toolpath."""

    BINDINGS: ClassVar[list[BindingType]] = [
        # the grid's edits act on the grid's cursor from any pane of this screen
        Binding("a", "add_item", "+Item"),
        Binding("x,delete", "delete_item", "−Item"),
        Binding("b", "add_block", "+Block"),
        Binding("X", "delete_block", "−Block", show=False),
        Binding("n", "toggle_numbering", "Numbering", show=False),
        Binding("i", "edit_block", "Block if", show=False),
        Binding("c", "copy", "Copy", show=False),
        Binding("v", "paste", "Paste", show=False),
        Binding("t", "add_table", "Add table", show=False),
        Binding("s", "edit_sets", "Set flags"),
        Binding("shift+left", "move_item(-1)", "Item left", show=False),
        Binding("shift+right", "move_item(1)", "Item right", show=False),
        Binding("shift+up", "move_block(-1)", "Block up", show=False),
        Binding("shift+down", "move_block(1)", "Block down", show=False),
        Binding("f6", "choose_sample", "Samples"),
        Binding("p", "toggle_plot", "Plot"),
        Binding("V", "plot_view", "Plot view", show=False),
    ]

    current: reactive[TableRef] = reactive(TableRef("command", "program_start"), init=False)
    block: reactive[int] = reactive(0, init=False)
    column: reactive[int] = reactive(ITEM_COLUMN, init=False)
    sample_path: reactive[Path | None] = reactive(None, init=False)
    #: a posting of the sample program is under way in a worker
    posting: reactive[bool] = reactive(False, init=False)

    def __init__(self, doc: PostDocument, sample_path: Path | None) -> None:
        super().__init__()
        self.doc = doc
        self.overrides: dict[str, dict[str, Any]] = {}
        self.copied: tuple[str, Any] | None = None
        self.preview: api.PreviewResult | None = None
        self.sample: Sample = Sample(sample_path)
        self.program = Program()
        self.plotted: PlottedPath | None = None
        self.set_reactive(MainScreen.sample_path, sample_path)
        self._read(sample_path)
        self.set_reactive(MainScreen.current, self._first_table())
        if self.sample.small:
            self.program = self._post_now()

    def compose(self) -> ComposeResult:
        yield Header()
        with Horizontal(id="body"):
            yield CommandsPane(id="commands")
            with Vertical(id="work"):
                yield Static("", id="table-title")
                yield CommandTable(id="table")
                yield Static("", id="inspector")
                yield PreviewPane(id="preview")
                yield TracePane(id="trace")
                with Horizontal(id="lower"):
                    yield ProgramView(id="program")
                    yield Backplot(id="backplot")
        yield EditorFooter(compact=True)

    def on_mount(self) -> None:
        self.show_all(scroll=True)
        self.query_one(CommandsPane).focus()
        # what exists now lives as long as the editor: keep it out of the collector's full
        # passes, whose pauses (over everything the process holds) would freeze a key
        gc.freeze()
        if self.sample.small:
            self.replot()
        else:
            self.repost()

    def on_resize(self, event: Resize) -> None:
        self.set_class(event.size.width < 100, "-narrow")

    # --- the document ----------------------------------------------------------------------

    def change(self, label: str, change: Any) -> bool:
        """Apply one edit to the post (one undo step); every screen shows it."""
        return edit_document(self, self.doc, label, change)

    @on(DocumentChanged)
    def _document_changed(self, message: DocumentChanged) -> None:
        if not message.delivered:
            return  # on its way up to the app, which sends it to every screen
        self.repost()
        self.show_all()

    # --- showing ---------------------------------------------------------------------------

    def show_all(self, scroll: bool = False) -> None:
        """Show the document in every widget of the screen."""
        self.show_title()
        self.show_commands()
        self.show_preview()
        self.show_table()
        self.show_program(scroll=scroll)

    def show_title(self) -> None:
        """File name, '● modified' and the number of problems in the header."""
        parts = [self.doc.path.name]
        if self.doc.dirty:
            parts.append("● modified")
        if self.doc.problems:
            count = len(self.doc.problems)
            parts.append(f"{count} problem{'s' if count != 1 else ''}")
        self.app.sub_title = " · ".join(parts)

    def show_commands(self) -> None:
        """Marks of the commands pane: used, missing, redirected, with problems."""
        troubled = set()
        for problem in self.doc.problems:
            if len(problem.path) >= 2 and problem.path[0] in ("commands", "custom_cycles",
                                                                "structures"):
                kind = {"commands": "command", "custom_cycles": "cycle",
                        "structures": "structure"}[problem.path[0]]
                troubled.add(TableRef(kind, str(problem.path[1])))
        self.query_one(CommandsPane).show(self.doc.model, set(self.sample.used), troubled,
                                          self.current)

    def blocks(self) -> list[BlockView]:
        """The rows of the current table."""
        return blocks_of(self.doc.model, self.current)

    def current_block(self) -> BlockView | None:
        """The block under the cursor, or None."""
        blocks = self.blocks()
        return blocks[self.block] if 0 <= self.block < len(blocks) else None

    def current_item(self) -> int | None:
        """Index of the item under the cursor, or None (block columns, '+', use:)."""
        block = self.current_block()
        index = self.column - ITEM_COLUMN
        if block is None or block.use is not None or not 0 <= index < len(block.items):
            return None
        return index

    def _relative(self, path: tuple[Any, ...]) -> tuple[Any, ...] | None:
        """A post path -> (block,) or (block, item) in the current table, else None."""
        prefix = self.current.blocks_path
        if path[:len(prefix)] != prefix or len(path) <= len(prefix):
            return None
        rest = path[len(prefix):]
        if len(rest) >= 3 and rest[1] == "items" and isinstance(rest[2], int):
            return (rest[0], rest[2])
        return (rest[0],)

    def show_table(self) -> None:
        """The grid, its title and which cells have problems or unfired conditions."""
        ref = self.current
        node = table_node(self.doc.model, ref)
        title = Text()
        title.append(ref.title, style="bold")
        title.append(f" · {ref.kind} {ref.name}", style="dim")
        redirect = redirect_of(self.doc.model, ref)
        blocks = self.blocks()
        if node is None:
            title.append(" · no table — press t to add one", style="yellow")
        elif redirect:
            title.append(f" · written with the table of {title_of(redirect)} (enter: go there)",
                         style="yellow")
        elif isinstance(node, api.Command) and node.expand:
            title.append(" · expanded into moves by the engine", style="yellow")
        else:
            title.append(f" · {len(blocks)} block{'s' if len(blocks) != 1 else ''}", style="dim")
            doc = api.command_doc(ref.name) if ref.kind == "command" else ""
            if doc:
                title.append(f" · {doc}", style="dim italic")
        self.query_one("#table-title", Static).update(title)
        bad = {rel for p in self.doc.problems if (rel := self._relative(p.path)) is not None}
        fired: dict[tuple[Any, ...], bool] = {}
        if self.preview is not None:
            for path, _source, result in self.preview.conditions:
                rel = self._relative(tuple(path))
                if rel is not None:
                    fired[rel] = result
        self.query_one(CommandTable).show(blocks, bad=bad, fired=fired,
                                          cursor=(self.block, self.column))
        self.show_inspector()

    def show_inspector(self) -> None:
        """The line under the grid: the cell in words and its problems."""
        block = self.current_block()
        text = Text()
        if block is None:
            if table_node(self.doc.model, self.current) is not None and \
                    not redirect_of(self.doc.model, self.current):
                text.append("no blocks: press b to add one", style="dim italic")
        elif block.use is not None:
            text.append(f"block {block.index + 1} inserts the structure '{block.use}'"
                        f" — enter: open it", style="magenta")
        else:
            index = self.current_item()
            if index is not None:
                text.append(f"block {block.index + 1} · item {index + 1}/{len(block.items)}: ",
                            style="bold")
                text.append(item_summary(block.items[index]))
            elif self.column < ITEM_COLUMN:
                text.append(f"block {block.index + 1}: ", style="bold")
                text.append(("numbered" if block.numbered else "not numbered")
                            + ("" if block.explicit_number else " (post default)"))
                text.append(f" · if {block.condition}" if block.condition else " · always")
                text.append(" — enter: edit the block", style="dim")
            else:
                text.append("enter or a: add an item at the end of the block", style="dim")
        path = self.current.blocks_path + (self.block,)
        if self.current_item() is not None:
            path += ("items", self.current_item())
        for problem in self.doc.problems_under(path)[:2] if block is not None else []:
            text.append(f"\n⚠ {problem_text(problem)}", style="bold red")
        self.query_one("#inspector", Static).update(text)

    def show_preview(self) -> None:
        """The command preview and its sample values (PPU's Preview)."""
        ref = self.current
        view = self.query_one(CommandPreview)
        samples = self.query_one(SampleTable)
        self.preview = None
        post = self.doc.post
        overrides = self.overrides.get(ref.name, {})
        node = table_node(self.doc.model, ref)
        values: dict[str, Any] = dict(node.preview or {}) if isinstance(node, api.Table) else {}
        if not ref.previewable:
            users = [e.ref.title for rows in entries(self.doc.model).values() for e in rows
                     if e.has_table and e.ref.previewable and
                     any(b.use == ref.name for b in blocks_of(self.doc.model, e.ref))]
            view.show([], [], note="a structure is previewed in the commands that use it: "
                      + (", ".join(users) or "none yet"))
        elif post is None:
            lines = [problem_text(p) for p in self.doc.problems[:4]]
            view.show([], [], error="cannot render — the post has problems:\n" +
                      "\n".join(lines))
        elif (ref.kind == "command" and ref.name not in post.commands) or \
                (ref.kind == "cycle" and ref.name not in post.custom_cycles):
            view.show([], [], note="the post has no table for this command: a program that "
                      "uses it cannot be posted (t: add a table)")
        else:
            try:
                self.preview = api.preview_command(post, ref.name, overrides)
            except (api.CLError, api.PostError) as exc:
                view.show([], [], error=str(exc))
            except Exception as exc:  # an engine bug: say so, keep the editor (and the work)
                view.show([], [], error=f"internal error in the preview: "
                                        f"{type(exc).__name__}: {exc}")
            else:
                values = self.preview.values
                self._show_preview_lines()
        names = names_read(self.doc.model, ref)
        samples.show([(name, overrides.get(name, values.get(name)), name in overrides)
                      for name in names])
        samples.border_title = "Sample values"
        view.border_title = f"Preview · {ref.title}"

    def _show_preview_lines(self) -> None:
        if self.preview is None:
            return
        highlight = self._block_range()
        self.query_one(CommandPreview).show(
            [(line.text, line.block in highlight) for line in self.preview.lines],
            [(self._where(path), source, fired)
             for path, source, fired in self.preview.conditions],
            error=self.preview.error and f"cannot render: {self.preview.error}")

    def _where(self, path: tuple[Any, ...]) -> str:
        rel = self._relative(tuple(path))
        if rel is None:
            return "in " + " ".join(str(p) for p in path[1:2]) + \
                (f" block {path[2] + 1}" if len(path) > 2 and isinstance(path[2], int) else "")
        return f"block {rel[0] + 1}" + (f" item {rel[1] + 1}" if len(rel) > 1 else "")

    def _block_range(self) -> range:
        ranges = compiled_blocks(self.doc.model, self.current)
        return ranges[self.block] if 0 <= self.block < len(ranges) else range(0)

    def show_highlight(self) -> None:
        """The cursor moved to another block: highlight its lines, keep everything else."""
        self.show_inspector()
        self._show_preview_lines()
        mark, start, _total = self._marker()
        self.query_one(ProgramView).remark(mark, scroll_to=start)

    # --- reactive state ---------------------------------------------------------------------

    def watch_current(self) -> None:
        self.show_commands()
        self.show_preview()
        self.show_table()
        self.show_program(scroll=True)
        self.show_plot_highlight()

    def watch_block(self) -> None:
        self.show_highlight()

    def watch_column(self) -> None:
        self.show_inspector()

    # --- messages from the widgets ------------------------------------------------------------

    def on_commands_pane_chosen(self, event: CommandsPane.Chosen) -> None:
        self.select_table(event.ref, event.go)

    def select_table(self, ref: TableRef, focus: bool = False) -> None:
        """Show another table; ``focus`` moves the keyboard to its grid."""
        if ref != self.current:
            self.set_reactive(MainScreen.block, 0)
            self.set_reactive(MainScreen.column, ITEM_COLUMN)
            self.current = ref
        if focus:
            self.query_one(CommandTable).focus()

    def go_to_cell(self, ref: TableRef, block: int, column: int) -> None:
        """Show a cell of a table and put the grid's cursor on it."""
        if ref != self.current:
            self.set_reactive(MainScreen.block, block)
            self.set_reactive(MainScreen.column, column)
            self.current = ref
        else:
            self.set_reactive(MainScreen.column, column)
            self.block = block
            self.show_table()
        table = self.query_one(CommandTable)
        table.focus()
        table.move_cursor(row=block, column=column, animate=False)

    def on_command_table_moved(self, event: CommandTable.Moved) -> None:
        self.column = event.column
        self.block = event.block

    def on_command_table_activated(self, event: CommandTable.Activated) -> None:
        self.set_reactive(MainScreen.block, event.block)
        self.set_reactive(MainScreen.column, event.column)
        self.action_edit()

    def on_sample_table_edit_requested(self, event: SampleTable.EditRequested) -> None:
        self.edit_sample(event.name)

    def on_descendant_focus(self) -> None:
        """The trace replaces the command preview while the program has the keyboard; at
        80 columns the commands pane folds while the keyboard is elsewhere."""
        self.set_class(not self.query_one(CommandsPane).has_focus, "-working")
        program = self.query_one(ProgramView)
        tracing = program.has_focus
        if tracing != self.has_class("-tracing"):
            self.set_class(tracing, "-tracing")
            if tracing:
                self.trace(program.cursor)

    # --- actions: samples -------------------------------------------------------------------

    def action_edit_sample(self) -> None:
        name = self.query_one(SampleTable).current
        if name is None:
            self.notify(f"{self.current.title} reads no parameters: nothing to set",
                        severity="warning")
            return
        self.edit_sample(name)

    def edit_sample(self, name: str) -> None:
        """Ask for a new sample value of ``name``; the preview renders it at once."""
        command = self.current.name
        current = self.overrides.get(command, {}).get(
            name, self.preview.values.get(name) if self.preview else None)

        def done(text: str | None) -> None:
            if text is not None:
                self.overrides.setdefault(command, {})[name] = parse_value(text)
                self.show_preview()
                self.show_table()

        info = api.parameters().get(name)
        self.app.push_screen(PromptDialog(f"Sample value of {name}", show_value(current),
                                          help=info.doc if info else "a variable of the post"),
                             done)

    def action_reset_sample(self) -> None:
        name = self.query_one(SampleTable).current
        if name is None or self.overrides.get(self.current.name, {}).pop(name, None) is None:
            self.notify("the value is the post's own sample value already")
            return
        self.show_preview()
        self.show_table()

    def action_reset_samples(self) -> None:
        self.overrides.pop(self.current.name, None)
        self.show_preview()
        self.show_table()

    # --- actions: the toolpath ----------------------------------------------------------------

    @property
    def plot_shown(self) -> bool:
        """Whether the backplot is on screen (at 80 columns only when asked for with p)."""
        if self.has_class("-narrow"):
            return self.has_class("-plot")
        return not self.has_class("-no-plot")

    def action_edit_sets(self) -> None:
        """The selected table's ``set:`` (flags it gives new values), in a dialog."""
        ref = self.current
        if ref.kind == "structure":
            self.notify(f"{ref.title} is a structure: set: belongs to the table of a command "
                        f"or custom cycle that uses it", severity="warning")
            return
        if self._table_ready():
            self.app.push_screen(SetEditor(self.doc, ref))

    def action_toggle_plot(self) -> None:
        """Show or hide the toolpath (at 80 columns it takes the command preview's place)."""
        shown = not self.plot_shown
        self.set_class(shown, "-plot")
        self.set_class(not shown, "-no-plot")
        plot = self.query_one(Backplot)
        if not shown and plot.has_focus:
            self.query_one(ProgramView).focus()
        self.notify("toolpath shown: V turns the view (XY, XZ, YZ)" if shown
                    else "toolpath hidden: p shows it again")

    def action_plot_view(self) -> None:
        """The next view of the toolpath: from the top, the front, the side."""
        if not self.plot_shown:
            self.action_toggle_plot()
        self.query_one(Backplot).action_next_view()
