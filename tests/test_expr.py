"""Tests of the post expression language (postdsl.lang.expr).

Python itself is the oracle for operator semantics and precedence: random expressions are
rendered to text that is valid in both languages, and the same text must give the same result
in both.  Everything the language deliberately does differently from Python (type checks,
rounding, rejected constructs) is tested with explicit examples.
"""

from __future__ import annotations

import ast
import contextlib
import math
import pickle
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from postdsl.lang import expr
from postdsl.lang.expr import (
    MAX_DEPTH,
    MAX_SOURCE_LENGTH,
    MAX_STRING_LENGTH,
    ExprError,
    ExprEvalError,
    compile_expr,
)


@dataclass
class SimpleScope:
    values: Mapping[str, Any] = field(default_factory=dict)
    changed: set[str] = field(default_factory=set)


def run(source: str, changed: tuple[str, ...] = (), **values: Any) -> Any:
    return compile_expr(source).evaluate(SimpleScope(values, set(changed)))


def load_error(source: str, known_names: Any = None) -> ExprError:
    with pytest.raises(ExprError) as info:
        compile_expr(source, known_names)
    return info.value


def run_error(source: str, **values: Any) -> str:
    expression = compile_expr(source)
    with pytest.raises(ExprEvalError) as info:
        expression.evaluate(SimpleScope(values))
    return str(info.value)


# ------------------------------------------------------------------------------------------
# Literals and names
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("0", 0),
        ("42", 42),
        ("007", 7),
        ("0.5", 0.5),
        (".5", 0.5),
        ("5.", 5.0),
        ("1e3", 1000.0),
        ("1E3", 1000.0),
        ("2.5e-3", 0.0025),
        ("1e+2", 100.0),
        ("'off'", "off"),
        ('"off"', "off"),
        ("''", ""),
        (r"'it\'s'", "it's"),
        (r'"say \"hi\""', 'say "hi"'),
        (r"'back\\slash'", "back\\slash"),
        ("'mixed \"quotes\"'", 'mixed "quotes"'),
        ("true", True),
        ("false", False),
        ("none", None),
        ("True", True),
        ("False", False),
        ("None", None),
    ],
)
def test_literals(source: str, expected: Any) -> None:
    result = run(source)
    assert result == expected
    assert type(result) is type(expected)


def test_integer_literal_of_thirty_digits_is_exact() -> None:
    assert run("9" * 30) == int("9" * 30)


def test_names_are_read_from_scope_values() -> None:
    assert run("feed_rate", feed_rate=120.5) == 120.5
    assert run("_x1", _x1="a") == "a"
    assert run("peck", peck=None) is None


def test_names_are_collected_including_probe_arguments() -> None:
    expression = compile_expr("x + y > 0 and changed(z) or defined(w) or x == 1")
    assert expression.names == frozenset({"x", "y", "z", "w"})
    assert compile_expr("1 + 2").names == frozenset()


def test_whitespace_and_newlines_are_insignificant() -> None:
    assert run("\n  x\t+\n 1\r\n  >  2 ", x=2) is True
    assert run("min(\n  x,\n  3,\n)", x=5) == 3


def test_expression_keeps_its_source_and_compares_without_the_closure() -> None:
    first, second = compile_expr("a > 1"), compile_expr("a > 1")
    assert first.source == "a > 1"
    assert first == second
    assert "evaluate" not in repr(first)
    with pytest.raises(AttributeError):
        first.source = "b"  # type: ignore[misc]


# ------------------------------------------------------------------------------------------
# Operators and precedence
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("1 + 2 * 3", 7),
        ("(1 + 2) * 3", 9),
        ("10 - 4 - 3", 3),
        ("10 - (4 - 3)", 9),
        ("100 / 10 / 5", 2.0),
        ("7 / 2", 3.5),
        ("7 // 2", 3),
        ("-7 // 2", -4),
        ("7 % 3", 1),
        ("-7 % 3", 2),
        ("7.5 % 2", 1.5),
        ("2 * 3 % 4", 2),
        ("-2 * 3", -6),
        ("- (2 * 3)", -6),
        ("--3", 3),
        ("-+-3", 3),
        ("+3", 3),
        ("1 - -1", 2),
        ("true + 1", 2),
        ("not 1 == 2", True),
        ("not true and false", False),
        ("not (true and false)", True),
        ("true or false and false", True),
        ("(true or false) and false", False),
        ("not not 3", True),
        ("1 + 2 == 3", True),
        ("1 < 2 == true", False),  # a chain: 1 < 2 and 2 == true
        ("(1 < 2) == true", True),
        ("2 * 3 > 5 and 1 + 1 == 2", True),
        ("'a' < 'b'", True),
        ("'b' <= 'a'", False),
        ("1 == 1.0", True),
        ("1 != '1'", True),
        ("none == none", True),
        ("none == 0", False),
        ("none != false", True),
    ],
)
def test_operator_examples(source: str, expected: Any) -> None:
    result = run(source)
    assert result == expected
    assert type(result) is type(expected)


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("x and 0", False),
        ("x and 'text'", True),
        ("x or y", True),
        ("0 or ''", False),
        ("y or 0", False),
    ],
)
def test_and_or_return_booleans_not_operands(source: str, expected: bool) -> None:
    assert run(source, x=5, y=0) is expected


def test_and_or_short_circuit() -> None:
    assert run("false and missing") is False
    assert run("true or missing") is True
    assert run("x > 0 and 1 / x > 0.1", x=0) is False
    assert run("a and b and c and missing", a=1, b=1, c=0) is False
    assert run("a or b or c or missing", a=0, b=0, c=1) is True


@pytest.mark.parametrize(
    ("x", "expected"),
    [(-1, False), (0, False), (1, True), (5, True), (5.5, False)],
)
def test_chained_comparison(x: float, expected: bool) -> None:
    assert run("0 < x <= 5", x=x) is expected


def test_chained_comparison_reads_each_operand_once_and_stops_early() -> None:
    reads: list[str] = []

    class CountingValues(dict[str, Any]):
        def __getitem__(self, name: str) -> Any:
            reads.append(name)
            return super().__getitem__(name)

    scope = SimpleScope(CountingValues(lo=0, x=3, hi=10))
    assert compile_expr("lo < x < hi").evaluate(scope) is True
    assert reads == ["lo", "x", "hi"]
    assert run("3 < 2 < missing") is False
    assert run("1 < 2 < 3 < 4 < 5") is True
    assert run("1 < 2 < 3 > 4") is False


# Python is the oracle.  The generators build text valid in both languages, parenthesised only
# where the intended tree needs it so that precedence and associativity are exercised, and keep
# "and"/"or"/"not" over booleans, where Python also returns booleans.

_ATOM, _SIGNED, _PRODUCT, _SUM, _COMPARE, _NOT, _AND, _OR = 9, 7, 6, 5, 4, 3, 2, 1
Rendered = tuple[str, int]  # source text, binding power of its top-level operator


def _wrap(item: Rendered, minimum: int) -> str:
    text, power = item
    return text if power >= minimum else f"({text})"


def _integer(value: int) -> Rendered:
    return (str(value), _ATOM if value >= 0 else _SIGNED)


def _signed(parts: tuple[str, Rendered]) -> Rendered:
    sign, operand = parts
    return (sign + _wrap(operand, _SIGNED), _SIGNED)


def _binary(power: int) -> Callable[[tuple[Rendered, str, Rendered]], Rendered]:
    def render(parts: tuple[Rendered, str, Rendered]) -> Rendered:
        left, op, right = parts
        return (f"{_wrap(left, power)} {op} {_wrap(right, power + 1)}", power)

    return render


def _comparison(parts: tuple[Rendered, list[tuple[str, Rendered]]]) -> Rendered:
    first, rest = parts
    text = _wrap(first, _SUM)
    for op, operand in rest:
        text += f" {op} {_wrap(operand, _SUM)}"
    return (text, _COMPARE)


def _booleans(numbers: st.SearchStrategy[Rendered]) -> st.SearchStrategy[Rendered]:
    comparisons = st.tuples(
        numbers,
        st.lists(
            st.tuples(st.sampled_from(["==", "!=", "<", "<=", ">", ">="]), numbers),
            min_size=1,
            max_size=3,
        ),
    ).map(_comparison)
    leaves = comparisons | st.sampled_from([("True", _ATOM), ("False", _ATOM)])
    return st.recursive(
        leaves,
        lambda inner: st.one_of(
            inner.map(lambda item: (f"not {_wrap(item, _NOT)}", _NOT)),
            st.tuples(inner, st.just("and"), inner).map(_binary(_AND)),
            st.tuples(inner, st.just("or"), inner).map(_binary(_OR)),
        ),
        max_leaves=4,
    )


def _test(parts: tuple[Rendered, str, Rendered, bool]) -> Rendered:
    left, op, right, negate = parts
    text = f"{_wrap(left, _SUM)} {op} {_wrap(right, _SUM)}"
    return (f"(not {text})" if negate else f"({text})", _ATOM)


_numbers: st.SearchStrategy[Rendered] = st.recursive(
    st.one_of(
        st.integers(-30, 30).map(_integer),
        st.sampled_from([("a", _ATOM), ("b", _ATOM), ("c", _ATOM)]),
    ),
    lambda inner: st.one_of(
        st.tuples(st.sampled_from("-+"), inner).map(_signed),
        st.tuples(inner, st.sampled_from(["+", "-"]), inner).map(_binary(_SUM)),
        st.tuples(inner, st.sampled_from(["*", "/", "//", "%"]), inner).map(_binary(_PRODUCT)),
        inner.map(lambda item: (f"({item[0]})", _ATOM)),
        # a parenthesised test is a number too (True + 1 == 2, in Python as here)
        st.tuples(inner, st.sampled_from(["<", "==", ">="]), inner, st.booleans()).map(_test),
    ),
    max_leaves=10,
)
_expressions = _numbers | _booleans(_numbers)


@settings(deadline=None)
@given(
    rendered=_expressions,
    a=st.integers(-5, 5),
    b=st.integers(-5, 5),
    c=st.integers(-5, 5),
)
@example(rendered=("a - b - c * a // b % c", _SUM), a=7, b=2, c=3)
@example(rendered=("not a < b < c or a == b and not c", _OR), a=1, b=2, c=3)
def test_agrees_with_python(rendered: Rendered, a: int, b: int, c: int) -> None:
    source = rendered[0]
    values = {"a": a, "b": b, "c": c}
    expression = compile_expr(source, known_names=values)
    try:
        # The oracle: test-generated text only, run by Python with no builtins.
        expected = eval(source, {"__builtins__": {}}, dict(values))
    except ZeroDivisionError:
        with pytest.raises(ExprEvalError, match="division by zero"):
            expression.evaluate(SimpleScope(values))
        return
    result = expression.evaluate(SimpleScope(values))
    assert result == expected
    assert type(result) is type(expected)


# ------------------------------------------------------------------------------------------
# Membership and strings
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("tool_type in ['drill', 'tap']", True),
        ("tool_type not in ['drill', 'tap']", False),
        ("tool_type in ['ream']", False),
        ("tool_type in []", False),
        ("tool_type in [other, 'x',]", True),
        ("2 in [1, 2.0]", True),
        ("none in [1, none]", True),
        ("'ri' in tool_type", True),
        ("'x' not in tool_type", True),
        ("3 in holes", True),
        ("4 not in holes", True),
        ("tool_type in ['drill'] and 1 in holes", True),
        ("1 < 2 in [2]", True),
    ],
)
def test_membership(source: str, expected: bool) -> None:
    values: dict[str, Any] = {"tool_type": "drill", "other": "drill", "holes": [1, 2, 3]}
    assert run(source, **values) is expected


def test_string_concatenation_and_comparison() -> None:
    assert run("prefix + '-' + name", prefix="T", name="drill") == "T-drill"
    assert run("name == 'drill'", name="drill") is True
    assert run("name < 'e'", name="drill") is True


def test_string_concatenation_is_capped() -> None:
    half = "x" * (MAX_STRING_LENGTH // 2)
    assert len(run("s + s", s=half)) == MAX_STRING_LENGTH
    assert run_error("s + s + 'y'", s=half) == (
        f"string would be longer than {MAX_STRING_LENGTH} characters in \"s + s + 'y'\""
    )


# ------------------------------------------------------------------------------------------
# changed() and defined()
# ------------------------------------------------------------------------------------------


def test_changed_tests_membership_in_scope_changed() -> None:
    assert run("changed(x)", changed=("x",), x=1) is True
    assert run("changed(x)", changed=("y",), x=1) is False
    # it inspects the name only, so a parameter without a value is fine
    assert run("changed(missing)") is False


def test_defined_means_present_and_not_none() -> None:
    assert run("defined(x)", x=0) is True
    assert run("defined(x)", x=False) is True
    assert run("defined(x)", x=None) is False
    assert run("defined(x)") is False
    assert run("defined(peck) and peck > 0", peck=None) is False


@pytest.mark.parametrize(
    ("source", "column"),
    [
        ("changed()", 8),
        ("changed(1)", 8),
        ("changed('x')", 8),
        ("defined(abs(x))", 8),
        ("defined(x + 1)", 10),
        ("changed(x, y)", 9),
    ],
)
def test_probes_take_exactly_one_bare_name(source: str, column: int) -> None:
    assert load_error(source).column == column


# ------------------------------------------------------------------------------------------
# Functions
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("abs(-3)", 3),
        ("abs(-2.5)", 2.5),
        ("abs(x)", 4),
        ("min(3, 1, 2)", 1),
        ("max(3, 1.5)", 3),
        ("min(x, 10)", -4),
        ("floor(2.7)", 2),
        ("floor(-2.1)", -3),
        ("ceil(2.1)", 3),
        ("ceil(-2.7)", -2),
        ("ceil(3)", 3),
        ("sqrt(16)", 4.0),
        ("sqrt(2)", math.sqrt(2)),
        ("int(2.9)", 2),
        ("int(-2.9)", -2),
        ("int(true)", 1),
        ("round(2.4)", 2),
        ("round(2.5)", 3),
        ("round(3.5)", 4),
        ("round(-2.5)", -3),
        ("round(-0.5)", -1),
        ("round(0.125, 2)", 0.13),
        ("round(-0.125, 2)", -0.13),
        ("round(2.675, 2)", 2.68),
        ("round(1.0005, 3)", 1.001),
        ("round(7, 2)", 7),
        ("round(1250, -2)", 1300),
        ("round(-1250, -2)", -1300),
        ("round(1249, -2)", 1200),
        ("round(1250.0, -2)", 1300.0),
        ("round(1e20)", 10**20),
        ("round(x / 3, 3)", -1.333),
    ],
)
def test_functions(source: str, expected: Any) -> None:
    result = run(source, x=-4)
    assert result == expected
    assert type(result) is type(expected)


def test_round_returns_int_without_digits_and_float_with_digits() -> None:
    assert type(run("round(2.5)")) is int
    assert type(run("round(2.5, 0)")) is float
    assert run("round(x, 2)", x=math.inf) == math.inf


@pytest.mark.parametrize(
    ("source", "message"),
    [
        ("abs()", "abs() takes 1 argument (0 given)"),
        ("abs(1, 2)", "abs() takes 1 argument (2 given)"),
        ("min(1)", "min() takes at least 2 arguments (1 given)"),
        ("max()", "max() takes at least 2 arguments (0 given)"),
        ("round()", "round() takes 1 or 2 arguments (0 given)"),
        ("round(1, 2, 3)", "round() takes 1 or 2 arguments (3 given)"),
        ("sqrt(1, 2)", "sqrt() takes 1 argument (2 given)"),
    ],
)
def test_function_arity_is_checked_at_load(source: str, message: str) -> None:
    error = load_error(source)
    assert (error.message, error.column) == (message, 0)


@pytest.mark.parametrize(
    ("source", "message"),
    [
        ("abs(s)", "abs() expects a number, got string in 'abs(s)'"),
        ("min(1, s)", "min() expects a number, got string in 'min(1, s)'"),
        ("floor(n)", "parameter 'n' has no value"),
        ("sqrt(-1)", "square root of a negative number in 'sqrt(-1)'"),
        ("floor(inf)", "inf has no integer value in 'floor(inf)'"),
        ("int(nan)", "nan has no integer value in 'int(nan)'"),
        ("round(inf)", "inf has no integer value in 'round(inf)'"),
        ("round(1.5, 0.5)", "round() expects a whole number of digits from -30 to 30"),
        ("round(1.5, 31)", "round() expects a whole number of digits from -30 to 30"),
        ("round(1.5, n)", "parameter 'n' has no value"),
    ],
)
def test_function_argument_errors(source: str, message: str) -> None:
    values = {"s": "text", "n": None, "inf": math.inf, "nan": math.nan}
    assert run_error(source, **values).startswith(message)


def test_huge_integers_report_range_errors() -> None:
    assert run_error("sqrt(big)", big=10**400) == "number out of range in 'sqrt(big)'"
    assert run_error("big / 3", big=10**400) == "number out of range in 'big / 3'"


def test_unknown_function_suggests_a_close_match() -> None:
    error = load_error("x + flor(x)")
    assert (error.message, error.column) == ("unknown function 'flor'; did you mean 'floor'?", 4)


def test_calling_a_parameter_is_reported_as_such() -> None:
    error = load_error("feed(2)", {"feed"})
    assert (error.message, error.column) == ("'feed' is a parameter, not a function", 0)


def test_function_names_are_usable_as_parameter_names() -> None:
    assert run("round + 1", round=2) == 3


# ------------------------------------------------------------------------------------------
# Rejected constructs
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("source", "column", "message"),
    [
        ("x ** 2", 2, "unexpected '**'"),
        ("9**9**9", 1, "unexpected '**'"),
        ("x.__class__", 1, "unexpected '.'"),
        ("x.y", 1, "attribute access is not supported"),
        ("().__class__", 1, "unexpected ')'"),
        ("__import__('os')", 0, "names starting with '__' are not allowed"),
        ("x + __builtins__", 4, "names starting with '__' are not allowed"),
        ("open('f')", 0, "unknown function 'open'"),
        ("print(x)", 0, "unknown function 'print'"),
        ("a[0", 3, "expected ']', found end of expression"),
        ("a[]", 2, "unexpected ']'"),
        ("(x)(1)", 3, "only functions can be called"),
        ("lambda: 1", 0, "keyword 'lambda' is not supported"),
        ("import os", 0, "keyword 'import' is not supported"),
        ("x if y", 6, "expected 'else', found end of expression"),
        ("x if y if z else w else v", 7, "expected 'else', found 'if'"),
        ("if x else y", 0, "unexpected 'if'"),
        ("str(x)", 5, "str() takes a number and the name of a format"),
        ("str(x, y)", 7, "the format name must be a quoted literal"),
        ("str(x, 'coord')", 0, "str() needs the post's formats"),
        ("x is none", 2, "keyword 'is' is not supported (use '==' or '!=')"),
        ("[c for c in x]", 0, "unexpected '['"),
        ("x = 1", 2, "unexpected '=' (use '==' to compare)"),
        ("(y := 1)", 3, "unexpected ':='"),
        ("x; y", 1, "unexpected ';'"),
        ("`x`", 0, "unexpected '`'"),
        ("f'{x}'", 0, "string prefixes such as f'...' are not supported"),
        ('rb"x"', 0, "string prefixes such as f'...' are not supported"),
        ("x && y", 2, "unexpected '&&' (use 'and')"),
        ("x || y", 2, "unexpected '||' (use 'or')"),
        ("!x", 0, "unexpected '!' (use 'not')"),
        ("x @ y", 2, "unexpected '@'"),
        ("{1: 2}", 0, "unexpected '{'"),
        ("x # comment", 2, "unexpected '#'"),
        ("x == not y", 5, "unexpected 'not'"),
        ("-not x", 1, "unexpected 'not'"),
        ("x not y", 6, "expected 'in', found name 'y'"),
        ("[1, 2]", 0, "a list can only follow 'in'"),
        ("x == [1]", 5, "a list can only follow 'in'"),
        ("x in [[1]]", 6, "a list can only follow 'in'"),
        ("x in [1] + y", 9, "a list can only be the right-hand side of 'in'"),
        ("x in [1] == y", 9, "a list can only be the right-hand side of 'in'"),
        ("x in [1][0]", 8, "a list after 'in' cannot be indexed"),
        ("1abc", 0, "invalid number '1abc'"),
        ("0x1F", 0, "invalid number '0x1F'"),
        ("1_000", 0, "invalid number '1_000'"),
        ("1.2.3", 0, "invalid number '1.2.3'"),
        ("1e", 0, "invalid number '1e'"),
        ("1e999", 0, "number literal is out of range"),
        ("'abc", 0, "unterminated string"),
        ("x == 'abc\\'", 5, "unterminated string"),
        ("'a\\nb'", 2, "invalid escape"),
        ("", 0, "expression is empty"),
        ("   ", 0, "expression is empty"),
        ("x +", 3, "unexpected end of expression"),
        ("(x", 2, "expected ')', found end of expression"),
        ("min(x y)", 6, "expected ')', found name 'y'"),
        ("x y", 2, "unexpected name 'y'"),
        ("x 1", 2, "unexpected number '1'"),
        ("x 'a'", 2, "unexpected string 'a'"),
        ("1 +* 2", 3, "unexpected '*'"),
        ("min(,)", 4, "unexpected ','"),
        ("café", 3, "unexpected 'é'"),
    ],
)
def test_rejected_at_load_with_column(source: str, column: int, message: str) -> None:
    error = load_error(source)
    assert message in error.message
    assert error.column == column


def test_error_message_is_str_and_survives_pickling() -> None:
    error = load_error("x ** 2")
    assert str(error) == error.message == "unexpected '**'"
    copy = pickle.loads(pickle.dumps(error))
    assert (copy.message, copy.column) == (error.message, error.column)


def test_first_error_from_the_left_is_reported() -> None:
    # A tokenizer error further right must not hide a parse error further left.
    assert load_error("x y ;").column == 2
    assert load_error("x ; y z").column == 2


def test_the_module_never_evaluates_text_with_python() -> None:
    # every module of the postdsl.lang.expr package
    modules = sorted(Path(expr.__file__).parent.glob("*.py"))
    assert {"__init__.py", "lexer.py", "parser.py", "compiler.py"} <= {p.name for p in modules}
    trees = [ast.parse(module.read_text(encoding="utf-8")) for module in modules]
    forbidden = {"eval", "exec", "compile", "__import__", "getattr", "setattr"}
    called = {
        node.func.id
        for tree in trees
        for node in ast.walk(tree)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
    }
    imported = {
        alias.name
        for tree in trees
        for node in ast.walk(tree)
        if isinstance(node, ast.Import | ast.ImportFrom)
        for alias in node.names
    }
    assert not called & forbidden
    assert "ast" not in imported


# ------------------------------------------------------------------------------------------
# Names known at load time
# ------------------------------------------------------------------------------------------


def test_unknown_name_with_suggestion() -> None:
    error = load_error("feedrat > 100", ["feedrate", "spindle"])
    assert error.message == "unknown name 'feedrat'; did you mean 'feedrate'?"
    assert error.column == 0


def test_unknown_name_without_close_match() -> None:
    error = load_error("x > 0 and zzz", {"x", "feedrate"})
    assert (error.message, error.column) == ("unknown name 'zzz'", 10)


def test_unknown_names_inside_probes_are_reported() -> None:
    error = load_error("changed(tool_nr)", {"tool_number"})
    assert error.message == "unknown name 'tool_nr'; did you mean 'tool_number'?"
    assert error.column == 8


def test_known_names_may_be_a_container_that_cannot_be_iterated() -> None:
    class Prefixed:
        def __contains__(self, name: object) -> bool:
            return isinstance(name, str) and name.startswith("p_")

    assert compile_expr("p_a + p_b", Prefixed()).names == {"p_a", "p_b"}
    assert load_error("p_a + q", Prefixed()).message == "unknown name 'q'"


def test_without_known_names_anything_goes_until_run_time() -> None:
    expression = compile_expr("anything + 1")
    assert run_error("anything + 1") == "parameter 'anything' has no value"
    assert expression.evaluate(SimpleScope({"anything": 1})) == 2


# ------------------------------------------------------------------------------------------
# Run-time errors
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("source", "message"),
    [
        ("peck + 1", "parameter 'peck' has no value"),
        ("1 - (peck)", "parameter 'peck' has no value"),
        ("-peck", "parameter 'peck' has no value"),
        ("peck > 0", "parameter 'peck' has no value"),
        ("0 < x < peck", "parameter 'peck' has no value"),
        ("x * 2 + peck", "parameter 'peck' has no value"),
        ("missing == 1", "parameter 'missing' has no value"),
        ("x in [1, missing]", "parameter 'missing' has no value"),
        ("x / zero", "division by zero in 'x / zero'"),
        ("x // 0", "division by zero in 'x // 0'"),
        ("x % (x - 3)", "division by zero in 'x % (x - 3)'"),
        ("1 + x / 0.0", "division by zero in 'x / 0.0'"),
        ("x + 1 - 2 / zero", "division by zero in '2 / zero'"),
        ("1 // 0 // x", "division by zero in '1 // 0'"),
        ("'a' + 'b' + x", "cannot apply '+' to string and int in \"'a' + 'b' + x\""),
        ("s * 3", "cannot apply '*' to string and int in 's * 3'"),
        ("3 * s", "cannot apply '*' to int and string in '3 * s'"),
        ("items * 2", "cannot apply '*' to list and int in 'items * 2'"),
        ("items + items", "cannot apply '+' to list and list in 'items + items'"),
        ("s + 1", "cannot apply '+' to string and int in 's + 1'"),
        ("x + 1 + s", "cannot apply '+' to int and string in 'x + 1 + s'"),
        ("s % x", "cannot apply '%' to string and int in 's % x'"),
        ("-s", "cannot apply '-' to string in '-s'"),
        ("s < 1", "cannot apply '<' to string and int in 's < 1'"),
        ("1 <= s", "cannot apply '<=' to int and string in '1 <= s'"),
        ("items > x", "cannot apply '>' to list and int in 'items > x'"),
        ("x < 5 < s", "cannot apply '<' to int and string in '5 < s'"),
        ("x in 3", "cannot apply 'in' to int and int in 'x in 3'"),
        ("x not in s", "cannot apply 'not in' to int and string in 'x not in s'"),
        ("flag < none", "cannot apply '<' to bool and none in 'flag < none'"),
    ],
)
def test_run_time_errors(source: str, message: str) -> None:
    values = {"peck": None, "x": 3, "zero": 0, "s": "ab", "items": [1], "flag": True}
    assert run_error(source, **values) == message


def test_run_time_error_quotes_source_text_verbatim() -> None:
    assert run_error("x /\n  zero", x=1, zero=0) == "division by zero in 'x /\\n  zero'"


def test_constant_errors_are_left_for_run_time() -> None:
    # Folding must not turn a branch that never runs into a load error.
    assert run("false and 1 / 0") is False
    assert run_error("1 / 0") == "division by zero in '1 / 0'"
    assert run_error("'a' * 2") == "cannot apply '*' to string and int in \"'a' * 2\""


def test_literal_only_subexpressions_are_folded() -> None:
    class NoValues:
        @property
        def values(self) -> Mapping[str, Any]:
            raise AssertionError("a constant must not look anything up")

        changed: frozenset[str] = frozenset()

    assert compile_expr("round(1 + 2 * 3.5, 1) > abs(-2) and 'a' + 'b' == 'ab'").evaluate(
        NoValues()
    )
    assert compile_expr("2 in [1, 1 + 1]").evaluate(NoValues()) is True


# ------------------------------------------------------------------------------------------
# Limits
# ------------------------------------------------------------------------------------------


def test_source_length_limit() -> None:
    longest = "x" + " " * (MAX_SOURCE_LENGTH - 1)
    assert compile_expr(longest).names == {"x"}
    error = load_error(longest + " ")
    assert (error.message, error.column) == (
        f"expression is longer than {MAX_SOURCE_LENGTH} characters",
        MAX_SOURCE_LENGTH,
    )


def _nested(opening: str, closing: str, levels: int) -> str:
    return opening * levels + "x" + closing * levels


@pytest.mark.parametrize(
    ("opening", "closing"),
    [("(", ")"), ("-", ""), ("not ", ""), ("abs(", ")"), ("1 + (", ")")],
)
def test_nesting_limit(opening: str, closing: str) -> None:
    assert run(_nested(opening, closing, MAX_DEPTH), x=1, y=1) is not None
    error = load_error(_nested(opening, closing, MAX_DEPTH + 1))
    assert error.message == f"expression is nested too deeply (more than {MAX_DEPTH} levels)"
    assert 0 <= error.column < len(_nested(opening, closing, MAX_DEPTH + 1))


def test_nesting_far_beyond_the_limit_is_an_expr_error_not_a_recursion_error() -> None:
    for source in ("(" * 999 + "x", "-" * 1999 + "x", "a or b and c == d + e * -(" * 70):
        assert "nested too deeply" in load_error(source).message


def test_precedence_levels_count_towards_the_depth_of_the_tree() -> None:
    level = "a or b and c == d + e * -("
    # each repetition adds six levels: or, and, ==, +, *, unary minus
    assert compile_expr(level * 10 + "x" + ")" * 10).names == set("abcdex")
    assert "nested too deeply" in load_error(level * 11 + "x" + ")" * 11).message


@pytest.mark.parametrize("operator", ["+", "-", "*", "and", "or", "<", "=="])
def test_long_flat_chains_are_not_nesting(operator: str) -> None:
    source = f" {operator} ".join(["x"] * 300)
    assert len(source) <= MAX_SOURCE_LENGTH
    run(source, x=1)  # must neither be rejected nor overflow the stack


def test_number_literal_digit_limit() -> None:
    assert run("1" * 30) == int("1" * 30)
    assert run("0." + "1" * 29) == float("0." + "1" * 29)
    assert "more than 30 digits" in load_error("1" * 31).message
    assert "more than 30 digits" in load_error("1.5e" + "1" * 29).message


# ------------------------------------------------------------------------------------------
# Robustness: whatever the text and the values, only the documented errors come out
# ------------------------------------------------------------------------------------------

_TOKENS = [
    *["a", "b", "x", "0", "1", "2.5", ".5", "1e3", "-1", "'s'", '"t"'],
    *["+", "-", "*", "/", "//", "%", "==", "!=", "<", "<=", ">", ">="],
    *["(", ")", "[", "]", ",", "."],
    *["and", "or", "not", "in", "true", "false", "none"],
    *["abs(", "min(", "max(", "round(", "floor(", "ceil(", "sqrt(", "int("],
    *["changed(", "defined("],
    *["**", "=", ";", "if", "lambda", "__x"],
]
_VALUES = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(),
    st.floats(),
    st.text(max_size=5),
    st.lists(st.integers(-3, 3), max_size=3),
)


# Joined with or without spaces, so that "a.b", "1e3" or "x==1" come up too.
_SOURCES = st.tuples(
    st.lists(st.sampled_from(_TOKENS), min_size=1, max_size=14), st.sampled_from([" ", ""])
).map(lambda parts: parts[1].join(parts[0]))


@settings(deadline=None)
@given(source=_SOURCES, a=_VALUES, b=_VALUES, x=_VALUES)
def test_token_soup_fails_only_with_documented_errors(source: str, a: Any, b: Any, x: Any) -> None:
    try:
        expression = compile_expr(source)
    except ExprError as error:
        assert 0 <= error.column <= len(source)
        return
    scope = SimpleScope({"a": a, "b": b, "x": x}, {"a"})
    with contextlib.suppress(ExprEvalError):
        expression.evaluate(scope)


@settings(deadline=None)
@given(source=st.text(max_size=30))
def test_arbitrary_text_fails_only_with_expr_error(source: str) -> None:
    try:
        compile_expr(source)
    except ExprError as error:
        assert 0 <= error.column <= len(source)


def test_non_string_source_is_a_type_error() -> None:
    with pytest.raises(TypeError):
        compile_expr(True)  # type: ignore[arg-type]


def test_expression_is_reusable_across_scopes() -> None:
    expression = compile_expr("x > 2")
    assert [expression.evaluate(SimpleScope({"x": value})) for value in (1, 3)] == [False, True]
