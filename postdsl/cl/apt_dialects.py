"""What each CAM family writes in its APT CL file, and what the reader does with each record.

APT (ISO 4343) is one language with many dialects: every CAM system adds
records of its own (NX's ``TLDATA``, SolidWorks CAM's ``CSI_SET_*``, Creo's
``MACHIN``) and writes the common ones its own way.  Each family is a table
here -- data, not special cases in the reader -- listing every record it
writes with one of three rules:

* ``read``: the record means something the CL carries; the reader's handler
  of that name turns it into CL commands (or state for later ones).
* ``ignore``: the record only describes display or CAM bookkeeping (colours,
  tolerances, the tool's flute length): it cannot change what the machine does,
  so it is read and dropped -- by this rule, never by accident.
* ``refuse``: the record changes the motion in a way no bundled post can
  honour (5-axis, cutter compensation on a centre-line path, a program stop):
  posting without it would cut something else, so the file is refused with
  the record, its line and the reason.

A file's dialect is decided by evidence: the first record (or ``$$`` comment)
that only one family writes.  Until then the file reads as plain ISO 4343;
after it, a record another family writes is refused (a file mixing two
dialects was not written by a CAM system).  Records the table does not list
are refused as unknown.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

__all__ = ["DIALECTS", "ISO", "Dialect", "Rule", "dialect_of_comment", "dialect_of_record"]


@dataclass(frozen=True)
class Rule:
    """What the reader does with one record: ``read`` (by ``handler``), ``ignore`` or ``refuse``."""

    action: str
    why: str
    #: the reader's handler for a ``read`` record (another record's, when the dialect
    #: spells an ISO record differently: SolidWorks CAM's UNIT is UNITS)
    handler: str = ""


def read(why: str, handler: str = "") -> Rule:
    return Rule("read", why, handler)


def ignore(why: str) -> Rule:
    return Rule("ignore", why)


def refuse(why: str) -> Rule:
    return Rule("refuse", why)


@dataclass(frozen=True)
class Dialect:
    """One CAM family: its name, the evidence that a file is its, and its records."""

    title: str
    #: record words only this family writes: one of them decides the dialect
    evidence: tuple[str, ...]
    #: ``$$`` comments only this family writes (a pattern on the comment's text)
    comment_evidence: str | None
    records: dict[str, Rule] = field(default_factory=dict)
    #: whether the keyword form of CYCLE (FEDTO, RAPTO, RTRCTO…) is read: only where real
    #: files show what its lengths are measured from (NX writes FEDTO as a negative
    #: value and RTRCTO,AUTO: another convention, refused rather than guessed)
    keyword_cycles: bool = False


#: the ISO 4343 records every family writes (see the reader's module docstring for each)
ISO: dict[str, Rule] = {
    "PARTNO": read("the program name (and number, from a first word O<digits>)"),
    "UNITS": read("MM or INCHES: inch files are converted to mm"),
    "PPRINT": read("an operator comment"),
    "LOADTL": read("tool change"),
    "CUTTER": read("diameter and corner radius of the tool"),
    "SPINDL": read("spindle on (speed, direction) or off"),
    "COOLNT": read("coolant on (flood, mist, through) or off"),
    "FEDRAT": read("feed per minute for the following moves"),
    "RAPID": read("the next GOTO is a rapid move"),
    "GOTO": read("move to a point (a tool axis other than +Z is refused)"),
    "FROM": read("the start point (no motion)"),
    "CIRCLE": read("the arc the next GOTO follows"),
    "INDIRV": read("the start direction of the next TLON,GOFWD arc"),
    "TLON,GOFWD": read("an arc along a circle up to a line"),
    "MOVARC": read("an arc of a given angle"),
    "DELAY": read("dwell for the given seconds"),
    "CYCLE": read("drilling cycles (positional or keyword form) and CYCLE/OFF"),
    "END": read("end of the program (program_end)"),
    "FINI": read("end of the CL file (program_end, once)"),
    "MULTAX": read("multi-axis GOTOs follow: read, since every GOTO's tool axis is checked "
                   "to be +Z (5-axis moves are refused there)"),
    "TLAXIS": read("the tool axis: +Z is accepted, any other axis is refused (5-axis)"),
    "CUTCOM": read("cutter compensation: LEFT, RIGHT, OFF (with ON, XYPLAN, a register) "
                   "as cutter_compensation, which the post's declared mode gives a meaning"),
    "INTOL": ignore("the CAM's inner tolerance for the path: bookkeeping"),
    "OUTTOL": ignore("the CAM's outer tolerance for the path: bookkeeping"),
    "TOLER": ignore("the CAM's tolerance for the path: bookkeeping"),
    "STOP": read("a program stop (M0): program_stop"),
    "OPSTOP": read("an optional stop (M1): optional_stop"),
}

_MACHIN = ignore("names the post-processor or machine the CAM setup had in mind: "
                 "bookkeeping, since the machine is the post's")
_TOOL_LOAD = read("LOAD/TOOL,n[,ADJUST,h]: tool change, as LOADTL", "load")
_TOOL_SELECT = ignore("SELECT/TOOL,n pre-selects the next tool in the magazine: it moves no "
                      "axis, and the post selects tools itself")

DIALECTS: dict[str, Dialect] = {
    "iso": Dialect("ISO 4343 APT", (), None, dict(ISO)),
    "solidworks-cam": Dialect(
        "SolidWorks CAM / CAMWorks",
        ("UNIT", "CSI_SET_FLUTE_LENGTH", "CSI_SET_EXTENSION_LENGTH", "TRNTYP", "CSYS"), None,
        {**ISO,
         "UNIT": read("UNIT/MM or UNIT/INCHES, as UNITS", "units"),
         "LOAD": _TOOL_LOAD,
         "SELECT": _TOOL_SELECT,
         "INSERT": read("text the CAM passes on (tool holder, stock size): read as a "
                        "comment; an INSERT that is a command (STOP, a G or M code) is "
                        "refused: the CL cannot carry it and must not drop it", "insert"),
         "CSI_SET_FLUTE_LENGTH": ignore("the tool's flute length: tool description"),
         "CSI_SET_EXTENSION_LENGTH": ignore("the tool's extension length: tool description"),
         "TRNTYP": read("TRNTYP/WORLD,0,0,0 (no transformation) is accepted; any other "
                        "transformation moves the part and is refused"),
         "CSYS": read("the identity coordinate system is accepted; any other rotates or "
                      "moves the part and is refused")},
        keyword_cycles=True),
    "creo": Dialect(
        "Creo / Pro/ENGINEER (Pro/CLfile)", (), r"\*\s*Pro/CLfile|->",
        {**ISO, "MACHIN": _MACHIN}, keyword_cycles=True),
    "nx": Dialect(
        "NX (CLSF)", ("TOOL PATH", "TLDATA", "MSYS", "PAINT", "END-OF-PATH", "GOHOME"), None,
        {**ISO,
         "TOOL PATH": ignore("the operation header (operation and tool names); the tool "
                             "itself comes with LOAD/TOOL"),
         "TLDATA": read("the tool's geometry (MILL: diameter, corner radius) for the next "
                        "LOAD/TOOL, as CUTTER"),
         "MSYS": read("the machine coordinate system the GOTOs after it are given in: "
                      "another than the identity is a tilted plane (a work_plane record, "
                      "3+2), the identity after one its reset; a three-axis post refuses "
                      "the plane"),
         "PAINT": ignore("display colours and speed of the CAM's path preview"),
         "END-OF-PATH": read("the end of an operation's path; as the last record it ends "
                             "the program (NX writes no FINI)", "end_of_path"),
         "GOHOME": read("GOHOME/x,y,z: the return move to the home point, at rapid, as "
                        "NX's posts write it"),
         "LOAD": _TOOL_LOAD,
         "SELECT": _TOOL_SELECT}),
    "catia": Dialect(
        "CATIA V5 (APT source)", ("TPRINT",), r"\*\s*CATIA",
        {**ISO,
         "TPRINT": ignore("the tool's description text"),
         "TOOLNO": ignore("the tool's number and geometry for the CAM's tool list; the tool "
                          "itself comes with LOADTL and CUTTER")}),
    "fusion": Dialect(
        "Autodesk Fusion / HSMWorks (Common ISO 4343 APT post)", ("MODE",), None,
        {**ISO,
         "MACHIN": _MACHIN,
         "MODE": read("MODE/MILL is accepted; a turning program (MODE/TURN) is refused")}),
}


def dialect_of_record(word: str) -> str | None:
    """The dialect a record word is evidence of, if only one family writes it."""
    return _EVIDENCE.get(word)


def dialect_of_comment(text: str) -> str | None:
    """The dialect a ``$$`` comment is evidence of (Creo's ``$$*  Pro/CLfile``…)."""
    for name, pattern in _COMMENT_EVIDENCE:
        if pattern.match(text):
            return name
    return None


_EVIDENCE = {word: name for name, dialect in DIALECTS.items() for word in dialect.evidence}
_COMMENT_EVIDENCE = [(name, re.compile(dialect.comment_evidence))
                     for name, dialect in DIALECTS.items() if dialect.comment_evidence]
