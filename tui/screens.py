"""The registry of the editor's extra screens (formats, variables, machine settings, …).

Each screen is registered with a name, a title for the command palette and an
optional key; the app binds the keys and lists every screen in the palette.
A later tool adds its own screen without touching the app, e.g. the review
of a post change::

    from tui.screens import register_screen
    register_screen("review", "Review post changes", ReviewScreen, key="f5")

The factory receives the editor's main screen (:class:`tui.main_screen.MainScreen`)
and gives the new screen what it needs of it — the post document, the sample
program — never the app.  A screen that shows the post handles
:class:`tui.messages.DocumentChanged` (sent after every edit, undo and redo) and
sets ``SHOWS_DOCUMENT = True``, so undo and redo work while it is open.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from textual.screen import Screen

if TYPE_CHECKING:
    from tui.main_screen import MainScreen


@dataclass(frozen=True)
class ScreenEntry:
    name: str
    title: str
    factory: Callable[[MainScreen], Screen[Any]]
    help: str = ""
    key: str | None = None
    #: the key's name in the footer (default: the title's first word)
    short: str = ""


_SCREENS: dict[str, ScreenEntry] = {}


def register_screen(name: str, title: str, factory: Callable[[MainScreen], Screen[Any]],
                    *, help: str = "", key: str | None = None, short: str = "") -> None:
    """Make a screen available to the editor (palette entry, and ``key`` when given)."""
    _SCREENS[name] = ScreenEntry(name, title, factory, help, key, short)


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

    register_screen("formats", "Formats", lambda main: FormatsEditor(main.doc), key="f2",
                    help="Edit the named number formats, with live examples")
    register_screen("variables", "Variables",
                    lambda main: VariablesEditor(main.doc, main.overrides), key="f3",
                    help="Edit the post's variables and see where they are written")
    register_screen("settings", "Machine settings",
                    lambda main: SettingsEditor(main.doc, main.program_view), key="f4",
                    short="Machine",
                    help="Machine data, limits, block numbering and line ending")
    register_screen("review", "Review unsaved changes",
                    lambda main: ReviewScreen(main.doc, main.sample_path), key="f5",
                    short="Review",
                    help="The NC lines the unsaved edits change in the machine's programs")


_register_builtins()
