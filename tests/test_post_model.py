"""The typed post model: the schema and the builder agree key for key, the model
finds every node by its path, and no module but the builder reads a post by key."""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from typing import Any

import pytest

from postdsl import api
from postdsl.lang.formats import NumberFormat
from postdsl.lang.loader import post_schema
from postdsl.lang.post import build_post
from postdsl.lang.post import nodes as n
from postdsl.lang.post.extends import overrides_of
from tests.conftest import MACHINES


class Recording(dict):  # type: ignore[type-arg]
    """A mapping that notes every key the builder asks it for, by the node's kind."""

    def __init__(self, kind: str, value: dict[str, Any], seen: set[tuple[str, str]]) -> None:
        super().__init__(value)
        self.kind, self.seen = kind, seen

    def get(self, key: Any, default: Any = None) -> Any:
        self.seen.add((self.kind, key))
        return super().get(key, default)

    def __getitem__(self, key: Any) -> Any:
        self.seen.add((self.kind, key))
        return super().__getitem__(key)

    def __contains__(self, key: Any) -> bool:
        self.seen.add((self.kind, key))
        return super().__contains__(key)


def recorded_reads() -> set[tuple[str, str]]:
    """Build a document with one node of every kind; the keys the builder read, by kind."""
    seen: set[tuple[str, str]] = set()

    def rec(kind: str, value: dict[str, Any]) -> Recording:
        return Recording(kind, value, seen)

    item_text = rec("item", {"text": " G0"})
    item_param = rec("item", {"param": "x"})
    item_expr = rec("item", {"expr": "x + 1"})
    block = rec("block", {"items": [item_text, item_param, item_expr, " M3"]})
    use = rec("block", {"use": "s"})
    command = rec("command", {"blocks": [block, use],
                              "reject": [rec("reject", {"if": "x > 1", "message": "m"})],
                              "verify": rec("verify", {"motion": "none"})})
    cycle = rec("custom_cycle", {"blocks": [], "parameters": {
        "depth": rec("cycle_parameter", {"default": 1})}})
    document = rec("post", {
        "postdsl": 1,
        "machine": rec("machine", {"name": "M", "tools": rec("tools", {})}),
        "output": rec("output", {"block_numbers": rec("block_numbers", {})}),
        "options": {"o": rec("option", {"type": "bool", "default": True})},
        "structures": {"s": []},
        "commands": {"rapid_move": command},
        "custom_cycles": {"c": cycle},
    })
    build_post(document, "post.yaml")
    overrides_of(document)  # override: is read by the extends resolver
    return seen


def schema_keys() -> dict[str, set[str]]:
    """The properties the schema allows, by the same kinds."""
    schema = post_schema()
    defs = schema["$defs"]
    item = next(b for b in defs["item"]["oneOf"] if b.get("type") == "object")
    block, use = defs["block"]["oneOf"]
    cycle = defs["custom_cycle"]
    return {
        "post": set(schema["properties"]),
        "machine": set(defs["machine"]["properties"]),
        "tools": set(defs["machine"]["properties"]["tools"]["properties"]),
        "output": set(defs["output"]["properties"]),
        "block_numbers": set(defs["output"]["properties"]["block_numbers"]["properties"]),
        "option": set(defs["option"]["properties"]),
        "item": set(item["properties"]),
        "block": set(block["properties"]) | set(use["properties"]),
        "command": set(defs["command"]["properties"]),
        "custom_cycle": set(cycle["properties"]),
        "cycle_parameter": set(cycle["properties"]["parameters"]["additionalProperties"]
                               ["properties"]),
        "reject": set(defs["reject"]["items"]["properties"]),
        "verify": set(defs["verify"]["properties"]),
    }


def test_every_schema_property_is_read_by_the_builder_and_nothing_else() -> None:
    reads: dict[str, set[str]] = {}
    for kind, key in recorded_reads():
        reads.setdefault(kind, set()).add(key)
    assert reads == schema_keys()


def test_every_format_key_of_the_schema_is_an_option_of_number_formats() -> None:
    options = {f.name for f in dataclasses.fields(NumberFormat)}
    assert set(post_schema()["$defs"]["format"]["properties"]) == options


def items_of(post: n.Post, data: Any) -> Iterator[tuple[n.Item, Any]]:
    """Every item of the model with the document node at its path."""
    for _, table in post.tables():
        for block in table.blocks or ():
            if isinstance(block, n.Block):
                for item in block.items:
                    yield item, node_at(data, item.path)


def node_at(data: Any, path: tuple[Any, ...]) -> Any:
    for key in path:
        data = data[key]
    return data


def _document_items(data: Any) -> int:
    """The items the post document itself holds, counted from the YAML (not the model)."""
    tables = [t.get("blocks") or [] for section in ("commands", "custom_cycles")
              for t in (data.get(section) or {}).values()]
    tables += list((data.get("structures") or {}).values())
    return sum(len(block.get("items") or []) for blocks in tables for block in blocks)


#: the bundled posts that are whole documents (a post with ``extends:`` is its base's
#: document with its own entries over it: tests/test_extends.py)
BUNDLED = sorted(p.stem for p in MACHINES.glob("*.yaml")
                 if "\nextends:" not in p.read_text(encoding="utf-8"))


@pytest.mark.parametrize("machine", BUNDLED)
def test_the_model_of_a_bundled_post_is_its_document(machine: str) -> None:
    post = api.load_post(machine)
    model = post.source.model
    count = 0
    # a post built on a library post (extends:) holds only its own part in its document:
    # its model is the merge (tests/test_extends.py); its compiled tables are checked below
    extends = post.source.source.data.get("extends") is not None
    for item, node in [] if extends else items_of(model, post.source.source.data):
        count += 1
        assert model.item_at(item.path) is item
        if isinstance(node, str):
            assert isinstance(item, n.PlainText) and item.text == node
            continue
        kind = {"text": n.TextItem, "param": n.ParamItem, "expr": n.ExprItem}
        [key] = [k for k in kind if k in node]
        assert isinstance(item, kind[key])
        for attr, yaml_key in (("prefix", "prefix"), ("suffix", "suffix"),
                               ("format", "format"), ("mode", "mode"), ("modal", "modal")):
            assert getattr(item, attr) == node.get(yaml_key)
        assert (item.condition.source if item.condition else None) == node.get("if")
        assert item.condition is None or item.condition.compiled is not None
    assert extends or count == _document_items(post.source.source.data) > 0
    # the compiled tables are the model's: every block of every table, use: inlined
    for name, command in post.commands.items():
        table = model.commands[name]
        while table.redirect is not None:
            table = model.commands[table.redirect]
        resolved = model.resolved(table.blocks)
        assert [b.path for b in command.blocks] == [r.block.path for r in resolved]


def test_resolved_blocks_say_which_structures_they_came_through() -> None:
    model = build_post({"postdsl": 1, "machine": {"name": "M"}, "commands": {
        "program_start": {"blocks": [{"use": "a"}, {"items": ["G90"]}]}},
        "structures": {"a": [{"items": ["G17"]}, {"use": "b"}], "b": [{"items": ["G21"]}]}},
        "p.yaml")
    resolved = model.resolved(model.commands["program_start"].blocks)
    assert [(r.block.path, r.via) for r in resolved] == [
        (("structures", "a", 0), ("a",)), (("structures", "b", 0), ("a", "b")),
        (("commands", "program_start", "blocks", 1), ())]


def test_a_document_of_the_wrong_shape_builds_what_it_can_for_the_editor() -> None:
    model = api.post_model({"commands": {"rapid_move": {"blocks": [
        {"items": [" G0", 5, {"param": "x"}]}, "junk", {"use": "s"}]}, "linear_move": 3},
        "structures": [1]})
    blocks = model.commands["rapid_move"].blocks or ()
    assert [type(b).__name__ for b in blocks] == ["Block", "Block", "Use"]
    first = blocks[0]
    assert isinstance(first, n.Block)
    assert [type(i).__name__ for i in first.items] == ["PlainText", "PlainText", "ParamItem"]
    assert model.commands["linear_move"].blocks is None
    assert model.structures == {}
