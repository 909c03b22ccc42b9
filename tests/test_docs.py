"""The documentation cannot go stale: the site's navigation, its links, its posts and its
commands are checked against the project as it is.

- every page in ``mkdocs.yml``'s nav exists, and every page under ``docs/`` is in it;
- every relative link of the pages and of the README resolves to a file of the project;
- every ```yaml block that is a whole post (a ``postdsl:`` or ``extends:`` key) loads with
  ``postdsl.api.load_post_text`` (one that ``extends:`` a file, with ``api.load_post`` as
  a file in a copy of ``machines/``, so ``extends: fanuc.yaml`` finds the library post),
  unless the line before its fence is ``<!-- fragment -->`` or
  ``<!-- fragment: why -->`` (a post shown in part, with ``...`` for what is left out);
- every ``postdsl …`` command of a ```sh block parses with the CLI's click parser: the
  command exists, every option is one it has, no argument is missing or left over;
- ``mkdocs build --strict`` passes (when mkdocs and the Material theme are installed).
"""

from __future__ import annotations

import importlib.util
import re
import shlex
import shutil
import subprocess
import sys
import textwrap
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import click
import pytest
import yaml

from postdsl import api
from postdsl.cli import main
from tests.conftest import ROOT

DOCS = ROOT / "docs"
#: the marker, on the line before a ```yaml fence, of a post shown in part:
#: ``<!-- fragment -->`` or ``<!-- fragment: why -->``
FRAGMENT = re.compile(r"<!-- fragment(:[^>]*)? -->")
#: a fenced block, also indented in a list item: its language and its text
FENCE = re.compile(r"^([ \t]*)```(\w*)[^\n]*\n(.*?)^[ \t]*```", re.S | re.M)
#: [text](target) and ![alt](target); a target has no spaces
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def nav_pages(nav: Any) -> Iterator[str]:
    """The page files of a mkdocs nav, in order."""
    if isinstance(nav, str):
        yield nav
    elif isinstance(nav, list):
        for entry in nav:
            yield from nav_pages(entry)
    elif isinstance(nav, dict):
        for value in nav.values():
            yield from nav_pages(value)


def config() -> dict[str, Any]:
    with open(ROOT / "mkdocs.yml", encoding="utf-8") as file:
        loaded: dict[str, Any] = yaml.safe_load(file)
    return loaded


def pages() -> list[Path]:
    return sorted(DOCS.rglob("*.md"))


def documents() -> list[Path]:
    return [ROOT / "README.md", *pages()]


def blocks(path: Path, language: str) -> Iterator[tuple[int, str, bool]]:
    """(line, text, marked as a fragment) of each fenced block in ``language``."""
    text = path.read_text(encoding="utf-8")
    for found in FENCE.finditer(text):
        if found.group(2) != language:
            continue
        before = text[:found.start()].rstrip("\n").rsplit("\n", 1)[-1].strip()
        yield (text.count("\n", 0, found.start()) + 1, textwrap.dedent(found.group(3)),
               FRAGMENT.fullmatch(before) is not None)


def without_code(text: str) -> str:
    """The text with fenced blocks and inline code blanked: links in code are examples."""
    text = FENCE.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    return re.sub(r"`[^`\n]*`", "``", text)


def test_every_nav_page_exists_and_every_page_is_in_the_nav() -> None:
    listed = list(nav_pages(config()["nav"]))
    assert listed, "mkdocs.yml has no nav"
    missing = [page for page in listed if not (DOCS / page).is_file()]
    assert not missing, f"in mkdocs.yml's nav, no such page under docs/: {missing}"
    assert len(set(listed)) == len(listed), "a page is twice in the nav"
    unlisted = [str(p.relative_to(DOCS)) for p in pages()
                if str(p.relative_to(DOCS)) not in listed]
    assert not unlisted, f"pages no one can reach from the nav: {unlisted}"


def test_the_generated_cl_reference_is_linked_and_current() -> None:
    """docs/cl-format.md stays ``python -m postdsl.cl.schema``'s output, and is in the nav."""
    from postdsl.cl.schema import render_reference

    assert "cl-format.md" in list(nav_pages(config()["nav"]))
    assert (DOCS / "cl-format.md").read_text(encoding="utf-8") == render_reference()


def broken_links(path: Path) -> list[str]:
    broken = []
    for target in LINK.findall(without_code(path.read_text(encoding="utf-8"))):
        if re.match(r"[a-z]+:", target) or target.startswith("#"):
            continue  # another site (checked by no test: no network), or this page
        file = target.split("#", 1)[0]
        if not (path.parent / file).exists():
            broken.append(target)
    return broken


@pytest.mark.parametrize("path", documents(), ids=lambda p: str(p.relative_to(ROOT)))
def test_every_internal_link_resolves(path: Path) -> None:
    assert not broken_links(path), f"{path.relative_to(ROOT)}: links to nothing"


def test_a_broken_link_is_found(tmp_path: Path) -> None:
    page = tmp_path / "page.md"
    page.write_text("[there](there.md) [here](#top) [out](https://example.org) `[x](y.md)`\n",
                    encoding="utf-8")
    assert broken_links(page) == ["there.md"]
    (tmp_path / "there.md").write_text("# There\n", encoding="utf-8")
    assert broken_links(page) == []


def whole_posts() -> list[tuple[str, str]]:
    found = []
    for path in documents():
        for line, text, fragment in blocks(path, "yaml"):
            if not fragment and re.search(r"^(postdsl|extends):", text, re.M):
                found.append((f"{path.relative_to(ROOT)}:{line}", text))
    return found


def test_there_are_whole_posts_to_check() -> None:
    assert len(whole_posts()) >= 2


@pytest.mark.parametrize(("where", "text"), whole_posts(), ids=[w for w, _ in whole_posts()])
def test_every_whole_post_loads(where: str, text: str, tmp_path: Path) -> None:
    if re.search(r"^extends:", text, re.M):
        # extends: a path relative to the post's file (fanuc.yaml): a post from text has
        # no file, so the example is written into a copy of the project's machines/
        shutil.copytree(ROOT / "machines", tmp_path / "machines")
        file = tmp_path / "machines" / "docs-example.yaml"
        file.write_text(text, encoding="utf-8")
        post = api.load_post(file)
    else:
        post = api.load_post_text(text, where)
    assert post.commands, f"{where}: a post with no tables"


def postdsl_commands() -> list[tuple[str, list[str]]]:
    """Each ``postdsl …`` command of a sh block (also after ``&&`` or ``|``), its words."""
    found = []
    for path in documents():
        for line, text, _ in blocks(path, "sh"):
            for offset, command in enumerate(text.splitlines()):
                for part in re.split(r"&&|\|\||\|", command):
                    words = shlex.split(part, comments=True)
                    if words and Path(words[0]).name == "postdsl":
                        found.append((f"{path.relative_to(ROOT)}:{line + 1 + offset}",
                                      words[1:]))
    return found


def parse_error(args: list[str]) -> str | None:
    """Why the CLI would refuse these words as a command line, or None."""
    ctx = main.make_context("postdsl", list(args), resilient_parsing=True)
    command: click.Command | None = main
    while isinstance(command, click.Group):
        if not args:
            return "no command"
        name, args = args[0], args[1:]
        command = command.get_command(ctx, name)
        if command is None:
            return f"no command {name!r}"
        ctx = command.make_context(name, list(args), parent=ctx, resilient_parsing=True)
    # resilient parsing stops at an unknown option and leaves the rest unparsed
    if ctx.args:
        return f"unknown option or extra argument: {ctx.args}"
    missing = [p.name for p in command.params
               if p.required and ctx.params.get(p.name) in (None, ())]
    return f"missing {missing}" if missing else None


def test_there_are_commands_to_check() -> None:
    assert len(postdsl_commands()) >= 25


@pytest.mark.parametrize(("where", "args"), postdsl_commands(),
                         ids=[w for w, _ in postdsl_commands()])
def test_every_command_parses(where: str, args: list[str]) -> None:
    assert parse_error(args) is None, f"{where}: postdsl {shlex.join(args)}: {parse_error(args)}"


@pytest.mark.parametrize("words", [
    "post vmc500 examples/vmc500_cycles.jsonl --no-such-option",
    "post vmc500 examples/vmc500_cycles.jsonl --option",
    "post vmc500",
    "post vmc500 a.jsonl b.jsonl",
    "pots vmc500 a.jsonl",
    "",
])
def test_a_wrong_command_is_found(words: str) -> None:
    assert parse_error(shlex.split(words)) is not None


def test_a_right_command_passes() -> None:
    assert parse_error(shlex.split(
        "post vmc500 examples/vmc500_cycles.jsonl -o x.nc --option a=b --no-verify")) is None


@pytest.mark.skipif(importlib.util.find_spec("mkdocs") is None
                    or importlib.util.find_spec("material") is None,
                    reason="mkdocs and mkdocs-material are not installed (the docs extra)")
def test_the_site_builds_strictly(tmp_path: Path) -> None:
    """No warning at all: a link to no page or anchor, a page left out of the nav."""
    # not --quiet: it hides the warnings from the count --strict fails on (mkdocs 1.6)
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict",
                           "--site-dir", str(tmp_path / "site")],
                          cwd=ROOT, capture_output=True, text=True, timeout=300,
                          env={"NO_MKDOCS_2_WARNING": "1", "PATH": "/usr/bin:/bin"})
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "site" / "tutorial" / "index.html").is_file()


def test_the_readme_is_a_front_page() -> None:
    """At most 150 lines; its first command is the one CI runs (.ci/run), word for word."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(readme.splitlines()) <= 150
    first = next(text for _, text, _ in blocks(ROOT / "README.md", "sh")).strip()
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    assert first in ci, f"the README's first command is not .ci/run's: {first}"
    assert "mkdocs build --strict" in readme
