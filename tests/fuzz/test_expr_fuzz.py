"""The expression language on generated expressions: its own errors only, in bounded time.

Expressions are built from the language's grammar (so most of them parse and run) and
from its tokens in any order (so the parser meets every kind of mistake), and evaluated
against parameter values of every kind a CL program or a post can give: numbers small
and huge, text, lists, none.  Loading may raise only ExprError, evaluation only
ExprEvalError; anything else, or a slow case, is a bug.
"""

from __future__ import annotations

import time
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from postdsl.lang.expr import ExprError, ExprEvalError, compile_expr
from postdsl.lang.formats import DEFAULT_MAX_DIGITS, NumberFormat

pytestmark = pytest.mark.fuzz

NAMES = ("x", "y", "z", "peck", "tool_number", "comment", "tools", "given", "missing")

#: the slowest a single expression may load and evaluate: the worst seen is ~1 ms, the
#: rest is room for a loaded CI machine (a hang or a runaway computation takes far longer)
BUDGET = 5.0

numbers = st.one_of(
    st.integers(min_value=-10**30, max_value=10**30),
    st.floats(allow_nan=False, allow_infinity=False),
    st.sampled_from([0, 0.0, -0.0, 1e308, -1e308, 5e-324, 2**1023, 10**29]),
)
values = st.one_of(numbers, st.text(max_size=20), st.booleans(), st.none(),
                   st.lists(st.integers(-5, 5), max_size=3))

literal = st.one_of(
    st.integers(min_value=0, max_value=10**30).map(str),
    st.floats(min_value=0, allow_nan=False, allow_infinity=False).map(repr),
    st.sampled_from(["1e308", "1e999", "0.0", "99999999999999999999999999999", "true",
                     "false", "none", "'text'", "''", "'a''b'"]),
    st.sampled_from(NAMES),
)


def _expressions() -> st.SearchStrategy[str]:
    def extend(inner: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
        binary = st.tuples(inner, st.sampled_from(
            ["+", "-", "*", "/", "//", "%", "==", "!=", "<", "<=", ">", ">=", "and", "or",
             "in", "not in"]), inner).map(lambda t: f"{t[0]} {t[1]} {t[2]}")
        unary = st.tuples(st.sampled_from(["-", "+", "not "]), inner).map("".join)
        call = st.tuples(st.sampled_from(
            ["abs", "min", "max", "round", "floor", "ceil", "sqrt", "int", "changed",
             "defined", "sin", "cos", "tan", "atan2", "degrees", "radians", "hypot", "str"]),
            st.lists(inner, min_size=0, max_size=3)).map(
            lambda t: f"{t[0]}({', '.join(t[1])})")
        text = inner.map(lambda e: f"str({e}, 'coord')")
        group = inner.map(lambda e: f"({e})")
        listed = st.lists(inner, max_size=3).map(lambda items: f"[{', '.join(items)}]")
        conditional = st.tuples(inner, inner, inner).map(lambda t: f"{t[0]} if {t[1]} else {t[2]}")
        indexed = st.tuples(inner, inner).map(lambda t: f"{t[0]}[{t[1]}]")
        return st.one_of(binary, unary, call, text, group, listed, conditional, indexed)

    return st.recursive(literal, extend, max_leaves=25)


#: the post formats ``str(x, 'coord')`` may name: one bounded as the loader bounds them
FORMATS = {"coord": NumberFormat(decimals=3, max_digits=DEFAULT_MAX_DIGITS)}

TOKENS = ["(", ")", "[", "]", ",", "+", "-", "*", "**", "/", "//", "%", "==", "=", "!=",
          "<", ">", "and", "or", "not", "in", "x", "1", "1e400", "'", "'s'", "__import__",
          ".", "lambda", "abs", "if", "else", "str", "'coord'", "sin", "hypot", ":", "@",
          "\\", "\x00", "\n", "é", "１"]
token_soup = st.lists(st.sampled_from(TOKENS), max_size=30).map(" ".join)


def _load_and_run(source: str, scope_values: dict[str, Any]) -> None:
    started = time.perf_counter()
    try:
        expression = compile_expr(source, set(NAMES), FORMATS)
    except ExprError as exc:
        assert isinstance(exc.column, int) and 0 <= exc.column <= len(source)
        return
    finally:
        assert time.perf_counter() - started < BUDGET, source

    class Scope:
        values = scope_values
        changed = frozenset({"x"})

    started = time.perf_counter()
    try:
        expression.evaluate(Scope())
    except ExprEvalError as exc:
        assert str(exc)
    assert time.perf_counter() - started < BUDGET, source


scopes = st.fixed_dictionaries({name: values for name in NAMES if name != "missing"})


@given(source=_expressions(), scope=scopes)
def test_generated_expressions_raise_only_their_own_errors(source: str,
                                                           scope: dict[str, Any]) -> None:
    _load_and_run(source, scope)


@given(source=token_soup, scope=scopes)
def test_token_soup_raises_only_expression_errors(source: str, scope: dict[str, Any]) -> None:
    _load_and_run(source, scope)


@given(source=st.text(max_size=60), scope=scopes)
def test_arbitrary_text_raises_only_expression_errors(source: str,
                                                      scope: dict[str, Any]) -> None:
    _load_and_run(source, scope)
