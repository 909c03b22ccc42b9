"""The two exceptions of the expression language: one for load time, one for run time.

They live apart from the modules that raise them so that every stage (lexer, parser,
compiler, run-time operations) can raise them without importing another stage.
"""

from __future__ import annotations


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
