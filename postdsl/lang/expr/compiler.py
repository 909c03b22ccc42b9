"""Compiler of the expression language: syntax tree -> nested closures.

Expressions run for every block of every CL command, so all dispatch on node types, operators
and literal values is paid once, at load time; at run time a node costs one Python call, and
literal-only sub-trees are already folded into constants.  The closures call the checked
operations of :mod:`postdsl.lang.expr.runtime`, each with a :class:`Blame` that words its error.
"""

from __future__ import annotations

from collections.abc import Callable, Container, Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Final

from postdsl.lang.expr import nodes
from postdsl.lang.expr.errors import ExprEvalError
from postdsl.lang.expr.runtime import (
    ARITHMETIC,
    COMPARISONS,
    FAILURES,
    FUNCTIONS,
    NUMBERS,
    ORDERINGS,
    SIGNS,
    Blame,
    Evaluator,
    Mismatch,
    Scope,
    TextFormat,
    format_text,
    index,
    no_value,
)


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
    #: the checked syntax tree and the formats ``str()`` was bound to, for back ends that
    #: write the expression out in another form (they must not parse the source again
    #: without the formats)
    tree: nodes.Node | None = field(default=None, repr=False, compare=False)
    formats: Mapping[str, TextFormat] = field(default_factory=dict, repr=False, compare=False)
    #: the formats ``str()`` writes with, by name (empty: the expression needs none)
    texts: frozenset[str] = field(default=frozenset(), compare=False)


def compile_expr(
    source: str,
    known_names: Container[str] | None = None,
    formats: Mapping[str, TextFormat] | None = None,
) -> Expression:
    """Check ``source`` and compile it, so that any mistake surfaces when the post loads.

    When ``known_names`` is given, every parameter name must be in it; a close match, if the
    container is iterable, is suggested in the error message.  ``formats`` are the post's
    named number formats, which ``str(x, 'name')`` writes with: the name is checked here and
    the format bound once, so an expression without ``str()`` needs none.

    Raises:
        ExprError: on any syntax error, unknown function, wrong number of arguments, unknown
            name, or when a limit on length, nesting or number size is exceeded.
    """
    if not isinstance(source, str):
        raise TypeError(f"expression source must be a string, not {type(source).__name__}")
    from postdsl.lang.expr.parser import parse  # a post from the cache holds its trees

    tree, names = parse(source, known_names, formats)
    code = Compiler(source, formats or {}).compile(tree)
    texts = frozenset(node.format for node in nodes.walk(tree) if isinstance(node, nodes.Text))
    return Expression(source=source, names=names, evaluate=code.run, tree=tree,
                      formats=formats or {}, texts=texts)


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
            raise no_value(name) from None

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


def _sign(apply: Callable[[Any], Any], operand: Evaluator, blame: Blame) -> Evaluator:
    def evaluate(scope: Scope) -> Any:
        value = operand(scope)
        if isinstance(value, NUMBERS):
            return apply(value)
        raise blame(Mismatch(), (value,))

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
    left: Evaluator, kernel: Callable[[Any, Any], Any], right: Evaluator, blame: Blame
) -> Evaluator:
    def evaluate(scope: Scope) -> Any:
        a = left(scope)
        b = right(scope)
        try:
            return kernel(a, b)
        except FAILURES as error:
            raise blame(error, (a, b)) from None

    return evaluate


def _equality(left: Evaluator, symbol: str, right: _Code) -> Evaluator:
    """``==`` / ``!=`` accept any operands, so they need no checks and get the fastest path.

    The result is whatever ``__eq__`` returns, which is a bool for every value a scope holds.
    """
    compare = COMPARISONS[symbol]
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


def _ordering(left: Evaluator, symbol: str, right: _Code, blame: Blame) -> Evaluator:
    """Specialise ``x > 0``-style tests: with a constant operand only the other is checked."""
    value = right.value
    if not right.constant or not isinstance(value, (*NUMBERS, str)):
        return _binary(left, COMPARISONS[symbol], right.run, blame)
    compare = ORDERINGS[symbol]
    kind = NUMBERS if isinstance(value, NUMBERS) else str

    def evaluate(scope: Scope) -> bool:
        a = left(scope)
        if isinstance(a, kind):
            return compare(a, value)
        raise blame(Mismatch(), (a, value))

    return evaluate


_Step = tuple[Callable[[Any, Any], Any], Evaluator, Blame]


def _fold_left(first: Evaluator, steps: tuple[_Step, ...]) -> Evaluator:
    """Evaluate ``a - b + c ...`` in a loop, so that a long chain costs no stack depth."""

    def evaluate(scope: Scope) -> Any:
        result = first(scope)
        for kernel, operand, blame in steps:
            value = operand(scope)
            try:
                result = kernel(result, value)
            except FAILURES as error:
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
            except FAILURES as error:
                raise blame(error, (left, right)) from None
            left = right
        return True

    return evaluate


def _call(impl: Callable[..., Any], args: tuple[Evaluator, ...], blame: Blame) -> Evaluator:
    if len(args) == 1:
        (arg,) = args

        def call_one(scope: Scope) -> Any:
            value = arg(scope)
            try:
                return impl(value)
            except FAILURES as error:
                raise blame(error, (value,)) from None

        return call_one

    def evaluate(scope: Scope) -> Any:
        values = [arg(scope) for arg in args]
        try:
            return impl(*values)
        except FAILURES as error:
            raise blame(error, values) from None

    return evaluate


def _choose(test: Evaluator, then: Evaluator, otherwise: Evaluator) -> Evaluator:
    def evaluate(scope: Scope) -> Any:
        return then(scope) if test(scope) else otherwise(scope)

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


def _parameter(node: nodes.Node | None) -> str | None:
    """The parameter an operand reads, if it is a bare name: a run-time error names it."""
    return node.name if isinstance(node, nodes.Name) else None


class Compiler:
    """Compiles the tree of one source text, which it keeps for quoting in run-time errors."""

    def __init__(self, source: str, formats: Mapping[str, TextFormat] | None = None) -> None:
        self._source = source
        self._formats = formats or {}
        #: id(node) -> (node, its code): the generated module's emitter asks for each
        #: sub-tree's code on its way down, which compiled every sub-tree again per level
        self._known: dict[int, tuple[nodes.Node, _Code]] = {}

    def compile(self, node: nodes.Node) -> _Code:
        known = self._known.get(id(node))
        if known is not None and known[0] is node:  # the node is kept: its id is its own
            return known[1]
        code = self._compile(node)
        self._known[id(node)] = (node, code)
        return code

    def _compile(self, node: nodes.Node) -> _Code:
        match node:
            case nodes.Const(value=value):
                return _literal(value)
            case nodes.Name(name=name):
                return _Code(_lookup(name))
            case nodes.Probe(function="changed", name=name):
                return _Code(_changed(name))
            case nodes.Probe(name=name):
                return _Code(_defined(name))
            case nodes.List(items=items):
                parts = [self.compile(item) for item in items]
                return self._fold(_tuple(tuple(part.run for part in parts)), parts)
            case nodes.Unary(op="not", operand=operand):
                part = self.compile(operand)
                return self._fold(_not(part.run), [part])
            case nodes.Unary(op=op, operand=operand):
                part = self.compile(operand)
                blame = Blame(repr(op), self._text(node), (_parameter(operand),))
                return self._fold(_sign(SIGNS[op], part.run, blame), [part])
            case nodes.Logical(op=op, operands=operands):
                parts = [self.compile(operand) for operand in operands]
                runs = tuple(part.run for part in parts)
                return self._fold(_all(runs) if op == "and" else _any(runs), parts)
            case nodes.Arithmetic() | nodes.Comparison():
                return self._chain(node)
            case nodes.Call(function=function, args=args):
                parts = [self.compile(arg) for arg in args]
                parameters = tuple(_parameter(arg) for arg in args)
                blame = Blame(f"{function}()", self._text(node), parameters, is_call=True)
                impl = FUNCTIONS[function].impl
                return self._fold(_call(impl, tuple(part.run for part in parts), blame), parts)
            case nodes.Conditional(then=then, test=test, otherwise=otherwise):
                condition = self.compile(test)
                if condition.constant:  # only the branch that can run is compiled in
                    return self.compile(then if condition.value else otherwise)
                first, second = self.compile(then), self.compile(otherwise)
                return _Code(_choose(condition.run, first.run, second.run))
            case nodes.Index(target=target, index=position):
                parts = [self.compile(target), self.compile(position)]
                blame = Blame("a subscript", self._text(node),
                              (_parameter(target), _parameter(position)), is_call=True)
                run = _binary(parts[0].run, index, parts[1].run, blame)
                return self._fold(run, parts)
            case nodes.Text(value=value, format=name):
                part = self.compile(value)
                blame = Blame("str()", self._text(node), (_parameter(value),), is_call=True)
                text = format_text(self._formats[name].render, name)
                return self._fold(_call(text, (part.run,), blame), [part])
        raise AssertionError(f"no compiler for {type(node).__name__}")

    def _chain(self, node: nodes.Arithmetic | nodes.Comparison) -> _Code:
        arithmetic = isinstance(node, nodes.Arithmetic)
        kernels = ARITHMETIC if arithmetic else COMPARISONS
        first = self.compile(node.first)
        parts = [first]
        steps: list[_Step] = []
        left_node: nodes.Node | None = node.first
        for symbol, right_node in node.rest:
            right = self.compile(right_node)
            parts.append(right)
            # In "a - b + c" the left operand of "+" is the result of "a - b"; in "a < b < c"
            # the second test is "b < c".  Quote and blame exactly that.
            start = node.first.start if left_node is None else left_node.start
            blame = Blame(
                repr(symbol),
                self._source[start : right_node.end],
                (_parameter(left_node), _parameter(right_node)),
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
            elif symbol in ORDERINGS:
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
            except FAILURES:
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

    def _text(self, node: nodes.Node) -> str:
        return self._source[node.start : node.end]
