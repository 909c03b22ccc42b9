"""The small, safe expression language of machine posts.

Conditions and computed values in a post (``coolant == 'off'``, ``defined(peck) and peck > 0``)
are written by technologists, and a post file must never be able to do more than compute a value.
So user text never reaches ``eval``, ``exec``, ``compile`` or the ``ast`` module: a tokenizer and a
Pratt parser written for exactly this grammar accept what is documented and reject everything else
*when the post loads*, with the 0-based column of the offending character.

The syntax tree is then compiled into nested closures.  Expressions run for every block of every
CL command, so all dispatch on node types, operators and literal values is paid once, at load
time; at run time a node costs one Python call, and literal-only sub-trees are already folded
into constants.

Python's operators are far more permissive than a post author expects (``'ab' * 3`` is
``'ababab'``, ``True + 1`` is ``2``, ``None < 1`` raises ``TypeError``).  Every operator and
function therefore checks its operands and raises :class:`ExprEvalError` naming the
sub-expression, or the parameter that has no value, rather than leaking a Python exception or
quietly writing nonsense into the NC program.

The source length, nesting depth and size of number literals are bounded so that no post, however
hostile, can exhaust the Python stack or make loading or evaluation take unbounded time.

One module per stage, in the order a source text meets them:

- :mod:`~postdsl.lang.expr.errors`    the load-time and run-time exceptions
- :mod:`~postdsl.lang.expr.lexer`     source text -> tokens
- :mod:`~postdsl.lang.expr.nodes`     the syntax tree
- :mod:`~postdsl.lang.expr.parser`    tokens -> syntax tree, name and arity checks, limits
- :mod:`~postdsl.lang.expr.runtime`   the checked operations and whitelisted functions
- :mod:`~postdsl.lang.expr.compiler`  syntax tree -> closures, constant folding,
  :func:`compile_expr`
- :mod:`~postdsl.lang.expr.substitute` names replaced by expression texts (structure parameters)

The run-time module needs only the exceptions, so the parser can check calls against its
function whitelist without an import cycle.

Only the names below are the package's API; the modules' own names may change.
"""

from typing import Any

from postdsl.lang.expr.compiler import Expression, compile_expr
from postdsl.lang.expr.errors import ExprError, ExprEvalError
from postdsl.lang.expr.runtime import MAX_STRING_LENGTH, Scope
from postdsl.lang.expr.substitute import substitute

#: the limits the lexer and the parser enforce, read from them when first asked for: a
#: post from the cache holds its checked syntax trees, so posting loads neither module
_PARSING_LIMITS = ("MAX_DEPTH", "MAX_NUMBER_DIGITS", "MAX_SOURCE_LENGTH")


def __getattr__(name: str) -> Any:
    if name not in _PARSING_LIMITS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    from postdsl.lang.expr.lexer import MAX_NUMBER_DIGITS
    from postdsl.lang.expr.parser import MAX_DEPTH, MAX_SOURCE_LENGTH

    limits = {"MAX_DEPTH": MAX_DEPTH, "MAX_NUMBER_DIGITS": MAX_NUMBER_DIGITS,
              "MAX_SOURCE_LENGTH": MAX_SOURCE_LENGTH}
    globals().update(limits)
    return limits[name]


__all__ = [
    "MAX_DEPTH",
    "MAX_NUMBER_DIGITS",
    "MAX_SOURCE_LENGTH",
    "MAX_STRING_LENGTH",
    "ExprError",
    "ExprEvalError",
    "Expression",
    "Scope",
    "compile_expr",
    "substitute",
]
