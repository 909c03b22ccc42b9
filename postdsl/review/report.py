"""A review as a report: for a terminal, a pull-request comment, or a script.

Every report lists the verdicts first — which programs move differently, which
changed their text only — and the diffs after them.  Names and messages come from
files a pull request brings, so the terminal report escapes them, and the Markdown
report shows each as literal text and quotes no error message (it may quote a CL
record, which may hold anything): only where the error is and what kind it is.
"""

from __future__ import annotations

import contextlib
import json
import re
import sys
from collections.abc import Callable, Iterator, Mapping, Sequence
from typing import Any
from urllib.parse import quote

from postdsl.errors import printable
from postdsl.review.plots import PlotFiles
from postdsl.review.results import (
    ADDED,
    CHANGED,
    ERROR,
    FORMAT_ONLY,
    MOTION,
    NOW_FAILS,
    NOW_POSTS,
    REMOVED,
    RENUMBERED,
    SAME,
    UNCHANGED,
    UNPOSTABLE,
    VERDICTS,
    ProgramDiff,
    Progress,
    ReviewResult,
)

FORMATS = ("text", "markdown", "json")


def _counts(program: ProgramDiff) -> str:
    return f"+{program.added} -{program.removed}"


def headline(program: ProgramDiff) -> str:
    """One line saying what happened to a program: "+3 -3 lines", "renumbering only (…)"."""
    status = program.status
    if status == RENUMBERED:
        text = f"renumbering only ({program.renumbered} block numbers"
        if program.renumber_example:
            old, new = program.renumber_example
            text += f"; first: '{old}' -> '{new}'"
        return text + ")"
    if status == UNPOSTABLE:
        if program.old_error == program.new_error:
            return f"cannot be posted by either version: {program.new_error}"
        return (f"cannot be posted by either version: before: {program.old_error}; "
                f"now: {program.new_error}")
    if status == ERROR:
        return f"error: {program.old_error}"
    if status == NOW_FAILS:
        return f"cannot be posted any more: {program.new_error}"
    if status == NOW_POSTS:
        return f"can be posted now ({program.added} lines; before: {program.old_error})"
    if status == ADDED:
        if program.new_error:
            return f"new machine file, which cannot post it: {program.new_error}"
        return f"new machine file: {program.added} lines added"
    if status == REMOVED:
        if program.old_error:
            return f"machine file removed (it could not post this: {program.old_error})"
        return f"machine file removed: {program.removed} lines removed"
    if status == CHANGED:
        text = f"{_counts(program)} lines"
        if program.motion_at is not None:
            text += f"; first motion change at {program.motion_at.describe()}"
        if program.renumbered:
            text += f"; block numbers also changed on {program.renumbered} other lines"
        return "; ".join([text, *program.notes])
    return "unchanged"


def _summary_line(result: ReviewResult) -> str:
    s = result.summary()
    parts = [f"{s['changed_programs'] - s[RENUMBERED]} changed (+{s['added_lines']} "
             f"-{s['removed_lines']} lines)"]
    if s[RENUMBERED]:
        parts.append(f"{s[RENUMBERED]} renumbering only")
    parts.append(f"{s[UNCHANGED]} unchanged")
    if s[UNPOSTABLE]:
        parts.append(f"{s[UNPOSTABLE]} cannot be posted by either version")
    if s["errors"]:
        parts.append(_plural(s["errors"], "error"))
    return (f"postdsl review against {result.against} ({result.commit[:12]}): "
            f"{_plural(s['programs'], 'program')} on {_plural(s['machines'], 'machine')}: "
            + ", ".join(parts))


def verdict_line(result: ReviewResult) -> str:
    """The verdicts counted, the ones a reviewer must read first first: "verdicts: 2 motion
    changed, 5 format only, 93 unchanged"."""
    counts = result.verdicts()
    shown = [f"{counts[verdict]} {verdict}" for verdict in VERDICTS if counts.get(verdict)]
    return "verdicts: " + (", ".join(shown) if shown else "no programs")


def _verdict_entry(program: ProgramDiff) -> str:
    """A program's verdict, located when its motion changed."""
    text = f"{program.verdict}: {program.machine}  {program.program}"
    if program.motion_at is not None:
        text += f" — at {program.motion_at.describe()}"
    return text


def _plural(count: int, noun: str) -> str:
    return f"{count} {noun}" if count == 1 else f"{count} {noun}s"


def _noteworthy(result: ReviewResult) -> list[ProgramDiff]:
    return list(result.by_verdict())


def _more(program: ProgramDiff, shown: int) -> str | None:
    left = program.diff_total - shown
    return f"… {left} more diff lines (run postdsl review locally, or --diff-lines 0)" \
        if left > 0 else None


def render_text(result: ReviewResult) -> str:
    """For a terminal: the verdicts, then each changed program's headline and diff, then
    the summary.  Errors are only counted: print ``result.errors`` to stderr beside it.
    """
    return "".join(line + "\n" for line in text_lines(result))


def text_lines(result: ReviewResult) -> Iterator[str]:
    """:func:`render_text`'s lines, one program's at a time (see :func:`write_report`)."""
    noteworthy = _noteworthy(result)
    # names and messages come from files: escaped, no terminal escape sequence runs
    out = [printable(verdict_line(result))]
    out += [printable("  " + _verdict_entry(program)) for program in noteworthy
            if program.verdict != SAME]
    out.append("")
    for program in noteworthy:
        out.append(printable(f"{program.machine}  {program.program}: {headline(program)}"))
        diff = result.diff_of(program)
        out.extend(printable(line) for line in diff)
        more = _more(program, len(diff))
        if more:
            out.append(more)
        if diff:
            out.append("")
        yield from out
        out.clear()
    # errors are not repeated here: the CLI writes them to stderr, where CI logs show them
    out.extend(printable(f"warning: {w}") for w in result.warnings)
    out.append(printable(_summary_line(result)))
    yield from out


# Markdown meant for a pull-request comment shows names (machines, paths) that come with
# the pull request, so none of them may turn into a link, a mention, an image, HTML or
# formatting; and no error message is quoted there, only where it is and what kind it is:
# messages quote the input (a CL record), which may hold anything, secrets included.

#: characters that mean something in Markdown: written with a backslash
_MD_PUNCTUATION = re.compile(r"([\\`*_\[\]()!|~])")
#: where an autolink, a mention or an issue reference would start
_MD_TRIGGERS = re.compile(r"(@|#|://|www\.)", re.IGNORECASE)
#: ``file:line:`` or ``file:line:column:`` at the start of a located message
_SITE = re.compile(r"^(?P<at>[^\n]*?:\d+(?::\d+)?): ")


def _md_cell(text: str) -> str:
    """Plain text in a Markdown table cell (or line): shown as it is, never interpreted."""
    return _untriggered(_MD_PUNCTUATION.sub(r"\\\1", _entities(text)))


def _html(text: str) -> str:
    """Text inside HTML (a ``<summary>``): entities for markup, nothing that links."""
    return _untriggered(_entities(text))


def _entities(text: str) -> str:
    text = "".join(c if c.isprintable() else " " for c in text)
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def _untriggered(text: str) -> str:
    # a zero-width space keeps @team, #12, http:// and www. from becoming mentions or links
    return _MD_TRIGGERS.sub(lambda m: m.group(1)[0] + "\u200b" + m.group(1)[1:], text)


def _md_code(text: str) -> str:
    """Text as a code span in a table cell: literal, whatever backticks it holds.

    A table splits its cells before it reads code spans, and takes a backslash before a
    pipe as an escape even there, so a name with a pipe is written as escaped text.
    """
    if "|" in text:
        return _md_cell(text)
    text = "".join(c if c.isprintable() else " " for c in text)
    fence = "`" * (max((len(run) for run in re.findall("`+", text)), default=0) + 1)
    padded = f" {text} " if text.startswith("`") or text.endswith("`") else text
    return f"{fence}{padded}{fence}"


def _md_error(message: str | None, kind: str) -> str:
    """An error for Markdown: its kind and where it is, never the message itself."""
    match = _SITE.match(message or "")
    if match is None:
        return f"{kind} (run postdsl review for the message)"
    return f"{kind} at {match.group('at')} (run postdsl review for the message)"


def _md_headline(program: ProgramDiff) -> str:
    """:func:`headline`, with every error message replaced by where and what it is."""
    status = program.status
    if status == ERROR:
        return _md_error(program.old_error, "error: the CL program cannot be read or posted")
    if status == UNPOSTABLE:
        return _md_error(program.new_error, "cannot be posted by either version")
    if status == NOW_FAILS:
        return _md_error(program.new_error, "cannot be posted any more")
    if status == NOW_POSTS:
        return f"can be posted now ({program.added} lines; before: " + \
            _md_error(program.old_error, "error") + ")"
    if status == ADDED and program.new_error:
        return _md_error(program.new_error, "new machine file, which cannot post it")
    if status == REMOVED and program.old_error:
        return _md_error(program.old_error, "machine file removed (it could not post this)")
    return headline(program)


def _fence(lines: Sequence[str]) -> str:
    longest = 0
    for line in lines:
        run = 0
        for char in line:
            run = run + 1 if char == "`" else 0
            longest = max(longest, run)
    return "`" * max(3, longest + 1)


def render_markdown(result: ReviewResult, max_diff_lines: int = 400,
                    plots: Mapping[tuple[str, str], PlotFiles] | None = None) -> str:
    """For a pull-request comment: a table of changed programs and folded diffs.

    Each diff is cut after ``max_diff_lines`` lines (hosts limit comment
    size); the counts in the table stay exact.  ``plots`` links each program
    whose motion changed to its before/after pictures (``review.plots``).
    """
    return "".join(line + "\n" for line in markdown_lines(result, max_diff_lines, plots))


def markdown_lines(result: ReviewResult, max_diff_lines: int = 400,
                    plots: Mapping[tuple[str, str], PlotFiles] | None = None) -> Iterator[str]:
    """:func:`render_markdown`'s lines, one program's at a time."""
    s = result.summary()
    out = [f"### postdsl review: {s['changed_programs']} of {s['programs']} programs change "
           f"(+{s['added_lines']} −{s['removed_lines']} lines)", "",
           f"Posted with each machine file at {_md_code(result.against)} "
           f"(`{result.commit[:12]}`) and in the {_md_cell(result.new_label)}.", ""]
    noteworthy = _noteworthy(result)
    out += [f"**{_md_cell(verdict_line(result))}**", ""]
    if noteworthy:
        out += ["| verdict | machine | program | change |", "|---|---|---|---|"]
        out += [f"| {_md_cell(p.verdict)} | {_md_cell(p.machine)} | {_md_code(p.program)} | "
                f"{_md_cell(_md_headline(p))} |" for p in noteworthy]
        out.append("")
    for program in noteworthy:
        diff = result.diff_of(program)
        if not diff:
            continue
        shown = diff[:max_diff_lines]
        fence = _fence(shown)
        out += [f"<details><summary>{_html(program.machine)} · "
                f"{_html(program.program)} ({_counts(program)})</summary>", "",
                *_md_motion(program, plots), f"{fence}diff", *shown, fence]
        if program.diff_total > len(shown):
            out.append(f"… {program.diff_total - len(shown)} more diff lines "
                       f"(run `postdsl review` locally)")
        out += ["", "</details>", ""]
        yield from out
        out.clear()
    for warning in result.warnings:
        out.append(f"> warning: {_md_cell(warning)}")
    for error in result.errors:
        for line in error.splitlines():
            out.append(f"> **error:** {_md_cell(_md_error(line, 'error'))}")
    if result.warnings or result.errors:
        out.append("")
    out.append(_md_cell(_summary_line(result)))
    yield from out




def _md_motion(program: ProgramDiff,
               plots: Mapping[tuple[str, str], PlotFiles] | None) -> list[str]:
    """The toolpath before and after, or that the moves stay the same (when replayed)."""
    if program.verdict == FORMAT_ONLY:
        return ["The toolpath is unchanged: the control model replays the same moves.", ""]
    if program.verdict != MOTION and program.motion is None:
        return []
    files = (plots or {}).get((program.machine, program.program))
    if files is None:
        return ["**The toolpath changes.**", ""]
    return ["**The toolpath changes:**", "",
            "| before | after |", "|---|---|",
            f"| ![before]({quote(files.before)}) | ![after]({quote(files.after)}) |", ""]


def motion_pictures(result: ReviewResult) -> list[tuple[str, str, str, str]]:
    """(machine, program, before SVG, after SVG) of every program whose motion changed."""
    return [(p.machine, p.program, p.motion.before, p.motion.after) for p in result.programs
            if p.motion is not None and p.motion.changed and p.motion.before is not None
            and p.motion.after is not None]


def render_json(result: ReviewResult) -> str:
    """For scripts: every pair (unchanged ones too), the summary and the errors."""
    return "".join(json_chunks(result))


def _json_member(key: str, value: object, last: bool = False) -> str:
    """``"key": value`` as a member of the top-level object, as ``json.dumps(document,
    indent=2)`` writes it."""
    text = json.dumps(value, indent=2, ensure_ascii=False).replace("\n", "\n  ")
    return f"  {json.dumps(key, ensure_ascii=False)}: {text}" + ("\n" if last else ",\n")


def json_chunks(result: ReviewResult) -> Iterator[str]:
    """:func:`render_json`'s document, written one program at a time.

    One JSON object, as before (a consumer ``json.load``s it and finds the same keys
    in the same order, byte for byte what ``json.dumps(document, indent=2)`` wrote),
    but never built whole in memory: the ``programs`` array, the part that grows
    with the archive, is written item by item, each program's diff read from the
    spool as it is written.  An output cut short by a crash is not valid JSON, so a
    consumer cannot take a partial list of programs for the whole one.
    """
    yield "{\n"
    yield _json_member("against", result.against)
    yield _json_member("commit", result.commit)
    yield _json_member("new", result.new_label)
    yield _json_member("exit_status", result.exit_status)
    yield _json_member("verdicts", {verdict: count for verdict in VERDICTS
                                    if (count := result.verdicts().get(verdict, 0))})
    yield _json_member("changes", [
        {"machine": p.machine, "program": p.program, "verdict": p.verdict,
         "motion_at": p.motion_at.to_json() if p.motion_at else None}
        for p in _noteworthy(result)])
    yield _json_member("summary", result.summary())
    if not result.programs:
        yield '  "programs": [],\n'
    else:
        yield '  "programs": [\n'
        for index, program in enumerate(result.programs):
            item = json.dumps({**program.to_json(), "diff": result.diff_of(program)},
                              indent=2, ensure_ascii=False).replace("\n", "\n    ")
            yield "    " + item + (",\n" if index + 1 < len(result.programs) else "\n")
        yield "  ],\n"
    yield _json_member("errors", result.errors)
    yield _json_member("warnings", result.warnings, last=True)
    yield "}\n"


#: the last line of a text report a failure cut short (the exit status is then 3)
INCOMPLETE = "REPORT INCOMPLETE: "


def _incomplete(fmt: str, exc: BaseException) -> str:
    """The line that ends a report cut short, saying so and why.

    A reader of a log or a pull-request comment sees the verdicts first and might
    take a cut report for a whole one; this line says it is not.  Markdown names the
    exception's kind only (its message may quote a CL record, see above)."""
    interrupted = isinstance(exc, KeyboardInterrupt)
    why = ("interrupted" if interrupted else
           f"postdsl failed while writing it (a bug, please report it): {type(exc).__name__}")
    if fmt == "markdown":
        return f"\n> **{INCOMPLETE}{_md_cell(why)}; the programs after this point are " \
               f"missing.**\n"
    detail = "" if interrupted else f": {exc}"
    return "\n" + printable(f"{INCOMPLETE}{why}{detail}; the programs after this point "
                              f"are missing") + "\n"


def write_report(result: ReviewResult, fmt: str, write: Callable[[str], object],
                 plots: Mapping[tuple[str, str], PlotFiles] | None = None) -> None:
    """Write a report through ``write`` a few thousand lines (JSON: programs) at a time,
    so a whole archive's report is never one string in memory.

    When rendering fails midway (a bug, an interrupt), what was written stays written
    and a text or Markdown report ends with a line saying it is incomplete and why;
    the exception goes on to the caller (the CLI's exit status 3).
    """
    if fmt == "json":
        batch_json: list[str] = []
        for chunk in json_chunks(result):
            batch_json.append(chunk)
            if len(batch_json) >= 256:
                write("".join(batch_json))
                batch_json.clear()
        write("".join(batch_json))
        return
    lines = text_lines(result) if fmt == "text" else markdown_lines(result, plots=plots)
    batch: list[str] = []
    try:
        for line in lines:
            batch.append(line)
            if len(batch) >= 4096:
                write("\n".join(batch) + "\n")
                batch.clear()
    except (Exception, KeyboardInterrupt) as exc:
        # the writer itself may be what failed: the exception raised below says why
        with contextlib.suppress(Exception):
            write("".join(line + "\n" for line in batch) + _incomplete(fmt, exc))
        raise
    if batch:
        write("\n".join(batch) + "\n")


def render(result: ReviewResult, fmt: str = "text") -> str:
    renderers: dict[str, Callable[[ReviewResult], str]] = {
        "text": render_text, "markdown": render_markdown, "json": render_json}
    return renderers[fmt](result)


def terminal_progress(label: str = "posting") -> tuple[Progress | None, Callable[[], None]]:
    """A progress callback drawing a bar on stderr, when stderr is a terminal (else None).

    Returns the callback and a function that finishes the bar; CI logs and
    pipes get neither, so they stay clean.
    """
    if not sys.stderr.isatty():
        return None, lambda: None
    import click

    state: dict[str, Any] = {}

    def update(done: int, total: int) -> None:
        bar = state.get("bar")
        if bar is None:
            bar = click.progressbar(length=total, label=label, file=sys.stderr,
                                    show_pos=True)
            bar.__enter__()
            state["bar"] = bar
            state["done"] = 0
        bar.update(done - state["done"])
        state["done"] = done

    def finish() -> None:
        bar = state.pop("bar", None)
        if bar is not None:
            bar.__exit__(None, None, None)

    return update, finish
