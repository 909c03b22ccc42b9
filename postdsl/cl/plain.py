"""The plain moves the APT and G-code readers make without their general path.

A finishing program is millions of one kind of line (``GOTO/x,y,z``, ``G1 X… Y… Z…``).
The readers take those lines by one precompiled pattern and hand their values either
to a first pass's fold (a :class:`~postdsl.cl.native.MoveSink`, no command at all) or
to the constructors here, which make the command the general path would make, field
for field, in a third of the time of the frozen dataclass's keyword ``__init__`` (it
sets every slot through ``object.__setattr__`` and takes keywords).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

from postdsl.cl.model import CLCommand, LinearMove, RapidMove

__all__ = ["linear_move", "rapid_move"]

Number = float | None


def _setters(cls: type[CLCommand], names: tuple[str, ...]) -> list[Callable[..., None]]:
    """The slot setters of ``line`` and ``names``, which must be every other field of ``cls``
    in order: a field added to the model later must not be left unset here."""
    fields = [f.name for f in dataclasses.fields(cls) if f.name != "line"]
    if fields != list(names) or hasattr(cls, "__post_init__"):
        raise TypeError(f"{cls.__name__} has the fields {fields}, not {list(names)}")
    return [next(c.__dict__[name] for c in cls.__mro__ if name in c.__dict__).__set__
            for name in ("line", *names)]


_new = object.__new__
_ROTARY = ("a", "b", "c", "tool_i", "tool_j", "tool_k")
_set_line, _set_x, _set_y, _set_z, _set_feed, *_set_rotary = _setters(
    LinearMove, ("x", "y", "z", "feed", *_ROTARY, "inverse_time", "rezero"))
_set_rline, _set_rx, _set_ry, _set_rz, *_set_rrotary = _setters(
    RapidMove, ("x", "y", "z", *_ROTARY, "rezero"))


def linear_move(x: Number, y: Number, z: Number, feed: Number, line: int) -> LinearMove:
    """``LinearMove(x=x, y=y, z=z, feed=feed, line=line)``, made without its ``__init__``."""
    move = _new(LinearMove)
    _set_line(move, line)
    _set_x(move, x)
    _set_y(move, y)
    _set_z(move, z)
    _set_feed(move, feed)
    for unset in _set_rotary:  # a plain move turns no rotary
        unset(move, None)
    return move


def rapid_move(x: Number, y: Number, z: Number, line: int) -> RapidMove:
    """``RapidMove(x=x, y=y, z=z, line=line)``, made without its ``__init__``."""
    move = _new(RapidMove)
    _set_rline(move, line)
    _set_rx(move, x)
    _set_ry(move, y)
    _set_rz(move, z)
    for unset in _set_rrotary:
        unset(move, None)
    return move
