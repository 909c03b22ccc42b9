"""The registry of the editor's extra screens (formats, variables, machine settings, …).

Each screen is registered with a name, a title for the command palette and an
optional key; the app binds the keys and lists every screen in the palette.
A later tool adds its own screen without touching the app, e.g. the review
of a post change::

    from tui.screens import register_screen
    register_screen("review", "Review post changes", ReviewScreen, key="f5")

The factory receives the running :class:`tui.app.EditorApp` (its ``doc``,
``program_lines``, ``change()``…) and returns the screen to push.  A screen
that shows the post may define ``document_changed()``: the app calls it after
every edit, undo and redo.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from textual.screen import Screen

if TYPE_CHECKING:
    from tui.app import EditorApp


@dataclass(frozen=True)
class ScreenEntry:
    name: str
    title: str
    factory: Callable[[EditorApp], Screen[Any]]
    help: str = ""
    key: str | None = None
    #: show the key in the footer (the footer has room for few keys at 80 columns)
    footer: bool = False


_SCREENS: dict[str, ScreenEntry] = {}


def register_screen(name: str, title: str, factory: Callable[[EditorApp], Screen[Any]],
                    *, help: str = "", key: str | None = None, footer: bool = False) -> None:
    """Make a screen available to the editor (palette entry, and ``key`` when given)."""
    _SCREENS[name] = ScreenEntry(name, title, factory, help, key, footer)


def registered_screens() -> list[ScreenEntry]:
    """Every registered screen, in registration order."""
    return list(_SCREENS.values())


def screen_entry(name: str) -> ScreenEntry | None:
    """The registered screen ``name``, or None."""
    return _SCREENS.get(name)


def _register_builtins() -> None:
    from tui.formats_editor import FormatsEditor
    from tui.review_screen import ReviewScreen
    from tui.settings_editor import SettingsEditor
    from tui.variables_editor import VariablesEditor

    register_screen("formats", "Formats", FormatsEditor, key="f2", footer=True,
                    help="Edit the named number formats, with live examples")
    register_screen("variables", "Variables", VariablesEditor, key="f3",
                    help="Edit the post's variables and see where they are written")
    register_screen("settings", "Machine settings", SettingsEditor, key="f4",
                    help="Machine data, limits, block numbering and line ending")
    register_screen("review", "Review unsaved changes", ReviewScreen, key="f5",
                    help="The NC lines the unsaved edits change in the machine's programs")


_register_builtins()
