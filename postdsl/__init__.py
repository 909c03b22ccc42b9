"""postdsl: a declarative post-processor for CNC milling.

CL reader -> CL commands -> compiled post (engine) -> NC text.  Tools built on
top (CLI, editor, review) use :mod:`postdsl.api` only.
"""

__version__ = "0.1.0"

# before any module of the package defines a dataclass: their methods' code is kept
from postdsl import classcode as _classcode

_classcode.install()
