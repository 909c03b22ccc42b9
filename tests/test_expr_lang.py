"""The expression language's additions of issue 12: trigonometry, ``a if c else b``,
``str(x, 'format')`` and indexing.

Python is the oracle where the meaning is Python's (the functions of ``math``, the
conditional expression, indexing); the post's own format is the oracle of ``str()``.
Everything else is an error that quotes the sub-expression, tested by example.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from postdsl.lang.expr import MAX_DEPTH, ExprError, ExprEvalError, compile_expr
from postdsl.lang.formats import NumberFormat


@dataclass
class Scope:
    values: Mapping[str, Any] = field(default_factory=dict)
    changed: set[str] = field(default_factory=set)


FORMATS = {
    "coord": NumberFormat(decimals=3, max_digits=6),
    "angle": NumberFormat(decimals=1, trailing_zeros=False),
    "tool": NumberFormat(integer=True, leading_zeros=2),
}


def run(source: str, **values: Any) -> Any:
    return compile_expr(source, None, FORMATS).evaluate(Scope(values))


def run_error(source: str, **values: Any) -> str:
    expression = compile_expr(source, None, FORMATS)
    with pytest.raises(ExprEvalError) as info:
        expression.evaluate(Scope(values))
    return str(info.value)


def load_error(source: str, names: Any = None) -> ExprError:
    with pytest.raises(ExprError) as info:
        compile_expr(source, names, FORMATS)
    return info.value


finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False)

# ------------------------------------------------------------------------------------------
# Trigonometry
# ------------------------------------------------------------------------------------------


@given(x=finite)
def test_one_argument_functions_are_pythons(x: float) -> None:
    for name in ("sin", "cos", "tan", "degrees", "radians"):
        assert run(f"{name}(x)", x=x) == getattr(math, name)(x)


@given(y=finite, x=finite, z=finite)
def test_two_argument_functions_are_pythons(y: float, x: float, z: float) -> None:
    assert run("atan2(y, x)", x=x, y=y) == math.atan2(y, x)
    assert run("hypot(x, y)", x=x, y=y) == math.hypot(x, y)
    assert run("hypot(x, y, z)", x=x, y=y, z=z) == math.hypot(x, y, z)


@given(angle=st.floats(min_value=-720, max_value=720))
def test_degrees_and_radians_convert_both_ways(angle: float) -> None:
    assert run("degrees(radians(a))", a=angle) == pytest.approx(angle, abs=1e-9)


def test_a_polar_move_as_a_heidenhain_post_writes_it() -> None:
    # LP PR+ PA+: the polar radius and angle of the point (3, 3) about the pole (0, 0)
    assert run("hypot(x - cx, y - cy)", x=3, y=4, cx=0, cy=0) == 5.0
    assert run("degrees(atan2(y - cy, x - cx))", x=0, y=2, cx=0, cy=0) == 90.0


@pytest.mark.parametrize(
    ("source", "values", "message"),
    [
        ("sin(x) + 1", {"x": "ten"}, "sin() expects a number, got string in 'sin(x)'"),
        ("atan2(y, x)", {"x": 1, "y": None}, "parameter 'y' has no value"),
        ("degrees(x)", {"x": 1e308}, "number out of range (too large) in 'degrees(x)'"),
        ("cos(x)", {"x": 10**400}, "number out of range (too large) in 'cos(x)'"),
        ("hypot(x, x)", {"x": 1.7e308}, "number out of range (too large) in 'hypot(x, x)'"),
        ("tan(x)", {"x": [1]}, "tan() expects a number, got list in 'tan(x)'"),
    ],
)
def test_function_errors_quote_the_sub_expression(source: str, values: dict[str, Any],
                                                  message: str) -> None:
    assert run_error(source, **values) == message


@pytest.mark.parametrize(
    ("source", "message"),
    [
        ("sin()", "sin() takes 1 argument (0 given)"),
        ("atan2(1)", "atan2() takes 2 arguments (1 given)"),
        ("hypot(1, 2, 3, 4)", "hypot() takes 2 or 3 arguments (4 given)"),
        ("sine(x)", "unknown function 'sine'; did you mean 'sin'?"),
    ],
)
def test_function_arity_and_names_are_checked_at_load(source: str, message: str) -> None:
    assert load_error(source).message == message


# ------------------------------------------------------------------------------------------
# a if c else b
# ------------------------------------------------------------------------------------------

_operands = st.sampled_from(["a", "b", "c", "1", "0", "-2", "a + b", "a * c", "(a - b)"])
_tests = st.sampled_from(["a", "b < c", "a == b", "not c", "a and b", "a or c", "b > 0"])


def _conditional(depth: int) -> st.SearchStrategy[str]:
    if depth == 0:
        return _operands
    inner = _conditional(depth - 1)
    return st.one_of(
        inner,
        st.tuples(inner, _tests, inner).map(lambda t: f"{t[0]} if {t[1]} else {t[2]}"),
        st.tuples(inner, _tests, inner).map(lambda t: f"({t[0]} if {t[1]} else {t[2]}) + 1"),
        st.tuples(inner, _tests, inner).map(lambda t: f"2 * ({t[0]} if {t[1]} else {t[2]})"),
    )


@given(source=_conditional(3), a=st.integers(-3, 3), b=st.integers(-3, 3),
       c=st.integers(-3, 3))
def test_conditional_agrees_with_python(source: str, a: int, b: int, c: int) -> None:
    values = {"a": a, "b": b, "c": c}
    # The oracle: test-generated text only, run by Python with no builtins.
    expected = eval(source, {"__builtins__": {}}, dict(values))
    assert run(source, **values) == expected


def test_only_the_chosen_branch_is_evaluated() -> None:
    assert run("x if defined(x) else 0", x=None) == 0
    assert run("1 / n if n != 0 else 0", n=0) == 0
    assert run("0 if n == 0 else 1 / n", n=4) == 0.25
    # a constant test picks its branch when the post loads: the other may never run
    assert run("1 if true else 1 / 0") == 1


def test_a_failing_branch_is_reported_when_it_runs() -> None:
    assert run_error("1 / n if n > -1 else 0", n=0) == "division by zero in '1 / n'"


@pytest.mark.parametrize("depth", [MAX_DEPTH + 1, 150])
def test_chained_conditionals_are_bounded(depth: int) -> None:
    source = "x if y else " * depth + "z"
    assert "nested too deeply" in load_error(source).message


# ------------------------------------------------------------------------------------------
# Indexing
# ------------------------------------------------------------------------------------------


@given(items=st.lists(st.integers(-99, 99), max_size=6), position=st.integers(-8, 8))
def test_indexing_agrees_with_python_or_names_the_bounds(items: list[int],
                                                         position: int) -> None:
    if -len(items) <= position < len(items):
        assert run("tools[i]", tools=tuple(items), i=position) == items[position]
    else:
        count = "item" if len(items) == 1 else "items"
        assert run_error("tools[i] + 1", tools=items, i=position) == (
            f"index {position} is out of range ({len(items)} {count}) in 'tools[i]'")


def test_indexing_binds_tighter_than_any_operator() -> None:
    assert run("-tools[0] * 2", tools=[3, 4]) == -6
    assert run("tools[1 if first else 0]", tools=[3, 4], first=True) == 4
    assert run("names[1][0]", names=["ab", "cd"]) == "c"
    assert run("'T' + str(tools[-1], 'tool')", tools=[3, 12]) == "T12"


@pytest.mark.parametrize(
    ("source", "values", "message"),
    [
        ("tools[0]", {"tools": None}, "parameter 'tools' has no value"),
        ("tools[n]", {"tools": [1], "n": None}, "parameter 'n' has no value"),
        ("x[0]", {"x": 3.5}, "a subscript expects a list or a text, got float in 'x[0]'"),
        ("tools[1.0]", {"tools": [1, 2]},
         "a subscript expects a whole number, got float in 'tools[1.0]'"),
        ("tools[true]", {"tools": [1, 2]},
         "a subscript expects a whole number, got bool in 'tools[true]'"),
    ],
)
def test_indexing_errors_name_the_operand(source: str, values: dict[str, Any],
                                          message: str) -> None:
    assert run_error(source, **values) == message


def test_deep_indexing_is_bounded() -> None:
    assert "nested too deeply" in load_error("x" + "[0]" * (MAX_DEPTH + 1)).message


# ------------------------------------------------------------------------------------------
# str(x, 'format')
# ------------------------------------------------------------------------------------------


@given(x=st.floats(min_value=-99999, max_value=99999))
def test_str_writes_a_number_as_the_named_format_does(x: float) -> None:
    assert run("str(x, 'coord')", x=x) == FORMATS["coord"].render(x)
    assert run("'X' + str(x, 'angle')", x=x) == "X" + FORMATS["angle"].render(x)


def test_str_of_an_integer_through_an_integer_format() -> None:
    assert run("str(t, 'tool')", t=7) == "07"


def test_str_checks_the_format_name_when_the_post_loads() -> None:
    error = load_error("str(x, 'cord')")
    assert error.message == "unknown format 'cord'; did you mean 'coord'?"
    assert error.column == 7


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ({"x": "ten"}, "str() expects a number, got string in \"str(x, 'coord')\""),
        ({"x": True}, "str() expects a number, got bool in \"str(x, 'coord')\""),
        ({"x": None}, "parameter 'x' has no value"),
        ({"x": 1234567.0}, "format 'coord' cannot write 1234567.0: 7 digits before the "
                           "point, more than the 6 the format allows (max_digits) in "
                           "\"str(x, 'coord')\""),
    ],
)
def test_str_refuses_what_the_format_cannot_write(values: dict[str, Any],
                                                  message: str) -> None:
    assert run_error("str(x, 'coord')", **values) == message
