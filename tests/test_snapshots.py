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
from tests.conftest import ROOT, THESIS_TIME


class NCSnapshot(SingleFileSnapshotExtension):
    """One readable text file per case, named after the machine and the program."""

    file_extension = "nc"
    _write_mode = WriteMode.TEXT


def corpus_cases() -> list[tuple[str, Path]]:
    corpus = YAML(typ="safe").load((ROOT / "corpus.yaml").read_text(encoding="utf-8"))
    return [(machine, ROOT / path) for machine, paths in corpus.items() for path in paths]


def post_case(machine: str, cl_path: Path) -> str:
    post = api.load_post(machine)
    commands = api.read_cl(cl_path)
    lines = api.post_commands(post, commands, cl_file=cl_path.name, now=THESIS_TIME)
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
