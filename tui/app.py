"""The table editor application: ``postdsl edit MACHINE [--cl SAMPLE]``.

The app holds the post document and what works on every screen: save, undo and
redo, quit, help, the extra screens' keys and the command palette.  Editing lives
on :class:`~tui.main_screen.MainScreen`.  When a screen changes the document it
posts :class:`~tui.messages.DocumentChanged`; the app sends it on to every screen
of the stack, so each shows the post again without the app knowing how.  Only
``postdsl.api`` (and the loader's round-trip document) is used from the library.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path, PurePath
from typing import Any, ClassVar

from textual import on
from textual.app import App
from textual.binding import Binding, BindingType
from textual.screen import ModalScreen, Screen

from postdsl import api
from tui.backplot import BACKPLOT_TCSS
from tui.command_table import CommandTable
from tui.commands_pane import entries
from tui.dialogs import Choice, ConfirmDialog
from tui.document import PostDocument
from tui.help_screen import HelpScreen, key_rows
from tui.main_screen import MainScreen
from tui.messages import DocumentChanged, DocumentSaved
from tui.model import TableRef, problem_text
from tui.palette import EditorCommands
from tui.preview_pane import SampleTable
from tui.program_view import ProgramView
from tui.screens import ScreenEntry, registered_screens, screen_entry


def first_sample(post: Path) -> Path | None:
    """The machine's showcase program: the first corpus.yaml lists, else its example."""
    programs = api.corpus_programs(post)
    return programs[0] if programs else api.example_program(post)


def unsaved_words(count: int | None) -> str:
    """``3 unsaved edits``; ``unsaved changes`` when the count is not known (an edit made
    after undoing past the saved state)."""
    if not count:
        return "unsaved changes"
    return f"{count} unsaved edit{'s' if count != 1 else ''}"


class EditorApp(App[None]):
    """The post editor."""

    CSS_PATH: ClassVar[list[str | PurePath]] = ["editor.tcss", BACKPLOT_TCSS]
    TITLE = "postdsl edit"
    COMMANDS: ClassVar[set[Any]] = App.COMMANDS | {EditorCommands}
    BINDINGS: ClassVar[list[BindingType]] = [
        # priority: they work in the editor screens too (formats, variables, settings)
        Binding("ctrl+s", "save", "Save", priority=True),
        Binding("ctrl+z", "undo", "Undo", priority=True),
        Binding("ctrl+y", "redo", "Redo", priority=True),
        Binding("ctrl+q", "quit", "Quit", priority=True),
        Binding("f1", "keys", "Help"),
    ]

    def __init__(self, post: str | Path, cl: str | Path | None = None) -> None:
        super().__init__()
        self.doc = PostDocument(post)
        self.sample_path = Path(cl) if cl is not None else first_sample(self.doc.path)

    def get_default_screen(self) -> Screen[Any]:
        """The editor's main screen (commands, table, previews)."""
        return MainScreen(self.doc, self.sample_path)

    def on_mount(self) -> None:
        for entry in registered_screens():
            if entry.key:
                self.bind(entry.key, f"open_screen('{entry.name}')",
                          description=entry.short or entry.title.split()[0], show=True)

    @property
    def main(self) -> MainScreen:
        """The main screen, whatever dialog is on top of it."""
        screen = self.screen_stack[0]
        assert isinstance(screen, MainScreen)
        return screen

    # --- the document reaches every screen ---------------------------------------------------

    @on(DocumentChanged)
    def _broadcast_change(self, message: DocumentChanged) -> None:
        if message.delivered:
            return
        for screen in self.screen_stack:
            screen.post_message(DocumentChanged(message.label, delivered=True))

    @on(DocumentSaved)
    def _broadcast_save(self, message: DocumentSaved) -> None:
        if message.delivered:
            return
        self.main.show_title()
        for screen in self.screen_stack:
            screen.post_message(DocumentSaved(delivered=True))

    # --- actions: document ----------------------------------------------------------------

    def _in_dialog(self) -> bool:
        """A dialog with uncommitted input is open: the post must not change under it."""
        screen = self.screen
        if isinstance(screen, ModalScreen) and not getattr(screen, "SHOWS_DOCUMENT", False):
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
        self.post_message(DocumentChanged(f"undo {label}"))

    def action_redo(self) -> None:
        if self._in_dialog():
            return
        label = self.doc.redo()
        if label is None:
            self.notify("nothing to redo")
            return
        self.notify(f"redone: {label}")
        self.post_message(DocumentChanged(f"redo {label}"))

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
        self.post_message(DocumentSaved())
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
            f"{self.doc.path.name} has {unsaved_words(self.doc.unsaved_edits)}.",
            [Choice("save", "Save and quit", "s", "primary"),
             Choice("quit", "Quit without saving", "q", "error"),
             Choice("cancel", "Cancel", "escape")], id="quit-dialog"), done)

    def action_keys(self) -> None:
        """The help screen: every key, every mark."""
        if isinstance(self.screen, HelpScreen):
            self.screen.dismiss(None)
            return
        display = self.get_key_display
        screens = [(entry.key or "", f"{entry.title}: {entry.help}")
                   for entry in registered_screens() if entry.key]
        self.push_screen(HelpScreen([
            ("Everywhere", key_rows(self.BINDINGS, display) + screens +
             [(display(Binding("ctrl+p", "command_palette")),
               "command palette: every action with its key, go to any command, "
               "type an NC word (G83) to find the cells that write it")]),
            ("Main screen (act on the grid's cursor from any pane)",
             key_rows(MainScreen.BINDINGS, display)),
            ("The grid", [("enter", "edit the cell: item, block (# N if columns), "
                                    "add an item (+ column), open a structure (⇢)")]),
            ("Sample values", key_rows(SampleTable.BINDINGS, display)),
            ("Program (tab to it)", [("↑ ↓ pgup pgdn", "choose a line: the pane above says "
                                                      "which CL record, table, block and item "
                                                      "wrote each word")] +
             key_rows([b for b in ProgramView.BINDINGS
                       if isinstance(b, Binding) and b.show], display) +
             [("← →", "choose a word of the line")]),
            ("Toolpath (beside the program; at 80 columns p shows it)",
             [("p", "show or hide it"), ("V", "from the top, the front, the side (v when it "
                                             "has the keyboard)")]),
            ("Dialogs", [("tab, ← →", "move between fields and buttons"),
                         ("enter / escape", "OK / cancel")]),
        ]))

    # --- screens and palette --------------------------------------------------------------------

    def screen_entries(self) -> list[ScreenEntry]:
        """The registered extra screens (formats, variables, settings, …)."""
        return registered_screens()

    def open_screen(self, name: str) -> None:
        """Push a registered screen by name."""
        entry = screen_entry(name)
        if entry is None:
            return
        if isinstance(self.screen, ModalScreen):  # the main screen is no ModalScreen
            self.notify(f"close this dialog first (escape), then {entry.key or 'open'} "
                        f"{entry.title}", severity="warning")
            return
        self.push_screen(entry.factory(self.main))

    def action_open_screen(self, name: str) -> None:
        self.open_screen(name)

    def table_titles(self) -> Iterator[tuple[TableRef, str]]:
        """Every table of the post, for the palette's 'Go to'."""
        for rows in entries(self.doc.model).values():
            for entry in rows:
                yield entry.ref, entry.ref.title

    @property
    def table(self) -> CommandTable:
        return self.main.query_one(CommandTable)
