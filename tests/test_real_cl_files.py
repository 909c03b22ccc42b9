"""Real CL files from CAM systems (tests/data/real, sources in SOURCES.md) through every machine.

Each file must post on a machine, or be refused at its line for a reason a
machinist accepts -- the message is part of the expectation below, so a new
refusal (or a refusal that goes away) fails here.  The motion of every program
that posts is checked against the CL: ``MOTION_CHECKS`` gives every machine
``postdsl verify`` (its control model) and the Feeler LinuxCNC's ``rs274`` too.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from postdsl import api
from tests.conftest import DATA, THESIS_TIME
from tests.test_rs274_oracle import HAVE_RS274, check_program

REAL = DATA / "real"
MACHINES = ("feeler", "vmc500", "emco")

#: the spindle speed each machine refuses, as its message says it
_SPEED = {"vmc500": "is outside the range of VMC 500 (0 to 8000 rpm)",
          "emco": "is outside the range of EMCO Concept Mill 105 (150 to 5000 rpm)",
          "feeler": "is outside the range of Feeler VMP-45A (0 to 10000 rpm)"}
_CUTCOM = "CUTCOM/LEFT: cutter compensation is refused: the CL is the tool centre"
_CSYS = "CSYS is not the identity: the CL has no way to carry a transformation"
_PECKS = ("deep_drill: a first peck of 5 and later pecks of 2, but the post's table "
          "'deep_drill' writes one peck depth (not first_peck)")
_GAGE = ("the Acramatic cycle leaves the tool at R + GAGE_HT_MM (top + clearance): a higher "
         "retract plane cannot be written")

#: file -> machine -> None (posts) or (CL line, the refusal's message, or a part of it)
EXPECTED: dict[str, dict[str, tuple[int, str] | None]] = {
    "creo_bohren_1.ncl": {"feeler": None,
                          "vmc500": (13, f"spindle speed 9000 rpm {_SPEED['vmc500']}"),
                          "emco": (13, f"spindle speed 9000 rpm {_SPEED['emco']}")},
    "creo_profilfraesen_2.ncl": {m: (13, f"spindle speed 15915.5 rpm {_SPEED[m]}")
                                 for m in MACHINES},
    # the first hole of a CYCLE/DEEP2 is the GOTO after it (line 40, 17); the VMC500's
    # cycles cannot return above R + GAGE_HT_MM (RTRCTO 25 is higher), the EMCO has 10 tools
    "swcam_paralelipipedo_furos.apt": {
        "feeler": (40, _PECKS), "vmc500": (18, f"single_peck: {_GAGE}"),
        "emco": (5, "tool 15 does not exist on EMCO Concept Mill 105 (tools 1 to 10)")},
    "swcam_suporte_parede_side_drill.apt": {
        "feeler": (17, _PECKS), "vmc500": (17, f"deep_drill: {_GAGE}"),
        "emco": (5, "tool 20 does not exist on EMCO Concept Mill 105 (tools 1 to 10)")},
    "swcam_lateral_leg_holder.apt": {m: (19, _CUTCOM) for m in MACHINES},
    "swcam_guincho_lbar1.apt": {m: (13, _CSYS) for m in MACHINES},
    "swcam_telemecanique_tilt_support1.apt": {m: (13, _CSYS) for m in MACHINES},
}

#: files read here but not yet posted: FreeCAD's grbl post writes the tool change as a
#: comment ("(M6 T1.0)", grbl has no tool changer), so these programs load no tool; the
#: engine's check of motion without a tool decides them (see the report of issue 10)
READ_ONLY = ("freecad_grbl_helix.nc", "freecad_grbl_drill.nc")

MotionCheck = Callable[[Path, api.CompiledPost, Path], None]


def _rs274(path: Path, post: api.CompiledPost, tmp_path: Path) -> None:
    if not HAVE_RS274:
        pytest.skip("the G-code oracle rs274 is not installed")
    moves, holes = check_program(str(path), tmp_path, post)
    assert moves + holes > 0


def _verify(path: Path, post: api.CompiledPost, tmp_path: Path) -> None:
    """postdsl verify: the NC replayed through the machine's control model, cut by cut."""
    verdict = api.verify_commands(post, api.read_cl(path), cl_file=str(path), now=THESIS_TIME)
    assert verdict.ok, str(verdict.divergence)
    assert verdict.cuts + verdict.holes > 0


def _verify_and_rs274(path: Path, post: api.CompiledPost, tmp_path: Path) -> None:
    _verify(path, post, tmp_path)
    _rs274(path, post, tmp_path)


#: machine -> the independent checks of its NC output's motion against the CL: the
#: control model of ``postdsl verify`` for every machine, and LinuxCNC's rs274 (an
#: interpreter postdsl does not share) for the Feeler's Fanuc G-code
MOTION_CHECKS: dict[str, MotionCheck] = {"feeler": _verify_and_rs274, "vmc500": _verify,
                                         "emco": _verify}


def test_every_real_file_is_listed_and_every_listed_file_exists() -> None:
    files = {p.name for p in REAL.iterdir() if p.suffix != ".md"}
    assert files == set(EXPECTED) | set(READ_ONLY)
    sources = (REAL / "SOURCES.md").read_text(encoding="utf-8")
    assert all(f"`{name}`" in sources for name in files)


@pytest.mark.parametrize(("name", "machine"),
                         [(n, m) for n in EXPECTED for m in MACHINES])
def test_a_real_file_posts_or_is_refused_for_its_reason(name: str, machine: str,
                                                        tmp_path: Path) -> None:
    path = REAL / name
    expected = EXPECTED[name][machine]
    post = api.load_post(machine)
    if expected is None:
        commands = api.read_cl(path)
        api.post_commands(post, commands, cl_file=str(path), now=THESIS_TIME)
        check = MOTION_CHECKS.get(machine)
        if check is not None:
            check(path, post, tmp_path)
        return
    line, message = expected
    with pytest.raises(api.CLError) as caught:
        api.post_commands(post, api.read_cl(path), cl_file=str(path), now=THESIS_TIME)
    assert caught.value.location is not None
    assert (caught.value.location.file, caught.value.location.line) == (str(path), line)
    assert message in caught.value.message


def test_some_real_file_posts_and_every_machine_has_a_motion_check() -> None:
    assert set(MOTION_CHECKS) == set(MACHINES)
    assert any(e is None for machines in EXPECTED.values() for e in machines.values())


def test_freecad_post_output_reads_in_mm_per_minute() -> None:
    """grbl_MIHO_post writes F30.00 for 30 mm/min: read as such, never x60."""
    from postdsl.cl.model import ArcMove, LinearMove

    helix = api.read_cl(REAL / "freecad_grbl_helix.nc")
    feeds = {c.feed for c in helix if isinstance(c, (LinearMove, ArcMove)) and c.feed}
    assert feeds == {30.0, 300.0}
    assert sum(isinstance(c, ArcMove) for c in helix) > 10
    drill = api.read_cl(REAL / "freecad_grbl_drill.nc")
    assert {c.feed for c in drill if isinstance(c, LinearMove) and c.feed} == {30.0}


def test_the_creo_drill_cycle_reads_from_the_hole_top() -> None:
    from postdsl.cl.model import CycleHole, DeepDrill

    commands = api.read_cl(REAL / "creo_bohren_1.ncl")
    [setup] = [c for c in commands if isinstance(c, DeepDrill)]
    assert (setup.x, setup.y, setup.top, setup.depth, setup.peck, setup.clearance,
            setup.feed) == (pytest.approx(-7.2290790757), -23.0, 0.5, 3.5, 1.0, 1.0, 50.0)
    assert [(c.x, c.y) for c in commands if isinstance(c, CycleHole)] == [
        (pytest.approx(-16.780389118), -23.0)]


#: file -> (the refused record, what it is replaced with to read on, then None when the rest
#: of the file reads, or the (line, message) of the next refusal)
_REST: dict[str, tuple[str, str, tuple[int, str] | None]] = {
    "swcam_lateral_leg_holder.apt": ("CUTCOM/LEFT", "CUTCOM/OFF", None),
    "swcam_guincho_lbar1.apt": ("CSYS/-1.,0,0,0,0,-1.,0,0,0,0,1.,0",
                                "CSYS/1.,0,0,0,0,1.,0,0,0,0,1.,0", None),
    # the tilt is in the GOTOs' tool axis too: refused there as well, for the same reason
    "swcam_telemecanique_tilt_support1.apt": (
        "CSYS/0,-0.984808,-0.173648,0,1.,0,0,0,0,-0.173648,.984808,0",
        "CSYS/1.,0,0,0,0,1.,0,0,0,0,1.,0",
        (15, "tool axis (-0.173648, 0, 0.984808) is not +Z")),
}


@pytest.mark.parametrize("name", sorted(_REST))
def test_a_file_refused_by_its_reader_is_refused_at_its_first_such_record_only(
        name: str) -> None:
    """With the refused record read as one that can be honoured, the rest of the file
    reads: the refusal was the file's first problem, not one of many."""
    record, replacement, then = _REST[name]
    text = (REAL / name).read_text(encoding="utf-8")
    assert record in text
    changed = text.replace(record, replacement)
    if then is None:
        assert api.read_cl_text(changed, name, "apt")
        return
    with pytest.raises(api.CLError) as caught:
        api.read_cl_text(changed, name, "apt")
    assert caught.value.location is not None and caught.value.location.line == then[0]
    assert then[1] in caught.value.message
