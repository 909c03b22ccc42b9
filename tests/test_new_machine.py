"""``postdsl new NAME --from POST``: a new machine is checked from its first commit.

Run in a copy of the project layout (machines/, examples/, tests/data, the snapshot
suite, a corpus of the library posts), as a user with a fresh clone would: new ->
the suite passes with the new machine's snapshots -> an edit to the post shows up as
the NC lines it changes.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from postdsl import api
from postdsl.cli import main
from postdsl.newmachine import NewMachineError, new_machine
from tests.conftest import ROOT

SNAPSHOTS = Path("tests/__snapshots__/test_snapshots")


def project(tmp_path: Path, corpus: str) -> Path:
    copy = tmp_path / "project"
    for name in ("machines", "examples", "tests/data"):
        shutil.copytree(ROOT / name, copy / name)
    for name in ("tests/__init__.py", "tests/conftest.py", "tests/test_snapshots.py"):
        shutil.copy(ROOT / name, copy / name)
    (copy / SNAPSHOTS).mkdir(parents=True)
    for snapshot in ("fanuc-feeler_milling", "fanuc-vmc500_cycles"):
        name = f"test_nc_output[{snapshot}].nc"
        shutil.copy(ROOT / SNAPSHOTS / name, copy / SNAPSHOTS / name)
    (copy / "corpus.yaml").write_text(corpus, encoding="utf-8")
    return copy


CORPUS = ("# the library posts\nfanuc:\n  - examples/feeler_milling.apt\n"
          "  - examples/vmc500_cycles.jsonl   # refused: a peck on a rigid tap\n")


def test_new_copies_the_post_lists_it_and_writes_verified_snapshots(tmp_path: Path) -> None:
    root = project(tmp_path, CORPUS)
    result = CliRunner().invoke(main, ["new", "mill2", "--from", "fanuc", "--root", str(root)])
    assert result.exit_code == 0, result.output
    post = (root / "machines" / "mill2.yaml").read_text(encoding="utf-8")
    assert post.startswith("# mill2: started from the library post fanuc")
    assert "\n  name: mill2\n" in post
    assert api.load_post(root / "machines" / "mill2.yaml").machine.name == "mill2"
    corpus = (root / "corpus.yaml").read_text(encoding="utf-8")
    assert corpus.startswith(CORPUS)   # the other entries and their comments stay
    assert corpus.endswith("mill2:                                # started from fanuc\n"
                           "  - examples/feeler_milling.apt\n"
                           "  - examples/vmc500_cycles.jsonl\n")
    written = sorted(p.name for p in (root / SNAPSHOTS).iterdir() if "mill2" in p.name)
    assert written == ["test_nc_output[mill2-feeler_milling].nc",
                       "test_nc_output[mill2-vmc500_cycles].nc"]
    milling = (root / SNAPSHOTS / written[0]).read_text(encoding="utf-8")
    assert milling == api.post_text(api.load_post("fanuc"), api.post_commands(
        api.load_post("fanuc"), api.read_cl(ROOT / "examples/feeler_milling.apt"),
        cl_file="feeler_milling.apt"))
    assert (root / SNAPSHOTS / written[1]).read_text(encoding="utf-8").startswith("REFUSED")

    # edit -> the suite shows the NC lines the edit changes
    suite = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
             "tests/test_snapshots.py::test_nc_output",
             "tests/test_snapshots.py::test_nc_output_verifies"]
    before = subprocess.run(suite, cwd=root, capture_output=True, text=True, check=False)
    assert before.returncode == 0, before.stdout
    edited = post.replace('items: [" G0 G17 G21 G40 G49 G80 G90 G94"]',
                          'items: [" G0 G17 G21 G40 G49 G80 G90 G94 G54"]')
    assert edited != post
    (root / "machines" / "mill2.yaml").write_text(edited, encoding="utf-8")
    after = subprocess.run(suite, cwd=root, capture_output=True, text=True, check=False)
    assert after.returncode == 1
    assert "- N10 G0 G17 G21 G40 G49 G80 G90 G94" in after.stdout
    assert "+ N10 G0 G17 G21 G40 G49 G80 G90 G94 G54" in after.stdout


@pytest.mark.parametrize(("name", "source", "message"), [
    ("Mill 2", "fanuc", "cannot name a machine"),
    ("fanuc", "fanuc", "exists already"),
    ("mill2", "haas", "no post 'haas'"),
    ("mill2", "grbl", "lists no CL program for 'grbl'"),
])
def test_new_refuses_what_it_cannot_make_and_changes_nothing(
        tmp_path: Path, name: str, source: str, message: str) -> None:
    root = project(tmp_path, CORPUS)
    before = sorted(p.name for p in (root / "machines").iterdir())
    with pytest.raises(NewMachineError, match=message):
        new_machine(name, source, root)
    assert sorted(p.name for p in (root / "machines").iterdir()) == before
    assert (root / "corpus.yaml").read_text(encoding="utf-8") == CORPUS


def test_new_outside_a_project_says_where_to_run_it(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, ["new", "mill2", "--from", "fanuc", "--root",
                                       str(tmp_path)])
    assert result.exit_code == 2
    assert "is not a postdsl project" in result.output
