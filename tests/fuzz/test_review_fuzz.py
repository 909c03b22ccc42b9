"""`postdsl review` on hostile corpora and names: nothing read outside, nothing leaked.

corpus.yaml comes with a pull request, and the Markdown goes back into it as a
comment.  Generated corpora (any keys, any paths: absolute, ``..``, links out of the
repository, control characters, NUL) are either read as programs inside the repository
or refused with a ReviewError located in corpus.yaml.  Generated results (any machine
and program names, error messages holding secrets) render to Markdown that keeps its
table shape, quotes no error message, and has no live link, mention or HTML.
"""

from __future__ import annotations

import json
import re
import tempfile
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from postdsl import review
from postdsl.review import ProgramDiff, ReviewError, ReviewResult

pytestmark = pytest.mark.fuzz

PATHS = st.one_of(
    st.sampled_from(["cl/a.jsonl", "cl/../cl/a.jsonl", "../outside.jsonl", "/etc/hostname",
                     "out/secret.jsonl", "cl/out.jsonl", "cl", ".", "", " ", "cl/a\x00.jsonl",
                     "cl\\..\\..\\x", "~/x", "cl/./a.jsonl", "C:/x", "cl/a.jsonl\n"]),
    st.text(max_size=30),
)
KEYS = st.one_of(st.sampled_from(["vmc500", "../x", "a/b", "", "vm\x00c", "-", "é", "x" * 300]),
                 st.text(max_size=20))
CORPORA = st.one_of(
    st.dictionaries(KEYS, st.one_of(st.lists(PATHS, max_size=4), PATHS, st.integers(),
                                    st.none()), max_size=4).map(json.dumps),
    st.text(max_size=200),
)


def _repository(folder: Path) -> Path:
    """A repository folder with one program, and links leading out of it."""
    root = folder / "repo"
    (root / "cl").mkdir(parents=True)
    (root / "cl" / "a.jsonl").write_text('{"cmd": "program_start"}\n', encoding="utf-8")
    (folder / "outside.jsonl").write_text("PASSWORD/hunter2\n", encoding="utf-8")
    (root / "cl" / "out.jsonl").symlink_to(folder / "outside.jsonl")
    (root / "out").symlink_to(folder)
    return root


@given(text=CORPORA)
def test_hostile_corpora_stay_inside_the_repository(text: str) -> None:
    with tempfile.TemporaryDirectory() as temporary:
        root = _repository(Path(temporary))
        corpus_file = root / "corpus.yaml"
        corpus_file.write_text(text, encoding="utf-8")
        try:
            corpus = review.load_corpus_file(corpus_file, root)
        except ReviewError as exc:
            assert exc.location is not None and exc.location.file == str(corpus_file)
            return
        for machine, programs in corpus.items():
            assert re.fullmatch(r"[A-Za-z0-9_][A-Za-z0-9_.-]*", machine)
            for program in programs:
                program.path.resolve().relative_to(root.resolve())  # inside, or ValueError


SECRET = "SECRET-7f3a"
NAMES = st.one_of(
    st.sampled_from(["@team", "[x](http://evil)", "<img src=x onerror=alert(1)>", "`", "``",
                     "| x |", "a\nb", "#12", "www.evil.example", "http://evil", "**bold**",
                     "<!--", "&lt;", "\\|", "x\r\n| y | z |", "<details>", "]]>"]),
    st.text(max_size=30),
)
STATUSES = st.sampled_from([review.CHANGED, review.RENUMBERED, review.ADDED, review.REMOVED,
                            review.NOW_FAILS, review.NOW_POSTS, review.UNPOSTABLE,
                            review.ERROR])
ERRORS = st.one_of(
    st.none(),
    st.tuples(NAMES, st.integers(0, 99), NAMES).map(
        lambda t: f"{t[0]}:{t[1]}: record {SECRET} {t[2]}"),
    NAMES.map(lambda name: f"{name}: {SECRET}"),
)


@st.composite
def results(draw: st.DrawFn) -> ReviewResult:
    programs = []
    for _ in range(draw(st.integers(1, 4))):
        status = draw(STATUSES)
        programs.append(ProgramDiff(
            draw(NAMES), draw(NAMES), status, added=draw(st.integers(0, 9)),
            removed=draw(st.integers(0, 9)), renumbered=draw(st.integers(0, 9)),
            old_error=draw(ERRORS), new_error=draw(ERRORS),
            renumber_example=draw(st.none() | st.tuples(NAMES, NAMES))))
    return ReviewResult(draw(NAMES), "0123456789abcdef", programs=programs,
                        errors=draw(st.lists(ERRORS.filter(bool), max_size=3)),
                        warnings=draw(st.lists(NAMES, max_size=2)))


OUR_TAGS = re.compile(r"</?details>|</?summary>")
CODE_SPAN = re.compile(r"(?<!\\)(`+)(?!`)(.+?)(?<!`)\1(?!`)")


@given(result=results())
def test_review_markdown_quotes_no_message_and_links_nothing(result: ReviewResult) -> None:
    markdown = review.render_markdown(result)
    assert SECRET not in markdown
    outside_fences = []
    fence: str | None = None
    for line in markdown.splitlines():
        if fence is None and line.startswith("```"):
            fence = line[:len(line) - len(line.lstrip("`"))]
        elif fence is not None and line == fence:
            fence = None
        elif fence is None:
            outside_fences.append(line)
    for line in outside_fences:
        # code spans show their text literally: nothing in them links or renders
        bare = CODE_SPAN.sub("code", OUR_TAGS.sub("", line.removeprefix("> ")))
        assert "<" not in bare and ">" not in bare.replace("&gt;", ""), line
        assert not re.search(r"@\w", bare), line          # no mention
        assert not re.search(r"(?<!\\)\]\(", bare), line  # no link
        assert "://" not in bare and not re.search(r"www\.", bare, re.I), line
        assert not re.search(r"#\d", bare), line
        if line.startswith("| ") and not line.startswith("| verdict |"):
            # a table row keeps its five cell borders, whatever the names hold
            assert len(re.findall(r"(?<!\\)\|", re.sub(r"\\\\", "", line))) == 5, line
