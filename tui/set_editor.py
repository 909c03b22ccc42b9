"""The ``set:`` of a table: the flags it gives new values after its blocks are written.

Opened with ``s`` on the command grid.  Each entry is a flag and an expression; a
new or changed entry is checked as it is typed with the post's own checks (the flag
must be declared, the expression must parse and read only names the post knows),
and a wrong one stays in its field with the message under it, never written.  An
entry of a table of the base post (``extends:``) is written as an override of
just that entry (``override: {commands/NAME/set/FLAG: …}``).
"""

from __future__ import annotations

from typing import Any, ClassVar

from rich.text import Text
from ruamel.yaml.comments import CommentedMap
from ruamel.yaml.scalarstring import DoubleQuotedScalarString, ScalarString
from textual import on
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Vertical
from textual.screen import ModalScreen
from textual.widgets import DataTable, Label, Static

from tui import edits
from tui.dialogs import PromptDialog, focus_now
from tui.document import PostDocument
from tui.flags import check_set_expression, check_set_flag
from tui.messages import DocumentView
from tui.model import TABLE_KEYS, TableRef, table_node
from tui.tables import fill


class SetEditor(DocumentView, ModalScreen[None]):
    """Add, change and remove the ``set: {flag: expression}`` entries of one table."""

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("escape", "close", "Close"),
        Binding("enter", "edit", "Change"),
        Binding("a", "add", "Add flag set"),
        Binding("x", "delete", "Remove"),
    ]

    def __init__(self, doc: PostDocument, ref: TableRef) -> None:
        super().__init__()
        self.doc = doc
        self.ref = ref
        self.current: str | None = None

    @property
    def path(self) -> tuple[Any, ...]:
        return self.ref.path + ("set",)

    @property
    def sets(self) -> dict[str, str]:
        """flag -> expression text, as the table states them now."""
        table = table_node(self.doc.model, self.ref)
        return {name: expr.source for name, expr in (getattr(table, "sets", None) or {}).items()}

    @property
    def inherited(self) -> bool:
        """The table is the base post's: entries are written as overrides of this post
        (``override: {commands/NAME/set/FLAG: …}``), each exactly the entry edited."""
        return self.doc.model.inherited(self.ref.path)

    def compose(self) -> ComposeResult:
        with Vertical(id="set-editor", classes="dialog"):
            yield Label(f"set: of {self.ref.title} — flags given new values after its "
                        f"blocks, in order", classes="dialog-title")
            yield DataTable(id="set-table", cursor_type="row", zebra_stripes=False)
            yield Static("", id="set-message", markup=False)
            yield Static("a: add · enter: change · x: remove · ctrl+z: undo · escape: close",
                         classes="dialog-hint")

    def on_mount(self) -> None:
        self.document_changed()
        focus_now(self.query_one(DataTable))

    def document_changed(self) -> None:
        """Show the entries again (after an edit, undo or redo)."""
        table = self.query_one(DataTable)
        sets = self.sets
        rows = []
        for flag, source in sets.items():
            problems = [p.message for p in self.doc.problems_under(self.path + (flag,))]
            rows.append(((Text(flag, style="bold"), source,
                          Text("; ".join(problems), style="red")), flag))
        fill(table, [("flag", "flag"), ("new value", "value"), ("problem", "problem")], rows)
        names = list(sets)
        if names:
            row = names.index(self.current) if self.current in names else \
                min(table.cursor_row, len(names) - 1)
            table.move_cursor(row=max(row, 0), animate=False)
            self.current = names[max(row, 0)]
        else:
            self.current = None
        message = "this table sets no flags: press a to add one" if not names else ""
        if self.inherited:
            message = (f"{self.ref.title} comes from the base post: a change is saved as an "
                       f"override of just that entry; the others stay the base's. " + message)
        self.query_one("#set-message", Static).update(message)

    @on(DataTable.RowHighlighted)
    def _highlighted(self, event: DataTable.RowHighlighted) -> None:
        event.stop()
        if event.row_key is not None and event.row_key.value in self.sets:
            self.current = str(event.row_key.value)

    @on(DataTable.RowSelected)
    def _selected(self, event: DataTable.RowSelected) -> None:
        event.stop()
        self.action_edit()

    def _editable(self) -> bool:
        """Every table's ``set:`` can be edited (the base's through overrides)."""
        return True

    def _ask_value(self, flag: str, value: str, label: str) -> None:
        """The expression prompt: checked as typed; a wrong one stays in the field."""
        def done(text: str | None) -> None:
            if text is not None:
                self.current = flag
                self.change(label, lambda data: self._put(data, flag, text.strip()))

        self.app.push_screen(PromptDialog(
            f"New value of flag {flag} after {self.ref.title}", value,
            help="an expression, as in conditions: true, false, a number, a name the post "
                 "knows (feed, a variable, another flag)",
            check=lambda text: check_set_expression(self.doc.model, self.ref, text)), done)

    def _put(self, data: Any, flag: str, source: str) -> None:
        """Write ``flag: "source"``: a new flag goes last (set: runs in order), a changed one
        keeps its place and quotes; always text, so ``true`` stays an expression."""
        if self.inherited:
            edits.override_field(data, self.path + (flag,), DoubleQuotedScalarString(source))
            return
        table = edits.node_at(data, self.ref.path)
        sets = table.get("set")
        if not isinstance(sets, CommentedMap):
            edits.insert_key(table, "set", edits.flow_map({}), TABLE_KEYS)
            sets = table["set"]
        old = sets.get(flag)
        sets[flag] = type(old)(source) if isinstance(old, ScalarString) \
            else DoubleQuotedScalarString(source)

    def action_add(self) -> None:
        if not self._editable():
            return
        taken = set(self.sets)

        def named(name: str | None) -> None:
            if name:
                self._ask_value(name.strip(), "true", f"set flag {name.strip()}")

        declared = ", ".join(f for f in self.doc.model.flags if f not in taken)
        self.app.push_screen(PromptDialog(
            f"Flag {self.ref.title} sets", help=f"a declared flag: {declared or 'none free'}",
            check=lambda text: check_set_flag(self.doc.model, text, taken)), named)

    def action_edit(self) -> None:
        flag = self.current
        if flag is None:
            self.action_add()
            return
        if self._editable():
            self._ask_value(flag, self.sets.get(flag, ""), f"set flag {flag}")

    def action_delete(self) -> None:
        flag = self.current
        if flag is None or not self._editable():
            return

        def remove(data: Any) -> None:
            if self.inherited:  # null: the base's entry is removed in this post
                edits.override_field(data, self.path + (flag,), None)
                return
            edits.set_value(data, self.path + (flag,), None)
            table = edits.node_at(data, self.ref.path)
            if "set" in table and not table["set"]:
                del table["set"]

        self.current = None
        self.change(f"remove set of flag {flag}", remove)

    def action_close(self) -> None:
        self.dismiss(None)
