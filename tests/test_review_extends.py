"""Issue 27: review never hides a change, and reads an ``extends:`` post as ``post`` does.

Each test builds its own git repository as ``postdsl new m --from fanuc --extends``
leaves one (the library post, the child beside it, corpus.yaml), commits it and
reviews from the project root, as the README's CI command does.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from postdsl import review
from postdsl.cli import main
from postdsl.newmachine import new_machine
from tests.conftest import DATA, MACHINES, ROOT
from tests.test_review import _clean_git_env, git  # noqa: F401 (the fixture is used)

CL = DATA / "review"
BIN = Path(sys.executable).parent


@pytest.fixture
def shop(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """fanuc and ``postdsl new m --from fanuc --extends``, committed."""
    root = tmp_path / "shop"
    (root / "machines").mkdir(parents=True)
    shutil.copy(MACHINES / "fanuc.yaml", root / "machines" / "fanuc.yaml")
    shutil.copytree(CL, root / "cl")
    (root / "corpus.yaml").write_text("fanuc:\n  - cl/mill.jsonl\n  - cl/plain.jsonl\n",
                                      encoding="utf-8")
    new_machine("m", "fanuc", root, extends=True)
    git(root, "init", "-q")
    git(root, "config", "user.name", "Test")
    git(root, "config", "user.email", "test@example.invalid")
    git(root, "add", "-A")
    git(root, "commit", "-q", "-m", "fanuc and m")
    monkeypatch.chdir(root)
    return root


def run(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["review", *args])
    if result.exception and not isinstance(result.exception, SystemExit):
        raise result.exception
    return result.exit_code, result.output


def test_review_of_an_extends_post_from_the_project_root(shop: Path) -> None:
    """It was ``extends: no post 'fanuc.yaml'``, exit 2."""
    assert "extends: fanuc.yaml" in (shop / "machines" / "m.yaml").read_text()
    status, output = run("--jobs", "1")
    assert status == 0, output
    assert "4 unchanged" in output
    child = shop / "machines" / "m.yaml"
    child.write_text(child.read_text() + "override:\n  formats/coord/decimals: 4\n")
    status, output = run("--jobs", "1", "--machine", "m", "--format", "json")
    assert status == 4, output  # a fourth decimal the machine does not resolve
    programs = {p["program"]: p for p in json.loads(output)["programs"]}
    assert programs["cl/mill.jsonl"]["status"] == "changed"


def test_a_base_change_is_a_change_of_its_children(shop: Path) -> None:
    """The child's file is the same on both sides, its base is not: not "unchanged"."""
    base = shop / "machines" / "fanuc.yaml"
    old = "    decimals: {option: program_units, mm: 3, inch: 4}\n"  # the coord format's
    assert old in base.read_text()
    base.write_text(base.read_text().replace(old, "    decimals: 4\n", 1))
    status, output = run("--jobs", "1", "--format", "json")
    assert status == 4, output  # format only: the fourth decimal is below the resolution
    statuses = {(p["machine"], p["program"]): p["status"]
                for p in json.loads(output)["programs"]}
    assert statuses[("m", "cl/mill.jsonl")] == "changed"
    assert statuses[("fanuc", "cl/mill.jsonl")] == "changed"


def test_the_readme_ci_command_on_an_extends_repository(shop: Path) -> None:
    git(shop, "branch", "main")
    child = shop / "machines" / "m.yaml"
    child.write_text(child.read_text() + "override:\n  formats/coord/decimals: 4\n")
    done = subprocess.run([str(BIN / "postdsl"), "review", "--against", "main",
                           "--format", "markdown"],
                          cwd=shop, capture_output=True, text=True, check=False)
    assert done.returncode == 4, done.stderr  # 4: text changes only, as the README says
    assert "| m |" in done.stdout or "m " in done.stdout


def test_a_lost_separator_after_the_number_is_a_change_not_renumbering() -> None:
    """The f4 corruption: ``suffix: ""`` gone, every numbered line gains a space
    (``N10  G0``).  Review called it "renumbering only"; it is a change of every line."""
    text = (MACHINES / "emco.yaml").read_text(encoding="utf-8")
    broken = text.replace('    suffix: ""           # every item brings its own leading space\n',
                          "", 1)
    assert broken != text
    diffs = review.review_texts(text, broken, [ROOT / "examples" / "emco_pocket.gcode"],
                                machine="emco")
    (diff,) = diffs
    assert diff.status == review.CHANGED
    assert diff.renumbered == 0 and diff.added == diff.removed > 0
    assert any(line.startswith("+N") and "  " in line[:9] for line in diff.diff)


def test_an_unknown_machine_is_named_not_corpus_yaml(shop: Path) -> None:
    """``review --machine nope`` said corpus.yaml lists no programs for it."""
    result = CliRunner().invoke(main, ["review", "--machine", "nope"])
    assert result.exit_code == 2
    assert "unknown machine 'nope'" in result.output
    assert "corpus.yaml" not in result.output
