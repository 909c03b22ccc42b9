"""The CL programs a review posts: corpus.yaml's lists, or every CL file of some folders.

corpus.yaml comes with a pull request and the review runs in CI with whatever that
machine can read, so every path is refused unless it names a file inside the
repository (no absolute path, no ``..``, no symbolic link out of it).
"""

from __future__ import annotations

import contextlib
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ruamel.yaml import YAML
from ruamel.yaml.error import YAMLError

from postdsl.errors import Location
from postdsl.review.gitrepo import repo_root
from postdsl.review.results import ReviewError

#: files in a --corpus folder that are documentation or posts, not CL programs
_NOT_CL = frozenset({".md", ".rst", ".yaml", ".yml"})


@dataclass(frozen=True)
class Program:
    """A CL program of the corpus: how it is shown, and where it is read from."""

    name: str
    path: Path


def _display(path: Path, root: Path) -> str:
    try:
        return path.resolve().relative_to(root.resolve()).as_posix()
    except ValueError:
        return str(path)


def load_corpus_file(corpus_file: Path, root: Path) -> dict[str, list[Program]]:
    """corpus.yaml: machine name -> its CL programs (paths relative to the file)."""
    try:
        text = corpus_file.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ReviewError(f"cannot read the corpus: {exc}", Location(str(corpus_file))) \
            from None
    try:
        data = YAML(typ="rt").load(text)
    except YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = Location(str(corpus_file), mark.line + 1, mark.column + 1) if mark else \
            Location(str(corpus_file))
        raise ReviewError(f"not valid YAML: {getattr(exc, 'problem', None) or exc}",
                          where) from None
    if data is None:
        return {}
    if not isinstance(data, Mapping):
        raise ReviewError("the corpus must map machine names to lists of CL files",
                          Location(str(corpus_file), 1))
    corpus: dict[str, list[Program]] = {}
    for machine, paths in data.items():
        line = data.lc.key(machine)[0] + 1 if hasattr(data, "lc") else None
        if not isinstance(machine, str) or not _MACHINE_NAME.fullmatch(machine):
            raise ReviewError("a corpus key must be a machine's name (letters, digits, '.', "
                              "'_', '-')", Location(str(corpus_file), line))
        if not isinstance(paths, list) or not all(isinstance(p, str) for p in paths):
            raise ReviewError(f"'{machine}': expected a list of CL file paths",
                              Location(str(corpus_file), line))
        programs = []
        for index, given in enumerate(paths):
            where = Location(str(corpus_file), _item_line(paths, index, line))
            path = _inside(corpus_file.parent, given, root, where)
            programs.append(Program(_display(path, root), path))
        corpus[machine] = programs
    return corpus


#: what a corpus key may be: the stem of a file in machines/
_MACHINE_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]*")


def _item_line(items: Any, index: int, fallback: int | None) -> int | None:
    try:
        return int(items.lc.item(index)[0]) + 1
    except (AttributeError, KeyError, TypeError):
        return fallback


def _inside(folder: Path, given: str, root: Path, where: Location) -> Path:
    """A corpus path, refused unless it names a file inside the repository.

    corpus.yaml comes with a pull request, and the review runs in CI with whatever
    that machine can read: an absolute path, ``..`` or a symbolic link out of the
    repository would post (and quote) files that are none of the pull request's.
    """
    if not given.isprintable() or not given.strip():
        raise ReviewError("a corpus path must be printable text", where)
    relative = Path(given)
    if relative.is_absolute() or ".." in relative.parts:
        raise ReviewError("corpus paths are relative to corpus.yaml and stay inside the "
                          "repository (no absolute paths, no '..')", where)
    path = folder / relative
    try:
        path.resolve().relative_to(root.resolve())
    except ValueError:
        raise ReviewError("the corpus path is a symbolic link (or lies in a linked folder) "
                          "leading outside the repository", where) from None
    return path


def corpus_for_machine(machine: str | Path, root: Path | None = None) -> list[Program]:
    """The programs corpus.yaml lists for ``machine`` (a name or a post path), for editors.

    corpus.yaml is looked for in ``root``, else in the folders above the post
    file, else at the top of the current git repository; no corpus found
    means no programs (an installed postdsl has none), not an error.
    """
    candidates: list[Path] = []
    if root is not None:
        candidates.append(root)
    else:
        given = Path(machine)
        if given.suffix in (".yaml", ".yml") and given.exists():
            candidates += given.resolve().parents
        with contextlib.suppress(ReviewError):  # not in a repository: no corpus there
            candidates.append(repo_root(Path.cwd()))
    for folder in candidates:
        corpus_file = folder / "corpus.yaml"
        if corpus_file.is_file():
            return load_corpus_file(corpus_file, folder).get(Path(machine).stem, [])
    return []


def corpus_from_paths(paths: Iterable[str | Path], root: Path) -> list[Program]:
    """Every CL file in the given folders (recursively; hidden, docs and YAML skipped)."""
    programs: list[Program] = []
    for given in paths:
        path = Path(given)
        if path.is_file():
            files = [path]
        elif path.is_dir():
            files = sorted(
                p for p in path.rglob("*")
                if p.is_file() and p.suffix.lower() not in _NOT_CL
                and not any(part.startswith(".") for part in p.relative_to(path).parts))
            for file in files:
                try:
                    file.resolve().relative_to(path.resolve())
                except ValueError:
                    raise ReviewError(f"a symbolic link leading outside {given}: the review "
                                      f"reads only the folder's own files",
                                      Location(str(file))) from None
        else:
            raise ReviewError("no such CL file or folder", Location(str(given)))
        programs += [Program(_display(p, root), p) for p in files]
    return programs

