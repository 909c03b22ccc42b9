"""What each control accepts in its comments and program names: facts from its manual.

One table, read by both sides of the project: the control models (which read a
comment as the control does) and the compiler (which escapes, or refuses, CL text
that a post writes into a comment or a program name).  A fact lives here once, so
the post that writes a comment and the model that reads it cannot disagree.

The module imports nothing of postdsl: the compiler may use it without reaching
the control models.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field


@dataclass(frozen=True)
class CommentSyntax:
    """How a control writes a comment, and what text inside one would break out of it.

    ``opens``/``closes``: the delimiters of an inline comment (``"("``/``")"``), or
    ``closes`` empty for a comment that runs to the end of the line (``";"``).
    ``line_comment``: a character that starts a comment running to the end of the
    line outside any other comment, or None.  ``breaks``: characters that end the
    comment early, start a nested one, or mean something to the control wherever
    they stand (``%`` on a Fanuc tape), each with the character that stands in
    for it in a comment written from CL text.  ``starts_block``: see the field.
    """

    opens: str
    closes: str
    line_comment: str | None
    breaks: dict[str, str] = field(default_factory=dict)
    #: texts that make a whole block a comment when the block starts with them (after
    #: its number): the rest of the block is text the control shows, not words
    starts_block: tuple[str, ...] = ()
    #: a comment whose text starts so is a command to the control, not a comment
    #: (LinuxCNC's ``(MSG,…)``, ``(LOGOPEN,path)``, ``(ABORT,…)``): CL text that starts
    #: so is written after ``_``, which the control reads as an ordinary comment
    active: re.Pattern[str] | None = None

    def escape(self, text: str) -> str:
        """``text`` as it may stand inside one of this control's comments."""
        for bad, good in self.breaks.items():
            if bad in text:
                text = text.replace(bad, good)
        if self.active is not None and self.active.match(text):
            text = "_" + text
        return text.replace("\r", " ").replace("\n", " ")

    def safe(self, text: str) -> bool:
        """Whether ``text`` can stand inside a comment unchanged."""
        return not any(bad in text for bad in self.breaks) and "\n" not in text \
            and "\r" not in text and (self.active is None or not self.active.match(text))


@dataclass(frozen=True)
class ProgramNames:
    """The characters a control accepts in a program's name, and how many."""

    allowed: re.Pattern[str]
    max_length: int
    what: str

    def problem(self, name: str) -> str | None:
        """Why ``name`` is not a program name this control loads; None when it is one."""
        if len(name) > self.max_length:
            return f"a program name has at most {self.max_length} characters ({self.what})"
        bad = sorted({c for c in name if not self.allowed.fullmatch(c)})
        if bad:
            shown = " ".join(repr(c) for c in bad)
            return f"{shown} cannot stand in a program name ({self.what})"
        return None


_PARENTHESES = {"(": "[", ")": "]"}

#: LinuxCNC G-code reference, "Comments" ("Messages", "Probe Logging", "Logging",
#: "Debug Messages", "Print Messages") and the Python plugins' ``(PY,…)``: a comment
#: that starts with one of these words, after blanks and in any case, acts on the
#: machine -- ``(ABORT,…)`` ends the program, ``(LOGOPEN,path)`` writes a file (rs274
#: runs both).  A word followed by anything but ``,`` or ``)`` is an ordinary comment;
#: the pattern is wider (any following non-letter) so no spelling slips through.
_LINUXCNC_ACTIVE = re.compile(
    r"\s*(?:MSG|DEBUG|PRINT|LOG|LOGOPEN|LOGAPPEND|LOGCLOSE|PROBEOPEN|PROBECLOSE|ABORT|PY)"
    r"(?![A-Z0-9_])", re.IGNORECASE)
#: GRBL 1.1 (grbl/protocol.c, "report_feedback_message"): ``(MSG,…)`` is shown as a message
_GRBL_ACTIVE = re.compile(r"\s*MSG(?![A-Z0-9_])", re.IGNORECASE)

#: control name (a post's ``machine.control``) -> its comment syntax
COMMENTS: dict[str, CommentSyntax] = {
    # Fanuc 0i-MD (B-64304EN, "Tape format": control-out "(" and control-in ")"; a
    # comment cannot nest; "%" is the end-of-record code wherever it stands on tape)
    "fanuc-0i": CommentSyntax("(", ")", None, {**_PARENTHESES, "%": "pct"}),
    # LinuxCNC G-code reference, "Comments": "(" … ")" ends at the first ")", a "(" inside
    # is an error ("nested comment"); ";" to the end of the line outside parentheses
    "linuxcnc": CommentSyntax("(", ")", ";", dict(_PARENTHESES), active=_LINUXCNC_ACTIVE),
    # GRBL 1.1 (grbl/protocol.c): "(" ... ")" or ";" to the end of the line outside them; inside
    # a comment every character to ")" or the end of the line is thrown away (no nested-
    # comment error); "%" is not supported outside a comment.  ")" ends it early, and "(" is
    # escaped too so the text reads the same on LinuxCNC
    "grbl-1.1": CommentSyntax("(", ")", ";", dict(_PARENTHESES), active=_GRBL_ACTIVE),
    # Sinumerik 828D (programming manual, "Comments"): ";" to the end of the block;
    # nothing inside breaks out of it but the end of the line
    "sinumerik-828d": CommentSyntax(";", "", ";"),
    # Acramatic 2100: ";" to the end of the line
    "acramatic-2100": CommentSyntax(";", "", ";"),
    # Heidenhain TNC 640 Klartext: ";" to the end of the block; a block starting with
    # "*" is a structure block ("* - TEXT"), its text shown in the program's outline;
    # a "~" ends a block that goes on in the next line (a cycle's Q parameters), so a
    # comment ending in one would swallow the next block
    "heidenhain-tnc640": CommentSyntax(";", "", ";", {"~": "-"}, starts_block=("*",)),
    # hmCNC: "//" to the end of the line
    "hmcnc": CommentSyntax("//", "", "//"),
}

@dataclass(frozen=True)
class NumberSyntax:
    """What a number written without a decimal point means to a control.

    Unless the machine is set to calculator input (``machine: calculator_input:
    true``), a number without a point at one of ``letters`` is a count of
    ``increment`` (mm, or seconds for a dwell's X): ``X10`` is 0.010 mm.
    """

    letters: frozenset[str]
    increment: float
    what: str

    def pointless(self, text: str) -> bool:
        """Whether a written number (``"10"``, ``"-2.5"``) has no decimal point."""
        return "." not in text


#: control name -> how it reads a number without a point (only controls where it differs
#: from the number written)
NUMBERS: dict[str, NumberSyntax] = {
    # Fanuc 0i-MD (B-64484EN, "Decimal point programming"; parameter 3401#0 DPI): with
    # DPI = 0, the default, a number without a point at an address that takes one is in
    # the least input increment, 0.001 mm (IS-B): X1000 is 1 mm.  The addresses: the
    # axes (rotary A B C too: 0.001 deg), I J K, R, Q (and X of G04, 0.001 s).  F is read
    # apart (mm/min in G94).
    "fanuc-0i": NumberSyntax(frozenset("XYZIJKRQABC"), 0.001,
                             "Fanuc parameter 3401#0 = 0: a number without a point is in "
                             "0.001 mm"),
}

#: control name -> the names it loads a program under
PROGRAM_NAMES: dict[str, ProgramNames] = {
    # TNC 640 user's manual, "File names": letters, digits and _ - . only (no spaces,
    # no ; ( ) % ...), at most 255 characters with the extension
    "heidenhain-tnc640": ProgramNames(re.compile(r"[A-Za-z0-9_\-.]"), 251,
                                      "TNC 640: letters, digits, _ - and . only"),
    # Sinumerik 828D: program names of letters, digits and _ (the first two letters)
    "sinumerik-828d": ProgramNames(re.compile(r"[A-Za-z0-9_]"), 24,
                                   "Sinumerik: letters, digits and _ only"),
}


def comment_syntax(control: str | None) -> CommentSyntax | None:
    """The comment syntax of a control, None for a post that names no known control."""
    return COMMENTS.get(control) if control is not None else None


def number_syntax(control: str | None) -> NumberSyntax | None:
    """How a control reads a number without a point; None where it is the number written."""
    return NUMBERS.get(control) if control is not None else None


def program_names(control: str | None) -> ProgramNames | None:
    """The program-name rules of a control, None where the control states none here."""
    return PROGRAM_NAMES.get(control) if control is not None else None


__all__ = ["COMMENTS", "NUMBERS", "PROGRAM_NAMES", "CommentSyntax", "NumberSyntax",
           "ProgramNames", "comment_syntax", "number_syntax", "program_names"]
