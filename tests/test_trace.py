"""From an NC word to the post cell that wrote it: ``api.trace_line``, ``postdsl explain``,
and the reverse search (``postdsl preview MACHINE G83``)."""

from __future__ import annotations

import pytest

from postdsl import api
from tests.conftest import DATA, EXAMPLES, ROOT, THESIS_TIME
from tests.test_cli import run

THESIS = EXAMPLES / "vmc500_cycles.jsonl"


@pytest.mark.parametrize(("machine", "program"), [
    ("vmc500", EXAMPLES / "vmc500_cycles.jsonl"),
    ("emco", DATA / "emco_thesis.dump.txt"),
    ("feeler", EXAMPLES / "feeler_milling.apt"),
    ("feeler", EXAMPLES / "feeler_probe_x.jsonl"),
])
def test_traced_program_is_the_posted_program_cut_into_words(machine: str, program: object) -> \
        None:
    post = api.load_post(machine)
    commands = list(api.read_cl(program))  # type: ignore[arg-type]
    plain = [line.text for line in api.post_commands(post, commands, now=THESIS_TIME)]
    traced = [api.trace_line(post, commands, number, now=THESIS_TIME)
              for number in range(1, len(plain) + 1)]
    assert [t.line.text for t in traced if t is not None] == plain
    for line in traced:
        assert line is not None
        # every character of the line is owned by exactly one item (or the numbering)
        assert "".join(word.text for word in line.words) == line.line.text
        assert all(w.path is None or w.path[0] in ("commands", "custom_cycles", "structures")
                   for w in line.words)


def test_each_word_of_a_deep_drill_line_names_its_item() -> None:
    post = api.load_post("vmc500")
    commands = list(api.read_cl(THESIS))
    traced = api.trace_line(post, commands, 29, now=THESIS_TIME)
    assert traced is not None
    assert traced.line.text == "N70 G83 X40. Y20. Z53.0043 R70.0 F200.0 J13 K10.0"
    assert traced.record.name == "deep_drill" and traced.line.cl_line == 17
    words = {w.text.strip(): w.path for w in traced.words}
    assert words["N70"] is None
    assert words["G83"] == ("commands", "deep_drill", "blocks", 2, "items", 0)
    assert words["K10.0"] == ("commands", "deep_drill", "blocks", 2, "items", 7)
    assert post.source.data["commands"]["deep_drill"]["blocks"][2]["items"][7]["param"] == "peck"
    # what the control holds after the line
    assert traced.registers["peck"] == "10.0"
    assert traced.registers["depth"] == "53.0043"


def test_a_line_past_the_end_is_none() -> None:
    post = api.load_post("vmc500")
    commands = list(api.read_cl(THESIS))
    assert api.trace_line(post, commands, 62) is None
    assert api.trace_line(post, commands, 0) is None


def test_word_writers_find_fixed_text_and_prefixes_as_whole_words() -> None:
    data = api.load_post("vmc500").source.data
    g83 = api.word_writers(data, "G83")
    assert {(w.name, w.block) for w in g83} >= {("deep_drill", 1), ("deep_drill", 2)}
    assert g83[0].sentence("G83") == "G83 is written by deep_drill, block 2, item 1"
    assert api.word_writers(data, "G8") == []  # G8 is not G83
    x = api.word_writers(data, "X12.5")  # no item writes that text; every X value can
    assert x and all(w.prefix for w in x)
    assert any(w.name == "rapid_move" for w in x)


def test_a_word_the_post_does_not_write_is_found_by_its_meaning() -> None:
    """G83 is deep drilling on ISO controls: Sinumerik writes it as CYCLE83, Heidenhain
    as CYCL DEF 200; a post that writes G83 itself, or a word that means no CL command,
    has no meaning to offer."""
    emco = api.load_post("emco").source.model
    g83 = api.word_meaning(emco, " g83")
    assert g83 is not None
    assert (g83.word, g83.command, g83.table, g83.kind) == ("G83", "deep_drill",
                                                            "deep_drill", "command")
    assert g83.sentence() == ("G83: deep drilling on ISO controls, written here by "
                              "deep_drill as MCALL CYCLE83")
    g73 = api.word_meaning(emco, "G73")  # break_chip redirects to deep_drill
    assert g73 is not None and g73.table == "deep_drill"
    assert g73.sentence().endswith("by break_chip through deep_drill as MCALL CYCLE83")
    heidenhain = api.word_meaning(api.load_post("heidenhain").source.data, "G83")
    assert heidenhain is not None and heidenhain.writes.startswith("CYCL DEF 20")
    assert api.word_meaning(api.load_post("fanuc").source.model, "G83") is None
    assert api.word_meaning(emco, "M99") is None
    assert api.word_meaning(emco, "deep_drill") is None


def test_explain_prints_the_origin_of_each_word() -> None:
    result = run("explain", "vmc500", str(THESIS), "--line", "29")
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0] == "NC line 29: N70 G83 X40. Y20. Z53.0043 R70.0 F200.0 J13 K10.0"
    assert lines[1].startswith(f"CL record  {THESIS}:17: deep_drill x=40 y=20 top=70")
    assert lines[2] == "written by table deep_drill, block 3"
    assert "  G83            item 1: fixed text 'G83'" in lines
    assert "  K10.0          item 8: parameter peck (prefix ' K', format cycle)" in lines
    assert lines[-1].startswith("registers after the line: ")
    assert "peck=10.0" in lines[-1]


def test_explain_a_line_the_program_does_not_have() -> None:
    result = run("explain", "vmc500", str(THESIS), "--line", "500")
    assert result.returncode == 2
    assert result.stderr.strip() == f"{THESIS}: the program has 61 NC lines, no line 500"


def test_explain_names_the_structure_a_line_comes_through() -> None:
    result = run("explain", "vmc500", str(THESIS), "--line", "30")
    assert result.returncode == 0, result.stderr
    assert "written by table deep_drill through structure cycle_separator, block 1" in \
        result.stdout


def test_preview_of_an_nc_word_names_the_tables_that_write_it() -> None:
    result = run("preview", "vmc500", "G83")
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines()[0] == "G83 is written by deep_drill, block 2, item 1"
    assert "no table" not in result.stdout + result.stderr


def test_preview_of_an_unknown_name_lists_the_tables() -> None:
    result = run("preview", "vmc500", "rapid_mov")
    assert result.returncode == 1  # as for any post that lacks a table
    assert "did you mean 'rapid_move'?" in result.stderr
    assert "its tables: arc_move, boring, boring_spindle_stop, break_chip," in result.stderr


def test_swapped_arguments_are_called_swapped() -> None:
    result = run("post", str(THESIS.relative_to(ROOT)), "vmc500")
    assert result.returncode == 2
    assert "the arguments look swapped" in result.stderr
    assert f"postdsl post vmc500 {THESIS.relative_to(ROOT)}" in result.stderr
    assert "YAML" not in result.stderr and "yaml" not in result.stderr


def test_corpus_programs_start_with_the_showcase() -> None:
    names = [p.relative_to(ROOT).as_posix() for p in api.corpus_programs("feeler")]
    assert names[0] == "examples/feeler_probe_x.jsonl"
    assert "examples/feeler_drilling.apt" in names
    assert api.corpus_programs("emco")[0].relative_to(ROOT).as_posix() == \
        "tests/data/emco_thesis.dump.txt"
