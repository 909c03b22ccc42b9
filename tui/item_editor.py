"""The item editor: one cell of a command table, as PPU's Item Properties.

Text, parameter (picked from the CL vocabulary and the post's variables) or a
computed value; prefix and suffix; the number format (each shown with the
sample value it would write); output mode; and the condition, checked as it
is typed with the error right under the field.  The line at the bottom shows
what the item writes for the sample values.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

from rich.text import Text
from textual import on
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, Vertical, VerticalScroll
from textual.screen import ModalScreen
from textual.widgets import Button, Input, Label, Select, Static

from postdsl import api
from tui.dialogs import ButtonRow, DialogInput, focus_now
from tui.model import MODES, ItemSpec, format_names, format_spec, show_value, visible

KINDS = (("Text", "text"), ("Parameter", "param"), ("Computed value", "expr"))
EXAMPLE_NUMBER = 1234.5678


@dataclass
class ItemContext:
    """What the editor needs to know around the item."""

    title: str
    post: api.Post
    samples: Mapping[str, Any] = field(default_factory=dict)
    extra_names: Sequence[str] = ()
    #: field key (value, prefix, format, mode, if, …) -> problem message
    problems: Mapping[str, str] = field(default_factory=dict)
    new: bool = False
    #: the CL command whose table is edited ('' for a custom cycle or a structure)
    command: str = ""


def set_by(name: str, source: str, command: str) -> str:
    """Which CL records give parameter ``name`` its value, said from the table being
    edited: Break Chip's peck is set by Break Chip, not by the first command that has one."""
    setters = api.commands_setting(name)
    if command and command in setters:
        return f" · set by this command ({command})"
    if setters:
        shown = ", ".join(setters[:3]) + (", …" if len(setters) > 3 else "")
        return f" · set by {shown}"
    return f" · {source}" if source else ""


def render_example(spec: ItemSpec, context: ItemContext) -> Text:
    """What the item writes for the sample values, spaces made visible."""
    if spec.kind == "text":
        body = spec.value
    elif spec.kind == "expr":
        return Text("computed when posted — see the preview", style="dim italic")
    else:
        if spec.value not in context.samples:
            return Text(f"no sample value for '{spec.value}'", style="dim italic")
        value = context.samples[spec.value]
        if value is None:
            return Text(f"'{spec.value}' has no value: the item writes nothing", style="dim")
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            fmt = format_spec(context.post, spec.format) if spec.format else None
            if spec.format and fmt is None:
                return Text(f"unknown format '{spec.format}'", style="red")
            try:
                body = api.render_number(fmt, value) if fmt is not None else show_value(value)
            except api.FormatSpecError as exc:
                return Text(f"format '{spec.format}': {exc.message}", style="red")
        else:
            body = show_value(value)
    text = Text(visible(spec.prefix + body + spec.suffix), style="bold")
    if spec.condition:
        text.append("   (when the condition holds)", style="dim")
    return text


class ItemEditor(ModalScreen["ItemSpec | str | None"]):
    """Edit one item; dismissed with the new ItemSpec, ``"delete"``, or None (cancel)."""

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("escape", "cancel", "Cancel"),
        Binding("ctrl+o", "ok", "OK"),
    ]

    def __init__(self, spec: ItemSpec, context: ItemContext) -> None:
        super().__init__()
        self.spec = spec
        self.context = context

    # --- layout --------------------------------------------------------------------------

    def compose(self) -> ComposeResult:
        spec, context = self.spec, self.context
        with Vertical(id="item-editor", classes="dialog wide"):
            yield Label(context.title, classes="dialog-title")
            with VerticalScroll(classes="form", can_focus=False):
                with Horizontal(classes="row"):
                    yield Label("Kind", classes="field-label")
                    yield Select(KINDS, value=spec.kind, allow_blank=False, compact=True,
                                 id="kind")
                with Horizontal(classes="row", id="row-text"):
                    yield Label("Text", classes="field-label")
                    yield DialogInput(spec.value if spec.kind == "text" else "", compact=True,
                                id="text", placeholder="fixed text, e.g. G83 or  J11")
                with Horizontal(classes="row", id="row-param"):
                    yield Label("Parameter", classes="field-label")
                    yield Select(self._param_options(),
                                 value=spec.value if spec.kind == "param" and
                                 spec.value in self._param_names() else Select.NULL,
                                 prompt="pick a parameter (type to search)", compact=True,
                                 id="param")
                yield Static("", id="param-doc", classes="field-help")
                with Horizontal(classes="row", id="row-expr"):
                    yield Label("Expression", classes="field-label")
                    yield DialogInput(spec.value if spec.kind == "expr" else "", compact=True,
                                id="expr", placeholder="e.g. floor(machining_time / 60)")
                yield Static("", id="expr-error", classes="field-error")
                with Horizontal(classes="row"):
                    yield Label("Prefix", classes="field-label")
                    yield DialogInput(spec.prefix, compact=True, id="prefix",
                                placeholder="address and the space before it, e.g. ' X'")
                with Horizontal(classes="row"):
                    yield Label("Suffix", classes="field-label")
                    yield DialogInput(spec.suffix, compact=True, id="suffix")
                with Horizontal(classes="row"):
                    yield Label("Format", classes="field-label")
                    yield Select(self._format_options(),
                                 value=spec.format if spec.format in
                                 format_names(context.post) else Select.NULL,
                                 prompt="no format (numbers as they are)", compact=True,
                                 id="format")
                yield Static("", id="format-error", classes="field-error")
                with Horizontal(classes="row"):
                    yield Label("Output", classes="field-label")
                    yield Select([(m, m) for m in MODES], value=spec.mode
                                 if spec.mode in MODES else "always", allow_blank=False,
                                 compact=True, id="mode")
                with Horizontal(classes="row"):
                    yield Label("Register", classes="field-label")
                    yield DialogInput(spec.modal, compact=True, id="modal",
                                placeholder="modal word compared for 'changed' (default: the "
                                            "parameter)")
                yield Static("", id="mode-error", classes="field-error")
                with Horizontal(classes="row"):
                    yield Label("Condition", classes="field-label")
                    yield DialogInput(spec.condition, compact=True, id="condition",
                                placeholder="write only if…, e.g. dwell > 0")
                yield Static("", id="condition-error", classes="field-error")
            with Horizontal(classes="row example-row"):
                yield Label("Writes", classes="field-label")
                yield Static("", id="example")
            with ButtonRow(classes="dialog-buttons"):
                yield Button("OK", id="ok", variant="primary", compact=True)
                yield Button("Cancel", id="cancel", compact=True)
                if not self.context.new:
                    yield Button("Delete item", id="delete", variant="error", compact=True)
            yield Static("enter: OK · escape: cancel · tab: next field", classes="dialog-hint")

    def _param_names(self) -> list[str]:
        return [value for _, value in self._param_options()]

    def _param_options(self) -> list[tuple[str, str]]:
        options = []
        for name in self.context.extra_names:
            options.append((f"{name}  (cycle parameter)", name))
        for name, variable in self.context.post.variables.items():
            value = variable.value
            options.append((f"{name}  = {show_value(value)}  (variable)", str(name)))
        for name, info in api.parameters().items():
            unit = f" [{info.unit}]" if info.unit else ""
            options.append((f"{name}  {info.doc}{unit}", name))
        if self.spec.kind == "param" and self.spec.value not in {v for _, v in options}:
            options.insert(0, (f"{self.spec.value}  (unknown)", self.spec.value))
        return options

    def _format_options(self, param: str | None = None) -> list[tuple[Text, str]]:
        if param is None:
            param = self.spec.value if self.spec.kind == "param" else ""
        sample = self._sample_number(param)
        options = []
        for name in format_names(self.context.post):
            spec = format_spec(self.context.post, name) or {}
            label = Text(f"{name:<14}")
            try:
                label.append(f"{show_value(sample)} → {api.render_number(spec, sample)}",
                             style="dim")
            except api.FormatSpecError as exc:
                label.append(exc.message, style="red")
            options.append((label, str(name)))
        return options

    def _sample_number(self, param: str) -> float:
        value = self.context.samples.get(param)
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return value
        return EXAMPLE_NUMBER

    def on_mount(self) -> None:
        self._show_kind(self.spec.kind)
        for key, message in self.context.problems.items():
            target = {"if": "condition-error", "expr": "expr-error", "param": "param-doc",
                      "format": "format-error", "mode": "mode-error", "modal": "mode-error",
                      "force_if": "condition-error"}.get(key, "condition-error")
            self._error(target, message)
        self._check_condition(self.spec.condition, initial=True)
        self._refresh()
        focus = {"text": "#text", "param": "#param", "expr": "#expr"}[self.spec.kind]
        focus_now(self.query_one(focus))

    # --- state -----------------------------------------------------------------------------

    def current(self) -> ItemSpec:
        """The item as the fields say now (not yet applied)."""
        kind = self.query_one("#kind", Select).value
        kind = kind if isinstance(kind, str) else "text"
        if kind == "param":
            param = self.query_one("#param", Select).value
            value = param if isinstance(param, str) else ""
        else:
            value = self.query_one(f"#{kind}", Input).value
        fmt = self.query_one("#format", Select).value
        mode = self.query_one("#mode", Select).value
        return ItemSpec(kind=kind, value=value,
                        prefix=self.query_one("#prefix", Input).value,
                        suffix=self.query_one("#suffix", Input).value,
                        format=fmt if isinstance(fmt, str) else "",
                        mode=mode if isinstance(mode, str) else "always",
                        modal=self.query_one("#modal", Input).value.strip(),
                        condition=self.query_one("#condition", Input).value.strip(),
                        force_if=self.spec.force_if, extra=dict(self.spec.extra))

    def _show_kind(self, kind: str) -> None:
        self.query_one("#row-text").display = kind == "text"
        self.query_one("#row-param").display = kind == "param"
        self.query_one("#param-doc").display = kind == "param"
        self.query_one("#row-expr").display = kind == "expr"
        self.query_one("#expr-error").display = kind == "expr" and \
            self.query_one("#expr-error").has_class("-shown")

    def _error(self, id: str, message: str | None) -> None:
        label = self.query_one(f"#{id}", Static)
        label.update(Text(message or "", style="bold red") if id == "param-doc" and message
                     else message or "")
        label.set_class(bool(message), "-shown")

    def _check_condition(self, source: str, initial: bool = False) -> bool:
        """Validate the condition as typed: the error, with a caret, under the field."""
        source = source.strip()
        if not source:
            self._error("condition-error", None)
            self.query_one("#condition", Input).remove_class("-invalid")
            return True
        result = api.check_expression(source, self.context.post, self.context.extra_names)
        if initial and result.error is None and self.context.problems.get("if"):
            return False
        self.query_one("#condition", Input).set_class(result.error is not None, "-invalid")
        if result.error is None:
            self._error("condition-error", None)
            return True
        self._error("condition-error",
                    f"{' ' * result.column}^ {result.error}" if result.column < 40
                    else result.error)
        return False

    def _check_expr(self, source: str) -> None:
        if self.query_one("#kind", Select).value != "expr":
            return
        result = api.check_expression(source, self.context.post, self.context.extra_names)
        self.query_one("#expr", Input).set_class(result.error is not None, "-invalid")
        self._error("expr-error", result.error)
        self.query_one("#expr-error").display = result.error is not None

    def _refresh(self) -> None:
        spec = self.current()
        info = api.parameters().get(spec.value) if spec.kind == "param" else None
        variables = {name: v.value for name, v in self.context.post.variables.items()}
        if spec.kind == "param" and not self.query_one("#param-doc").has_class("-shown"):
            if info is not None:
                where = set_by(spec.value, info.source, self.context.command)
                doc = f"{info.doc}{(' [' + info.unit + ']') if info.unit else ''}{where}"
            elif spec.value in variables:
                doc = f"variable of this post = {show_value(variables[spec.value])}"
            elif spec.value in self.context.extra_names:
                doc = "parameter of this custom cycle"
            else:
                doc = ""
            self.query_one("#param-doc", Static).update(Text(doc, style="dim"))
        mode_error = None
        if spec.mode != "always" and spec.kind in ("text", "expr") and not spec.modal:
            mode_error = f"a {'text' if spec.kind == 'text' else 'computed'} item in mode " \
                         f"'{spec.mode}' needs a register to compare with (e.g. motion)"
        if mode_error or not self.context.problems.get("mode"):
            self._error("mode-error", mode_error)
        self.query_one("#example", Static).update(render_example(spec, self.context))

    # --- events ----------------------------------------------------------------------------

    @on(Select.Changed)
    def _select_changed(self, event: Select.Changed) -> None:
        event.stop()
        if event.select.id == "kind":
            self._show_kind(str(event.value))
            self._check_expr(self.query_one("#expr", Input).value)
        if event.select.id == "param":
            self._error("param-doc", None)
            formats = self.query_one("#format", Select)
            keep = formats.value
            formats.set_options(self._format_options(
                event.value if isinstance(event.value, str) else ""))
            if keep != Select.NULL:
                formats.value = keep
        self._refresh()

    @on(Input.Changed)
    def _input_changed(self, event: Input.Changed) -> None:
        event.stop()
        if event.input.id == "condition":
            self._check_condition(event.value)
        elif event.input.id == "expr":
            self._check_expr(event.value)
        self._refresh()

    @on(Input.Submitted)
    def _submitted(self, event: Input.Submitted) -> None:
        event.stop()
        self.action_ok()

    @on(Button.Pressed)
    def _pressed(self, event: Button.Pressed) -> None:
        event.stop()
        if event.button.id == "ok":
            self.action_ok()
        elif event.button.id == "delete":
            self.dismiss("delete")
        else:
            self.action_cancel()

    def action_ok(self) -> None:
        spec = self.current()
        if spec.kind == "param" and not spec.value:
            self._error("param-doc", "pick a parameter first")
            return
        self.dismiss(spec)

    def action_cancel(self) -> None:
        self.dismiss(None)
