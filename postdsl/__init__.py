"""postdsl: a declarative post-processor for CNC milling.

CL reader -> CL commands -> compiled post (engine) -> NC text.  Tools built on
top (CLI, editor, review) use :mod:`postdsl.api` only.
"""

__version__ = "0.1.0"
