"""Where the bundled schemas and machine posts live.

In a source checkout (and an editable install) they are the top-level
``schemas/`` and ``machines/`` folders; a wheel carries copies inside the
package (``postdsl/_data/``).  Everything else asks this module, so the two
layouts never leak into the rest of the code.
"""

from __future__ import annotations

from pathlib import Path

from postdsl.errors import Location, PostError

_PACKAGE = Path(__file__).resolve().parent


def _data_dir(name: str) -> Path:
    bundled = _PACKAGE / "_data" / name
    if bundled.is_dir():
        return bundled
    return _PACKAGE.parent / name


def schema_path(name: str) -> Path:
    return _data_dir("schemas") / name


def machines_dir() -> Path:
    return _data_dir("machines")


def bundled_machines() -> list[str]:
    """Names of the machines shipped with postdsl."""
    return sorted(p.stem for p in machines_dir().glob("*.yaml"))


def resolve_machine(machine: str) -> Path:
    """A machine argument -> its post file: a path to a YAML file, or a bundled name."""
    candidate = Path(machine)
    if candidate.suffix in (".yaml", ".yml") or candidate.exists():
        if not candidate.is_file():
            raise PostError("no such post file", Location(machine))
        return candidate
    bundled = machines_dir() / f"{machine}.yaml"
    if bundled.is_file():
        return bundled
    names = ", ".join(bundled_machines()) or "none"
    raise PostError(f"unknown machine '{machine}' (bundled machines: {names}; "
                    f"or give the path of a .yaml post)")
