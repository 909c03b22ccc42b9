"""The fast render path writes byte for byte what the Decimal reference writes.

``compile_fast`` (scaled integers, no ``Decimal``) is what every NC word goes
through; ``compile_decimal`` is the implementation it replaced, kept as the
oracle.  Hypothesis draws every combination of format options and floats of
every magnitude (ties at the rounding place, values that round to zero, huge,
tiny and negative zero), and both must give the same text or the same error.
``rounding: binary`` is checked against Python's own ``format`` as well, and
``rounding``/``zero_sign`` by examples a post engineer can read.
"""

from __future__ import annotations

from decimal import Decimal
from typing import Any

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from postdsl.format_render import compile_decimal, compile_fast
from postdsl.formats import MAX_DECIMALS, DigitsError, FormatSpecError, NumberFormat

EDGES = [2.675, 1.0005, -4.3755, 0.5, -0.5, 1.5, 2.5, 1e-7, -1e-7, 1e16, -1e16, 1e22, -0.0, 0.0,
         -0.0004, -0.0005, 0.0005, 0.00049999999999999, 5e-324, -5e-324, 1.7976931348623157e308,
         123456789.123456789, 0.1, 0.7, 9.9995, -9.9995, 99999999.5, 4503599627370495.5,
         4503599627370497.0, 9007199254740993, 1e-5, 12.34500000001, 33.333333333333336]


@st.composite
def formats(draw: st.DrawFn) -> NumberFormat:
    """Any valid format: every option, including rounding and zero_sign."""
    integer = draw(st.booleans())
    decimals = 0 if integer else draw(st.integers(0, MAX_DECIMALS))
    point = "needed" if integer else draw(st.sampled_from(["always", "needed", "never"]))
    trailing = True if point == "never" else draw(st.booleans())
    sign = draw(st.sampled_from(["negative", "always", "never"]))
    max_digits = draw(st.one_of(st.none(), st.integers(1, 30)))
    leading = draw(st.integers(0, 12 if max_digits is None else min(12, max_digits)))
    return NumberFormat(
        decimals=decimals,
        trailing_zeros=trailing,
        min_decimals=draw(st.integers(0, decimals)),
        point=point,
        leading_zeros=leading,
        width=draw(st.integers(0, 40)),
        sign=sign,
        multiplier=draw(st.sampled_from([1.0, 1, 60, 1000.0, 0.001, 25.4, -1, -60, 1 / 3,
                                         1e-6, 1e6, 2.5e-5, 1 / 25.4])),
        integer=integer,
        max_digits=max_digits,
        rounding=draw(st.sampled_from(["half_away", "half_even", "binary"])),
        zero_sign=draw(st.sampled_from(["none", "plus"])) if sign == "always" else "none",
    )


@st.composite
def ties(draw: st.DrawFn) -> float:
    """Floats whose shortest repr ends exactly on a half at some rounding place."""
    k = draw(st.integers(min_value=-(10**9), max_value=10**9))
    return float(f"{k}5e-{draw(st.integers(1, 16))}")


@st.composite
def magnitudes(draw: st.DrawFn) -> float:
    """A few significant digits at any power of ten: plain and exponent reprs alike."""
    digits = draw(st.integers(min_value=-(10**6), max_value=10**6))
    return float(f"{digits}e{draw(st.integers(-330, 310))}")


values = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False),
    st.floats(allow_nan=False, allow_infinity=False, min_value=-1e9, max_value=1e9),
    st.floats(allow_nan=False, allow_infinity=False, min_value=-0.01, max_value=0.01),
    ties(), magnitudes(), st.sampled_from(EDGES),
    st.integers(-(10**20), 10**20), st.integers(-1000, 1000),
)


def outcome(render: Any, value: Any) -> tuple[str, str]:
    """The text ``render`` writes, or the type and message of its error."""
    try:
        return "text", render(value)
    except (ValueError, TypeError) as exc:
        return type(exc).__name__, str(exc)


@settings(max_examples=1500)
@given(fmt=formats(), value=values)
def test_fast_path_writes_what_the_decimal_path_writes(fmt: NumberFormat, value: float) -> None:
    assert outcome(compile_fast(fmt), value) == outcome(compile_decimal(fmt), value)


@pytest.mark.parametrize("value", EDGES)
@given(fmt=formats())
def test_edge_values_in_every_format(fmt: NumberFormat, value: float) -> None:
    assert outcome(fmt.render, value) == outcome(compile_decimal(fmt), value)


@given(fmt=formats(), value=values)
def test_decimal_inputs_take_the_reference_path(fmt: NumberFormat, value: float) -> None:
    exact = Decimal(repr(value))
    assert outcome(fmt.render, exact) == outcome(compile_decimal(fmt), exact)


@given(decimals=st.integers(0, MAX_DECIMALS),
       value=st.one_of(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e15,
                                 max_value=1e15), ties(), st.sampled_from(EDGES)))
@example(decimals=3, value=-4.3755)
def test_binary_rounding_is_what_python_format_writes(decimals: int, value: float) -> None:
    value = float(value)  # an int is exact in every rounding (times a whole multiplier)
    fmt = NumberFormat(decimals=decimals, rounding="binary")
    expected = format(value, f".{decimals}f")
    if expected.startswith("-") and not expected.strip("-0."):
        expected = expected[1:]  # never "-0"
    assert fmt.render(value) == expected


@pytest.mark.parametrize(("options", "value", "expected"), [
    # the example: FreeCAD's posts write the double -4.37549999...
    ({"decimals": 3, "rounding": "binary"}, -4.3755, "-4.375"),
    ({"decimals": 3}, -4.3755, "-4.376"),
    ({"decimals": 3, "rounding": "half_even"}, -4.3755, "-4.376"),
    ({"decimals": 2}, 2.675, "2.68"),
    ({"decimals": 2, "rounding": "binary"}, 2.675, "2.67"),
    ({"decimals": 2, "rounding": "half_even"}, 2.665, "2.66"),
    ({"decimals": 2, "rounding": "half_even"}, 2.675, "2.68"),
    ({"decimals": 2, "rounding": "half_even"}, 2.6651, "2.67"),
    ({"integer": True, "rounding": "half_even"}, 0.5, "0"),
    ({"integer": True, "rounding": "half_even"}, 1.5, "2"),
    ({"integer": True, "rounding": "half_even"}, -2.5, "-2"),
    ({"integer": True}, -2.5, "-3"),
    ({"integer": True, "rounding": "binary"}, 2.5, "2"),
    ({"decimals": 3, "rounding": "binary", "multiplier": 60}, 0.1, "6.000"),
    ({"decimals": 3, "rounding": "binary"}, -0.0004, "0.000"),
    ({"decimals": 3, "rounding": "binary", "trailing_zeros": False}, 1.0005, "1"),
    ({"decimals": 3, "trailing_zeros": False}, 1.0005, "1.001"),
    # Heidenhain: a zero carries the plus sign every other positive value carries
    ({"decimals": 3, "sign": "always", "zero_sign": "plus", "trailing_zeros": False}, 0, "+0"),
    ({"decimals": 3, "sign": "always", "zero_sign": "plus", "trailing_zeros": False},
     -0.0001, "+0"),
    ({"decimals": 3, "sign": "always", "zero_sign": "plus"}, -0.0, "+0.000"),
    ({"decimals": 3, "sign": "always", "zero_sign": "plus"}, 12.5, "+12.500"),
    ({"decimals": 3, "sign": "always", "zero_sign": "plus"}, -12.5, "-12.500"),
    ({"decimals": 3, "sign": "always"}, 0.0, "0.000"),
    ({"integer": True, "sign": "always", "zero_sign": "plus", "rounding": "binary"}, -0.4, "+0"),
])
def test_rounding_and_zero_sign(options: dict[str, Any], value: float, expected: str) -> None:
    fmt = NumberFormat.from_mapping(options)
    assert fmt.render(value) == expected
    assert compile_decimal(fmt)(value) == expected


@pytest.mark.parametrize(("options", "key"), [
    ({"rounding": "up"}, "rounding"),
    ({"rounding": True}, "rounding"),
    ({"zero_sign": "minus", "sign": "always"}, "zero_sign"),
    ({"zero_sign": "plus"}, "zero_sign"),  # without sign: always
    ({"zero_sign": "plus", "sign": "never"}, "zero_sign"),
])
def test_bad_rounding_and_zero_sign_name_their_key(options: dict[str, Any], key: str) -> None:
    with pytest.raises(FormatSpecError) as caught:
        NumberFormat.from_mapping(options)
    assert caught.value.key == key


def test_new_options_round_trip_and_describe() -> None:
    fmt = NumberFormat.from_mapping({"rounding": "binary", "sign": "always", "zero_sign": "plus"})
    assert fmt.to_mapping() == {"rounding": "binary", "sign": "always", "zero_sign": "plus"}
    assert NumberFormat.from_mapping(fmt.to_mapping()) == fmt
    assert fmt.describe() == "3 decimals, sign always, rounding binary, zero as +0"


def test_binary_product_too_large_for_a_double() -> None:
    fmt = NumberFormat(rounding="binary", multiplier=2.5)  # not whole: ints become doubles
    for render in (fmt.render, compile_decimal(fmt)):
        with pytest.raises(ValueError, match="too large for a double"):
            render(1e308)
        with pytest.raises(ValueError, match="too large for a double"):
            render(10**400)


def test_max_digits_counts_the_same_digits() -> None:
    fmt = NumberFormat(decimals=3, max_digits=4)
    assert fmt.render(9999.9994) == "9999.999"
    with pytest.raises(DigitsError) as caught:
        fmt.render(9999.9995)  # rounds up to a fifth digit
    assert caught.value.digits == 5
    with pytest.raises(DigitsError) as caught:
        fmt.render(10**5000)
    assert caught.value.digits == outcome_digits(compile_decimal(fmt), 10**5000)


def outcome_digits(render: Any, value: Any) -> int:
    with pytest.raises(DigitsError) as caught:
        render(value)
    return caught.value.digits
