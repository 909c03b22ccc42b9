"""The messages that tell every screen the post changed, and the one way to change it.

An edit can start anywhere (the grid, the formats editor, undo); every screen that
shows the post must then show it again.  Rather than the app calling each
screen's refresh methods, the screen that edits posts :class:`DocumentChanged`;
it bubbles to the app, which sends it on to every screen of the stack.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ruamel.yaml.comments import CommentedMap
from textual.message import Message
from textual.widget import Widget

from tui.document import PostDocument


class DocumentChanged(Message):
    """The post document changed (an edit, undo or redo).

    ``delivered`` is False on the way up to the app and True on the copies the
    app sends to each screen, so a screen's copy is not sent round again.
    """

    def __init__(self, label: str = "", delivered: bool = False) -> None:
        super().__init__()
        self.label = label
        self.delivered = delivered


class DocumentSaved(Message):
    """The post was written to its file: nothing is unsaved any more."""

    def __init__(self, delivered: bool = False) -> None:
        super().__init__()
        self.delivered = delivered


def edit_document(node: Widget, doc: PostDocument, label: str,
                  change: Callable[[CommentedMap], Any]) -> bool:
    """Apply one edit (one undo step) and tell every screen; False when nothing changed.

    An edit that fails is reported, never raised: a bug in one edit must not take the
    editor, and the unsaved work, down.
    """
    try:
        changed = doc.edit(label, change)
    except Exception as exc:
        node.notify(f"{label}: {exc}", title="Edit failed", severity="error")
        return False
    if changed:
        node.post_message(DocumentChanged(label))
    return changed


class DocumentView:
    """What a screen that shows and edits the post has in common: it is given the
    document (never the app), edits it with :meth:`change`, and shows it again when
    any screen changed it (:meth:`document_changed`).

    Mix it into a Screen class: ``class FormatsEditor(DocumentView, ModalScreen[None])``.
    """

    #: undo and redo may change the post while this screen is open
    SHOWS_DOCUMENT = True
    doc: PostDocument

    def change(self, label: str, change: Callable[[CommentedMap], Any]) -> bool:
        """One undoable edit of the post, shown on every screen."""
        return edit_document(self, self.doc, label, change)  # type: ignore[arg-type]  # mixed into a Screen

    def on_document_changed(self, message: DocumentChanged) -> None:
        if message.delivered:
            self.document_changed()

    def on_document_saved(self, message: DocumentSaved) -> None:
        if message.delivered:
            self.document_saved()

    def document_changed(self) -> None:
        """Show the post again (after an edit, undo or redo on any screen)."""
        raise NotImplementedError(f"{type(self).__name__} must show the changed document")

    def document_saved(self) -> None:
        """The post was saved; most screens show nothing different."""
