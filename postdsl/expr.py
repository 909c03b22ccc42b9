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
"""

from __future__ import annotations

import difflib
import keyword
import math
import operator
import re
from collections.abc import Callable, Container, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field, replace
from decimal import ROUND_HALF_UP, Context, Decimal
from types import MappingProxyType
from typing import Any, Final, NamedTuple, Protocol

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
]

#: Longest accepted source text, in characters.
MAX_SOURCE_LENGTH: Final = 2000
#: Deepest accepted nesting of brackets, calls, prefix operators and operator precedence levels.
MAX_DEPTH: Final = 64
#: Most digits a number literal may have.
MAX_NUMBER_DIGITS: Final = 30
#: Longest string that ``+`` may build at run time.
MAX_STRING_LENGTH: Final = 10_000


# --------------------------------------------------------------------------------------------
# Public API
# --------------------------------------------------------------------------------------------


class ExprError(Exception):
    """Syntax or name error found at load time.

    It carries the column separately from the message so that the post loader can point at
    the character inside the YAML value instead of making the technologist hunt for it.
    """

    message: str
    column: int

    def __init__(self, message: str, column: int) -> None:
        super().__init__(message)
        self.message = message
        self.column = column

    def __reduce__(self) -> tuple[type[ExprError], tuple[str, int]]:
        # The default reduction replays only ``args``; keep the column across pickling so that
        # errors survive being sent between processes.
        return (type(self), (self.message, self.column))


class ExprEvalError(Exception):
    """Error at run time (e.g. arithmetic on a parameter that has no value, division by zero).

    Its message names the parameter or quotes the sub-expression, because at run time the
    engine only knows which expression failed, not which part of it.
    """


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


@dataclass(frozen=True)
class Expression:
    """A checked, compiled expression, ready to be evaluated in the per-block hot path.

    ``names`` lets the post compiler know, without evaluating anything, which parameters an
    expression depends on (including those only inspected by ``changed()`` and
    ``defined()``).  Two expressions compare equal when their source and names do; the
    closure is not part of the comparison because it is derived from them.
    """

    source: str
    names: frozenset[str]
    evaluate: Evaluator = field(repr=False, compare=False)


def compile_expr(source: str, known_names: Container[str] | None = None) -> Expression:
    """Check ``source`` and compile it, so that any mistake surfaces when the post loads.

    When ``known_names`` is given, every parameter name must be in it; a close match, if the
    container is iterable, is suggested in the error message.

    Raises:
        ExprError: on any syntax error, unknown function, wrong number of arguments, unknown
            name, or when a limit on length, nesting or number size is exceeded.
    """
    if not isinstance(source, str):
        raise TypeError(f"expression source must be a string, not {type(source).__name__}")
    if len(source) > MAX_SOURCE_LENGTH:
        raise ExprError(
            f"expression is longer than {MAX_SOURCE_LENGTH} characters", MAX_SOURCE_LENGTH
        )
    parser = _Parser(source, known_names)
    tree = parser.parse()
    code = _Compiler(source).compile(tree)
    return Expression(source=source, names=frozenset(parser.names), evaluate=code.run)


# --------------------------------------------------------------------------------------------
# Tokenizer
# --------------------------------------------------------------------------------------------

_NUMBER: Final = "number"
_STRING: Final = "string"
_CONSTANT: Final = "constant"
_NAME: Final = "name"
_OPERATOR: Final = "operator"
_END: Final = "end"


class _Token(NamedTuple):
    kind: str
    #: the exact source text, so that the token's extent is known for spans and messages
    text: str
    start: int
    value: Any = None

    @property
    def end(self) -> int:
        return self.start + len(self.text)


_SPACE = re.compile(r"\s+")
# ASCII digits only: str.isdigit() and \d would accept digits of other scripts.
_NUMBER_LITERAL = re.compile(r"(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_NUMBER_LIKE = re.compile(r"[A-Za-z0-9_.]+")
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
# Besides the language's own operators, this recognises Python and C spellings that people are
# likely to try, so that they are reported whole and with advice instead of one character at a
# time.  Any other character is reported on its own.
_OPERATOR_TOKEN = re.compile(r"\*\*|==|!=|<=|>=|//|:=|&&|\|\||[-+*/%<>()\[\],]")
_OPERATORS = frozenset(
    {"==", "!=", "<=", ">=", "//", "-", "+", "*", "/", "%", "<", ">", "(", ")", "[", "]", ","}
)
_REJECTED_HINTS = {
    "=": "use '==' to compare",
    "!": "use 'not'",
    "&&": "use 'and'",
    "&": "use 'and'",
    "||": "use 'or'",
    "|": "use 'or'",
    ".": "attribute access is not supported",
}
_WORD_OPERATORS = frozenset({"and", "or", "not", "in"})
_CONSTANTS: Mapping[str, Any] = {
    "true": True,
    "false": False,
    "none": None,
    "True": True,
    "False": False,
    "None": None,
}
_KEYWORD_HINTS = {
    "is": "use '==' or '!='",
    "if": "conditional expressions are not supported",
    "else": "conditional expressions are not supported",
}
_QUOTES = "'\""
_ESCAPABLE = "'\"\\"


def _tokenize(source: str) -> Iterator[_Token]:
    """Yield tokens lazily, so that the parser reports the leftmost error of any kind first.

    After the end of the source it keeps yielding end tokens, which spares the parser a
    special case for looking past the end.
    """
    length = len(source)
    position = 0
    while True:
        space = _SPACE.match(source, position)
        if space:
            position = space.end()
        if position >= length:
            break
        if match := _NUMBER_LITERAL.match(source, position):
            token = _number(source, match)
        elif match := _IDENTIFIER.match(source, position):
            token = _word(source, match)
        elif source[position] in _QUOTES:
            token = _string(source, position)
        else:
            token = _operator(source, position)
        yield token
        position = token.end
    while True:
        yield _Token(_END, "", length)


def _number(source: str, match: re.Match[str]) -> _Token:
    text, start = match.group(), match.start()
    tail = _NUMBER_LIKE.match(source, match.end())
    if tail:
        # "1abc", "0x1f", "1_000", "1.2.3": report the whole run rather than splitting it.
        raise ExprError(f"invalid number {source[start : tail.end()]!r}", start)
    if sum(char.isdigit() for char in text) > MAX_NUMBER_DIGITS:
        raise ExprError(f"number literal has more than {MAX_NUMBER_DIGITS} digits", start)
    if "." in text or "e" in text or "E" in text:
        value: int | float = float(text)
        if not math.isfinite(value):
            raise ExprError("number literal is out of range", start)
    else:
        value = int(text)
    return _Token(_NUMBER, text, start, value)


def _word(source: str, match: re.Match[str]) -> _Token:
    text, start, end = match.group(), match.start(), match.end()
    if end < len(source) and source[end] in _QUOTES:
        raise ExprError("string prefixes such as f'...' are not supported", start)
    if text.startswith("__"):
        raise ExprError("names starting with '__' are not allowed", start)
    if text in _WORD_OPERATORS:
        return _Token(_OPERATOR, text, start)
    if text in _CONSTANTS:
        return _Token(_CONSTANT, text, start, _CONSTANTS[text])
    if keyword.iskeyword(text):
        # Reserved even where harmless, so that Python-isms fail loudly instead of being
        # taken for parameter names, and so that the language can grow without breaking posts.
        hint = _KEYWORD_HINTS.get(text)
        message = f"keyword {text!r} is not supported"
        raise ExprError(f"{message} ({hint})" if hint else message, start)
    return _Token(_NAME, text, start)


def _string(source: str, start: int) -> _Token:
    quote = source[start]
    chars: list[str] = []
    position = start + 1
    length = len(source)
    while position < length:
        char = source[position]
        if char == quote:
            end = position + 1
            return _Token(_STRING, source[start:end], start, "".join(chars))
        if char == "\\":
            escaped = source[position + 1 : position + 2]
            if not escaped:
                break
            if escaped not in _ESCAPABLE:
                raise ExprError(
                    f"invalid escape '\\{escaped}' (only \\', \\\" and \\\\ are allowed)",
                    position,
                )
            chars.append(escaped)
            position += 2
        else:
            chars.append(char)
            position += 1
    raise ExprError("unterminated string", start)


def _operator(source: str, position: int) -> _Token:
    match = _OPERATOR_TOKEN.match(source, position)
    text = match.group() if match else source[position]
    if text not in _OPERATORS:
        hint = _REJECTED_HINTS.get(text)
        raise ExprError(f"unexpected {text!r}" + (f" ({hint})" if hint else ""), position)
    return _Token(_OPERATOR, text, position)


# --------------------------------------------------------------------------------------------
# Syntax tree
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class _Node:
    #: source span, parentheses included, for quoting the sub-expression in run-time errors
    start: int
    end: int
    #: levels of operators in the sub-tree (0 for a leaf); bounded so that compiling and
    #: evaluating cannot overflow the stack
    depth: int


@dataclass(frozen=True, slots=True)
class _Const(_Node):
    value: Any


@dataclass(frozen=True, slots=True)
class _Name(_Node):
    name: str


@dataclass(frozen=True, slots=True)
class _Probe(_Node):
    """``changed(name)`` or ``defined(name)``: they inspect a parameter instead of reading it."""

    function: str
    name: str


@dataclass(frozen=True, slots=True)
class _List(_Node):
    items: tuple[_Node, ...]


@dataclass(frozen=True, slots=True)
class _Unary(_Node):
    op: str
    operand: _Node


@dataclass(frozen=True, slots=True)
class _Logical(_Node):
    """``and`` / ``or`` over any number of operands: a flat chain keeps the tree shallow."""

    op: str
    operands: tuple[_Node, ...]


@dataclass(frozen=True, slots=True)
class _Arithmetic(_Node):
    """A left-associative chain such as ``a - b + c``, flat so that long sums stay shallow."""

    first: _Node
    rest: tuple[tuple[str, _Node], ...]


@dataclass(frozen=True, slots=True)
class _Comparison(_Node):
    """A comparison chain such as ``0 < x <= 5``, with Python's pairwise meaning."""

    first: _Node
    rest: tuple[tuple[str, _Node], ...]


@dataclass(frozen=True, slots=True)
class _Call(_Node):
    function: str
    args: tuple[_Node, ...]


# --------------------------------------------------------------------------------------------
# Parser
# --------------------------------------------------------------------------------------------

# Binding powers, loosest first.  A prefix operator's power is the one its operand is parsed
# with: ``not`` takes a whole comparison, unary minus only a single factor.
_OR: Final = 1
_AND: Final = 2
_NOT: Final = 3
_COMPARE: Final = 4
_SUM: Final = 5
_PRODUCT: Final = 6
_SIGN: Final = 7

_INFIX_POWER: Mapping[str, int] = {
    "or": _OR,
    "and": _AND,
    "==": _COMPARE,
    "!=": _COMPARE,
    "<": _COMPARE,
    "<=": _COMPARE,
    ">": _COMPARE,
    ">=": _COMPARE,
    "in": _COMPARE,
    "not": _COMPARE,  # the first half of "not in"
    "+": _SUM,
    "-": _SUM,
    "*": _PRODUCT,
    "/": _PRODUCT,
    "//": _PRODUCT,
    "%": _PRODUCT,
}
_MISPLACED_HINTS = {
    "(": "only functions can be called",
    "[": "subscripts are not supported",
}
_PROBES = frozenset({"changed", "defined"})


class _Parser:
    """Pratt parser: one loop handles every binary precedence level.

    Compared with one recursive function per level it needs only a couple of stack frames
    per bracket, which keeps even the deepest accepted expression far from Python's
    recursion limit.
    """

    def __init__(self, source: str, known_names: Container[str] | None) -> None:
        self._tokens = _tokenize(source)
        self._token = next(self._tokens)
        self._known_names = known_names
        self._nesting = 0
        self.names: set[str] = set()

    def parse(self) -> _Node:
        if self._token.kind == _END:
            raise ExprError("expression is empty", 0)
        node = self._expression(0)
        if self._token.kind != _END:
            raise self._unexpected()
        return node

    # -- expressions ---------------------------------------------------------------------

    def _expression(self, min_power: int) -> _Node:
        """Parse operators that bind tighter than ``min_power``.

        Operators of one level are gathered into a single flat node; since the parsed right
        operand swallows every tighter operator, the levels met here only ever get looser.
        """
        left = self._prefix(min_power)
        power = 0
        rest: list[tuple[str, _Node]] = []
        while True:
            token = self._token
            op_power = _INFIX_POWER.get(token.text) if token.kind == _OPERATOR else None
            if op_power is None:
                if token.kind == _OPERATOR and token.text in _MISPLACED_HINTS:
                    raise self._unexpected(_MISPLACED_HINTS[token.text])
                break
            if op_power <= min_power:
                break
            self._advance()
            op = token.text
            if op == "not":
                self._expect("in")
                op = "not in"
            if op in ("in", "not in") and self._at("["):
                right = self._list()
            else:
                right = self._expression(op_power)
            if rest and op_power != power:
                left = self._chain(power, left, rest)
                rest = []
            power = op_power
            rest.append((op, right))
        return self._chain(power, left, rest) if rest else left

    def _prefix(self, min_power: int) -> _Node:
        token = self._token
        if token.kind in (_NUMBER, _STRING, _CONSTANT):
            self._advance()
            return _Const(token.start, token.end, 0, token.value)
        if token.kind == _NAME:
            self._advance()
            return self._call(token) if self._at("(") else self._name(token)
        if token.kind == _OPERATOR:
            if token.text == "(":
                return self._group()
            if token.text in ("-", "+"):
                return self._unary(_SIGN)
            if token.text == "not":
                if min_power >= _COMPARE:
                    # As in Python: "a == not b" and "-not a" are errors, not guesses.
                    raise self._unexpected("put 'not ...' in parentheses")
                return self._unary(_NOT)
            if token.text == "[":
                raise self._unexpected("a list can only follow 'in' or 'not in'")
        raise self._unexpected()

    def _group(self) -> _Node:
        opening = self._descend()
        inner = self._expression(0)
        closing = self._expect(")")
        self._nesting -= 1
        # Widen the span so that run-time messages quote balanced text.
        return replace(inner, start=opening.start, end=closing.end)

    def _unary(self, power: int) -> _Node:
        token = self._descend()
        operand = self._expression(power)
        self._nesting -= 1
        depth = self._depth((operand,), token.start)
        return _Unary(token.start, operand.end, depth, token.text, operand)

    def _list(self) -> _Node:
        opening = self._descend()
        items: list[_Node] = []
        while not self._at("]"):
            items.append(self._expression(0))
            if not self._at(","):
                break
            self._advance()
        closing = self._expect("]")
        self._nesting -= 1
        token = self._token
        if token.kind == _OPERATOR and _INFIX_POWER.get(token.text, 0) >= _COMPARE:
            # A list is not a value of the language, only the right-hand side of a membership
            # test, so it cannot take part in any further comparison or arithmetic.
            raise self._unexpected("a list can only be the right-hand side of 'in'")
        depth = self._depth(items, opening.start)
        return _List(opening.start, closing.end, depth, tuple(items))

    def _call(self, name: _Token) -> _Node:
        function = name.text
        if function in _PROBES:
            return self._probe(name)
        spec = _FUNCTIONS.get(function)
        if spec is None:
            raise self._unknown_function(name)
        self._descend()
        args: list[_Node] = []
        while not self._at(")"):
            args.append(self._expression(0))
            if not self._at(","):
                break
            self._advance()
        closing = self._expect(")")
        self._nesting -= 1
        most = len(args) if spec.max_args is None else spec.max_args
        if not spec.min_args <= len(args) <= most:
            raise ExprError(_arity_message(function, spec, len(args)), name.start)
        depth = self._depth(args, name.start)
        return _Call(name.start, closing.end, depth, function, tuple(args))

    def _probe(self, name: _Token) -> _Node:
        """Parse ``changed(x)`` / ``defined(x)``, whose argument is a name, never a value."""
        self._advance()
        argument = self._token
        if argument.kind != _NAME:
            raise ExprError(f"{name.text}() expects a parameter name", argument.start)
        self._advance()
        if self._at("("):
            raise ExprError(f"{name.text}() expects a parameter name", argument.start)
        closing = self._expect(")")
        self._use_name(argument)
        return _Probe(name.start, closing.end, 0, name.text, argument.text)

    def _name(self, token: _Token) -> _Node:
        self._use_name(token)
        return _Name(token.start, token.end, 0, token.text)

    def _chain(self, power: int, first: _Node, rest: Sequence[tuple[str, _Node]]) -> _Node:
        operands = (first, *(node for _, node in rest))
        start, end = first.start, operands[-1].end
        depth = self._depth(operands, start)
        if power == _OR:
            return _Logical(start, end, depth, "or", operands)
        if power == _AND:
            return _Logical(start, end, depth, "and", operands)
        if power == _COMPARE:
            return _Comparison(start, end, depth, first, tuple(rest))
        return _Arithmetic(start, end, depth, first, tuple(rest))

    # -- bookkeeping ---------------------------------------------------------------------

    def _advance(self) -> _Token:
        token = self._token
        self._token = next(self._tokens)
        return token

    def _at(self, text: str) -> bool:
        return self._token.kind == _OPERATOR and self._token.text == text

    def _expect(self, text: str) -> _Token:
        if not self._at(text):
            token = self._token
            raise ExprError(f"expected {text!r}, found {_describe(token)}", token.start)
        return self._advance()

    def _descend(self) -> _Token:
        """Consume an opening token, refusing to go deeper than the limit.

        Checked on the way down, before recursing, because a tree height computed on the
        way back up would come too late to protect the parser's own stack.
        """
        self._nesting += 1
        if self._nesting > MAX_DEPTH:
            raise ExprError(_too_deep(), self._token.start)
        return self._advance()

    @staticmethod
    def _depth(children: Iterable[_Node], column: int) -> int:
        # Operator precedence can stack several tree levels inside one bracket, so the height
        # of the tree, which bounds recursion when compiling and evaluating, is checked too.
        depth = 1 + max((child.depth for child in children), default=0)
        if depth > MAX_DEPTH:
            raise ExprError(_too_deep(), column)
        return depth

    def _use_name(self, token: _Token) -> None:
        name = token.text
        known = self._known_names
        if known is not None and name not in known:
            raise ExprError(_unknown("name", name, known), token.start)
        self.names.add(name)

    def _unknown_function(self, token: _Token) -> ExprError:
        name = token.text
        known = self._known_names
        if known is not None and name in known:
            return ExprError(f"{name!r} is a parameter, not a function", token.start)
        return ExprError(_unknown("function", name, [*_FUNCTIONS, *_PROBES]), token.start)

    def _unexpected(self, hint: str | None = None) -> ExprError:
        token = self._token
        message = f"unexpected {_describe(token)}"
        return ExprError(f"{message} ({hint})" if hint else message, token.start)


def _describe(token: _Token) -> str:
    if token.kind == _END:
        return "end of expression"
    if token.kind == _STRING:
        return f"string {token.text}"  # already quoted
    if token.kind in (_NAME, _NUMBER):
        return f"{token.kind} {token.text!r}"
    return repr(token.text)


def _unknown(what: str, name: str, candidates: object) -> str:
    message = f"unknown {what} {name!r}"
    if isinstance(candidates, Iterable):
        words = [candidate for candidate in candidates if isinstance(candidate, str)]
        matches = difflib.get_close_matches(name, words, n=1)
        if matches:
            message += f"; did you mean {matches[0]!r}?"
    return message


def _too_deep() -> str:
    return f"expression is nested too deeply (more than {MAX_DEPTH} levels)"


def _arity_message(function: str, spec: _Function, given: int) -> str:
    low, high = spec.min_args, spec.max_args
    if high is None:
        expected = f"at least {low} arguments"
    elif low == high:
        expected = f"{low} argument" + ("" if low == 1 else "s")
    else:
        expected = f"{low} or {high} arguments"
    return f"{function}() takes {expected} ({given} given)"


# --------------------------------------------------------------------------------------------
# Run-time semantics
# --------------------------------------------------------------------------------------------

#: bool is included on purpose: it is an int in Python, and "count + flag" has its usual meaning.
_NUMBERS: Final = (int, float)
_SEQUENCES: Final = (list, tuple)


class _Mismatch(Exception):
    """Operands of a type the operation does not accept.

    Raised by the kernels below, which do not know the source text; the closure that called
    them turns it into an :class:`ExprEvalError` through a :class:`_Blame`.
    """

    def __init__(self, index: int | None = None, expected: str = "a number") -> None:
        super().__init__(expected)
        self.index = index
        self.expected = expected


class _Invalid(Exception):
    """Operands of the right type but outside the operation's domain (e.g. ``sqrt(-1)``)."""


def _add(a: Any, b: Any) -> Any:
    if isinstance(a, _NUMBERS) and isinstance(b, _NUMBERS):
        return a + b
    if isinstance(a, str) and isinstance(b, str):
        if len(a) + len(b) > MAX_STRING_LENGTH:
            raise _Invalid(f"string would be longer than {MAX_STRING_LENGTH} characters")
        return a + b
    raise _Mismatch


def _numeric(apply: Callable[[Any, Any], Any]) -> Callable[[Any, Any], Any]:
    """Restrict a Python operator to numbers, so that ``*`` never repeats a string or list."""

    def kernel(a: Any, b: Any) -> Any:
        if isinstance(a, _NUMBERS) and isinstance(b, _NUMBERS):
            return apply(a, b)
        raise _Mismatch

    return kernel


def _ordered(compare: Callable[[Any, Any], bool]) -> Callable[[Any, Any], bool]:
    """Restrict an ordering to number/number and string/string, the only meaningful pairs."""

    def kernel(a: Any, b: Any) -> bool:
        if (isinstance(a, _NUMBERS) and isinstance(b, _NUMBERS)) or (
            isinstance(a, str) and isinstance(b, str)
        ):
            return compare(a, b)
        raise _Mismatch

    return kernel


def _contains(item: Any, container: Any) -> bool:
    if isinstance(container, _SEQUENCES) or (isinstance(container, str) and isinstance(item, str)):
        return item in container
    raise _Mismatch


def _not_contains(item: Any, container: Any) -> bool:
    return not _contains(item, container)


_ARITHMETIC: Mapping[str, Callable[[Any, Any], Any]] = {
    "+": _add,
    "-": _numeric(operator.sub),
    "*": _numeric(operator.mul),
    "/": _numeric(operator.truediv),
    "//": _numeric(operator.floordiv),
    "%": _numeric(operator.mod),
}
_ORDERINGS: Mapping[str, Callable[[Any, Any], bool]] = {
    "<": operator.lt,
    "<=": operator.le,
    ">": operator.gt,
    ">=": operator.ge,
}
_COMPARISONS: Mapping[str, Callable[[Any, Any], bool]] = {
    "==": operator.eq,
    "!=": operator.ne,
    **{symbol: _ordered(compare) for symbol, compare in _ORDERINGS.items()},
    "in": _contains,
    "not in": _not_contains,
}
_SIGNS: Mapping[str, Callable[[Any], Any]] = {"-": operator.neg, "+": operator.pos}


def _check_numbers(*args: Any) -> None:
    for index, value in enumerate(args):
        if not isinstance(value, _NUMBERS):
            raise _Mismatch(index)


def _integral(value: Any) -> float:
    """Check for a finite number, the only kind that has an integer value."""
    _check_numbers(value)
    if isinstance(value, float) and not math.isfinite(value):
        raise _Invalid(f"{value!r} has no integer value")
    return value  # type: ignore[no-any-return]


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
        raise _Invalid("square root of a negative number")
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
        raise _Mismatch(1, f"a whole number of digits from -{_ROUND_DIGITS} to {_ROUND_DIGITS}")
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


class _Function(NamedTuple):
    impl: Callable[..., Any]
    min_args: int
    #: None: no upper bound
    max_args: int | None


_FUNCTIONS: Mapping[str, _Function] = {
    "abs": _Function(_abs, 1, 1),
    "min": _Function(_min, 2, None),
    "max": _Function(_max, 2, None),
    "round": _Function(_round, 1, 2),
    "floor": _Function(_floor, 1, 1),
    "ceil": _Function(_ceil, 1, 1),
    "sqrt": _Function(_sqrt, 1, 1),
    "int": _Function(_int, 1, 1),
}

#: What the kernels may raise on bad input; anything else is a bug and should propagate.
_FAILURES: Final = (_Mismatch, _Invalid, ArithmeticError, ValueError)


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


def _no_value(name: str) -> ExprEvalError:
    return ExprEvalError(f"parameter {name!r} has no value")


@dataclass(frozen=True, slots=True)
class _Blame:
    """Words the run-time error of one operation.

    Everything it needs is prepared at compile time, so that the hot path carries no
    diagnostic baggage beyond a reference to this object.
    """

    #: how the operation is named in messages: "'+'" or "round()"
    symbol: str
    #: the sub-expression's source, quoted in messages
    text: str
    #: the operand nodes, or None for an intermediate result of a chain
    operands: tuple[_Node | None, ...]
    is_call: bool = False

    def __call__(self, error: Exception, values: Sequence[Any]) -> ExprEvalError:
        # A parameter without a value is nearly always the real cause, so it is named first.
        for value, node in zip(values, self.operands, strict=False):
            if value is None and isinstance(node, _Name):
                return _no_value(node.name)
        where = f"in {self.text!r}"
        if isinstance(error, ZeroDivisionError):
            return ExprEvalError(f"division by zero {where}")
        if isinstance(error, _Invalid):
            return ExprEvalError(f"{error} {where}")
        if isinstance(error, _Mismatch):
            if self.is_call:
                got = _type_name(values[error.index or 0])
                return ExprEvalError(f"{self.symbol} expects {error.expected}, got {got} {where}")
            types = " and ".join(_type_name(value) for value in values)
            return ExprEvalError(f"cannot apply {self.symbol} to {types} {where}")
        return ExprEvalError(f"number out of range {where}")


# --------------------------------------------------------------------------------------------
# Closures
#
# Each factory returns the evaluator of one node.  They are module-level functions rather than
# methods so that the closures capture only what they use.
# --------------------------------------------------------------------------------------------


def _constant(value: Any) -> Evaluator:
    def evaluate(scope: Scope) -> Any:
        return value

    return evaluate


def _lookup(name: str) -> Evaluator:
    def evaluate(scope: Scope) -> Any:
        try:
            return scope.values[name]
        except KeyError:
            raise _no_value(name) from None

    return evaluate


def _changed(name: str) -> Evaluator:
    def evaluate(scope: Scope) -> bool:
        return name in scope.changed

    return evaluate


def _defined(name: str) -> Evaluator:
    def evaluate(scope: Scope) -> bool:
        return scope.values.get(name) is not None

    return evaluate


def _tuple(items: tuple[Evaluator, ...]) -> Evaluator:
    def evaluate(scope: Scope) -> tuple[Any, ...]:
        return tuple([item(scope) for item in items])

    return evaluate


def _not(operand: Evaluator) -> Evaluator:
    def evaluate(scope: Scope) -> bool:
        return not operand(scope)

    return evaluate


def _sign(apply: Callable[[Any], Any], operand: Evaluator, blame: _Blame) -> Evaluator:
    def evaluate(scope: Scope) -> Any:
        value = operand(scope)
        if isinstance(value, _NUMBERS):
            return apply(value)
        raise blame(_Mismatch(), (value,))

    return evaluate


def _all(operands: tuple[Evaluator, ...]) -> Evaluator:
    if len(operands) == 2:
        first, second = operands

        def evaluate_pair(scope: Scope) -> bool:
            return bool(first(scope) and second(scope))

        return evaluate_pair

    def evaluate(scope: Scope) -> bool:
        for operand in operands:  # noqa: SIM110 - all() over a generator is slower here
            if not operand(scope):
                return False
        return True

    return evaluate


def _any(operands: tuple[Evaluator, ...]) -> Evaluator:
    if len(operands) == 2:
        first, second = operands

        def evaluate_pair(scope: Scope) -> bool:
            return bool(first(scope) or second(scope))

        return evaluate_pair

    def evaluate(scope: Scope) -> bool:
        for operand in operands:  # noqa: SIM110 - any() over a generator is slower here
            if operand(scope):
                return True
        return False

    return evaluate


def _binary(
    left: Evaluator, kernel: Callable[[Any, Any], Any], right: Evaluator, blame: _Blame
) -> Evaluator:
    def evaluate(scope: Scope) -> Any:
        a = left(scope)
        b = right(scope)
        try:
            return kernel(a, b)
        except _FAILURES as error:
            raise blame(error, (a, b)) from None

    return evaluate


def _equality(left: Evaluator, symbol: str, right: _Code) -> Evaluator:
    """``==`` / ``!=`` accept any operands, so they need no checks and get the fastest path.

    The result is whatever ``__eq__`` returns, which is a bool for every value a scope holds.
    """
    compare = _COMPARISONS[symbol]
    if right.constant:
        value = right.value
        if symbol == "==":

            def equals_constant(scope: Scope) -> Any:
                return left(scope) == value

            return equals_constant

        def differs_from_constant(scope: Scope) -> Any:
            return left(scope) != value

        return differs_from_constant
    fetch = right.run

    def evaluate(scope: Scope) -> Any:
        return compare(left(scope), fetch(scope))

    return evaluate


def _ordering(left: Evaluator, symbol: str, right: _Code, blame: _Blame) -> Evaluator:
    """Specialise ``x > 0``-style tests: with a constant operand only the other is checked."""
    value = right.value
    if not right.constant or not isinstance(value, (*_NUMBERS, str)):
        return _binary(left, _COMPARISONS[symbol], right.run, blame)
    compare = _ORDERINGS[symbol]
    kind = _NUMBERS if isinstance(value, _NUMBERS) else str

    def evaluate(scope: Scope) -> bool:
        a = left(scope)
        if isinstance(a, kind):
            return compare(a, value)
        raise blame(_Mismatch(), (a, value))

    return evaluate


_Step = tuple[Callable[[Any, Any], Any], Evaluator, _Blame]


def _fold_left(first: Evaluator, steps: tuple[_Step, ...]) -> Evaluator:
    """Evaluate ``a - b + c ...`` in a loop, so that a long chain costs no stack depth."""

    def evaluate(scope: Scope) -> Any:
        result = first(scope)
        for kernel, operand, blame in steps:
            value = operand(scope)
            try:
                result = kernel(result, value)
            except _FAILURES as error:
                raise blame(error, (result, value)) from None
        return result

    return evaluate


def _compare_chain(first: Evaluator, steps: tuple[_Step, ...]) -> Evaluator:
    """``a < b < c`` means ``a < b and b < c`` with ``b`` evaluated once, as in Python."""

    def evaluate(scope: Scope) -> bool:
        left = first(scope)
        for kernel, operand, blame in steps:
            right = operand(scope)
            try:
                if not kernel(left, right):
                    return False
            except _FAILURES as error:
                raise blame(error, (left, right)) from None
            left = right
        return True

    return evaluate


def _call(impl: Callable[..., Any], args: tuple[Evaluator, ...], blame: _Blame) -> Evaluator:
    if len(args) == 1:
        (arg,) = args

        def call_one(scope: Scope) -> Any:
            value = arg(scope)
            try:
                return impl(value)
            except _FAILURES as error:
                raise blame(error, (value,)) from None

        return call_one

    def evaluate(scope: Scope) -> Any:
        values = [arg(scope) for arg in args]
        try:
            return impl(*values)
        except _FAILURES as error:
            raise blame(error, values) from None

    return evaluate


# --------------------------------------------------------------------------------------------
# Compiler
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class _Code:
    """A compiled node; constants carry their value so that parents can fold or specialise."""

    run: Evaluator
    constant: bool = False
    value: Any = None


def _literal(value: Any) -> _Code:
    return _Code(_constant(value), constant=True, value=value)


class _FoldingScope:
    """The scope constant sub-trees are folded in: they never look anything up."""

    values: Mapping[str, Any] = MappingProxyType({})
    changed: Container[str] = frozenset()


_FOLDING_SCOPE: Final = _FoldingScope()


class _Compiler:
    def __init__(self, source: str) -> None:
        self._source = source

    def compile(self, node: _Node) -> _Code:
        match node:
            case _Const(value=value):
                return _literal(value)
            case _Name(name=name):
                return _Code(_lookup(name))
            case _Probe(function="changed", name=name):
                return _Code(_changed(name))
            case _Probe(name=name):
                return _Code(_defined(name))
            case _List(items=items):
                parts = [self.compile(item) for item in items]
                return self._fold(_tuple(tuple(part.run for part in parts)), parts)
            case _Unary(op="not", operand=operand):
                part = self.compile(operand)
                return self._fold(_not(part.run), [part])
            case _Unary(op=op, operand=operand):
                part = self.compile(operand)
                blame = _Blame(repr(op), self._text(node), (operand,))
                return self._fold(_sign(_SIGNS[op], part.run, blame), [part])
            case _Logical(op=op, operands=operands):
                parts = [self.compile(operand) for operand in operands]
                runs = tuple(part.run for part in parts)
                return self._fold(_all(runs) if op == "and" else _any(runs), parts)
            case _Arithmetic() | _Comparison():
                return self._chain(node)
            case _Call(function=function, args=args):
                parts = [self.compile(arg) for arg in args]
                blame = _Blame(f"{function}()", self._text(node), args, is_call=True)
                impl = _FUNCTIONS[function].impl
                return self._fold(_call(impl, tuple(part.run for part in parts), blame), parts)
        raise AssertionError(f"no compiler for {type(node).__name__}")

    def _chain(self, node: _Arithmetic | _Comparison) -> _Code:
        arithmetic = isinstance(node, _Arithmetic)
        kernels = _ARITHMETIC if arithmetic else _COMPARISONS
        first = self.compile(node.first)
        parts = [first]
        steps: list[_Step] = []
        left_node: _Node | None = node.first
        for symbol, right_node in node.rest:
            right = self.compile(right_node)
            parts.append(right)
            # In "a - b + c" the left operand of "+" is the result of "a - b"; in "a < b < c"
            # the second test is "b < c".  Quote and blame exactly that.
            start = node.first.start if left_node is None else left_node.start
            blame = _Blame(
                repr(symbol), self._source[start : right_node.end], (left_node, right_node)
            )
            steps.append((kernels[symbol], right.run, blame))
            left_node = None if arithmetic else right_node
        if arithmetic:
            first, steps = self._fold_prefix(first, parts, steps)
        if len(steps) > 1:
            run = (_fold_left if arithmetic else _compare_chain)(first.run, tuple(steps))
        else:
            symbol = node.rest[-1][0]
            kernel, operand, blame = steps[0]
            if symbol in ("==", "!="):
                run = _equality(first.run, symbol, parts[-1])
            elif symbol in _ORDERINGS:
                run = _ordering(first.run, symbol, parts[-1], blame)
            else:
                run = _binary(first.run, kernel, operand, blame)
        return self._fold(run, parts)

    @staticmethod
    def _fold_prefix(
        first: _Code, parts: Sequence[_Code], steps: list[_Step]
    ) -> tuple[_Code, list[_Step]]:
        """Fold the literal-only start of a chain: ``1 + 2 + x`` is ``(1 + 2) + x``."""
        folded = 0
        while folded < len(steps) - 1 and first.constant and parts[folded + 1].constant:
            try:
                value = steps[folded][0](first.value, parts[folded + 1].value)
            except _FAILURES:
                break  # leave the error to run time, like _fold()
            first = _literal(value)
            folded += 1
        return first, steps[folded:]

    def _fold(self, run: Evaluator, parts: Sequence[_Code]) -> _Code:
        """Precompute a node whose operands are all constant.

        If that fails, the node is left for run time instead: ``false and 1 / 0`` must not
        stop a post from loading, and a failure in a branch that does run is still reported,
        with the same message, when it runs.
        """
        if all(part.constant for part in parts):
            try:
                return _literal(run(_FOLDING_SCOPE))
            except ExprEvalError:
                pass
        return _Code(run)

    def _text(self, node: _Node) -> str:
        return self._source[node.start : node.end]
