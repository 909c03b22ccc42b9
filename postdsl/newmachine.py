"""``postdsl new``: a new machine, started from a library post, inside the checks at once.

A machine file that no corpus entry names is posted by nothing and locked by no
snapshot (``review`` only warns about it).  So a new machine is never only a
file: it is a copy of the library post it starts from, with the CL programs that
post is checked with listed for it in ``corpus.yaml``.  Its snapshots are then
written by the project's snapshot suite (the CLI runs it), so the first commit of a
new machine already locks what it writes.

The copy is the library post's text, comments included (they say what each
table writes and which manual it follows), with the machine's name changed and a
first line saying where it came from.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from postdsl.errors import Location, PostdslError, PostError
from postdsl.loader import parse_yaml

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


def new_machine(name: str, source: str, root: Path) -> NewMachine:
    """Copy the post ``source`` to ``root/machines/NAME.yaml`` and list it in the corpus.

    ``source`` is a machine of ``root/machines`` (a library post) or a path to a
    post.  The new machine is given every CL program of ``corpus.yaml`` the source
    is listed with, refusals included: a program the source refuses, the copy
    refuses too until its tables are changed, and its snapshot says so.
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
    copy, count = _MACHINE_NAME.subn(lambda m: f"{m.group(1)} {name}", text, count=1)
    if count != 1:
        raise PostError("the post has no machine: name: line to rename", Location(
            str(source_path)))
    header = (f"# {name}: started from the library post {source_path.stem} "
              f"(postdsl new {name} --from {source}).\n"
              f"# Fit machine: (travels, spindle, feeds) and the tables to the real machine;\n"
              f"# its CL programs are listed in corpus.yaml, its snapshots in tests/.\n#\n")
    target.write_text(header + copy, encoding="utf-8")
    block = f"{name}:                                # started from {source_path.stem}\n" + \
        "".join(f"  - {program}\n" for program in programs)
    separator = "" if corpus_text.endswith("\n") or not corpus_text else "\n"
    corpus.write_text(corpus_text + separator + block, encoding="utf-8")
    return NewMachine(name, target, source_path, programs)


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
