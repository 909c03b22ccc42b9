"""Loading a post: a machine's name, a post file or an editor's buffer made ready to post.

Posting, verifying, drawing and tracing a file all start from a compiled post, so this
module sits at the bottom of the API; it keeps the warm path short (the checked post from
the cache, no YAML parse) because ``postdsl post`` pays for it before its first line.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from postdsl.compile.compiler import CompiledPost, compile_post
from postdsl.lang.loader import PostSource, check, parse_yaml
from postdsl.lang.post import Post, build_post
from postdsl.lang.post.build import build_item
from postdsl.lang.post.nodes import Item, Option
from postdsl.resources import resolve_machine

#: option values by name, as ``--option NAME=VALUE`` gives them (text) or typed values
Options = Mapping[str, Any]


def load_post(machine: str | Path, options: Options | None = None) -> CompiledPost:
    """A bundled machine's name or a post path -> a compiled post, or a PostError.

    ``options`` sets the post's options (the others keep their defaults); an unknown
    name or a value the option's type or choices refuse is a PostError at the option.
    """
    # the checked post from the cache when it is there: no YAML parse, no checks
    from postdsl.compile.postcache import load_checked

    return compile_post(load_checked(resolve_machine(str(machine))), options)


def load_post_text(text: str, file: str = "<post>", options: Options | None = None) \
        -> CompiledPost:
    """Compile a post from YAML text (the editor's unsaved buffer)."""
    return compile_source(PostSource(file, parse_yaml(text, file), text), options)


def compile_source(source: PostSource, options: Options | None = None) -> CompiledPost:
    return compile_post(check(source), options)


def post_model(data: Mapping[str, Any], file: str = "<post>") -> Post:
    """The typed model of a post document that may not be valid (the editor's, mid-edit):
    whatever of it has the right shape."""
    return build_post(data, file, lenient=True)


def item_model(value: Any) -> Item:
    """A YAML item (a string or a mapping, as the clipboard holds one) as a model item."""
    return build_item(value)


def _model(post: Post | Mapping[str, Any]) -> Post:
    return post if isinstance(post, Post) else post_model(post)


def post_options(post: CompiledPost | Post) -> list[Option]:
    """The options a post declares, in file order (name, type, default, choices…)."""
    model = post.source.model if isinstance(post, CompiledPost) else post
    return list(model.options.values())
