"""boring (G85/G89) and boring_spindle_stop (G86): read from G-code, written as cycles
where the control has them, as moves where not, refused with the control's reason, and
verified -- a feed-out bore is not a spindle-stop bore."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import pytest

from postdsl import api
from postdsl.cl.model import Boring, BoringSpindleStop
from postdsl.errors import CLError, PostError
from tests.conftest import ROOT
from tests.test_rs274_oracle import check_program, needs_rs274

BORING = ROOT / "examples" / "boring.jsonl"
STOP = ROOT / "examples" / "boring_spindle_stop.jsonl"


def test_gcode_g85_g89_g86_are_read_as_boring_setups() -> None:
    text = ("G21 G90\nT1 M6\nS800 M3\nG0 X0 Y0 Z30\nG98 G85 X20 Y20 Z-15 R3 F60\n"
            "G89 X20 Y50 Z-15 R3 P0.5 F60\nG86 X20 Y80 Z-15 R3 F60\nG80\nM30\n")
    setups = [(c.name, c.line, c.dwell) for c in api.read_cl_text(text, "b.ngc", "gcode")
              if isinstance(c, (Boring, BoringSpindleStop))]
    assert setups == [("boring", 5, 0.0), ("boring", 6, 0.5), ("boring_spindle_stop", 7, 0.0)]


@pytest.mark.parametrize(("machine", "words"), [
    ("fanuc", ["G85", "G89", "G86"]), ("feeler", ["G85", "G89", "G86"]),
    ("linuxcnc", ["G85", "G89", "G86"])])
def test_iso_posts_write_the_boring_cycles(machine: str, words: list[str]) -> None:
    post = api.load_post(machine)
    text = "\n".join(line.text for cl in (BORING, STOP)
                     for line in api.post_commands(post, api.read_cl(cl)))
    for word in words:
        assert f"{word} X" in text, word


@pytest.mark.parametrize(("machine", "words"), [
    ("emco", ["MCALL CYCLE85(30.000, 0.000, 3.000, -15.000, , , 60, 60)", "0 F60\n",
              "MCALL CYCLE89(30.000, 0.000, 3.000, -15.000, , 0.5)"]),
    ("heidenhain", ["CYCL DEF 201 REAMING ~", "  Q211=+0.5 ;DWELL TIME AT DEPTH ~",
                    "  Q208=+60 ;RETRACTION FEED RATE ~", "11 L X+20 Y+20 R0 FMAX M99"])])
def test_sinumerik_and_tnc_posts_write_their_boring_cycles(machine: str,
                                                          words: list[str]) -> None:
    """EMCO (Sinumerik): CYCLE85 feeds in at FFR and out at RFF, CYCLE89 dwells first at
    the active F; TNC: cycle 201 REAMING with Q208 = Q206 -- each verified as a bore."""
    post = api.load_post(machine)
    text = "\n".join(line.text for line in api.post_commands(post, api.read_cl(BORING)))
    for word in words:
        assert word in text, word
    verdict = api.verify_commands(api.load_post(machine), api.read_cl(BORING))
    assert verdict.divergence is None, verdict.divergence
    assert verdict.holes == 4


@pytest.mark.parametrize(("machine", "old", "new", "message"), [
    ("emco", "{expr: \"feed\", format: feed, prefix: \", \"}   # RFF",
     "{expr: \"feed * 2\", format: feed, prefix: \", \"}   # RFF",
     "CYCLE85 with a retraction feed RFF other than FFR is not modelled"),
    ("heidenhain", 'q: "208", value: "feed"', 'q: "208", value: "feed * 2"',
     "cycle 201: retraction feed Q208=120 other than the plunging feed Q206=60"),
])
def test_a_bore_leaving_at_another_feed_is_not_passed(machine: str, old: str, new: str,
                                                      message: str) -> None:
    text = (ROOT / "machines" / f"{machine}.yaml").read_text(encoding="utf-8")
    assert text.count(old) == 1
    wrong = api.load_post_text(text.replace(old, new), f"{machine}.yaml")
    verdict = api.verify_commands(wrong, api.read_cl(BORING))
    assert verdict.divergence is not None and message in verdict.divergence.message


@pytest.mark.parametrize("machine", ["grbl", "vmc500"])
def test_posts_without_the_cycle_bore_as_moves_feeding_out(machine: str) -> None:
    lines = [line.text for line in api.post_commands(api.load_post(machine),
                                                     api.read_cl(BORING))]
    assert not any(re.search(r"\bG8[59] X", line) for line in lines)
    verdict = api.verify_commands(api.load_post(machine), api.read_cl(BORING))
    assert verdict.divergence is None, verdict.divergence
    assert verdict.cuts == 10  # per hole: down and up at the feed (2 holes dwell between)


@pytest.mark.parametrize(("machine", "reason"), [
    ("grbl", "no canned cycles"), ("emco", "CYCLE86"), ("heidenhain", "cycle 202"),
    ("vmc500", "boring with a spindle stop is not written")])
def test_a_spindle_stop_bore_is_refused_where_the_post_cannot_write_it(machine: str,
                                                                    reason: str) -> None:
    with pytest.raises(CLError) as caught:
        list(api.post_commands(api.load_post(machine), api.read_cl(STOP), cl_file=STOP.name))
    assert caught.value.location is not None and caught.value.location.line == 5
    assert reason in caught.value.message


@pytest.mark.parametrize(("cl", "old", "new", "message"), [
    (STOP, '          - " G86"\n', '          - " G85"\n', "a bore cycle, CL says bore stop"),
    (BORING, '{text: " G85", if: "dwell == 0"}', '{text: " G81", if: "dwell == 0"}',
     "a drill cycle, CL says bore"),
])
def test_verify_tells_the_bores_apart(cl: Path, old: str, new: str, message: str) -> None:
    text = (ROOT / "machines" / "fanuc.yaml").read_text(encoding="utf-8")
    at = text.index(old, text.index("  boring:"))
    wrong = api.load_post_text(text[:at] + new + text[at + len(old):], "fanuc.yaml")
    verdict = api.verify_commands(wrong, api.read_cl(cl))
    assert verdict.divergence is not None and message in verdict.divergence.message


@needs_rs274
@pytest.mark.parametrize("example", ["boring.jsonl", "boring_spindle_stop.jsonl"])
def test_rs274_bores_the_fanuc_holes_as_the_cl(example: str, tmp_path: Path) -> None:
    _moves, holes = check_program(example, tmp_path, api.load_post("fanuc"),
                                 drill_per_rev=False)
    assert holes > 0


FINE = ROOT / "examples" / "fine_boring.jsonl"


@pytest.mark.parametrize(("machine", "words"), [
    ("fanuc", ["G98 G76 X20. Y20. Z-15. R3. Q0.2 F60.", "G98 G76 X20. Y50. Z-15. R3. Q0.2 P500"]),
    ("emco", ["MCALL CYCLE86(30.000, 0.000, 3.000, -15.000, , 0.0, 3, 0.200, 0.000, 0, 0.000)",
              "MCALL CYCLE86(30.000, 0.000, 3.000, -15.000, , 0.5, 3, 0.200, 0.000, 0, 0.000)"])])
def test_fine_boring_is_the_controls_cycle_and_verifies(machine: str, words: list[str]) -> None:
    """Fanuc G76 Q (the shift; its direction is parameter 5101's, the post's variable),
    Sinumerik CYCLE86 with the shift as RPA/RPO: verify replays both as a fine bore."""
    post = api.load_post(machine)
    text = "\n".join(line.text for line in api.post_commands(post, api.read_cl(FINE)))
    for word in words:
        assert word in text, word
    verdict = api.verify_commands(api.load_post(machine), api.read_cl(FINE))
    assert verdict.divergence is None, verdict.divergence
    assert verdict.holes == 3


@pytest.mark.parametrize(("machine", "reason"), [
    ("linuxcnc", "no fine-boring cycle"), ("grbl", "no oriented spindle stop"),
    ("feeler", "parameter 5101"), ("heidenhain", "cycle 202"), ("vmc500", "thesis post")])
def test_fine_boring_is_refused_where_the_post_cannot_write_it(machine: str,
                                                              reason: str) -> None:
    with pytest.raises(CLError) as caught:
        list(api.post_commands(api.load_post(machine), api.read_cl(FINE), cl_file=FINE.name))
    assert caught.value.location is not None and caught.value.location.line == 5
    assert reason in caught.value.message


def test_fine_boring_refuses_a_shift_the_machine_does_not_make() -> None:
    """The Fanuc's G76 shifts the way parameter 5101 says (+X here): a CL shift in -Y is
    refused, not written as a G76 that would drag the edge across the wall."""
    commands = [c if c.name != "fine_boring" else dataclasses.replace(c, shift_direction="-y")
                for c in api.read_cl(FINE)]
    with pytest.raises(CLError) as caught:
        list(api.post_commands(api.load_post("fanuc"), commands))
    assert "parameter 5101 (RD1, RD2)" in caught.value.message


def test_verify_tells_a_fine_bore_from_a_bore() -> None:
    text = (ROOT / "machines" / "fanuc.yaml").read_text(encoding="utf-8")
    wrong = api.load_post_text(text.replace('          - " G76"\n', '          - " G85"\n', 1)
                               .replace('          - {param: shift, prefix: " Q", '
                                        'format: coord}\n', "", 1), "fanuc.yaml")
    verdict = api.verify_commands(wrong, api.read_cl(FINE))
    assert verdict.divergence is not None and "fine bore" in verdict.divergence.message


def test_fine_boring_cannot_be_expanded() -> None:
    text = (ROOT / "machines" / "grbl.yaml").read_text(encoding="utf-8")
    at = text.index("  fine_boring:\n")
    end = text.index("    blocks: []\n", at) + len("    blocks: []\n")
    wrong = text[:at] + "  fine_boring:\n    expand: true\n" + text[end:]
    with pytest.raises(PostError) as caught:
        api.load_post_text(wrong, "grbl.yaml")
    assert "fine_boring cannot be expanded into moves" in str(caught.value)


@pytest.mark.parametrize(("machine", "old", "new", "message"), [
    ("fanuc", '          - {param: shift, prefix: " Q", format: coord}\n',
     '          - {expr: "shift * 2", prefix: " Q", format: coord}\n',
     "a fine bore shifting 0.400 mm off the wall, CL says 0.200 mm"),
    ("emco", "shift if shift_direction == '+x' else (-shift",
     "shift * 2 if shift_direction == '+x' else (-shift",
     "a fine bore shifting 0.400 mm off the wall, CL says 0.200 mm"),
    ("emco", "shift if shift_direction == '+x' else (-shift",
     "-shift if shift_direction == '+x' else (-shift",
     "a fine bore shifting -x, CL says +x"),
])
def test_verify_compares_the_fine_boring_shift(machine: str, old: str, new: str,
                                               message: str) -> None:
    """A post writing the wrong shift (G76 Q, CYCLE86 RPA) is caught: too little marks the
    finished wall, too much (or the wrong way) drives the bar's back into it."""
    text = (ROOT / "machines" / f"{machine}.yaml").read_text(encoding="utf-8")
    assert text.count(old) == 1
    wrong = api.load_post_text(text.replace(old, new), f"{machine}.yaml")
    verdict = api.verify_commands(wrong, api.read_cl(FINE))
    assert verdict.divergence is not None and message in verdict.divergence.message, \
        verdict.divergence


def _tnc(lift_off: str, old: str = "", new: str = "") -> api.CompiledPost:
    """The Heidenhain post with the machine's cycle 202 lift-off distance declared."""
    text = (ROOT / "machines" / "heidenhain.yaml").read_text(encoding="utf-8")
    assert text.count("  fine_boring_lift_off: 0\n") == 1 and (not old or text.count(old) == 1)
    text = text.replace("  fine_boring_lift_off: 0\n", f"  fine_boring_lift_off: {lift_off}\n")
    return api.load_post_text(text.replace(old, new), "heidenhain.yaml")


def test_tnc_cycle_202_bores_where_the_machines_lift_off_is_the_cl_shift() -> None:
    """Cycle 202 BORING: Q214=3 disengages in +X (the CL's +x), by the control's own distance,
    which the post takes from fine_boring_lift_off; the model replays a fine bore and
    compares the direction."""
    post = _tnc("0.2")
    text = "\n".join(line.text for line in api.post_commands(post, api.read_cl(FINE)))
    for word in ("CYCL DEF 202 BORING ~", "  Q214=+3 ;DISENGAGING DIRECTN ~",
                 "  Q211=+0.5 ;DWELL TIME AT DEPTH ~", "14 L X+20 Y+50 R0 FMAX M99"):
        assert word in text, word
    verdict = api.verify_commands(post, api.read_cl(FINE))
    assert verdict.divergence is None, verdict.divergence
    assert verdict.holes == 3


def test_tnc_cycle_202_refuses_a_shift_the_control_does_not_make() -> None:
    with pytest.raises(CLError) as caught:
        list(api.post_commands(_tnc("0.3"), api.read_cl(FINE), cl_file=FINE.name))
    assert caught.value.location is not None and caught.value.location.line == 5
    assert "disengages by this machine's fine_boring_lift_off, not by the CL's shift" in \
        caught.value.message


def test_verify_catches_a_wrong_disengaging_direction() -> None:
    """A post mapping +x to Q214=1 (-X) would drive the bar's back into the wall: caught."""
    post = _tnc("0.2", "(3 if shift_direction == '+x' else 4)",
                "(1 if shift_direction == '+x' else 4)")
    verdict = api.verify_commands(post, api.read_cl(FINE))
    assert verdict.divergence is not None
    assert "a fine bore shifting -x, CL says +x" in verdict.divergence.message
