"""The formats editor: the post's named number formats, each with live examples.

The table shows every format writing the same example numbers, so formats
can be compared at a glance; the form below edits the selected one and its
examples change as you type, before anything is committed to the post.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, ClassVar

from rich.text import Text
from textual import on
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, Vertical
from textual.screen import ModalScreen
from textual.widgets import DataTable, Label, Static

from postdsl import api
from tui import edits
from tui.dialogs import Choice, ConfirmDialog, PromptDialog, focus_now
from tui.document import PostDocument
from tui.fields import Field, FieldForm
from tui.messages import DocumentView
from tui.model import FORMAT_KEYS, format_names, format_spec, show_value, uses_of
from tui.tables import fill

EXAMPLES = (40, -0.5, 53.0043, 1234.5678, 0.0001)
FORMAT_FIELDS = (
    Field("decimals", "Decimals", "int", default="3"),
    Field("min_decimals", "Min decimals", "int", default="0"),
    Field("trailing_zeros", "Trailing zeros", "bool", default="yes"),
    Field("point", "Decimal point", "choice", ("always", "needed", "never"), default="needed"),
    Field("leading_zeros", "Leading zeros", "int", default="0"),
    Field("width", "Width", "int", default="0"),
    Field("sign", "Sign", "choice", ("negative", "always", "never"), default="negative"),
    Field("multiplier", "Multiplier", "number", default="1"),
    Field("integer", "Integer", "bool", default="no"),
)


def render_examples(spec: Mapping[str, Any]) -> tuple[list[str], api.FormatSpecError | None]:
    """The example numbers written with ``spec``, or the spec's error."""
    try:
        return [api.render_number(spec, value) for value in EXAMPLES], None
    except api.FormatSpecError as exc:
        return [], exc


def describe(spec: Mapping[str, Any]) -> str:
    """A spec in one line (``decimals 3, point always``)."""
    return ", ".join(f"{k} {show_value(v)}" for k, v in spec.items()) or "defaults"


class FormatsEditor(DocumentView, ModalScreen[None]):
    """Add, delete and edit formats; every change is one undoable edit of the post."""

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("escape", "close", "Close"),
        Binding("a", "add", "Add format"),
        Binding("x", "delete", "Delete format"),
    ]

    def __init__(self, doc: PostDocument) -> None:
        super().__init__()
        self.doc = doc
        self.current: str | None = None

    @property
    def formats(self) -> Mapping[str, Any]:
        model = self.doc.model
        return {name: format_spec(model, name) or {} for name in format_names(model)}

    def compose(self) -> ComposeResult:
        with Vertical(id="formats-editor", classes="dialog full"):
            yield Label("Formats — how numbers are written", classes="dialog-title")
            yield DataTable(id="formats-table", cursor_type="row", zebra_stripes=False)
            with Horizontal(id="format-body"):
                yield FieldForm(FORMAT_FIELDS, id="format-form")
                with Vertical(id="format-side"):
                    yield Static("", id="format-example")
                    yield Static("", id="format-uses")
            yield Static("↑↓ choose · tab: fields · enter: apply the field · a: add · "
                         "x: delete · ctrl+z: undo · escape: close", classes="dialog-hint")

    def on_mount(self) -> None:
        self.document_changed()
        focus_now(self.query_one("#formats-table", DataTable))

    def document_changed(self) -> None:
        """The post changed (an edit, undo or redo): show it again."""
        table = self.query_one("#formats-table", DataTable)
        row = table.cursor_row
        data = self.doc.model
        rows = []
        for name, spec in self.formats.items():
            rendered, error = render_examples(spec)
            cells: list[Any] = [Text(str(name), style="bold")]
            if error is not None:
                cells += [Text(error.message, style="red")] + [""] * (len(EXAMPLES) - 1)
            else:
                cells += rendered
            cells.append(str(len(uses_of(data, "format", str(name)))))
            rows.append((cells, str(name)))
        fill(table, [("format", "name")] + [(show_value(v), f"x{v}") for v in EXAMPLES]
             + [("used", "used")], rows)
        names = list(self.formats)
        if names:
            if self.current in names:
                row = names.index(self.current)
            table.move_cursor(row=min(row, len(names) - 1), animate=False)
            self._select(names[min(row, len(names) - 1)])
        else:
            self.current = None

    def _select(self, name: str) -> None:
        self.current = name
        spec = self.formats.get(name) or {}
        form = self.query_one(FieldForm)
        form.load({k: spec.get(k) for k in FORMAT_KEYS})
        self._show_example()

    @on(DataTable.RowHighlighted, "#formats-table")
    def _highlighted(self, event: DataTable.RowHighlighted) -> None:
        event.stop()
        if event.row_key is not None and event.row_key.value != self.current \
                and event.row_key.value in self.formats:
            self._select(str(event.row_key.value))

    def _show_example(self) -> None:
        if self.current is None:
            return
        form = self.query_one(FieldForm)
        spec = form.values()
        rendered, error = render_examples(spec)
        text = Text()
        text.append(f"{self.current}", style="bold")
        text.append(f"  {describe(spec)}\n", style="dim")
        if error is not None:
            text.append(error.message, style="bold red")
            if error.key in form.fields:
                form.error(error.key, error.message)
        else:
            for value, shown in zip(EXAMPLES, rendered, strict=True):
                text.append(f"{show_value(value):>10} → ", style="dim")
                text.append(f"{shown}\n", style="bold")
        self.query_one("#format-example", Static).update(text)
        uses = uses_of(self.doc.model, "format", self.current)
        where = sorted({" ".join(str(p) for p in path[:2]) for path in uses})
        self.query_one("#format-uses", Static).update(Text(
            f"used by {len(uses)} item{'s' if len(uses) != 1 else ''}"
            + (": " + ", ".join(w.split(' ', 1)[1] for w in where[:8]) if where else ""),
            style="dim"))

    @on(FieldForm.Edited)
    def _edited(self, event: FieldForm.Edited) -> None:
        event.stop()
        self._show_example()

    @on(FieldForm.Committed)
    def _committed(self, event: FieldForm.Committed) -> None:
        event.stop()
        if self.current is None:
            return
        name, key, value = self.current, event.field.key, event.value
        path = ("formats", name, key)
        if self.doc.model.inherited(("formats", name)):  # the base's: override that key only
            self.change(f"format {name}: {key}", lambda data: edits.override_field(
                data, path, value))
        else:
            self.change(f"format {name}: {key}", lambda data: edits.set_value(
                data, path, value))

    def action_add(self) -> None:
        def check(text: str) -> str | None:
            if not text.isidentifier():
                return "a format name is a word: letters, digits and _"
            if text in self.formats:
                return f"there is already a format '{text}'"
            return None

        def done(name: str | None) -> None:
            if name:
                self.current = name
                self.change(f"add format {name}", lambda data: edits.set_value(
                    data, ("formats", name), edits.rebuild({"decimals": 3})))

        self.app.push_screen(PromptDialog("New format name", check=check,
                                          placeholder="e.g. feed"), done)

    def action_delete(self) -> None:
        name = self.current
        if name is None:
            return
        if self.doc.model.inherited(("formats", name)):
            self.notify(f"format '{name}' is the base post's: it cannot be removed from "
                        f"this one", severity="error")
            return
        uses = uses_of(self.doc.model, "format", name)

        def done(answer: str | None) -> None:
            if answer == "delete":
                self.current = None
                self.change(f"delete format {name}",
                                   lambda data: edits.set_value(
                                       data, ("formats", name), None))

        if not uses:
            done("delete")
            return
        self.app.push_screen(ConfirmDialog(
            f"Delete format '{name}'?",
            f"{len(uses)} items use it; they will be marked until they get another format.",
            [Choice("delete", "Delete", "d", "error"), Choice("cancel", "Cancel", "escape")]),
            done)

    def action_close(self) -> None:
        self.dismiss(None)
