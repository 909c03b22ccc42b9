"""Edits of the round-trip post document, made in place so untouched nodes keep their style.

Each function changes one thing and keeps what the file already says about
spelling: a string replaced keeps its quote style, a mapping keeps its key
order (new keys go where posts usually write them), new item mappings are
written in flow style (``{param: x, prefix: " X"}``) like the rest of a post.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from ruamel.yaml.comments import CommentedMap, CommentedSeq
from ruamel.yaml.scalarstring import DoubleQuotedScalarString, ScalarString

from tui.model import BLOCK_KEYS, ITEM_KEYS, ItemSpec, key_order

Path_ = tuple[Any, ...]


def styled(value: Any, like: Any = None) -> Any:
    """``value`` spelled like ``like`` (same quotes); new text with edge spaces double-quoted."""
    if not isinstance(value, str):
        return value
    if isinstance(like, ScalarString):
        return type(like)(value)
    if value != value.strip() or value == "" or any(c in value for c in "\"'#:{}[],&*!|>%@`"):
        return DoubleQuotedScalarString(value)
    return value


def node_at(data: Any, path: Path_) -> Any:
    """The node at ``path`` (KeyError/IndexError when it is not there)."""
    node = data
    for part in path:
        node = node[part]
    return node


def insert_key(mapping: CommentedMap, key: str, value: Any, order: Sequence[str]) -> None:
    """Set ``key``; a new key goes after the keys that usually come before it, a key
    ``order`` does not know after every other (where a reader looks for the newest)."""
    if key in mapping:
        old = mapping[key]
        if not (old == value and isinstance(old, bool) == isinstance(value, bool)):
            mapping[key] = styled(value, old)
        return
    if key not in order:  # a key of no known place (an override, a variable): last
        mapping.insert(len(mapping), key, styled(value))
        return
    rank = order.index(key)
    position = 0
    for index, existing in enumerate(mapping):
        if (order.index(existing) if existing in order else len(order)) < rank:
            position = index + 1
    mapping.insert(position, key, styled(value))


def update_mapping(mapping: CommentedMap, wanted: Mapping[str, Any],
                   order: Sequence[str]) -> None:
    """Make ``mapping`` say ``wanted``; of the keys in ``order`` (the ones the editor
    manages) those not wanted are removed, other keys are left alone."""
    for key in [k for k in mapping if k not in wanted and k in order]:
        del mapping[key]
    for key, value in wanted.items():
        insert_key(mapping, key, value, order)


def flow_map(values: Mapping[str, Any]) -> CommentedMap:
    """A new mapping written on one line, as items are (``{param: x}``)."""
    mapping = CommentedMap()
    for key, value in values.items():
        mapping[key] = styled(value)
    mapping.fa.set_flow_style()
    return mapping


def item_node(spec: ItemSpec, old: Any = None) -> Any:
    """The YAML node for an item; updates ``old`` in place when it is a mapping."""
    if spec.plain:
        return styled(spec.value, old if isinstance(old, str) else None)
    wanted = spec.as_mapping()
    if isinstance(old, CommentedMap):
        update_mapping(old, wanted, ITEM_KEYS)
        return old
    return flow_map(wanted)


# --- items ----------------------------------------------------------------------------------


def items_of(data: Any, blocks_path: Path_, block: int) -> CommentedSeq:
    """The items of a block, created (flow style) when the block has none."""
    node = node_at(data, blocks_path)[block]
    items: CommentedSeq | None = node.get("items")
    if items is None:
        items = CommentedSeq()
        items.fa.set_flow_style()
        insert_key(node, "items", items, BLOCK_KEYS)
        items = node["items"]
    return items


def set_item(data: Any, blocks_path: Path_, block: int, index: int, spec: ItemSpec) -> None:
    """Replace an item, updating a mapping in place so its layout stays."""
    items = items_of(data, blocks_path, block)
    new = item_node(spec, items[index])
    if new is not items[index]:
        items[index] = new


def insert_item(data: Any, blocks_path: Path_, block: int, index: int, spec: ItemSpec) -> None:
    """Insert a new item at ``index`` of a block."""
    items = items_of(data, blocks_path, block)
    items.insert(min(index, len(items)), item_node(spec))


def delete_item(data: Any, blocks_path: Path_, block: int, index: int) -> None:
    """Delete an item; comment lines around it stay."""
    delete_entry(items_of(data, blocks_path, block), index)


def move_item(data: Any, blocks_path: Path_, block: int, index: int, offset: int) -> None:
    """Swap an item with its neighbour ``offset`` (-1 or 1) away."""
    swap(items_of(data, blocks_path, block), index, index + offset)


def swap(seq: list[Any], index: int, other: int) -> None:
    """Exchange two entries; comment lines stay where they are in the file."""
    if 0 <= index < len(seq) and 0 <= other < len(seq):
        first, second = seq[index], seq[other]
        list.__setitem__(seq, index, second)
        list.__setitem__(seq, other, first)


def delete_entry(seq: list[Any], index: int) -> None:
    """Delete an entry; comment lines that followed it stay (with the entry before it)."""
    comments = getattr(seq, "ca", None)
    kept = comments.items.get(index) if comments is not None else None
    del seq[index]
    if kept is not None and comments is not None and index > 0 \
            and index - 1 not in comments.items:
        comments.items[index - 1] = kept


# --- blocks ---------------------------------------------------------------------------------


def new_block(items: Sequence[ItemSpec] = (), props: Mapping[str, Any] | None = None
              ) -> CommentedMap:
    """A new block: optional properties, then its items."""
    block = CommentedMap()
    for key, value in (props or {}).items():
        block[key] = styled(value)
    seq = CommentedSeq([item_node(spec) for spec in items])
    seq.fa.set_flow_style()
    block["items"] = seq
    return block


def insert_block(data: Any, blocks_path: Path_, index: int, block: CommentedMap) -> None:
    """Insert a block at ``index`` (creating the table's block list if needed)."""
    try:
        blocks = node_at(data, blocks_path)
    except (KeyError, TypeError):
        blocks = None
    if blocks is None:  # a table without blocks yet
        set_value(data, blocks_path, CommentedSeq())
        blocks = node_at(data, blocks_path)
    blocks.insert(min(index, len(blocks)), block)


def delete_block(data: Any, blocks_path: Path_, index: int) -> None:
    """Delete a block; comment lines around it stay."""
    delete_entry(node_at(data, blocks_path), index)


def move_block(data: Any, blocks_path: Path_, index: int, offset: int) -> None:
    """Swap a block with its neighbour ``offset`` (-1 or 1) away."""
    swap(node_at(data, blocks_path), index, index + offset)


def set_block_props(data: Any, blocks_path: Path_, index: int,
                    props: Mapping[str, Any]) -> None:
    """Set or (value None) remove a block's ``if``, ``number``, ``renumber``, ``for_each``."""
    block = node_at(data, blocks_path)[index]
    for key, value in props.items():
        if value is None:
            if key in block:
                del block[key]
        else:
            insert_key(block, key, value, BLOCK_KEYS)


# --- any value --------------------------------------------------------------------------------


# --- overrides of a base post (extends:) ---------------------------------------------------


def override_key(path: Path_) -> str:
    """A post path as an ``override:`` key: ``commands/drill/blocks/2/items/0``."""
    return "/".join(str(part) for part in path)


def override_block(data: Any, path: Path_, block: CommentedMap) -> tuple[Path_, str]:
    """Write ``block`` as the override of the base's block at ``path``; it replaces the
    overrides of that block's items (the block holds them now).  Returns where the block
    now lives, as (container, key) for the block edits above."""
    key = override_key(path)
    overrides = data.get("override")
    if isinstance(overrides, CommentedMap):
        for old in [k for k in overrides if str(k).startswith(key + "/items/")]:
            del overrides[old]
    set_value(data, ("override", key), block)
    return ("override",), key


def override_item(data: Any, path: Path_, spec: ItemSpec) -> None:
    """Write ``spec`` as the override of the base's item at ``path``."""
    set_value(data, ("override", override_key(path)), item_node(spec))


def override_field(data: Any, path: Path_, value: Any) -> None:
    """Write ``value`` as the override of the base's field at ``path`` (one key of a
    format, a ``set:`` entry…): exactly that field, so the child keeps everything else
    the base gives.  ``None`` is written as ``null``: the base's key is removed."""
    key = override_key(path)
    overrides = data.get("override")
    if isinstance(overrides, CommentedMap) and key in overrides:
        if value is None:
            overrides[key] = None
        else:
            overrides[key] = styled(value, overrides[key])
        return
    set_value(data, ("override", key), value if value is not None else "")
    if value is None:
        data["override"][key] = None


def add_table(data: Any, path: Path_) -> None:
    """An empty table of blocks at ``path`` (a command or a custom cycle)."""
    table = CommentedMap()
    table["blocks"] = CommentedSeq()
    set_value(data, path, table)


def set_value(data: Any, path: Path_, value: Any) -> None:
    """Set the value at ``path`` (creating mappings on the way); ``None`` removes the key.

    New keys go where posts usually write them (see :func:`tui.model.key_order`).
    """
    node = data
    for depth, part in enumerate(path[:-1]):
        if part not in node or node[part] is None:
            if value is None:
                return
            insert_key(node, part, CommentedMap(), key_order(path[:depth]))
        node = node[part]
    key = path[-1]
    if value is None:
        if key in node:
            del node[key]
        return
    if isinstance(node, list):
        if isinstance(key, int) and key < len(node):
            node[key] = styled(value, node[key])
        return
    insert_key(node, key, value, key_order(path[:-1]))


def plain(node: Any) -> Any:
    """A round-trip node as plain Python data (copying it without comments or positions)."""
    if isinstance(node, Mapping):
        return {str(k): plain(v) for k, v in node.items()}
    if isinstance(node, list):
        return [plain(v) for v in node]
    if isinstance(node, str):
        return str(node)
    if isinstance(node, bool) or node is None:
        return node
    if isinstance(node, int):
        return int(node)
    if isinstance(node, float):
        return float(node)
    return node


def rebuild(value: Any, flow: bool = False) -> Any:
    """Plain data -> round-trip nodes in the editor's style (items in flow style)."""
    if isinstance(value, Mapping):
        mapping = CommentedMap()
        for key, item in value.items():
            if key == "items":
                seq = CommentedSeq([rebuild(v, flow=True) for v in item])
                seq.fa.set_flow_style()
                mapping[key] = seq
            else:
                mapping[key] = rebuild(item, flow)
        if flow:
            mapping.fa.set_flow_style()
        return mapping
    if isinstance(value, list):
        return CommentedSeq([rebuild(v, flow) for v in value])
    return styled(value)


def flow_seq(values: Sequence[Any]) -> CommentedSeq:
    """A short list written on one line (``[-10, 510]``)."""
    seq = CommentedSeq([styled(v) for v in values])
    seq.fa.set_flow_style()
    return seq
