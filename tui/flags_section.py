"""The flags part of the variables editor: the post's ``flags:`` declarations.

A flag is declared with its value at the start of the program; tables change it
with ``set:`` (``s`` on the grid) and conditions read it.  Here a flag is added (its
name checked against every name the post already knows), its start value changed,
or removed — refused while a table still sets or reads it, naming those tables, as
the post would not load without the declaration.
"""

from __future__ import annotations

import copy
from typing import TYPE_CHECKING, Any

from rich.text import Text
from ruamel.yaml.comments import CommentedMap
from textual.widgets import DataTable

from tui import edits
from tui.dialogs import PromptDialog
from tui.flags import check_flag_name, check_start_value, flag_users, start_value
from tui.model import show_value
from tui.tables import fill

if TYPE_CHECKING:
    from collections.abc import Callable

    from textual.app import App

    from tui.document import PostDocument


def append_key(mapping: CommentedMap, key: str, value: Any) -> None:
    """Add ``key`` last in a block mapping.  The blank lines after the last entry belong
    to its comment in ruamel; they move to the new entry, so the section still ends
    with them and the next section does not move up."""
    last = list(mapping)[-1]
    token = (mapping.ca.items.get(last) or [None] * 4)[2]
    after = None
    if token is not None:
        head, _newline, rest = token.value.partition("\n")
        if rest:
            after = copy.copy(token)
            after.value = "\n" + rest
            token.value = head + "\n"
    mapping[key] = value
    if after is not None:
        mapping.ca.items[key] = [None, None, after, None]


def remove_key(mapping: CommentedMap, key: str) -> None:
    """Delete ``key``; when it is the last entry, the blank lines after it stay (they go
    back to the entry before it), the reverse of :func:`append_key`."""
    keys = list(mapping)
    token = (mapping.ca.items.get(key) or [None] * 4)[2]
    rest = token.value.partition("\n")[2] if token is not None else ""
    del mapping[key]
    if keys[-1] != key or not rest:
        return
    before: list[Any] = mapping.ca.items.setdefault(keys[-2], [None] * 4)
    if before[2] is None:
        moved = copy.copy(token)
        moved.value = "\n" + rest
        before[2] = moved
    else:
        before[2].value += rest


class FlagsTable(DataTable[Any]):
    """The post's flags, one a row: name, start value, the tables that set or read it."""

    def show(self, doc: PostDocument, current: str | None) -> str | None:
        """Fill the rows; the flag under the cursor afterwards (``current`` if still there)."""
        model = doc.model
        rows = []
        for name, flag in model.flags.items():
            users = flag_users(model, name)
            origin = Text(" ↑ base", style="dim") if model.inherited(("flags", name)) else ""
            rows.append(((Text(name, style="bold"), show_value(flag.value),
                          ", ".join(users) or Text("unused", style="dim"), origin), name))
        row = self.cursor_row
        fill(self, [("flag", "name"), ("start value", "value"), ("set or read by", "used"),
                    ("", "origin")], rows)
        names = list(model.flags)
        if not names:
            return None
        if current in names:
            row = names.index(current)
        row = max(0, min(row, len(names) - 1))
        self.move_cursor(row=row, animate=False)
        return names[row]


class FlagActions:
    """Add, change and remove flags; mixed into the variables editor, which owns the keys."""

    doc: PostDocument
    app: App[Any]
    current_flag: str | None
    change: Callable[..., bool]
    notify: Callable[..., None]

    def edit_flag(self) -> None:
        name = self.current_flag
        if name is None:
            self.add_flag()
            return
        flag = self.doc.model.flags.get(name)

        def done(text: str | None) -> None:
            if text is not None:
                self.change(f"flag {name}", lambda data: edits.set_value(
                    data, ("flags", name), start_value(text)))

        self.app.push_screen(PromptDialog(
            f"Start value of flag {name}", show_value(flag.value if flag else None),
            help="the value before any table sets it: a number, true/false, none or text"
                 + (" (saved in this post: it replaces the base post's)"
                    if self.doc.model.inherited(("flags", name)) else ""),
            check=check_start_value), done)

    def add_flag(self) -> None:
        def named(name: str | None) -> None:
            if not name:
                return

            def valued(text: str | None) -> None:
                if text is not None:
                    self.current_flag = name
                    self.change(f"add flag {name}", lambda data: self._append(
                        data, name, start_value(text)))

            self.app.push_screen(PromptDialog(
                f"Start value of flag {name}", "false",
                help="the value before any table sets it: a number, true/false, none or "
                     "text", check=check_start_value), valued)

        self.app.push_screen(PromptDialog(
            "New flag name", help="state the post keeps: tables set it (s on the grid), "
                                  "conditions read it",
            check=lambda text: check_flag_name(self.doc.model, text)), named)

    def delete_flag(self) -> None:
        name = self.current_flag
        if name is None:
            return
        model = self.doc.model
        if model.inherited(("flags", name)):
            self.notify(f"flag '{name}' is declared in the base post: it cannot be removed "
                        f"from this one", severity="error")
            return
        users = flag_users(model, name)
        if users:
            self.notify(f"flag '{name}' cannot be removed: {', '.join(users)} still set or "
                        f"read it; change those tables first", severity="error")
            return
        self.current_flag = None
        self.change(f"delete flag {name}", lambda data: self._remove(data, name))

    @staticmethod
    def _append(data: Any, name: str, value: Any) -> None:
        """A new flag goes after the others, where a reader of ``flags:`` looks last."""
        flags = data.get("flags")
        if isinstance(flags, CommentedMap) and flags:
            append_key(flags, name, edits.styled(value))
        else:
            edits.set_value(data, ("flags", name), value)

    @staticmethod
    def _remove(data: Any, name: str) -> None:
        flags = data.get("flags")
        if isinstance(flags, CommentedMap) and len(flags) > 1:
            remove_key(flags, name)
        else:
            edits.set_value(data, ("flags", name), None)
        if "flags" in data and not data["flags"]:
            del data["flags"]
