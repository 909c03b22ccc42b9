"""The variables editor: the post's fixed values, and what the commands using them write;
below them the post's flags (state tables set and conditions read, :mod:`tui.flags_section`).
The keys act on the table that has the focus (tab moves between them)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, ClassVar

from rich.text import Text
from textual import on
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Vertical, VerticalScroll
from textual.screen import ModalScreen
from textual.widgets import DataTable, Label, Static

from postdsl import api
from tui import edits
from tui.commands_pane import entries
from tui.dialogs import Choice, ConfirmDialog, PromptDialog, focus_now
from tui.document import PostDocument
from tui.flags_section import FlagActions, FlagsTable
from tui.messages import DocumentView
from tui.model import names_read, parse_value, show_value, uses_of
from tui.tables import fill


def kind_of(value: Any) -> str:
    """What a variable holds, in words."""
    if isinstance(value, bool):
        return "yes/no"
    if isinstance(value, (int, float)):
        return "number"
    return "text"


class VariablesEditor(FlagActions, DocumentView, ModalScreen[None]):
    """Edit variable values, add and delete variables; the example shows their use live.
    The same keys edit the flags when their table has the focus."""

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("escape", "close", "Close"),
        Binding("enter", "edit", "Edit value"),
        Binding("a", "add", "Add"),
        Binding("x", "delete", "Delete"),
    ]

    def __init__(self, doc: PostDocument, overrides: Mapping[str, Mapping[str, Any]]) -> None:
        super().__init__()
        self.doc = doc
        #: the main screen's sample values, so the examples match its preview
        self.overrides = overrides
        self.current: str | None = None
        self.current_flag: str | None = None

    @property
    def variables(self) -> Mapping[str, Any]:
        return {name: v.value for name, v in self.doc.model.variables.items()}

    def compose(self) -> ComposeResult:
        with Vertical(id="variables-editor", classes="dialog full"):
            yield Label("Variables — fixed values of this post, used like parameters",
                        classes="dialog-title")
            yield DataTable(id="variables-table", cursor_type="row", zebra_stripes=False)
            yield Label("Flags — state the post keeps: set by tables (s on the grid), read "
                        "in conditions", classes="dialog-title")
            yield FlagsTable(id="flags-table", cursor_type="row", zebra_stripes=False)
            with VerticalScroll(id="variable-example"):
                yield Static("", id="variable-example-text")
            yield Static("enter: edit value · a: add · x: delete · tab: variables / flags · "
                         "ctrl+z: undo · escape: close",
                         classes="dialog-hint")

    def on_mount(self) -> None:
        self.document_changed()
        focus_now(self.query_one("#variables-table", DataTable))

    @property
    def on_flags(self) -> bool:
        """The flags table has the focus: the keys act on flags."""
        return isinstance(self.focused, FlagsTable)

    def _users(self, name: str) -> list[str]:
        data = self.doc.model
        return [entry.ref.name for rows in entries(data).values() for entry in rows
                if entry.has_table and entry.ref.previewable and name in names_read(data,
                                                                                     entry.ref)]

    def document_changed(self) -> None:
        """Show the variables again (after an edit, undo or redo)."""
        self.current_flag = self.query_one(FlagsTable).show(self.doc, self.current_flag)
        table = self.query_one("#variables-table", DataTable)
        row = table.cursor_row
        rows = []
        for name, value in self.variables.items():
            users = self._users(str(name))
            rows.append(((Text(str(name), style="bold"), show_value(value), kind_of(value),
                          ", ".join(users) or Text("unused", style="dim")), str(name)))
        fill(table, [("variable", "name"), ("value", "value"), ("kind", "kind"),
                     ("used by", "used")], rows)
        names = list(self.variables)
        if self.current in names:
            row = names.index(self.current)
        if names:
            table.move_cursor(row=min(row, len(names) - 1), animate=False)
            self.current = str(names[min(row, len(names) - 1)])
        else:
            self.current = None
        self._show_example()

    @on(DataTable.RowHighlighted)
    def _highlighted(self, event: DataTable.RowHighlighted) -> None:
        event.stop()
        if isinstance(event.data_table, FlagsTable):
            if event.row_key is not None and event.row_key.value in self.doc.model.flags:
                self.current_flag = str(event.row_key.value)
            return
        if event.row_key is not None and event.row_key.value in self.variables:
            self.current = str(event.row_key.value)
            self._show_example()

    @on(DataTable.RowSelected)
    def _selected(self, event: DataTable.RowSelected) -> None:
        event.stop()
        self.action_edit()

    def _show_example(self) -> None:
        """What the commands that read the variable write, rendered with its value now."""
        text = Text()
        name = self.current
        post = self.doc.post
        if name is None:
            text.append("no variables: press a to add one", style="dim italic")
        elif post is None:
            text.append("the post has problems; fix them to see the example", style="red")
        else:
            users = self._users(name)
            if not users:
                text.append(f"'{name}' is not used by any command yet", style="dim italic")
            for command in users[:4]:
                text.append(f"{command}\n", style="bold")
                try:
                    result = api.preview_command(post, command,
                                                 self.overrides.get(command))
                except api.PostError as exc:
                    text.append(f"  {exc.message}\n", style="red")
                    continue
                for line in result.lines[:8]:
                    text.append(f"  {line.text}\n")
                if result.error:
                    text.append(f"  {result.error}\n", style="red")
        self.query_one("#variable-example-text", Static).update(text)

    def action_edit(self) -> None:
        if self.on_flags:
            self.edit_flag()
            return
        name = self.current
        if name is None:
            return

        def done(value: str | None) -> None:
            if value is not None:
                self.change(f"variable {name}", lambda data: edits.set_value(
                    data, ("variables", name), parse_value(value)))

        self.app.push_screen(PromptDialog(
            f"Value of {name}", show_value(self.variables.get(name)),
            help="a number, yes/no as true/false, or text"), done)

    def action_add(self) -> None:
        if self.on_flags:
            self.add_flag()
            return

        def check(text: str) -> str | None:
            if not text.isidentifier():
                return "a variable name is a word: letters, digits and _"
            if text in self.variables:
                return f"there is already a variable '{text}'"
            if text in api.parameters():
                return f"'{text}' is a CL parameter; a variable must not hide it"
            return None

        def named(name: str | None) -> None:
            if not name:
                return

            def valued(value: str | None) -> None:
                if value is not None:
                    self.current = name
                    self.change(f"add variable {name}", lambda data: edits.set_value(
                        data, ("variables", name), parse_value(value)))

            self.app.push_screen(PromptDialog(f"Value of {name}", "0"), valued)

        self.app.push_screen(PromptDialog("New variable name", check=check), named)

    def action_delete(self) -> None:
        if self.on_flags:
            self.delete_flag()
            return
        name = self.current
        if name is None:
            return

        def done(answer: str | None) -> None:
            if answer == "delete":
                self.current = None
                self.change(f"delete variable {name}", lambda data: edits.set_value(
                    data, ("variables", name), None))

        uses = uses_of(self.doc.model, "param", name) or self._users(name)
        if not uses:
            done("delete")
            return
        self.app.push_screen(ConfirmDialog(
            f"Delete variable '{name}'?",
            "Commands use it; their items will be marked until they read something else.",
            [Choice("delete", "Delete", "d", "error"), Choice("cancel", "Cancel", "escape")]),
            done)

    def action_close(self) -> None:
        self.dismiss(None)
