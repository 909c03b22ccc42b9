"""The library's public API: what the CLI, the editor and the review tool call.

Nothing outside ``postdsl`` should import the engine's modules directly;
this package is the seam, so the engine can change inside without breaking
the tools on top.  Callers import the package (``from postdsl import api``, then
``api.load_post``); its modules are named for what a caller does, and each imports
only what its task needs, so ``postdsl post`` loads no tracing, drawing or editor code:

- :mod:`~postdsl.api.loading` a post compiled from a machine's name, a file or a buffer;
- :mod:`~postdsl.api.posting` CL commands posted in memory, the lines with their origins;
- :mod:`~postdsl.api.verifying` the lines replayed through the control model, compared
  with the CL;
- :mod:`~postdsl.api.files` a CL file to an NC file (or a verdict), streamed in two passes;
- :mod:`~postdsl.api.drawing` the toolpath, its SVG picture, two toolpaths compared;
- :mod:`~postdsl.api.tracing` which record, table and item wrote a line or a word;
- :mod:`~postdsl.api.previewing` one table's blocks for sample values;
- :mod:`~postdsl.api.editing` the editor's checks and the CL vocabulary;
- :mod:`~postdsl.api.machines` the bundled machines and their sample programs.

Top to bottom (``api-layers`` in pyproject's ``[tool.importlinter]``): drawing; files;
previewing, editing; tracing, verifying; posting, loading, machines.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from postdsl.api.drawing import plot_file, same_motion, toolpath, toolpath_file, toolpath_of_lines
from postdsl.api.editing import (
    check_expression,
    check_source,
    command_doc,
    command_groups,
    commands_setting,
    parameters,
    place_in_post,
    render_number,
)
from postdsl.api.files import NO_CONTROL_MODEL as NO_CONTROL_MODEL
from postdsl.api.files import PassProgress as PassProgress
from postdsl.api.files import post_file as post_file
from postdsl.api.files import verify_file, write_program
from postdsl.api.loading import (
    Options,
    compile_source,
    item_model,
    load_post,
    load_post_text,
    post_model,
    post_options,
)
from postdsl.api.machines import arguments_swapped, corpus_programs, example_program
from postdsl.api.machines import machines_root as machines_root
from postdsl.api.posting import (
    iter_post,
    post_commands,
    post_text,
    posting_time,
    without_block_number,
)
from postdsl.api.previewing import preview_command, unknown_command_message
from postdsl.api.tracing import explain_line, explain_text, trace_line, word_meaning, word_writers

# the inner steps of verifying that tests and docs/explanation/trust.md reach as api.X
from postdsl.api.verifying import _compare as _compare
from postdsl.api.verifying import _LineNotes as _LineNotes
from postdsl.api.verifying import _nc_input as _nc_input
from postdsl.api.verifying import _post_verified as _post_verified
from postdsl.api.verifying import control_events, post_verified, verify_commands
from postdsl.cl.model import CLCommand, ParamInfo
from postdsl.cl.readers import read_cl, read_cl_text
from postdsl.compile.compiler import CompiledPost
from postdsl.compile.runtime import NCLine
from postdsl.errors import CLError, Location, PostError, VerifyError
from postdsl.lang.formats import FormatSpecError
from postdsl.lang.loader import PostSource
from postdsl.lang.post import Post
from postdsl.lang.post.nodes import (
    Block,
    Command,
    CustomCycle,
    Expr,
    ExprItem,
    Item,
    Option,
    ParamItem,
    PlainText,
    Structure,
    Table,
    TextItem,
    Use,
)
from postdsl.lang.post.options import resolve as resolve_option
from postdsl.run.writer import write_atomic

if TYPE_CHECKING:
    from postdsl.check.toolpath import VIEW_AXES, Segment, Toolpath, projector
    from postdsl.check.verify import Verdict
    from postdsl.newmachine import NewMachine, new_machine
    from postdsl.results import CheckResult, ExpressionCheck, PostProblem, PreviewResult
    from postdsl.run.trace import TracedLine, WordMeaning, WordWriter, looks_like_word

#: names of the API that live in modules posting does not need (the control models, the
#: toolpath and its pictures, tracing, verifying, new machines, what the editor's previews
#: and checks return): each is imported when first asked for (:func:`__getattr__`), so
#: ``postdsl post`` does not load them
_LAZY = {
    "PreviewResult": "postdsl.results", "PostProblem": "postdsl.results",
    "CheckResult": "postdsl.results", "ExpressionCheck": "postdsl.results",
    "NewMachine": "postdsl.newmachine", "new_machine": "postdsl.newmachine",
    "Segment": "postdsl.check.toolpath", "Toolpath": "postdsl.check.toolpath",
    "VIEW_AXES": "postdsl.check.toolpath", "projector": "postdsl.check.toolpath",
    "TracedLine": "postdsl.run.trace", "WordWriter": "postdsl.run.trace",
    "WordMeaning": "postdsl.run.trace",
    "looks_like_word": "postdsl.run.trace", "Verdict": "postdsl.check.verify",
    "control_model": "postdsl.check.controls",
}


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


__all__ = [
    "VIEW_AXES",
    "Block",
    "CLCommand",
    "CLError",
    "CheckResult",
    "Command",
    "CompiledPost",
    "CustomCycle",
    "Expr",
    "ExprItem",
    "ExpressionCheck",
    "FormatSpecError",
    "Item",
    "Location",
    "NCLine",
    "NewMachine",
    "Option",
    "Options",
    "ParamInfo",
    "ParamItem",
    "PlainText",
    "Post",
    "PostError",
    "PostProblem",
    "PostSource",
    "PreviewResult",
    "Segment",
    "Structure",
    "Table",
    "TextItem",
    "Toolpath",
    "TracedLine",
    "Use",
    "Verdict",
    "VerifyError",
    "WordMeaning",
    "WordWriter",
    "arguments_swapped",
    "check_expression",
    "check_source",
    "command_doc",
    "command_groups",
    "commands_setting",
    "compile_source",
    "control_events",
    "corpus_programs",
    "example_program",
    "explain_line",
    "explain_text",
    "item_model",
    "iter_post",
    "load_post",
    "load_post_text",
    "looks_like_word",
    "new_machine",
    "parameters",
    "place_in_post",
    "plot_file",
    "post_commands",
    "post_model",
    "post_options",
    "post_text",
    "post_verified",
    "posting_time",
    "preview_command",
    "projector",
    "read_cl",
    "read_cl_text",
    "render_number",
    "resolve_option",
    "same_motion",
    "toolpath",
    "toolpath_file",
    "toolpath_of_lines",
    "trace_line",
    "unknown_command_message",
    "verify_commands",
    "verify_file",
    "without_block_number",
    "word_meaning",
    "word_writers",
    "write_atomic",
    "write_program",
]
