"""Options: values a post declares and the user sets when posting.

A post is a machine family in one file: ``options:`` name what may differ between its
members (block numbers on or off, the decimals of the coordinates, a header), each
with a type and a default.  Expressions and conditions read an option by name, as
they read a variable; a few settings may take an option's value with the explicit
form ``{option: NAME}`` (a format's keys, ``output.block_numbers``), resolved when
the post is compiled for one set of option values.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from postdsl.lang.post import nodes as n

#: option type -> how a message names a value of it
OPTION_TYPES: dict[str, str] = {"bool": "true or false", "int": "a whole number",
                                "number": "a number", "string": "text"}


class OptionValueError(ValueError):
    """An option value the post does not accept; the message names the option and why."""

    def __init__(self, message: str, option: str | None = None) -> None:
        super().__init__(message)
        #: the declared option the value was meant for (None: the post has no such option)
        self.option = option


def type_matches(kind: str, value: Any) -> bool:
    """Whether ``value`` (a YAML value) is of the option type ``kind``."""
    if kind == "bool":
        return isinstance(value, bool)
    if kind == "int":
        return isinstance(value, int) and not isinstance(value, bool)
    if kind == "number":
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    return isinstance(value, str)


_TRUE = ("true", "yes", "on", "1")
_FALSE = ("false", "no", "off", "0")


def parse_value(option: n.Option, text: str) -> Any:
    """The value of ``text`` (as typed after ``--option NAME=``) for ``option``."""
    value: Any = text
    stripped = text.strip()
    try:
        if option.type == "bool":
            if stripped.lower() not in _TRUE + _FALSE:
                raise ValueError(text)
            value = stripped.lower() in _TRUE
        elif option.type == "int":
            value = int(stripped)
        elif option.type == "number":
            value = float(stripped)
            if value != value or value in (float("inf"), float("-inf")):
                raise ValueError(text)
    except ValueError:
        raise _wrong(option, text) from None
    return checked_value(option, value)


def _wrong(option: n.Option, value: Any) -> OptionValueError:
    allowed = ", ".join(str(c) for c in option.choices) if option.choices is not None \
        else OPTION_TYPES[option.type]
    what = "one of " if option.choices is not None else ""
    return OptionValueError(f"option '{option.name}' is {what}{allowed}, not {value!r}",
                            option.name)


def checked_value(option: n.Option, value: Any) -> Any:
    """``value`` for ``option`` if its type and choices allow it; OptionValueError if not."""
    if option.type == "number" and type_matches("int", value):
        value = float(value)
    if not type_matches(option.type, value) or \
            (option.choices is not None and value not in option.choices):
        raise _wrong(option, value)
    return value


def option_values(post: n.Post, given: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Every option's value: its default, or the one ``given`` (text is parsed).

    Raises OptionValueError naming an unknown option (and the post's options) or a
    value its type or choices do not allow.
    """
    values = {name: option.default for name, option in post.options.items()}
    for name, value in (given or {}).items():
        option = post.options.get(name)
        if option is None:
            known = ", ".join(post.options) or "none"
            raise OptionValueError(f"unknown option '{name}' (the post's options: {known})")
        values[name] = parse_value(option, value) if isinstance(value, str) and \
            option.type != "string" else checked_value(option, value)
    return values


def resolve(value: Any, values: Mapping[str, Any]) -> Any:
    """A setting's value: an :class:`~nodes.OptionRef` becomes the option's value."""
    if isinstance(value, n.OptionRef):
        chosen = values.get(value.option)
        if value.by_value is not None:
            return dict(value.by_value).get(str(chosen))
        return chosen
    return value


def resolve_settings(settings: Mapping[str, Any], values: Mapping[str, Any]) \
        -> dict[str, Any]:
    return {key: resolve(value, values) for key, value in settings.items()}
