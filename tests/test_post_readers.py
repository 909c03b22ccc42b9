"""No module but the post model's builder reads a post document by key: the typed model
(postdsl/lang/post/) is the one reader, so a key the language gains reaches every tool."""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path

from tests.conftest import ROOT

# --- the model is the only reader --------------------------------------------------------

#: modules allowed to read a post document by key: the model's package (its builder and
#: the extends resolver) and the editor's writer of edits by path; the loader's schema
#: and size steps read no key by name.  A line that indexes something else by a word
#: of the post language says so with "# not a post".
ALLOWED_FOLDER = "postdsl/lang/post/"
ALLOWED = {"tui/edits.py"}

#: a key of the post language read from a mapping: data["commands"], .get("items") …
POST_KEYS = ("postdsl", "extends", "machine", "output", "formats", "variables", "options",
             "override", "structures", "commands", "custom_cycles", "blocks", "items",
             "use", "param", "expr", "text", "prefix", "suffix", "format", "modal",
             "force_if", "replace", "redirect", "reset", "assume", "reject", "preview",
             "parameters", "block_numbers", "new_cycle_if", "only_with_values", "for_each",
             "renumber", "travel", "tools")
_KEY = "|".join(POST_KEYS)
READ = re.compile(r"""(?:\.get\(\s*|\[\s*)["'](""" + _KEY + r""")["']|["'](""" + _KEY +
                  r""")["']\s+(?:not\s+)?in\s+\w""")


def readers() -> Iterator[tuple[str, int, str]]:
    for folder in ("postdsl", "tui"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            rel = path.relative_to(ROOT).as_posix()
            if rel in ALLOWED or rel.startswith(ALLOWED_FOLDER):
                continue
            for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                if READ.search(line) and "# not a post" not in line:
                    yield rel, number, line.strip()


def test_no_module_but_the_builder_reads_a_post_document_by_key() -> None:
    found = list(readers())
    assert found == [], "\n".join(f"{f}:{n}: {line}" for f, n, line in found)


def test_the_reader_check_sees_a_key_read() -> None:
    assert READ.search('blocks = table.get("blocks") or []')
    assert READ.search("x = data['commands'][name]")
    assert READ.search('if "use" in block:')
    assert not READ.search('values.get("feed")')
    assert not READ.search("post.commands.get(name)")


def test_the_reader_check_covers_the_sources() -> None:
    assert Path(ROOT / "postdsl" / "lang" / "post" / "build.py").is_file()
    assert len(list((ROOT / "tui").glob("*.py"))) > 10
