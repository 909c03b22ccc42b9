"""The APT and FreeCAD G-code readers' plain-move paths change nothing they read.

Both readers take their commonest line (``GOTO/x,y,z``; a G0 or G1 of plain decimals,
in G-code or in FreeCAD's dump) by one pattern on the line itself, and hand its values
either to the first pass's fold (no command at all) or to a fast constructor.  Two
things must hold for every file, generated or in the repository, odd lines and all:

* the commands read are those the reader's general path reads with the plain-move
  path switched off -- the same types, values (``1`` is not ``1.0``) and lines, or
  the same error at the same place;
* the first pass gives the summary that folding those commands gives, as
  :mod:`tests.test_first_pass` states it (:func:`~tests.test_first_pass.reference_summary`).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from contextlib import ExitStack, contextmanager
from pathlib import Path
from typing import Any
from unittest import mock

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from postdsl.cl import apt, freecad
from postdsl.cl.lines import SourceLines, text_blocks
from postdsl.cl.readers import fold_commands, read_cl, read_cl_text
from postdsl.cl.source import CLSource
from postdsl.errors import CLError
from postdsl.run.program import SummaryFolder, summarize_source
from tests.conftest import DATA, EXAMPLES, ROOT
from tests.test_first_pass import RAPID_RATE, outcome, reference_summary

_NEVER = re.compile(r"(?!)")


@contextmanager
def general_paths() -> Iterator[None]:
    """The readers with their plain-move paths switched off."""
    with ExitStack() as stack:
        stack.enter_context(mock.patch.object(apt, "_PLAIN_GOTO_LINE", _NEVER))
        stack.enter_context(mock.patch.object(apt._Reader, "plain_goto",
                                              lambda *args: None))
        stack.enter_context(mock.patch.object(freecad, "_PLAIN_MOVE", _NEVER))
        stack.enter_context(mock.patch.object(freecad, "_PLAIN_DUMP_MOVE", _NEVER))
        yield


def read_outcome(read: Callable[[], list[Any]]) -> Any:
    """The commands as their reprs (types and values), or the error and its place."""
    try:
        return ("commands", [repr(command) for command in read()])
    except CLError as exc:
        return ("error", exc.message, exc.location)


def fold(text: str, file: str, fmt: str | None, feed_units: str | None) -> Any:
    folder = SummaryFolder(RAPID_RATE)
    fold_commands(SourceLines(text_blocks(text), file), folder, fmt, feed_units)
    return folder.summary()


def assert_unchanged(text: str, file: str, fmt: str | None = None,
                     feed_units: str | None = None) -> Any:
    """Both guarantees for one program; its outcome (commands or the error)."""
    def read() -> list[Any]:
        return read_cl_text(text, file, fmt, feed_units)

    with general_paths():
        expected = read_outcome(read)
        reference = outcome(lambda: reference_summary(read(), RAPID_RATE))
    assert read_outcome(read) == expected
    assert outcome(lambda: fold(text, file, fmt, feed_units)) == reference
    return expected


# --- APT -------------------------------------------------------------------------------

_NUMBER = st.one_of(
    st.integers(-500, 500).map(str),
    st.floats(-500, 500, allow_nan=False).map(lambda v: f"{v:.4f}"),
    st.sampled_from(["0", "-0.", ".5", "+1.", "-.25", "007.100", "1e3", "1.2.3", "", "+",
                     "9" * 400, " 2 ", "1 5", "\t3"]))


def _odd(draw: st.DrawFn, odd: bool, plain: st.SearchStrategy[str]) -> str:
    return draw(_NUMBER) if odd and draw(st.integers(0, 12)) == 0 else draw(plain)


@st.composite
def goto(draw: st.DrawFn, odd: bool) -> str:
    plain = st.floats(-200, 200, allow_nan=False).map(lambda v: f"{v:.3f}".rstrip("0"))
    values = [_odd(draw, odd, plain) for _ in range(3)]
    if draw(st.integers(0, 5)) == 0:  # NX's tool axis after the point
        values += draw(st.sampled_from([["0", "0", "1"], ["0.", "-0.", "1.000"]] +
                                       ([["0", "1", "0"], ["0", "0", "-1"], ["0", "0", "1e-9"],
                                         ["0", "0", "0"], [".5", "0", "1"], ["0", "0", ""],
                                         ["0", "0", "9" * 400], ["0", "9" * 400, "1"],
                                         ["1"]] if odd else [])))
    word = draw(st.sampled_from(["GOTO", "GOTO", "GOTO", "goto", "Goto"])) if odd else "GOTO"
    word += draw(st.sampled_from(["", "", " ", "  ", "\t"]))  # Creo: GOTO / x, y, z
    line = f"{word}/" + draw(st.sampled_from([",", ", ", " ,"])).join(values)
    if odd:
        line = draw(st.sampled_from(["", "", "", " ", "  "])) + line + \
            draw(st.sampled_from(["", "", "", " ", "\t", " $$ note"]))
    return line


@st.composite
def apt_programs(draw: st.DrawFn, odd: bool = False) -> str:
    lines = []
    if draw(st.booleans()):
        lines.append("PARTNO/GEN")
    if draw(st.integers(0, 3)) == 0:
        lines.append(draw(st.sampled_from(["UNITS/MM", "UNITS/INCHES"])))
    if draw(st.booleans()):
        lines += ["CUTTER/6,1", "LOADTL/1", "SPINDL/2000,RPM,CLW"]
    if draw(st.booleans()):
        lines.append("FROM/0,0,50")
    if not odd or draw(st.integers(0, 4)):
        lines.append(draw(st.sampled_from(["FEDRAT/300", "FEDRAT/12.5,MMPM", "FEDRAT/2,IPM"])))
    for _ in range(draw(st.integers(0, 40))):
        choice = draw(st.integers(0, 19))
        if choice < 9:
            lines.append(draw(goto(odd)))
        elif choice < 11:
            lines += ["RAPID", draw(goto(odd))]
        elif choice == 11:
            lines.append(draw(st.sampled_from(["FEDRAT/500", "FEDRAT/800,MMPM", "FEDRAT/20,IPM",
                                               "fedrat/250"] + ["FEDRAT/0"] * odd)))
        elif choice == 12:
            lines += draw(st.sampled_from([["GOTO/10,0,0", "CIRCLE/0,0,0,0,0,1,10", "GOTO/0,10,0"],
                                           ["GOTO/10,0,0", "MOVARC/0,0,0,0,0,1,10,ANGLE,90"],
                                           ["GOTO/10,0,0", "MOVARC/0,0,0,0,0,1,10,ANGLE,90",
                                            "GOTO/0,10,0", "GOTO/0,10,0"]]))
        elif choice == 13:
            lines += ["CYCLE/DRILL,5,MMPM,100,2", "GOTO/1,1,0", "GOTO/2,2,0", "CYCLE/OFF"]
        elif choice == 14:
            lines += ["GOTO/1,$", "2,3"]
        elif choice == 15:
            lines += draw(st.sampled_from([["$$ a note", "PPRINT hello"],
                                           ["$$-> CSYS / 1, $", "0,0,1", "GOTO/4,5,6"],
                                           ["$$-> CSYS / 1, $", "GOTO/4,5,6"]]))
        elif choice == 16:
            lines.append(draw(st.sampled_from(["", "LOADTL/2", "COOLNT/FLOOD", "DELAY/1",
                                               "SPINDL/OFF", "TLAXIS/0,0,1"])))
        elif choice == 17:
            lines += ["LOADTL/3", draw(goto(odd))]  # a move with the tool change pending
        elif odd:
            lines.append(draw(st.sampled_from(["RAPID", "END", "FINI", "GOTO/1,2", "BOGUS/1",
                                               "GOTO/", "GOTO/(CIRCLE/1)", "RAPID/"])))
    if not odd or draw(st.integers(0, 15)):
        lines += draw(st.sampled_from([["END", "FINI"], ["FINI"], ["END"]]))
    if odd and draw(st.integers(0, 15)) == 0:
        lines.append("GOTO/1,2,3")
    return "\n".join(lines) + draw(st.sampled_from(["\n", "", "\r\n"]))


_SETTINGS = settings(deadline=None,
                     suppress_health_check=[HealthCheck.too_slow])


@_SETTINGS
@given(apt_programs())
@example("PARTNO/P\nLOADTL/1\nFEDRAT/100\nGOTO/1,2,3\nRAPID\nGOTO/4,5,6\nGOTO/7,8,9\nEND\n")
@example("UNITS/INCHES\nLOADTL/1\nFEDRAT/10\nGOTO/1,2,3\nFINI\n")
def test_a_generated_apt_program_reads_and_folds_unchanged(text: str) -> None:
    assert_unchanged(text, "gen.apt", "apt")


@_SETTINGS
@given(apt_programs(odd=True))
@example("LOADTL/1\nGOTO/1,2,3\nEND\n")  # a feed move before any FEDRAT
@example("LOADTL/1\nFEDRAT/1\nGOTO/1e3,2,3\nGOTO/1,2\nGOTO/" + "9" * 400 + ",1,1\nEND\n")
@example("LOADTL/1\nFEDRAT/1\nGOTO/1,$\n2,3\nRAPID\nGOTO/1,2,3 $$ x\nEND\n")
@example("LOADTL/1\nFEDRAT/1\n$$-> CSYS / 1, $\n0,0\nGOTO/1,2,3\nEND\nFINI\nGOTO/1,2,3\n")
@example("LOADTL/1\nFEDRAT/1\nRAPID\nRAPID\nGOTO/1,2,3\nEND\n")
@example("LOADTL/1\nFEDRAT/1\nGOTO/1,2,3\n")  # no END
def test_an_odd_apt_program_reads_and_folds_or_fails_unchanged(text: str) -> None:
    assert_unchanged(text, "odd.apt", "apt")


# --- FreeCAD G-code and dump -------------------------------------------------------------

_HEADERS = ("(Exported by FreeCAD)\n(Post Processor: linuxcnc_post)\nG17 G54 G40 G49 G80 G90\n"
            "G21\nM6 T1\nG43 H1\nM3 S3000\n",
            "(path, as Path.toGCode writes it)\nG90\nG17\nM6 T1.000000\nM3 S3000.000000\n",
            "G90\nM6 T1\nM3 S1000\n")


@st.composite
def move_words(draw: st.DrawFn, odd: bool, dump: bool) -> str:
    plain = st.floats(-200, 200, allow_nan=False).map(lambda v: f"{v:.6f}")
    letters = draw(st.lists(st.sampled_from("XYZF"), unique=True, max_size=4))
    if not draw(st.integers(0, 3)):
        letters.sort()
    if odd and draw(st.integers(0, 8)) == 0:
        letters.append(draw(st.sampled_from("XFIKRSN")))
    values = []
    for letter in letters:
        if letter == "F" and not odd:
            value = draw(st.sampled_from(["20.000000", "500", "13.3333"]))
        else:
            value = _odd(draw, odd, plain)
        values.append((letter, value))
    if dump:
        return "".join(f" {letter}:{value}" for letter, value in values)
    # one blank between words, or none (both read alike), or now and then two
    blank = draw(st.sampled_from([" ", " ", " ", ""] + (["  ", "\t"] if odd else [])))
    return "".join(f"{blank or ' ' if index == 0 else blank}{letter}{value}"
                   for index, (letter, value) in enumerate(values))


#: the feed units each header may be posted with (its own evidence, or the user's word)
_UNITS = ((None, "mm/min"), (None, "mm/s", "mm/s"), ("mm/min", "mm/s"))


@st.composite
def gcode_programs(draw: st.DrawFn, odd: bool = False) -> tuple[str, str | None]:
    """A program in one of FreeCAD's forms, and the --feed-units to read it with."""
    dump = draw(st.integers(0, 3)) == 0
    header = draw(st.integers(0, len(_HEADERS) - 1))
    units = draw(st.sampled_from((None, "mm/s") if dump else _UNITS[header]))
    if odd and draw(st.integers(0, 10)) == 0:
        units = draw(st.sampled_from([None, "mm/min", "mm/s"]))
    lines = ["(Path: Gen)", "Command M6 [ T:1 ]", "Command M3 [ S:3000 ]"] if dump else \
        [_HEADERS[header].rstrip("\n")]
    if not odd or draw(st.booleans()):
        lines += ["Command G0 [ X:0 Y:0 Z:5 ]", "Command G1 [ F:5 X:0 ]"] if dump else \
            ["G0 X0 Y0 Z5", "G1 X0 F300"]
    if draw(st.booleans()):  # the lines after the first 200 are read as they are, unstripped
        lines += ["Command (pad) [ ]" if dump else "(pad)"] * freecad._EVIDENCE_WINDOW
    numbered = not dump and draw(st.integers(0, 4)) == 0
    for _ in range(draw(st.integers(0, 40))):
        choice = draw(st.integers(0, 14))
        if choice < 9:
            code = draw(st.sampled_from(["G1", "G1", "G0", "G01", "G00"] +
                                        ([""] if not dump else []) +
                                        (["g1", "G1 ", "G1  "] if odd else [])))
            words = draw(move_words(odd, dump))
            line = f"Command {code} [{words} ]" if dump else (code + words).lstrip(" ")
            # the blank FreeCAD's linuxcnc post leaves at the end of its lines
            line += draw(st.sampled_from(["", "", " "] + (["  ", "\t"] if odd else [])))
            block = [line]
        elif choice < 11:
            block = draw(st.sampled_from([["G3 X10 Y0 I5 J0 F300"], ["G2 X0 Y0 I-5"], ["X5 Y5"],
                                          ["Z-1"], ["G18", "G3 X1 Z1 I1"], ["G17"],
                                          ["G91", "G1 X1 Y-1", "G0 Z1", "G90"]]))
            if dump:
                block = draw(st.sampled_from([["Command G91 [ ]", "Command G1 [ X:1 ]",
                                               "Command G90 [ ]"],
                                              ["Command G3 [ I:5 J:0 X:10 Y:0 ]"]]))
        elif choice == 11:
            block = draw(st.sampled_from([["G81 X1 Y1 Z-5 R2 F100", "G81 X2 Y2", "G80", "G0 Z5"],
                                          ["G99"], ["G98"],
                                          ["G81 X1 Y1 Z-5 R2 F100", "G1 X3 Y3"]]))
            if dump:
                block = ["Command G81 [ F:1 R:2 X:1 Y:1 Z:-5 ]", "Command G1 [ Z:5 ]"]
        elif choice == 12:
            block = [draw(st.sampled_from(["(a comment)", "M8", "M9", "G4 P1", "; note"]))]
            if dump:
                block = ["Command (a comment) [ ]"]
        elif odd:
            block = [draw(st.sampled_from(["G1 X1 X2", "G1 F0", "G1 F-5", "G0 F100 X1",
                                           "G1 X1e400", "G1 Xabc", "%", "M2", "G20"]))]
            if dump:
                block = [draw(st.sampled_from(["Command G1 [ F:0 ]", "Command G1 [ X:1 X:2 ]",
                                               "Command G1 ( X:1 )", "(banner)"]))]
        else:
            block = [""]
        for line in block:
            lines.append(f"N{len(lines) * 10} {line}" if numbered and line else line)
    if not dump and (not odd or draw(st.integers(0, 10))):
        lines += ["M5", "M2"]
    text = "\n".join(lines)
    return text + ("\n" if not odd or draw(st.integers(0, 10)) else ""), units


@_SETTINGS
@given(gcode_programs())
@example(("G90\nM6 T1\nG1 X1 Y2 Z3 F100\nG0 Z5\nG1 X4\nM2\n", "mm/min"))
@example(("(Path: P)\nCommand G1 [ F:5 X:1 Y:2 Z:3 ]\nCommand G0 [ Z:5 ]\n", None))
def test_a_generated_gcode_program_reads_and_folds_or_fails_unchanged(
        program: tuple[str, str | None]) -> None:
    assert_unchanged(program[0], "gen.gcode", "freecad", program[1])


@_SETTINGS
@given(gcode_programs(odd=True).map(lambda program: program[0]),
       st.sampled_from([None, "mm/min", "mm/s"]))
@example("G90\nG1 X1 F100\nG1 F0 X2\nM2\n", "mm/min")
@example("G90\nG0 X1 F100\nG1 X2\nM2\n", "mm/min")  # a post's G0 F: the feed in force
@example("(x)\nG0 X1 F100\nG1 X2\n", "mm/s")  # the internal path's G0 F: not a feed
@example("G90\nG1 X1 F100 F200\nM2\n", "mm/min")
@example("G90\nG1 X" + "9" * 400 + " F100\nM2\n", "mm/min")
@example("G90\nG81 X1 Y1 Z-5 R2 F100\nG1 X5\nM2\n", "mm/min")
@example("G91\nG1 X1 F100\nM2\n", "mm/min")
@example("G90\nM2\nG1 X1\n", "mm/min")
def test_an_odd_gcode_program_reads_and_folds_or_fails_unchanged(
        text: str, units: str | None) -> None:
    assert_unchanged(text, "odd.gcode", "freecad", units)


def test_the_plain_moves_reach_the_fold_without_a_command() -> None:
    """A raster's GOTO and G0/G1 lines never become commands in the first pass."""
    apt_text = "LOADTL/1\nFEDRAT/100\n" + "GOTO/1,2,3\n" * 50 + "RAPID\nGOTO/1,2,9\nEND\n"
    gcode_text = "G21\nG90\nM6 T1\nG0 X0 Y0 Z5\n" + "G1 X1.5 Y2 Z-1 F300\n" * 50 + "M2\n"
    dump_text = "(Path: P)\nCommand G0 [ Z:5 ]\n" + "Command G1 [ F:5 X:1 Y:2 ]\n" * 50

    class Watch(SummaryFolder):
        def __init__(self) -> None:
            super().__init__(RAPID_RATE)
            self.seen: list[str] = []

        def command(self, command: Any) -> None:
            self.seen.append(command.name)
            super().command(command)

    for text, fmt in ((apt_text, "apt"), (gcode_text, "freecad"), (dump_text, "freecad")):
        watch = Watch()
        fold_commands(SourceLines(text_blocks(text), "f"), watch, fmt)
        assert watch.seen and not {"rapid_move", "linear_move"} & set(watch.seen), fmt


# --- every CL file of the repository ---------------------------------------------------------

CL_FILES = sorted(path for folder in (EXAMPLES, DATA) for path in folder.rglob("*")
                  if path.suffix in {".apt", ".gcode", ".ncl", ".ngc", ".nc"}
                  or path.name.endswith(".dump.txt"))


def test_the_repository_has_apt_and_gcode_files() -> None:
    assert {".apt", ".gcode", ".ncl", ".ngc", ".nc", ".txt"} <= \
        {path.suffix for path in CL_FILES}


@pytest.mark.parametrize("path", CL_FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_apt_and_gcode_file_reads_and_folds_unchanged(path: Path) -> None:
    def first_pass() -> Any:
        with CLSource(path) as source:
            return summarize_source(source, RAPID_RATE)

    with general_paths():
        expected = read_outcome(lambda: read_cl(path))
        reference = outcome(lambda: reference_summary(read_cl(path), RAPID_RATE))
    assert read_outcome(lambda: read_cl(path)) == expected
    assert outcome(first_pass) == reference
