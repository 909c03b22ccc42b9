"""``postdsl new``: a new machine, started from a library post, inside the checks at once.

A machine file that no corpus entry names is posted by nothing and locked by no
snapshot (``review`` only warns about it).  So a new machine is never only a
file: it is a copy of the library post it starts from, with the CL programs that
post is checked with listed for it in ``corpus.yaml``.  Its snapshots are then
written by the project's snapshot suite (the CLI runs it), so the first commit of a
new machine already locks what it writes.

The copy is the library post's text, comments included (they say what each
table writes and which manual it follows), with the machine's name changed and a
first line saying where it came from.  With ``--extends`` the machine file is
instead a few lines, ``extends:`` the library post and the machine's name, with a
comment showing how to replace a table or override one block or item: it posts
exactly what the base posts until it is edited, and follows the base when the
base is fixed.  The base is named by a path relative to the new file (``POST.yaml``, its
sibling), so the project's own copy of the library post is the base, not
the one installed with postdsl.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

from postdsl.errors import Location, PostdslError, PostError
from postdsl.lang.loader import load, parse_yaml

#: a machine name: it becomes a file name, a corpus key and part of snapshot names
NAME = re.compile(r"[a-z][a-z0-9_]{0,39}\Z")

_MACHINE_NAME = re.compile(r"^(machine:[^\n]*\n(?:[ \t]*#[^\n]*\n|[ \t]*\n)*"
                           r"(?:  [^\n]*\n)*?  name:)[^\n]*$", re.MULTILINE)


class NewMachineError(PostdslError):
    """The new machine cannot be made as asked (bad name, no such post, already there)."""

    exit_code = 2


@dataclass(frozen=True)
class NewMachine:
    """What ``new_machine`` made: the machine file and the CL programs listed for it."""

    name: str
    path: Path
    source: Path
    programs: list[str]
    #: True: the machine file extends the source; False: it is a copy of it
    extends: bool = False


def new_machine(name: str, source: str, root: Path, extends: bool = False) -> NewMachine:
    """Start ``root/machines/NAME.yaml`` from the post ``source`` and list it in the corpus.

    ``source`` is a machine of ``root/machines`` (a library post) or a path to a
    post; the new file is a renamed copy of it, or with ``extends`` a file that
    extends it.  The new machine is given every CL program of ``corpus.yaml`` the
    source is listed with, refusals included: a program the source refuses, the new
    machine refuses too until its tables are changed, and its snapshot says so.
    """
    if not NAME.match(name):
        raise NewMachineError(f"'{name}' cannot name a machine: use lower-case letters, "
                              f"digits and _ (starting with a letter, at most 40)")
    machines = root / "machines"
    corpus = root / "corpus.yaml"
    if not machines.is_dir() or not corpus.is_file():
        raise NewMachineError(f"{root} is not a postdsl project: it needs machines/ and "
                              f"corpus.yaml (run postdsl new in the project's folder, or give "
                              f"--root)")
    target = machines / f"{name}.yaml"
    if target.exists():
        raise NewMachineError(f"{target} exists already: choose another name")
    source_path = _source_path(source, machines)
    text = source_path.read_text(encoding="utf-8")
    corpus_text = corpus.read_text(encoding="utf-8")
    entries = parse_yaml(corpus_text, str(corpus))
    if not isinstance(entries, dict):
        raise PostError("corpus.yaml is not a table of machines", Location(str(corpus)))
    if name in entries:
        raise NewMachineError(f"corpus.yaml lists '{name}' already: choose another name, or "
                              f"remove its entry first")
    programs = [str(p) for p in entries.get(source_path.stem) or [] if isinstance(p, str)]
    if not programs:
        raise NewMachineError(f"corpus.yaml lists no CL program for '{source_path.stem}': a "
                              f"machine started from it would be checked by nothing")
    content = _extending(name, source, source_path, target, _option_names(source_path)) \
        if extends else \
        _copy(name, source, source_path, text)
    target.write_text(content, encoding="utf-8")
    how = "extends" if extends else "started from"
    block = f"{name}:                                # {how} {source_path.stem}\n" + \
        "".join(f"  - {program}\n" for program in programs)
    separator = "" if corpus_text.endswith("\n") or not corpus_text else "\n"
    corpus.write_text(corpus_text + separator + block, encoding="utf-8")
    return NewMachine(name, target, source_path, programs, extends)


def _copy(name: str, source: str, source_path: Path, text: str) -> str:
    """The source's text with the machine's name changed, and where it came from."""
    copy, count = _MACHINE_NAME.subn(lambda m: f"{m.group(1)} {name}", text, count=1)
    if count != 1:
        raise PostError("the post has no machine: name: line to rename", Location(
            str(source_path)))
    header = (f"# {name}: started from the library post {source_path.stem} "
              f"(postdsl new {name} --from {source}).\n"
              f"# Fit machine: (travels, spindle, feeds) and the tables to the real machine;\n"
              f"# its CL programs are listed in corpus.yaml, its snapshots in tests/.\n#\n")
    return header + copy


def _option_names(source_path: Path) -> list[str]:
    """The options of the source post, its bases' included (a user sets them when posting);
    read from the checked model, so a broken base is a located error here, not later."""
    return list(load(source_path).model.options)


def _extending(name: str, source: str, source_path: Path, target: Path,
               options: list[str]) -> str:
    """A machine file that extends the source: its name, and how to change the rest."""
    base = Path(os.path.relpath(source_path.resolve(), target.parent.resolve())).as_posix() \
        if source_path.resolve().anchor == target.parent.resolve().anchor \
        else source_path.resolve().as_posix()
    return (
        f"# {name}: built on the library post {source_path.stem} "
        f"(postdsl new {name} --from {source} --extends).\n"
        f"# Everything not written here is {source_path.stem}'s ({base}, read from this\n"
        f"# file's folder) and follows it when it changes.  To fit the real machine:\n"
        f"#  - merge keys into machine: or output: (travel:, spindle:, max_feed: ...);\n"
        f"#  - name a format, variable, option, structure or command: it replaces the\n"
        f"#    base's of that name, e.g.\n"
        f"#      commands:\n"
        f"#        program_end:\n"
        f"#          blocks: [{{items: [\"M30\"]}}]\n"
        f"#  - or override: one block or item, by its path in the base (blocks and items\n"
        f"#    count from 0, as in the YAML), e.g.\n"
        f"#      override:\n"
        f"#        commands/program_end/blocks/0/items/0: \"M30\"\n"
        + (f"#  - its options ({', '.join(options)}) are set when posting\n"
           f"#    (--option NAME=VALUE), or declared again under options: with another default.\n"
           if options else "") +
        f"# (docs/reference/post-language.md, extends:).  Its CL programs are listed in\n"
        f"# corpus.yaml, its snapshots in tests/.\n"
        f"postdsl: 1\n"
        f"extends: {_yaml_string(base)}\n"
        f"\n"
        f"machine:\n"
        f"  name: {name}\n")


def _yaml_string(text: str) -> str:
    """``text`` as a YAML scalar: plain when it reads back as itself, else double-quoted."""
    if re.fullmatch(r"[A-Za-z0-9_./][A-Za-z0-9_./ -]*", text) and not text.endswith(" "):
        return text
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _source_path(source: str, machines: Path) -> Path:
    candidate = Path(source)
    if candidate.suffix in (".yaml", ".yml"):
        if not candidate.is_file():
            raise NewMachineError(f"{source}: no such post file")
        return candidate
    named = machines / f"{source}.yaml"
    if named.is_file():
        return named
    known = ", ".join(sorted(p.stem for p in machines.glob("*.yaml"))) or "none"
    raise NewMachineError(f"no post '{source}' in {machines} (there are: {known})")
