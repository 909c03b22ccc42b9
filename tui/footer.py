"""The footer, fitted to the terminal: the editor's own keys first, names shortened when
the full ones do not fit.

Textual's footer lists the focused widget's keys first and lets the rest run off
the right edge, so at 80 columns f1, f3, f4 and f5 were never seen.  Here the keys
of the app and of the screen (save, undo, help, the editors) come first, then the
focused widget's; when they do not fit, each name is shortened (``Formats`` ->
``Fmt``), and only then are the widget's keys left to the help screen (f1).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from textual.app import ComposeResult
from textual.binding import Binding
from textual.screen import Screen
from textual.widgets import Footer
from textual.widgets._footer import FooterKey

#: short names for narrow terminals
SHORT = {
    "Save": "Save", "Undo": "Undo", "Redo": "Redo", "Quit": "Quit", "Help": "Help",
    "Formats": "Fmt", "Variables": "Var", "Machine": "Mach", "Review": "Rev",
    "Samples": "CL", "+Item": "+It", "−Item": "−It", "+Block": "+Bl", "Edit": "Edit",
    "Go to cell": "Cell", "Set flags": "Set", "Edit value": "Edit", "Reset value": "Reset",
}
#: the main keys' order: what a newcomer looks for first
ORDER = {key: index for index, key in enumerate(
    ("f1", "ctrl+s", "ctrl+z", "ctrl+y", "f2", "f3", "f4", "f5", "f6", "ctrl+q"))}
#: room kept for the command palette key at the right (its name is left out when narrow)
PALETTE = 13
PALETTE_NARROW = 5


def _cost(key: str, description: str) -> int:
    return len(key) + (len(description) + 1 if description else 0) + 1


def fit(keys: Iterable[tuple[str, str, bool]], width: int) -> list[tuple[str, str]]:
    """(key display, description) pairs that fit ``width``.  ``keys`` are (display,
    description, essential), essential ones first.  Full names when the essential keys
    fit with them (the others follow while there is room), else short names."""
    keys = list(keys)
    for names in ({}, SHORT):
        chosen = [(key, names.get(text, text), essential) for key, text, essential in keys]
        used = sum(_cost(key, text) for key, text, essential in chosen if essential)
        if used > width and names is not SHORT:
            continue
        result = []
        for key, text, essential in chosen:
            if not essential:
                if used + _cost(key, text) > width:
                    continue
                used += _cost(key, text)
            result.append((key, text))
        return result
    return []


class EditorFooter(Footer):
    """Every main key, shortened at 80 columns."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._shown: tuple[object, ...] = ()

    def _signature(self) -> tuple[object, ...]:
        """What the footer would show: rebuilding it costs a layout, so only on a change."""
        return (self.size.width, tuple(
            (binding.key, binding.description, enabled)
            for _node, binding, enabled, _tooltip in self.screen.active_bindings.values()
            if binding.show))

    def bindings_changed(self, screen: Screen[Any]) -> None:
        self._bindings_ready = True
        if not screen.app.app_focus or not self.is_attached or screen is not self.screen:
            return
        signature = self._signature()
        if signature != self._shown:
            self._shown = signature
            self.call_after_refresh(self.recompose)

    def compose(self) -> ComposeResult:
        if not self._bindings_ready:
            return
        app = self.app
        seen: set[str] = set()
        shown: list[tuple[Binding, bool, str, bool]] = []
        for node, binding, enabled, tooltip in self.screen.active_bindings.values():
            if not binding.show or binding.action in seen:
                continue
            seen.add(binding.action)
            # the app's keys and the function keys (the editors) are the main keys
            essential = node is app or binding.key.startswith("f")
            shown.append((binding, enabled, tooltip, essential))
        shown.sort(key=lambda entry: (not entry[3], ORDER.get(entry[0].key, len(ORDER))))
        total = self.size.width or app.size.width
        narrow = total < 100
        width = total - (PALETTE_NARROW if narrow else PALETTE)
        fitted = dict(fit(((app.get_key_display(b), b.description, essential)
                           for b, _enabled, _tooltip, essential in shown), width))
        for binding, enabled, tooltip, _essential in shown:
            key = app.get_key_display(binding)
            if key not in fitted:
                continue
            yield FooterKey(binding.key, key, fitted[key], binding.action,
                            disabled=not enabled, tooltip=tooltip or binding.description,
                            ).data_bind(compact=Footer.compact)
        if self.show_command_palette and app.ENABLE_COMMAND_PALETTE:
            try:
                _node, binding, enabled, tooltip = self.screen.active_bindings[
                    app.COMMAND_PALETTE_BINDING]
            except KeyError:
                return
            yield FooterKey(binding.key, app.get_key_display(binding),
                            "" if narrow else binding.description,
                            binding.action, classes="-command-palette", disabled=not enabled,
                            tooltip=binding.tooltip or binding.description)

    def on_resize(self) -> None:
        self._shown = ()
        self.bindings_changed(self.screen)
