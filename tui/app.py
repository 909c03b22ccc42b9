"""The table editor application: ``postdsl edit MACHINE [--cl SAMPLE]``.

The app is the controller: widgets report what the user did (a table chosen,
the cursor moved, a cell activated) and bindings call the app's actions; the
app changes the :class:`~tui.document.PostDocument` and shows the result in
every widget.  Only ``postdsl.api`` (and the loader's round-trip document) is
used from the library.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, ClassVar

from rich.text import Text
from ruamel.yaml.comments import CommentedMap, CommentedSeq
from textual.app import App, ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, Vertical
from textual.events import Resize
from textual.screen import ModalScreen, Screen
from textual.widgets import Footer, Header, Static

from postdsl import api
from tui import edits
from tui.block_editor import BlockEditor
from tui.command_table import ITEM_COLUMN, CommandTable
from tui.commands_pane import CommandsPane, entries
from tui.dialogs import Choice, ConfirmDialog, PromptDialog
from tui.document import PostDocument
from tui.item_editor import ItemContext, ItemEditor
from tui.model import (
    BlockView,
    ItemSpec,
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
from tui.palette import EditorCommands
from tui.preview_pane import CommandPreview, PreviewPane, SampleTable
from tui.program_view import BLOCK, PLAIN, TABLE, ProgramView
from tui.screens import ScreenEntry, registered_screens, screen_entry


class MainScreen(Screen[None]):
    """Commands | table, inspector line, preview and sample values, program."""

    def compose(self) -> ComposeResult:
        yield Header()
        with Horizontal(id="body"):
            yield CommandsPane(id="commands")
            with Vertical(id="work"):
                yield Static("", id="table-title")
                yield CommandTable(id="table")
                yield Static("", id="inspector")
                yield PreviewPane(id="preview")
                yield ProgramView(id="program")
        yield Footer(compact=True)

    def on_mount(self) -> None:
        self.app.main_ready()  # type: ignore[attr-defined]

    def on_resize(self, event: Resize) -> None:
        self.set_class(event.size.width < 100, "-narrow")


class EditorApp(App[None]):
    """The post editor."""

    CSS_PATH = "editor.tcss"
    TITLE = "postdsl edit"
    COMMANDS: ClassVar[set[Any]] = App.COMMANDS | {EditorCommands}
    BINDINGS: ClassVar[list[BindingType]] = [
        # priority: they work in the editor screens too (formats, variables, settings)
        Binding("ctrl+s", "save", "Save", priority=True),
        Binding("ctrl+z", "undo", "Undo", priority=True),
        Binding("ctrl+y", "redo", "Redo", show=False, priority=True),
        Binding("ctrl+q", "quit", "Quit", priority=True),
        Binding("f1", "keys", "Keys", show=False),
    ]

    def __init__(self, post: str | Path, cl: str | Path | None = None) -> None:
        super().__init__()
        self.doc = PostDocument(post)
        self.sample_path = Path(cl) if cl is not None else api.example_program(self.doc.path)
        self.sample_commands: list[api.CLCommand] = []
        self.sample_error: str | None = None
        self._read_sample()
        self.current = self._first_table()
        self.block = 0
        self.column = ITEM_COLUMN
        self.overrides: dict[str, dict[str, Any]] = {}
        self.copied: tuple[str, Any] | None = None
        self.program: list[api.NCLine] = []
        self.program_error: str | None = None
        self.preview: api.PreviewResult | None = None
        self._post_program()

    # --- setup ---------------------------------------------------------------------------

    def _read_sample(self) -> None:
        if self.sample_path is None:
            self.sample_error = "no sample program: start the editor with --cl FILE"
            return
        try:
            self.sample_commands = list(api.read_cl(self.sample_path))
        except api.CLError as exc:
            self.sample_error = str(exc)
        except OSError as exc:
            self.sample_error = f"cannot read the sample program: {exc}"

    def _first_table(self) -> TableRef:
        """Open where the machining starts: the first command of the sample program (after
        its start and comments) that has a table, so the previews show real blocks."""
        commands = self.doc.data.get("commands") or {}
        for command in self.sample_commands:
            if command.name not in ("program_start", "operation", "comment") and \
                    command.name in commands:
                return TableRef("command", command.name)
        return TableRef("command", "program_start")

    def get_default_screen(self) -> Screen[Any]:
        """The editor's main screen (commands, table, previews)."""
        return MainScreen()

    def on_mount(self) -> None:
        for entry in registered_screens():
            if entry.key:
                self.bind(entry.key, f"open_screen('{entry.name}')",
                          description=entry.title.split()[0], show=entry.footer)

    def main_ready(self) -> None:
        """The main screen is composed: fill it."""
        self.refresh_all(scroll=True)
        self.main.query_one(CommandsPane).focus()

    @property
    def main(self) -> Screen[Any]:
        """The main screen, whatever dialog is on top of it."""
        return self.screen_stack[0]

    @property
    def table(self) -> CommandTable:
        return self.main.query_one(CommandTable)

    @property
    def used_commands(self) -> set[str]:
        """CL command (and custom cycle) names the sample program uses."""
        names = set()
        for command in self.sample_commands:
            names.add(command.name)
            cycle = getattr(command, "cycle", None)
            if command.name == "custom_cycle" and cycle:
                names.add(cycle)
        return names

    @property
    def program_lines(self) -> list[str]:
        """The posted sample program's text lines (for the settings example)."""
        return [line.text for line in self.program]

    # --- the document ----------------------------------------------------------------------

    def change(self, label: str, change: Callable[[CommentedMap], Any]) -> bool:
        """Apply one edit to the post (one undo step) and show it everywhere."""
        try:
            changed = self.doc.edit(label, change)
        except Exception as exc:  # an edit must never take the editor down
            self.notify(f"{label}: {exc}", title="Edit failed", severity="error")
            return False
        if changed:
            self.after_change()
        return changed

    def after_change(self) -> None:
        """The post changed (edit, undo, redo): re-post the sample, show it everywhere."""
        self._post_program()
        self.refresh_all()
        self.refresh_bindings()
        for screen in self.screen_stack[1:]:
            hook = getattr(screen, "document_changed", None)
            if hook is not None:
                hook()

    def _post_program(self) -> None:
        self.program, self.program_error = [], None
        post = self.doc.post
        if post is None:
            count = len(self.doc.problems)
            self.program_error = f"the post has {count} problem{'s' if count != 1 else ''}: " \
                                 f"the program cannot be posted"
        elif self.sample_error:
            self.program_error = self.sample_error
        else:
            try:
                name = self.sample_path.name if self.sample_path else "<cl>"
                self.program = api.post_commands(post, self.sample_commands, cl_file=name)
            except (api.CLError, api.PostError) as exc:
                self.program_error = str(exc)
            except Exception as exc:  # an engine bug: say so, keep the editor (and the work)
                self.program_error = f"internal error while posting: {type(exc).__name__}: {exc}"

    # --- showing ---------------------------------------------------------------------------

    def refresh_all(self, scroll: bool = False) -> None:
        """Show the document in every widget of the main screen."""
        self.update_title()
        self.refresh_commands()
        self.refresh_table()
        self.refresh_preview()
        self.refresh_program(scroll=scroll)

    def update_title(self) -> None:
        """File name, '● modified' and the number of problems in the header."""
        parts = [self.doc.path.name]
        if self.doc.dirty:
            parts.append("● modified")
        if self.doc.problems:
            count = len(self.doc.problems)
            parts.append(f"{count} problem{'s' if count != 1 else ''}")
        self.sub_title = " · ".join(parts)

    def refresh_commands(self) -> None:
        """Marks of the commands pane: used, missing, redirected, with problems."""
        troubled = set()
        for problem in self.doc.problems:
            if len(problem.path) >= 2 and problem.path[0] in ("commands", "custom_cycles",
                                                                "structures"):
                kind = {"commands": "command", "custom_cycles": "cycle",
                        "structures": "structure"}[problem.path[0]]
                troubled.add(TableRef(kind, str(problem.path[1])))
        self.main.query_one(CommandsPane).show(self.doc.data, self.used_commands, troubled,
                                               self.current)

    def blocks(self) -> list[BlockView]:
        """The rows of the current table."""
        return blocks_of(self.doc.data, self.current)

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

    def refresh_table(self) -> None:
        """The grid, its title and which cells have problems or unfired conditions."""
        ref = self.current
        node = table_node(self.doc.data, ref)
        title = Text()
        title.append(ref.title, style="bold")
        title.append(f" · {ref.kind} {ref.name}", style="dim")
        redirect = redirect_of(self.doc.data, ref)
        blocks = self.blocks()
        if node is None:
            title.append(" · no table — press t to add one", style="yellow")
        elif redirect:
            title.append(f" · written with the table of {title_of(redirect)} (enter: go there)",
                         style="yellow")
        elif isinstance(node, dict) and node.get("expand"):
            title.append(" · expanded into moves by the engine", style="yellow")
        else:
            title.append(f" · {len(blocks)} block{'s' if len(blocks) != 1 else ''}", style="dim")
            doc = api.command_doc(ref.name) if ref.kind == "command" else ""
            if doc:
                title.append(f" · {doc}", style="dim italic")
        self.main.query_one("#table-title", Static).update(title)
        bad = {rel for p in self.doc.problems if (rel := self._relative(p.path)) is not None}
        fired: dict[tuple[Any, ...], bool] = {}
        if self.preview is not None:
            for path, _source, result in self.preview.conditions:
                rel = self._relative(tuple(path))
                if rel is not None:
                    fired[rel] = result
        self.table.show(blocks, bad=bad, fired=fired, cursor=(self.block, self.column))
        self.refresh_inspector()

    def refresh_inspector(self) -> None:
        """The line under the grid: the cell in words and its problems."""
        block = self.current_block()
        text = Text()
        if block is None:
            if table_node(self.doc.data, self.current) is not None and \
                    not redirect_of(self.doc.data, self.current):
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
        self.main.query_one("#inspector", Static).update(text)

    def refresh_preview(self) -> None:
        """The command preview and its sample values (PPU's Preview)."""
        ref = self.current
        view = self.main.query_one(CommandPreview)
        samples = self.main.query_one(SampleTable)
        self.preview = None
        post = self.doc.post
        overrides = self.overrides.get(ref.name, {})
        values: dict[str, Any] = dict((table_node(self.doc.data, ref) or {}).get("preview") or {}) \
            if isinstance(table_node(self.doc.data, ref), dict) else {}
        if not ref.previewable:
            users = [e.ref.title for rows in entries(self.doc.data).values() for e in rows
                     if e.has_table and e.ref.previewable and
                     any(b.use == ref.name for b in blocks_of(self.doc.data, e.ref))]
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
                highlight = self._block_range()
                view.show([(line.text, line.block in highlight) for line in self.preview.lines],
                          [(self._where(path), source, fired)
                           for path, source, fired in self.preview.conditions],
                          error=self.preview.error and f"cannot render: {self.preview.error}")
        names = names_read(self.doc.data, ref)
        samples.show([(name, overrides.get(name, values.get(name)), name in overrides)
                      for name in names])
        samples.border_title = "Sample values"
        view.border_title = f"Preview · {ref.title}"

    def _where(self, path: tuple[Any, ...]) -> str:
        rel = self._relative(tuple(path))
        if rel is None:
            return "in " + " ".join(str(p) for p in path[1:2]) + \
                (f" block {path[2] + 1}" if len(path) > 2 and isinstance(path[2], int) else "")
        return f"block {rel[0] + 1}" + (f" item {rel[1] + 1}" if len(rel) > 1 else "")

    def _block_range(self) -> range:
        ranges = compiled_blocks(self.doc.data, self.current)
        return ranges[self.block] if 0 <= self.block < len(ranges) else range(0)

    def refresh_program(self, scroll: bool = False) -> None:
        """The sample program with the current table's (and block's) lines marked."""
        view = self.main.query_one(ProgramView)
        ref = self.current
        redirect = redirect_of(self.doc.data, ref)
        highlight = self._block_range()
        marks = []
        count = 0
        for line in self.program:
            if ref.kind == "cycle":
                ours = line.command == "custom_cycle" and line.table == ref.name
            elif ref.kind == "structure":
                ours = False
            elif redirect:
                ours = line.command == ref.name
            else:
                ours = line.table == ref.name
            count += ours
            marks.append(PLAIN if not ours else BLOCK if line.block in highlight and
                         not redirect else TABLE)
        name = self.sample_path.name if self.sample_path else "no sample program"
        view.border_title = f"Program · {name} · {len(self.program)} lines"
        view.border_subtitle = f"{count} from {ref.title}" if count else ""
        view.show(self.program_lines, marks, message=self.program_error or "", scroll=scroll)

    def refresh_highlight(self) -> None:
        """The cursor moved to another block: highlight its lines, keep everything else."""
        self.refresh_inspector()
        if self.preview is not None:
            highlight = self._block_range()
            self.main.query_one(CommandPreview).show(
                [(line.text, line.block in highlight) for line in self.preview.lines],
                [(self._where(path), source, fired)
                 for path, source, fired in self.preview.conditions],
                error=self.preview.error and f"cannot render: {self.preview.error}")
        self.refresh_program(scroll=True)

    # --- messages from the widgets ------------------------------------------------------------

    def on_commands_pane_chosen(self, event: CommandsPane.Chosen) -> None:
        self.select_table(event.ref, event.go)

    def select_table(self, ref: TableRef, focus: bool = False) -> None:
        """Show another table; ``focus`` moves the keyboard to its grid."""
        if ref != self.current:
            self.current = ref
            self.refresh_bindings()
            self.block, self.column = 0, ITEM_COLUMN
            self.refresh_commands()
            self.refresh_preview()
            self.refresh_table()
            self.refresh_program(scroll=True)
        if focus:
            self.table.focus()

    def on_command_table_moved(self, event: CommandTable.Moved) -> None:
        moved_block = event.block != self.block
        self.block, self.column = event.block, event.column
        if moved_block:
            self.refresh_highlight()
        else:
            self.refresh_inspector()

    def on_command_table_activated(self, event: CommandTable.Activated) -> None:
        self.block, self.column = event.block, event.column
        self.action_edit()

    def on_sample_table_edit_requested(self, event: SampleTable.EditRequested) -> None:
        self.edit_sample(event.name)

    # --- actions: cells -------------------------------------------------------------------------

    def _table_ready(self) -> bool:
        """The current table has blocks of its own to edit; says why not otherwise."""
        node = table_node(self.doc.data, self.current)
        redirect = redirect_of(self.doc.data, self.current)
        if node is None:
            self.notify(f"{self.current.title} has no table: press t to add one",
                        severity="warning")
            return False
        if redirect:
            self.notify(f"{self.current.title} is written with {title_of(redirect)}'s table",
                        severity="warning")
            return False
        if isinstance(node, dict) and node.get("expand"):
            self.notify(f"{self.current.title} is expanded into moves", severity="warning")
            return False
        return True

    def action_edit(self) -> None:
        focused = self.focused
        if isinstance(focused, SampleTable):
            self.action_edit_sample()
            return
        redirect = redirect_of(self.doc.data, self.current)
        if redirect:
            self.select_table(TableRef("command", redirect), focus=True)
            return
        if not self._table_ready():
            return
        block = self.current_block()
        if block is None:
            self.action_add_block()
            return
        if block.use is not None:
            self.select_table(TableRef("structure", block.use), focus=True)
            return
        if self.column < ITEM_COLUMN:
            self.action_edit_block()
            return
        index = self.current_item()
        if index is None:
            self.action_add_item(at_end=True)
            return
        self._open_item_editor(block, index, ItemSpec.of(block.items[index]), new=False)

    def _item_context(self, block: BlockView, index: int, new: bool) -> ItemContext:
        path = self.current.blocks_path + (block.index, "items", index)
        problems: dict[str, str] = {}
        if not new:
            for problem in self.doc.problems_under(path):
                key = str(problem.path[len(path)]) if len(problem.path) > len(path) else "value"
                problems.setdefault(key, problem.message)
        samples: dict[str, Any] = dict(self.preview.values) if self.preview else {}
        samples.update(self.overrides.get(self.current.name, {}))
        verb = "New item" if new else f"Item {index + 1}"
        return ItemContext(f"{verb} of block {block.index + 1} — {self.current.title}",
                           self.doc.data, samples, self._extra_names(), problems, new)

    def _extra_names(self) -> list[str]:
        node = table_node(self.doc.data, self.current)
        if self.current.kind == "cycle" and isinstance(node, dict):
            return [str(name) for name in node.get("parameters") or {}]
        return []

    def _open_item_editor(self, block: BlockView, index: int, spec: ItemSpec,
                          new: bool) -> None:
        where = (self.current.blocks_path, block.index)

        def done(result: ItemSpec | str | None) -> None:
            if result is None:
                return
            if result == "delete":
                self.change("delete item", lambda data: edits.delete_item(data, *where, index))
            elif isinstance(result, ItemSpec) and new:
                if self.change("add item", lambda data: edits.insert_item(data, *where, index,
                                                                          result)):
                    self.column = ITEM_COLUMN + index
                    self.refresh_table()
            elif isinstance(result, ItemSpec):
                self.change("edit item", lambda data: edits.set_item(data, *where, index,
                                                                     result))

        self.push_screen(ItemEditor(spec, self._item_context(block, index, new)), done)

    def action_add_item(self, at_end: bool = False) -> None:
        if not self._table_ready():
            return
        block = self.current_block()
        if block is None:
            self.notify("add a block first (b)", severity="warning")
            return
        if block.use is not None:
            self.notify(f"block {block.index + 1} inserts '{block.use}': open it to add items",
                        severity="warning")
            return
        item = self.current_item()
        index = len(block.items) if at_end or (item is None and self.column >= ITEM_COLUMN) \
            else 0 if item is None else item + 1
        self._open_item_editor(block, index, ItemSpec(), new=True)

    def action_delete_item(self) -> None:
        index = self.current_item()
        if index is None or not self._table_ready():
            return
        self.change("delete item", lambda data: edits.delete_item(
            data, self.current.blocks_path, self.block, index))

    def action_move_item(self, offset: int) -> None:
        index = self.current_item()
        block = self.current_block()
        if index is None or block is None or not 0 <= index + offset < len(block.items):
            return
        if self.change("move item", lambda data: edits.move_item(
                data, self.current.blocks_path, self.block, index, offset)):
            self.column += offset
            self.refresh_table()

    def action_add_block(self) -> None:
        if not self._table_ready():
            return
        index = self.block + 1 if self.blocks() else 0
        if self.change("add block", lambda data: edits.insert_block(
                data, self.current.blocks_path, index, edits.new_block())):
            self.block, self.column = index, ITEM_COLUMN
            self.refresh_table()
            self.refresh_highlight()

    def action_delete_block(self) -> None:
        if self.current_block() is None or not self._table_ready():
            return
        number = self.block + 1
        if self.change("delete block", lambda data: edits.delete_block(
                data, self.current.blocks_path, self.block)):
            self.notify(f"deleted block {number} (ctrl+z: undo)")

    def action_move_block(self, offset: int) -> None:
        if self.current_block() is None or not 0 <= self.block + offset < len(self.blocks()):
            return
        if self.change("move block", lambda data: edits.move_block(
                data, self.current.blocks_path, self.block, offset)):
            self.block += offset
            self.refresh_table()
            self.refresh_highlight()

    def _numbered_by_default(self) -> bool:
        return bool(self.doc.get(("output", "block_numbers", "default"), True))

    def action_toggle_numbering(self) -> None:
        block = self.current_block()
        if block is None or block.use is not None or not self._table_ready():
            return
        self.change("block numbering", lambda data: edits.set_block_props(
            data, self.current.blocks_path, self.block, {"number": not block.numbered}))

    def action_edit_block(self) -> None:
        block = self.current_block()
        if block is None or block.use is not None or not self._table_ready():
            return
        problems = [p.message for p in self.doc.problems
                    if p.path == self.current.blocks_path + (block.index, "if")]

        def done(props: dict[str, Any] | None) -> None:
            if props is not None:
                self.change("edit block", lambda data: edits.set_block_props(
                    data, self.current.blocks_path, block.index, props))

        self.push_screen(BlockEditor(f"Block {block.index + 1} — {self.current.title}", block,
                                     self.doc.data, self._numbered_by_default(),
                                     self._extra_names(),
                                     problems[0] if problems else None), done)

    def action_copy(self) -> None:
        block = self.current_block()
        if block is None:
            return
        node = self.doc.get(self.current.blocks_path + (self.block,))
        index = self.current_item()
        if index is not None:
            self.copied = ("item", edits.plain(node["items"][index]))
            self.notify(f"copied item {index + 1} of block {self.block + 1}")
        else:
            self.copied = ("block", edits.plain(node))
            self.notify(f"copied block {self.block + 1}")

    def action_paste(self) -> None:
        if self.copied is None or not self._table_ready():
            self.notify("nothing copied yet (c copies)", severity="warning")
            return
        kind, value = self.copied
        if kind == "block":
            index = self.block + 1 if self.blocks() else 0
            if self.change("paste block", lambda data: edits.insert_block(
                    data, self.current.blocks_path, index, edits.rebuild(value))):
                self.block = index
                self.refresh_table()
            return
        block = self.current_block()
        if block is None or block.use is not None:
            self.notify("paste an item into a block with items", severity="warning")
            return
        item = self.current_item()
        index = len(block.items) if item is None else item + 1
        spec = ItemSpec.of(value)
        if self.change("paste item", lambda data: edits.insert_item(
                data, self.current.blocks_path, self.block, index, spec)):
            self.column = ITEM_COLUMN + index
            self.refresh_table()

    def action_add_table(self) -> None:
        ref = self.current
        if ref.kind != "command" or table_node(self.doc.data, ref) is not None:
            self.notify(f"{ref.title} already has a table", severity="warning")
            return

        def add(data: CommentedMap) -> None:
            table = CommentedMap()
            table["blocks"] = CommentedSeq()
            edits.set_value(data, ("commands", ref.name), table)

        if self.change(f"add table {ref.name}", add):
            self.refresh_bindings()
            self.table.focus()

    # --- actions: samples -------------------------------------------------------------------

    def action_edit_sample(self) -> None:
        name = self.main.query_one(SampleTable).current
        if name is not None:
            self.edit_sample(name)

    def edit_sample(self, name: str) -> None:
        """Ask for a new sample value of ``name``; the preview renders it at once."""
        command = self.current.name
        current = self.overrides.get(command, {}).get(
            name, self.preview.values.get(name) if self.preview else None)

        def done(text: str | None) -> None:
            if text is not None:
                self.overrides.setdefault(command, {})[name] = parse_value(text)
                self.refresh_preview()
                self.refresh_table()

        info = api.parameters().get(name)
        self.push_screen(PromptDialog(f"Sample value of {name}", show_value(current),
                                      help=info.doc if info else "a variable of the post"),
                         done)

    def action_reset_sample(self) -> None:
        name = self.main.query_one(SampleTable).current
        if name is not None and self.overrides.get(self.current.name, {}).pop(name, None) \
                is not None:
            self.refresh_preview()
            self.refresh_table()

    def action_reset_samples(self) -> None:
        self.overrides.pop(self.current.name, None)
        self.refresh_preview()
        self.refresh_table()

    # --- actions: document ----------------------------------------------------------------

    def _in_dialog(self) -> bool:
        """A dialog with uncommitted input is open: the post must not change under it."""
        screen = self.screen
        if isinstance(screen, ModalScreen) and not hasattr(screen, "document_changed"):
            self.notify("finish or cancel the dialog first", severity="warning")
            return True
        return False

    def action_undo(self) -> None:
        if self._in_dialog():
            return
        label = self.doc.undo()
        if label is None:
            self.notify("nothing to undo")
            return
        self.notify(f"undone: {label}")
        self.after_change()

    def action_redo(self) -> None:
        if self._in_dialog():
            return
        label = self.doc.redo()
        if label is None:
            self.notify("nothing to redo")
            return
        self.notify(f"redone: {label}")
        self.after_change()

    def action_save(self, then_quit: bool = False) -> None:
        if not then_quit and self._in_dialog():
            return
        problems = self.doc.problems
        if not problems:
            self._save(then_quit)
            return
        listing = "\n".join(problem_text(p) for p in problems[:6])

        def done(answer: str | None) -> None:
            if answer == "save":
                self._save(then_quit)
            else:
                self.notify("not saved: the post has problems", severity="warning")

        self.push_screen(ConfirmDialog(
            f"The post has {len(problems)} problem{'s' if len(problems) != 1 else ''}",
            f"{listing}\n\n`postdsl post` refuses a post with problems. Save it anyway?",
            [Choice("save", "Save anyway", "s", "warning"), Choice("cancel", "Cancel",
                                                                   "escape")],
            id="save-dialog"), done)

    def _save(self, then_quit: bool = False) -> None:
        try:
            self.doc.save()
        except OSError as exc:
            self.notify(f"cannot save: {exc}", severity="error")
            return
        self.update_title()
        for screen in self.screen_stack[1:]:  # e.g. the review of unsaved changes
            hook = getattr(screen, "document_saved", None)
            if hook is not None:
                hook()
        self.notify(f"saved {self.doc.path.name}")
        if then_quit:
            self.exit()

    async def action_quit(self) -> None:
        if self.screen.id == "quit-dialog" or not self.doc.dirty:
            self.exit()
            return

        def done(answer: str | None) -> None:
            if answer == "quit":
                self.exit()
            elif answer == "save":
                self.action_save(then_quit=True)

        self.push_screen(ConfirmDialog(
            "Quit with unsaved changes?",
            f"{self.doc.path.name} has {len(self.doc.undo_stack)} unsaved "
            f"edit{'s' if len(self.doc.undo_stack) != 1 else ''}.",
            [Choice("save", "Save and quit", "s", "primary"),
             Choice("quit", "Quit without saving", "q", "error"),
             Choice("cancel", "Cancel", "escape")], id="quit-dialog"), done)

    def check_action(self, action: str, parameters: tuple[object, ...]) -> bool | None:
        """Offer 'Add table' (footer, palette) only where a command has no table."""
        if action == "add_table":
            return self.current.kind == "command" and \
                table_node(self.doc.data, self.current) is None
        return True

    def action_keys(self) -> None:
        """Show or hide Textual's panel of the keys of the focused widget."""
        if self.screen.query("HelpPanel"):
            self.action_hide_help_panel()
        else:
            self.action_show_help_panel()

    # --- screens and palette --------------------------------------------------------------------

    def screen_entries(self) -> list[ScreenEntry]:
        """The registered extra screens (formats, variables, settings, …)."""
        return registered_screens()

    def open_screen(self, name: str) -> None:
        """Push a registered screen by name."""
        entry = screen_entry(name)
        if entry is not None:
            self.push_screen(entry.factory(self))

    def action_open_screen(self, name: str) -> None:
        self.open_screen(name)

    def table_titles(self) -> Iterator[tuple[TableRef, str]]:
        """Every table of the post, for the palette's 'Go to'."""
        for rows in entries(self.doc.data).values():
            for entry in rows:
                yield entry.ref, entry.ref.title
