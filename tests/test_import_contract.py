"""The import contract of pyproject.toml ([tool.importlinter]) holds, and would catch a break.

The contracts: no import circle; no library module but the CLI imports the editor; the
layers of the "Layout" page (docs/explanation/layout.md), every arrow pointing down.
Each is checked on the real import graph, then on the graph with one forbidden import
added (the circle codegen -> engine that was, the API importing the editor, the loader
importing the compiler), which must break exactly that contract: a contract that cannot
fail protects nothing.
"""

from __future__ import annotations

import re
import tomllib
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import grimp
import pytest
from importlinter import configuration
from importlinter.adapters.building import GraphBuilder
from importlinter.application import use_cases
from importlinter.application.app_config import settings

PYPROJECT = str(Path(__file__).parents[1] / "pyproject.toml")

configuration.configure()


class _WithImports(GraphBuilder):
    """The real graph with some imports added, as if a module had written them."""

    def __init__(self, added: list[tuple[str, str]]) -> None:
        self.added = added

    def build(self, *args: Any, **kwargs: Any) -> grimp.ImportGraph:
        graph = super().build(*args, **kwargs)
        for importer, imported in self.added:
            graph.add_import(importer=importer, imported=imported, line_number=1,
                             line_contents=f"import {imported}  # added by the test")
        return graph


@contextmanager
def _added(*imports: tuple[str, str]) -> Iterator[None]:
    before = settings.GRAPH_BUILDER
    settings.configure(GRAPH_BUILDER=_WithImports(list(imports)))
    try:
        yield
    finally:
        settings.configure(GRAPH_BUILDER=before)


def _kept(*contracts: str) -> bool:
    return use_cases.lint_imports(config_filename=PYPROJECT, limit_to_contracts=contracts,
                                  cache_dir=None, no_logo=True)


def test_the_import_contracts_are_kept() -> None:
    assert _kept("no-circles", "library-not-editor", "layers", "review-layers", "api-layers")


@pytest.mark.parametrize(("importer", "imported", "broken", "kept"), [
    # the circle that was: codegen imported the engine inside a function
    ("postdsl.compile.codegen", "postdsl.run.engine", ["no-circles", "layers"],
     ["library-not-editor"]),
    # a circle inside a package
    ("postdsl.lang.post.nodes", "postdsl.lang.post.checks", ["no-circles"], ["library-not-editor"]),
    ("tui.model", "tui.app", ["no-circles"], ["layers"]),
    ("postdsl.api", "tui.app", ["library-not-editor"], ["no-circles"]),
    ("postdsl.lang.loader", "postdsl.compile.compiler", ["layers"], ["library-not-editor"]),
    ("postdsl.cl.readers", "postdsl.lang.loader", ["layers"], ["library-not-editor"]),
    # review: the per-program function never reaches the executors that run it
    ("postdsl.review.posting", "postdsl.review.executors", ["review-layers"], ["layers"]),
    # the API: posting in memory never reaches verifying (the control models), and two
    # tasks of one layer stay apart
    ("postdsl.api.posting", "postdsl.api.verifying", ["api-layers"], ["layers"]),
    ("postdsl.api.previewing", "postdsl.api.editing", ["api-layers"], ["no-circles"]),
])
def test_a_forbidden_import_breaks_its_contract(importer: str, imported: str,
                                                broken: list[str], kept: list[str]) -> None:
    with _added((importer, imported)):
        for contract in broken:
            assert not _kept(contract), f"{importer} -> {imported} kept {contract}"
        for contract in kept:
            assert _kept(contract), f"{importer} -> {imported} broke {contract}"


def _graph() -> grimp.ImportGraph:
    return grimp.build_graph("postdsl", "tui", cache_dir=None,
                             exclude_type_checking_imports=True)


def test_the_graph_has_imports_inside_functions_and_not_type_only_ones() -> None:
    """What the contract sees: an import in a function body counts (the CLI imports the
    editor only in ``postdsl edit``), one under ``if TYPE_CHECKING:`` does not (the
    palette names the app's type)."""
    graph = _graph()
    assert "tui.app" in graph.find_modules_directly_imported_by("postdsl.cli")
    assert "tui.app" not in graph.find_modules_directly_imported_by("tui.palette")


def _package_circles(graph: grimp.ImportGraph) -> list[tuple[str, str]]:
    return [(module, parent) for module in sorted(graph.modules)
            for parent in graph.find_modules_directly_imported_by(module)
            if module.startswith(parent + ".")
            and graph.chain_exists(importer=parent, imported=module)]


def test_no_module_imports_a_package_that_imports_it_back() -> None:
    """The one circle ``acyclic_siblings`` does not compare: a module and its own package
    (an ``__init__`` importing a module that imports the ``__init__``)."""
    graph = _graph()
    assert _package_circles(graph) == []
    # a module reading its package's __init__, and the __init__ importing it back
    graph.add_import(importer="postdsl.lang.expr.lexer", imported="postdsl.lang.expr")
    graph.add_import(importer="postdsl.lang.expr", imported="postdsl.lang.expr.lexer")
    assert _package_circles(graph) == [("postdsl.lang.expr.lexer", "postdsl.lang.expr")]


def _layers() -> list[str]:
    """The layers contract's layers, top first."""
    with open(PYPROJECT, "rb") as file:
        contracts = tomllib.load(file)["tool"]["importlinter"]["contracts"]
    return next(c["layers"] for c in contracts if c["id"] == "layers")


def test_the_readme_states_the_layers_of_the_contract() -> None:
    """The "Layout" page's table (docs/explanation/layout.md) is the contract's layers, in order."""
    layers = _layers()
    readme = (Path(__file__).parents[1] / "docs" / "explanation" / "layout.md").read_text(
        encoding="utf-8")
    table = readme[readme.index("| layer | modules of `postdsl/` |"):]
    rows = [line for line in table.splitlines()[2:] if line.startswith("|")][:len(layers) + 1]
    stated = [set(re.findall(r"`([a-z_]+)/?`", row.split("|")[2].split(" — ")[0]))
              for row in rows]
    assert stated == [set(layer.split(" : ")) for layer in layers]


def test_the_apis_lazy_modules_are_below_it() -> None:
    """``postdsl.api`` imports some modules by name when first asked (``_LAZY``), which no
    import statement shows the contract: each must still be in the API's layer or below."""
    from postdsl import api

    layers = _layers()
    level = {name: index for index, layer in enumerate(layers) for name in layer.split(" : ")}
    lazy = {module.split(".")[1] for module in api._LAZY.values()}
    assert lazy and all(level[name] >= level["api"] for name in lazy), lazy


def test_only_the_command_line_runs_the_test_suite() -> None:
    """The library, its public API above all, never runs the project's tests: ``postdsl
    new`` writes a new machine's snapshots by running the suite from ``cli.py``."""
    package = Path(__file__).parents[1] / "postdsl"
    runners = sorted(str(path.relative_to(package)) for path in package.rglob("*.py")
                     if re.search(r"""["']pytest["']""", path.read_text(encoding="utf-8")))
    assert runners == ["cli.py"]
