"""The block editor: a block's condition, block numbering and repetition."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, ClassVar

from textual import on
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, Vertical
from textual.screen import ModalScreen
from textual.widgets import Button, Input, Label, Select, Static

from postdsl import api
from tui.dialogs import ButtonRow, DialogInput, focus_now
from tui.model import BlockView

YES_NO = [("yes", True), ("no", False)]


class BlockEditor(ModalScreen["dict[str, Any] | None"]):
    """Dismissed with the block's new properties (None values remove a key) or None."""

    BINDINGS: ClassVar[list[BindingType]] = [Binding("escape", "cancel", "Cancel")]

    def __init__(self, title: str, block: BlockView, post: api.Post,
                 numbered_by_default: bool, extra_names: Sequence[str] = (),
                 problem: str | None = None) -> None:
        super().__init__()
        self.title_text = title
        self.block = block
        self.post = post
        self.default = numbered_by_default
        self.extra_names = extra_names
        self.problem = problem

    def compose(self) -> ComposeResult:
        block = self.block
        default = "yes" if self.default else "no"
        with Vertical(id="block-editor", classes="dialog"):
            yield Label(self.title_text, classes="dialog-title")
            with Horizontal(classes="row"):
                yield Label("Condition", classes="field-label")
                yield DialogInput(block.condition, compact=True, id="condition",
                            placeholder="write the block only if…, e.g. spindle != 'off'")
            yield Static("", id="condition-error", classes="field-error")
            with Horizontal(classes="row"):
                yield Label("Numbered", classes="field-label")
                yield Select(YES_NO, value=block.numbered if block.explicit_number
                             else Select.NULL, prompt=f"post default ({default})",
                             compact=True, id="number")
            with Horizontal(classes="row"):
                yield Label("Renumber", classes="field-label")
                yield Select(YES_NO, value=True if block.renumber else Select.NULL,
                             prompt="no (restart numbering here: yes)", compact=True,
                             id="renumber")
            with Horizontal(classes="row"):
                yield Label("Only if valued", classes="field-label")
                yield Select(YES_NO, value=True if block.only_with_values else Select.NULL,
                             prompt="no (yes: skip the block when no parameter is written)",
                             compact=True, id="only_with_values")
            with Horizontal(classes="row"):
                yield Label("Repeat", classes="field-label")
                yield Select([("once per tool of the program", "tool")],
                             value=block.for_each or Select.NULL, prompt="once",
                             compact=True, id="for_each")
            with ButtonRow(classes="dialog-buttons"):
                yield Button("OK", id="ok", variant="primary", compact=True)
                yield Button("Cancel", id="cancel", compact=True)
            yield Static("enter: OK · escape: cancel", classes="dialog-hint")

    def on_mount(self) -> None:
        if self.problem:
            self._error(self.problem)
        else:
            self._check(self.block.condition)
        focus_now(self.query_one("#condition", Input))

    def _error(self, message: str | None) -> None:
        label = self.query_one("#condition-error", Static)
        label.update(message or "")
        label.set_class(bool(message), "-shown")
        self.query_one("#condition", Input).set_class(bool(message), "-invalid")

    def _check(self, source: str) -> None:
        if not source.strip():
            self._error(None)
            return
        result = api.check_expression(source.strip(), self.post, self.extra_names)
        self._error(None if result.error is None else
                    f"{' ' * result.column}^ {result.error}" if result.column < 40
                    else result.error)

    @on(Input.Changed, "#condition")
    def _changed(self, event: Input.Changed) -> None:
        self._check(event.value)

    @on(Input.Submitted)
    def _submitted(self) -> None:
        self.action_ok()

    @on(Button.Pressed)
    def _pressed(self, event: Button.Pressed) -> None:
        event.stop()
        if event.button.id == "ok":
            self.action_ok()
        else:
            self.action_cancel()

    def action_ok(self) -> None:
        def value(id: str) -> Any:
            chosen = self.query_one(f"#{id}", Select).value
            return None if chosen == Select.NULL else chosen

        self.dismiss({
            "if": self.query_one("#condition", Input).value.strip() or None,
            "number": value("number"),
            "renumber": True if value("renumber") else None,
            "only_with_values": True if value("only_with_values") else None,
            "for_each": value("for_each"),
        })

    def action_cancel(self) -> None:
        self.dismiss(None)
