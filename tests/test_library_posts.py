"""The library posts (machines/fanuc.yaml, grbl.yaml, hmcnc.yaml): what each writes and refuses.

Their corpus snapshots are locked and verified in tests/test_snapshots.py; here
the Fanuc-family output is read by LinuxCNC's own interpreter (``rs274``) and
compared with the CL point by point, and the rules each post's header promises
are checked on small programs.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from ruamel.yaml import YAML

from postdsl import api
from tests.conftest import ROOT, THESIS_TIME
from tests.test_rs274_oracle import check_program, needs_rs274


def corpus_of(machine: str) -> list[str]:
    corpus = YAML(typ="safe").load((ROOT / "corpus.yaml").read_text(encoding="utf-8"))
    return list(corpus[machine])


def post(machine: str, cl: Path | str) -> list[str]:
    return [line.text for line in api.post_commands(
        api.load_post(machine), api.read_cl(ROOT / cl), now=THESIS_TIME)]


# --- fanuc.yaml -------------------------------------------------------------------------------

def _posts(machine: str, program: str) -> bool:
    try:
        post(machine, program)
    except api.CLError:
        return False
    return True


@needs_rs274
@pytest.mark.parametrize("program", corpus_of("fanuc"))
def test_every_fanuc_program_moves_to_the_cl_points_in_rs274(program: str,
                                                             tmp_path: Path) -> None:
    """rs274 reads each program the generic Fanuc post writes and moves where the CL says."""
    if not _posts("fanuc", program):
        pytest.skip("the post refuses this program (its snapshot locks the refusal)")
    moves, holes = check_program(str(ROOT / program), tmp_path, api.load_post("fanuc"),
                                 drill_per_rev=False)
    assert moves + holes > 0
