"""Both fast render paths write byte for byte what the Decimal reference writes.

Every NC word goes through a function generated for its format's options
(``postdsl.lang.format_codegen``), which leaves ties, huge values and other types to
``compile_fast`` (scaled integers, no ``Decimal``); ``compile_decimal`` is the
implementation both replaced, kept as the oracle.  Hypothesis draws every
combination of format options and floats of every magnitude (ties at the
rounding place, values at the edge of the generated path's tie guard and
bounds, values that round to zero, huge, tiny and negative zero), and each path
must give the same text or the same error.  The generated path is tested with
the oracle itself as its fallback, so a difference can only be its own.
``rounding: binary`` is checked against Python's own ``format`` as well, and
``rounding``/``zero_sign`` by examples a post engineer can read.
"""

from __future__ import annotations

import dataclasses
import math
from decimal import Decimal
from typing import Any

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from postdsl.lang.format_codegen import (
    TIE_GUARD,
    compile_render,
    compile_special,
    count_text,
    special_source,
)
from postdsl.lang.format_render import compile_decimal, compile_fast
from postdsl.lang.formats import MAX_DECIMALS, DigitsError, FormatSpecError, NumberFormat
from tests.conftest import compiled_post

EDGES = [2.675, 1.0005, -4.3755, 0.5, -0.5, 1.5, 2.5, 1e-7, -1e-7, 1e16, -1e16, 1e22, -0.0, 0.0,
         -0.0004, -0.0005, 0.0005, 0.00049999999999999, 5e-324, -5e-324, 1.7976931348623157e308,
         123456789.123456789, 0.1, 0.7, 9.9995, -9.9995, 99999999.5, 4503599627370495.5,
         4503599627370497.0, 9007199254740993, 1e-5, 12.34500000001, 33.333333333333336,
         # the bounds of the generated path: max_digits 8, 1e12 scaled, 2**53 for ints
         99999998.9996, 99999999.0, -99999999.0, 99999999.4, 1e8, 999999999999.4,
         999999999999.6, 1e12, 99999999, 100000000, -100000000, 10**12 - 1, 10**15,
         2**53 - 1, 2**53, -(2**53), 0, 1, -1, 7]


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


def at_the_rounding_place(fmt: NumberFormat) -> st.SearchStrategy[float]:
    """Values whose scaled value ``v × multiplier × 10**decimals`` is ``k + f``.

    ``f`` near a half, inside or just outside the generated path's tie guard
    (``0.5 ± TIE_GUARD``), where it stops and the exact path starts, or anywhere;
    ``k`` of 0 and -1 put the value next to the half that decides between zero
    (never "-0") and one unit.
    """
    low, high = 0.5 - TIE_GUARD, 0.5 + TIE_GUARD
    units = st.one_of(st.sampled_from([0, -1, 1, -2, 99999999, -100000000]),
                      st.integers(-(10**12), 10**12))
    fractions = st.one_of(
        st.sampled_from([low, high, 1 - low, 1 - high, 0.5, 0.0]).flatmap(
            lambda edge: st.sampled_from([edge, edge + 1e-9, edge - 1e-9, edge + 1e-5,
                                          edge - 1e-5])),
        st.floats(min_value=0.0, max_value=1.0))
    scale = 10**fmt.decimals * fmt.multiplier
    return st.builds(lambda k, f: (k + f) / scale, units, fractions)


values = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False),
    st.floats(allow_nan=False, allow_infinity=False, min_value=-1e9, max_value=1e9),
    st.floats(allow_nan=False, allow_infinity=False, min_value=-0.01, max_value=0.01),
    ties(), magnitudes(), st.sampled_from(EDGES),
    st.integers(-(10**20), 10**20), st.integers(-1000, 1000),
    st.integers(-(2**54), 2**54),
)


def outcome(render: Any, value: Any) -> tuple[str, str]:
    """The text ``render`` writes, or the type and message of its error."""
    try:
        return "text", render(value)
    except (ValueError, TypeError) as exc:
        return type(exc).__name__, str(exc)


@given(fmt=formats(), value=values)
def test_fast_path_writes_what_the_decimal_path_writes(fmt: NumberFormat, value: float) -> None:
    assert outcome(compile_fast(fmt), value) == outcome(compile_decimal(fmt), value)


@given(fmt=formats(), data=st.data())
def test_generated_path_writes_what_the_decimal_path_writes(fmt: NumberFormat,
                                                             data: st.DataObject) -> None:
    value = data.draw(st.one_of(values, at_the_rounding_place(fmt)), label="value")
    reference = compile_decimal(fmt)
    generated = compile_special(fmt, reference)
    if generated is None:  # only formats whose exact range would be too short
        assert fmt.rounding != "binary" and fmt.decimals >= 11
        return
    assert outcome(generated, value) == outcome(reference, value)


@st.composite
def half_formats(draw: st.DrawFn) -> NumberFormat:
    """Formats that round a half of the decimal text (half_away, half_even) with a
    point and a fraction: those whose generated path decides the half itself."""
    fmt = draw(formats())
    decimals = fmt.decimals or draw(st.integers(1, MAX_DECIMALS))
    return dataclasses.replace(
        fmt, integer=False, multiplier=draw(st.sampled_from([1.0, 1])), max_digits=None,
        decimals=decimals, min_decimals=min(fmt.min_decimals, decimals),
        point="always" if fmt.point == "never" else fmt.point,
        rounding=draw(st.sampled_from(["half_away", "half_even"])))


@given(fmt=st.one_of(half_formats(), formats()), digits=st.integers(-(10**9), 10**9),
       nudge=st.integers(-2, 2))
def test_generated_path_at_a_half_of_the_decimal_text(fmt: NumberFormat, digits: int,
                                                       nudge: int) -> None:
    """Values whose repr ends on a 5 just past the rounding place (``2.675`` at two
    decimals), and the doubles next to them (``2.6750000000000003``): the repr's digits
    decide, on the generated path as on the exact one."""
    value = float(f"{digits}5e-{fmt.decimals + 1}")
    for _ in range(abs(nudge)):
        value = math.nextafter(value, math.copysign(math.inf, nudge))
    reference = compile_decimal(fmt)
    generated = compile_special(fmt, reference)
    if generated is not None:
        assert outcome(generated, value) == outcome(reference, value)


@given(fmt=formats(), unit=st.floats(min_value=-0.6, max_value=0.6), nudge=st.integers(-2, 2))
def test_generated_path_near_zero(fmt: NumberFormat, unit: float, nudge: int) -> None:
    """Values that round to zero or to one unit (``-0.0004995``): "0.000", never "-0.000"."""
    value = unit / (10**fmt.decimals * fmt.multiplier)
    for _ in range(abs(nudge)):  # the neighbouring doubles, at the edges of the guard
        value = math.nextafter(value, math.copysign(math.inf, nudge))
    reference = compile_decimal(fmt)
    generated = compile_special(fmt, reference)
    if generated is not None:
        assert outcome(generated, value) == outcome(reference, value)


@pytest.mark.parametrize("value", EDGES)
@given(fmt=formats())
def test_edge_values_in_every_format(fmt: NumberFormat, value: float) -> None:
    reference = compile_decimal(fmt)
    assert outcome(fmt.render, value) == outcome(reference, value)
    generated = compile_special(fmt, reference)
    if generated is not None:
        assert outcome(generated, value) == outcome(reference, value)


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


BUNDLED = sorted((machine, name, fmt)
                 for machine in ("emco", "fanuc", "feeler", "grbl", "heidenhain", "hmcnc",
                                 "linuxcnc", "vmc500")
                 for name, fmt in compiled_post(machine).formats.items())


def raster(count: int) -> list[float | int]:
    """What a CAM writes: coordinates with all their digits, whole numbers, ints, zeros."""
    values: list[float | int] = [50 + 40 * math.sin(n * 0.0137) for n in range(count)]
    values += [-v for v in values] + [float(n - 500) for n in range(1000)]
    return values + list(range(-500, 500)) + [0.0, -0.0, 0]


def recorded(fmt: NumberFormat) -> tuple[Any, Any, list[Any]]:
    """The reference, the generated function, and the values it leaves to the exact path."""
    reference = compile_decimal(fmt)
    left: list[Any] = []

    def fallback(value: Any) -> str:
        left.append(value)
        return reference(value)

    return reference, compile_special(fmt, fallback), left


@pytest.mark.parametrize(("machine", "name", "fmt"), BUNDLED,
                         ids=[f"{m}-{n}" for m, n, _ in BUNDLED])
def test_bundled_formats_write_common_numbers_on_the_generated_path(
        machine: str, name: str, fmt: NumberFormat) -> None:
    reference, generated, left = recorded(fmt)
    if fmt.decimals >= 11:  # vmc500's raw stock size (14 decimals): the exact path
        assert generated is None and special_source(fmt) is None
        return
    assert generated is not None
    assert fmt.render.__code__.co_filename == generated.__code__.co_filename
    values = raster(3000)
    assert [generated(v) for v in values] == [reference(v) for v in values]
    # only values within the tie guard (0.2 % of a full-digit coordinate's) are left
    assert len(left) <= 0.01 * len(values), left[:10]


@pytest.mark.parametrize(("options", "value", "expected"), [
    ({"decimals": 3, "multiplier": 10}, 0.26755, "2.676"),
    ({"integer": True}, 2.5, "3"),
    ({"integer": True, "rounding": "half_even"}, 2.5, "2"),
    ({"decimals": 1, "point": "never"}, -0.05, "-1"),
    ({"decimals": 3, "max_digits": 4}, 9999.9995, "DigitsError"),
    ({"integer": True, "max_digits": 12}, 999999999999.6, "DigitsError"),
    ({"decimals": 4}, 5e-05, "0.0001"),  # a half whose repr has an exponent
    ({"decimals": 3}, "12.5", "TypeError"),
    ({"decimals": 3}, Decimal("2.0005"), "2.001"),
    ({"decimals": 3}, True, "1.000"),
])
def test_ties_errors_and_other_types_are_left_to_the_exact_path(
        options: dict[str, Any], value: Any, expected: str) -> None:
    fmt = NumberFormat.from_mapping(options)
    _reference, generated, left = recorded(fmt)
    assert generated is not None
    kind, text = outcome(generated, value)
    assert (text if kind == "text" else kind) == expected
    assert left == [value]
    assert outcome(fmt.render, value) == (kind, text)


@pytest.mark.parametrize(("options", "value", "expected"), [
    ({"decimals": 2}, 2.675, "2.68"),  # the double is 2.67499999...: format says 2.67
    ({"decimals": 3}, -4.3755, "-4.376"),
    ({"decimals": 3, "trailing_zeros": False}, -84.5455, "-84.546"),
    ({"decimals": 3}, 1.2344999, "1.234"),  # near a half, below it in the text
    ({"decimals": 3}, -0.0004999, "0.000"),  # rounds to zero: never "-0.000"
    ({"decimals": 3}, 0.0005, "0.001"),
    ({"decimals": 2, "rounding": "half_even"}, 2.665, "2.66"),  # to the even digit
    ({"decimals": 2, "rounding": "half_even"}, 2.675, "2.68"),
    ({"decimals": 2, "rounding": "half_even"}, 2.66500001, "2.67"),  # past the half
    ({"decimals": 2, "rounding": "half_even", "sign": "always", "leading_zeros": 2},
     -0.125, "-00.12"),
])
def test_a_tie_of_the_double_is_decided_on_the_generated_path_by_its_repr(
        options: dict[str, Any], value: float, expected: str) -> None:
    """The digits of the repr, which the exact path rounds, decide a half there too:
    the value is moved a hundredth of a unit that way and written as any other."""
    fmt = NumberFormat.from_mapping(options)
    reference, generated, left = recorded(fmt)
    assert generated is not None
    assert outcome(generated, value) == ("text", expected) == outcome(reference, value)
    assert left == []


@pytest.mark.parametrize(("options", "lines"), [
    # vmc500's coordinate: one format call and one rstrip for a positive number
    ({"decimals": 3, "trailing_zeros": False, "point": "always"},
     ["return value.__format__('.3f').rstrip('0')"]),
    # a whole-number format rounds the scaled value as an integer
    ({"integer": True, "leading_zeros": 2}, ["return ('%02d' % (value + 0.5))",
                                             "return ('%03d' % (value - 0.5))"]),
    # ints times a whole multiplier are written as ints, with the zeros of the fraction
    ({"decimals": 3, "multiplier": 60}, ["n = value * 60", "return (str(n) + '.000')"]),
    # a sign or zeros the C formatting would write slowly are added as text
    ({"decimals": 3, "sign": "always", "leading_zeros": 2, "trailing_zeros": False,
      "min_decimals": 1}, ["t = ('%06.3f' % value)",
                           "u = t.rstrip('0')",
                           "return ('+' + (t[:-2] if u[-1] == '.' else u))"]),
    # printf rounding has no tie guard, only a zero that must not be "-0.000"
    ({"decimals": 3, "rounding": "binary"}, ["return value.__format__('.3f')",
                                             "if t == '-0.000':"]),
])
def test_generated_text_is_specialised_to_the_options(options: dict[str, Any],
                                                      lines: list[str]) -> None:
    source = special_source(NumberFormat.from_mapping(options))
    assert source is not None
    written = [line.strip() for line in source.splitlines()]
    for line in lines:
        assert line in written


@given(fmt=formats(), data=st.data())
def test_block_number_text_in_line_is_the_render_functions(fmt: NumberFormat,
                                                            data: st.DataObject) -> None:
    """A block number's text written in line (``count_text``) is what the format's
    render function writes, for every int of the numbering's range; where the render
    would do more than its int branch, nothing is written in line."""
    low = data.draw(st.sampled_from([0, 1, 2, 10, 100]), label="start")
    high = data.draw(st.sampled_from([9, 99, 9999, 99999, 10**8 - 1, 10**12]), label="maximum")
    expression = count_text(fmt, "number", low, high)
    if expression is None:
        return
    assert low >= 1 and float(fmt.multiplier) >= 1  # zero and negatives go to the call
    render = compile_render(fmt)
    code = compile(expression, "<block number>", "eval")
    for number in {low, high, data.draw(st.integers(low, high), label="number")}:
        assert eval(code, {}, {"number": number}) == render(number)  # our own text


@pytest.mark.parametrize(("options", "low", "high", "expected"), [
    ({"integer": True}, 10, 99999, "str(number)"),  # every bundled post's numbering
    ({"integer": True, "leading_zeros": 4}, 1, 9999, "str(number).zfill(4)"),
    ({"integer": True}, 0, 99999, None),  # a zero has its own text
    ({"integer": True, "max_digits": 4}, 1, 99999, None),  # past its digits: an error
    ({"integer": True, "multiplier": -1}, 1, 99, None),
])
def test_block_number_text_in_line(options: dict[str, Any], low: int, high: int,
                                   expected: str | None) -> None:
    assert count_text(NumberFormat.from_mapping(options), "number", low, high) == expected
