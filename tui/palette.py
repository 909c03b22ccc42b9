"""The command palette (ctrl+p): every editor action with its key, every screen, every
table — and the cells that write an NC word (type ``G83``), or, where the post does not
write it, the table for what it means on ISO controls (G83: deep drilling, CYCLE83)."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from functools import partial
from typing import TYPE_CHECKING, ClassVar, Protocol

from textual.binding import Binding
from textual.command import DiscoveryHit, Hit, Hits, Provider
from textual.content import Content

from postdsl import api
from tui.command_table import ITEM_COLUMN
from tui.model import TableRef

if TYPE_CHECKING:
    from textual.binding import BindingType
    from textual.dom import DOMNode

    from tui.document import PostDocument
    from tui.main_screen import MainScreen
    from tui.screens import ScreenEntry


class EditorApp(Protocol):
    """What the palette asks of the editor (:class:`tui.app.EditorApp` is one).

    A protocol, not the app's class: the app imports the palette, and the palette
    importing the app back, if only for its type, was an import circle.
    """

    BINDINGS: ClassVar[list[BindingType]]
    doc: PostDocument

    @property
    def main(self) -> MainScreen: ...

    def get_key_display(self, binding: Binding) -> str: ...

    async def run_action(self, action: str, default_namespace: DOMNode | None = None) \
        -> bool: ...

    def screen_entries(self) -> list[ScreenEntry]: ...

    def open_screen(self, name: str) -> None: ...

    def table_titles(self) -> Iterator[tuple[TableRef, str]]: ...

#: (title, action, help) — the palette's list of editor actions; an action without a
#: namespace runs on the main screen, ``app.`` ones on the app
ACTIONS: tuple[tuple[str, str, str], ...] = (
    ("Save", "app.save", "Write the post (atomically); asks first if it has problems"),
    ("Undo", "app.undo", "Undo the last edit"),
    ("Redo", "app.redo", "Redo the edit undone last"),
    ("Keys and marks", "app.keys", "Every key, and what the marks in the grid and list mean"),
    ("Edit cell", "edit", "Edit the item, block or sample under the cursor"),
    ("Add item", "add_item", "Add an item after the cursor"),
    ("Delete item", "delete_item", "Delete the item under the cursor"),
    ("Move item left", "move_item(-1)", "Swap the item with the one before it"),
    ("Move item right", "move_item(1)", "Swap the item with the one after it"),
    ("Add block", "add_block", "Add an empty block after the cursor's block"),
    ("Delete block", "delete_block", "Delete the block under the cursor"),
    ("Move block up", "move_block(-1)", "Swap the block with the one above"),
    ("Move block down", "move_block(1)", "Swap the block with the one below"),
    ("Block condition and numbering", "edit_block", "Edit the block's if, numbering, repeat"),
    ("Toggle block numbering", "toggle_numbering", "Number the block or not"),
    ("Copy", "copy", "Copy the item (or the block, from the # N if columns)"),
    ("Paste", "paste", "Paste the copied item or block after the cursor"),
    ("Add table", "add_table", "Give the selected command a table (it has none)"),
    ("Set flags", "edit_sets",
     "The flags the selected table gives new values (set:): add, change, remove"),
    ("Show or hide the toolpath", "toggle_plot",
     "The sample program's toolpath, replayed through the control model"),
    ("Turn the toolpath view", "plot_view",
     "Look from the top (XY), the front (XZ), the side (YZ)"),
    ("Choose the sample program", "choose_sample",
     "Post another of the machine's corpus programs in the previews"),
    ("Edit sample value", "edit_sample", "Change a sample value of the preview"),
    ("Reset sample values", "reset_samples", "Back to the post's sample values"),
    ("Focus commands", "app.focus('commands')", "Move to the commands pane"),
    ("Focus table", "app.focus('table')", "Move to the command table"),
    ("Focus sample values", "app.focus('samples')", "Move to the sample values"),
    ("Focus program", "app.focus('program')",
     "Move to the program: choose a line to see which cell wrote each word"),
    ("Quit", "app.quit", "Leave the editor (asks when there are unsaved changes)"),
)


def action_keys(app: EditorApp) -> dict[str, str]:
    """Action -> the key that runs it, as the footer shows keys (``^s``, ``f2``)."""
    from tui.main_screen import MainScreen

    keys: dict[str, str] = {}
    for owner, bindings in (("app.", app.BINDINGS), ("", MainScreen.BINDINGS)):
        for binding in bindings:
            if isinstance(binding, Binding):
                first = binding.key.split(",")[0]
                keys.setdefault(owner + binding.action,
                                app.get_key_display(Binding(first, binding.action)))
    keys.setdefault("edit", "enter")
    return keys


class EditorCommands(Provider):
    """Editor actions, registered screens, 'Go to <command>' and NC words."""

    def _commands(self) -> Iterator[tuple[str, str, Callable[[], object], str]]:
        app: EditorApp = self.app  # type: ignore[assignment]  # this palette runs in EditorApp only
        main = app.main
        keys = action_keys(app)
        for title, action, help in ACTIONS:
            yield title, keys.get(action, ""), partial(app.run_action, action, main), help
        for entry in app.screen_entries():
            yield f"Open {entry.title}", app.get_key_display(Binding(entry.key, "")) \
                if entry.key else "", partial(app.open_screen, entry.name), entry.help
        for ref, title in app.table_titles():
            yield f"Go to {title}", "", partial(main.select_table, ref, True), \
                f"Show the {ref.kind} '{ref.name}'"

    @staticmethod
    def _shown(title: Content | str, key: str) -> Content:
        """The title and, after it, the key that runs the action without the palette."""
        text = Content(title) if isinstance(title, str) else title
        return Content.assemble(text, (f"  {key}", "dim")) if key else text

    async def discover(self) -> Hits:
        for title, key, command, help in self._commands():
            yield DiscoveryHit(self._shown(title, key), command, text=title, help=help)

    async def search(self, query: str) -> Hits:
        app: EditorApp = self.app  # type: ignore[assignment]  # this palette runs in EditorApp only
        if api.looks_like_word(query):
            word = query.strip().upper()
            meaning = api.word_meaning(app.doc.model, word)
            if meaning is not None:
                # G83 on a post that writes deep drilling otherwise (CYCLE83, CYCL DEF 200)
                said = meaning.sentence()
                yield Hit(1.0, said, partial(app.main.select_table,
                                             TableRef(meaning.kind, meaning.table), True),
                          text=said, help=f"go to the {meaning.table} table: what "
                          f"{meaning.word} means on ISO controls, as this post writes it")
            for writer in api.word_writers(app.doc.model, word):
                ref = TableRef(writer.kind, writer.name)
                yield Hit(1.0, writer.sentence(word),
                          partial(app.main.go_to_cell, ref, writer.block,
                                  ITEM_COLUMN + writer.item),
                          text=writer.sentence(word), help="go to the cell that writes it")
        matcher = self.matcher(query)
        for title, key, command, help in self._commands():
            score = matcher.match(title)
            if score > 0:
                yield Hit(score, self._shown(matcher.highlight(title), key), command,
                          text=title, help=help)
