"""The ``postdsl`` command line.

Exit status: 0 ok, 1 invalid post, 2 bad CL input (or bad usage), 3 a bug in
postdsl, 4 the NC program does not do what the CL says (``verify``, and ``post``,
which verifies what it writes unless told ``--no-verify``).  Every
message goes to stderr as ``file:line:column: message``; a traceback is a
bug in postdsl, never the user's fault.
"""

from __future__ import annotations

import os
import re
import sys
from collections.abc import Callable, Mapping, Sequence
from functools import wraps
from pathlib import Path
from typing import Any, NoReturn, TypeVar

import click

from postdsl import api
from postdsl.errors import PostdslError, PostError, VerifyError, printable
from postdsl.progress import terminal_progress

F = TypeVar("F", bound=Callable[..., Any])

FORMATS = ("native", "apt", "freecad", "gcode")
FEED_UNITS = ("mm/min", "mm/s")


def reports_errors(func: F) -> F:
    """Turn postdsl errors into located messages and exit codes."""

    @wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except PostError as exc:
            click.echo(exc.report(), err=True)
            sys.exit(exc.exit_code)
        except PostdslError as exc:
            click.echo(str(exc), err=True)
            sys.exit(exc.exit_code)
        except (KeyboardInterrupt, SystemExit, click.exceptions.ClickException,
                click.exceptions.Exit, click.exceptions.Abort):
            raise
        except Exception as exc:  # a bug in postdsl, not the user's input
            _internal_error(exc)

    return wrapper  # type: ignore[return-value]  # the wrapper takes and returns what func does


def _internal_error(exc: Exception) -> NoReturn:
    """A bug in postdsl: one line and exit 3 (the traceback with POSTDSL_DEBUG=1)."""
    if os.environ.get("POSTDSL_DEBUG"):
        raise exc
    click.echo(f"postdsl: internal error: {type(exc).__name__}: {exc}\n"
               f"(a bug in postdsl; run with POSTDSL_DEBUG=1 for the traceback)", err=True)
    sys.exit(3)


def with_options(func: F) -> F:
    """``--option NAME=VALUE`` (repeatable): set one of the post's options for this run."""
    return click.option(
        "--option", "options", multiple=True, metavar="NAME=VALUE",
        help="Set an option the post declares (repeatable); the post checks the value "
             "against the option's type and choices.")(func)


def option_values(options: tuple[str, ...]) -> dict[str, str]:
    """``("line_numbers=false", …)`` -> ``{"line_numbers": "false"}``; the post types them."""
    values: dict[str, str] = {}
    for option in options:
        name, sep, value = option.partition("=")
        if not sep or not name.strip():
            raise click.BadParameter(f"'{option}' is not NAME=VALUE", param_hint="--option")
        values[name.strip()] = value.strip()
    return values


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="postdsl")
def main() -> None:
    """postdsl: declarative post-processor for CNC milling.

    MACHINE is a bundled machine's name (see `postdsl machines`) or the path
    of a YAML post.
    """


@main.command()
@click.argument("machine")
@click.argument("clfile", type=click.Path(dir_okay=False))
@click.option("-o", "--output", type=click.Path(dir_okay=False),
              help="Write the NC program here (atomically) instead of stdout.")
@click.option("-f", "--format", "fmt", type=click.Choice(FORMATS),
              help="CL input format; detected from the content when omitted.")
@click.option("--feed-units", type=click.Choice(FEED_UNITS),
              help="What F means in FreeCAD G-code whose text does not say (a FreeCAD "
                   "post's output is mm/min, FreeCAD's internal path mm/s).")
@click.option("--verify/--no-verify", "verify", default=True,
              help="Replay every line through the control model as it is written (the "
                   "default): write nothing and exit 4 if the program does not do what the "
                   "CL says.  --no-verify posts without it, and says so.")
@with_options
@reports_errors
def post(machine: str, clfile: str, output: str | None, fmt: str | None,
         feed_units: str | None, verify: bool, options: tuple[str, ...]) -> None:
    """Post CLFILE for MACHINE (CLFILE - reads standard input), verified.

    The file is read once for what the header needs, and the program posted from what
    that pass kept, written as it is posted, so its length does not matter.  Each line
    is replayed through the model of the machine's control as it is written and
    compared with the CL (as `postdsl verify`): when the program does not do what the
    CL says, nothing is written and the exit status is 4, with the CL line and the NC
    line.  Nothing is written when any error stops it.  A post whose control has no
    model is posted unverified, and says so.  On a terminal a large file shows a
    progress bar.
    """
    _not_swapped("post", machine, clfile)
    if not verify:
        click.echo(f"{clfile}: posted without verifying it (--no-verify): nothing checks that "
                   f"the program does what the CL says", err=True)
    progress, finish = terminal_progress()
    sys.stdout.flush()
    try:
        api.write_program(machine, clfile, output, fmt, feed_units, verify=verify,
                          progress=progress, stdout=sys.stdout.buffer,
                          options=option_values(options),
                          notice=lambda text: click.echo(f"{machine}: {text}", err=True))
    finally:
        finish()


@main.command("verify")
@click.argument("machine")
@click.argument("clfile", type=click.Path(dir_okay=False))
@click.option("-f", "--format", "fmt", type=click.Choice(FORMATS),
              help="CL input format; detected from the content when omitted.")
@click.option("--feed-units", type=click.Choice(FEED_UNITS),
              help="What F means in FreeCAD G-code whose text does not say.")
@with_options
@reports_errors
def verify_command(machine: str, clfile: str, fmt: str | None,
                   feed_units: str | None, options: tuple[str, ...]) -> None:
    """Check that MACHINE's program for CLFILE does what the CL says.

    The program is posted and replayed through the model of the machine's
    control (machine/control); every cut is compared with the CL within
    machine/resolution (a control moving in motor steps: one step of each
    axis, as the program states them).  Exit 4 at the first divergence, named by its CL line
    and NC line.
    """
    _not_swapped("verify", machine, clfile)
    progress, finish = terminal_progress()
    try:
        verdict = api.verify_file(machine, clfile, fmt, feed_units, option_values(options),
                                  progress=progress)
    finally:
        finish()
    click.echo(f"{clfile}: the NC program does what the CL says ({verdict.cuts} cuts, "
               f"{verdict.holes} of them holes, {verdict.rapids} rapid moves checked)", err=True)


@main.command("plot")
@click.argument("machine")
@click.argument("clfile", type=click.Path(dir_okay=False))
@click.option("-o", "--output", type=click.Path(dir_okay=False), required=True,
              help="The SVG file to write (atomically).")
@click.option("--view", "views", type=click.Choice(("xy", "xz", "yz", "iso", "all")),
              multiple=True, help="A view to draw (repeatable); default: xy, xz and yz "
              "side by side.")
@click.option("-f", "--format", "fmt", type=click.Choice(FORMATS),
              help="CL input format; detected from the content when omitted.")
@click.option("--feed-units", type=click.Choice(FEED_UNITS),
              help="What F means in FreeCAD G-code whose text does not say.")
@with_options
@reports_errors
def plot_command(machine: str, clfile: str, output: str, views: tuple[str, ...],
                 fmt: str | None, feed_units: str | None, options: tuple[str, ...]) -> None:
    """Draw MACHINE's toolpath for CLFILE as an SVG picture.

    The program is posted and replayed through the model of the machine's
    control (as `postdsl verify` does), so the picture shows what the NC
    text makes the machine do.  Exit 4 when the control model refuses a
    line (the picture then ends there and says so), or when the program does
    not do what the CL says (verified as `postdsl post` verifies: the picture
    shows what the NC program does, the message where it departs from the CL).
    """
    chosen: list[str] = []
    for view in views or ("all",):
        for name in (("xy", "xz", "yz") if view == "all" else (view,)):
            if name not in chosen:
                chosen.append(name)
    path = api.plot_file(machine, clfile, output, chosen, fmt, feed_units,
                         option_values(options))
    if path.stopped is not None:
        click.echo(f"{clfile}: the control model stops at {path.stopped}; {output} shows the "
                   f"path up to there", err=True)
        sys.exit(4)
    holes = sum(s.kind == "hole" for s in path.segments)
    axes = sum(s.kind == "axis" for s in path.segments)  # a direction, not a move
    tilted = f", the tool axis of {axes} tilted planes" if axes else ""
    click.echo(f"{output}: {len(path.segments) - axes} moves drawn ({holes} holes{tilted})",
               err=True)
    try:
        api.verify_file(machine, clfile, fmt, feed_units, option_values(options))
    except VerifyError as exc:
        click.echo(f"{exc}\n{output} shows what the NC program does, not what the CL says",
                   err=True)
        sys.exit(exc.exit_code)


@main.command("new")
@click.argument("name")
@click.option("--from", "source", required=True, metavar="POST",
              help="The library post to start from (see `postdsl machines`) or a post file.")
@click.option("--root", type=click.Path(file_okay=False, exists=True), default=".",
              show_default=True, help="The project folder (machines/, corpus.yaml, tests/).")
@click.option("--extends", "extends", is_flag=True,
              help="Write a machine file that extends the post (its name and extends:) "
                   "instead of a copy of it.")
@click.option("--no-snapshots", is_flag=True,
              help="Only write the machine file and list it in corpus.yaml.")
@reports_errors
def new_command(name: str, source: str, root: str, extends: bool, no_snapshots: bool) -> None:
    """Start machine NAME from a library post: machines/NAME.yaml (a copy, or with
    --extends a file built on the post), its corpus.yaml entry, and its snapshots
    (posted and verified by the project's snapshot suite)."""
    from pathlib import Path

    made = api.new_machine(name, source, Path(root), extends=extends)
    click.echo(f"{made.path}: {'extends' if made.extends else 'started from'} {made.source}",
               err=True)
    click.echo(f"corpus.yaml: {name} posts {len(made.programs)} CL program"
               f"{'s' if len(made.programs) != 1 else ''}", err=True)
    if no_snapshots:
        return
    status = write_snapshots(name, made.programs, Path(root))
    if status is None:
        click.echo("no tests/test_snapshots.py here: no snapshots written", err=True)
        return
    if status != 0:
        click.echo(f"the snapshot suite failed for {name} (exit {status}): see above", err=True)
        sys.exit(4)
    click.echo(f"tests/__snapshots__/test_snapshots: {name}'s snapshots written and verified; "
               f"edit {made.path}, then review with pytest tests/test_snapshots.py", err=True)


def write_snapshots(machine: str, programs: Sequence[str], root: Path) -> int | None:
    """Run the project's snapshot suite for ``machine``: write its NC snapshots and verify
    each (``postdsl new``).  The pytest exit status, or None without the suite in ``root``.

    The suite, not this function, writes the files: a snapshot is whatever the suite
    compares, byte for byte, so it is made by the same code that will check it.  It is
    here, in the command line, not in the library (:mod:`postdsl.api`,
    :mod:`postdsl.newmachine`): the library does not run the project's test suite.
    """
    import subprocess

    suite = root / "tests" / "test_snapshots.py"
    if not suite.is_file():
        return None
    ids = [f"{machine}-{Path(program).name.split('.')[0]}" for program in programs]
    nodes = [f"tests/test_snapshots.py::{test}[{case}]" for case in ids
             for test in ("test_nc_output", "test_nc_output_verifies")]
    command = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
               "--snapshot-update", *nodes]
    return subprocess.run(command, cwd=root, check=False).returncode


@main.command("check")
@click.argument("machines", nargs=-1, required=True)
@reports_errors
def check_command(machines: tuple[str, ...]) -> None:
    """Validate posts; list every problem as file:line:column: message."""
    failed: list[PostError] = []
    for machine in machines:
        try:
            api.load_post(machine)
        except PostError as exc:
            failed.append(exc)
            continue
        click.echo(f"{machine}: ok", err=True)
    if failed:
        click.echo("\n".join(exc.report() for exc in failed), err=True)
        sys.exit(1)


def _parse_value(text: str) -> Any:
    lowered = text.lower()
    if lowered in ("true", "false"):
        return lowered == "true"
    if lowered in ("none", "null"):
        return None
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


@main.command()
@click.argument("machine")
@click.argument("command")
@click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
              help="Override a sample value (repeatable).")
@click.option("--conditions", is_flag=True, help="Also list the conditions and their results.")
@with_options
@reports_errors
def preview(machine: str, command: str, settings: tuple[str, ...], conditions: bool,
            options: tuple[str, ...]) -> None:
    """Show COMMAND's blocks for its sample values (as PPU's Preview)."""
    overrides: dict[str, Any] = {}
    for setting in settings:
        name, sep, value = setting.partition("=")
        if not sep or not name.strip():
            raise click.BadParameter(f"'{setting}' is not NAME=VALUE", param_hint="--set")
        overrides[name.strip()] = _parse_value(value.strip())
    post = api.load_post(machine, option_values(options))
    if command not in post.commands and command not in post.custom_cycles:
        # a technologist asks by NC word (G83): answer with the tables that write it
        message = api.unknown_command_message(post, command)
        found = api.looks_like_word(command) and " is written by " in message
        # a cell that writes the word as fixed text answers; else the word's meaning (G83:
        # deep drilling) where the post has that table (CYCLE83, CYCL DEF 203)
        meaning = api.word_meaning(post.source.model, command)
        if meaning is not None:
            click.echo(f"{post.file} does not write '{command}'; on ISO controls "
                       f"{meaning.word} is {meaning.command.replace('_', ' ')} (the CL "
                       f"command {meaning.command}), which this post writes with its "
                       f"{meaning.command} table:", err=True)
            command = meaning.command
        else:
            click.echo(message, err=not found)
            sys.exit(0 if found else 1)
    result = api.preview_command(post, command, overrides)
    for line in result.lines:
        click.echo(line.text)
    if conditions:
        if not result.conditions:
            click.echo(f"  no conditions: no block or item of {command} has an if:", err=True)
        for path, source, fired in result.conditions:
            where = "/".join(str(p) for p in path)
            click.echo(f"  {'yes' if fired else 'no ':3} {source}    [{where}]", err=True)
    if result.error:
        click.echo(f"{post.file}: preview of {command}: {result.error}", err=True)
        sys.exit(2)


@main.command("review")
@click.option("--against", "rev", default="HEAD", show_default=True, metavar="REV",
              help="Compare with the machine files as they are at this git revision.")
@click.option("--machine", "machine_names", multiple=True, metavar="NAME",
              help="Review only this machine (machines/NAME.yaml, or a path); repeatable.")
@click.option("--corpus", "corpora", multiple=True, metavar="DIR",
              help="Post every CL file in DIR with every machine, instead of the programs "
                   "corpus.yaml lists; repeatable.")
@click.option("--format", "fmt", type=click.Choice(("text", "markdown", "json")),
              default="text", show_default=True, help="markdown suits a pull request, json "
              "a script.")
@click.option("-j", "--jobs", type=click.IntRange(min=1), metavar="N",
              help="Processes to post with (default: one per CPU).")
@click.option("-U", "--context", type=click.IntRange(min=0), default=3, show_default=True,
              help="Unchanged lines shown around each change.")
@click.option("--plots", "plots_dir", type=click.Path(file_okay=False), metavar="DIR",
              help="With --format markdown: replay each changed program on both sides and, "
                   "where the toolpath changed, write before/after SVG pictures into DIR and "
                   "link them (relative to where the markdown is saved).")
@click.option("--executor", type=click.Choice(("local", "dask")), default="local",
              show_default=True, help="Where programs are posted: a local process pool, or "
              "a Dask cluster (pip install 'postdsl[dask]').")
@click.option("--scheduler", metavar="ADDRESS",
              help="With --executor dask: the scheduler's address (tcp://HOST:8786).")
@click.option("--diff-lines", type=click.IntRange(min=0), default=400, show_default=True,
              help="Diff lines kept per program (0: all).")
@click.option("--no-cache", is_flag=True,
              help="Post every program, ignoring results kept from earlier reviews.")
def review_command(rev: str, machine_names: tuple[str, ...], corpora: tuple[str, ...],
                   fmt: str, jobs: int | None, context: int, plots_dir: str | None,
                   executor: str, scheduler: str | None, diff_lines: int,
                   no_cache: bool) -> None:
    """Show how the NC output changes between REV's machine files and the working tree.

    Exit status 0: no output changed; 4: text changes only (format only, renumbering
    only: every program moves as before); 1: a program may move differently (motion
    changed, newly refused or posting, no control model to tell, a machine file added
    or removed); 2: errors; 3: a bug in postdsl.
    """
    from postdsl import review
    from postdsl.review.plots import write_plots

    if plots_dir is not None and fmt != "markdown":
        raise click.UsageError("--plots goes with --format markdown (the pictures are linked "
                               "from the markdown)")
    progress, finish = review.terminal_progress()
    try:
        result = review.review(against=rev, machines=machine_names, corpora=corpora,
                               jobs=jobs, context=context, progress=progress,
                               plots=plots_dir is not None, executor=executor,
                               scheduler=scheduler, spool=True, use_cache=not no_cache,
                               diff_limit=diff_lines or None)
        links = write_plots(review.motion_pictures(result), plots_dir) \
            if plots_dir is not None else None
        # written as it is rendered: a whole archive's report is never one string
        review.write_report(result, fmt, lambda text: click.echo(text, nl=False), links)
    except PostdslError as exc:
        # exit 1 means "outputs changed": every error of the review itself is 2, a bad
        # post included (which `check` reports with 1)
        click.echo(exc.report() if isinstance(exc, PostError) else str(exc), err=True)
        sys.exit(2)
    except (KeyboardInterrupt, SystemExit):
        raise
    except Exception as exc:  # a bug in postdsl: never a traceback, never exit 1
        _internal_error(exc)
    finally:
        finish()
    for error in result.errors:
        click.echo("\n".join(printable(line) for line in error.splitlines()), err=True)
    sys.exit(result.exit_status)


@main.command()
@click.argument("machine")
@click.option("--cl", "sample", type=click.Path(dir_okay=False, exists=True),
              help="CL program to preview the post with (default: the machine's showcase, "
                   "the first program corpus.yaml lists; f6 in the editor switches).")
@reports_errors
def edit(machine: str, sample: str | None) -> None:
    """Edit MACHINE's post in the terminal table editor, with a live preview."""
    from postdsl.resources import resolve_machine
    from tui.app import EditorApp  # Textual loads only for the editor

    app = EditorApp(resolve_machine(machine), sample)  # a bad post: its errors, first
    if not (sys.stdin.isatty() and sys.stdout.isatty()):
        # Textual would wait forever for a terminal that is not there (a pipe, CI)
        click.echo("postdsl edit needs a terminal: its standard input and output are not "
                   "one (a pipe or a script?); run it in a terminal, or use postdsl check, "
                   "preview or review in scripts", err=True)
        sys.exit(2)
    app.run()


@main.command()
@click.argument("machine")
@click.argument("clfile", type=click.Path(dir_okay=False))
@click.option("--line", "number", type=click.IntRange(min=1), required=True, metavar="N",
              help="The NC line to explain (1-based, as an editor numbers it).")
@click.option("-f", "--format", "fmt", type=click.Choice(FORMATS),
              help="CL input format; detected from the content when omitted.")
@with_options
@reports_errors
def explain(machine: str, clfile: str, number: int, fmt: str | None,
            options: tuple[str, ...]) -> None:
    """Where NC line N of CLFILE posted for MACHINE comes from: the CL record, the table,
    block and item of each word, the conditions that fired, the registers after it."""
    _not_swapped("explain", machine, clfile)
    for text in api.explain_line(machine, clfile, number, fmt, option_values(options)):
        click.echo(text)


def _not_swapped(command: str, machine: str, clfile: str) -> None:
    if api.arguments_swapped(machine, clfile):
        raise click.UsageError(f"the arguments look swapped: '{machine}' is a CL file and "
                               f"'{clfile}' a machine; the machine comes first: "
                               f"postdsl {command} {clfile} {machine}")


@main.group("freecad")
def freecad_group() -> None:
    """postdsl as a post FreeCAD calls (its Post Process command)."""


@freecad_group.command("install")
@click.option("--freecad-dir", "folder", type=click.Path(file_okay=False),
              help="The folder FreeCAD looks for posts in (default: FreeCAD's user macro "
                   "folder, ~/.local/share/FreeCAD/Macro).")
@reports_errors
def freecad_install(folder: str | None) -> None:
    """Write the post script postdsl_post.py into FreeCAD's post folder.

    FreeCAD then lists "postdsl" among its posts; the Job's post arguments pick the
    machine and options (--machine NAME --option line_numbers=true).  The script
    imports postdsl from this installation (its environment and Python version are
    recorded): run it again after moving or upgrading the environment."""
    from postdsl import freecad_post

    try:
        target = freecad_post.install(Path(folder) if folder else None)
    except OSError as exc:
        raise click.ClickException(f"cannot write the FreeCAD post: {exc}") from None
    click.echo(f"{target}: FreeCAD lists it as the post 'postdsl'; give the Job the post "
               f"arguments --machine NAME [--option NAME=VALUE ...]")


@main.command()
@click.option("--names", is_flag=True, help="Names only, one a line (for scripts).")
def machines(names: bool) -> None:
    """List the bundled machines: name, control and what the machine is."""
    from postdsl.resources import bundled_machines, resolve_machine

    if names:
        for name in bundled_machines():
            click.echo(name)
        return
    rows = [(name, *_machine_summary(resolve_machine(name))) for name in bundled_machines()]
    width = max((len(row[0]) for row in rows), default=0)
    control_width = max((len(row[1]) for row in rows), default=0)
    for name, control, description in rows:
        click.echo(f"{name:<{width}}  {control:<{control_width}}  {description}".rstrip())


def _machine_summary(path: Path) -> tuple[str, str]:
    """(controller and its verify model, the first sentence of the file's leading comment):
    enough to choose a machine by, read without compiling the post."""
    from postdsl.lang.loader import read_source

    try:
        source = read_source(path)
    except PostError as exc:
        return "?", f"cannot be read: {exc.message}"
    data = source.data if isinstance(source.data, Mapping) else {}
    machine = api.post_model(data, str(path)).machine  # the typed model: no key reading here
    controller = machine.controller if machine is not None else None
    model = machine.control if machine is not None else None
    control = str(controller or model or "?")
    if controller and model:
        control += f" ({model})"
    comment = []
    for line in source.text.splitlines():
        if not line.startswith("#"):
            break
        text = line.lstrip("#").strip()
        if not text:
            break
        comment.append(text)
    words = " ".join(comment)
    end = re.search(r"\.(\s|$)", words)
    sentence = words[:end.start() + 1] if end else words
    return control, sentence[:100] + ("…" if len(sentence) > 100 else "")


if __name__ == "__main__":  # pragma: no cover
    main()
