"""The typed model of a machine post (:mod:`nodes`) and the one walker that builds it
from a post document (:mod:`build`)."""

from postdsl.lang.post.build import build_post
from postdsl.lang.post.nodes import Post

__all__ = ["Post", "build_post"]
