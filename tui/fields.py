"""A form of typed fields (text, whole number, number, choice, yes/no) for the settings editors.

An empty field or a blank choice means "not set": the key is left out of the
post and the default applies (shown as the placeholder).  Typing updates the
live example at once (``Edited``); a value is committed to the post when the
field is left, enter is pressed or a choice is made (``Committed``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from textual import on
from textual.app import ComposeResult
from textual.containers import Horizontal, VerticalScroll
from textual.message import Message
from textual.widgets import Input, Label, Select, Static

from tui.dialogs import DialogInput
from tui.model import show_value


@dataclass(frozen=True)
class Field:
    key: str
    label: str
    kind: str = "text"  # text | int | number | choice | bool
    choices: tuple[str, ...] = ()
    default: str = ""
    help: str = ""


class FieldError(ValueError):
    pass


def parse(field: Field, raw: Any) -> Any:
    """A field's widget value -> the YAML value (None: leave the key out)."""
    if field.kind in ("choice", "bool"):
        return None if raw == Select.NULL else raw
    text = str(raw)
    if field.kind == "text":
        return text if text != "" else None
    if not text.strip():
        return None
    try:
        if field.kind == "int":
            return int(text.strip())
        number = float(text.strip())
        return int(number) if number.is_integer() and "." not in text else number
    except ValueError:
        what = "a whole number" if field.kind == "int" else "a number"
        raise FieldError(f"{field.label}: must be {what}, not '{text.strip()}'") from None


class FieldForm(VerticalScroll, can_focus=False):
    """Labelled fields, one per row, each with its error line under it."""

    class Edited(Message):
        def __init__(self, form: FieldForm, field: Field) -> None:
            super().__init__()
            self.form = form
            self.field = field

    class Committed(Message):
        def __init__(self, form: FieldForm, field: Field, value: Any) -> None:
            super().__init__()
            self.form = form
            self.field = field
            self.value = value

    def __init__(self, fields: Sequence[Field], id: str | None = None,
                 classes: str | None = None) -> None:
        super().__init__(id=id, classes=classes)
        self.fields = {f.key: f for f in fields}
        self.loaded: dict[str, Any] = {}
        #: each widget's value as :meth:`load` (or the last commit) left it: a field the
        #: user did not change is never committed, whatever its value parses to (an empty
        #: ``suffix: ""`` shows as an empty field, which parses to "not set")
        self.shown: dict[str, Any] = {}

    def compose(self) -> ComposeResult:
        for field in self.fields.values():
            with Horizontal(classes="row"):
                label = Label(field.label, classes="field-label")
                if field.help:
                    label.tooltip = field.help
                yield label
                if field.kind == "choice":
                    yield Select([(c, c) for c in field.choices], compact=True,
                                 prompt=f"default ({field.default})" if field.default
                                 else "not set", id=f"f-{field.key}")
                elif field.kind == "bool":
                    yield Select([("yes", True), ("no", False)], compact=True,
                                 prompt=f"default ({field.default})" if field.default
                                 else "not set", id=f"f-{field.key}")
                else:
                    yield DialogInput(compact=True, id=f"f-{field.key}",
                                placeholder=f"default: {field.default}" if field.default
                                else field.help)
            yield Static("", id=f"e-{field.key}", classes="field-error")

    def load(self, values: Mapping[str, Any]) -> None:
        """Show values without committing them."""
        self.loaded = dict(values)
        with self.prevent(Input.Changed, Select.Changed):
            for field in self.fields.values():
                widget = self.query_one(f"#f-{field.key}")
                value = values.get(field.key)
                if isinstance(widget, Select):
                    widget.value = value if value is not None and \
                        value in [v for _, v in widget._options] else Select.NULL
                elif isinstance(widget, Input):
                    widget.value = "" if value is None else show_value(value)
                self.shown[field.key] = widget.value  # type: ignore[attr-defined]  # an Input or Select: both have .value
                self.error(field.key, None)

    def raw(self, key: str) -> Any:
        """A field's widget value, unparsed."""
        widget = self.query_one(f"#f-{key}")
        return widget.value  # type: ignore[attr-defined]  # an Input or Select: both have .value

    def values(self) -> dict[str, Any]:
        """Every field parsed (fields that do not parse are left out)."""
        result = {}
        for field in self.fields.values():
            try:
                value = parse(field, self.raw(field.key))
            except FieldError:
                continue
            if value is not None:
                result[field.key] = value
        return result

    def error(self, key: str, message: str | None) -> None:
        """Show (or clear, None) the error under a field."""
        label = self.query_one(f"#e-{key}", Static)
        label.update(message or "")
        label.set_class(bool(message), "-shown")
        self.query_one(f"#f-{key}").set_class(bool(message), "-invalid")

    def _commit(self, key: str) -> None:
        """Commit a field the user changed; a field only passed through (focused and
        left) commits nothing, so the post keeps its bytes there."""
        field = self.fields[key]
        raw = self.raw(key)
        if key in self.shown and raw == self.shown[key]:
            self.error(key, None)
            return
        try:
            value = parse(field, raw)
        except FieldError as exc:
            self.error(key, str(exc))
            return
        self.error(key, None)
        self.shown[key] = raw
        if value != self.loaded.get(key) or type(value) is not type(self.loaded.get(key)):
            self.loaded[key] = value
            self.post_message(self.Committed(self, field, value))

    def _key(self, widget_id: str | None) -> str | None:
        if widget_id and widget_id.startswith("f-") and widget_id[2:] in self.fields:
            return widget_id[2:]
        return None

    @on(Input.Changed)
    def _changed(self, event: Input.Changed) -> None:
        event.stop()
        key = self._key(event.input.id)
        if key is not None:
            try:
                parse(self.fields[key], event.value)
                self.error(key, None)
            except FieldError as exc:
                self.error(key, str(exc))
            self.post_message(self.Edited(self, self.fields[key]))

    @on(Input.Submitted)
    @on(Input.Blurred)
    def _done(self, event: Input.Submitted | Input.Blurred) -> None:
        event.stop()
        key = self._key(event.input.id)
        if key is not None:
            self._commit(key)

    @on(Select.Changed)
    def _chosen(self, event: Select.Changed) -> None:
        event.stop()
        key = self._key(event.select.id)
        if key is not None:
            self.post_message(self.Edited(self, self.fields[key]))
            self._commit(key)
