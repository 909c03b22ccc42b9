"""Plain RS274/NGC G-code, as any CAM system writes it -> CL records.

The G-code of hobby and open-source CAM systems (Fusion's grbl, Mach3 and LinuxCNC
posts, Vectric, Estlcam, Carbide Create, PyCAM, CAMotics…) is RS274/NGC: a block is
a line of words, and what the block does follows RS274's *order of execution*, not
the order the words are written in (``G0 X0 Y0 S15000 M3`` starts the spindle, then
moves; ``T1 M6`` and ``M6 T1`` both load tool 1).  This reader takes the blocks
whole, puts their words in that order and hands them to the meaning rules of the
FreeCAD reader (:mod:`postdsl.cl.freecad`: moves, arcs, canned cycles, G90/G91,
planes, the end of the program), so both read a word alike.

What happens to each word (docs/reference/cl-input.md, "Plain G-code", lists them too):

* ``N`` (first word), ``%`` lines at the start and end, blank lines: read, no record.
* ``(text)`` and ``; text`` comments, alone or after code (``G40 (disable…)``): a
  comment record each, before the block's commands.
* ``F`` alone on a block: the feed in force from there on (the next cutting move
  carries it); on a motion block: that move's feed.  Per minute (G94, RS274's
  default); ``G94`` is accepted.  ``G95`` (per revolution): F times the spindle speed in
  force is the CL's mm/min, exactly, converted again when S changes; a cutting move with
  no speed in force is refused at its line.  Switching G94/G95 drops the F in force, as
  rs274 does (SET_FEED_RATE(0)): the next cutting move gives its own.
  ``G93`` (inverse time) is refused: its F is one over the move's time, which only a
  post (knowing the machine) writes.
* ``S`` with ``M3``/``M4``: spindle_on; ``S`` alone: the speed of the next M3/M4, or
  a spindle_on at once when the spindle turns.  ``M5``: spindle_off.
* ``T`` selects the tool, ``M6`` loads the selected one (``T1 M6``, ``T1M6``, ``M6 T1``,
  ``T1`` then ``M6``): tool_change.
* ``G20`` inches: every length (X Y Z I J K R Q) and feed after it is converted to mm
  exactly (the decimal written times 25.4, rounded once); ``G21`` mm.
* ``G2``/``G3`` with ``R`` (radius form): the centre RS274 gives the arc (the shorter arc
  for R > 0, the longer for R < 0), written as I J K; R with I J K, a radius too short
  for the chord and an arc ending where it starts are refused.
* ``G0 G1 G2 G3``, ``G4 P`` (seconds), ``G17-G19``, ``G90/G91``, ``G81-G84 G73 G74``,
  ``G80``, ``G98/G99``, ``G40``/``G41 D``/``G42 D`` (cutter_compensation where the side
  changes), ``G43 H``/``G49``, ``G54``-``G59`` (work_offset where
  the offset changes), ``M7 M8 M9``, ``M2 M30``,
  ``M0``/``M1`` (program_stop, optional_stop: after the block's motion, as RS274 runs them):
  as the FreeCAD reader reads them; a block of axis words alone repeats the motion
  (or the canned cycle) in force.
* ``G61``, ``G61.1``, ``G64 [P Q]``: the path-control mode, a fact (input_modes
  path_mode, path_tolerance) that posts may echo.
* Refused at the line, with the reason: ``G41.1``/``G42.1`` (a diameter in the
  program), ``G54.1`` and ``G59.1-G59.3`` (further work offsets), ``G53``,
  ``G28``, ``G30`` (moves in machine coordinates, which the CL has none of), ``G92``,
  ``#`` parameters and ``[…]``
  expressions (the CL needs every value written out), ``O`` words (subprograms,
  loops, program numbers), block delete ``/``, and every word this list does not name.

Detection is by evidence: a file goes to this reader when its first lines are all
word-address blocks and not every one fits the FreeCAD reader (a ``T1 M6``, an ``S``
or ``F`` alone); the user may also name it with ``--format gcode``.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Iterator
from decimal import Decimal, InvalidOperation

from postdsl.cl.freecad import (
    _DRILLS,
    _NUMBER,
    _Command,
    _normal_name,
    _shorten,
    _State,
    read_freecad,
)
from postdsl.cl.model import CLCommand
from postdsl.cl.native import MoveSink
from postdsl.cl.record_log import RecordLog
from postdsl.errors import CLError, Location

__all__ = ["looks_like_gcode", "read_gcode", "starts_block"]

_WORD = re.compile(rf"([A-Za-z])[ \t]*({_NUMBER})")
#: a line as G-code starts one: a block number, a comment, ``%``, or a word (with the
#: words this reader refuses, so that their files are refused at the line)
_LINE = re.compile(r"\s*(?:[Nn]\d+\s*)?(?:$|[(;%/#]|[A-Za-z]\s*[-+\d.#\[])")

_MOTIONS = {"G0", "G1", "G2", "G3"}
_CYCLES = set(_DRILLS)
#: lengths converted from inches: the axes, the arc centre, the cycles' R and peck Q
_LENGTHS = frozenset("XYZIJKRQ")
_INCH = Decimal("25.4")

_COMPENSATION = ("dynamic cutter compensation ({code}: a diameter in the program) is not "
                 "read: the CL's cutter_compensation takes the control's register (G41/G42 "
                 "D..)")
_MACHINE = ("{code} moves in machine coordinates ({what}), which the CL carries only as a "
            "retract of Z alone (G28 G91 Z0, G53 G0 Z..); the post writes its own "
            "retracts at tool changes and at the program end: remove the block")
_REFUSED_G: dict[str, str] = {
    "G41.1": _COMPENSATION.format(code="G41.1"),
    "G42.1": _COMPENSATION.format(code="G42.1"),
    "G30": _MACHINE.format(code="G30", what="a return to the second reference point"),
    "G93": "inverse-time feed (G93) is not read: its F is one over the move's time, which "
           "depends on the move's length and on the machine's kinematics; only a post knows "
           "them and writes G93 (a rotary post's inverse-time moves): post the program in "
           "G94 or G95",
    "G92": "G92 shifts the program's coordinate system: the CL's points would no longer "
           "be where the part is; set the work offset on the machine instead",
    "G10": "G10 writes the control's offset tables, which the CL does not carry",
    "G43.1": "dynamic tool length offset (G43.1) is not read: the post writes the loaded "
             "tool's own length offset",
    "G33": "threading (G33) has no CL word", "G33.1": "rigid tapping by G33.1 has no CL "
    "word: write it as the CAM's tapping cycle (G84)", "G76": "threading (G76) has no CL word",
    "G38.2": "probing (G38.2) is written as the post's custom cycles, not read from G-code",
    "G20": "", "G21": "",  # read by this module, never handed on
    "G90.1": "absolute arc centres (G90.1) are not read: the reader takes I J K relative "
             "to the start point (G91.1); post the program with incremental centres",
    **{f"G59.{n}": f"work offset G59.{n} is not read from G-code: write it as a native "
       f"work_offset record (7 and up), which each post maps to its control"
       for n in (1, 2, 3)},
    "G54.1": "extended work offsets (G54.1 P) are not read from G-code: write them as "
             "native work_offset records (7 and up), which each post maps to its control",
}
_REFUSED_M: dict[str, str] = {
    "M60": "a pallet change (M60) has no CL word",
}
#: the G and M codes a block may hand on, in RS274's order of execution (after F, S, T)
_ORDER = ["M6", "M3", "M4", "M5", "M7", "M8", "M9", "G4", "G17", "G18", "G19", "G40", "G41",
          "G42",
          "G43", "G49", "G54", "G55", "G56", "G57", "G58", "G59", "G61", "G61.1", "G64", "G90",
          "G91", "G91.1", "G94", "G98", "G99"]
#: the stops, last in RS274's order of execution (after the motion of their block)
_ENDS = ("M0", "M1", "M2", "M30")


def looks_like_gcode(lines: list[str]) -> bool:
    """Detector: every sampled line is a word-address block, a comment or ``%``."""
    return bool(lines) and all(starts_block(line) for line in lines)


def starts_block(line: str) -> bool:
    """One line as RS274 G-code starts one."""
    return _LINE.match(line) is not None


def read_gcode(lines: Iterable[str], file: str = "<cl>", sink: MoveSink | None = None,
               log: RecordLog | None = None) -> Iterator[CLCommand]:
    """Stream CL commands from plain RS274 G-code; every refusal names file:line."""
    return read_freecad(lines, file, sink=sink, log=log, block_reader=read_block)


def _comments(text: str, where: Location) -> tuple[str, list[str]]:
    """The block's code without its comments, and the comments' texts."""
    code: list[str] = []
    comments: list[str] = []
    index, length = 0, len(text)
    while index < length:
        char = text[index]
        if char == "(":
            close = text.find(")", index + 1)
            inner = text[index + 1:close] if close >= 0 else ""
            if close < 0 or "(" in inner:
                raise CLError(f"a comment is not closed, or holds another '(': "
                              f"{_shorten(text)}", where)
            comments.append(inner.strip())
            index = close + 1
        elif char == ";":
            comments.append(text[index + 1:].strip())
            break
        else:
            code.append(char)
            index += 1
    return "".join(code), comments


def read_block(state: _State, text: str, number: int) -> list[_Command]:
    """One block's commands, in RS274's order of execution; a located error for what the
    CL cannot carry."""
    file = state.file
    where = Location(file, number)
    code, comments = _comments(text, where)
    body = code.strip()
    out = [_Command("(", {}, number, comment) for comment in comments]
    if not body:
        return out
    if body.startswith("/"):
        raise CLError(f"block delete ('/') is not read: whether the block runs depends on a "
                      f"switch on the control, which the CL cannot know: {_shorten(text)}",
                      where)
    if "#" in body or "[" in body:
        raise CLError(f"parameters ('#') and expressions ('[…]') are not read: the CL needs "
                      f"every value written out (post the program from the CAM without "
                      f"them): {_shorten(text)}", where)
    g: list[str] = []
    m: list[str] = []
    raw: dict[str, str] = {}
    position, length, first = 0, len(code), True
    while position < length:
        if code[position] in " \t":
            position += 1
            continue
        word = _WORD.match(code, position)
        if word is None:
            rest = code[position:].strip()
            raise CLError(f"cannot read '{_shorten(rest, 20)}' (expected words like X12.5): "
                          f"{_shorten(text)}", Location(file, number, position + 1))
        letter, value = word.group(1).upper(), word.group(2)
        position = word.end()
        if letter == "N" and first:
            first = False
            continue
        first = False
        if letter == "O":
            raise CLError(f"O words (subprograms, loops, program numbers) are not read: the "
                          f"CL needs the program written out: {_shorten(text)}", where)
        if letter == "G":
            g.append(_normal_name("G" + value, number, file, text))
        elif letter == "M":
            m.append(_normal_name("M" + value, number, file, text))
        elif letter in raw:
            raise CLError(f"two {letter} words in one block: {_shorten(text)}", where)
        else:
            raw[letter] = value
    for name in g:
        if _REFUSED_G.get(name):
            raise CLError(f"{_REFUSED_G[name]}: {_shorten(text)}", where)
    for name in m:
        if name in _REFUSED_M:
            raise CLError(f"{_REFUSED_M[name]}: {_shorten(text)}", where)
    if "G21" in g:
        state.inch = False
    if "G20" in g:  # RS274: the units are set before any value of the block is used
        state.inch = True
    if "G94" in g and "G95" in g:
        raise CLError(f"G94 and G95 in one block: {_shorten(text)}", where)
    if ("G95" in g) != state.per_rev and ("G95" in g or "G94" in g):
        # RS274: the feed mode is set before F; the F in force was in the other mode, so
        # the next cutting move needs its own (refused at its line, never reinterpreted)
        state.per_rev = "G95" in g
        state.per_rev_feed = None
        state.feed = None
        state.feed_unsent = False
    values = {letter: _value(state, letter, text, number) for letter, text in raw.items()}
    motion = [name for name in g if name in _MOTIONS or name in _CYCLES or name == "G80"]
    if len(motion) == 2 and "G80" in motion and not any(
            letter in raw for letter in "XYZIJKRPQ"):
        # "G00 … G80" (Vectric's safe-start block, which Mach3 takes): the cycle is
        # cancelled and the motion mode set, as the two blocks G80 and G0 would
        g.remove("G80")
        motion.remove("G80")
        if state.cycle is not None:
            out.append(_Command("G80", {}, number, text))
    if len(motion) > 1:
        raise CLError(f"two motion codes ({' '.join(motion)}) in one block: "
                      f"{_shorten(text)}", where)
    unknown = [name for name in (*g, *m) if name not in _ORDER and name not in _ENDS
               and name not in motion and name not in ("G20", "G21", "G28", "G53", "G95")]
    if unknown:
        raise CLError(f"{unknown[0]} is not a code this reader knows (RS274 G-code: see the "
                      f"docs, reference/cl-input.md): {_shorten(text)}", where)
    # A B C: rotary words in degrees (never scaled in inches), read on G0/G1 only
    axes = {letter: values.pop(letter) for letter in "XYZIJKRPQABC" if letter in values}
    # P: G4's time, else G64's tolerance, else the cycle's dwell
    special: dict[str, dict[str, float]] = {}
    for name, letters in (("G4", "P"), ("G64", "PQ")):
        if name in g:
            special[name] = {letter: axes.pop(letter) for letter in letters if letter in axes}
    if "P" in special.get("G64", {}):  # G64's P is a length (G4's is seconds)
        special["G64"]["P"] = _value(state, "R", raw["P"], number)
    if "G43" in g and "H" in values:
        special["G43"] = {"H": values.pop("H")}
    for name in ("G41", "G42"):  # D: the radius register of the compensation
        if name in g and "D" in values:
            special[name] = {"D": values.pop("D")}
    if "G28" in g or "G53" in g:
        return out + _machine_retract(state, g, m, axes, values, raw, text, number)
    move: str | None = motion[0] if motion else None
    if move is None and any(letter in axes for letter in "XYZIJKABC"):
        move = state.modal or (state.cycle.key[0] if state.cycle is not None else None)  # type: ignore[assignment]  # a motion word (str) or None
        if move is None:
            raise CLError(f"axis words without a motion mode (no G0, G1, G2, G3 or cycle in "
                          f"force): {_shorten(text)}", where)
    if "R" in axes and move in ("G2", "G3"):
        axes = _centre_from_radius(state, move, g, axes, text, number)
    bare = move in _MOTIONS and not axes
    feed = values.pop("F", None)
    if "F" in raw and (move is None or move == "G80" or bare):
        out.append(_Command("F", {"F": feed}, number, text))  # type: ignore[dict-item]  # F in raw: its value was read
        feed = None
    speed = values.pop("S", None)
    spindle = next((name for name in ("M3", "M4") if name in m), None)
    if speed is not None and spindle is None:
        out.append(_Command("S", {"S": speed}, number, text))
    tool = values.pop("T", None)
    if tool is not None and "M6" not in m:
        out.append(_Command("T", {"T": tool}, number, text))
    if values:
        letter = sorted(values)[0]
        raise CLError(f"{letter} is not a word of this block (it has "
                      f"{' '.join([*g, *m]) or 'no command'}): {_shorten(text)}", where)
    # the machine functions in RS274's order, then the modal G codes as written (their
    # order does not change what they mean), then the motion
    functions = [name for name in _ORDER if name in m]
    for name in functions + [name for name in g if name in _ORDER]:
        args = dict(special.get(name, {}))
        if name == "M6" and tool is not None:
            args["T"] = tool
        elif name == spindle and speed is not None:
            args["S"] = speed
        out.append(_Command(name, args, number, text))
    if bare:  # a motion word alone sets the mode for the blocks after it
        out.append(_Command("=" + move, {}, number, text))  # type: ignore[operator]  # bare: move is a motion word
    elif move is not None:
        args = dict(axes)
        if feed is not None:
            args["F"] = feed
        out.append(_Command(move, args, number, text))
    elif axes:
        letter = sorted(axes)[0]
        raise CLError(f"{letter} is not a word of this block (it has "
                      f"{' '.join([*g, *m]) or 'no command'}): {_shorten(text)}", where)
    out.extend(_Command(name, {}, number, text) for name in m if name in _ENDS)
    return out


def _machine_retract(state: _State, g: list[str], m: list[str], axes: dict[str, float],
                     values: dict[str, float], raw: dict[str, str], text: str,
                     number: int) -> list[_Command]:
    """``G28 G91 Z0`` (Z to the reference point, through where it stands) or ``G53 G0 Z..``
    (Z to a machine position): a machine_retract; any other G28 or G53 is refused."""
    where = Location(state.file, number)
    code = "G28" if "G28" in g else "G53"
    others = [name for name in (*g, *m) if name not in (code, "G0", "G90", "G91")]
    if others or values or set(axes) != {"Z"}:
        what = ("X or Y to the reference point" if code == "G28" else
                "X or Y in machine coordinates") if set(axes) - {"Z"} else "other words"
        raise CLError(f"{_MACHINE.format(code=code, what=what)}: {_shorten(text)}", where)
    incremental = "G91" in g or (state.incremental and "G90" not in g)
    out = [_Command(name, {}, number, text) for name in ("G90", "G91") if name in g]
    if code == "G28":
        through_here = axes["Z"] == 0 if incremental else axes["Z"] == state.pos[2]
        if not through_here:
            raise CLError(f"G28 through another Z than the tool's own (a move before the "
                          f"return, then the return): write the move, then G28 G91 Z0: "
                          f"{_shorten(text)}", where)
    elif "G0" not in g or incremental:
        raise CLError(f"G53 is read only as a rapid to an absolute machine Z (G53 G0 Z..): "
                      f"{_shorten(text)}", where)
    out.append(_Command(code, {"Z": axes["Z"]}, number, text))
    return out


#: the arc plane's axes in RS274's order (first, second), with their centre words
_PLANE_AXES = {"xy": ((0, "I"), (1, "J")), "zx": ((2, "K"), (0, "I")),
               "yz": ((1, "J"), (2, "K"))}
#: RS274's tolerance on a radius too short for its chord (NCE_ARC_RADIUS_TOO_SMALL_…), mm
_RADIUS_TOLERANCE = 0.0001


def _centre_from_radius(state: _State, move: str, g: list[str], axes: dict[str, float],
                        text: str, number: int) -> dict[str, float]:
    """An arc in radius form (``G2 X.. Y.. R..``) as RS274 defines it, with its centre
    written as I J K: on the side of the chord the direction says, the shorter arc for
    R > 0 and the longer for R < 0.  The centre is computed (a square root), not read,
    so it is as exact as a float; rs274 computes the same point."""
    where = Location(state.file, number)
    if any(letter in axes for letter in "IJK"):
        raise CLError(f"an arc with both R and I J K: RS274 takes one form: "
                      f"{_shorten(text)}", where)
    plane = "xy" if "G17" in g else "zx" if "G18" in g else "yz" if "G19" in g \
        else state.plane
    (first, first_word), (second, second_word) = _PLANE_AXES[plane]
    incremental = "G91" in g or (state.incremental and "G90" not in g)
    ends: list[float] = []
    starts: list[float] = []
    for index in (first, second):
        start = state.pos[index]
        if start is None:
            raise CLError(f"{move} before the tool position is known (an arc's centre "
                          f"follows from its start point): {_shorten(text)}", where)
        letter = "XYZ"[index]
        value = axes.get(letter, 0.0 if incremental else start)
        ends.append(start + value if incremental and letter in axes else value)
        starts.append(start)
    radius = axes["R"]
    chord = (ends[0] - starts[0], ends[1] - starts[1])
    half = math.hypot(*chord) / 2
    tolerance = _RADIUS_TOLERANCE * (float(_INCH) if state.inch else 1.0)
    if half == 0:
        raise CLError(f"an arc in radius form (R) with its end point at its start point: "
                      f"R says no centre (a full circle needs I J K): {_shorten(text)}", where)
    if half - abs(radius) > tolerance:
        raise CLError(f"the radius R{abs(radius):g} is too short for the arc's chord of "
                      f"{2 * half:g} (RS274 refuses it): {_shorten(text)}", where)
    rise = math.sqrt(max(radius * radius - half * half, 0.0))
    # the centre is right of the chord (start to end) for G2 with R > 0, left for G3;
    # a negative R takes the other side (the arc of more than 180 degrees)
    side = (-1.0 if move == "G2" else 1.0) * (1.0 if radius > 0 else -1.0)
    unit = (chord[0] / (2 * half), chord[1] / (2 * half))
    centre = (starts[0] + chord[0] / 2 - side * rise * unit[1],
              starts[1] + chord[1] / 2 + side * rise * unit[0])
    out = {letter: value for letter, value in axes.items() if letter != "R"}
    out[first_word] = centre[0] - starts[0]
    out[second_word] = centre[1] - starts[1]
    return out


def _value(state: _State, letter: str, text: str, number: int) -> float:
    """A word's value in the CL's units: a length or feed in inches times 25.4, exactly."""
    try:
        exact = Decimal(text)
    except InvalidOperation:  # pragma: no cover - the word pattern reads decimals only
        exact = Decimal("nan")
    if state.inch and (letter in _LENGTHS or letter == "F"):
        exact *= _INCH
    value = float(exact)
    if not math.isfinite(value):
        raise CLError(f"{letter} is not a finite number: {_shorten(text)}",
                      Location(state.file, number))
    return value
