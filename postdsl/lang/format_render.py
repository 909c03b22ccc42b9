"""The render functions of number formats: an exact fast path and the Decimal reference.

:mod:`postdsl.lang.formats` validates a format's options; this module turns them into
the closure that writes every number of every NC word, so it is the hot path of
posting (issue 11: ``Decimal`` took 30 % of a post's time).  Two compilers:

* :func:`compile_fast` — for floats and ints, on scaled integers.  The digits
  ``repr(float)`` prints are the shortest decimal text that reads back as the
  same double, i.e. the exact decimal the CAM system meant; they are read as an
  integer mantissa and a power of ten, multiplied by the multiplier's own exact
  digits, and rounded with one ``divmod`` — never with binary float arithmetic,
  which mis-rounds ``2.675`` or ``-4.3755``.  ``rounding: binary`` instead asks
  for exactly what printf and Python's ``format`` write, so it uses ``format``.
* :func:`compile_decimal` — the original ``decimal``-module implementation,
  kept as the slow path for ``Decimal`` inputs and as the oracle the property
  tests compare the fast path with, byte for byte, for every option.

Both take any object with the options of :class:`postdsl.lang.formats.NumberFormat`.
"""

from __future__ import annotations

from collections.abc import Callable
from decimal import (
    MAX_EMAX,
    MAX_PREC,
    MIN_EMIN,
    ROUND_HALF_EVEN,
    ROUND_HALF_UP,
    Context,
    Decimal,
)
from math import isfinite
from numbers import Integral
from typing import Any, Protocol

__all__ = ["DigitsError", "compile_decimal", "compile_fast"]

Render = Callable[[Any], str]

# Exact arithmetic: with the maximum precision a product of two decimals is
# never rounded, and ``quantize`` rounds exactly once.  Operators on Decimal
# would use the caller's thread context (precision 28 by default, or whatever
# someone set), so every operation names a context explicitly.
_CTX_HALF_AWAY = Context(prec=MAX_PREC, rounding=ROUND_HALF_UP, Emax=MAX_EMAX, Emin=MIN_EMIN)
_CTX_HALF_EVEN = Context(prec=MAX_PREC, rounding=ROUND_HALF_EVEN, Emax=MAX_EMAX, Emin=MIN_EMIN)

# Below 2**52 a float's integer part and fraction are exact, and a half
# (k + 0.5) is representable, so comparing the fraction with 0.5 rounds the
# shortest repr and the binary value alike.  Used for whole-number formats.
_EXACT_FLOAT_LIMIT = float(2**52)

# str(Decimal) switches to exponent notation when the adjusted exponent is
# below -6; after quantize to N places it is at least -N, so plain str() is
# safe (and much faster than format(q, "f")) up to 6 decimals.
_PLAIN_STR_DECIMALS = 6

# Powers of ten by exponent, for the scaled-integer path: a double's repr has
# an exponent from -324 to 308, decimals add up to 15 and a multiplier's digits
# up to about 20, so 400 covers every shift; beyond it ``10 ** n`` is computed.
_POW10 = tuple(10**n for n in range(400))

# The quick path's bounds (see compile_fast): below 1e12 a scaled double is
# within 1.2e-4 of its exact value, so a fraction more than 1e-3 from a half
# cannot belong to a tie of the shortest repr.
_QUICK_LIMIT = 1e12
_TIE_GUARD = 1e-3


class _Options(Protocol):
    # read-only members: a NumberFormat is a frozen dataclass
    @property
    def decimals(self) -> int: ...
    @property
    def trailing_zeros(self) -> bool: ...
    @property
    def min_decimals(self) -> int: ...
    @property
    def point(self) -> str: ...
    @property
    def leading_zeros(self) -> int: ...
    @property
    def width(self) -> int: ...
    @property
    def sign(self) -> str: ...
    @property
    def multiplier(self) -> float: ...
    @property
    def max_digits(self) -> int | None: ...
    @property
    def rounding(self) -> str: ...
    @property
    def zero_sign(self) -> str: ...


class DigitsError(ValueError):
    """A value with more digits before the point than its format allows (``max_digits``)."""

    def __init__(self, digits: int, allowed: int) -> None:
        super().__init__(f"{digits} digits before the point, more than the {allowed} "
                         f"the format allows (max_digits)")
        self.digits = digits
        self.allowed = allowed

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self), (self.digits, self.allowed))


def exact_decimal(value: int | float) -> Decimal:
    """The decimal a human means by ``value``: ints exactly, floats by shortest repr."""
    if isinstance(value, int):
        return Decimal(int(value))
    return Decimal(float.__repr__(value))


def coerce(value: object) -> int | float | Decimal:
    """Map the less common number types onto the three that render handles."""
    if isinstance(value, Integral):  # bool, IntEnum, numpy integers
        return int(value)
    if isinstance(value, float):  # float subclasses, e.g. numpy.float64
        return float(value)
    if isinstance(value, Decimal):
        return Decimal(value)
    raise TypeError(f"cannot write {type(value).__name__} {value!r} as a number")


def _layout(fmt: _Options) -> Callable[[str, str, str], str]:
    """The function that assembles sign, integer digits and fraction into the word."""
    trim = not fmt.trailing_zeros
    keep = fmt.min_decimals if trim else fmt.decimals
    leading = fmt.leading_zeros
    always_point = fmt.point == "always"
    never_point = fmt.point == "never"
    strip_integer_zero = never_point and not leading
    width = fmt.width

    def layout(prefix: str, integral: str, fraction: str) -> str:
        if trim:
            fraction = fraction.rstrip("0").ljust(keep, "0")
        if leading:
            integral = integral.zfill(leading)
        if always_point:
            body = f"{prefix}{integral}.{fraction}"
        elif never_point:
            digits = integral + fraction
            if strip_integer_zero:
                digits = digits.lstrip("0") or "0"
            body = prefix + digits
        elif fraction:
            body = f"{prefix}{integral}.{fraction}"
        else:
            body = prefix + integral
        return body.rjust(width) if width else body

    return layout


def _signs(fmt: _Options) -> tuple[str, str, str]:
    """The prefixes of a negative, a positive and a zero result."""
    minus = "" if fmt.sign == "never" else "-"
    plus = "+" if fmt.sign == "always" else ""
    zero = "+" if fmt.zero_sign == "plus" else ""
    return minus, plus, zero


def float_product(value: float | int, multiplier: float) -> float:
    """``value × multiplier`` as a Python post computes it: in doubles (``rounding: binary``).

    Raises ValueError when the product is no finite double, which no word can hold.
    """
    try:
        product = value * multiplier
    except OverflowError:  # an int too large for a double
        raise ValueError(f"cannot write {value!r}: too large for a double") from None
    if not isfinite(product):
        raise ValueError(f"cannot write {value!r} × {multiplier!r}: the product is too "
                         f"large for a double")
    return product


def _digits_error(n: int, places: int, max_digits: int) -> DigitsError:
    """The error for a scaled integer ``n`` (value × 10**places) with too many digits."""
    if n.bit_length() >= 10_000:  # str() refuses integers of more than 4,300 digits
        return DigitsError(n.bit_length() * 3 // 10 - places, max_digits)
    return DigitsError(len(str(abs(n))) - places, max_digits)


def compile_fast(fmt: _Options) -> Render:
    """The render function of ``fmt`` for floats and ints, without ``Decimal``.

    Falls back to :func:`compile_decimal`'s function for ``Decimal`` inputs and
    coerces other number types as it does, so both give the same text for
    every value (``tests/test_format_render.py`` proves it with hypothesis).
    """
    slow = compile_decimal(fmt)
    places = fmt.decimals
    mult = exact_decimal(fmt.multiplier).normalize(_CTX_HALF_AWAY)  # 1.0 -> 1, 1000.0 -> 1E+3
    sign_m, digits_m, exp_m = mult.as_tuple()
    assert isinstance(exp_m, int)  # a finite multiplier: checked by NumberFormat
    # the multiplier's magnitude as an integer; its sign flips the value's
    mult_int = int("".join(map(str, digits_m)))
    flip = bool(sign_m)
    if exp_m > 0:
        mult_int *= 10**exp_m
        exp_m = 0
    # value * multiplier * 10**places == mantissa * mult_int * 10**(places + exp_m - e10)
    base_shift = places + exp_m
    unit = mult_int == 1 and exp_m == 0 and not flip
    whole_multiplier = (-mult_int if flip else mult_int) if exp_m == 0 else None
    half_even = fmt.rounding == "half_even"
    binary = fmt.rounding == "binary"
    float_multiplier = float(fmt.multiplier)
    spec = f".{places}f"
    fast_whole = places == 0 and unit and fmt.rounding == "half_away"
    low, high = -_EXACT_FLOAT_LIMIT, _EXACT_FLOAT_LIMIT
    minus, plus, zero = _signs(fmt)
    max_digits = fmt.max_digits
    too_big = 10 ** (max_digits + places) if max_digits is not None else None
    too_big_int = 10**max_digits if max_digits is not None else None
    layout = _layout(fmt)
    pow10 = _POW10
    repr_ = float.__repr__
    zeros = "0" * places

    def scaled_int(n: int) -> str:
        """Write the exact integer ``n`` = result × 10**places, already rounded."""
        if too_big is not None and not -too_big < n < too_big:
            raise _digits_error(n, places, max_digits)  # type: ignore[arg-type]  # too_big is set only with max_digits
        if n < 0:
            prefix = minus
            text = str(-n)
        elif n:
            prefix = plus
            text = str(n)
        else:
            return layout(zero, "0", zeros)
        if places:
            text = text.rjust(places + 1, "0")
            return layout(prefix, text[:-places], text[-places:])
        return layout(prefix, text, "")

    def binary_text(number: float) -> str:
        """What printf's ``%.Nf`` writes for the double ``number``, made into the word."""
        text = format(number, spec)
        if text[0] == "-":
            text = text[1:]
            prefix = minus
        else:
            prefix = plus
        integral, _, fraction = text.partition(".")
        if not integral.strip("0") and not fraction.strip("0"):
            prefix = zero  # -0.0001 rounds to 0: never "-0"
        if max_digits is not None and len(integral) > max_digits:
            raise DigitsError(len(integral), max_digits)
        return layout(prefix, integral, fraction)

    # The quick path: ``format(value, ".Nf")`` is C code, and rounds the double
    # (binary) where half_away/half_even round the shortest repr.  The two agree
    # unless that repr is exactly a tie at the rounding place (``2.675``): only
    # then can the tie lie between the repr and the double, else the repr would
    # have been the tie.  A repr tie leaves value × 10**N within 2 ulp of k + 0.5,
    # so values whose scaled fraction is farther than _TIE_GUARD from a half take
    # the quick path; the rest (and |value × 10**N| >= 1e12, where the guard
    # would not hold) are rounded exactly on scaled integers below.
    quick = unit and not binary
    scale = float(10**places)
    quick_limit = _QUICK_LIMIT / scale
    tie_low, tie_high = 0.5 - _TIE_GUARD, 0.5 + _TIE_GUARD
    trim = not fmt.trailing_zeros
    keep = fmt.min_decimals if trim else places
    leading = fmt.leading_zeros
    always_point = fmt.point == "always"
    never_point = fmt.point == "never"
    strip_integer_zero = never_point and not leading
    width = fmt.width
    cut = -places - 1  # format's text without its point and decimals

    def render(value: Any) -> str:  # Any: it dispatches on the runtime type itself
        kind = type(value)
        if kind is float and quick and -quick_limit < value < quick_limit:
            if fast_whole:
                # whole numbers: below 2**52 the fraction is exact, and so is a half
                n = int(value)  # truncates toward zero; value - n is exact
                rest = value - n
                if rest >= 0.5:
                    n += 1
                elif rest <= -0.5:
                    n -= 1
                if n < 0:
                    prefix, integral = minus, str(-n)
                elif n:
                    prefix, integral = plus, str(n)
                else:
                    prefix, integral = zero, "0"
                if max_digits is not None and len(integral) > max_digits:
                    raise DigitsError(len(integral), max_digits)
                fraction = ""
                exact = True
            else:
                scaled = value * scale
                rest = scaled - int(scaled)
                if rest < 0:
                    rest = -rest
                exact = not tie_low < rest < tie_high
            if exact and not fast_whole:
                if -0.5 < scaled < 0.5:
                    prefix, integral, fraction = zero, "0", zeros
                else:
                    text = format(value, spec)
                    if text[0] == "-":
                        text = text[1:]
                        prefix = minus
                    else:
                        prefix = plus
                    if places:
                        integral = text[:cut]
                        fraction = text[-places:]
                    else:
                        integral, fraction = text, ""
                    if max_digits is not None and len(integral) > max_digits:
                        raise DigitsError(len(integral), max_digits)
        elif kind is int and unit and -quick_limit < value < quick_limit:
            # a whole number read from the CL (JSON's -140): its digits are the integral
            # part as they stand, whatever the rounding; the fraction is zeros
            if value < 0:
                prefix, integral = minus, str(-value)
            elif value:
                prefix, integral = plus, str(value)
            else:
                prefix, integral = zero, "0"
            if max_digits is not None and len(integral) > max_digits:
                raise DigitsError(len(integral), max_digits)
            fraction = zeros
            exact = True
        else:
            exact = False
        if exact:
            # the layout of _layout, inlined: this is the hot path of posting
            if trim:
                fraction = fraction.rstrip("0").ljust(keep, "0")
            if leading:
                integral = integral.zfill(leading)
            if always_point:
                body = f"{prefix}{integral}.{fraction}"
            elif never_point:
                digits = integral + fraction
                if strip_integer_zero:
                    digits = digits.lstrip("0") or "0"
                body = prefix + digits
            elif fraction:
                body = f"{prefix}{integral}.{fraction}"
            else:
                body = prefix + integral
            return body.rjust(width) if width else body
        if kind is float:
            if not isfinite(value):
                raise ValueError(f"cannot write {value!r}")
            if binary:
                return binary_text(value if unit else float_product(value, float_multiplier))
            if fast_whole and low < value < high:
                n = int(value)  # truncates toward zero; value - n is exact
                rest = value - n
                if rest >= 0.5:
                    n += 1
                elif rest <= -0.5:
                    n -= 1
                return scaled_int(n)
            text = repr_(value)
            negative = text[0] == "-"
            if negative:
                text = text[1:]
            if flip:
                negative = not negative
            mantissa, _, exponent = text.partition("e")
            integral, _, fraction = mantissa.partition(".")
            m = int(integral + fraction)
            if not unit:
                m *= mult_int
            shift = base_shift - len(fraction) + (int(exponent) if exponent else 0)
            if shift >= 0:
                n = m * (pow10[shift] if shift < 400 else 10**shift)
            else:
                divisor = pow10[-shift] if shift > -400 else 10**-shift
                n, rest = divmod(m, divisor)  # m >= 0: the sign is kept apart
                twice = rest + rest
                if twice > divisor or (twice == divisor and (not half_even or n & 1)):
                    n += 1
            return scaled_int(-n if negative else n)
        if kind is int:
            if whole_multiplier is None:
                if binary:
                    return binary_text(float_product(value, float_multiplier))
                return slow(value)
            n = value * whole_multiplier
            if too_big_int is not None and not -too_big_int < n < too_big_int:
                raise _digits_error(n, 0, max_digits)  # type: ignore[arg-type]  # too_big_int is set only with max_digits
            return scaled_int(n * pow10[places])
        if kind is Decimal:
            return slow(value)
        return render(coerce(value))

    return render


def compile_decimal(fmt: _Options) -> Render:
    """The reference render function of ``fmt``, on ``decimal`` arithmetic.

    Slower, and the definition of right: what ``render`` wrote before the fast
    path existed.  ``rounding: binary`` rounds ``float(value × multiplier)``
    exactly, half to even, which is what printf does.
    """
    places = fmt.decimals
    ctx = _CTX_HALF_EVEN if fmt.rounding != "half_away" else _CTX_HALF_AWAY
    binary = fmt.rounding == "binary"
    quantum = Decimal(1).scaleb(-places, context=ctx)
    multiplier = exact_decimal(fmt.multiplier)
    float_multiplier = float(fmt.multiplier)
    unit = multiplier == 1
    # ints times a whole multiplier stay ints: no decimal arithmetic at all
    whole = multiplier == multiplier.to_integral_value(context=ctx)
    whole_multiplier = int(multiplier) if whole else None
    # whole-number formats round unit floats with two float operations
    fast_whole = places == 0 and unit and not binary and ctx is _CTX_HALF_AWAY
    low, high = -_EXACT_FLOAT_LIMIT, _EXACT_FLOAT_LIMIT
    plain_str = places <= _PLAIN_STR_DECIMALS
    int_fraction = "0" * places  # the fraction of an exact int (layout trims it)
    minus, plus, zero = _signs(fmt)
    max_digits = fmt.max_digits
    #: whole numbers at or above this have too many digits (checked before str(), which
    #: refuses integers of more than 4,300 digits)
    too_big = 10**max_digits if max_digits is not None else None
    layout = _layout(fmt)

    def render(value: Any) -> str:  # Any: it dispatches on the runtime type itself
        kind = type(value)
        if kind is float:
            if not isfinite(value):
                raise ValueError(f"cannot write {value!r}")
            if binary:
                product = value if unit else float_product(value, float_multiplier)
                number: Decimal | None = Decimal(product)  # the double, exactly
            elif fast_whole and low < value < high:
                n = int(value)  # truncates toward zero; value - n is exact
                rest = value - n
                if rest >= 0.5:
                    n += 1
                elif rest <= -0.5:
                    n -= 1
                number = None
            else:
                number = Decimal(repr(value))
        elif kind is int:
            if whole_multiplier is not None:
                n = value * whole_multiplier
                number = None
            elif binary:
                number = Decimal(float_product(value, float_multiplier))  # the double, exactly
            else:
                number = Decimal(value)
        elif kind is Decimal:
            if not value.is_finite():
                raise ValueError(f"cannot write {value}")
            if binary:
                return render(float(value))
            number = value
        else:
            return render(coerce(value))

        if number is None:
            if too_big is not None and not -too_big < n < too_big:
                # too_big is not None only when max_digits is not None
                raise DigitsError(len(str(abs(n))) if n.bit_length() < 10_000
                                  else n.bit_length() * 3 // 10, max_digits)  # type: ignore[arg-type]  # too_big is set only with max_digits
            if n < 0:
                integral = str(-n)
                prefix = minus
            else:
                integral = str(n)
                prefix = plus if n else zero
            return layout(prefix, integral, int_fraction)
        if not unit and not binary:
            number = ctx.multiply(number, multiplier)
        rounded = number.quantize(quantum, context=ctx)
        text = str(rounded) if plain_str else format(rounded, "f")
        if text[0] == "-":
            text = text[1:]
            prefix = minus if rounded else zero  # -0.0001 rounds to 0, never "-0"
        else:
            prefix = plus if rounded else zero
        integral, _, fraction = text.partition(".")
        if max_digits is not None and len(integral) > max_digits:
            raise DigitsError(len(integral), max_digits)
        return layout(prefix, integral, fraction)

    return render
