"""The CL vocabulary: every cutter-location command postdsl understands.

CL readers (native, APT, FreeCAD) produce these records; the engine maps each
one to the post's table of the same name.  The names follow the commands of
Autodesk's Post Processor Utility so that a technologist finds "Deep Drill"
as ``deep_drill``.

A record's fields are also the *parameters* a post can print or test: the
engine keeps one flat table of the latest value of every field, as PPU does,
so a drilling block can print the spindle speed set two commands earlier.
Field names are therefore unique across the vocabulary unless they mean the
same thing (``x`` of a rapid and of a hole).

This module is the single source of truth for the vocabulary: the native
format's JSON Schema (``schemas/cl.schema.json``) is generated from it, and
the post loader checks parameter and command names against it.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any, ClassVar, Final

#: Command groups, in the order editors list them.
GROUPS = ("program", "tool and spindle", "motion", "drilling", "probing", "other")

DRILL_SETUPS = (
    "single_peck",
    "deep_drill",
    "break_chip",
    "tapping",
    "rigid_tapping",
    "tapping_ccw",
    "rigid_tapping_ccw",
    "boring",
    "boring_spindle_stop",
    "fine_boring",
)


def param(
    default: Any = None,
    doc: str = "",
    *,
    choices: tuple[str, ...] | None = None,
    sticky: bool = False,
    unit: str = "",
) -> Any:
    """A CL field with the metadata the schema generator and editors need.

    ``sticky`` fields keep their previous value when a record omits them
    (an axis not named in a move has not moved).
    """
    return field(
        default=default,
        metadata={"doc": doc, "choices": choices, "sticky": sticky, "unit": unit},
    )


@dataclass(frozen=True, slots=True, kw_only=True)
class CLCommand:
    """Base of all CL records.  ``line`` is the 1-based source line (0 when made in code)."""

    name: ClassVar[str] = ""
    group: ClassVar[str] = "other"
    doc: ClassVar[str] = ""
    #: a record as the native format writes it, for the schema and the documentation
    example: ClassVar[dict[str, Any]] = {}

    line: int = field(default=0, compare=False)

    #: a record of facts about the input: a post without a table for it writes nothing
    #: (every other record needs its table, so that nothing the CL says is dropped)
    facts_only: ClassVar[bool] = False


# --- program -------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True, kw_only=True)
class ProgramStart(CLCommand):
    """The program's own data, for the header blocks a post writes before any motion."""

    name = "program_start"
    group = "program"
    doc = "Start of the program, with the program data the CAM system knows."
    example = {
        "cmd": "program_start",
        "program_name": "BP_Vagner",
        "project": "BP_Vsechny_cykly",
        "author": "Thinkpad",
        "stock_x": 9.99999999999999,
        "stock_y": 9.99999999999999,
        "stock_z": 50,
        "machining_time": 238,
    }

    program_name: str = param("", "name of the NC program")
    program_number: int | None = param(None, "program number (the O-number of many controls)")
    project: str = param("", "CAM project name")
    author: str = param("", "who or which computer created the program")
    units: str = param("mm", "units the part was programmed in (informational: CL lengths "
                       "are always mm)", choices=("mm", "inch"))
    stock_x: float | None = param(None, "stock size along X", unit="mm")
    stock_y: float | None = param(None, "stock size along Y", unit="mm")
    stock_z: float | None = param(None, "stock size along Z", unit="mm")
    machining_time: float | None = param(
        None, "estimated machining time; computed from the moves when absent", unit="s",
        sticky=True,
    )


class ProgramEnd(CLCommand):
    """The end of the CL, where a post writes its closing blocks."""

    __slots__ = ()  # no fields of its own: CLCommand's dataclass methods serve

    name = "program_end"
    group = "program"
    doc = "End of the program."
    example = {"cmd": "program_end"}


class ProgramStop(CLCommand):
    """A programmed stop: the control halts until the operator presses cycle start."""

    __slots__ = ()  # no fields of its own: CLCommand's dataclass methods serve

    name = "program_stop"
    group = "program"
    doc = (
        "Stop the program until the operator starts it again (RS274 M0, APT STOP): to "
        "check a part, turn it over, clear chips.  Nothing moves.  Whether the spindle "
        "and coolant stop with it is the control's (many controls' M0 stops both): a CL "
        "that cuts after a stop says spindle_on again.  A post without a table, or whose "
        "control has no stop, refuses it: the program would run on "
        "where the operator was meant to act."
    )
    example = {"cmd": "program_stop"}


class OptionalStop(CLCommand):
    """A stop the control makes only while its optional-stop switch is on."""

    __slots__ = ()  # no fields of its own: CLCommand's dataclass methods serve

    name = "optional_stop"
    group = "program"
    doc = (
        "Stop the program if the operator has switched optional stop on (RS274 M1, APT "
        "OPSTOP); otherwise run on.  Nothing moves.  A post whose control ignores M1 "
        "(GRBL 1.1) or has no stop refuses it."
    )
    example = {"cmd": "optional_stop"}


@dataclass(frozen=True, slots=True, kw_only=True)
class WorkOffset(CLCommand):
    """The work offset (fixture zero) the following moves are programmed in."""

    name = "work_offset"
    group = "program"
    doc = (
        "Select the work offset the following moves are programmed in: the control's "
        "work_offset_index-th settable zero.  1-6 are RS274's G54-G59 (1, G54, is in force "
        "before any work_offset record); beyond them each control numbers on in its own "
        "table: G54.1 P1-P48 are 7-54, G59.1-G59.3 7-9, a control whose settable offsets "
        "are G54-G57 and G505-G599 takes 1-4 and 5-99, a preset table's row is the number "
        "itself.  A post writes its control's word, or refuses a number its control lacks.  "
        "postdsl verify compares the offset in force at each cut with the CL's (the offset's "
        "value is on the machine, not in the program: verify compares in the part frame)."
    )
    example = {"cmd": "work_offset", "work_offset_index": 2}

    work_offset_index: int = param(1, "the work offset: 1-6 are G54-G59, higher numbers "
                                    "the control's further offsets")


@dataclass(frozen=True, slots=True, kw_only=True)
class WorkPlane(CLCommand):
    """A tilted working plane (3+2): the moves after it are three-axis moves in its frame."""

    name = "work_plane"
    group = "program"
    doc = (
        "Tilt the working plane (3+2 machining): the following moves, arcs and holes are "
        "programmed in a frame whose origin is (origin_x, origin_y, origin_z) and whose X "
        "and Z axes are the unit vectors x_axis_* and z_axis_* (at right angles), all in the "
        "part frame; Z is the tool axis, Y is Z x X.  work_plane: reset returns to the part "
        "frame (the fields are then left out).  A post writes its control's tilted-plane "
        "block from the derived angles plane_angle_1-3 (in the convention its "
        "machine.tilted_plane names) and cancels it at reset; a three-axis post refuses "
        "the record.  postdsl verify compares the frame in force at each cut (tool axis, "
        "plane axes and origin in the part frame) with the CL's."
    )
    example = {"cmd": "work_plane", "origin_x": 100, "origin_y": 0, "origin_z": 0,
               "x_axis_i": 0, "x_axis_j": 1, "x_axis_k": 0,
               "z_axis_i": 1, "z_axis_j": 0, "z_axis_k": 0}

    work_plane: str = param("tilted", "tilted: the plane the fields give; reset: back to "
                            "the part frame", choices=("tilted", "reset"))
    origin_x: float = param(0.0, "the plane's origin, X in the part frame", unit="mm")
    origin_y: float = param(0.0, "the plane's origin, Y in the part frame", unit="mm")
    origin_z: float = param(0.0, "the plane's origin, Z in the part frame", unit="mm")
    x_axis_i: float = param(1.0, "the plane's X axis, X component (unit vector)")
    x_axis_j: float = param(0.0, "the plane's X axis, Y component")
    x_axis_k: float = param(0.0, "the plane's X axis, Z component")
    z_axis_i: float = param(0.0, "the plane's Z axis (the tool axis), X component "
                            "(unit vector)")
    z_axis_j: float = param(0.0, "the plane's Z axis, Y component")
    z_axis_k: float = param(1.0, "the plane's Z axis, Z component")


@dataclass(frozen=True, slots=True, kw_only=True)
class CutterCompensation(CLCommand):
    """Cutter radius compensation on one side of the path, or off."""

    name = "cutter_compensation"
    group = "motion"
    doc = (
        "Cutter radius compensation from the next move on: the tool keeps to the left or "
        "right of the programmed path (RS274 G41/G42, APT CUTCOM/LEFT|RIGHT, TNC RL/RR), "
        "or runs on the path again (off: G40, R0).  A CL alone does not say what its path "
        "is, so the post's cutter_compensation mode declares it: off (refused), wear (the "
        "path is the tool centre; the control's radius register holds wear only) or "
        "control (the path is the part contour; the control offsets it by the tool's "
        "radius).  The next move must be a straight move in the plane: the control starts "
        "and ends compensation on it.  postdsl verify replays the control's offset path "
        "against the CL's path (control: the CL contour offset by half the CL tool "
        "diameter)."
    )
    example = {"cmd": "cutter_compensation", "compensation_side": "left"}

    compensation_side: str = param("off", "the tool's side of the path, looking along the "
                                   "motion", choices=("left", "right", "off"))
    compensation_register: int | None = param(None, "the control's radius register (D); "
                                              "none: the post's own, usually the tool's")


@dataclass(frozen=True, slots=True, kw_only=True)
class Operation(CLCommand):
    """Where a CAM toolpath starts: operation names for comments and operation-end events."""

    name = "operation"
    group = "program"
    doc = "Start of a CAM operation (toolpath); a boundary, usually writes nothing."
    example = {"cmd": "operation", "operation": "Pocket_Shape"}

    operation: str = param("", "operation (toolpath) name")


@dataclass(frozen=True, slots=True, kw_only=True)
class InputModes(CLCommand):
    """The input's modal words kept as facts, so a post can test or echo them."""

    name = "input_modes"
    group = "other"
    doc = (
        "Modal states the input program set, where it says them (G90/G91, G17/G18/G19 and "
        "G98/G99 in FreeCAD G-code): facts a post may test in conditions.  The CL never "
        "depends on them -- its coordinates are absolute, every arc carries its plane and "
        "every drilling setup its retract -- so a post without a table for this record "
        "writes nothing for it.  Each record gives the modes its input line set; the "
        "others keep their values (sticky), so 'distance_mode' in given says the line was "
        "a G90/G91, and a post may echo the very words the input wrote."
    )
    example = {"cmd": "input_modes", "distance_mode": "absolute", "active_plane": "xy"}
    facts_only = True

    distance_mode: str | None = param(
        None, "absolute (G90) or incremental (G91) coordinates in the input; the CL's "
        "stay absolute", choices=("absolute", "incremental"), sticky=True)
    active_plane: str | None = param(
        None, "the plane the input selected (G17 xy, G18 zx, G19 yz)",
        choices=("xy", "zx", "yz"), sticky=True)
    cycle_return: str | None = param(
        None, "the canned cycles' return level the input selected: initial (G98) or "
        "r_plane (G99); the drilling setups carry it too", choices=("initial", "r_plane"),
        sticky=True)
    path_mode: str | None = param(
        None, "the path-control mode the input selected: exact_stop (G61), exact_path "
        "(G61.1) or blend (G64, with path_tolerance when it gave P)",
        choices=("exact_stop", "exact_path", "blend"), sticky=True)
    path_tolerance: float | None = param(
        None, "the blending tolerance of G64 P (mm), when the input gave one", unit="mm")


@dataclass(frozen=True, slots=True, kw_only=True)
class Comment(CLCommand):
    """Operator text the CAM system wrote, for a post to pass on or drop."""

    name = "comment"
    group = "other"
    doc = "An operator comment."
    example = {"cmd": "comment", "comment": "T1: D16"}

    comment: str = param("", "comment text")


# --- tool and spindle -----------------------------------------------------------------------


@dataclass(frozen=True, slots=True, kw_only=True)
class ToolChange(CLCommand):
    """A tool call: its number and geometry, for the tool-change table and the tool list."""

    name = "tool_change"
    group = "tool and spindle"
    doc = "Load a tool into the spindle."
    example = {"cmd": "tool_change", "tool_number": 1, "tool_type": "drill", "tool_diameter": 8}

    tool_number: int = param(0, "tool (pocket) number")
    tool_type: str = param("", "tool type as the CAM names it (drill, tap, end mill, probe…)")
    tool_diameter: float = param(0.0, "tool diameter", unit="mm")
    tool_corner_radius: float = param(0.0, "tool corner radius", unit="mm")
    tool_name: str = param("", "tool name or description")


@dataclass(frozen=True, slots=True, kw_only=True)
class SpindleOn(CLCommand):
    """Spindle speed and direction, which a post writes with M3/M4 or keeps for a later block."""

    name = "spindle_on"
    group = "tool and spindle"
    doc = "Start the spindle."
    example = {"cmd": "spindle_on", "spindle_speed": 500, "spindle": "cw"}

    spindle_speed: float = param(0.0, "spindle speed", unit="rpm")
    spindle: str = param("cw", "spindle direction", choices=("cw", "ccw"))


class SpindleOff(CLCommand):
    """The spindle stopping, which a post writes as its own word (M5)."""

    __slots__ = ()  # no fields of its own: CLCommand's dataclass methods serve

    name = "spindle_off"
    group = "tool and spindle"
    doc = "Stop the spindle (sets the parameter spindle to 'off')."
    example = {"cmd": "spindle_off"}


@dataclass(frozen=True, slots=True, kw_only=True)
class CoolantOn(CLCommand):
    """The coolant a post switches on, by kind (flood, mist, through the tool)."""

    name = "coolant_on"
    group = "tool and spindle"
    doc = "Switch coolant on."
    example = {"cmd": "coolant_on", "coolant": "flood"}

    coolant: str = param("flood", "coolant kind", choices=("flood", "mist", "through"))


class CoolantOff(CLCommand):
    """The coolant being switched off, which a post writes as its own word (M9)."""

    __slots__ = ()  # no fields of its own: CLCommand's dataclass methods serve

    name = "coolant_off"
    group = "tool and spindle"
    doc = "Switch coolant off (sets the parameter coolant to 'off')."
    example = {"cmd": "coolant_off"}


# --- motion ---------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True, kw_only=True)
class RapidMove(CLCommand):
    """A positioning move, which posts write as G0 with only the axes that change."""

    name = "rapid_move"
    group = "motion"
    doc = "Move at rapid rate; an axis left out keeps its position."
    example = {"cmd": "rapid_move", "x": 40, "y": 20, "z": 80}

    x: float | None = param(None, "end point X", sticky=True, unit="mm")
    y: float | None = param(None, "end point Y", sticky=True, unit="mm")
    z: float | None = param(None, "end point Z", sticky=True, unit="mm")
    a: float | None = param(None, "rotary axis A at the end point (about X), as the CAM "
                            "gives it", sticky=True, unit="deg")
    b: float | None = param(None, "rotary axis B at the end point (about Y)", sticky=True,
                            unit="deg")
    c: float | None = param(None, "rotary axis C at the end point (about Z)", sticky=True,
                            unit="deg")
    tool_i: float | None = param(None, "tool axis in the part frame, X component (APT "
                                 "GOTO/x,y,z,i,j,k under MULTAX); the post solves the "
                                 "rotary angles from it", sticky=True)
    tool_j: float | None = param(None, "tool axis, Y component", sticky=True)
    tool_k: float | None = param(None, "tool axis, Z component", sticky=True)
    rezero: float | None = param(
        None, "where the post re-zeroes its continuous rotary axis before this move "
        "(machine: rotary: {wrap: rezero}): the value the axis's present position is set "
        "to (G92 A...); set by the post, not given by the CAM", unit="deg")


@dataclass(frozen=True, slots=True, kw_only=True)
class SafeRetract(CLCommand):
    """The CAM's "go safe" before the first tool: a rapid in Z alone, before any tool_change.

    CAM systems start a job by sending the spindle up to a clearance height before the
    first tool is called (FreeCAD's Job: ``G54``, then ``G0 Z<clearance>``).  On a machine
    with a tool changer no tool, and so no length offset, is active there: the height is
    not a place the control can go in program coordinates.  A post for such a machine
    writes its own retract in machine coordinates (``G91 G28 Z0``, ``G53 G0 Z0``,
    ``L Z… M91``, ``SUPA G0 Z…``) in its ``safe_retract`` table, or gives the table no
    blocks when its tool-change sequence retracts Z first; a post without the table
    writes the record as the rapid_move it is (refused before any tool on a machine
    with a tool changer).
    """

    name = "safe_retract"
    group = "motion"
    doc = (
        "The CAM's move to a safe height before the first tool: a rapid in Z alone, before "
        "any tool_change.  z is the CAM's clearance height in program coordinates.  A post "
        "for a machine with a tool changer writes its own retract in machine coordinates "
        "(its safe_retract table; no blocks when its tool change retracts Z first); a post "
        "without a safe_retract table writes it as a rapid_move to z."
    )
    example = {"cmd": "safe_retract", "z": 15}

    z: float | None = param(None, "end point Z", sticky=True, unit="mm")


@dataclass(frozen=True, slots=True, kw_only=True)
class MachineRetract(CLCommand):
    """A retract in Z the input wrote in machine coordinates (G28 G91 Z0, G53 G0 Z…)."""

    name = "machine_retract"
    group = "motion"
    doc = (
        "A retract of Z alone in machine coordinates, as the input wrote it: to the "
        "reference point through the tool's own position (RS274 G28 G91 Z0), or to the "
        "machine Z machine_z (G53 G0 Z...).  The CL's position in Z is unknown after it.  "
        "A post writes it in its control's words (G91 G28 Z0, G53 G0 Z..., L Z... M91, "
        "SUPA G0 Z...) or refuses what its control cannot do; a post without a table "
        "refuses it."
    )
    example = {"cmd": "machine_retract"}

    machine_z: float | None = param(
        None, "the machine-coordinate Z of a G53 retract; omitted: the reference point "
        "(G28)", unit="mm")


@dataclass(frozen=True, slots=True, kw_only=True)
class LinearMove(CLCommand):
    """A cutting move in a straight line, the bulk of most programs."""

    name = "linear_move"
    group = "motion"
    doc = "Move in a straight line at the feed rate; an axis left out keeps its position."
    example = {"cmd": "linear_move", "x": 7, "y": -7, "z": 12.5, "feed": 200}

    x: float | None = param(None, "end point X", sticky=True, unit="mm")
    y: float | None = param(None, "end point Y", sticky=True, unit="mm")
    z: float | None = param(None, "end point Z", sticky=True, unit="mm")
    feed: float | None = param(None, "feed rate", sticky=True, unit="mm/min")
    a: float | None = param(None, "rotary axis A at the end point (about X), as the CAM "
                            "gives it", sticky=True, unit="deg")
    b: float | None = param(None, "rotary axis B at the end point (about Y)", sticky=True,
                            unit="deg")
    c: float | None = param(None, "rotary axis C at the end point (about Z)", sticky=True,
                            unit="deg")
    tool_i: float | None = param(None, "tool axis in the part frame, X component (APT "
                                 "GOTO/x,y,z,i,j,k under MULTAX); the post solves the "
                                 "rotary angles from it", sticky=True)
    tool_j: float | None = param(None, "tool axis, Y component", sticky=True)
    tool_k: float | None = param(None, "tool axis, Z component", sticky=True)
    inverse_time: float | None = param(
        None, "1 / the move's time in minutes, where it turns a rotary axis (G93 F): set by "
        "the post from the tool tip's path in the part, not given by the CAM", unit="1/min")
    rezero: float | None = param(
        None, "where the post re-zeroes its continuous rotary axis before this move "
        "(machine: rotary: {wrap: rezero}): the value the axis's present position is set "
        "to (G92 A...); set by the post, not given by the CAM", unit="deg")


@dataclass(frozen=True, slots=True, kw_only=True)
class ArcMove(CLCommand):
    """A circular or helical cut, by absolute centre, from which posts derive I, J, K or R."""

    name = "arc_move"
    group = "motion"
    doc = (
        "Circular (or helical) move about an absolute centre.  The parameters i, j, k "
        "(centre minus start point) and radius are derived."
    )
    example = {
        "cmd": "arc_move",
        "x": 46.211,
        "y": 66.477,
        "cx": 45.0,
        "cy": 30.0,
        "arc_direction": "cw",
    }

    x: float | None = param(None, "end point X", sticky=True, unit="mm")
    y: float | None = param(None, "end point Y", sticky=True, unit="mm")
    z: float | None = param(None, "end point Z (differs from the start on a helix)",
                            sticky=True, unit="mm")
    cx: float | None = param(None, "centre X (absolute); the start X when omitted", unit="mm")
    cy: float | None = param(None, "centre Y (absolute); the start Y when omitted", unit="mm")
    cz: float | None = param(None, "centre Z (absolute); the start Z when omitted", unit="mm")
    arc_direction: str = param("ccw", "direction seen from the plane's normal",
                               choices=("cw", "ccw"))
    plane: str = param("xy", "plane of the arc", choices=("xy", "zx", "yz"))
    feed: float | None = param(None, "feed rate", sticky=True, unit="mm/min")


@dataclass(frozen=True, slots=True, kw_only=True)
class Dwell(CLCommand):
    """A pause in place, which a post writes as G4 in its control's units."""

    name = "dwell"
    group = "motion"
    doc = "Wait in place."
    example = {"cmd": "dwell", "dwell": 0.5}

    dwell: float = param(0.0, "dwell time", unit="s")


# --- drilling -------------------------------------------------------------------------------


class CycleStart(CLCommand):
    """Opens a drilling cycle, so a post can write what comes before its setup."""

    __slots__ = ()  # no fields of its own: CLCommand's dataclass methods serve

    name = "cycle_start"
    group = "drilling"
    doc = "Start of a drilling cycle; its setup command follows."
    example = {"cmd": "cycle_start"}


@dataclass(frozen=True, slots=True, kw_only=True)
class DrillSetup(CLCommand):
    """Common fields of the drilling setups; the first hole is at (x, y).

    Geometry: the hole's top is ``top`` (absolute Z), its bottom ``top - depth``;
    the tool rapids to ``top + clearance``, feeds to the bottom and leaves to
    ``retract`` (absolute Z; ``top + clearance`` when omitted).
    """

    group = "drilling"

    x: float | None = param(None, "hole centre X", sticky=True, unit="mm")
    y: float | None = param(None, "hole centre Y", sticky=True, unit="mm")
    top: float = param(0.0, "absolute Z of the top of the hole", unit="mm")
    depth: float = param(0.0, "hole depth measured down from the top (positive)", unit="mm")
    clearance: float = param(0.0, "distance above the top where the feed starts", unit="mm")
    retract: float | None = param(None, "absolute Z the tool leaves to; top + clearance "
                                  "when omitted", unit="mm")
    peck: float = param(0.0, "peck depth (0: no pecking)", unit="mm")
    first_peck: float | None = param(
        None, "depth of the first peck below the top when it differs from the later pecks "
        "(peck); omitted: every peck is peck deep.  A post whose table does not write it "
        "has the hole refused (or expanded into moves), never drilled at one depth",
        unit="mm")
    dwell: float = param(0.0, "dwell at the bottom", unit="s")
    feed: float | None = param(None, "feed rate", sticky=True, unit="mm/min")
    cycle_return: str | None = param(
        None, "the return level the input wrote for the cycle, where it writes one: "
        "initial (G98) or r_plane (G99); retract already says where the tool goes",
        choices=("initial", "r_plane"))


def _setup(name: str, doc: str, example: dict[str, Any]) -> type[DrillSetup]:
    """A named drilling setup: PPU has one command per kind, with the same fields.

    It adds no field, so it is a plain subclass (no slots of its own, no ``__dict__``)
    that inherits DrillSetup's dataclass methods: making them again for each of the seven
    would cost every run of postdsl several milliseconds at import and change nothing.
    """
    title = "".join(part.capitalize() for part in name.split("_"))
    namespace = {"__slots__": (), "__module__": __name__, "__qualname__": title,
                 "__doc__": doc, "name": name, "doc": doc,
                 "example": {"cmd": name, **example}}
    return type(title, (DrillSetup,), namespace)


_HOLE = {"x": 40, "y": 20, "top": 70, "clearance": 5, "feed": 200}
SinglePeck = _setup("single_peck", "Drill in one feed, optionally dwelling at the bottom.",
                    {**_HOLE, "depth": 50, "dwell": 0.5})
DeepDrill = _setup("deep_drill", "Peck drilling with full retract between pecks.",
                   {**_HOLE, "depth": 53.0043, "peck": 10})
BreakChip = _setup("break_chip", "Peck drilling with a short retract to break the chip.",
                   {**_HOLE, "depth": 53.0043, "peck": 10})
Tapping = _setup("tapping", "Tapping with a floating holder (right-hand thread).",
                 {**_HOLE, "depth": 35, "dwell": 0.5, "feed": 100})
RigidTapping = _setup("rigid_tapping", "Rigid tapping (right-hand thread).",
                      {**_HOLE, "depth": 35, "peck": 10, "feed": 100})
TappingCcw = _setup("tapping_ccw", "Tapping with a floating holder, left-hand thread.",
                    {**_HOLE, "depth": 35, "feed": 100})
RigidTappingCcw = _setup("rigid_tapping_ccw", "Rigid tapping, left-hand thread.",
                         {**_HOLE, "depth": 35, "feed": 100})

Boring = _setup("boring", "Boring or reaming: feed to the bottom, dwell there if given, feed "
                "out to the clearance level, then leave at rapid (RS274 G85; G89 with a "
                "dwell).  No peck.", {**_HOLE, "depth": 20, "feed": 80})
BoringSpindleStop = _setup(
    "boring_spindle_stop", "Boring: feed to the bottom, dwell there if given, stop the "
    "spindle, leave at rapid; the spindle starts again as it turned (RS274 G86).  No peck.",
    {**_HOLE, "depth": 20, "feed": 80})


@dataclass(frozen=True, slots=True, kw_only=True)
class FineBoring(DrillSetup):
    """Fine boring: the tool must not mark the finished wall on its way out."""

    name = "fine_boring"
    doc = ("Fine boring: feed to the bottom, dwell there if given, stop the spindle at its "
           "oriented angle, move the cutting edge off the wall by the shift, leave at rapid, "
           "move back and start the spindle again (a fine-boring cycle: RS274 G76 Q on the "
           "controls that have one).  The oriented stop is the machine's: no post can write "
           "it as moves.  No peck.")
    example = {"cmd": "fine_boring", **_HOLE, "depth": 20, "feed": 60, "shift": 0.2,
               "shift_direction": "-x"}

    shift: float = param(0.0, "how far the cutting edge moves off the wall at the bottom, "
                         "after the oriented stop", unit="mm")
    shift_direction: str = param("-x", "the direction of the shift, away from the cutting "
                                 "edge, which the spindle's orientation points at the wall",
                                 choices=("+x", "-x", "+y", "-y"))


@dataclass(frozen=True, slots=True, kw_only=True)
class CycleHole(CLCommand):
    """A further hole of the active cycle: only the position changes."""

    name = "cycle_hole"
    group = "drilling"
    doc = "A further hole of the active drilling cycle."
    example = {"cmd": "cycle_hole", "x": 60, "y": 20}

    x: float | None = param(None, "hole centre X", sticky=True, unit="mm")
    y: float | None = param(None, "hole centre Y", sticky=True, unit="mm")
    top: float | None = param(None, "absolute Z of the top of this hole (the cycle's when "
                              "omitted)", sticky=True, unit="mm")


@dataclass(frozen=True, slots=True, kw_only=True)
class CycleEnd(CLCommand):
    """Closes a drilling cycle, with what ended it, so a post can cancel it (G80)."""

    name = "cycle_end"
    group = "drilling"
    doc = "End of the drilling cycle."
    example = {"cmd": "cycle_end", "ended_by": "cancel"}

    ended_by: str = param(
        "cancel", "what ended the cycle in the input: cancel (G80, CYCLE/OFF, or a "
        "native cycle_end), next_cycle (another cycle followed without a cancel), motion "
        "(a move, as RS274 ends a cycle) or other (another command, or the program end)",
        choices=("cancel", "next_cycle", "motion", "other"))


# --- custom cycles (probing) ----------------------------------------------------------------


@dataclass(frozen=True, slots=True, kw_only=True)
class CustomCycle(CLCommand):
    """A post-defined cycle (probing, engraving), named with free parameters."""

    name = "custom_cycle"
    group = "probing"
    doc = (
        "A cycle the post defines itself (probing, engraving…): ``cycle`` names the post's "
        "custom cycle table and ``params`` holds its named parameters."
    )
    example = {"cmd": "custom_cycle", "cycle": "probe_x", "params": {"target_x": 10}}

    cycle: str = param("", "name of the custom cycle in the post")
    params: dict[str, Any] = field(default_factory=dict,
                                   metadata={"doc": "named parameters (numbers or text)",
                                             "choices": None, "sticky": False, "unit": ""})


COMMAND_TYPES: tuple[type[CLCommand], ...] = (
    ProgramStart, ProgramEnd, ProgramStop, OptionalStop, WorkOffset, Operation, ToolChange,
    SpindleOn, SpindleOff, CoolantOn, CoolantOff, RapidMove, SafeRetract, MachineRetract,
    LinearMove, ArcMove, Dwell, CycleStart, SinglePeck, DeepDrill, BreakChip, Tapping,
    RigidTapping, TappingCcw, RigidTappingCcw, Boring, BoringSpindleStop, FineBoring,
    CycleHole, CycleEnd,
    CustomCycle, Comment,
    InputModes, WorkPlane, CutterCompensation,
)

#: command name -> record class
COMMANDS: dict[str, type[CLCommand]] = {cls.name: cls for cls in COMMAND_TYPES}


class OperationEnd(CLCommand):
    """The end of a CAM operation: an event the engine raises, never a CL record.

    CL files mark where an operation starts (``operation``), not where it ends; an
    operation that moved the tool ends where the next one starts, at a tool change and at
    the end of the program.  Posts that close an operation (cancel a cycle once, switch
    coolant off, retract) give a table for it under ``commands:``.
    """

    __slots__ = ()  # no fields of its own: CLCommand's dataclass methods serve

    name = "operation_end"
    group = "program"
    doc = ("End of a CAM operation (an event, not a CL record): after the tool moved, before "
           "the next operation record, tool change or the end of the program; once each.")
    example = {"cmd": "operation_end"}


#: events the engine raises itself, which a post may give tables for like CL commands
EVENTS: dict[str, type[CLCommand]] = {OperationEnd.name: OperationEnd}


@dataclass(frozen=True)
class ParamInfo:
    """What a parameter is, for the loader's checks and the editor's pickers."""

    name: str
    doc: str
    kind: str  # "number", "text" or "list"
    unit: str = ""
    choices: tuple[str, ...] | None = None
    source: str = ""  # the command that sets it, or "derived", "program", "built-in"


def command_fields(cls: type[CLCommand]) -> list[dataclasses.Field[Any]]:
    """The CL fields of a record class (without the source line)."""
    return [f for f in dataclasses.fields(cls) if f.name != "line"]


def record_builder(cls: type[CLCommand]) -> Callable[[dict[str, Any], int], CLCommand]:
    """A constructor of ``cls`` for a record whose fields a reader has already checked.

    ``builder(fields, line)`` is ``cls(line=line, **fields)`` without the frozen
    dataclass's ``__init__``, which sets each slot through ``object.__setattr__``: a
    reader makes one record per CL line, and this makes it in a fraction of the time.
    Only for classes without ``__post_init__`` and with plain defaults (a class with
    either gets ``cls`` itself); ``fields`` must hold only field names of ``cls``.
    """
    fields = dataclasses.fields(cls)
    if hasattr(cls, "__post_init__") or any(
            f.default is dataclasses.MISSING for f in fields):
        return lambda values, line: cls(line=line, **values)
    setters = []
    for f in fields:
        owner = next(c for c in cls.__mro__ if f.name in c.__dict__)
        if f.name != "line":
            setters.append((f.name, owner.__dict__[f.name].__set__, f.default))
        else:
            set_line = owner.__dict__[f.name].__set__
    new = object.__new__

    def build(values: dict[str, Any], line: int) -> CLCommand:
        record = new(cls)
        set_line(record, line)
        get = values.get
        for name, setter, default in setters:
            setter(record, get(name, default))
        return record

    return build


def field_type(f: dataclasses.Field[Any]) -> tuple[str, bool]:
    """(kind, optional) of a CL field: kind is "number", "integer", "text" or "object".

    The one place that reads the annotations, for the reader, the schema and the editor.
    """
    text = str(f.type)
    if "dict" in text:
        kind = "object"
    elif "str" in text:
        kind = "text"
    elif text.startswith("int"):
        kind = "integer"
    else:
        kind = "number"
    return kind, "None" in text


def _kind_of(f: dataclasses.Field[Any]) -> str:
    kind = field_type(f)[0]
    return {"integer": "number", "object": "list"}.get(kind, kind)


def _build_params() -> dict[str, ParamInfo]:
    params: dict[str, ParamInfo] = {}
    for cls in COMMAND_TYPES:
        for f in command_fields(cls):
            if f.name == "params":
                continue
            if f.name in params:
                continue
            params[f.name] = ParamInfo(
                f.name, f.metadata["doc"], _kind_of(f), f.metadata["unit"],
                f.metadata["choices"], cls.name,
            )
    derived = [
        ("i", "arc centre minus start point, X", "number", "mm"),
        ("j", "arc centre minus start point, Y", "number", "mm"),
        ("k", "arc centre minus start point, Z", "number", "mm"),
        ("radius", "arc radius", "number", "mm"),
        ("bottom", "absolute Z of the bottom of the hole (top - depth)", "number", "mm"),
        ("cycle", "the active drilling cycle's command name, '' outside a cycle", "text", ""),
        ("prev_x", "X before the current command", "number", "mm"),
        ("prev_y", "Y before the current command", "number", "mm"),
        ("prev_z", "Z before the current command", "number", "mm"),
        ("first_move", "true while the first motion (rapid, linear, arc or drilling setup) "
         "after a tool change is posted, false otherwise", "number", ""),
        ("given", "names of the fields the current CL record carries (not null), e.g. "
         "'z' in given: the move names Z itself rather than keeping it", "list", ""),
        ("plane_angle_1", "a work_plane's first angle in the convention of the post's "
         "machine.tilted_plane (euler_zxz: G68.2 I; fixed_xyz: SPA; rotated_xyz: "
         "CYCLE800 A); 0 at reset", "number", "deg"),
        ("plane_angle_2", "a work_plane's second angle (G68.2 J, SPB, CYCLE800 B)",
         "number", "deg"),
        ("plane_angle_3", "a work_plane's third angle (G68.2 K, SPC, CYCLE800 C)",
         "number", "deg"),
        ("compensation", "the cutter compensation the written program has on: left, right "
         "or off (it changes on the move that writes it)", "text", ""),
        ("compensation_start", "on the move in X/Y that starts or ends cutter compensation "
         "(the next after a cutter_compensation record): left, right or off; '' on every "
         "other move", "text", ""),
        ("compensation_waiting", "the cutter compensation a record asked for while its move "
         "in X/Y has not come ('' none): an arc then is refused", "text", ""),
    ]
    for name, doc, kind, unit in derived:
        params[name] = ParamInfo(name, doc, kind, unit, None, "derived")
    program = [
        ("tool_count", "number of distinct tools in the program", "number", ""),
        ("tools", "tool numbers in order of first use", "list", ""),
        ("min_x", "smallest X the tool reaches (holes included)", "number", "mm"),
        ("max_x", "largest X the tool reaches", "number", "mm"),
        ("min_y", "smallest Y the tool reaches", "number", "mm"),
        ("max_y", "largest Y the tool reaches", "number", "mm"),
        ("min_z", "smallest Z the tool reaches (hole bottoms included)", "number", "mm"),
        ("max_z", "largest Z the tool reaches", "number", "mm"),
        ("next_tool", "the tool of the next tool change (before the first: the first "
         "tool); none after the last, e.g. for pre-staging T.. after M6", "number", ""),
        ("next_spindle_speed", "from a tool change on: the speed of the first spindle_on "
         "after it (none if that tool never turns), for controls that take it with the tool "
         "call", "number", "rpm"),
    ]
    for name, doc, kind, unit in program:
        params[name] = ParamInfo(name, doc, kind, unit, None, "program")
    builtins = [
        ("block_number", "number of the block being written", "number"),
        ("year", "year the program was posted", "number"),
        ("month", "month (1-12)", "number"),
        ("day", "day of the month", "number"),
        ("hour", "hour (0-23)", "number"),
        ("minute", "minute", "number"),
        ("second", "second", "number"),
        ("machine_name", "the post's machine name", "text"),
        ("controller", "the post's controller name", "text"),
        ("cl_file", "name of the CL file being posted", "text"),
    ]
    for name, doc, kind in builtins:
        params[name] = ParamInfo(name, doc, kind, "", None, "built-in")
    return params


#: every parameter a post may print or test, by name
PARAMETERS: dict[str, ParamInfo] = _build_params()

#: ``prev_<name>`` reads the value a parameter (or a post's variable or flag) had before the
#: current CL record changed it; it equals the value itself when the record left it alone
PREVIOUS: Final = "prev_"


def with_previous(names: Iterable[str]) -> frozenset[str]:
    """``names`` and the ``prev_`` name of each, as conditions and expressions may read them.

    ``prev_x``, ``prev_y`` and ``prev_z`` are parameters of their own already (the start
    of a move); they too mean "before the current record".
    """
    known = frozenset(names)
    return known | {PREVIOUS + name for name in known if not name.startswith(PREVIOUS)}


#: a plain rapid or linear move as a reader hands it to posting without a command object
#: (a first pass checked and folded it; the second only posts it):
#: ``(RapidMove, line, x, y, z)`` or ``(LinearMove, line, x, y, z, feed)``, a field the
#: record leaves out None.  It means exactly the command :func:`plain_command` makes of it.
PlainMove = tuple[Any, ...]
#: the fields of a rapid or linear move that a machine's rotaries consume
#: (:mod:`postdsl.run.rotary`): not part of a plain move
ROTARY_FIELDS: Final = frozenset({"a", "b", "c", "tool_i", "tool_j", "tool_k", "inverse_time",
                                  "rezero"})


def plain_command(move: PlainMove) -> CLCommand:
    """The command a :data:`PlainMove` stands for."""
    if move[0] is LinearMove:
        _cls, line, x, y, z, feed = move
        return LinearMove(x=x, y=y, z=z, feed=feed, line=line)
    _cls, line, x, y, z = move
    return RapidMove(x=x, y=y, z=z, line=line)


def plain_move_of(command: CLCommand) -> PlainMove:
    """The :data:`PlainMove` of a rapid or linear move command."""
    if command.__class__ is LinearMove:
        return (LinearMove, command.line, command.x, command.y, command.z,
                command.feed)
    # a RapidMove (the caller's promise): mypy narrows `__class__ is` only for LinearMove above
    return (RapidMove, command.line, command.x, command.y, command.z)  # type: ignore[attr-defined]
