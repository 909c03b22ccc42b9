"""The command palette (ctrl+p): every editor action, every screen, every table."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from functools import partial
from typing import TYPE_CHECKING

from textual.command import DiscoveryHit, Hit, Hits, Provider

if TYPE_CHECKING:
    from tui.app import EditorApp

#: (title, action on the app, help) — the palette's list of editor actions
ACTIONS: tuple[tuple[str, str, str], ...] = (
    ("Save", "save", "Write the post (atomically); asks first if it has problems"),
    ("Undo", "undo", "Undo the last edit"),
    ("Redo", "redo", "Redo the edit undone last"),
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
    ("Edit sample value", "edit_sample", "Change a sample value of the preview"),
    ("Reset sample values", "reset_samples", "Back to the post's sample values"),
    ("Focus commands", "focus('commands')", "Move to the commands pane"),
    ("Focus table", "focus('table')", "Move to the command table"),
    ("Focus sample values", "focus('samples')", "Move to the sample values"),
    ("Focus program", "focus('program')", "Move to the program preview"),
    ("Quit", "quit", "Leave the editor (asks when there are unsaved changes)"),
)


class EditorCommands(Provider):
    """Editor actions, registered screens and 'Go to <command>'."""

    def _commands(self) -> Iterator[tuple[str, Callable[[], object], str]]:
        app: EditorApp = self.app  # type: ignore[assignment]
        for title, action, help in ACTIONS:
            yield title, partial(app.run_action, action), help
        for entry in app.screen_entries():
            yield f"Open {entry.title}", partial(app.open_screen, entry.name), entry.help
        for ref, title in app.table_titles():
            yield f"Go to {title}", partial(app.select_table, ref, True), \
                f"Show the {ref.kind} '{ref.name}'"

    async def discover(self) -> Hits:
        for title, command, help in self._commands():
            yield DiscoveryHit(title, command, help=help)

    async def search(self, query: str) -> Hits:
        matcher = self.matcher(query)
        for title, command, help in self._commands():
            score = matcher.match(title)
            if score > 0:
                yield Hit(score, matcher.highlight(title), command, help=help)
