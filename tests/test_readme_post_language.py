"""The post language page's examples of options and extends (docs/reference/post-language.md,
once the README's): work as the page says."""

from __future__ import annotations

import re
from pathlib import Path

from postdsl import api
from postdsl.cl.model import RapidMove
from tests.conftest import EXAMPLES, ROOT, THESIS_TIME


def readme_yaml(after: str) -> str:
    text = (ROOT / "docs" / "reference" / "post-language.md").read_text(encoding="utf-8")
    start = text.index(after)
    return re.search(r"```yaml\n(.*?)```", text[start:], re.S).group(1)  # type: ignore[union-attr]


def test_the_extends_example_changes_only_what_it_overrides(tmp_path: Path) -> None:
    post = tmp_path / "vmc500_m30.yaml"
    post.write_text(readme_yaml("**`extends:`**"), encoding="utf-8")
    cl = EXAMPLES / "vmc500_cycles.jsonl"
    base = [line.text for line in api.post_commands(api.load_post("vmc500"), api.read_cl(cl),
                                                     now=THESIS_TIME)]
    child = [line.text for line in api.post_commands(api.load_post(post), api.read_cl(cl),
                                                      now=THESIS_TIME)]
    assert len(base) == len(child)
    changed = [(a, b) for a, b in zip(base, child, strict=True) if a != b]
    assert changed
    for old, new in changed:
        assert new in (old.replace(" G1", " G01"), old.replace(" G0", " G00"),
                       old.replace(" M2", " M30"), old.replace("VMC 500", "VMC 500 (M30)")), \
            (old, new)
    assert any(" G00" in new for _, new in changed)
    assert child[-1].endswith(" M30")
    # the cycles program has no feed moves: the item override is seen in the table
    moves = api.preview_command(api.load_post(post), "linear_move", {}, now=THESIS_TIME)
    assert moves.lines and moves.lines[0].text.split()[1] == "G01"


def test_the_options_example_loads_and_switches(tmp_path: Path) -> None:
    options = readme_yaml("**Options** make one post")
    text = ("postdsl: 1\nmachine: {name: Family, tool_changer: false}\n" + options +
            "  program_start:\n    blocks: [{items: [\"%\"]}]\n")
    post = api.load_post_text(text, "family.yaml")
    assert [o.name for o in api.post_options(post)] == ["line_numbers", "precision",
                                                        "comments", "modal"]
    assert post.formats["coord"].render(1.5) == "1.500"
    assert not post.numbering.default
    four = api.load_post_text(text, "family.yaml", {"precision": "4", "line_numbers": "yes"})
    assert four.formats["coord"].render(1.5) == "1.5000"
    assert four.numbering.default


def test_the_options_example_makes_words_modal_by_option() -> None:
    options = readme_yaml("**Options** make one post")
    text = ("postdsl: 1\nmachine: {name: Family, tool_changer: false}\n" + options +
            "  program_start:\n    blocks: [{items: [\"%\"]}]\n"
            "  program_end:\n    blocks: [{items: [\"%\"]}]\n")
    moves = [RapidMove(line=1, x=1.0), RapidMove(line=2, x=1.0), RapidMove(line=3, x=2.0)]

    def lines(modal: str) -> list[str]:
        post = api.load_post_text(text, "family.yaml", {"modal": modal})
        # the space a suppressed first word leaves is output.word_separator's business
        return [line.text.strip() for line in api.post_commands(post, moves)][1:-1]

    assert lines("false") == ["G0 X1.000", "G0 X1.000", "G0 X2.000"]
    assert lines("true") == ["G0 X1.000", "X2.000"]  # the repeated move writes nothing
