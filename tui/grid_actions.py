"""The grid's edits: items and blocks added, deleted, moved, copied; block conditions.

They are actions of the main screen (a mixin of :class:`~tui.main_screen.MainScreen`,
kept apart so each module stays readable): the screen owns the grid's cursor and
the document, and the keys act on that cursor from any pane.  Every key that
cannot act says why.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from textual.reactive import reactive

from postdsl import api
from tui import edits
from tui.block_editor import BlockEditor
from tui.command_table import ITEM_COLUMN, CommandTable
from tui.item_editor import ItemContext, ItemEditor
from tui.model import (
    BlockView,
    ItemSpec,
    TableRef,
    numbered_by_default,
    redirect_of,
    table_node,
    title_of,
)
from tui.preview_pane import SampleTable

if TYPE_CHECKING:
    from postdsl import api
    from tui.document import PostDocument
    from tui.screen_host import ScreenHost as _Host
else:
    # at run time the mixin adds its methods only: MainScreen brings the Screen
    _Host = object


class GridActions(_Host):
    """The main screen's actions on the grid's cursor."""

    # the main screen's state these actions read and change
    doc: PostDocument
    current: TableRef
    block: reactive[int]
    column: reactive[int]
    copied: tuple[str, Any] | None
    preview: api.PreviewResult | None
    overrides: dict[str, dict[str, Any]]

    def _table_ready(self) -> bool:
        """The current table has blocks of its own to edit; says why not otherwise."""
        node = table_node(self.doc.model, self.current)
        redirect = redirect_of(self.doc.model, self.current)
        if node is None:
            self.notify(f"{self.current.title} has no table: press t to add one",
                        severity="warning")
            return False
        if redirect:
            self.notify(f"{self.current.title} is written with {title_of(redirect)}'s table",
                        severity="warning")
            return False
        if isinstance(node, api.Command) and node.expand:
            self.notify(f"{self.current.title} is expanded into moves", severity="warning")
            return False
        return True

    def _structure_row(self, block: BlockView, what: str) -> bool:
        """Says why a key cannot act on a row that inserts a structure."""
        if block.use is None:
            return False
        self.notify(f"block {block.index + 1} inserts the structure '{block.use}': {what} in "
                    f"the structure itself (enter opens it)", severity="warning")
        return True

    def action_edit(self) -> None:
        focused = self.focused
        if isinstance(focused, SampleTable):
            self.action_edit_sample()
            return
        redirect = redirect_of(self.doc.model, self.current)
        if redirect:
            self.select_table(TableRef("command", redirect), focus=True)
            return
        if not self._table_ready():
            return
        block = self.current_block()
        if block is None:
            self.action_add_block()
            return
        if block.use is not None:
            self.select_table(TableRef("structure", block.use), focus=True)
            return
        if self.column < ITEM_COLUMN:
            self.action_edit_block()
            return
        index = self.current_item()
        if index is None:
            self.action_add_item(at_end=True)
            return
        self._open_item_editor(block, index, ItemSpec.of(block.items[index]), new=False)

    def _item_context(self, block: BlockView, index: int, new: bool) -> ItemContext:
        path = self.current.blocks_path + (block.index, "items", index)
        problems: dict[str, str] = {}
        if not new:
            for problem in self.doc.problems_under(path):
                key = str(problem.path[len(path)]) if len(problem.path) > len(path) else "value"
                problems.setdefault(key, problem.message)
        samples: dict[str, Any] = dict(self.preview.values) if self.preview else {}
        samples.update(self.overrides.get(self.current.name, {}))
        verb = "New item" if new else f"Item {index + 1}"
        return ItemContext(f"{verb} of block {block.index + 1} — {self.current.title}",
                           self.doc.model, samples, self._extra_names(), problems, new,
                           command=self.current.name if self.current.kind == "command" else "")

    def _extra_names(self) -> list[str]:
        node = table_node(self.doc.model, self.current)
        if isinstance(node, api.CustomCycle):
            return list(node.parameters or {})
        return []

    # --- where an edit is written: the post itself, or an override of its base ---------

    def _block_place(self, data: Any, index: int) -> tuple[tuple[Any, ...], Any]:
        """(container, key) of block ``index`` of the current table in the document, for
        the block and item edits; a block of the base post (extends:) is first written as
        an override of this post, so the edit changes only this file."""
        path = self.current.blocks_path + (index,)
        file, where = self.doc.model.origin_of(path)
        if file is None:
            return where[:-1], where[-1]
        view = self.blocks()[index]
        props = {"if": view.condition or None,
                 "number": view.numbered if view.explicit_number else None,
                 "renumber": view.renumber or None, "for_each": view.for_each or None,
                 "only_with_values": view.only_with_values or None}
        block = edits.new_block([ItemSpec.of(item) for item in view.items],
                                {k: v for k, v in props.items() if v is not None})
        return edits.override_block(data, path, block)

    def _set_block_props(self, data: Any, index: int, props: dict[str, Any]) -> None:
        """Set block properties; of a block of the base post, each property becomes an
        override of just that property (its items stay the base's)."""
        path = self.current.blocks_path + (index,)
        file, where = self.doc.model.origin_of(path)
        if file is None:
            edits.set_block_props(data, where[:-1], where[-1], props)
            return
        view = self.blocks()[index]
        now = {"if": view.condition or None,
               "number": view.numbered if view.explicit_number else None,
               "renumber": view.renumber or None, "for_each": view.for_each or None,
               "only_with_values": view.only_with_values or None}
        for key, value in props.items():
            if value != now.get(key):
                edits.override_field(data, path + (key,), value)

    def _set_item(self, data: Any, block: int, index: int, spec: ItemSpec) -> None:
        """Change one item; an item of the base post becomes an override of just that item."""
        path = self.current.blocks_path + (block, "items", index)
        file, where = self.doc.model.origin_of(path)
        if file is not None:
            edits.override_item(data, path, spec)
        elif where[-2:-1] != ("items",):  # an item override of this post: replace it
            edits.set_value(data, where, edits.item_node(spec, self.doc.get(where)))
        else:
            edits.set_item(data, *self._block_place(data, block), index, spec)

    def _table_inherited(self, what: str) -> bool:
        """Says why a table of the base post cannot gain, lose or reorder blocks here."""
        if not self.doc.model.inherited(self.current.path):
            return False
        self.notify(f"{self.current.title} comes from the base post: its cells and blocks can "
                    f"be edited (saved as overrides), but to {what} give this post its own "
                    f"table", severity="warning")
        return True

    def _open_item_editor(self, block: BlockView, index: int, spec: ItemSpec,
                          new: bool) -> None:
        def done(result: ItemSpec | str | None) -> None:
            if result is None:
                return
            if result == "delete":
                self.change("delete item", lambda data: edits.delete_item(
                    data, *self._block_place(data, block.index), index))
            elif isinstance(result, ItemSpec) and new:
                self.set_reactive(type(self).column, ITEM_COLUMN + index)
                self.change("add item", lambda data: edits.insert_item(
                    data, *self._block_place(data, block.index), index, result))
            elif isinstance(result, ItemSpec):
                self.change("edit item", lambda data: self._set_item(
                    data, block.index, index, result))

        self.app.push_screen(ItemEditor(spec, self._item_context(block, index, new)), done)

    def action_add_item(self, at_end: bool = False) -> None:
        if not self._table_ready():
            return
        block = self.current_block()
        if block is None:
            self.notify("add a block first (b)", severity="warning")
            return
        if self._structure_row(block, "add items"):
            return
        item = self.current_item()
        index = len(block.items) if at_end or (item is None and self.column >= ITEM_COLUMN) \
            else 0 if item is None else item + 1
        self._open_item_editor(block, index, ItemSpec(), new=True)

    def action_delete_item(self) -> None:
        if not self._table_ready():
            return
        block = self.current_block()
        if block is not None and self._structure_row(block, "delete items"):
            return
        index = self.current_item()
        if index is None:
            self.notify("no item under the cursor: move onto an item to delete it "
                        "(X deletes the block)", severity="warning")
            return
        self.change("delete item", lambda data: edits.delete_item(
            data, *self._block_place(data, self.block), index))

    def action_move_item(self, offset: int) -> None:
        index = self.current_item()
        block = self.current_block()
        if index is None or block is None:
            self.notify("no item under the cursor to move", severity="warning")
            return
        if not 0 <= index + offset < len(block.items):
            self.notify(f"item {index + 1} is already the {'first' if offset < 0 else 'last'}"
                        f" of the block", severity="warning")
            return
        self.set_reactive(type(self).column, self.column + offset)
        self.change("move item", lambda data: edits.move_item(
            data, *self._block_place(data, self.block), index, offset))

    def action_add_block(self) -> None:
        if not self._table_ready() or self._table_inherited("add blocks"):
            return
        index = self.block + 1 if self.blocks() else 0
        self.set_reactive(type(self).column, ITEM_COLUMN)
        self.set_reactive(type(self).block, index)
        self.change("add block", lambda data: edits.insert_block(
            data, self.current.blocks_path, index, edits.new_block()))

    def action_delete_block(self) -> None:
        if not self._table_ready() or self._table_inherited("delete blocks"):
            return
        if self.current_block() is None:
            self.notify("the table has no blocks to delete", severity="warning")
            return
        number = self.block + 1
        if self.change("delete block", lambda data: edits.delete_block(
                data, self.current.blocks_path, self.block)):
            self.notify(f"deleted block {number} (ctrl+z: undo)")

    def action_move_block(self, offset: int) -> None:
        if self._table_inherited("move blocks"):
            return
        if self.current_block() is None:
            self.notify("no block under the cursor to move", severity="warning")
            return
        if not 0 <= self.block + offset < len(self.blocks()):
            self.notify(f"block {self.block + 1} is already the "
                        f"{'first' if offset < 0 else 'last'}", severity="warning")
            return
        moved = self.block
        self.set_reactive(type(self).block, moved + offset)
        self.change("move block", lambda data: edits.move_block(
            data, self.current.blocks_path, moved, offset))

    def _numbered_by_default(self) -> bool:
        return numbered_by_default(self.doc.model)

    def _block_to_edit(self, what: str) -> BlockView | None:
        """The block under the cursor when it can be edited; says why not otherwise."""
        if not self._table_ready():
            return None
        block = self.current_block()
        if block is None:
            self.notify("the table has no blocks: press b to add one", severity="warning")
            return None
        if self._structure_row(block, what):
            return None
        return block

    def action_toggle_numbering(self) -> None:
        block = self._block_to_edit("number its blocks")
        if block is None:
            return
        self.change("block numbering", lambda data: self._set_block_props(
            data, block.index, {"number": not block.numbered}))

    def action_edit_block(self) -> None:
        block = self._block_to_edit("give its blocks conditions")
        if block is None:
            return
        problems = [p.message for p in self.doc.problems
                    if p.path == self.current.blocks_path + (block.index, "if")]

        def done(props: dict[str, Any] | None) -> None:
            if props is not None:
                self.change("edit block", lambda data: self._set_block_props(
                    data, block.index, props))

        self.app.push_screen(BlockEditor(f"Block {block.index + 1} — {self.current.title}",
                                         block, self.doc.model, self._numbered_by_default(),
                                         self._extra_names(),
                                         problems[0] if problems else None), done)

    def action_copy(self) -> None:
        block = self.current_block()
        if block is None:
            self.notify("nothing to copy: the table has no blocks", severity="warning")
            return
        index = self.current_item()
        if index is not None:
            self.copied = ("item", ItemSpec.of(block.items[index]).as_mapping())
            self.notify(f"copied item {index + 1} of block {self.block + 1}")
        else:
            node = self.doc.get(self.doc.model.origin_of(
                self.current.blocks_path + (self.block,))[1])
            if self.doc.model.inherited(self.current.blocks_path + (self.block,)):
                node = edits.new_block([ItemSpec.of(item) for item in block.items])
            self.copied = ("block", edits.plain(node))
            self.notify(f"copied block {self.block + 1}")

    def action_paste(self) -> None:
        if self.copied is None:
            self.notify("nothing copied yet (c copies)", severity="warning")
            return
        if not self._table_ready():
            return
        kind, value = self.copied
        if kind == "block" and self._table_inherited("paste blocks"):
            return
        if kind == "block":
            index = self.block + 1 if self.blocks() else 0
            self.set_reactive(type(self).block, index)
            self.change("paste block", lambda data: edits.insert_block(
                data, self.current.blocks_path, index, edits.rebuild(value)))
            return
        block = self.current_block()
        if block is None or block.use is not None:
            self.notify("paste an item into a block with items", severity="warning")
            return
        item = self.current_item()
        index = len(block.items) if item is None else item + 1
        spec = ItemSpec.of(value)
        self.set_reactive(type(self).column, ITEM_COLUMN + index)
        self.change("paste item", lambda data: edits.insert_item(
            data, *self._block_place(data, self.block), index, spec))

    def action_add_table(self) -> None:
        ref = self.current
        if ref.kind != "command":
            self.notify(f"{ref.title} is a {ref.kind}: only a CL command can be given a table",
                        severity="warning")
            return
        if table_node(self.doc.model, ref) is not None:
            self.notify(f"{ref.title} already has a table", severity="warning")
            return

        if self.change(f"add table {ref.name}",
                       lambda data: edits.add_table(data, ("commands", ref.name))):
            self.query_one(CommandTable).focus()
