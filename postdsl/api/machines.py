"""Finding machines and their sample programs: the bundled folder, a machine's
example and the programs ``corpus.yaml`` lists for it.

Apart from the rest because none of it compiles or posts anything: it reads folders and
the corpus list for the editor's and the CLI's choices.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from postdsl.errors import PostError
from postdsl.lang.loader import parse_yaml
from postdsl.resources import machines_dir


def machines_root() -> Path:
    """The folder that holds ``machines/``, ``examples/`` and ``corpus.yaml``."""
    return machines_dir().parent


def example_program(machine: str | Path) -> Path | None:
    """The CL program bundled for a machine (``examples/<machine>_*``), else the first
    program ``corpus.yaml`` lists for it (a library post has no example of its own), or
    None."""
    folder = machines_dir().parent / "examples"
    name = Path(str(machine)).stem
    candidates = sorted(p for p in folder.glob(f"{name}_*") if p.is_file()) \
        if folder.is_dir() else []
    if candidates:
        return candidates[0]
    listed = [path for path in _listed_programs(name) if path.is_file()]
    return listed[0] if listed else None


def _listed_programs(name: str) -> list[Path]:
    """The programs ``corpus.yaml`` lists for machine ``name`` (none when it cannot be read)."""
    root = machines_root()
    corpus = root / "corpus.yaml"
    if not corpus.is_file():
        return []
    try:
        data = parse_yaml(corpus.read_text(encoding="utf-8"), str(corpus))
    except (PostError, OSError, UnicodeDecodeError):
        return []
    entries = data.get(name) if isinstance(data, Mapping) else None
    if not isinstance(entries, list):
        return []
    return [root / str(entry) for entry in entries if isinstance(entry, str)]


def corpus_programs(machine: str | Path) -> list[Path]:
    """The CL programs ``corpus.yaml`` lists for a machine, the showcase (its first) first;
    the bundled example when the corpus does not name the machine.  Missing files are left
    out: a sample list must only offer what can be opened."""
    listed = _listed_programs(Path(str(machine)).stem)
    example = example_program(machine)
    if not listed and example is not None:
        listed = [example]
    return [path for path in listed if path.is_file()]


def arguments_swapped(machine: str, cl_file: str) -> bool:
    """``postdsl post FILE MACHINE``: the machine argument is a CL file and the CL argument
    names a machine.  Said plainly, rather than as the YAML error reading a CL file as a
    post would give."""
    machine_path = Path(machine)
    if machine_path.suffix.lower() in (".yaml", ".yml") or not machine_path.is_file():
        return False
    from postdsl.resources import bundled_machines

    return cl_file in bundled_machines() or Path(cl_file).suffix.lower() in (".yaml", ".yml")
