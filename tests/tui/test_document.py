"""The editor's document model: minimal-diff saving, edits in place, undo/redo, problems."""

from __future__ import annotations

import difflib
from pathlib import Path

import pytest

from postdsl import api
from postdsl.lang.loader import PostSource, parse_yaml
from tui import edits
from tui.document import PostDocument, dump
from tui.merge import merge_edit
from tui.model import ItemSpec, TableRef, compiled_blocks, item_cell, names_read

BREAK_CHIP = ("commands", "break_chip", "blocks")


def changed_lines(before: str, after: str) -> list[str]:
    return [line for line in difflib.unified_diff(before.splitlines(), after.splitlines(),
                                                  lineterm="", n=0)
            if line[:1] in "+-" and not line.startswith(("---", "+++"))]


# --- merge ------------------------------------------------------------------------------------


def test_merge_keeps_the_original_spelling_where_the_edit_did_not_reach() -> None:
    original = "a: [x, {p: 1}]   # one\nb:   'two'\nc: 3\n"
    before = "a: [x, p: 1]   # one\nb: 'two'\nc: 3\n"  # how an emitter may respell it
    after = "a: [x, p: 1]   # one\nb: 'two'\nc: 4\n"
    assert merge_edit(original, before, after) == "a: [x, {p: 1}]   # one\nb:   'two'\nc: 4\n"


def test_merge_takes_the_emitters_spelling_inside_the_edit() -> None:
    original = "a: [x, {p: 1}]\nc: 3\n"
    before = "a: [x, p: 1]\nc: 3\n"
    after = "a: [y, p: 1]\nc: 3\n"
    assert merge_edit(original, before, after) == after


def test_merge_keeps_lines_the_emitter_dropped_and_crlf() -> None:
    original = "a: 1\r\n\r\n\r\nb: 2\r\n"
    before = "a: 1\n\nb: 2\n"
    after = "a: 1\n\nb: 5\n"
    assert merge_edit(original, before, after) == "a: 1\r\n\r\n\r\nb: 5\r\n"


def test_merge_of_an_insertion_next_to_a_respelled_region() -> None:
    original = "a: [x, {p: 1}]\nc: 3\n"
    before = "a: [x, p: 1]\nc: 3\n"
    after = "a: [x, p: 1]\nb: 2\nc: 3\n"
    assert merge_edit(original, before, after) == "a: [x, {p: 1}]\nb: 2\nc: 3\n"


# --- the document -------------------------------------------------------------------------------


def test_untouched_post_dumps_byte_identical(vmc500: Path) -> None:
    doc = PostDocument(vmc500)
    assert dump(doc.data) == vmc500.read_text(encoding="utf-8")
    assert doc.post is not None and doc.problems == []


def test_edit_changes_only_the_edited_value(vmc500: Path) -> None:
    doc = PostDocument(vmc500)
    original = doc.text
    assert doc.edit("x", lambda data: edits.set_item(
        data, BREAK_CHIP, 2, 6, ItemSpec("text", " J1")))
    assert changed_lines(original, doc.text) == ['-          - " J11"', '+          - " J1"']
    assert doc.dirty
    assert not doc.edit("same", lambda data: edits.set_item(
        data, BREAK_CHIP, 2, 6, ItemSpec("text", " J1")))  # no change, no history
    assert len(doc.undo_stack) == 1


def test_item_mapping_edits_keep_key_order_and_quotes(vmc500: Path) -> None:
    doc = PostDocument(vmc500)
    original = doc.text
    spec = ItemSpec.of(doc.get(BREAK_CHIP + (2, "items", 1)))
    assert spec == ItemSpec("param", "x", prefix=" X", format="coord")
    spec.condition = "x > 0"
    spec.mode = "changed"
    doc.edit("x", lambda data: edits.set_item(data, BREAK_CHIP, 2, 1, spec))
    assert changed_lines(original, doc.text) == [
        '-          - {param: x, prefix: " X", format: coord}',
        '+          - {param: x, prefix: " X", format: coord, mode: changed, if: "x > 0"}']


def test_delete_and_move_keep_comment_lines(vmc500: Path) -> None:
    doc = PostDocument(vmc500)
    spindle = ("commands", "spindle_on", "blocks")
    comment = "# coolant goes out with the spindle"
    doc.edit("move", lambda data: edits.move_item(data, spindle, 0, 3, -1))
    assert comment in doc.text
    doc.undo()
    doc.edit("delete", lambda data: edits.delete_item(data, spindle, 0, 2))
    assert comment in doc.text
    assert "{param: spindle_speed" not in doc.text


def test_new_block_and_its_problems(vmc500: Path) -> None:
    doc = PostDocument(vmc500)
    block = edits.new_block([ItemSpec("param", "dwel", prefix=" F", format="cycle")],
                            {"if": "dwell >"})
    doc.edit("add", lambda data: edits.insert_block(data, BREAK_CHIP, 3, block))
    assert '- if: "dwell >"' in doc.text
    assert "items: [{param: dwel, prefix: \" F\", format: cycle}]" in doc.text
    assert doc.post is None
    paths = {p.path: p.message for p in doc.problems}
    assert set(paths) == {BREAK_CHIP + (3, "if"), BREAK_CHIP + (3, "items", 0, "param")}
    assert "did you mean 'dwell'" in paths[BREAK_CHIP + (3, "items", 0, "param")]
    for problem in doc.problems:  # fresh positions: they point into the new text
        line = doc.text.splitlines()[problem.location.line - 1]
        assert "dwel" in line


def test_undo_redo_and_save(vmc500: Path) -> None:
    doc = PostDocument(vmc500)
    original = doc.text
    doc.edit("a", lambda data: edits.set_block_props(data, BREAK_CHIP, 2, {"number": False}))
    first = doc.text
    doc.edit("b", lambda data: edits.move_block(data, BREAK_CHIP, 2, -1))
    second = doc.text
    assert doc.undo() == "b" and doc.text == first
    assert doc.undo() == "a" and doc.text == original and not doc.dirty
    assert doc.undo() is None
    assert doc.redo() == "a" and doc.redo() == "b" and doc.text == second
    assert doc.redo() is None
    doc.save()
    assert vmc500.read_text(encoding="utf-8") == second and not doc.dirty
    assert [p.name for p in vmc500.parent.iterdir()] == ["vmc500.yaml"]  # no temp file left


def test_failed_edit_leaves_the_document_as_it_was(vmc500: Path) -> None:
    doc = PostDocument(vmc500)
    original = doc.text

    def broken(data: object) -> None:
        edits.set_block_props(data, BREAK_CHIP, 2, {"number": False})
        raise RuntimeError("boom")

    with pytest.raises(RuntimeError):
        doc.edit("broken", broken)
    assert doc.text == original and dump(doc.data) == original and not doc.undo_stack


# --- what the table shows ------------------------------------------------------------------------


CYCLE_POST = """\
postdsl: 1
machine: {name: Test}
formats:
  coord: {decimals: 3}
structures:
  head:
    - items: ["; start"]
    - items: ["; ", {param: tool_number, format: coord}]
commands:
  break_chip:
    preview: {x: 1, dwell: 0.5}
    blocks:
      - use: head
      - if: "peck > 0"
        items:
          - "G83"
          - {param: x, prefix: " X", format: coord}
          - {text: " M8", if: "coolant != 'off'", modal: coolant, mode: changed}
          - {expr: "top - depth", prefix: " Z", format: coord}
"""


def test_cells_names_and_compiled_blocks(tmp_path: Path) -> None:
    post = tmp_path / "test.yaml"
    post.write_text(CYCLE_POST, encoding="utf-8")
    doc = PostDocument(post)
    assert doc.problems == []
    ref = TableRef("command", "break_chip")
    items = doc.get(BREAK_CHIP + (1, "items"))
    assert [item_cell(i) for i in items] == ["G83", "␣X{x:coord}", "␣M8?~",
                                             "␣Z{=top - depth:coord}"]
    assert names_read(doc.model, ref) == ["x", "dwell", "tool_number", "peck", "coolant",
                                         "depth", "top"]
    assert compiled_blocks(doc.model, ref) == [range(0, 2), range(2, 3)]


# --- the API the editor added ---------------------------------------------------------------------


def test_check_source_maps_problems_to_paths() -> None:
    text = (Path(__file__).parents[2] / "machines" / "vmc500.yaml").read_text(encoding="utf-8")
    text = text.replace('{param: peck, prefix: " K", format: cycle}',
                        '{param: peck, prefix: " K", format: cycel, if: "peck >> 1"}', 1)
    result = api.check_source(PostSource("post.yaml", parse_yaml(text, "post.yaml"), text))
    assert result.post is None
    found = {p.path: p.message for p in result.problems}
    deep = ("commands", "deep_drill", "blocks", 2, "items", 7)
    assert set(found) == {deep + ("format",), deep + ("if",)}
    assert "did you mean 'cycle'" in found[deep + ("format",)]


def test_check_expression() -> None:
    data = {"variables": {"g83_relief": 1.0}}
    assert api.check_expression("dwell > 0 and g83_relief", data).names == \
        {"dwell", "g83_relief"}
    bad = api.check_expression("dwel > 0", data)
    assert bad.error is not None and "dwell" in bad.error and bad.column == 0
    assert api.check_expression("x >", data).column == 3
    assert api.check_expression("  ", data).error
    assert api.check_expression("depth > p", data, ["p"]).error is None
