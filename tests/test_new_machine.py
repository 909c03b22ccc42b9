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


@pytest.mark.slow  # runs the snapshot suite in a subprocess
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
    edited = post.replace('" G40 G49 G80 G90 G94"]', '" G40 G49 G80 G90 G94 G54"]')
    assert edited != post
    (root / "machines" / "mill2.yaml").write_text(edited, encoding="utf-8")
    after = subprocess.run(suite, cwd=root, capture_output=True, text=True, check=False)
    assert after.returncode == 1
    assert "- N10 G0 G17 G21 G40 G49 G80 G90 G94" in after.stdout
    assert "+ N10 G0 G17 G21 G40 G49 G80 G90 G94 G54" in after.stdout


@pytest.mark.slow  # runs the snapshot suite in a subprocess
def test_new_extends_writes_a_small_file_that_posts_what_its_base_posts(
        tmp_path: Path) -> None:
    """new --extends -> the base's snapshots byte for byte -> an override shows as its line."""
    root = project(tmp_path, CORPUS)
    result = CliRunner().invoke(main, ["new", "mill3", "--from", "fanuc", "--extends",
                                       "--root", str(root)])
    assert result.exit_code == 0, result.output
    path = root / "machines" / "mill3.yaml"
    post = path.read_text(encoding="utf-8")
    assert post.startswith("# mill3: built on the library post fanuc "
                           "(postdsl new mill3 --from fanuc --extends).\n")
    assert "#      override:\n" in post and "prestage_next_tool" in post
    assert post.endswith("postdsl: 1\nextends: fanuc.yaml\n\nmachine:\n  name: mill3\n")
    assert len(post.splitlines()) < 30   # the base's tables stay in the base
    loaded = api.load_post(path)
    assert loaded.machine.name == "mill3"
    assert loaded.machine.controller == api.load_post("fanuc").machine.controller
    corpus = (root / "corpus.yaml").read_text(encoding="utf-8")
    assert corpus == CORPUS + ("mill3:                                # extends fanuc\n"
                               "  - examples/feeler_milling.apt\n"
                               "  - examples/vmc500_cycles.jsonl\n")
    for program in ("feeler_milling", "vmc500_cycles"):   # a program and a refusal
        written = root / SNAPSHOTS / f"test_nc_output[mill3-{program}].nc"
        base = root / SNAPSHOTS / f"test_nc_output[fanuc-{program}].nc"
        assert written.read_bytes() == base.read_bytes()

    # edit: one item overridden -> the suite shows that NC line and no other
    edited = post + ("override:\n  commands/program_start/blocks/3/items/3: "
                     "\" G40 G49 G80 G90 G94 G54\"\n")
    path.write_text(edited, encoding="utf-8")
    lines = [line.text for line in api.post_commands(
        api.load_post(path), api.read_cl(root / "examples/feeler_milling.apt"))]
    base_lines = (root / SNAPSHOTS / "test_nc_output[fanuc-feeler_milling].nc").read_text(
        encoding="utf-8").splitlines()
    changed = [(a, b) for a, b in zip(base_lines, lines, strict=True) if a != b]
    assert changed == [("N10 G0 G17 G21 G40 G49 G80 G90 G94",
                        "N10 G0 G17 G21 G40 G49 G80 G90 G94 G54")]
    suite = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
             "tests/test_snapshots.py::test_nc_output"]
    after = subprocess.run(suite, cwd=root, capture_output=True, text=True, check=False)
    assert after.returncode == 1
    assert "+ N10 G0 G17 G21 G40 G49 G80 G90 G94 G54" in after.stdout
    assert "1 failed" in after.stdout


def test_new_extends_names_a_post_outside_machines_by_its_relative_path(
        tmp_path: Path) -> None:
    root = project(tmp_path, CORPUS)
    (root / "family").mkdir()
    shutil.move(root / "machines" / "fanuc.yaml", root / "family" / "fanuc.yaml")
    corpus = CORPUS.replace("fanuc:", "fanuc:  # now in family/")
    (root / "corpus.yaml").write_text(corpus, encoding="utf-8")
    made = new_machine("mill4", str(root / "family" / "fanuc.yaml"), root, extends=True)
    assert made.extends and "\nextends: ../family/fanuc.yaml\n" in made.path.read_text(
        encoding="utf-8")
    assert api.load_post(made.path).machine.name == "mill4"


@pytest.mark.parametrize(("name", "source", "message"), [
    ("Mill 2", "fanuc", "cannot name a machine"),
    ("fanuc", "fanuc", "exists already"),
    ("mill2", "haas", "no post 'haas'"),
    ("mill2", "grbl", "lists no CL program for 'grbl'"),
])
@pytest.mark.parametrize("extends", [False, True])
def test_new_refuses_what_it_cannot_make_and_changes_nothing(
        tmp_path: Path, name: str, source: str, message: str, extends: bool) -> None:
    root = project(tmp_path, CORPUS)
    before = sorted(p.name for p in (root / "machines").iterdir())
    with pytest.raises(NewMachineError, match=message):
        new_machine(name, source, root, extends=extends)
    assert sorted(p.name for p in (root / "machines").iterdir()) == before
    assert (root / "corpus.yaml").read_text(encoding="utf-8") == CORPUS


def test_new_outside_a_project_says_where_to_run_it(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, ["new", "mill2", "--from", "fanuc", "--root",
                                       str(tmp_path)])
    assert result.exit_code == 2
    assert "is not a postdsl project" in result.output
