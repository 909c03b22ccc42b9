"""Inch programs from the mm CL: the Fanuc post with ``--option program_units=inch``
writes G20 and every length and feed in inches; the control model reads the program in
its units, and rs274 moves the inch program as it moves the mm one."""

from __future__ import annotations

from pathlib import Path

import pytest
from syrupy.extensions.single_file import SingleFileSnapshotExtension, WriteMode

from postdsl import api
from postdsl.errors import CLError, PostError
from tests.conftest import EXAMPLES, THESIS_TIME, compiled_post
from tests.test_rs274_oracle import Move, for_rs274, needs_rs274, run_rs274

INCH = {"program_units": "inch"}
#: the corpus programs posted in inches (lines, arcs in three planes, a helix, every
#: drilling cycle, boring, work offsets and stops)
PROGRAMS = ["feeler_milling.apt", "feeler_drilling.apt", "boring.jsonl",
            "boring_spindle_stop.jsonl", "work_offsets.jsonl", "program_stops.jsonl"]


class NCSnapshot(SingleFileSnapshotExtension):
    file_extension = "nc"
    _write_mode = WriteMode.TEXT


def posted(machine: str, example: str, options: dict[str, str] | None = None) -> list[str]:
    post = compiled_post(machine, options)
    path = EXAMPLES / example
    return [line.text for line in api.post_commands(post, api.read_cl(path), cl_file=path.name,
                                                    now=THESIS_TIME)]


@pytest.mark.parametrize("example", PROGRAMS)
def test_the_inch_program_verifies(example: str) -> None:
    """The Fanuc model reads G20: lengths and feeds times 25.4 -- within the inch step
    (0.0001 in = 0.00254 mm, the post's resolution in inches) of the CL."""
    post = compiled_post("fanuc", INCH)
    assert post.machine.units == "inch" and post.machine.resolution == 0.00254
    verdict = api.verify_commands(post, api.read_cl(EXAMPLES / example))
    assert verdict.ok, verdict.divergence


def test_inch_words() -> None:
    lines = posted("fanuc", "feeler_milling.apt", INCH)
    assert any(" G20 " in line for line in lines)
    assert not any("G21" in line for line in lines)
    assert "N110 X1.5748 F19.69" in lines  # X40 mm, F500 mm/min
    mm = posted("fanuc", "feeler_milling.apt")
    assert "N110 X40. F500." in mm and any(" G21 " in line for line in mm)


def test_the_model_reads_the_program_in_its_units() -> None:
    """Read as mm (a post writing inches under G21), the program is 25.4 times too
    small: verify says so at the first move."""
    text = (Path(__file__).parents[1] / "machines" / "fanuc.yaml").read_text(encoding="utf-8")
    old = '{text: " G20", if: "program_units == \'inch\'"}'
    assert text.count(old) == 1
    wrong = api.load_post_text(text.replace(old, old.replace("G20", "G21")), "fanuc.yaml",
                               INCH)
    verdict = api.verify_commands(wrong, api.read_cl(EXAMPLES / "feeler_milling.apt"))
    assert verdict.divergence is not None


def test_an_option_value_per_choice_is_checked() -> None:
    text = (Path(__file__).parents[1] / "machines" / "fanuc.yaml").read_text(encoding="utf-8")
    wrong = text.replace("decimals: {option: program_units, mm: 3, inch: 4}",
                         "decimals: {option: program_units, mm: 3}")
    with pytest.raises(PostError) as caught:
        api.load_post_text(wrong, "fanuc.yaml")
    assert "must give a value for each choice of option 'program_units' (mm, inch): " \
           "inch missing" in str(caught.value)


def test_inch_snapshot(snapshot) -> None:
    """Read as a machinist: G20 in the safe-start block; X Y Z R Q in inches to 4
    decimals, F in inch/min to 2; P (ms) and S (rpm) as in mm."""
    text = "\n".join(posted("fanuc", "feeler_drilling.apt", INCH)) + "\n"
    assert text == snapshot.use_extension(NCSnapshot)


#: two inch steps (mm): a word is within half a step (0.00127 mm) of the CL; a peck
#: cycle's inner depths are R - n Q, so they add the roundings of R and of each Q
#: (4 mm is Q0.1575, 4.0005 mm: the fourth peck of N170 G83 ends 0.003 mm off)
TOLERANCE = 2 * 0.00254


def _same_motion(inch: list[Move], mm: list[Move]) -> None:
    assert [(m.kind, m.line) for m in inch] == [(m.kind, m.line) for m in mm]
    for a, b in zip(inch, mm, strict=True):
        assert all(abs(x * 25.4 - y) <= TOLERANCE
                   for x, y in zip(a.end, b.end, strict=True)), (a, b)
        assert abs(a.feed * 25.4 - b.feed) <= 0.5, (a, b)


@needs_rs274
@pytest.mark.parametrize("example", PROGRAMS)
def test_rs274_moves_the_inch_program_as_the_mm_one(example: str, tmp_path: Path) -> None:
    """rs274 reads G20 (USE_LENGTH_UNITS(CANON_UNITS_INCHES)) and reports in inches: each
    move of the inch program, times 25.4, is the mm program's, NC line by NC line."""
    (tmp_path / "in").mkdir()
    (tmp_path / "mm").mkdir()
    inch = run_rs274(for_rs274(posted("fanuc", example, INCH)), tmp_path / "in")
    mm = run_rs274(for_rs274(posted("fanuc", example)), tmp_path / "mm")
    assert "CANON_UNITS_INCHES" in inch.units and mm.units == {"CANON_UNITS_MM"}
    assert inch.moves
    _same_motion(inch.moves, mm.moves)
    assert [(line, round(s, 3)) for line, s in inch.dwells] == \
        [(line, round(s, 3)) for line, s in mm.dwells]


# --- LinuxCNC: FreeCAD's --inches ---------------------------------------------------------

LINUXCNC_INCH = {"program_units": "inch", "precision": "4"}
LINUXCNC_PROGRAMS = ["feeler_milling.apt", "boring.jsonl", "linuxcnc_rigid_tapping.jsonl",
                     "work_offsets.jsonl", "program_stops.jsonl"]


@pytest.mark.parametrize("example", LINUXCNC_PROGRAMS)
def test_the_linuxcnc_inch_program_verifies(example: str) -> None:
    """G20, lengths in inches, G4 P and the cycles' P still in seconds, G33.1 K in inches
    per revolution to 6 places (1.5 mm: K0.059055, 0.0001 % off the pitch)."""
    post = compiled_post("linuxcnc", LINUXCNC_INCH)
    verdict = api.verify_commands(post, api.read_cl(EXAMPLES / example))
    assert verdict.ok, verdict.divergence
    lines = posted("linuxcnc", example, LINUXCNC_INCH)
    assert "G20" in lines and "G21" not in lines


@needs_rs274
@pytest.mark.parametrize("example", LINUXCNC_PROGRAMS)
def test_rs274_moves_the_linuxcnc_inch_program_as_the_mm_one(example: str,
                                                            tmp_path: Path) -> None:
    (tmp_path / "in").mkdir()
    (tmp_path / "mm").mkdir()
    inch = run_rs274(posted("linuxcnc", example, LINUXCNC_INCH), tmp_path / "in")
    mm = run_rs274(posted("linuxcnc", example), tmp_path / "mm")
    assert "CANON_UNITS_INCHES" in inch.units and "CANON_UNITS_INCHES" not in mm.units
    assert inch.moves
    _same_motion(inch.moves, mm.moves)
    assert inch.dwells == mm.dwells


# --- EMCO (Sinumerik 828D): G700 -------------------------------------------------------------

EMCO_PROGRAMS = ["boring.jsonl", "fine_boring.jsonl", "emco_drilling.jsonl", "emco_pocket.gcode",
                 "feeler_milling.apt", "work_offsets.jsonl", "program_stops.jsonl"]


@pytest.mark.parametrize("example", EMCO_PROGRAMS)
def test_the_emco_inch_program_verifies(example: str) -> None:
    """G700: lengths, F and the cycles' lengths and feeds in inches (RTP RFP SDIS DP FDPR
    PIT RPA FFR…); dwells (G4 F, DTB) in seconds and POSS in degrees as in mm."""
    post = compiled_post("emco", INCH)
    verdict = api.verify_commands(post, api.read_cl(EXAMPLES / example))
    assert verdict.ok, verdict.divergence


def test_emco_inch_words() -> None:
    lines = posted("emco", "emco_drilling.jsonl", INCH)
    assert "N60 G700" in lines
    assert "N130 MCALL CYCLE81(0.7874, 0.0000, 0.0787, -0.0787)" in lines  # RTP 20 mm
    assert "N520 MCALL CYCLE840(0.7874, 0.0000, 0.1181, -0.7087, , 0.3, 4, 3, 1, , " \
           "0.059055)" in lines  # DTB 0.3 s, PIT 1.5 mm
    assert "N320 G4 F0.5" in posted("emco", "emco_pocket.gcode", INCH)  # seconds
    assert not any(line.endswith("G700") for line in posted("emco", "emco_drilling.jsonl"))


def test_the_sinumerik_model_reads_g700_and_g710() -> None:
    """Read as mm (G710 where the post writes G700), the inch program is 25.4 times too
    small: verify says so."""
    text = (Path(__file__).parents[1] / "machines" / "emco.yaml").read_text(encoding="utf-8")
    old = '      - items: [" G700"]\n'
    assert text.count(old) == 1
    wrong = api.load_post_text(text.replace(old, old.replace("G700", "G710")), "emco.yaml",
                               INCH)
    verdict = api.verify_commands(wrong, api.read_cl(EXAMPLES / "emco_drilling.jsonl"))
    assert verdict.divergence is not None


# --- HEIDENHAIN TNC 640: BEGIN PGM ... INCH --------------------------------------------------

#: corpus programs the Heidenhain post writes (lines, arcs in three planes, helices, every
#: cycle it has, bores, presets, stops, compensation, a probing cycle)
HEIDENHAIN_PROGRAMS = ["feeler_milling.apt", "heidenhain_cycles.jsonl", "boring.jsonl",
                       "work_offsets.jsonl", "program_stops.jsonl", "cutter_compensation.jsonl",
                       "linuxcnc_pocket.dump.txt", "feeler_probe_x.jsonl"]


@pytest.mark.parametrize("example", HEIDENHAIN_PROGRAMS)
def test_the_heidenhain_inch_program_verifies(example: str) -> None:
    """BEGIN PGM ... INCH: lengths (and the cycles' Q lengths, Q239 the pitch) in inches
    to 4 decimals, F and Q206/Q208 in 1/10 inch/min; the TNC model reads them back."""
    post = compiled_post("heidenhain", INCH)
    assert post.machine.units == "inch" and post.machine.resolution == 0.00254
    verdict = api.verify_commands(post, api.read_cl(EXAMPLES / example))
    assert verdict.ok, verdict.divergence


def test_heidenhain_inch_words() -> None:
    lines = posted("heidenhain", "feeler_milling.apt", INCH)
    assert lines[0] == "0 BEGIN PGM FEELER_MILLING INCH"
    assert lines[-1].endswith("END PGM FEELER_MILLING INCH")
    assert "14 L X+1.5748 R0 F196.9" in lines  # X40 mm; F500 mm/min = 19.685 inch/min
    mm = posted("heidenhain", "feeler_milling.apt")
    assert "14 L X+40 R0 F500" in mm and mm[0].endswith(" MM")
    cycles = posted("heidenhain", "heidenhain_cycles.jsonl", INCH)
    assert "  Q206=+70.8661 ;FEED RATE FOR PLNGNG ~" in cycles  # 180 mm/min
    assert "  Q239=+0.0492 ;THREAD PITCH ~" in cycles  # 1.25 mm per revolution
    assert "  Q211=+0.5 ;DWELL TIME AT DEPTH" in cycles  # seconds, as in mm


@pytest.mark.parametrize(("old", "new"), [
    # the feed written in inch/min, not the TNC's 1/10 inch/min: ten times too slow
    ("    multiplier: {option: program_units, mm: 1, inch: 0.3937007874015748}\n",
     "    multiplier: {option: program_units, mm: 1, inch: 0.03937007874015748}\n"),
    # inch values under BEGIN PGM ... MM: 25.4 times too small
    ("""          - {text: " INCH", if: "program_units == 'inch'"}\n""",
     """          - {text: " MM", if: "program_units == 'inch'"}\n"""),
])
def test_the_tnc_model_reads_the_program_in_its_units(old: str, new: str) -> None:
    text = (Path(__file__).parents[1] / "machines" / "heidenhain.yaml").read_text(
        encoding="utf-8")
    assert text.count(old) >= 1
    wrong = api.load_post_text(text.replace(old, new), "heidenhain.yaml", INCH)
    verdict = api.verify_commands(wrong, api.read_cl(EXAMPLES / "feeler_milling.apt"))
    assert verdict.divergence is not None


def test_a_full_circle_after_a_helix_is_refused_in_inches() -> None:
    """The CP's end is the control's (from the rounded CC and start): a full circle from
    it, its end rounded to 0.0001 inch, may not close (emco_pocket: 35 mm is X+1.378, the
    helix ends at X+1.1812 and the circle would end at X+1.1811)."""
    with pytest.raises(CLError) as caught:
        posted("heidenhain", "emco_pocket.gcode", INCH)
    assert "a full circle (C) right after a helix (CP) in an inch program" in \
        caught.value.message
    assert posted("heidenhain", "emco_pocket.gcode")  # in mm the grid holds every point


def test_heidenhain_inch_snapshot(snapshot) -> None:
    """Read as a machinist: BEGIN/END PGM ... INCH, BLK FORM and every X Y Z in inches to 4
    decimals, the cycles' Q200-Q204, Q257, Q256 of 203 in inches, Q206/Q208 in 1/10 inch/min,
    Q239 the pitch in inches per revolution (+-0.0492 for M8x1.25), dwells in seconds,
    S in rpm."""
    text = "\n".join(posted("heidenhain", "heidenhain_cycles.jsonl", INCH)) + "\n"
    assert text == snapshot.use_extension(NCSnapshot)
