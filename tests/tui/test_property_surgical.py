"""Issue 27's property: a post changes only where the technologist changes it.

Hypothesis drives random sequences of the editor's own actions through the Pilot
(``App.run_test()``): keys and widget values on the real screens — formats (f2),
machine settings and options (f4, tabbing through the form as a user does),
variables (f3), item conditions (the item editor), block numbering (n), ``set:``
entries (s), undo, redo and save — for every bundled post and for a post made with
``postdsl new m --from fanuc --extends``.  The actions' parameters are drawn from
the post as it is at that moment (``st.data()``), which makes the test a state
machine driven from inside one running app (Hypothesis' ``RuleBasedStateMachine``
cannot await the Pilot).

After each save:

* the YAML differs from the last save only at the nodes the actions since then
  named (a structural diff of the two documents: a key, an entry or a scalar);
  an edit of something the base post gives is named as its ``override:`` key;
* the NC of the post's corpus programs differs only in lines written by the
  tables those nodes reach (every other line byte-identical); an edit of a
  setting that reaches every line (block numbering, a variable) is exempt.

The number of examples follows the Hypothesis profile (``ci``: a few per post;
``--hypothesis-profile=nightly`` or ``long``: many more).
"""

from __future__ import annotations

import asyncio
import difflib
import shutil
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from ruamel.yaml import YAML
from textual.pilot import Pilot
from textual.widgets import DataTable, Input, Select

from postdsl import api, review
from postdsl.api import ExprItem
from postdsl.newmachine import new_machine
from tests.conftest import MACHINES, ROOT
from tests.tui.conftest import choose
from tui.app import EditorApp
from tui.command_table import ITEM_COLUMN, CommandTable
from tui.formats_editor import FormatsEditor
from tui.item_editor import ItemEditor
from tui.set_editor import SetEditor
from tui.settings_editor import PATHS, SettingsEditor
from tui.variables_editor import VariablesEditor

Path_ = tuple[Any, ...]
EXTENDS = "fanuc_extends"
POSTS = [*sorted(p.stem for p in MACHINES.glob("*.yaml")), EXTENDS]
#: examples per post: a hundredth of the profile's budget (the ci profile's default of
#: 100: one per post, ~10 s each; a nightly profile of 2 000: 20 per post)
EXAMPLES = max(1, settings.default.max_examples // 100)
#: most actions in one example (a save after the last one)
STEPS = 5
#: the corpus programs each save posts with both versions (the first is the sample)
PROGRAMS = 2
NOW = datetime(2021, 1, 22, 4, 57, 30, tzinfo=UTC)
#: an action whose effect on the NC is not confined to some tables
EVERYWHERE = "everywhere"


# --- the post and its corpus ------------------------------------------------------------------


def prepare(folder: Path, name: str) -> tuple[Path, list[Path]]:
    """A private copy of post ``name`` (or ``postdsl new m --from fanuc --extends``)
    and its corpus programs."""
    if name == EXTENDS:
        (folder / "machines").mkdir()
        shutil.copy(MACHINES / "fanuc.yaml", folder / "machines" / "fanuc.yaml")
        programs = api.corpus_programs(MACHINES / "fanuc.yaml")
        (folder / "corpus.yaml").write_text(
            "fanuc:\n" + "".join(f"  - {p}\n" for p in programs), encoding="utf-8")
        post = new_machine("m", "fanuc", folder, extends=True).path
    else:
        post = folder / f"{name}.yaml"
        shutil.copy(MACHINES / f"{name}.yaml", post)
        programs = api.corpus_programs(MACHINES / f"{name}.yaml")
    return post, [Path(p) for p in programs][:PROGRAMS]


def structural_diff(old: Any, new: Any, path: Path_ = ()) -> list[tuple[Path_, bool]]:
    """Where two documents differ: (path, whether the node is missing on one side)."""
    if isinstance(old, dict) and isinstance(new, dict):
        found: list[tuple[Path_, bool]] = []
        for key in [*old, *(k for k in new if k not in old)]:
            if key not in old or key not in new:
                found.append((path + (key,), True))
            else:
                found += structural_diff(old[key], new[key], path + (key,))
        return found
    if isinstance(old, list) and isinstance(new, list) and len(old) == len(new):
        return [d for i, (a, b) in enumerate(zip(old, new, strict=True))
                for d in structural_diff(a, b, path + (i,))]
    if old == new and type(old) is type(new):
        return []
    return [(path, False)]


def named_covers(named: set[Path_], where: Path_, missing: bool) -> bool:
    """A change at ``where`` is inside a named node, or (a mapping created or removed
    whole) holds one."""
    return any(where[:len(n)] == n or (missing and n[:len(where)] == where) for n in named)


def nc_of(text: str, post: Path, programs: list[Path]) -> list[list[api.NCLine] | str]:
    compiled = review.load_side(text, str(post), post)
    posted: list[list[api.NCLine] | str] = []
    for program in programs:
        try:
            posted.append(api.post_commands(compiled, api.read_cl(program), now=NOW))
        except api.CLError as exc:
            posted.append(f"refused: {exc}")
    return posted


@dataclass
class Step:
    """What one action names: the YAML nodes, and the tables whose NC lines it reaches."""

    named: set[Path_] = field(default_factory=set)
    tables: set[str] = field(default_factory=set)

    def add(self, other: Step) -> None:
        self.named |= other.named
        self.tables |= other.tables


@dataclass
class Ledger:
    """The actions since the last save, and the undo/redo history of their steps."""

    since_save: Step = field(default_factory=Step)
    undo: list[Step] = field(default_factory=list)
    redo: list[Step] = field(default_factory=list)
    log: list[str] = field(default_factory=list)


# --- what an edit names -----------------------------------------------------------------------


def node_name(model: api.Post, path: Path_) -> Path_:
    """Where an edit of the node at model ``path`` is written: the node itself, or (the
    base's) its ``override:`` key.  ``machine:`` and ``output:`` merge key by key, and a
    variable or flag is one value: the child's own key is exactly the field."""
    if path[0] in ("machine", "output", "variables", "flags"):
        return path
    file, where = model.origin_of(path)
    if file is None:
        return where
    return ("override", "/".join(str(p) for p in path))


def tables_reading(model: api.Post, test: Callable[[Any], bool]) -> set[str]:
    """Commands and cycles with a (resolved) block or item for which ``test`` holds, and
    the commands redirected to them."""
    found: set[str] = set()
    for section in (model.commands, model.custom_cycles):
        for name, table in section.items():
            for resolved in model.resolved(table.blocks):
                block = resolved.block
                if test(block) or any(test(item) for item in block.items):
                    found.add(name)
    for name, command in model.commands.items():
        if command.redirect in found:
            found.add(name)
    return found


def uses_format(name: str) -> Callable[[Any], bool]:
    def test(node: Any) -> bool:
        if getattr(node, "format", None) == name:
            return True
        sources = [getattr(node, key, None) for key in ("condition", "force_if")]
        if isinstance(node, ExprItem):
            sources.append(node.expr)
        return any(s is not None and (f"'{name}'" in s.source or f'"{name}"' in s.source)
                   for s in sources)
    return test


# --- the actions, through the Pilot ------------------------------------------------------------


Draw = Callable[[st.SearchStrategy[Any]], Any]


async def close_dialogs(app: EditorApp, pilot: Pilot[Any]) -> None:
    for _ in range(4):
        if len(app.screen_stack) == 1:
            return
        await pilot.press("escape")
        await pilot.pause()


async def format_key(app: EditorApp, pilot: Pilot[Any], draw: Draw) -> Step | None:
    """f2: one key of one format."""
    model = app.doc.model
    names = list(model.formats)
    if not names:
        return None
    name = draw(st.sampled_from(names))
    key = draw(st.sampled_from(["decimals", "trailing_zeros", "point"]))
    await pilot.press("f2")
    await pilot.pause()
    editor = app.screen
    assert isinstance(editor, FormatsEditor)
    editor.query_one("#formats-table", DataTable).move_cursor(row=names.index(name))
    await pilot.pause()
    assert editor.current == name
    widget = editor.query_one(f"#f-{key}")
    if isinstance(widget, Input):
        widget.focus()
        widget.value = str(draw(st.integers(0, 5)))
        await pilot.press("enter")
    else:
        assert isinstance(widget, Select)
        widget.value = draw(st.sampled_from([v for _, v in widget._options
                                             if v != Select.NULL]))
    await pilot.pause()
    table = uses_format(name)
    reached = tables_reading(model, table) | tables_reading(app.doc.model, table)
    numbers = model.block_numbers.format == name
    return Step({node_name(model, ("formats", name, key))},
                {EVERYWHERE} if numbers else reached)


async def settings_form(app: EditorApp, pilot: Pilot[Any], draw: Draw) -> Step | None:
    """f4: tab through the form as a user does, to a setting or an option, and change it
    (or only pass through)."""
    model = app.doc.model
    targets = ["n_increment", "extension", "pass"] + (["option"] if model.options else [])
    target = draw(st.sampled_from(targets))
    await pilot.press("f4")
    await pilot.pause()
    editor = app.screen
    assert isinstance(editor, SettingsEditor)
    keys = [w.id[2:] for w in editor.query("#settings-form Input, #settings-form Select")
            if w.id]
    index = draw(st.integers(0, len(keys) - 1)) if target == "pass" else \
        len(PATHS) if target == "option" else keys.index(target)
    for _ in range(index):
        await pilot.press("tab")
    await pilot.pause()
    widget = app.focused
    assert widget is editor.query_one(f"#f-{keys[index]}")
    step = Step()
    if target == "n_increment":
        assert isinstance(widget, Input)
        widget.value = str(draw(st.integers(1, 20)))
        await pilot.press("enter")
        step = Step({node_name(model, PATHS["n_increment"])}, {EVERYWHERE})
    elif target == "extension":
        assert isinstance(widget, Input)
        widget.value = draw(st.sampled_from([".nc", ".txt", ".mpf"]))
        await pilot.press("enter")
        step = Step({node_name(model, PATHS["extension"])})
    elif target == "option":  # the preview's value: never part of the post
        assert isinstance(widget, Select)
        widget.value = draw(st.sampled_from([v for _, v in widget._options]))
    await pilot.pause()
    await pilot.press("tab")  # leave the field, as a user does
    await pilot.pause()
    return step


async def variable(app: EditorApp, pilot: Pilot[Any], draw: Draw) -> Step | None:
    """f3: a variable's value, of its kind."""
    model = app.doc.model
    names = [n for n, v in model.variables.items()
             if isinstance(v.value, (bool, int, float, str))]
    if not names:
        return None
    name = draw(st.sampled_from(names))
    value = model.variables[name].value
    new = ("false" if value else "true") if isinstance(value, bool) else \
        str(draw(st.integers(1, 9)) + (value if isinstance(value, int) else 0)) \
        if isinstance(value, (int, float)) else value + draw(st.sampled_from(["1", "_"]))
    await pilot.press("f3")
    await pilot.pause()
    editor = app.screen
    assert isinstance(editor, VariablesEditor)
    rows = list(editor.variables)
    editor.query_one("#variables-table", DataTable).move_cursor(row=rows.index(name))
    await pilot.pause()
    await pilot.press("enter")
    await pilot.pause()
    field_ = app.screen.query_one(Input)
    field_.value = new
    await pilot.press("enter")
    await pilot.pause()
    # a variable is one value: the child's entry of that name replaces exactly it, an
    # extends: post included (no override: needed)
    return Step({("variables", name)}, {EVERYWHERE})


def table_blocks(model: api.Post) -> list[tuple[str, int, int]]:
    """(command, block, item) of every item of a command's own table (not a ``use:``)."""
    found = []
    for name, command in model.commands.items():
        if command.redirect is not None:
            continue
        for index, block in enumerate(command.blocks or ()):
            for item in range(len(getattr(block, "items", ()))):
                found.append((name, index, item))
    return found


async def open_cell(app: EditorApp, pilot: Pilot[Any], name: str, row: int,
                    column: int) -> CommandTable:
    await choose(pilot, name)
    table = app.main.query_one(CommandTable)
    table.focus()
    table.move_cursor(row=row, column=column)
    await pilot.pause()
    return table


async def item_condition(app: EditorApp, pilot: Pilot[Any], draw: Draw) -> Step | None:
    """The item editor: give an item a condition (``if: "true"``, or one that reads the
    sample)."""
    model = app.doc.model
    cells = [c for c in table_blocks(model)
             if model.item_at(("commands", c[0], "blocks", c[1], "items", c[2])).condition
             is None]
    if not cells:
        return None
    name, block, item = draw(st.sampled_from(cells))
    await open_cell(app, pilot, name, block, ITEM_COLUMN + item)
    await pilot.press("enter")
    await pilot.pause()
    editor = app.screen
    if not isinstance(editor, ItemEditor):
        return Step()
    editor.query_one("#condition", Input).value = draw(st.sampled_from(["true", "1 > 0"]))
    await pilot.pause()
    await pilot.press("ctrl+o")
    await pilot.pause()
    path = ("commands", name, "blocks", block, "items", item)
    return Step({node_name(model, path)}, tables_reading(
        model, lambda node: getattr(node, "path", None) in (path, path[:4])) | {name})


async def block_numbering(app: EditorApp, pilot: Pilot[Any], draw: Draw) -> Step | None:
    """n on a block: numbered or not (every later number moves: reaches every line)."""
    model = app.doc.model
    cells = sorted({(c[0], c[1]) for c in table_blocks(model)})
    if not cells:
        return None
    name, block = draw(st.sampled_from(cells))
    await open_cell(app, pilot, name, block, 1)
    await pilot.press("n")
    await pilot.pause()
    return Step({node_name(model, ("commands", name, "blocks", block, "number"))},
                {EVERYWHERE})


async def set_entry(app: EditorApp, pilot: Pilot[Any], draw: Draw) -> Step | None:
    """s on a table with a ``set:``: change one entry to what it was or its negation."""
    model = app.doc.model
    tables = [(n, c) for n, c in model.commands.items() if c.sets]
    if not tables:
        return None
    name, command = draw(st.sampled_from(tables))
    flag = draw(st.sampled_from(sorted(command.sets)))
    await choose(pilot, name)
    app.main.query_one(CommandTable).focus()
    await pilot.press("s")
    await pilot.pause()
    editor = app.screen
    if not isinstance(editor, SetEditor):
        return Step()
    editor.query_one(DataTable).move_cursor(row=list(editor.sets).index(flag))
    await pilot.pause()
    await pilot.press("enter")
    await pilot.pause()
    source = command.sets[flag].source
    app.screen.query_one(Input).value = draw(st.sampled_from(
        [source, f"not ({source})"]))
    await pilot.press("enter")
    await pilot.pause()
    return Step({node_name(model, ("commands", name, "set", flag))}, {EVERYWHERE})


ACTIONS = {"format": format_key, "settings": settings_form, "variable": variable,
           "item": item_condition, "numbering": block_numbering, "set": set_entry}


# --- the property -----------------------------------------------------------------------------


class Saved:
    """The post as last saved: its document and its NC."""

    def __init__(self, post: Path, programs: list[Path]) -> None:
        self.post, self.programs = post, programs
        self.take()

    def take(self) -> None:
        self.text = self.post.read_text(encoding="utf-8")
        self.data = YAML(typ="safe").load(self.text)
        self.nc = nc_of(self.text, self.post, self.programs)

    def check(self, ledger: Ledger) -> None:
        """The saved file against the last save: only named nodes and reached lines."""
        text = self.post.read_text(encoding="utf-8")
        data = YAML(typ="safe").load(text)
        named = ledger.since_save.named
        stray = [where for where, missing in structural_diff(self.data, data)
                 if not named_covers(named, where, missing)]
        assert not stray, (f"saving changed nodes no action named: {stray}\nactions: "
                           f"{ledger.log}\nnamed: {sorted(map(str, named))}\n"
                           + "".join(difflib.unified_diff(self.text.splitlines(True),
                                                          text.splitlines(True))))
        tables = ledger.since_save.tables
        if EVERYWHERE not in tables:
            for program, old, new in zip(self.programs, self.nc, nc_of(
                    text, self.post, self.programs), strict=True):
                assert_reached(program, old, new, tables, ledger)
        self.take()


def assert_reached(program: Path, old: list[api.NCLine] | str, new: list[api.NCLine] | str,
                   tables: set[str], ledger: Ledger) -> None:
    """Every NC line that changed was written by a table the actions reach."""
    if isinstance(old, str) or isinstance(new, str):
        assert old == new or tables, f"{program.name}: {old!r:.200} -> {new!r:.200}"
        return
    matcher = difflib.SequenceMatcher(None, [line.text for line in old],
                                      [line.text for line in new], autojunk=False)
    for tag, i1, i2, j1, j2 in matcher.get_opcodes():
        if tag == "equal":
            continue
        lines = [*old[i1:i2], *new[j1:j2]]
        stray = [f"{line.table}: {line.text}" for line in lines if line.table not in tables]
        assert not stray, (f"{program.name}: NC lines changed outside the tables the "
                           f"actions reach ({sorted(tables)}): {stray[:6]}\nactions: "
                           f"{ledger.log}")


async def act(app: EditorApp, pilot: Pilot[Any], draw: Draw, saved: Saved,
              ledger: Ledger) -> None:
    """One action drawn from those the post allows now; its step in the ledger."""
    doc = app.doc
    kind = draw(st.sampled_from([*ACTIONS, "undo", "redo", "save"]))
    before = len(doc.undo_stack)
    if kind == "save":
        ledger.log.append("save")
        await save(app, pilot, saved, ledger)
        return
    if kind in ("undo", "redo"):
        ledger.log.append(kind)
        source, target = (ledger.undo, ledger.redo) if kind == "undo" else \
            (ledger.redo, ledger.undo)
        await pilot.press("ctrl+z" if kind == "undo" else "ctrl+y")
        await pilot.pause()
        if source and len(doc.undo_stack) != before:
            step = source.pop()
            target.append(step)
            ledger.since_save.add(step)
        return
    step = await ACTIONS[kind](app, pilot, draw)
    await close_dialogs(app, pilot)
    if step is None:
        return
    ledger.log.append(f"{kind} {sorted(map(str, step.named))}")
    if len(doc.undo_stack) > before:
        ledger.undo.append(step)
        ledger.redo.clear()
        ledger.since_save.add(step)
        if doc.problems:  # the technologist takes back an edit the post refuses
            await pilot.press("ctrl+z")
            await pilot.pause()
            ledger.redo.append(ledger.undo.pop())
            ledger.log.append("undo (problems)")


async def save(app: EditorApp, pilot: Pilot[Any], saved: Saved, ledger: Ledger) -> None:
    await pilot.press("ctrl+s")
    await pilot.pause()
    assert not app.doc.dirty
    saved.check(ledger)
    ledger.since_save = Step()


def run_actions(name: str, draw: Draw, steps: int) -> None:
    """Open post ``name`` in the editor, run ``steps`` drawn actions, save, check."""
    folder = Path(tempfile.mkdtemp(prefix="postdsl-surgical-"))
    try:
        post, programs = prepare(folder, name)
        saved = Saved(post, programs)
        ledger = Ledger()

        async def main() -> None:
            app = EditorApp(post, programs[0] if programs else None)
            async with app.run_test(size=(160, 50)) as pilot:
                await pilot.pause()
                for _ in range(steps):
                    await act(app, pilot, draw, saved, ledger)
                await save(app, pilot, saved, ledger)

        asyncio.run(main())
    finally:
        shutil.rmtree(folder, ignore_errors=True)


@pytest.fixture(autouse=True)
def fixed_time(monkeypatch: pytest.MonkeyPatch) -> None:
    """The posting date of the previews (the checks post at NOW themselves)."""
    monkeypatch.setenv("SOURCE_DATE_EPOCH", str(int(NOW.timestamp())))


@pytest.mark.parametrize("name", POSTS)
@settings(max_examples=EXAMPLES, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(data=st.data())
def test_an_edit_changes_only_the_nodes_it_names(name: str, data: st.DataObject) -> None:
    steps = data.draw(st.integers(1, STEPS), label="steps")
    run_actions(name, data.draw, steps)


# --- the property catches the corruptions of issue 27 ---------------------------------------


def scripted(*choices: Any) -> Draw:
    """A draw that answers from a script (a value for each draw, in order)."""
    answers = list(choices)

    def draw(strategy: st.SearchStrategy[Any]) -> Any:
        return answers.pop(0)
    return draw


def test_the_property_catches_a_form_that_commits_fields_passed_through(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The f4 corruption put back (a field passed through is committed): tabbing to
    Increment deletes ``suffix: ""`` and the property says so."""
    from tui.fields import FieldForm, parse

    def old_commit(self: FieldForm, key: str) -> None:
        field_ = self.fields[key]
        value = parse(field_, self.raw(key))
        if value != self.loaded.get(key) or type(value) is not type(self.loaded.get(key)):
            self.loaded[key] = value
            self.post_message(self.Committed(self, field_, value))

    monkeypatch.setattr(FieldForm, "_commit", old_commit)
    with pytest.raises(AssertionError, match=r"\('output', 'block_numbers', 'suffix'\)"):
        run_actions("emco", scripted("settings", "n_increment", 5), 1)


def test_the_property_catches_a_format_edit_that_replaces_the_base_format(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The f2 corruption put back (``formats: {coord: {decimals: 2}}`` in the child)."""
    from tui import edits

    monkeypatch.setattr(edits, "override_field", edits.set_value)  # the format, whole
    with pytest.raises(AssertionError, match=r"\('formats',\)"):
        run_actions(EXTENDS, scripted("format", "coord", "decimals", 2), 1)


def test_the_corpus_of_every_post_is_there() -> None:
    """The NC half of the property needs programs: every bundled post has some."""
    for name in POSTS[:-1]:
        assert api.corpus_programs(MACHINES / f"{name}.yaml"), name
    assert (ROOT / "corpus.yaml").is_file()
