"""postdsl as a FreeCAD post: the script FreeCAD loads, and what it runs.

FreeCAD (0.20 to 1.0) finds a post as a module ``NAME_post.py`` in its post search
path (the user's macro folder first) and calls ``export(objectslist, filename,
argstring)`` with the Job's objects: the fixture, each tool controller before the
operations using it, the operations.  FreeCAD 1.1 and later look for a class named
``NAME.title()`` in that module and, when there is none, wrap the module's ``export``
(its ``WrapperPost``), calling it with the file name ``-`` and writing the text it
returns themselves (no file for None).  So one ``export`` serves every version: it
writes the file itself unless the name is ``-``, and returns the text.

**Why a script and a module.**  FreeCAD runs its own Python, which does not see the
environment postdsl is installed in.  ``postdsl freecad install`` writes a small script
(:func:`script_text`) that records that environment's site directories and Python
version and imports this module from there; everything else lives here, tested with the
rest of postdsl.  A FreeCAD whose Python is another minor version cannot load the
compiled dependencies: the script says so instead of failing at an import.

**What is posted.**  The objects become a FreeCAD dump (``(Path: label)``, ``Command
NAME [ X:… ]``), the form :mod:`postdsl.cl.freecad` reads, with every number written in
full (``repr`` of the double: the dump post's five significant digits would round a
coordinate and the feed), so the CL is the Job's own values: feeds in mm/s are read
as FreeCAD keeps them and multiplied by 60 exactly once, by the reader.  The program is
posted as ``postdsl post`` posts that dump (:func:`postdsl.api.write_program`: verified,
written atomically), so the two give the same NC.  An inactive operation is left out
and an operation's coolant mode becomes ``M8``/``M7`` at its start and ``M9`` at its
end, as FreeCAD's own posts read them.

**Refusals.**  Any problem -- the arguments, the post, a CL value the post cannot write,
a program that does not do what the CL says -- writes no file and returns None, and the
located message goes to FreeCAD's report view (``FreeCAD.Console.PrintError``) with the
dump line translated to the Job object and the command it came from.  Nothing raises
into FreeCAD: a traceback in the report view tells a user nothing they can act on.
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import shlex
import sys
import sysconfig
import tempfile
import xml.etree.ElementTree as ElementTree
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from postdsl import api
from postdsl.errors import PostdslError, PostError

#: the module name FreeCAD lists the post under ("postdsl" in its post list)
SCRIPT_NAME = "postdsl_post.py"

#: what FreeCAD shows when the post is picked in its list
TOOLTIP = ("postdsl: a declarative post, verified.  Arguments: --machine NAME (a bundled "
           "machine or a post's YAML path) and --option NAME=VALUE (repeatable).")

TOOLTIP_ARGS = ("--machine NAME      the machine (postdsl machines) or a post's YAML path\n"
                "--option NAME=VALUE one of the post's options (repeatable)\n")


class JobRefused(PostdslError):
    """The Job cannot be posted: the message names its object and command."""


class ArgumentError(PostdslError):
    """The post's argument string (the Job's PostProcessorArgs) is not one postdsl reads."""


@dataclass(frozen=True)
class Arguments:
    """What the argument string picks: the machine and the post's option values."""

    machine: str
    options: dict[str, str] = field(default_factory=dict)


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> Any:  # argparse would exit the FreeCAD process
        raise ArgumentError(f"the post's arguments: {message}")


def parse_arguments(argstring: str) -> Arguments:
    """``--machine NAME --option line_numbers=true`` -> the machine and its options."""
    parser = _Parser(prog="postdsl", add_help=False)
    parser.add_argument("--machine", required=True)
    parser.add_argument("--option", action="append", default=[])
    try:
        words = shlex.split(argstring or "")
    except ValueError as exc:
        raise ArgumentError(f"the post's arguments: {exc} in {argstring!r}") from None
    parsed = parser.parse_args(words)
    options: dict[str, str] = {}
    for option in parsed.option:
        name, sep, value = option.partition("=")
        if not sep or not name.strip():
            raise ArgumentError(f"the post's arguments: --option {option!r} is not NAME=VALUE")
        options[name.strip()] = value.strip()
    return Arguments(parsed.machine, options)


# --- the Job's objects as a dump ----------------------------------------------------


@dataclass
class Dump:
    """The dump's lines, and for each the Job object (and command) it came from."""

    lines: list[str] = field(default_factory=list)
    origins: list[str] = field(default_factory=list)

    def add(self, line: str, origin: str) -> None:
        self.lines.append(line)
        self.origins.append(origin)

    def origin(self, line: int) -> str | None:
        """The object and command of 1-based dump ``line``."""
        return self.origins[line - 1] if 0 < line <= len(self.origins) else None


def _number(value: Any) -> str:
    return repr(float(value))


def command_line(name: str, parameters: dict[str, Any]) -> str:
    """One ``Path.Command`` as a dump record, its numbers in full."""
    if name.startswith("("):
        return f"Command {name} [ ]"
    words = " ".join(f"{letter}:{_number(parameters[letter])}" for letter in sorted(parameters))
    return f"Command {name} [ {words} ]" if words else f"Command {name} [ ]"


def _active(obj: Any) -> bool:
    base = getattr(obj, "Base", None)
    return bool(getattr(obj, "Active", True)) and bool(getattr(base, "Active", True))


def _coolant(obj: Any) -> str:
    mode = getattr(obj, "CoolantMode", None)
    if mode is None:
        mode = getattr(getattr(obj, "Base", None), "CoolantMode", None)
    return str(mode or "None")


_COOLANT_ON = {"Flood": "M8", "Mist": "M7"}


def job_dump(objects: Iterable[Any]) -> Dump:
    """The objects FreeCAD hands a post, as the dump :mod:`postdsl.cl.freecad` reads."""
    dump = Dump()
    for obj in objects:
        _add_object(dump, obj)
    return dump


def _add_object(dump: Dump, obj: Any) -> None:
    label = str(getattr(obj, "Label", getattr(obj, "Name", "?")))
    if not _active(obj):
        return
    group = getattr(obj, "Group", None)
    if group is not None and not hasattr(obj, "Path"):
        dump.add(f"(compound: {label})", f"'{label}'")
        for child in group:
            _add_object(dump, child)
        return
    if not hasattr(obj, "Path"):
        raise ArgumentError(f"the object '{label}' is not a path: select a Job, its operations "
                            f"or compounds of them")
    dump.add(f"(Path: {label})", f"'{label}'")
    coolant = _coolant(obj)
    if coolant in _COOLANT_ON:
        dump.add(f"Command {_COOLANT_ON[coolant]} [ ]", f"'{label}' (coolant {coolant})")
    elif coolant != "None":
        raise ArgumentError(f"'{label}': coolant mode '{coolant}' is not one postdsl reads "
                            f"(Flood, Mist or None)")
    for command in obj.Path.Commands:
        name, parameters = str(command.Name), dict(command.Parameters)
        dump.add(command_line(name, parameters), f"'{label}', command {_shown(name, parameters)}")
    if coolant in _COOLANT_ON:
        dump.add("Command M9 [ ]", f"'{label}' (coolant off)")


def _shown(name: str, parameters: dict[str, Any]) -> str:
    words = " ".join(f"{letter}{float(parameters[letter]):g}" for letter in sorted(parameters))
    return f"{name} {words}".strip()


# --- posting --------------------------------------------------------------------------


def post_objects(objects: Sequence[Any], filename: str, argstring: str) -> str:
    """Post the Job's objects with the machine and options of ``argstring``; the NC text.

    Writes ``filename`` (atomically) unless it is ``-``; raises a PostdslError, the
    dump's lines named by their Job object, and then writes nothing."""
    arguments = parse_arguments(argstring)
    dump = job_dump(objects)
    with tempfile.TemporaryDirectory(prefix="postdsl-freecad-") as folder:
        cl_file = Path(folder) / "job.dump.txt"
        cl_file.write_text("\n".join(dump.lines) + "\n", encoding="utf-8")
        try:
            return api.post_file(arguments.machine, cl_file,
                                 None if filename == "-" else filename,
                                 options=arguments.options)
        except PostdslError as exc:
            text = exc.report() if isinstance(exc, PostError) else str(exc)
            raise JobRefused(_named(text, str(cl_file), dump)) from None


def _named(message: str, cl_file: str, dump: Dump) -> str:
    """``/tmp/…/job.dump.txt:57: …`` -> ``'Pocket', command G1 X10 (dump line 57): …``."""

    def name(match: re.Match[str]) -> str:
        line = int(match.group(1))
        origin = dump.origin(line)
        return f"{origin} (dump line {line})" if origin else f"the Job (dump line {line})"

    named = re.sub(re.escape(cl_file) + r":(\d+)(?::\d+)?", name, message)
    return named.replace(cl_file, "the Job")


def export(objectslist: Sequence[Any], filename: str, argstring: str) -> str | None:
    """FreeCAD's post entry point: the NC text, or None (nothing written) on a refusal,
    the message in the report view."""
    try:
        return post_objects(objectslist, filename, argstring)
    except PostdslError as exc:
        report(f"postdsl: {exc}")
    except OSError as exc:
        report(f"postdsl: {exc}")
    return None


def report(message: str) -> None:
    """Into FreeCAD's report view (its Console), or standard error outside FreeCAD."""
    try:
        console = importlib.import_module("FreeCAD").Console
    except ImportError:
        sys.stderr.write(message + "\n")
        return
    console.PrintError(message.rstrip("\n") + "\n")


# --- installing the script ------------------------------------------------------------


def site_directories() -> list[str]:
    """Where this Python finds postdsl and its dependencies (added, .pth files read, by the
    script): the environment's site-packages and the folder postdsl is imported from."""
    paths = sysconfig.get_paths()
    folders = [paths["purelib"], paths["platlib"],
               str(Path(__file__).resolve().parent.parent)]
    return list(dict.fromkeys(folders))


def script_text(folders: Sequence[str], version: tuple[int, int]) -> str:
    """The post script FreeCAD loads: finds postdsl where it was installed from."""
    return _SCRIPT.format(folders=repr(list(folders)), version=repr(tuple(version)),
                          python=repr(sys.executable), python_plain=sys.executable,
                          tooltip=repr(TOOLTIP),
                          tooltip_args=repr(TOOLTIP_ARGS))


_SCRIPT = '''\
"""postdsl's post for FreeCAD, written by `postdsl freecad install`.

FreeCAD lists it as "postdsl".  Its arguments (the Job's PostProcessorArgs) pick the
machine and the post's options:  --machine NAME --option line_numbers=true
It finds postdsl where it was installed from (the environment of {python_plain}); install
it again after moving that environment.
"""

import site
import sys

TOOLTIP = {tooltip}
TOOLTIP_ARGS = {tooltip_args}
UNITS = "G21"

_FOLDERS = {folders}
_PYTHON = {version}


def _report(message):
    try:
        import FreeCAD
        FreeCAD.Console.PrintError(message + "\\n")
    except ImportError:
        sys.stderr.write(message + "\\n")


def export(objectslist, filename, argstring):
    if tuple(sys.version_info[:2]) != _PYTHON:
        _report("postdsl: FreeCAD runs Python %d.%d, postdsl was installed for %d.%d "
                "(%s): install postdsl with a Python %d.%d and run `postdsl freecad "
                "install` again" % (sys.version_info[0], sys.version_info[1], _PYTHON[0],
                                    _PYTHON[1], {python}, sys.version_info[0],
                                    sys.version_info[1]))
        return None
    for folder in _FOLDERS:
        if folder not in sys.path:
            site.addsitedir(folder)
    try:
        from postdsl import freecad_post
    except ImportError as exc:
        _report("postdsl: cannot import postdsl from %s: %s (run `postdsl freecad install` "
                "again)" % (_FOLDERS, exc))
        return None
    return freecad_post.export(objectslist, filename, argstring)
'''


def default_folder(home: Path | None = None, environ: dict[str, str] | None = None) -> Path:
    """FreeCAD's user macro folder, the first place it looks for a post.

    The macro path set in FreeCAD's preferences (``user.cfg``) when there is one; else
    ``~/.FreeCAD/Macro`` where that older folder exists (FreeCAD keeps using it), else
    ``$XDG_DATA_HOME/FreeCAD/Macro`` (``~/.local/share/FreeCAD/Macro``: what FreeCAD 0.20
    on Linux uses).  ``--freecad-dir`` names another."""
    home = home or Path.home()
    env = os.environ if environ is None else environ
    config = Path(env.get("XDG_CONFIG_HOME") or home / ".config")
    for cfg in (config / "FreeCAD" / "user.cfg", home / ".FreeCAD" / "user.cfg"):
        chosen = _macro_path(cfg)
        if chosen is not None:
            return chosen
    if (home / ".FreeCAD").is_dir():
        return home / ".FreeCAD" / "Macro"
    data = Path(env.get("XDG_DATA_HOME") or home / ".local" / "share")
    return data / "FreeCAD" / "Macro"


def _macro_path(cfg: Path) -> Path | None:
    """The MacroPath FreeCAD's preferences set, if the file says one."""
    try:
        root = ElementTree.parse(cfg).getroot()
    except (OSError, ElementTree.ParseError):
        return None
    for node in root.iter("FCText"):
        if node.get("Name") == "MacroPath" and node.text and node.text.strip():
            return Path(node.text.strip())
    return None


def install(folder: Path | None = None) -> Path:
    """Write the post script into ``folder`` (FreeCAD's macro folder by default); its path."""
    target_folder = folder or default_folder()
    target_folder.mkdir(parents=True, exist_ok=True)
    target = target_folder / SCRIPT_NAME
    api.write_atomic(target, script_text(site_directories(), sys.version_info[:2]))
    return target
