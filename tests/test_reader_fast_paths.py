"""The readers' fast paths (issue 11) read exactly what their general paths read.

The APT and FreeCAD G-code readers take the common line -- ``GOTO/x,y,z``,
``G1 X… Y… F…`` -- through one precompiled pattern instead of the word-by-word loop;
whatever line the pattern takes, the loop must make the same of it (errors included).
"""

from __future__ import annotations

from hypothesis import example, given, settings
from hypothesis import strategies as st

from postdsl.cl import apt, freecad
from postdsl.errors import CLError

_DECIMAL = st.one_of(
    st.integers(-10**6, 10**6).map(str),
    st.tuples(st.integers(-9999, 9999), st.integers(0, 10**6)).map(lambda t: f"{t[0]}.{t[1]}"),
    st.sampled_from(["0", "-0.", ".5", "+1.", "-.25", "1" * 30, "9" * 320, "007.100"]))
#: what a record's value may hold on the fast path's characters, decimal or not
_TOKEN = st.one_of(_DECIMAL, st.text(alphabet="+-.0123456789 ", max_size=6))
_BLANK = st.sampled_from(["", " ", "  ", "\t"])


def _error(exc: CLError | None) -> tuple | None:
    return None if exc is None else (exc.message, exc.location)


def _outcome(read, *args):
    try:
        return ("ok", read(*args))
    except CLError as exc:
        return ("error", exc.message, exc.location)


@settings(deadline=None)
@given(st.sampled_from(["GOTO", "goto", "FEDRAT", "FROM", "Circle", "LOADTL", "SPINDL"]),
       st.lists(st.tuples(_BLANK, _TOKEN, _BLANK), min_size=1, max_size=7))
@example("GOTO", [("", "1", ""), ("", "2", ""), ("  ", "3", "\t")])
@example("GOTO", [("", "1.2.3", ""), ("", "2", ""), ("", "3", "")])
@example("GOTO", [("", "", ""), ("", "2", "")])
@example("GOTO", [("", "+", ""), ("", ".", ""), ("", "1-2", ""), ("", "1 5", "")])
def test_a_plain_apt_record_reads_as_the_general_path_reads_it(word: str, values: list) -> None:
    text = f"{word}/" + ",".join(f"{a}{v}{b}" for a, v, b in values)
    fast = _outcome(apt._parse_record, text, 4, "f.apt")
    general = _outcome(apt._parse_any_record, text, 4, "f.apt")
    if fast[0] == "ok" and general[0] == "ok":
        f, g = fast[1], general[1]
        assert (f.word, f.args, f.text, f.line, f.literal) == \
            (g.word, g.args, g.text, g.line, g.literal)
        assert _error(f.error) == _error(g.error)
    else:
        assert fast == general


_LETTER = st.sampled_from(list("XYZFIJKRQPSTHN"))


@settings(deadline=None)
@given(st.sampled_from(["G0", "G1", "G01", "G2", "G3", "G81", "M3", "M6", "G90"]),
       st.lists(st.tuples(_LETTER, _DECIMAL), max_size=6),
       st.sampled_from(["", "N10 ", "N0020 "]))
@example("G1", [("X", "1"), ("X", "2")], "")
@example("G1", [("X", "9" * 320)], "")
def test_a_plain_gcode_line_reads_as_the_word_by_word_loop_reads_it(
        name: str, words: list, block: str) -> None:
    text = block + " ".join([name] + [f"{letter}{value}" for letter, value in words])
    plain = freecad._PLAIN_LINE.match(text)
    general = _outcome(freecad._plain_words, text, 3, "f.nc", None)
    if plain is None:
        return
    fast = _outcome(lambda: [freecad._plain_command(plain, text, 3, "f.nc")])
    if fast[0] == "ok" and general[0] == "ok":
        assert [(c.name, c.args, c.line, c.text) for c in fast[1]] == \
            [(c.name, c.args, c.line, c.text) for c in general[1]]
    else:
        assert fast == general


@settings(deadline=None)
@given(st.sampled_from(["G0", "G1", "G01", "G2", "G81", "M3", "M6", "G90"]),
       st.lists(st.tuples(_LETTER, _DECIMAL), max_size=6))
@example("G1", [("X", "1"), ("X", "2")])
@example("G1", [("F", "9" * 320)])
def test_a_plain_dump_record_reads_as_the_general_path_reads_it(name: str, words: list) -> None:
    text = f"Command {name} [" + "".join(f" {letter}:{value}" for letter, value in words) + " ]"
    assert freecad._PLAIN_DUMP.match(text) is not None
    fast = _outcome(freecad._dump_command, text, 5, "f.txt")
    general = _outcome(freecad._dump_any_command, text, 5, "f.txt")
    if fast[0] == "ok" and general[0] == "ok":
        f, g = fast[1], general[1]
        assert (f.name, f.args, f.line, f.text) == (g.name, g.args, g.line, g.text)
    else:
        assert fast == general
