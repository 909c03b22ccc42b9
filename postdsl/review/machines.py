"""The machine files a review compares: each one's two versions, bases included.

A post that ``extends:`` another is read from a path, so its base is found as
``postdsl post`` finds it: the working tree's from its own path, the revision's from
a copy of its chain at the revision (same paths relative to the repository).
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass
from pathlib import Path

from postdsl import api
from postdsl.errors import Location, PostdslError
from postdsl.review.gitrepo import file_at, files_at
from postdsl.review.results import ReviewError


@dataclass(frozen=True)
class MachineSides:
    """A machine file's two versions, as text (None: the file does not exist there).

    A post that ``extends:`` another is read from a path, so its base is found as
    ``postdsl post`` finds it (relative to the post's folder): ``old_path`` is a copy
    of the old side's chain at the revision, ``new_path`` the working-tree file.  The
    bases' texts are part of each side: a base that changed changes every child.
    """

    old_text: str | None
    new_text: str | None
    old_file: str
    new_file: str
    old_path: Path | None = None
    new_path: Path | None = None
    old_bases: tuple[str, ...] = ()
    new_bases: tuple[str, ...] = ()

    @property
    def same(self) -> bool:
        """Both sides are the same post, bases included: nothing to post."""
        return self.old_text == self.new_text and self.old_bases == self.new_bases


    def digest(self, new: bool) -> str:
        """What one side's postings depend on: its text and its bases' (the cache key)."""
        text = self.new_text if new else self.old_text
        bases = self.new_bases if new else self.old_bases
        digest = hashlib.sha256()
        for part in (text or "", *bases):
            digest.update(part.encode("utf-8", "surrogatepass") + b"\0")
        return digest.hexdigest()


def load_side(text: str, file: str, path: Path | None) -> api.CompiledPost:
    """A post's text compiled as read from ``path`` (its ``extends:`` found from there)."""
    from postdsl.lang.loader import PostSource, parse_yaml

    if path is None:
        return api.load_post_text(text, file)
    return api.compile_source(PostSource(file, parse_yaml(text, file), text, path))


def machine_file(root: Path, machine: str, commit: str) -> tuple[str, str]:
    """A --machine argument -> (its display name, its path relative to the repository)."""
    given = Path(machine)
    if given.suffix in (".yaml", ".yml") or os.sep in machine or "/" in machine:
        absolute = given if given.is_absolute() else Path.cwd() / given
        try:
            relative = absolute.resolve().relative_to(root.resolve()).as_posix()
        except ValueError:
            raise ReviewError("the machine file is outside the repository, so git has no "
                              "old version of it", Location(machine)) from None
        return given.stem, relative
    for suffix in (".yaml", ".yml"):
        relative = f"machines/{machine}{suffix}"
        if (root / relative).is_file() or file_at(root, commit, relative) is not None:
            return machine, relative
    raise ReviewError(f"unknown machine '{machine}': no machines/{machine}.yaml in the "
                      f"working tree or at {commit[:12]}")


def all_machines(root: Path, commit: str) -> list[str]:
    names = {p.stem for p in (root / "machines").glob("*.y*ml")}
    names |= {Path(p).stem for p in files_at(root, commit, "machines")
              if p.endswith((".yaml", ".yml"))}
    return sorted(names)


def read_sides(root: Path, commit: str, against: str, relpath: str,
                old_copy: Path | None = None) -> tuple[MachineSides, list[str]]:
    """Both versions of a machine file, and the errors that make them unusable.

    A post that ``extends:`` another is read as ``postdsl post`` reads it: the working
    tree's from its own path, the revision's from a copy of its chain at the revision
    under ``old_copy`` (same paths relative to the repository), so its base is found
    the same way on both sides, from whatever folder the review runs in.
    """
    errors: list[str] = []
    old_bytes = file_at(root, commit, relpath)
    old_text = new_text = None
    if old_bytes is not None:
        try:
            old_text = old_bytes.decode("utf-8")
        except UnicodeDecodeError as exc:
            errors.append(f"{against}:{relpath}: not UTF-8 text ({exc.reason})")
    new_path = root / relpath
    if new_path.exists():
        try:
            new_text = new_path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            errors.append(f"{relpath}: cannot read the post: {exc}")
    if old_bytes is None and not new_path.exists():
        errors.append(f"{relpath}: no such machine file in the working tree or at {against}")
    old_path: Path | None = None
    old_bases: tuple[str, ...] = ()
    if old_text is not None and old_copy is not None:
        old_path, old_bases = _chain_at(root, commit, relpath, old_text, old_copy)
    new_bases = _bases_now(new_path, new_text) if new_text is not None else ()
    sides = MachineSides(old_text, new_text, f"{against}:{relpath}", relpath,
                          old_path, new_path if new_text is not None else None,
                          old_bases, new_bases)
    for text, file, path in ((old_text, sides.old_file, sides.old_path),
                             (new_text, sides.new_file, sides.new_path)):
        if text is None or sides.same:
            continue
        try:
            load_side(text, file, path)
        except api.PostError as exc:
            errors.append(exc.report())
    return sides, errors


def _extends_name(text: str, file: str) -> str | None:
    from postdsl.lang.loader import parse_yaml
    from postdsl.lang.post.extends import extends_of

    try:
        return extends_of(parse_yaml(text, file))
    except PostdslError:
        return None  # the post itself is broken: loading it says where


def _bases_now(path: Path, text: str) -> tuple[str, ...]:
    """The texts of the working-tree post's bases, nearest first."""
    from postdsl.lang.loader import parse_yaml, read_source
    from postdsl.lang.post.extends import ExtendsError, chain_of
    from postdsl.resources import machines_dir

    if _extends_name(text, str(path)) is None:
        return ()
    try:
        chain = chain_of(path, str(path), parse_yaml(text, str(path)), read_source,
                         machines_dir())
    except (ExtendsError, PostdslError):
        return ()  # loading the post reports it, located
    return tuple(source.text for source in chain)


def _chain_at(root: Path, commit: str, relpath: str, text: str, copy: Path
              ) -> tuple[Path, tuple[str, ...]]:
    """Write the post at ``relpath`` and the bases it names by path, as they are at
    ``commit``, under ``copy``; its path there and the bases' texts.  A base named as a
    bundled post (``extends: BASE``) is the installed one, on both sides."""
    from postdsl.lang.post.extends import base_file
    from postdsl.resources import machines_dir

    target = copy / relpath
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(text, encoding="utf-8")
    bases: list[str] = []
    current, current_text, seen = relpath, text, {relpath}
    while (name := _extends_name(current_text, current)) is not None and len(seen) < 32:
        pathlike = Path(name).suffix in (".yaml", ".yml") or "/" in name or "\\" in name
        if not pathlike or Path(name).is_absolute():
            found = base_file(name, copy / current, machines_dir())
            if found is None:
                break
            bases.append(found.read_text(encoding="utf-8", errors="replace"))
            current, current_text = found.as_posix(), bases[-1]
            if not pathlike:
                break  # the installed post's own bases are the installed ones
            continue
        relative = os.path.normpath(os.path.join(os.path.dirname(current), name))
        relative = Path(relative).as_posix()
        data = file_at(root, commit, relative) if not relative.startswith("..") else None
        if data is None or relative in seen:
            break  # loading the copy reports the missing base (or the loop), located
        seen.add(relative)
        current, current_text = relative, data.decode("utf-8", errors="replace")
        (copy / relative).parent.mkdir(parents=True, exist_ok=True)
        (copy / relative).write_text(current_text, encoding="utf-8")
        bases.append(current_text)
    return target, tuple(bases)

