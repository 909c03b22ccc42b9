"""extends: a post on a base, overriding by command, block and item; every message in
the file the node is written in."""

from __future__ import annotations

from pathlib import Path

import pytest

from postdsl import api
from postdsl.cl.model import CLCommand, LinearMove, ProgramEnd, ProgramStart, RapidMove
from postdsl.errors import PostError
from postdsl.lang.post.extends import base_file

BASE = """\
postdsl: 1
formats:
  coord: {decimals: 3}
  feed: {decimals: 0}
output:
  block_numbers: {default: false}
commands:
  program_start:
    blocks:
      - items: ["%"]
      - use: safe
  rapid_move:
    blocks:
      - items:
          - "G0"
          - {param: x, prefix: " X", format: coord}
          - {param: y, prefix: " Y", format: coord}
  linear_move:
    blocks:
      - items:
          - "G1"
          - {param: x, prefix: " X", format: coord}
          - {param: feed, prefix: " F", format: feed}
  program_end:
    blocks:
      - items: ["M30"]
      - items: ["%"]
structures:
  safe:
    - items: ["G17 G21 G90"]
"""

CHILD = """\
postdsl: 1
extends: base.yaml
machine:
  name: Child
  tool_changer: false
formats:
  coord: {decimals: 2}
commands:
  program_end:
    blocks:
      - items: ["M2"]
override:
  commands/linear_move/blocks/0/items/0: "G01"
  structures/safe/0: {items: ["G17 G20 G90"]}
"""


def program() -> list[CLCommand]:
    return [ProgramStart(line=1), RapidMove(line=2, x=1.23456, y=2.0),
            LinearMove(line=3, x=3.0, feed=250.0), ProgramEnd(line=4)]


def write(folder: Path, **files: str) -> Path:
    for name, text in files.items():
        (folder / f"{name}.yaml").write_text(text, encoding="utf-8")
    return folder / f"{next(iter(files))}.yaml"


def posted(path: Path) -> list[str]:
    return [line.text for line in api.post_commands(api.load_post(path), program())]


def test_a_child_inherits_and_overrides_by_name_block_and_item(tmp_path: Path) -> None:
    child = write(tmp_path, child=CHILD, base=BASE)
    assert posted(child) == ["%", "G17 G20 G90", "G0 X1.23 Y2.00", "G01 X3.00 F250", "M2"]


def test_the_model_says_what_is_inherited_and_from_where(tmp_path: Path) -> None:
    child = write(tmp_path, child=CHILD, base=BASE)
    model = api.load_post(child).source.model
    base = str(tmp_path / "base.yaml")
    assert model.inherited(("commands", "rapid_move", "blocks", 0))
    assert model.origin_of(("commands", "rapid_move", "blocks", 0, "items", 1)) == (
        base, ("commands", "rapid_move", "blocks", 0, "items", 1))
    assert not model.inherited(("commands", "program_end"))
    assert model.origin_of(("commands", "linear_move", "blocks", 0, "items", 0)) == (
        None, ("override", "commands/linear_move/blocks/0/items/0"))
    assert model.inherited(("commands", "linear_move", "blocks", 0, "items", 1))
    assert model.inherited(("output", "block_numbers"))
    assert model.commands["rapid_move"].file == base
    assert model.commands["program_end"].file is None


def test_a_chain_of_bases_is_followed(tmp_path: Path) -> None:
    middle = "postdsl: 1\nextends: base.yaml\nformats:\n  feed: {decimals: 1}\n"
    child = write(tmp_path, child=CHILD.replace("base.yaml", "middle.yaml"), middle=middle,
                  base=BASE)
    assert posted(child)[3] == "G01 X3.00 F250.0"


def test_a_problem_in_an_inherited_node_is_located_in_the_base(tmp_path: Path) -> None:
    child = write(tmp_path, child=CHILD, base=BASE.replace("param: y,", "param: yy,"))
    with pytest.raises(PostError) as info:
        api.load_post(child)
    assert str(info.value) == f"{tmp_path / 'base.yaml'}:17:21: unknown parameter 'yy' " \
                              f"(did you mean 'y'?)"


def test_a_problem_in_an_override_is_located_in_the_child(tmp_path: Path) -> None:
    text = CHILD.replace('structures/safe/0: {items: ["G17 G20 G90"]}',
                         'structures/safe/0: {items: [{param: zz}]}')
    child = write(tmp_path, child=text, base=BASE)
    with pytest.raises(PostError) as info:
        api.load_post(child)
    assert str(info.value) == f"{child}:14:39: unknown parameter 'zz' (did you mean 'z'?)"


@pytest.mark.parametrize(("key", "message"), [
    ("commands/linear_move/blocks/3", "override 'commands/linear_move/blocks/3': command "
                                      "'linear_move' has no block 4 (blocks count from 0 in "
                                      "the path)"),
    ("commands/linear_move/blocks/0/items/9", "override 'commands/linear_move/blocks/0/items/9'"
                                              ": block 1 has no item 10"),
    ("commands/arc_move/blocks/0", "override 'commands/arc_move/blocks/0': the post has no "
                                   "command 'arc_move'"),
])
def test_an_override_must_address_a_block_or_item_that_is_there(
        tmp_path: Path, key: str, message: str) -> None:
    text = CHILD.replace("commands/linear_move/blocks/0/items/0: \"G01\"",
                         f"{key}: {{items: [\"G01\"]}}" if "items/" not in key else
                         f"{key}: \"G01\"")
    child = write(tmp_path, child=text, base=BASE)
    with pytest.raises(PostError) as info:
        api.load_post(child)
    assert str(info.value) == f"{child}:13:3: {message}"


def test_an_override_key_must_be_a_block_or_item_path(tmp_path: Path) -> None:
    text = CHILD.replace("commands/linear_move/blocks/0/items/0", "commands/linear_move")
    child = write(tmp_path, child=text, base=BASE)
    with pytest.raises(PostError) as info:
        api.load_post(child)
    assert str(info.value) == f"{child}:13:3: unknown key 'commands/linear_move'"


def test_a_missing_base_is_located_at_extends(tmp_path: Path) -> None:
    child = write(tmp_path, child=CHILD)
    with pytest.raises(PostError) as info:
        api.load_post(child)
    assert str(info.value) == (f"{child}:2:10: extends: no post 'base.yaml' (a path relative "
                               f"to this file, an absolute path, or a bundled post's or base's "
                               f"name)")


def test_an_extends_loop_is_refused(tmp_path: Path) -> None:
    child = write(tmp_path, child=CHILD, base="postdsl: 1\nextends: child.yaml\n")
    with pytest.raises(PostError) as info:
        api.load_post(child)
    assert str(info.value) == f"{tmp_path / 'base.yaml'}:2:10: extends loop: child.yaml -> " \
                              f"base.yaml -> child.yaml"


def test_a_post_with_no_machine_anywhere_is_refused(tmp_path: Path) -> None:
    child = write(tmp_path, child="postdsl: 1\nextends: base.yaml\n", base=BASE)
    with pytest.raises(PostError) as info:
        api.load_post(child)
    assert str(info.value) == f"{child}:1:1: the post has no machine: neither it nor the " \
                              f"posts it extends declare machine: (name, …)"


def test_a_base_may_be_named_absolute_or_bundled(tmp_path: Path) -> None:
    machines = tmp_path / "machines"
    (machines / "bases").mkdir(parents=True)
    (machines / "bases" / "iso-milling.yaml").write_text(BASE, encoding="utf-8")
    (machines / "vmc.yaml").write_text(BASE, encoding="utf-8")
    child = tmp_path / "posts" / "child.yaml"
    child.parent.mkdir()
    assert base_file("iso-milling", child, machines) == machines / "bases" / "iso-milling.yaml"
    assert base_file("vmc", child, machines) == machines / "vmc.yaml"
    assert base_file(str(machines / "vmc.yaml"), child, machines) == machines / "vmc.yaml"
    assert base_file("../machines/vmc.yaml", child, machines) == \
        child.parent / "../machines/vmc.yaml"
    assert base_file("nothing", child, machines) is None


def test_a_bundled_post_can_be_extended(tmp_path: Path) -> None:
    child = tmp_path / "vmc.yaml"
    child.write_text("postdsl: 1\nextends: vmc500\nmachine:\n  name: VMC 500 copy\n",
                     encoding="utf-8")
    own = api.load_post("vmc500")
    copy = api.load_post(child)
    assert copy.machine.name == "VMC 500 copy"
    assert copy.machine.travel == own.machine.travel
    assert set(copy.commands) == set(own.commands)


# --- issue 27: the inheritance is complete ---------------------------------------------------

HEAD = "postdsl: 1\nextends: base.yaml\nmachine: {name: C, tool_changer: false}\n"


def test_a_child_names_a_base_format_in_str(tmp_path: Path) -> None:
    """``str(x, 'coord')`` in a child whose ``coord`` is the base's was "unknown format"."""
    child = write(tmp_path, child=HEAD + "override:\n  commands/program_end/blocks/0/items/0: "
                  "{expr: \"'M30 ; ' + str(1.5, 'coord')\"}\n", base=BASE)
    assert posted(child)[-2] == "M30 ; 1.500"


def test_override_one_key_of_a_format_keeps_the_others(tmp_path: Path) -> None:
    base = BASE.replace("coord: {decimals: 3}", "coord: {decimals: 3, trailing_zeros: false}")
    child = write(tmp_path, child=HEAD + "override:\n  formats/coord/decimals: 1\n", base=base)
    assert posted(child)[2] == "G0 X1.2 Y2"
    model = api.load_post(child).source.model
    assert model.formats["coord"].values == {"decimals": 1, "trailing_zeros": False}
    assert model.origin_of(("formats", "coord", "decimals")) == (
        None, ("override", "formats/coord/decimals"))


TABLES = BASE.replace("flags:", "").replace("structures:\n", """\
flags: {opened: false}
structures:
""").replace("""  program_end:
    blocks:""", """  program_end:
    set: {opened: "false"}
    blocks:""")


def test_override_adds_and_replaces_set_assume_reject_and_conditions(tmp_path: Path) -> None:
    child = write(tmp_path, child="""\
postdsl: 1
extends: base.yaml
machine: {name: C, tool_changer: false}
override:
  commands/rapid_move/set/opened: "true"
  commands/rapid_move/assume: {plane: "'G17'"}
  commands/linear_move/reject/0: {if: "feed > 200", message: too fast}
  commands/program_end/blocks/1/if: "opened"
  commands/program_end/set: {opened: "false"}
""", base=TABLES)
    model = api.load_post(child).source.model
    assert model.commands["rapid_move"].sets["opened"].source == "true"
    assert model.commands["rapid_move"].assume["plane"].source == "'G17'"
    assert [r.message for r in model.commands["linear_move"].reject] == ["too fast"]
    block = model.block_at(("commands", "program_end", "blocks", 1))
    assert block.condition.source == "opened"
    assert model.origin_of(("commands", "rapid_move", "set", "opened")) == (
        None, ("override", "commands/rapid_move/set/opened"))
    with pytest.raises(api.CLError, match="too fast"):
        posted(child)
    slow = [ProgramStart(line=1), RapidMove(line=2, x=1.0, y=2.0),
            LinearMove(line=3, x=3.0, feed=100.0), ProgramEnd(line=4)]
    lines = [line.text for line in api.post_commands(api.load_post(child), slow)]
    assert lines[-2:] == ["M30", "%"]  # opened: set by the rapid move, so the % is written


def test_a_wrong_override_of_a_table_key_is_located(tmp_path: Path) -> None:
    child = write(tmp_path, child=HEAD + "override:\n  commands/nope/set/opened: \"true\"\n"
                  "  formats/nope/decimals: 2\n", base=TABLES)
    with pytest.raises(PostError) as info:
        api.load_post(child)
    text = info.value.report() if hasattr(info.value, "report") else str(info.value)
    assert "override 'commands/nope/set/opened': the post has no command 'nope'" in text
    assert "override 'formats/nope/decimals': the post has no format 'nope'" in text


def test_trim_line_ends_lets_a_child_strip_what_its_base_writes(tmp_path: Path) -> None:
    """LinuxCNC's items end in a space (FreeCAD strips it when writing): a Mach3 post
    extending it could not, short of overriding every item."""
    from tests.conftest import EXAMPLES, THESIS_TIME

    child = write(tmp_path, mach3="postdsl: 1\nextends: linuxcnc\nmachine: {name: Mach3}\n"
                  "output: {trim_line_ends: true}\n")
    cl = api.read_cl(EXAMPLES / "feeler_milling.apt")
    now = THESIS_TIME
    base = [line.text for line in api.post_commands(api.load_post("linuxcnc"), cl, now=now)]
    lines = [line.text for line in api.post_commands(api.load_post(child), cl, now=now)]
    assert any(text.endswith(" ") for text in base)
    assert lines == [text.rstrip(" ") for text in base]
    model = api.load_post(child).source.model
    assert model.output.trim_line_ends is True
