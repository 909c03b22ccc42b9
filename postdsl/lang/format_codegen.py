"""Render functions written for one format's options: the hot path of posting.

:func:`postdsl.lang.format_render.compile_fast` is one closure for every format, and
it decides, for each number, what the format decided when the post loaded:
trimmed or not, which point, which sign, which multiplier (issue 11: 1.8 µs a
coordinate, 300 000 coordinates in a 100 000-move program).  This module writes
the few lines one format needs as Python source — like :mod:`postdsl.compile.codegen`
does for tables — and compiles them once per set of options.  The text is made
only from the validated options: numbers and strings through ``repr``, never
anything a user typed.

What the generated function does itself (everything else goes to the generic
function, which stays the reference for it):

* a float, or an int of at most 53 bits, whose product with the multiplier lies
  strictly between the bounds below;
* ``half_away``/``half_even``: formats the double with C's ``format`` (binary
  rounding) when ``value × multiplier × 10**decimals`` is farther than
  :data:`TIE_GUARD` from a half.  The scaled double is within 4.5e-4 of the
  exact product of the two shortest reprs below 1e12 (four roundings of 2**-53
  relative each), so it rounds the way the repr digits do; a repr tie (``2.675``)
  is always inside the guard, and goes to the exact path;
* ``binary``: ``format`` of the double product is the definition itself.

A value whose rounded text could have more digits than ``max_digits`` allows
is outside the bounds, so the generic function raises the DigitsError.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache
from typing import Any

from postdsl.lang.format_render import (
    _TIE_GUARD,
    Render,
    _layout,
    _Options,
    _signs,
    compile_fast,
)

__all__ = ["TIE_GUARD", "compile_render", "compile_special", "count_text", "special_source"]

#: half_away/half_even: a scaled value this close to a half may be a tie of its repr
TIE_GUARD = _TIE_GUARD
#: the scaled values (value × multiplier × 10**decimals) the quick rounding is exact
#: for; the error bound above holds below it
_SCALED_LIMIT = 1e12
#: a half-rounding format takes the generated path only if its decimals leave it this
#: much range (at 11 or more decimals it would serve almost no value)
_MIN_RANGE = 100.0
#: binary rounding has no tie to guard against: the bound only keeps huge words (and
#: their DigitsError) on the generic path, where their text is made the same way
_BINARY_LIMIT = 1e15
#: ints beyond this are not exact doubles: the generic function multiplies them exactly
_INT_LIMIT = 2**53

_FILENAME = "<postdsl number format>"


def compile_render(fmt: _Options) -> Render:
    """The render function of ``fmt``: generated when its options allow, else generic."""
    generic = compile_fast(fmt)
    return compile_special(fmt, generic) or generic


def compile_special(fmt: _Options, fallback: Render) -> Render | None:
    """The generated render function of ``fmt``, calling ``fallback`` for what it leaves.

    None when the options leave (almost) every value to the fallback.  The
    tests pass the Decimal reference as ``fallback``, so that any difference from
    it is the generated code's own.
    """
    source = special_source(fmt)
    if source is None:
        return None
    namespace: dict[str, Any] = {"fallback": fallback}
    exec(_compiled(source), namespace)  # text made from validated options only
    render: Callable[[Any], str] = namespace["render"]
    return render


@lru_cache(maxsize=512)
def _compiled(source: str) -> Any:
    """The code object of ``source``: formats with equal options share it, and a run
    takes it from the code cache (:mod:`postdsl.codecache`) when an earlier one made it."""
    from postdsl.codecache import cached_code

    return cached_code(source, "format", lambda: compile(source, _FILENAME, "exec"))


def special_source(fmt: _Options) -> str | None:
    """The Python text of ``fmt``'s render function, or None (see :func:`compile_special`)."""
    return _Writer(fmt).source()


def count_text(fmt: _Options, name: str, low: int, high: int) -> str | None:
    """The expression of ``fmt``'s text of the int ``name``, known to lie in ``[low,
    high]`` (a block number): the generated render's own int branch, for the caller to
    write in line (a block number is formatted on every numbered line, and the call was
    a twentieth of a straight move's lane).  None when the render would do more for
    such an int than that branch: no generated render, a multiplier that is not a
    positive whole number, a zero, or a number past its digits."""
    writer = _Writer(fmt)
    multiplier = writer.multiplier
    if low < 1 or high < low or not multiplier.is_integer() or multiplier < 1 \
            or writer.limit() is None:
        return None
    factor = int(multiplier)
    limit = 10**writer.max_digits if writer.max_digits is not None else 10**15
    if high * factor >= limit:
        return None
    quantity = name if factor == 1 else f"({name} * {factor!r})"
    return writer.int_text(quantity, negative=False)


class _Writer:
    """Writes one format's render function from its options (constants through repr)."""

    def __init__(self, fmt: _Options) -> None:
        self.places = fmt.decimals
        self.binary = fmt.rounding == "binary"
        self.half_even = fmt.rounding == "half_even"
        self.multiplier = float(fmt.multiplier)
        self.unit = self.multiplier == 1.0
        self.point = fmt.point
        self.trim = not fmt.trailing_zeros and fmt.min_decimals < fmt.decimals
        self.keep = fmt.min_decimals
        self.leading = fmt.leading_zeros
        self.width = fmt.width
        self.sign = fmt.sign
        self.plus_zero = fmt.zero_sign == "plus"
        self.max_digits = fmt.max_digits
        minus, plus, zero = _signs(fmt)
        self.minus, self.plus = minus, plus
        #: the text of every value that rounds to zero
        self.zero = _layout(fmt)(zero, "0", "0" * self.places)
        #: integers are written from the rounded scaled value: no point to place
        self.integral = not self.binary and (self.places == 0 or self.point == "never")
        self.scale = float(10**self.places)

    # -- the bounds -----------------------------------------------------------------

    def limit(self) -> float | None:
        """The bound on |value × multiplier| (on the scaled value, for integral).

        None when the decimals leave too short a range to be worth a function
        (half_away/half_even at 11 or more decimals: below 1e12 scaled, values
        below 10); a short range from max_digits is fine, the rest being errors.
        """
        digits = self.max_digits
        if self.binary:
            if digits is not None and digits < 15:
                return float(10**digits - 1)
            return _BINARY_LIMIT
        if _SCALED_LIMIT / self.scale < _MIN_RANGE:
            return None
        if self.integral:
            # the rounded scaled value has at most this many digits: 12, and within
            # max_digits (with the decimals, which an implied point writes too)
            total = 12 if digits is None else min(12, digits + self.places)
            return float(10**total - 1)
        bound = _SCALED_LIMIT / self.scale
        if digits is not None and digits < 12:
            bound = min(bound, float(10**digits - 1))
        return bound

    # -- the text -------------------------------------------------------------------

    def source(self) -> str | None:
        """The module text defining ``render``, or None when the range is too short."""
        limit = self.limit()
        if limit is None:
            return None
        whole = self.multiplier.is_integer()
        if whole:  # ints times a whole multiplier stay ints: written without rounding
            lines = ["def render(value):", "    if type(value) is float:"]
        else:
            lines = ["def render(value):",
                     f"    if type(value) is float or type(value) is int and "
                     f"{-_INT_LIMIT!r} < value < {_INT_LIMIT!r}:"]
        lines += self.float_part(limit)
        if whole:
            lines.append("    elif type(value) is int:")
            lines += self.int_part(int(self.multiplier))
        lines.append("    return fallback(value)")
        return "\n".join(lines) + "\n"

    def float_part(self, limit: float) -> list[str]:
        """The branches of a float (or of an int times a multiplier with a fraction)."""
        if self.integral:
            factor = self.multiplier * self.scale
            quantity = "x"
            product = None if factor == 1.0 else f"x = value * {factor!r}"
        else:
            quantity = "p"
            product = None if self.unit else f"p = value * {self.multiplier!r}"
        if product is None:
            quantity = "value"
        lines = [] if product is None else [f"        {product}"]
        lines.append(f"        if 0.0 < {quantity} < {limit!r}:")
        lines += self.branch(quantity, negative=False)
        lines.append(f"        elif {-limit!r} < {quantity} < 0.0:")
        lines += self.branch(quantity, negative=True)
        lines.append(f"        elif {quantity} == 0:")
        lines.append(f"            return {self.zero!r}")
        return lines

    def int_part(self, multiplier: int) -> list[str]:
        """The branches of an int times a whole multiplier: its digits, and zeros."""
        digits = self.max_digits
        limit = 10**digits if digits is not None else 10**15
        quantity = "value"
        lines: list[str] = []
        if multiplier != 1:
            lines.append(f"        n = value * {multiplier!r}")
            quantity = "n"
        lines.append(f"        if 0 < {quantity} < {limit!r}:")
        lines.append(f"            return {self.int_text(quantity, negative=False)}")
        lines.append(f"        elif {-limit!r} < {quantity} < 0:")
        lines.append(f"            return {self.int_text(quantity, negative=True)}")
        lines.append(f"        elif {quantity} == 0:")
        lines.append(f"            return {self.zero!r}")
        return lines

    def int_text(self, quantity: str, *, negative: bool) -> str:
        """``str(n)`` with its sign, leading zeros and the fraction's zeros (as trimmed)."""
        if self.point == "never":
            suffix = "0" * self.places
        else:
            fraction = "0" * (self.keep if self.trim else self.places)
            suffix = "." + fraction if fraction or self.point == "always" else ""
        prefix, sign_width = self.sign_of(negative)
        digits = f"str({self.magnitude(quantity, negative)})"
        if self.leading:  # zfill pads after str's own "-"
            digits += f".zfill({self.leading + sign_width!r})"
        return self.finish(self.join(prefix, digits, suffix))

    def branch(self, quantity: str, *, negative: bool) -> list[str]:
        """The lines of one sign's branch, indented under its ``if``."""
        pad = " " * 12
        if self.binary:
            return [pad + line for line in self.binary_lines(quantity, negative)]
        lines: list[str] = []
        scaled = quantity
        if not self.integral and self.scale != 1.0:
            lines.append(f"x = {quantity} * {self.scale!r}")
            scaled = "x"
        low, high = 0.5 - TIE_GUARD, 0.5 + TIE_GUARD
        lines.append(f"if not {low!r} < {scaled} % 1.0 < {high!r}:")
        inner: list[str] = []
        if negative:
            inner.append(f"if {scaled} > -0.5:")
            inner.append(f"    return {self.zero!r}")
        elif self.sign == "always" and not self.plus_zero:
            inner.append(f"if {scaled} < 0.5:")
            inner.append(f"    return {self.zero!r}")
        if self.integral:
            inner.append(f"return {self.integral_text(scaled, negative)}")
        else:
            inner += self.float_lines(quantity, negative)
        lines += ["    " + line for line in inner]
        if quantity == "value" and not self.integral:
            lines += self.tie_lines(scaled, negative, inner)
        return [pad + line for line in lines]

    def tie_lines(self, scaled: str, negative: bool, inner: list[str]) -> list[str]:
        """A value at a tie of its double: its repr's digits decide, as the exact path's.

        The repr is the decimal text the exact path rounds.  Its first dropped digit
        (and, for half_even, the rest and the last kept digit) says which way; the
        value is then moved a hundredth of a unit of the last place that way, far past
        the double's error (below 1e-4 of a unit under the scaled limit) and far from
        the other half, and written as any other value.  A repr with an exponent goes
        to the exact path.
        """
        places = self.places
        step = 10.0 ** -(places + 2)
        lines = ["else:  # at a half: the repr's digits decide",
                 "    r = repr(value)",
                 "    i = r.find('.')",
                 f"    if i > 0 and 'e' not in r and len(r) > i + {places + 1}:"]
        if self.half_even:
            lines.append(f"        d = r[i + {places + 1}]")
            lines.append(f"        if d > '5' or d == '5' and (len(r) > i + {places + 2} "
                         f"or r[i + {places}] in '13579'):")
        else:
            lines.append(f"        if r[i + {places + 1}] >= '5':")
        away, toward = ("-", "+") if negative else ("+", "-")
        lines.append(f"            value = value {away} {step!r}")
        lines.append("        else:")
        lines.append(f"            value = value {toward} {step!r}")
        if scaled != "value":
            lines.append(f"        {scaled} = value * {self.scale!r}")
        lines += ["        " + line for line in inner]
        return lines

    def sign_of(self, negative: bool) -> tuple[str, int]:
        """The prefix to put before the formatted magnitude, and the width of the
        sign the formatting writes itself ("-" of a negative value)."""
        if negative:
            return ("", 0) if self.sign == "never" else ("", 1)
        return ("+", 0) if self.sign == "always" else ("", 0)

    def magnitude(self, quantity: str, negative: bool) -> str:
        """What is formatted: the value itself, or its absolute value (sign never)."""
        return f"(-{quantity})" if negative and self.sign == "never" else quantity

    @staticmethod
    def join(prefix: str, text: str, suffix: str = "") -> str:
        """The expression of ``prefix + text + suffix``, constants through repr."""
        parts = [repr(prefix)] if prefix else []
        parts.append(text)
        if suffix:
            parts.append(repr(suffix))
        return text if len(parts) == 1 else f"({' + '.join(parts)})"

    def pattern(self, negative: bool) -> tuple[str, bool]:
        """The spec formatting the magnitude with its decimals and leading zeros, and
        whether it is a ``%`` pattern (else a ``format`` spec).

        ``float.__format__`` is the quickest for a plain spec, ``%`` for a padded one;
        both are C's correctly rounded conversion of the double.
        """
        _, sign_width = self.sign_of(negative)
        places = self.places
        # "#" keeps the point of a whole number ("12."): point always, no decimals
        alternate = "#" if places == 0 and self.point == "always" else ""
        if not self.leading:
            return f"{alternate}.{places}f", False
        # the width counts the sign, the point and the decimals
        point_width = places + 1 if places or alternate else 0
        return f"%{alternate}0{self.leading + sign_width + point_width}.{places}f", True

    def formatted(self, quantity: str, negative: bool) -> str:
        """The expression formatting the magnitude (see :meth:`pattern`)."""
        pattern, percent = self.pattern(negative)
        operand = self.magnitude(quantity, negative)
        return f"({pattern!r} % {operand})" if percent else f"{operand}.__format__({pattern!r})"

    def formatted_zero(self, negative: bool) -> str:
        """What :meth:`formatted` writes for a value that rounds to zero."""
        pattern, percent = self.pattern(negative)
        zero = -0.0 if negative and self.sign != "never" else 0.0
        return pattern % zero if percent else format(zero, pattern)

    def finish(self, text: str) -> str:
        """``text`` right-aligned in the format's width, if it has one."""
        return f"{text}.rjust({self.width!r})" if self.width else text

    def integral_text(self, scaled: str, negative: bool) -> str:
        """``'%d' % (x ± 0.5)``: the rounded scaled value as digits, point and sign."""
        prefix, sign_width = self.sign_of(negative)
        zero_pad = f"0{self.leading + self.places + sign_width}" if self.leading else ""
        dot = "." if self.point == "always" and self.places == 0 else ""
        pattern = f"%{zero_pad}d{dot}"
        if not negative:
            operand = f"{scaled} + 0.5"
        elif self.sign == "never":
            operand = f"0.5 - {scaled}"
        else:
            operand = f"{scaled} - 0.5"
        return self.finish(self.join(prefix, f"({pattern!r} % ({operand}))"))

    def float_lines(self, quantity: str, negative: bool) -> list[str]:
        """Format the double (half_away, half_even: known to round as its repr does)."""
        return self.trimmed(self.formatted(quantity, negative), negative)

    def binary_lines(self, quantity: str, negative: bool) -> list[str]:
        """``rounding: binary``: the double's own digits, as printf writes them."""
        if self.point == "never" and self.places:
            return self.binary_implied(quantity, negative)
        text = self.formatted(quantity, negative)
        # "-0.000" (and "0.000" where zero takes no sign) is the zero's own text
        needs_zero = (negative and self.sign != "never") or (
            not negative and self.sign == "always" and not self.plus_zero)
        lines: list[str] = []
        if needs_zero:
            lines.append(f"t = {text}")
            lines.append(f"if t == {self.formatted_zero(negative)!r}:")
            lines.append(f"    return {self.zero!r}")
            text = "t"
        return lines + self.trimmed(text, negative)

    def trimmed(self, text: str, negative: bool) -> list[str]:
        """Return ``text`` with its fraction's zeros trimmed as far as the options
        allow, after the sign the formatting did not write."""
        prefix, _ = self.sign_of(negative)
        if not self.trim:
            return [f"return {self.finish(self.join(prefix, text))}"]
        if self.keep == 0:
            strip = ".rstrip('0')" if self.point == "always" else ".rstrip('0').rstrip('.')"
            return [f"return {self.finish(self.join(prefix, text + strip))}"]
        # keep min_decimals: if rstrip took some of them, the cut at min_decimals is it
        drop, keep = self.places - self.keep, self.keep
        lines = [] if text == "t" else [f"t = {text}"]
        if drop == 1:  # only the last digit may go
            chosen = "(t[:-1] if t[-1] == '0' else t)"
            return [*lines, f"return {self.finish(self.join(prefix, chosen))}"]
        short = "u[-1] == '.'" if keep == 1 else f"'.' in u[{-keep}:]"
        chosen = f"(t[:{-drop}] if {short} else u)"
        return [*lines, "u = t.rstrip('0')", f"return {self.finish(self.join(prefix, chosen))}"]

    def binary_implied(self, quantity: str, negative: bool) -> list[str]:
        """Binary rounding with an implied point: the digits without their point."""
        places, leading = self.places, self.leading
        spec = f"0{leading + places + 1}.{places}f" if leading else f".{places}f"
        operand = f"(-{quantity})" if negative else quantity
        prefix = self.minus if negative else self.plus
        lines = [f"d = {operand}.__format__({spec!r}).replace('.', '')"]
        if leading:
            lines.append(f"if d == {'0' * (leading + places)!r}:")
        else:
            lines.append("d = d.lstrip('0')")
            lines.append("if not d:")
        lines.append(f"    return {self.zero!r}")
        word = f"{prefix!r} + d" if prefix else "d"
        lines.append(f"return {self.finish(f'({word})')}")
        return lines
