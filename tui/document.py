"""The post being edited: its text, the round-trip document, undo/redo and saving.

The *text* is the truth.  An edit changes the ruamel round-trip document in
place, the document is dumped, and :func:`tui.merge.merge_edit` keeps every
untouched region spelled exactly as before; the result is parsed again so
that every node knows its fresh line and column (the problems' ``file:line:column``;
a problem names its cell by its path).  Undo and redo are therefore snapshots of text: cheap for a
post, exact, and what is saved is always what the history shows.
"""

from __future__ import annotations

import io
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ruamel.yaml import YAML
from ruamel.yaml.comments import CommentedMap

from postdsl import api
from postdsl.lang.loader import PostSource, make_yaml, parse_yaml, read_source
from tui.merge import merge_edit

Path_ = tuple[Any, ...]


def editor_yaml() -> YAML:
    """The loader's YAML configuration, writing ``[a, {b: c}]`` as it was read.

    Without ``brace_single_entry_mapping_in_flow_sequence`` ruamel writes a
    one-key mapping inside a flow sequence as ``[a, b: c]`` (valid YAML, but not
    what the technologist wrote).
    """
    yaml = make_yaml()
    yaml.brace_single_entry_mapping_in_flow_sequence = True
    return yaml


def dump(data: Any) -> str:
    """A document as the editor writes it (before merging with the original text)."""
    stream = io.StringIO()
    editor_yaml().dump(data, stream)
    return stream.getvalue()


@dataclass(frozen=True)
class Snapshot:
    label: str
    text: str


class PostDocument:
    """One post file open in the editor."""

    def __init__(self, path: str | Path) -> None:
        source = read_source(path)
        self.path = Path(path)
        self.file = source.file
        self.saved_text = source.text
        self.undo_stack: list[Snapshot] = []
        self.redo_stack: list[Snapshot] = []
        #: the undo depth at which the text is the saved one; None once an edit made
        #: after undoing past it took the saved state out of the history
        self.saved_depth: int | None = 0
        #: option values the preview posts with (the post's defaults for the others);
        #: not part of the file: a post's options are set when posting
        self.options: dict[str, Any] = {}
        self._load(source.text, source.data)

    # --- state ---------------------------------------------------------------------------

    def _load(self, text: str, data: CommentedMap | None = None, stale: bool = False) -> None:
        """Make ``text`` current; ``data`` is its document when the caller has it.

        After an edit the document is already the new text's document, but the
        nodes it changed have no positions (``stale``); positions only matter to the
        problems' line and column (their paths are exact either way), so the text is
        parsed again only when there are problems.
        """
        self.text = text
        self.data = data if data is not None else parse_yaml(text, self.file)
        self._dumped: str | None = None
        try:
            self.result = api.check_source(PostSource(self.file, self.data, text, self.path),
                                           self.options)
        except (KeyError, IndexError, TypeError) as exc:
            if stale:
                self._load(text)  # the loader looked up the position of a node edited in memory
                return
            self.result = _internal_error(self.file, exc)
        except Exception as exc:  # a checker bug must not take the technologist's work with it
            self.result = _internal_error(self.file, exc)
        if self.result.problems and stale:
            self._load(text)
            return
        self.model = self._model()

    def _model(self) -> api.Post:
        """What the editor shows: the checked post's model (its bases merged in), or what
        can be read of a document with problems."""
        if self.result.post is not None:
            return self.result.post.source.model
        try:
            return api.post_model(self.data, self.file)
        except Exception:  # a builder bug must not take the technologist's work with it
            return api.Post(self.file)

    def set_options(self, values: dict[str, Any]) -> None:
        """Post the preview with these option values from now on (checked as posting
        checks them: a wrong one is a problem of the post)."""
        self.options = dict(values)
        self._load(self.text, self.data)

    @property
    def post(self) -> api.CompiledPost | None:
        """The compiled post, or None while the document has problems."""
        return self.result.post

    @property
    def problems(self) -> list[api.PostProblem]:
        """Every problem of the post, each with the YAML path of its node."""
        return self.result.problems

    @property
    def unsaved_edits(self) -> int | None:
        """How many undo steps away from the saved text the document is (an undo after
        saving is one too); None when the saved state is no longer in the history."""
        if not self.dirty:
            return 0
        if self.saved_depth is None:
            return None
        return abs(len(self.undo_stack) - self.saved_depth) or None

    @property
    def dirty(self) -> bool:
        """The text differs from what is on disk."""
        return self.text != self.saved_text

    def problems_under(self, path: Path_) -> list[api.PostProblem]:
        """Problems about ``path`` or anything inside it."""
        return [p for p in self.problems if p.path[:len(path)] == path]

    def get(self, path: Path_, default: Any = None) -> Any:
        """The node at ``path``, or ``default`` when the post has none there."""
        node: Any = self.data
        for part in path:
            try:
                node = node[part]
            except (KeyError, IndexError, TypeError):
                return default
        return node

    # --- editing -------------------------------------------------------------------------

    def edit(self, label: str, change: Callable[[CommentedMap], Any]) -> bool:
        """Apply ``change`` to the document as one undoable step; False if nothing changed."""
        if self._dumped is None:
            self._dumped = dump(self.data)
        before = self._dumped
        try:
            change(self.data)
            after = dump(self.data)
        except Exception:
            self._load(self.text)  # never keep a half-applied change
            raise
        if after == before:
            return False
        text = merge_edit(self.text, before, after)
        if self.saved_depth is not None and len(self.undo_stack) < self.saved_depth:
            self.saved_depth = None  # the saved state was undone and is now overwritten
        self.undo_stack.append(Snapshot(label, self.text))
        self.redo_stack.clear()
        edited = self.data
        self._load(text, edited, stale=True)
        if self.data is edited:
            self._dumped = after
        return True

    def undo(self) -> str | None:
        """Step back; the label of the undone edit, or None when there is nothing to undo."""
        if not self.undo_stack:
            return None
        snapshot = self.undo_stack.pop()
        self.redo_stack.append(Snapshot(snapshot.label, self.text))
        self._load(snapshot.text)
        return snapshot.label

    def redo(self) -> str | None:
        """Step forward again; the label of the redone edit, or None."""
        if not self.redo_stack:
            return None
        snapshot = self.redo_stack.pop()
        self.undo_stack.append(Snapshot(snapshot.label, self.text))
        self._load(snapshot.text)
        return snapshot.label

    def save(self) -> None:
        """Write the text atomically (temporary file + rename)."""
        api.write_atomic(self.path, self.text)
        self.saved_text = self.text
        self.saved_depth = len(self.undo_stack)


def _internal_error(file: str, exc: Exception) -> api.CheckResult:
    """A crash of the checker, shown as a problem of the post (saving then asks first)."""
    message = f"internal error while checking the post ({type(exc).__name__}: {exc})"
    return api.CheckResult(None, [api.PostProblem((), message, api.Location(file))])
