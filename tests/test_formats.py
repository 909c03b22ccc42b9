"""Tests of postdsl.lang.formats: every digit of every NC word comes from here.

The property tests check ``render`` against an independent oracle built on
``fractions.Fraction`` (exact rational arithmetic, half away from zero written
out by hand), so they do not share the decimal code they are checking.
"""

from __future__ import annotations

import copy
import dataclasses
import pickle
import threading
from decimal import ROUND_DOWN, Decimal, localcontext
from fractions import Fraction
from types import MappingProxyType
from typing import Any

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from postdsl.lang.formats import MAX_DECIMALS, FormatSpecError, NumberFormat

COORD = NumberFormat(decimals=3, trailing_zeros=False, point="always")
CYCLE = NumberFormat(decimals=4, trailing_zeros=False, min_decimals=1)
SINUMERIK = NumberFormat(decimals=3)
FEED = NumberFormat(integer=True, multiplier=60)


# ---------------------------------------------------------------- oracle


def half_away(value: float | int, decimals: int, multiplier: float | int = 1) -> Fraction:
    """The exact result render must write: shortest repr, scaled, rounded half away from 0."""
    exact = Fraction(repr(value)) * Fraction(repr(multiplier))
    scaled = exact * 10**decimals
    magnitude = int(abs(scaled) + Fraction(1, 2))  # floor, as the operand is >= 0
    return Fraction(-magnitude if scaled < 0 else magnitude, 10**decimals)


def read_back(text: str, fmt: NumberFormat) -> Fraction:
    """The number an NC controller reads from ``text`` written with ``fmt``."""
    number = Decimal(text.strip())
    if fmt.point == "never":
        number = number.scaleb(-fmt.decimals)
    return Fraction(number)


def assert_no_negative_zero(text: str) -> None:
    body = text.strip()
    if body.startswith("-0") or body.startswith("+0"):
        assert any(c in "123456789" for c in body), text
    if Decimal(body) == 0:
        assert body[0] not in "+-", text


# ---------------------------------------------------------------- reference NC programs

REFERENCE_CASES = [
    # coordinates: decimals 3, trimmed, point always
    (COORD, 40, "40."),
    (COORD, 16.9957, "16.996"),
    (COORD, -5, "-5."),
    (COORD, 0, "0."),
    (COORD, 40.0, "40."),
    (COORD, -5.0, "-5."),
    (COORD, 0.0, "0."),
    # cycle values: decimals 4, trimmed to at least 1
    (CYCLE, 50, "50.0"),
    (CYCLE, 53.0043, "53.0043"),
    (CYCLE, 70, "70.0"),
    (CYCLE, 200, "200.0"),
    (CYCLE, 0.5, "0.5"),
    (CYCLE, 50.0, "50.0"),
    # Sinumerik: decimals 3, trailing zeros kept
    (SINUMERIK, 6, "6.000"),
    (SINUMERIK, -20, "-20.000"),
    (SINUMERIK, 12.5, "12.500"),
    (SINUMERIK, -6.4775, "-6.478"),
    # feed: integer, mm/s -> mm/min
    (FEED, 3.3333, "200"),
    # raw-looking stock dimensions
    (NumberFormat(decimals=14, trailing_zeros=False), 9.99999999999999, "9.99999999999999"),
    (NumberFormat(decimals=14, trailing_zeros=False), 50, "50"),
    (NumberFormat(decimals=14, trailing_zeros=False), 50.0, "50"),
    # FeatureCAM style
    (NumberFormat(leading_zeros=3, decimals=1, trailing_zeros=True, point="always"), 10, "010.0"),
    (NumberFormat(leading_zeros=3, sign="always", integer=True), 10, "+010"),
    (NumberFormat(leading_zeros=2, integer=True), 7, "07"),
    # old Fanuc: implied decimal point
    (NumberFormat(decimals=3, point="never"), 1.5, "1500"),
    (NumberFormat(decimals=3, point="never"), -0.25, "-250"),
    (NumberFormat(decimals=3, point="never"), 0, "0"),
]


@pytest.mark.parametrize(("fmt", "value", "expected"), REFERENCE_CASES)
def test_reference_programs(fmt: NumberFormat, value: float, expected: str) -> None:
    assert fmt.render(value) == expected


# ---------------------------------------------------------------- every option

OPTION_CASES: list[tuple[dict[str, Any], float | int, str]] = [
    # decimals
    ({"decimals": 0}, 12.5, "13"),
    ({"decimals": 0}, 12.4, "12"),
    ({"decimals": 1}, 12.25, "12.3"),
    ({"decimals": 3}, 12.5, "12.500"),
    ({"decimals": 6}, 0.0000005, "0.000001"),
    ({"decimals": 7}, 0.0000001, "0.0000001"),
    ({"decimals": 12}, 1e-7, "0.000000100000"),
    ({"decimals": 12}, 1 / 3, "0.333333333333"),
    ({"decimals": 15}, 0.1, "0.100000000000000"),
    ({"decimals": 15, "trailing_zeros": False}, 1e-15, "0.000000000000001"),
    ({"decimals": 15, "trailing_zeros": False}, 4e-16, "0"),
    # trailing_zeros
    ({"trailing_zeros": True}, 1.5, "1.500"),
    ({"trailing_zeros": False}, 1.5, "1.5"),
    ({"trailing_zeros": False}, 2, "2"),
    ({"trailing_zeros": False}, 2.0, "2"),
    ({"trailing_zeros": False}, 2.0004, "2"),
    ({"trailing_zeros": False}, 2.0005, "2.001"),
    # min_decimals
    ({"trailing_zeros": False, "min_decimals": 1}, 50, "50.0"),
    ({"trailing_zeros": False, "min_decimals": 2}, 50.5, "50.50"),
    ({"trailing_zeros": False, "min_decimals": 2}, 50.125, "50.125"),
    ({"trailing_zeros": False, "min_decimals": 3}, 0, "0.000"),
    ({"trailing_zeros": True, "min_decimals": 1}, 50, "50.000"),  # no effect when keeping
    # point
    ({"point": "needed", "decimals": 0}, 40, "40"),
    ({"point": "always", "decimals": 0}, 40, "40."),
    ({"point": "always", "decimals": 0}, 39.5, "40."),
    ({"point": "needed", "trailing_zeros": False}, 40.0, "40"),
    ({"point": "always", "trailing_zeros": False}, 40.0, "40."),
    ({"point": "always"}, 40, "40.000"),
    ({"point": "never"}, 40, "40000"),
    ({"point": "never", "decimals": 0}, 40.4, "40"),
    ({"point": "never", "decimals": 0}, 0, "0"),
    ({"point": "never"}, 0.5, "500"),
    ({"point": "never"}, 0.0004, "0"),
    ({"point": "never"}, 0.001, "1"),
    ({"point": "never"}, -0.001, "-1"),
    ({"point": "never", "leading_zeros": 1}, 0.5, "0500"),
    ({"point": "never", "leading_zeros": 3}, 1.5, "001500"),
    # leading_zeros
    ({"leading_zeros": 0}, 0.5, "0.500"),
    ({"leading_zeros": 0, "trailing_zeros": False}, 0.5, "0.5"),
    ({"leading_zeros": 1}, 0.5, "0.500"),
    ({"leading_zeros": 3, "decimals": 1, "point": "always"}, 10, "010.0"),
    ({"leading_zeros": 3, "decimals": 1}, -10, "-010.0"),
    ({"leading_zeros": 2}, 123.4, "123.400"),  # never cuts digits
    ({"leading_zeros": 4, "decimals": 0}, 0, "0000"),
    # width
    ({"width": 8}, 1.5, "   1.500"),
    ({"width": 8}, -1.5, "  -1.500"),
    ({"width": 3}, 1234.5, "1234.500"),  # never cuts digits
    ({"width": 5, "integer": True}, 42, "   42"),
    # sign
    ({"sign": "negative"}, 1.5, "1.500"),
    ({"sign": "negative"}, -1.5, "-1.500"),
    ({"sign": "always"}, 1.5, "+1.500"),
    ({"sign": "always"}, -1.5, "-1.500"),
    ({"sign": "always"}, 0, "0.000"),
    ({"sign": "always"}, 0.0001, "0.000"),
    ({"sign": "always"}, -0.0001, "0.000"),
    ({"sign": "never"}, -1.5, "1.500"),
    ({"sign": "never"}, 1.5, "1.500"),
    ({"sign": "always", "point": "never"}, 0.25, "+250"),
    # multiplier
    ({"integer": True, "multiplier": 60}, 3.3333, "200"),
    ({"integer": True, "multiplier": 60.0}, 3.3333, "200"),
    ({"integer": True, "multiplier": 1000}, 0.5, "500"),
    ({"integer": True, "multiplier": 1000.0}, 0.5, "500"),
    ({"integer": True, "multiplier": 60}, 5, "300"),
    ({"multiplier": 0.001}, 1500, "1.500"),
    ({"multiplier": 0.1}, 3, "0.300"),  # not 0.30000000000000004
    ({"multiplier": 25.4, "decimals": 4}, 0.1, "2.5400"),
    ({"multiplier": -1}, 2.5, "-2.500"),
    ({"multiplier": -1}, 0, "0.000"),
    ({"multiplier": 2, "decimals": 0}, 1.25, "3"),
    # integer
    ({"integer": True}, 7, "7"),
    ({"integer": True}, 7.5, "8"),
    ({"integer": True}, -7.5, "-8"),
    ({"integer": True}, 7.49, "7"),
    ({"integer": True}, 0.4, "0"),
    ({"integer": True}, -0.4, "0"),
    ({"integer": True, "decimals": 0}, 2.5, "3"),
    ({"integer": True, "trailing_zeros": False}, 2.5, "3"),
]


@pytest.mark.parametrize(("options", "value", "expected"), OPTION_CASES)
def test_options(options: dict[str, Any], value: float, expected: str) -> None:
    assert NumberFormat(**options).render(value) == expected
    assert NumberFormat.from_mapping(options).render(value) == expected


# ---------------------------------------------------------------- rounding


@pytest.mark.parametrize(
    ("decimals", "value", "expected"),
    [
        (2, 2.675, "2.68"),  # the double is 2.67499999..., the user wrote 2.675
        (2, -2.675, "-2.68"),
        (3, 0.0005, "0.001"),
        (3, -0.0005, "-0.001"),
        (3, 0.0004, "0.000"),
        (3, -0.0004, "0.000"),
        (3, 1.0005, "1.001"),
        (3, -1.0005, "-1.001"),
        (3, 1.2345, "1.235"),  # half even would give 1.234
        (3, -1.2345, "-1.235"),
        (1, 0.25, "0.3"),
        (1, -0.25, "-0.3"),
        (0, 0.5, "1"),
        (0, -0.5, "-1"),
        (0, 1.5, "2"),
        (0, 2.5, "3"),
        (0, -2.5, "-3"),
        (0, 0.49999999999999994, "0"),  # float(x + 0.5) would say 1
        (0, -0.49999999999999994, "0"),
        (0, 4503599627370495.5, "4503599627370496"),  # largest float with a half
        (0, -4503599627370495.5, "-4503599627370496"),
        (0, 9007199254740993.0, "9007199254740992"),  # beyond 2**53: the float itself
        (3, 1e22, "10000000000000000000000.000"),
        (0, 1e23, "1" + "0" * 23),  # repr 1e+23, not the double 99999999999999991611392
    ],
)
def test_round_half_away_from_zero(decimals: int, value: float, expected: str) -> None:
    assert NumberFormat(decimals=decimals).render(value) == expected


@pytest.mark.parametrize(
    "value", [0.5, 1.5, 2.5, -0.5, -1.5, -2.5, 0.49999999999999994, 1e15 + 0.5]
)
def test_integer_fast_path_agrees_with_decimals_zero(value: float) -> None:
    # integer formats with multiplier 1 round floats with float arithmetic; a multiplier
    # of -1 on the negated value forces the decimal path for the same number
    expected = half_away(value, 0)
    assert Fraction(NumberFormat(integer=True).render(value)) == expected
    assert Fraction(NumberFormat(decimals=0, multiplier=-1).render(-value)) == expected


def test_large_values_are_exact() -> None:
    assert NumberFormat(integer=True).render(1e300) == "1" + "0" * 300
    assert NumberFormat(integer=True).render(10**40 + 1) == "1" + "0" * 39 + "1"
    assert NumberFormat(multiplier=0.5).render(10**40 + 1) == "5" + "0" * 38 + "0.500"
    assert NumberFormat(decimals=3).render(-1.7976931348623157e308).startswith("-17976931348623157")


def test_ignores_the_callers_decimal_context() -> None:
    with localcontext() as ctx:
        ctx.prec = 2
        ctx.rounding = ROUND_DOWN
        assert NumberFormat(decimals=3).render(16.9957) == "16.996"
        assert NumberFormat(decimals=3, multiplier=60).render(123.4567) == "7407.402"


@pytest.mark.parametrize(
    "value", [-0.0, -1e-5, -4e-5, -4.9999e-5, -1e-300, -5e-324, Decimal("-0"), Decimal("-1E-9")]
)
@pytest.mark.parametrize(
    "fmt",
    [
        COORD,
        CYCLE,
        SINUMERIK,
        NumberFormat(integer=True),
        NumberFormat(decimals=0),
        NumberFormat(point="never"),
        NumberFormat(sign="always", trailing_zeros=False),
        NumberFormat(leading_zeros=3, point="always"),
        NumberFormat(decimals=3, multiplier=0.001),
    ],
)
def test_no_negative_zero(fmt: NumberFormat, value: float) -> None:
    text = fmt.render(value)
    assert "-" not in text
    assert "+" not in text
    assert Decimal(text.strip()) == 0


# ---------------------------------------------------------------- input types


@pytest.mark.parametrize(
    ("fmt", "value", "expected"),
    [
        (COORD, True, "1."),
        (COORD, False, "0."),
        (NumberFormat(integer=True), True, "1"),
        (SINUMERIK, True, "1.000"),
        (SINUMERIK, Decimal("2.675"), "2.675"),
        (NumberFormat(decimals=2), Decimal("2.675"), "2.68"),
        (NumberFormat(decimals=2), Decimal("-2.675"), "-2.68"),
        (NumberFormat(decimals=2, multiplier=60), Decimal("0.01"), "0.60"),
    ],
)
def test_other_number_types(fmt: NumberFormat, value: Any, expected: str) -> None:
    assert fmt.render(value) == expected


def test_int_and_float_subclasses() -> None:
    class Meters(float):
        def __repr__(self) -> str:  # a subclass repr must not leak into the NC text
            return f"Meters({float(self)})"

    class Count(int):
        pass

    assert COORD.render(Meters(16.9957)) == "16.996"
    assert COORD.render(Count(3)) == "3."


@pytest.mark.parametrize("value", ["1.5", None, b"1", 1j, [1], Fraction(1, 2), object()])
def test_non_numbers_raise_type_error(value: Any) -> None:
    with pytest.raises(TypeError):
        COORD.render(value)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (float("nan"), "cannot write nan"),
        (float("inf"), "cannot write inf"),
        (float("-inf"), "cannot write -inf"),
        (Decimal("nan"), "cannot write NaN"),
        (Decimal("-Infinity"), "cannot write -Infinity"),
    ],
)
@pytest.mark.parametrize("fmt", [COORD, FEED, NumberFormat(integer=True)])
def test_non_finite_raise_value_error(fmt: NumberFormat, value: Any, message: str) -> None:
    with pytest.raises(ValueError, match=f"^{message}$"):
        fmt.render(value)


def test_render_through_the_class() -> None:
    assert NumberFormat.render(COORD, 40) == "40."


# ---------------------------------------------------------------- from_mapping errors

SPEC_ERRORS: list[tuple[Any, str | None, str]] = [
    ({"point": "sometimes"}, "point",
     "point must be one of always, needed, never, not 'sometimes'"),
    ({"sign": "positive"}, "sign", "sign must be one of negative, always, never, not 'positive'"),
    ({"sign": 1}, "sign", "sign must be one of negative, always, never, not 1"),
    ({"decimals": True}, "decimals", "decimals must be an integer, not True"),
    ({"decimals": 3.0}, "decimals", "decimals must be an integer, not 3.0"),
    ({"decimals": "3"}, "decimals", "decimals must be an integer, not '3'"),
    ({"decimals": -1}, "decimals", f"decimals must be from 0 to {MAX_DECIMALS}, not -1"),
    ({"decimals": MAX_DECIMALS + 1}, "decimals",
     f"decimals must be from 0 to {MAX_DECIMALS}, not {MAX_DECIMALS + 1}"),
    ({"trailing_zeros": "no"}, "trailing_zeros", "trailing_zeros must be true or false, not 'no'"),
    ({"trailing_zeros": 0}, "trailing_zeros", "trailing_zeros must be true or false, not 0"),
    ({"min_decimals": False}, "min_decimals", "min_decimals must be an integer, not False"),
    ({"min_decimals": -1}, "min_decimals", "min_decimals must be from 0 to 15, not -1"),
    ({"trailing_zeros": False, "min_decimals": 4}, "min_decimals",
     "min_decimals must be at most decimals (3), not 4"),
    ({"decimals": 1, "trailing_zeros": False, "min_decimals": 2}, "min_decimals",
     "min_decimals must be at most decimals (1), not 2"),
    ({"integer": True, "min_decimals": 1}, "min_decimals",
     "min_decimals must be at most decimals (0), not 1"),
    ({"leading_zeros": 1.5}, "leading_zeros", "leading_zeros must be an integer, not 1.5"),
    ({"leading_zeros": 13}, "leading_zeros", "leading_zeros must be from 0 to 12, not 13"),
    ({"width": -1}, "width", "width must be from 0 to 40, not -1"),
    ({"width": None}, "width", "width must be an integer, not None"),
    ({"multiplier": "60"}, "multiplier", "multiplier must be a number, not '60'"),
    ({"multiplier": True}, "multiplier", "multiplier must be a number, not True"),
    ({"multiplier": 0}, "multiplier", "multiplier must not be 0"),
    ({"multiplier": 0.0}, "multiplier", "multiplier must not be 0"),
    ({"multiplier": 1e300}, "multiplier", "multiplier must lie between 1e-06 and 1e+06 "
                                          "(either sign), not 1e+300"),
    ({"multiplier": -1e-9}, "multiplier", "multiplier must lie between 1e-06 and 1e+06 "
                                          "(either sign), not -1e-09"),
    ({"multiplier": float("nan")}, "multiplier", "multiplier must be a finite number, not nan"),
    ({"multiplier": float("inf")}, "multiplier", "multiplier must be a finite number, not inf"),
    ({"integer": "yes"}, "integer", "integer must be true or false, not 'yes'"),
    ({"integer": True, "decimals": 2}, "decimals",
     "decimals must be 0 or left out when integer is true, not 2"),
    ({"integer": True, "decimals": 3}, "decimals",
     "decimals must be 0 or left out when integer is true, not 3"),
    ({"integer": True, "point": "always"}, "point",
     "point must be left out when integer is true (whole numbers are written without a point), "
     "not 'always'"),
    ({"integer": True, "point": "never"}, "point",
     "point must be left out when integer is true (whole numbers are written without a point), "
     "not 'never'"),
    ({"point": "never", "trailing_zeros": False}, "point",
     "point 'never' needs trailing_zeros true: with an implied decimal point every decimal "
     "digit must be written"),
    ({"decimal": 3}, "decimal",
     "unknown option 'decimal' (did you mean 'decimals'?); options are decimals, trailing_zeros, "
     "min_decimals, point, leading_zeros, width, sign, multiplier, integer, max_digits, "
     "rounding, zero_sign"),
    ({"colour": "red"}, "colour",
     "unknown option 'colour'; options are decimals, trailing_zeros, min_decimals, point, "
     "leading_zeros, width, sign, multiplier, integer, max_digits, rounding, zero_sign"),
    ({3: 1}, "3", "option names must be text, not 3"),
    ([("decimals", 3)], None, "a number format must be a mapping of options, not list"),
    (None, None, "a number format must be a mapping of options, not NoneType"),
]


@pytest.mark.parametrize(("data", "key", "message"), SPEC_ERRORS)
def test_from_mapping_errors_name_their_key(data: Any, key: str | None, message: str) -> None:
    with pytest.raises(FormatSpecError) as caught:
        NumberFormat.from_mapping(data)
    assert caught.value.key == key
    assert caught.value.message == message
    assert str(caught.value) == message
    assert isinstance(caught.value, ValueError)


OPTION_NAMES = {f.name for f in dataclasses.fields(NumberFormat)}


@pytest.mark.parametrize(
    "data",
    [
        data
        for data, _, _ in SPEC_ERRORS
        if isinstance(data, dict)
        and set(data) <= OPTION_NAMES
        and data != {"integer": True, "decimals": 3}  # see the next test
    ],
)
def test_constructor_validates_too(data: dict[str, Any]) -> None:
    with pytest.raises(FormatSpecError):
        NumberFormat(**data)


def test_constructor_treats_decimals_3_as_the_default_with_integer() -> None:
    # the constructor cannot tell decimals=3 from the default; from_mapping can
    assert NumberFormat(integer=True, decimals=3) == NumberFormat(integer=True)
    assert NumberFormat(integer=True).decimals == 0


def test_spec_error_pickles_with_its_key() -> None:
    error = FormatSpecError(key="point", message="point must be one of ...")
    clone = pickle.loads(pickle.dumps(error))
    assert (clone.key, clone.message, str(clone)) == ("point", "point must be one of ...",
                                                      "point must be one of ...")


def test_from_mapping_accepts_any_mapping() -> None:
    assert NumberFormat.from_mapping(MappingProxyType({"decimals": 2})) == NumberFormat(decimals=2)
    assert NumberFormat.from_mapping({}) == NumberFormat()


# ---------------------------------------------------------------- to_mapping, describe

MAPPINGS: list[dict[str, Any]] = [
    {},
    {"trailing_zeros": False, "point": "always"},
    {"decimals": 4, "trailing_zeros": False, "min_decimals": 1},
    {"multiplier": 60, "integer": True},
    {"decimals": 14, "trailing_zeros": False},
    {"decimals": 1, "point": "always", "leading_zeros": 3},
    {"leading_zeros": 3, "sign": "always", "integer": True},
    {"leading_zeros": 2, "integer": True},
    {"point": "never"},
    {"decimals": 0, "point": "always", "width": 6, "sign": "never", "multiplier": 0.001},
]


@pytest.mark.parametrize("data", MAPPINGS)
def test_to_mapping_round_trips(data: dict[str, Any]) -> None:
    fmt = NumberFormat.from_mapping(data)
    assert fmt.to_mapping() == data
    assert list(fmt.to_mapping()) == list(data)  # declared key order
    assert NumberFormat.from_mapping(fmt.to_mapping()) == fmt


def test_to_mapping_leaves_out_what_integer_implies() -> None:
    assert NumberFormat(integer=True, decimals=0).to_mapping() == {"integer": True}
    assert NumberFormat(multiplier=1).to_mapping() == {}
    assert NumberFormat(decimals=0).to_mapping() == {"decimals": 0}


@pytest.mark.parametrize(
    ("fmt", "line"),
    [
        (COORD, "3 decimals, trim zeros, point always"),
        (CYCLE, "4 decimals, trim zeros (keep 1)"),
        (SINUMERIK, "3 decimals"),
        (FEED, "integer, times 60"),
        (NumberFormat(decimals=1, point="always", leading_zeros=3), "1 decimal, point always, "
                                                                    "3 integer digits"),
        (NumberFormat(decimals=0), "no decimals"),
        (NumberFormat(point="never", sign="always", width=8, multiplier=0.001),
         "3 decimals, implied point, sign always, times 0.001, width 8"),
        (NumberFormat(sign="never"), "3 decimals, no sign"),
    ],
)
def test_describe(fmt: NumberFormat, line: str) -> None:
    assert fmt.describe() == line


# ---------------------------------------------------------------- value semantics


def test_value_semantics() -> None:
    assert NumberFormat(decimals=3, trailing_zeros=False, point="always") == COORD
    assert hash(COORD) == hash(NumberFormat(decimals=3, trailing_zeros=False, point="always"))
    assert NumberFormat(multiplier=60) == NumberFormat(multiplier=60.0)
    assert COORD != CYCLE
    assert repr(COORD) == (
        "NumberFormat(decimals=3, trailing_zeros=False, min_decimals=0, point='always', "
        "leading_zeros=0, width=0, sign='negative', multiplier=1.0, integer=False, "
        "max_digits=None, rounding='half_away', zero_sign='none')"
    )
    with pytest.raises(dataclasses.FrozenInstanceError):
        COORD.decimals = 4  # type: ignore[misc]


@pytest.mark.parametrize(
    "clone",
    [
        lambda f: pickle.loads(pickle.dumps(f)),
        copy.copy,
        copy.deepcopy,
        dataclasses.replace,
    ],
)
def test_copies_render_the_same(clone: Any) -> None:
    for fmt in (COORD, CYCLE, FEED, NumberFormat(point="never", width=7)):
        other = clone(fmt)
        assert other == fmt
        assert other.render(-16.9957) == fmt.render(-16.9957)


def test_replace_recompiles() -> None:
    assert dataclasses.replace(COORD, decimals=1).render(16.9957) == "17."


def test_thread_safe() -> None:
    values = [i / 7 - 500 for i in range(2000)]
    expected = [COORD.render(v) for v in values]
    results: list[list[str]] = []

    def work() -> None:
        results.append([COORD.render(v) for v in values])

    threads = [threading.Thread(target=work) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert results == [expected] * 4


# ---------------------------------------------------------------- properties

finite_floats = st.floats(allow_nan=False, allow_infinity=False, min_value=-1e12, max_value=1e12)
any_floats = st.floats(allow_nan=False, allow_infinity=False)


@st.composite
def ties(draw: st.DrawFn, decimals: int) -> float:
    """Floats whose shortest repr ends exactly on a half at the rounding place."""
    k = draw(st.integers(min_value=-(10**9), max_value=10**9))
    return float(f"{k}5e-{decimals + 1}")


@st.composite
def formats(draw: st.DrawFn) -> NumberFormat:
    """Any valid format, from its options."""
    integer = draw(st.booleans())
    decimals = 0 if integer else draw(st.integers(0, MAX_DECIMALS))
    point = "needed" if integer else draw(st.sampled_from(["always", "needed", "never"]))
    trailing = True if point == "never" else draw(st.booleans())
    return NumberFormat(
        decimals=decimals,
        trailing_zeros=trailing,
        min_decimals=draw(st.integers(0, decimals)),
        point=point,
        leading_zeros=draw(st.integers(0, 12)),
        width=draw(st.integers(0, 40)),
        sign=draw(st.sampled_from(["negative", "always", "never"])),
        multiplier=draw(st.sampled_from([1.0, 1, 60, 1000.0, 0.001, 25.4, -1, 1 / 3])),
        integer=integer,
    )


TRIMMED = NumberFormat(decimals=3, trailing_zeros=False)
KEPT = NumberFormat(decimals=3)
ALWAYS = NumberFormat(decimals=3, trailing_zeros=False, point="always")
IMPLIED = NumberFormat(decimals=3, point="never")
FORMS = [TRIMMED, KEPT, ALWAYS, IMPLIED, CYCLE, FEED, NumberFormat(integer=True),
         NumberFormat(decimals=14, trailing_zeros=False)]


@pytest.mark.parametrize("fmt", FORMS, ids=lambda f: f.describe())
@given(value=st.one_of(finite_floats, any_floats, ties(2), ties(3), ties(0),
                       st.integers(-(10**20), 10**20)))
@example(value=2.675)
@example(value=-0.0005)
@example(value=-0.0)
def test_render_round_trips(fmt: NumberFormat, value: float) -> None:
    text = fmt.render(value)
    assert read_back(text, fmt) == half_away(value, fmt.decimals, fmt.multiplier)
    assert_no_negative_zero(text)


@pytest.mark.parametrize("fmt", FORMS, ids=lambda f: f.describe())
@given(value=st.one_of(finite_floats, ties(3)))
def test_shape_of_the_text(fmt: NumberFormat, value: float) -> None:
    text = fmt.render(value)
    integral, point, fraction = text.lstrip("-").partition(".")
    assert integral.isdigit()
    assert not fraction or fraction.isdigit()
    if fmt.point == "always":
        assert point
    if fmt.point == "never" or fmt.integer:
        assert not point
    if fmt.trailing_zeros and fmt.point != "never" and fmt.decimals:
        assert len(fraction) == fmt.decimals
    if not fmt.trailing_zeros and len(fraction) > fmt.min_decimals:
        assert not fraction.endswith("0")


@given(fmt=formats(), value=st.one_of(finite_floats, ties(3), st.integers(-(10**15), 10**15)))
def test_any_format_round_trips(fmt: NumberFormat, value: float) -> None:
    text = fmt.render(value)
    assert len(text) >= fmt.width
    assert text == text.strip().rjust(fmt.width)
    expected = half_away(value, fmt.decimals, fmt.multiplier)
    if fmt.sign == "never":
        expected = abs(expected)
    assert read_back(text, fmt) == expected
    assert_no_negative_zero(text)
    if fmt.sign == "always" and expected > 0:
        assert text.strip().startswith("+")
    digits = text.strip().lstrip("+-").partition(".")[0]
    if fmt.point != "never":
        assert len(digits) >= max(fmt.leading_zeros, 1)


@given(fmt=formats(), value=st.integers(-(10**15), 10**15))
def test_ints_render_like_equal_floats(fmt: NumberFormat, value: int) -> None:
    exact: Any = Decimal(value)  # accepted at runtime, outside the declared float | int
    assert fmt.render(value) == fmt.render(float(value)) == fmt.render(exact)


@given(fmt=formats())
def test_any_format_round_trips_through_its_mapping(fmt: NumberFormat) -> None:
    assert NumberFormat.from_mapping(fmt.to_mapping()) == fmt


@given(value=st.floats(min_value=-0.0005, max_value=0.0, allow_nan=False, exclude_max=False))
def test_tiny_negatives_never_write_minus_zero(value: float) -> None:
    for fmt in (COORD, SINUMERIK, TRIMMED, IMPLIED, NumberFormat(sign="always")):
        text = fmt.render(value)
        assert_no_negative_zero(text)
        assert text.startswith("-") == (value <= -0.0005)
