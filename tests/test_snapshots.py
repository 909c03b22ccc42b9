"""Every bundled machine x every CL program of corpus.yaml, locked as one NC file each.

The snapshot files (``tests/__snapshots__/test_snapshots/*.nc``) are plain NC
programs, so a post change shows up in ``git diff`` as the NC lines it
changes.  After reviewing a change, accept it with ``pytest --snapshot-update``.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from ruamel.yaml import YAML
from syrupy.extensions.single_file import SingleFileSnapshotExtension, WriteMode

from postdsl import api
from postdsl.errors import CLError
from tests.conftest import ROOT, THESIS_TIME, compiled_post


class NCSnapshot(SingleFileSnapshotExtension):
    """One readable text file per case, named after the machine and the program."""

    file_extension = "nc"
    _write_mode = WriteMode.TEXT


def corpus_cases() -> list[tuple[str, Path]]:
    corpus = YAML(typ="safe").load((ROOT / "corpus.yaml").read_text(encoding="utf-8"))
    return [(machine, ROOT / path) for machine, paths in corpus.items() for path in paths]


def post_case(machine: str, cl_path: Path) -> str:
    """The NC program, verified as it is posted, or -- when the machine must refuse the
    program -- the refusal.

    A machine refuses a program it cannot write as the CL means it (a peck its tap
    cycle has no word for, a retract plane its cycles cannot reach): the snapshot then
    locks that refusal and its reason, so a post change that starts writing such a
    program silently wrong shows in the diff like any other changed output.  The
    program is replayed through the machine's control model as it is posted (as
    ``postdsl post`` does): a snapshot is never written of a program that does not do
    what its CL says, unless its case is a known defect (:data:`KNOWN_DEFECTS`).
    """
    post = compiled_post(ROOT / "machines" / f"{machine}.yaml")  # this tree's post
    commands = api.read_cl(cl_path)
    lines: list[api.NCLine] = []
    try:
        if post.machine.control is None or post.machine.resolution is None:
            lines = list(api.post_commands(post, commands, cl_file=cl_path.name,
                                           now=THESIS_TIME))  # no control model to verify
        else:
            verdict = api.verify_commands(post, commands, cl_file=cl_path.name,
                                          now=THESIS_TIME, written=lines)
            known = (machine, cl_path.name.split(".")[0]) in KNOWN_DEFECTS
            assert verdict.ok or known, f"the snapshot does not verify: {verdict.divergence}"
            if not verdict.ok:  # a known defect: verify stopped at it, the snapshot is whole
                lines = list(api.post_commands(post, commands, cl_file=cl_path.name,
                                               now=THESIS_TIME))
    except CLError as exc:
        return f"REFUSED (no NC program is written): {exc}\n"
    return api.post_text(post, lines)


@pytest.fixture
def nc_snapshot(snapshot):
    return snapshot.use_extension(NCSnapshot)


@pytest.mark.parametrize(
    ("machine", "cl_path"),
    [pytest.param(m, p, id=f"{m}-{p.name.split('.')[0]}") for m, p in corpus_cases()],
)
def test_nc_output(machine: str, cl_path: Path, nc_snapshot) -> None:
    assert post_case(machine, cl_path) == nc_snapshot


#: (machine, program) -> why its snapshot does not verify today: defects of issue 9 that are
#: being fixed in the posts and the engine.  strict: the mark fails the suite once the fix
#: lands, so it is removed with the fix.
KNOWN_DEFECTS: dict[tuple[str, str], str] = {
}


def verify_cases() -> list:
    cases = []
    for machine, path in corpus_cases():
        program = path.name.split(".")[0]
        reason = KNOWN_DEFECTS.get((machine, program))
        marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
        cases.append(pytest.param(machine, path, id=f"{machine}-{program}", marks=marks))
    return cases


@pytest.mark.parametrize(("machine", "cl_path"), verify_cases())
def test_nc_output_verifies(machine: str, cl_path: Path) -> None:
    """Every snapshot does what its CL says, replayed through the machine's control model."""
    post = compiled_post(ROOT / "machines" / f"{machine}.yaml")
    try:
        verdict = api.verify_commands(post, api.read_cl(cl_path), cl_file=cl_path.name,
                                      now=THESIS_TIME)
    except CLError as exc:
        # a program the machine refuses has no NC to replay: its snapshot is the refusal
        assert post_case(machine, cl_path) == f"REFUSED (no NC program is written): {exc}\n"
        return
    assert verdict.ok, str(verdict.divergence)


def test_every_known_defect_names_a_corpus_case() -> None:
    """No stale mark: each names a program of its machine (a copy may post fewer machines)."""
    cases = {(m, p.name.split(".")[0]) for m, p in corpus_cases()}
    machines = {machine for machine, _ in cases}
    assert {key for key in KNOWN_DEFECTS if key[0] in machines} <= cases


@pytest.mark.slow  # runs the snapshot suite in a subprocess
def test_a_one_character_format_change_fails_the_suite_with_a_readable_diff(
        tmp_path: Path) -> None:
    """On a copy of the project: coord decimals 3 -> 2 in the VMC500 post."""
    import shutil
    import subprocess
    import sys

    copy = tmp_path / "project"
    for name in ("machines", "examples", "tests/data"):
        shutil.copytree(ROOT / name, copy / name)
    for name in ("tests/__init__.py", "tests/conftest.py", "tests/test_snapshots.py"):
        shutil.copy(ROOT / name, copy / name)
    (copy / "corpus.yaml").write_text("vmc500:\n  - examples/vmc500_cycles.jsonl\n",
                                      encoding="utf-8")
    snapshot = "test_nc_output[vmc500-vmc500_cycles].nc"
    (copy / "tests/__snapshots__/test_snapshots").mkdir(parents=True)
    shutil.copy(ROOT / "tests/__snapshots__/test_snapshots" / snapshot,
                copy / "tests/__snapshots__/test_snapshots" / snapshot)
    post = copy / "machines" / "vmc500.yaml"
    text = post.read_text(encoding="utf-8")
    changed = text.replace("  coord:               # 40. / 16.996 : point always, trailing zeros "
                           "trimmed\n    decimals: 3", "  coord:               # 40. / 16.996 : "
                           "point always, trailing zeros trimmed\n    decimals: 2")
    assert sum(a != b for a, b in zip(text, changed, strict=True)) == 1
    command = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
               "tests/test_snapshots.py::test_nc_output"]
    before = subprocess.run(command, cwd=copy, capture_output=True, text=True, check=False)
    assert before.returncode == 0, before.stdout
    post.write_text(changed, encoding="utf-8")
    after = subprocess.run(command, cwd=copy, capture_output=True, text=True, check=False)
    assert after.returncode == 1
    # the diff shows the NC line as it was and as it is now (16.9957 -> 17. with 2 decimals)
    assert "- ; pohyb nastroje (XxYxZ): (40.;100.) x (20.;20.) x (16.996;150.)" in after.stdout
    assert "+ ; pohyb nastroje (XxYxZ): (40.;100.) x (20.;20.) x (17.;150.)" in after.stdout
