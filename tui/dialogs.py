"""Small modal dialogs: a question with answers, and a one-line prompt."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import ClassVar

from textual import on
from textual.app import ComposeResult
from textual.binding import Binding, BindingType
from textual.containers import Horizontal, Vertical
from textual.events import Key
from textual.screen import ModalScreen
from textual.widget import Widget
from textual.widgets import Button, Input, Label, Static


def focus_now(widget: Widget) -> None:
    """Give ``widget`` the focus at once, not after the pending messages.

    ``Widget.focus()`` waits for the message queue; a dialog that focuses its field so,
    on mount, loses the keys typed in the same burst as the key that opened it (they
    reach a screen with nothing focused).  Call it from ``on_mount``.
    """
    widget.screen.set_focus(widget)


class DialogInput(Input):
    """An ``Input`` that applies every key in the order typed.

    Textual inserts a printable key in the field's own ``_on_key`` but runs the field's
    editing bindings (backspace, delete, home, end, ctrl+a, ctrl+k, ...) only once the
    key has bubbled up, one message queue at a time, to ``App._on_key``.  Keys of one
    burst (a fast typist, a terminal multiplexer, a paste of keys) are all queued at the
    field first, so its printable keys were inserted before the editing keys typed
    before them: ``ctrl+a ctrl+k 4 2`` left the field empty.  Here the field's own
    bindings run at once, in ``_on_key``; every other key goes on as before.
    """

    async def _on_key(self, event: Key) -> None:
        if not event.is_printable:
            # the same bindings, in the same way, as App._check_bindings runs for the
            # focused widget (priority bindings were checked before the key came here)
            for binding in self._bindings.key_to_bindings.get(event.key, ()):
                if not binding.priority and await self.app.run_action(binding.action, self):
                    event.stop()
                    event.prevent_default()
                    return
        await super()._on_key(event)


class ButtonRow(Horizontal):
    """A dialog's buttons: left and right move between them, as in any dialog box."""

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("left", "step(-1)", "Previous button", show=False),
        Binding("right", "step(1)", "Next button", show=False),
    ]

    def action_step(self, offset: int) -> None:
        buttons = [button for button in self.query(Button) if button.focusable]
        if not buttons:
            return
        focused = self.screen.focused
        index = buttons.index(focused) if focused in buttons else 0
        buttons[(index + offset) % len(buttons)].focus()


@dataclass(frozen=True)
class Choice:
    id: str
    label: str
    key: str
    variant: str = "default"


class ConfirmDialog(ModalScreen[str]):
    """A question; dismissed with the chosen answer's id (``cancel`` on escape)."""

    BINDINGS: ClassVar[list[BindingType]] = [Binding("escape", "choose('cancel')", "Cancel")]

    def __init__(self, title: str, message: str, choices: Sequence[Choice],
                 focus: str = "cancel", id: str | None = None) -> None:
        super().__init__(id=id)
        self.title_text = title
        self.message = message
        self.choices = list(choices)
        self.initial = focus

    def compose(self) -> ComposeResult:
        with Vertical(classes="dialog"):
            yield Label(self.title_text, classes="dialog-title")
            yield Static(self.message, classes="dialog-message", markup=False)
            with ButtonRow(classes="dialog-buttons"):
                for choice in self.choices:
                    yield Button(f"{choice.label} [{choice.key}]", id=f"choice-{choice.id}",
                                 variant=choice.variant, compact=True)  # type: ignore[arg-type]  # variant: one of Button's names

    def on_mount(self) -> None:
        focus_now(self.query_one(f"#choice-{self.initial}", Button))

    def on_key(self, event: Key) -> None:
        for choice in self.choices:
            if event.key == choice.key:
                event.stop()
                self.dismiss(choice.id)

    @on(Button.Pressed)
    def _pressed(self, event: Button.Pressed) -> None:
        event.stop()
        self.dismiss((event.button.id or "choice-cancel").removeprefix("choice-"))

    def action_choose(self, choice: str) -> None:
        self.dismiss(choice)


class PromptDialog(ModalScreen[str | None]):
    """One line of input; ``check`` returns an error shown under the field (None: fine)."""

    BINDINGS: ClassVar[list[BindingType]] = [Binding("escape", "cancel", "Cancel")]

    def __init__(self, title: str, value: str = "", *, help: str = "",
                 check: Callable[[str], str | None] | None = None,
                 placeholder: str = "") -> None:
        super().__init__()
        self.title_text = title
        self.value = value
        self.help = help
        self.check = check
        self.placeholder = placeholder

    def compose(self) -> ComposeResult:
        with Vertical(classes="dialog"):
            yield Label(self.title_text, classes="dialog-title")
            if self.help:
                yield Static(self.help, classes="dialog-message", markup=False)
            yield DialogInput(self.value, placeholder=self.placeholder, id="prompt-input")
            yield Static("", id="prompt-error", classes="field-error", markup=False)
            yield Static("enter: OK · escape: cancel", classes="dialog-hint")

    def on_mount(self) -> None:
        focus_now(self.query_one(Input))

    @on(Input.Changed)
    def _changed(self, event: Input.Changed) -> None:
        self._show(self.check(event.value) if self.check else None)

    @on(Input.Submitted)
    def _submitted(self, event: Input.Submitted) -> None:
        event.stop()
        error = self.check(event.value) if self.check else None
        self._show(error)
        if error is None:
            self.dismiss(event.value)

    def _show(self, error: str | None) -> None:
        label = self.query_one("#prompt-error", Static)
        label.update(error or "")
        label.set_class(bool(error), "-shown")

    def action_cancel(self) -> None:
        self.dismiss(None)
