"""Named number formats: the one place where numbers become NC text.

A machine post declares formats (decimals, point, zeros, sign...) the way
Autodesk PPU, FeatureCAM or Fusion's ``createFormat`` do, and every numeric
word of every block goes through :meth:`NumberFormat.render`.  A wrong digit
here moves a real axis, so the rules are strict:

* Rounding is decimal, half away from zero, on the *shortest repr* of a float
  (what the user and the CAM system wrote), never on its binary expansion:
  ``2.675`` with 2 decimals is ``2.68`` although the double is 2.67499999...
  A post that must match a printf-based post asks for ``rounding: binary``.
* A negative zero is never written: ``-0.0001`` with 3 decimals is ``0.000``.
* Anything ambiguous in a format spec is refused with a :class:`FormatSpecError`
  naming the option, instead of guessed.

Speed matters second: each format compiles itself once into a function written
for its options (:mod:`postdsl.lang.format_codegen`: one C conversion of the double
where it provably rounds as the repr does), which leaves ties, huge values and
other types to the generic closure of :mod:`postdsl.lang.format_render` (exact, on
scaled integers rather than through ``Decimal``).
"""

from __future__ import annotations

import difflib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, fields
from math import isfinite
from typing import Any

from postdsl.lang.format_codegen import compile_render
from postdsl.lang.format_render import DigitsError

__all__ = ["DEFAULT_MAX_DIGITS", "MAX_DECIMALS", "DigitsError", "FormatSpecError",
           "NumberFormat"]

#: Most decimals a format may ask for.  A double carries 15 significant decimal
#: digits reliably (``sys.float_info.dig``); more places than that only ever add
#: zeros.  14 is seen in real programs ("raw" stock dimensions), hence not 12.
MAX_DECIMALS = 15
#: Integer digits a format may zero-pad to; more is certainly a typo.
MAX_LEADING_ZEROS = 12
#: Widest space-padded word; more is certainly a typo.
MAX_WIDTH = 40
#: Digits before the point a post's word may have unless its format says otherwise (the
#: loader gives it to every format of a post): common milling controls read at most 8
#: digits in a word, and 100 km in mm is no coordinate, feed or dwell any milling machine
#: is given.  A 300-digit I word is a CL value gone wrong, and must stop posting, not
#: reach the control.  A format built in code has no bound unless it asks for one.
DEFAULT_MAX_DIGITS = 8
#: Most digits before the point a format may allow.
MAX_MAX_DIGITS = 30

# integer=True overrides this default (see NumberFormat.__post_init__)
_DEFAULT_DECIMALS = 3

_POINTS = ("always", "needed", "never")
_SIGNS = ("negative", "always", "never")
#: half_away: half away from zero on the shortest repr (what the CAM meant);
#: half_even: the same digits, a tie to the even digit (banker's rounding);
#: binary: what printf and Python's format write, rounding the double itself
#: (FreeCAD's posts: ``-4.3755`` is the double -4.37549999..., written ``-4.375``)
_ROUNDINGS = ("half_away", "half_even", "binary")
#: the sign of a value written as zero: none (``X0``) or plus (``X+0``, Heidenhain)
_ZERO_SIGNS = ("none", "plus")

class FormatSpecError(ValueError):
    """A format spec that cannot be trusted to write numbers.

    ``key`` names the offending option so an editor or the post checker can
    point at the exact YAML line; it is ``None`` when no single option is to
    blame (e.g. the spec is not a mapping at all).
    """

    key: str | None
    message: str

    def __init__(self, message: str, key: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.key = key

    def __reduce__(self) -> tuple[Any, ...]:
        # keep ``key`` across pickling (multiprocessing workers re-raise these)
        return (type(self), (self.message, self.key))


def _check_int(key: str, value: object, low: int, high: int) -> None:
    # bool is an int subclass, but ``decimals: true`` in YAML is a mistake
    if not isinstance(value, int) or isinstance(value, bool):
        raise FormatSpecError(f"{key} must be an integer, not {value!r}", key)
    if not low <= value <= high:
        raise FormatSpecError(f"{key} must be from {low} to {high}, not {value}", key)


def _check_bool(key: str, value: object) -> None:
    if not isinstance(value, bool):
        raise FormatSpecError(f"{key} must be true or false, not {value!r}", key)


def _check_choice(key: str, value: object, choices: tuple[str, ...]) -> None:
    if not isinstance(value, str) or value not in choices:
        raise FormatSpecError(f"{key} must be one of {', '.join(choices)}, not {value!r}", key)


def _check_multiplier(value: object) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise FormatSpecError(f"multiplier must be a number, not {value!r}", "multiplier")
    if isinstance(value, float) and not isfinite(value):
        raise FormatSpecError(f"multiplier must be a finite number, not {value!r}", "multiplier")
    if value == 0:
        # every word would read 0: a unit-conversion typo, never an intent
        raise FormatSpecError("multiplier must not be 0", "multiplier")
    if not 1e-6 <= abs(value) <= 1e6:
        # unit conversions and scales (x60, x1000, steps per mm) live well inside this;
        # beyond it every word turns into a hundred digits
        raise FormatSpecError(f"multiplier must lie between 1e-06 and 1e+06 (either sign), "
                              f"not {value!r}", "multiplier")


def _number_text(value: int | float) -> str:
    text = repr(value)
    return text[:-2] if text.endswith(".0") else text


@dataclass(frozen=True)
class NumberFormat:
    """How one kind of number (coordinate, feed, dwell...) is written in NC code.

    Construction validates and compiles; an instance is immutable, hashable
    and safe to share between threads.  The defaults write ``12.500``.
    """

    decimals: int = _DEFAULT_DECIMALS
    trailing_zeros: bool = True
    min_decimals: int = 0
    point: str = "needed"
    leading_zeros: int = 0
    width: int = 0
    sign: str = "negative"
    multiplier: float = 1.0
    integer: bool = False
    #: most digits before the point (after the multiplier); more is a DigitsError
    max_digits: int | None = None
    rounding: str = "half_away"
    zero_sign: str = "none"

    def __post_init__(self) -> None:
        _check_int("decimals", self.decimals, 0, MAX_DECIMALS)
        _check_bool("trailing_zeros", self.trailing_zeros)
        _check_int("min_decimals", self.min_decimals, 0, MAX_DECIMALS)
        _check_choice("point", self.point, _POINTS)
        _check_int("leading_zeros", self.leading_zeros, 0, MAX_LEADING_ZEROS)
        _check_int("width", self.width, 0, MAX_WIDTH)
        _check_choice("sign", self.sign, _SIGNS)
        _check_multiplier(self.multiplier)
        _check_bool("integer", self.integer)
        _check_choice("rounding", self.rounding, _ROUNDINGS)
        _check_choice("zero_sign", self.zero_sign, _ZERO_SIGNS)
        if self.zero_sign == "plus" and self.sign != "always":
            # "+0" next to "5" and "-5" is no control's convention: a typo, not an intent
            raise FormatSpecError(
                f"zero_sign plus needs sign always (a zero gets the sign the other "
                f"positive values get), not sign {self.sign!r}", "zero_sign")
        if self.max_digits is not None:
            _check_int("max_digits", self.max_digits, 1, MAX_MAX_DIGITS)
        if self.max_digits is not None and self.leading_zeros > self.max_digits:
            raise FormatSpecError(
                f"leading_zeros ({self.leading_zeros}) is more than max_digits "
                f"({self.max_digits}): no value could be written", "leading_zeros")
        if self.integer:
            # The constructor cannot tell an explicit decimals=3 from the
            # default, so only other values are refused here; from_mapping,
            # which sees the keys, refuses any decimals > 0 next to integer.
            if self.decimals not in (0, _DEFAULT_DECIMALS):
                raise FormatSpecError(
                    f"decimals must be 0 or left out when integer is true, not {self.decimals}",
                    "decimals")
            if self.point != "needed":
                raise FormatSpecError(
                    f"point must be left out when integer is true (whole numbers are "
                    f"written without a point), not {self.point!r}", "point")
            object.__setattr__(self, "decimals", 0)
        if self.min_decimals > self.decimals:
            raise FormatSpecError(
                f"min_decimals must be at most decimals ({self.decimals}), "
                f"not {self.min_decimals}", "min_decimals")
        if self.point == "never" and not self.trailing_zeros:
            # with an implied point the digit count *is* the scale: 1.5 must
            # be 1500 with 3 decimals, trimming would turn it into 15 (0.015)
            raise FormatSpecError(
                "point 'never' needs trailing_zeros true: with an implied decimal point "
                "every decimal digit must be written", "point")
        # Shadow the class method with the compiled closure: it holds every
        # constant in cells, so rendering does no attribute lookups at all.
        object.__setattr__(self, "render", compile_render(self))

    def __reduce__(self) -> tuple[Any, ...]:
        # the compiled closure cannot be pickled; rebuild it from the options
        return (type(self), tuple(getattr(self, f.name) for f in fields(self)))

    @classmethod
    def from_mapping(cls, data: Mapping[str, Any]) -> NumberFormat:
        """Build a format from a post's YAML mapping, refusing anything doubtful.

        Every error is a :class:`FormatSpecError` whose ``key`` is the option
        at fault, so the post checker can point at the right line.
        """
        if not isinstance(data, Mapping):
            raise FormatSpecError(
                f"a number format must be a mapping of options, not {type(data).__name__}")
        names = [f.name for f in fields(cls)]
        for key in data:
            if not isinstance(key, str):
                raise FormatSpecError(f"option names must be text, not {key!r}", str(key))
            if key not in names:
                close = difflib.get_close_matches(key, names, n=1)
                hint = f" (did you mean '{close[0]}'?)" if close else ""
                raise FormatSpecError(
                    f"unknown option '{key}'{hint}; options are {', '.join(names)}", key)
        decimals = data.get("decimals")
        if (data.get("integer") is True and isinstance(decimals, int)
                and not isinstance(decimals, bool) and decimals > 0):
            raise FormatSpecError(
                f"decimals must be 0 or left out when integer is true, not {decimals}",
                "decimals")
        return cls(**data)

    def render(self, value: float | int) -> str:
        """The NC text of ``value``.

        Raises TypeError for anything that is not a real number (a str from a
        CL file must be parsed first, not silently written) and ValueError for
        nan and infinities, which no controller can read.  A Fraction is
        refused too rather than silently rounded through a float.  A ``decimal.Decimal``
        is accepted and taken exactly as it is, for callers that kept the text
        of a number rather than a float.
        """
        # Only reached through the class (NumberFormat.render(fmt, v)): every
        # instance shadows this method with its compiled closure.
        compiled: Callable[[float | int], str] = vars(self)["render"]
        return compiled(value)

    def to_mapping(self) -> dict[str, Any]:
        """The options that differ from the defaults, ready to dump as YAML.

        ``decimals`` and ``point`` are implied by ``integer`` and left out
        with it, so the mapping reads back through :meth:`from_mapping`.
        """
        out: dict[str, Any] = {}
        for f in fields(self):
            if self.integer and f.name in ("decimals", "point"):
                continue
            value = getattr(self, f.name)
            if value != f.default:  # so multiplier 1 (int) counts as the default 1.0
                out[f.name] = value
        return out

    def describe(self) -> str:
        """A short line for editors and error messages, e.g. "3 decimals, trim zeros"."""
        parts: list[str] = []
        if self.integer:
            parts.append("integer")
        elif self.decimals == 0:
            parts.append("no decimals")
        else:
            parts.append(f"{self.decimals} decimal{'s' if self.decimals != 1 else ''}")
            if not self.trailing_zeros:
                parts.append(f"trim zeros (keep {self.min_decimals})" if self.min_decimals
                             else "trim zeros")
        if self.point == "always":
            parts.append("point always")
        elif self.point == "never":
            parts.append("implied point")
        if self.leading_zeros:
            parts.append(f"{self.leading_zeros} integer digits")
        if self.sign == "always":
            parts.append("sign always")
        elif self.sign == "never":
            parts.append("no sign")
        if self.multiplier != 1:
            parts.append(f"times {_number_text(self.multiplier)}")
        if self.width:
            parts.append(f"width {self.width}")
        if self.max_digits is not None:
            parts.append(f"at most {self.max_digits} integer digits")
        if self.rounding != "half_away":
            parts.append(f"rounding {self.rounding.replace('_', ' ')}")
        if self.zero_sign == "plus":
            parts.append("zero as +0")
        return ", ".join(parts)
