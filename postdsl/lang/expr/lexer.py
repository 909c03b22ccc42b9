"""Tokenizer of the expression language: source text -> tokens.

Written for exactly this grammar (never Python's ``tokenize``), it accepts what is documented
and rejects everything else with the 0-based column of the offending character.  Python and C
spellings that people are likely to try are recognised whole, so that they can be reported
with advice.
"""

from __future__ import annotations

import keyword
import math
import re
from collections.abc import Iterator, Mapping
from typing import Any, Final, NamedTuple

from postdsl.lang.expr.errors import ExprError

#: Most digits a number literal may have.
MAX_NUMBER_DIGITS: Final = 30

# Token kinds.
NUMBER: Final = "number"
STRING: Final = "string"
CONSTANT: Final = "constant"
NAME: Final = "name"
OPERATOR: Final = "operator"
END: Final = "end"


class Token(NamedTuple):
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
_WORD_OPERATORS = frozenset({"and", "or", "not", "in", "if", "else"})
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
}
_QUOTES = "'\""
_ESCAPABLE = "'\"\\"


def tokenize(source: str) -> Iterator[Token]:
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
        yield Token(END, "", length)


def describe(token: Token) -> str:
    """Name a token in an error message: ``name 'y'``, ``string 'a'``, ``'*'``."""
    if token.kind == END:
        return "end of expression"
    if token.kind == STRING:
        return f"string {token.text}"  # already quoted
    if token.kind in (NAME, NUMBER):
        return f"{token.kind} {token.text!r}"
    return repr(token.text)


def _number(source: str, match: re.Match[str]) -> Token:
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
    return Token(NUMBER, text, start, value)


def _word(source: str, match: re.Match[str]) -> Token:
    text, start, end = match.group(), match.start(), match.end()
    if end < len(source) and source[end] in _QUOTES:
        raise ExprError("string prefixes such as f'...' are not supported", start)
    if text.startswith("__"):
        raise ExprError("names starting with '__' are not allowed", start)
    if text in _WORD_OPERATORS:
        return Token(OPERATOR, text, start)
    if text in _CONSTANTS:
        return Token(CONSTANT, text, start, _CONSTANTS[text])
    if keyword.iskeyword(text):
        # Reserved even where harmless, so that Python-isms fail loudly instead of being
        # taken for parameter names, and so that the language can grow without breaking posts.
        hint = _KEYWORD_HINTS.get(text)
        message = f"keyword {text!r} is not supported"
        raise ExprError(f"{message} ({hint})" if hint else message, start)
    return Token(NAME, text, start)


def _string(source: str, start: int) -> Token:
    quote = source[start]
    chars: list[str] = []
    position = start + 1
    length = len(source)
    while position < length:
        char = source[position]
        if char == quote:
            end = position + 1
            return Token(STRING, source[start:end], start, "".join(chars))
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


def _operator(source: str, position: int) -> Token:
    match = _OPERATOR_TOKEN.match(source, position)
    text = match.group() if match else source[position]
    if text not in _OPERATORS:
        hint = _REJECTED_HINTS.get(text)
        raise ExprError(f"unexpected {text!r}" + (f" ({hint})" if hint else ""), position)
    return Token(OPERATOR, text, position)
