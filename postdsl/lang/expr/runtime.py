"""Run-time semantics: the operations and whitelisted functions that compiled closures call.

Python's operators are far more permissive than a post author expects (``'ab' * 3`` is
``'ababab'``, ``True + 1`` is ``2``, ``None < 1`` raises ``TypeError``).  Every operator and
function therefore checks its operands.  The kernels here do not know the source text: they
raise :class:`Mismatch` or :class:`Invalid`, and the closure that called them turns that, through
the :class:`Blame` prepared for it at compile time, into an :class:`ExprEvalError` naming the
sub-expression, or the parameter that has no value, rather than leaking a Python exception or
quietly writing nonsense into the NC program.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable, Container, Mapping, Sequence
from dataclasses import dataclass
from decimal import ROUND_HALF_UP, Context, Decimal
from typing import Any, Final, NamedTuple, Protocol

from postdsl.lang.expr.errors import ExprEvalError

#: Longest string that ``+`` may build at run time.
MAX_STRING_LENGTH: Final = 10_000


class Scope(Protocol):
    """The part of the engine's state that an expression may see.

    Declared with read-only properties so that any object exposing these two attributes
    qualifies, including the engine itself and frozen dataclasses.
    """

    @property
    def values(self) -> Mapping[str, Any]:
        """Current parameter values: numbers, strings, bools, None or lists."""

    @property
    def changed(self) -> Container[str]:
        """Names whose value changed with the current CL command."""


Evaluator = Callable[[Scope], Any]

#: bool is included on purpose: it is an int in Python, and "count + flag" has its usual meaning.
NUMBERS: Final = (int, float)
_SEQUENCES: Final = (list, tuple)


class Mismatch(Exception):
    """Operands of a type the operation does not accept.

    Raised by the kernels below, which do not know the source text; the closure that called
    them turns it into an :class:`ExprEvalError` through a :class:`Blame`.
    """

    def __init__(self, index: int | None = None, expected: str = "a number") -> None:
        super().__init__(expected)
        self.index = index
        self.expected = expected


class Invalid(Exception):
    """Operands of the right type but outside the operation's domain (e.g. ``sqrt(-1)``)."""


# --------------------------------------------------------------------------------------------
# Operators
# --------------------------------------------------------------------------------------------


#: Largest magnitude of a computed whole number, in bits: what a float can hold (about
#: 1.8e308).  Python's integers grow without end, and a product of products reaches
#: thousands of digits that no control reads and ``str()`` refuses to write.
MAX_INTEGER_BITS: Final = 1024


def _in_range(result: Any) -> Any:
    """A computed number no NC word can hold is an error where it is computed.

    Python floats overflow to infinity in silence and integers never overflow at all;
    either would surface later, far from its cause, or not at all.
    """
    if result.__class__ is float:
        if not math.isfinite(result):
            raise Invalid("number out of range (too large)")
    elif isinstance(result, int) and result.bit_length() > MAX_INTEGER_BITS:
        raise Invalid("number out of range (too large)")
    return result


def _add(a: Any, b: Any) -> Any:
    if isinstance(a, NUMBERS) and isinstance(b, NUMBERS):
        return _in_range(a + b)
    if isinstance(a, str) and isinstance(b, str):
        if len(a) + len(b) > MAX_STRING_LENGTH:
            raise Invalid(f"string would be longer than {MAX_STRING_LENGTH} characters")
        return a + b
    raise Mismatch


def _numeric(apply: Callable[[Any, Any], Any]) -> Callable[[Any, Any], Any]:
    """Restrict a Python operator to numbers, so that ``*`` never repeats a string or list."""

    def kernel(a: Any, b: Any) -> Any:
        if isinstance(a, NUMBERS) and isinstance(b, NUMBERS):
            return _in_range(apply(a, b))
        raise Mismatch

    return kernel


def _ordered(compare: Callable[[Any, Any], bool]) -> Callable[[Any, Any], bool]:
    """Restrict an ordering to number/number and string/string, the only meaningful pairs."""

    def kernel(a: Any, b: Any) -> bool:
        if (isinstance(a, NUMBERS) and isinstance(b, NUMBERS)) or (
            isinstance(a, str) and isinstance(b, str)
        ):
            return compare(a, b)
        raise Mismatch

    return kernel


def _contains(item: Any, container: Any) -> bool:
    if isinstance(container, _SEQUENCES) or (isinstance(container, str) and isinstance(item, str)):
        return item in container
    raise Mismatch


def _not_contains(item: Any, container: Any) -> bool:
    return not _contains(item, container)


ARITHMETIC: Mapping[str, Callable[[Any, Any], Any]] = {
    "+": _add,
    "-": _numeric(operator.sub),
    "*": _numeric(operator.mul),
    "/": _numeric(operator.truediv),
    "//": _numeric(operator.floordiv),
    "%": _numeric(operator.mod),
}
#: Unchecked orderings, for callers that have already checked the operand types.
ORDERINGS: Mapping[str, Callable[[Any, Any], bool]] = {
    "<": operator.lt,
    "<=": operator.le,
    ">": operator.gt,
    ">=": operator.ge,
}
COMPARISONS: Mapping[str, Callable[[Any, Any], bool]] = {
    "==": operator.eq,
    "!=": operator.ne,
    **{symbol: _ordered(compare) for symbol, compare in ORDERINGS.items()},
    "in": _contains,
    "not in": _not_contains,
}
#: Unchecked prefix signs, for callers that have already checked the operand type.
SIGNS: Mapping[str, Callable[[Any], Any]] = {"-": operator.neg, "+": operator.pos}


# --------------------------------------------------------------------------------------------
# Functions
# --------------------------------------------------------------------------------------------


def _check_numbers(*args: Any) -> None:
    for index, value in enumerate(args):
        if not isinstance(value, NUMBERS):
            raise Mismatch(index)


def _integral(value: Any) -> float:
    """Check for a finite number, the only kind that has an integer value."""
    _check_numbers(value)
    if isinstance(value, float) and not math.isfinite(value):
        raise Invalid(f"{value!r} has no integer value")
    return value  # type: ignore[no-any-return]  # a number: _check_numbers


def _abs(x: Any) -> Any:
    _check_numbers(x)
    return abs(x)


def _min(*args: Any) -> Any:
    _check_numbers(*args)
    return min(args)


def _max(*args: Any) -> Any:
    _check_numbers(*args)
    return max(args)


def _floor(x: Any) -> int:
    return math.floor(_integral(x))


def _ceil(x: Any) -> int:
    return math.ceil(_integral(x))


def _int(x: Any) -> int:
    return int(_integral(x))


def _sqrt(x: Any) -> float:
    _check_numbers(x)
    if x < 0:
        raise Invalid("square root of a negative number")
    return math.sqrt(x)


_ROUND_DIGITS: Final = 30
# Rounding a float to a fixed exponent can need as many digits as the float's integer part
# (309 at most) plus the requested decimals; give quantize() room for all of them.
_ROUNDING = Context(prec=400, rounding=ROUND_HALF_UP)
_QUANTA = {
    digits: Decimal((0, (1,), -digits)) for digits in range(-_ROUND_DIGITS, _ROUND_DIGITS + 1)
}


def _round(x: Any, *digits: Any) -> int | float:
    """Round half away from zero, as machinists and controllers do.

    Python's ``round`` rounds half to even and works on the binary value, so ``round(2.5)``
    is 2 and ``round(0.125, 2)`` is 0.12; here the decimal text of the number is rounded,
    giving 3 and 0.13.  Digits are taken as ``*digits`` so that an explicit ``none`` is an
    error rather than a silent "no digits".
    """
    if not digits:
        number = _integral(x)
        return int(_decimal_round(number, 0)) if isinstance(number, float) else int(number)
    _check_numbers(x)
    places = digits[0]
    if not isinstance(places, int) or isinstance(places, bool) or abs(places) > _ROUND_DIGITS:
        raise Mismatch(1, f"a whole number of digits from -{_ROUND_DIGITS} to {_ROUND_DIGITS}")
    if isinstance(x, float):
        # like Python's round(), infinities and NaN are returned unchanged when digits are given
        return float(_decimal_round(x, places)) if math.isfinite(x) else x
    return _integer_round(int(x), places)


def _decimal_round(x: float, places: int) -> Decimal:
    # repr() is the shortest text that reads back as x: the number as the user wrote it.
    return Decimal(repr(x)).quantize(_QUANTA[places], context=_ROUNDING)


def _integer_round(x: int, places: int) -> int:
    # Integers are rounded exactly, without Decimal's precision or str()'s digit limits.
    if places >= 0:
        return x
    unit: int = 10**-places
    quotient, remainder = divmod(abs(x), unit)
    if 2 * remainder >= unit:
        quotient += 1
    return quotient * unit if x >= 0 else -quotient * unit


def _finite(*args: Any) -> None:
    """Numbers a float function can take: an infinity has no sine and no angle."""
    _check_numbers(*args)
    for value in args:
        if isinstance(value, float) and not math.isfinite(value):
            raise Invalid(f"{value!r} is not a finite number")


def _float_function(apply: Callable[..., float]) -> Callable[..., float]:
    """A math function on checked numbers, its result bounded like every computed number.

    ``degrees(1e308)`` overflows to infinity and ``sin(10**400)`` cannot be converted to a
    float at all: both are reported where they happen, never written.
    """

    def function(*args: Any) -> float:
        _finite(*args)
        try:
            result = apply(*args)
        except OverflowError:
            raise Invalid("number out of range (too large)") from None
        return _in_range(result)  # type: ignore[no-any-return]  # _in_range returns its number

    return function


def index(target: Any, position: Any) -> Any:
    """``target[position]``: an item of a list or a character of a text, bounds checked.

    Negative positions count from the end, as in Python (``tools[-1]`` is the last tool).
    """
    if not isinstance(target, (*_SEQUENCES, str)):
        raise Mismatch(0, "a list or a text")
    if position.__class__ is bool or not isinstance(position, int):
        raise Mismatch(1, "a whole number")
    size = len(target)
    if not -size <= position < size:
        items = "item" if size == 1 else "items"
        raise Invalid(f"index {position} is out of range ({size} {items})")
    return target[position]


class TextFormat(Protocol):
    """A post's number format, as ``str(x, 'name')`` uses it: the NC text of a number."""

    def render(self, value: float | int) -> str: ...


def format_text(render: Callable[[Any], str], name: str) -> Callable[[Any], str]:
    """``str(value, name)``: a number as the format writes it; text is refused, not echoed."""

    def text(value: Any) -> str:
        if value.__class__ is bool or not isinstance(value, NUMBERS):
            raise Mismatch(0)
        if isinstance(value, float) and not math.isfinite(value):
            raise Invalid(f"{value!r} cannot be written")
        try:
            return render(value)
        except ValueError as error:  # max_digits exceeded
            raise Invalid(f"format {name!r} cannot write {value!r}: {error}") from None

    return text


class Function(NamedTuple):
    impl: Callable[..., Any]
    min_args: int
    #: None: no upper bound
    max_args: int | None


#: The whitelist: the only functions an expression can call.  The parser checks names and
#: argument counts against it at load time.
FUNCTIONS: Mapping[str, Function] = {
    "abs": Function(_abs, 1, 1),
    "min": Function(_min, 2, None),
    "max": Function(_max, 2, None),
    "round": Function(_round, 1, 2),
    "floor": Function(_floor, 1, 1),
    "ceil": Function(_ceil, 1, 1),
    "sqrt": Function(_sqrt, 1, 1),
    "int": Function(_int, 1, 1),
    # angles in radians, as in Python and every math library; degrees() and radians()
    # convert for controls that take degrees (Heidenhain polar moves, helix angles)
    "sin": Function(_float_function(math.sin), 1, 1),
    "cos": Function(_float_function(math.cos), 1, 1),
    "tan": Function(_float_function(math.tan), 1, 1),
    "atan2": Function(_float_function(math.atan2), 2, 2),
    "degrees": Function(_float_function(math.degrees), 1, 1),
    "radians": Function(_float_function(math.radians), 1, 1),
    "hypot": Function(_float_function(math.hypot), 2, 3),
}


# --------------------------------------------------------------------------------------------
# Errors
# --------------------------------------------------------------------------------------------

#: What the kernels may raise on bad input; anything else is a bug and should propagate.
FAILURES: Final = (Mismatch, Invalid, ArithmeticError, ValueError)


def _type_name(value: Any) -> str:
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, int):
        return "int"
    if isinstance(value, float):
        return "float"
    if isinstance(value, str):
        return "string"
    if isinstance(value, _SEQUENCES):
        return "list"
    return type(value).__name__


def no_value(name: str) -> ExprEvalError:
    return ExprEvalError(f"parameter {name!r} has no value")


@dataclass(frozen=True, slots=True)
class Blame:
    """Words the run-time error of one operation.

    Everything it needs is prepared at compile time, so that the hot path carries no
    diagnostic baggage beyond a reference to this object.
    """

    #: how the operation is named in messages: "'+'" or "round()"
    symbol: str
    #: the sub-expression's source, quoted in messages
    text: str
    #: for each operand, the parameter it reads when it is a bare name, else None (also for
    #: an intermediate result of a chain)
    parameters: tuple[str | None, ...]
    is_call: bool = False

    def __call__(self, error: Exception, values: Sequence[Any]) -> ExprEvalError:
        # A parameter without a value is nearly always the real cause, so it is named first.
        for value, name in zip(values, self.parameters, strict=False):
            if value is None and name is not None:
                return no_value(name)
        where = f"in {self.text!r}"
        if isinstance(error, ZeroDivisionError):
            return ExprEvalError(f"division by zero {where}")
        if isinstance(error, Invalid):
            return ExprEvalError(f"{error} {where}")
        if isinstance(error, Mismatch):
            if self.is_call:
                got = _type_name(values[error.index or 0])
                return ExprEvalError(f"{self.symbol} expects {error.expected}, got {got} {where}")
            types = " and ".join(_type_name(value) for value in values)
            return ExprEvalError(f"cannot apply {self.symbol} to {types} {where}")
        return ExprEvalError(f"number out of range {where}")
