"""Parser of the expression language: tokens -> syntax tree.

A Pratt parser written for exactly this grammar accepts what is documented and rejects
everything else *when the post loads*, with the 0-based column of the offending character.
It also checks names (against the post's parameters, when known) and the argument counts of
functions, and bounds the source length and nesting depth so that no post, however hostile,
can exhaust the Python stack or make loading take unbounded time.
"""

from __future__ import annotations

import difflib
from collections.abc import Container, Iterable, Mapping, Sequence
from dataclasses import replace
from typing import Final

from postdsl.lang.expr import nodes
from postdsl.lang.expr.errors import ExprError
from postdsl.lang.expr.lexer import (
    CONSTANT,
    END,
    NAME,
    NUMBER,
    OPERATOR,
    STRING,
    Token,
    describe,
    tokenize,
)
from postdsl.lang.expr.runtime import FUNCTIONS, Function

#: Longest accepted source text, in characters.
MAX_SOURCE_LENGTH: Final = 2000
#: Deepest accepted nesting of brackets, calls, prefix operators and operator precedence levels.
MAX_DEPTH: Final = 64

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
    "[": "a list after 'in' cannot be indexed",
}
_PROBES = frozenset({"changed", "defined"})
#: ``str(x, 'format')`` takes a format name, not a value, so it is parsed apart from FUNCTIONS
_TEXT = "str"


def parse(
    source: str,
    known_names: Container[str] | None = None,
    format_names: Container[str] | None = None,
) -> tuple[nodes.Node, frozenset[str]]:
    """Build the syntax tree of ``source`` and collect the parameter names it uses.

    The length is checked before the first token is read, so that a huge text costs nothing.
    See :func:`postdsl.lang.expr.compile_expr` for ``known_names`` and ``format_names``.

    Raises:
        ExprError: on any syntax error, unknown function, wrong number of arguments, unknown
            name, or when a limit on length, nesting or number size is exceeded.
    """
    if len(source) > MAX_SOURCE_LENGTH:
        raise ExprError(
            f"expression is longer than {MAX_SOURCE_LENGTH} characters", MAX_SOURCE_LENGTH
        )
    parser = Parser(source, known_names, format_names)
    tree = parser.parse()
    return tree, frozenset(parser.names)


class Parser:
    """Pratt parser: one loop handles every binary precedence level.

    Compared with one recursive function per level it needs only a couple of stack frames
    per bracket, which keeps even the deepest accepted expression far from Python's
    recursion limit.
    """

    def __init__(
        self,
        source: str,
        known_names: Container[str] | None,
        format_names: Container[str] | None = None,
    ) -> None:
        self._tokens = tokenize(source)
        self._token = next(self._tokens)
        self._known_names = known_names
        self._format_names = format_names
        self._nesting = 0
        self.names: set[str] = set()

    def parse(self) -> nodes.Node:
        if self._token.kind == END:
            raise ExprError("expression is empty", 0)
        node = self._conditional()
        if self._token.kind != END:
            raise self._unexpected()
        return node

    # -- expressions ---------------------------------------------------------------------

    def _conditional(self) -> nodes.Node:
        """``a if c else b``, the loosest construct, as in Python.

        The test is an ``or`` chain, never another conditional, and the ``else`` branch may
        be one (``a if c else b if d else e``): each nesting counts towards the depth limit.
        """
        then = self._expression(0)
        if not self._at("if"):
            return then
        self._descend()
        test = self._expression(0)
        self._expect("else")
        otherwise = self._conditional()
        self._nesting -= 1
        depth = self._depth((then, test, otherwise), then.start)
        return nodes.Conditional(then.start, otherwise.end, depth, then, test, otherwise)

    def _expression(self, min_power: int) -> nodes.Node:
        """Parse operators that bind tighter than ``min_power``.

        Operators of one level are gathered into a single flat node; since the parsed right
        operand swallows every tighter operator, the levels met here only ever get looser.
        """
        left = self._prefix(min_power)
        power = 0
        rest: list[tuple[str, nodes.Node]] = []
        while True:
            token = self._token
            op_power = _INFIX_POWER.get(token.text) if token.kind == OPERATOR else None
            if op_power is None:
                if token.kind == OPERATOR and token.text in _MISPLACED_HINTS:
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

    def _prefix(self, min_power: int) -> nodes.Node:
        token = self._token
        if token.kind in (NUMBER, STRING, CONSTANT):
            self._advance()
            return self._subscripts(nodes.Const(token.start, token.end, 0, token.value))
        if token.kind == NAME:
            self._advance()
            return self._subscripts(self._call(token) if self._at("(") else self._name(token))
        if token.kind == OPERATOR:
            if token.text == "(":
                return self._subscripts(self._group())
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

    def _subscripts(self, target: nodes.Node) -> nodes.Node:
        """``tools[0]``, ``names[i][0]``: indexing binds tighter than any operator."""
        while self._at("["):
            self._descend()
            index = self._conditional()
            closing = self._expect("]")
            self._nesting -= 1
            depth = self._depth((target, index), target.start)
            target = nodes.Index(target.start, closing.end, depth, target, index)
        return target

    def _group(self) -> nodes.Node:
        opening = self._descend()
        inner = self._conditional()
        closing = self._expect(")")
        self._nesting -= 1
        # Widen the span so that run-time messages quote balanced text.
        return replace(inner, start=opening.start, end=closing.end)

    def _unary(self, power: int) -> nodes.Node:
        token = self._descend()
        operand = self._expression(power)
        self._nesting -= 1
        depth = self._depth((operand,), token.start)
        return nodes.Unary(token.start, operand.end, depth, token.text, operand)

    def _list(self) -> nodes.Node:
        opening = self._descend()
        items: list[nodes.Node] = []
        while not self._at("]"):
            items.append(self._conditional())
            if not self._at(","):
                break
            self._advance()
        closing = self._expect("]")
        self._nesting -= 1
        token = self._token
        if token.kind == OPERATOR and _INFIX_POWER.get(token.text, 0) >= _COMPARE:
            # A list is not a value of the language, only the right-hand side of a membership
            # test, so it cannot take part in any further comparison or arithmetic.
            raise self._unexpected("a list can only be the right-hand side of 'in'")
        depth = self._depth(items, opening.start)
        return nodes.List(opening.start, closing.end, depth, tuple(items))

    def _call(self, name: Token) -> nodes.Node:
        function = name.text
        if function in _PROBES:
            return self._probe(name)
        if function == _TEXT:
            return self._text(name)
        spec = FUNCTIONS.get(function)
        if spec is None:
            raise self._unknown_function(name)
        self._descend()
        args: list[nodes.Node] = []
        while not self._at(")"):
            args.append(self._conditional())
            if not self._at(","):
                break
            self._advance()
        closing = self._expect(")")
        self._nesting -= 1
        most = len(args) if spec.max_args is None else spec.max_args
        if not spec.min_args <= len(args) <= most:
            raise ExprError(_arity_message(function, spec, len(args)), name.start)
        depth = self._depth(args, name.start)
        return nodes.Call(name.start, closing.end, depth, function, tuple(args))

    def _probe(self, name: Token) -> nodes.Node:
        """Parse ``changed(x)`` / ``defined(x)``, whose argument is a name, never a value."""
        self._advance()
        argument = self._token
        if argument.kind != NAME:
            raise ExprError(f"{name.text}() expects a parameter name", argument.start)
        self._advance()
        if self._at("("):
            raise ExprError(f"{name.text}() expects a parameter name", argument.start)
        closing = self._expect(")")
        self._use_name(argument)
        return nodes.Probe(name.start, closing.end, 0, name.text, argument.text)

    def _text(self, name: Token) -> nodes.Node:
        """Parse ``str(value, 'format')``, whose format is a name the post must define."""
        usage = f"{_TEXT}() takes a number and the name of a format, as in {_TEXT}(x, 'coord')"
        self._descend()
        if self._at(")"):
            raise ExprError(usage, name.start)
        value = self._conditional()
        if not self._at(","):
            raise ExprError(usage, self._token.start)
        self._advance()
        token = self._token
        if token.kind != STRING:
            raise ExprError(f"{usage}: the format name must be a quoted literal", token.start)
        self._advance()
        closing = self._expect(")")
        self._nesting -= 1
        formats = self._format_names
        if formats is None:
            raise ExprError(f"{_TEXT}() needs the post's formats, and none are known here",
                            name.start)
        if token.value not in formats:
            raise ExprError(_unknown("format", token.value, formats), token.start)
        depth = self._depth((value,), name.start)
        return nodes.Text(name.start, closing.end, depth, value, token.value)

    def _name(self, token: Token) -> nodes.Node:
        self._use_name(token)
        return nodes.Name(token.start, token.end, 0, token.text)

    def _chain(
        self, power: int, first: nodes.Node, rest: Sequence[tuple[str, nodes.Node]]
    ) -> nodes.Node:
        operands = (first, *(node for _, node in rest))
        start, end = first.start, operands[-1].end
        depth = self._depth(operands, start)
        if power == _OR:
            return nodes.Logical(start, end, depth, "or", operands)
        if power == _AND:
            return nodes.Logical(start, end, depth, "and", operands)
        if power == _COMPARE:
            return nodes.Comparison(start, end, depth, first, tuple(rest))
        return nodes.Arithmetic(start, end, depth, first, tuple(rest))

    # -- bookkeeping ---------------------------------------------------------------------

    def _advance(self) -> Token:
        token = self._token
        self._token = next(self._tokens)
        return token

    def _at(self, text: str) -> bool:
        return self._token.kind == OPERATOR and self._token.text == text

    def _expect(self, text: str) -> Token:
        if not self._at(text):
            token = self._token
            raise ExprError(f"expected {text!r}, found {describe(token)}", token.start)
        return self._advance()

    def _descend(self) -> Token:
        """Consume an opening token, refusing to go deeper than the limit.

        Checked on the way down, before recursing, because a tree height computed on the
        way back up would come too late to protect the parser's own stack.
        """
        self._nesting += 1
        if self._nesting > MAX_DEPTH:
            raise ExprError(_too_deep(), self._token.start)
        return self._advance()

    @staticmethod
    def _depth(children: Iterable[nodes.Node], column: int) -> int:
        # Operator precedence can stack several tree levels inside one bracket, so the height
        # of the tree, which bounds recursion when compiling and evaluating, is checked too.
        depth = 1 + max((child.depth for child in children), default=0)
        if depth > MAX_DEPTH:
            raise ExprError(_too_deep(), column)
        return depth

    def _use_name(self, token: Token) -> None:
        name = token.text
        known = self._known_names
        if known is not None and name not in known:
            raise ExprError(_unknown("name", name, known), token.start)
        self.names.add(name)

    def _unknown_function(self, token: Token) -> ExprError:
        name = token.text
        known = self._known_names
        if known is not None and name in known:
            return ExprError(f"{name!r} is a parameter, not a function", token.start)
        return ExprError(_unknown("function", name, [*FUNCTIONS, *_PROBES, _TEXT]), token.start)

    def _unexpected(self, hint: str | None = None) -> ExprError:
        token = self._token
        message = f"unexpected {describe(token)}"
        return ExprError(f"{message} ({hint})" if hint else message, token.start)


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


def _arity_message(function: str, spec: Function, given: int) -> str:
    low, high = spec.min_args, spec.max_args
    if high is None:
        expected = f"at least {low} arguments"
    elif low == high:
        expected = f"{low} argument" + ("" if low == 1 else "s")
    else:
        expected = f"{low} or {high} arguments"
    return f"{function}() takes {expected} ({given} given)"
