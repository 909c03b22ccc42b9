"""The generated post code: its flavours write the same bytes, and its text is safe.

Every table of a post runs as a generated Python function; there is no other
executor.  Its flavours must never differ, in the lines written or in the error
refusing a program: the plain module (``postdsl post``, previews, review), its traced
flavour (``postdsl explain``, the editor's trace), and the text lanes writing a file.
Here every corpus case and random variations of it are posted each way, and each
traced line's words are checked to be the line's own text.  The generated text is
checked to carry the post's texts only as string constants, and the cache of
compiled code to be used only when sound.
"""

from __future__ import annotations

import ast
import dataclasses
import tempfile
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from postdsl import api, codecache
from postdsl.cl.model import CLCommand
from postdsl.cl.native import write_native
from postdsl.compile import codegen
from postdsl.compile.runtime import NCLine
from postdsl.errors import CLError
from postdsl.lang import format_codegen
from postdsl.lang.expr import ExprEvalError, compile_expr
from postdsl.lang.expr.codegen import NAMESPACE, emit_expression
from postdsl.lang.expr.runtime import no_value
from postdsl.run.engine import Engine
from postdsl.run.trace import TracingEngine, trace_lines
from tests.conftest import ROOT, THESIS_EPOCH, THESIS_TIME, compiled_post, examples
from tests.test_snapshots import corpus_cases

MACHINES = sorted(p.stem for p in (ROOT / "machines").glob("*.yaml"))


@pytest.fixture(autouse=True)
def _cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(codecache.CACHE_VARIABLE, str(tmp_path / "cache"))


def _written(post: api.CompiledPost, lines: list[NCLine]) -> str:
    return api.post_text(post, lines) + "".join(
        f"\n{line.command}/{line.table}/{line.cl_line}/{line.block}" for line in lines)


def post_both(post: api.CompiledPost, commands: list[CLCommand]) -> tuple[str, str]:
    """The program (or the refusal) through the generated code, then through its traced
    flavour -- where every traced line's words must be that line's own text, in order."""
    results = []
    try:
        lines = api.post_commands(post, commands, cl_file="job", now=THESIS_TIME)
    except CLError as exc:
        results.append(f"REFUSED: {exc}")
    else:
        results.append(_written(post, lines))
    traced: list[NCLine] = []
    try:
        for line in trace_lines(post, commands, cl_file="job", now=THESIS_TIME):
            traced.append(line.line)
            text = line.line.text
            if line.words:  # none only where trailing spaces were trimmed from the words
                assert line.words[0].start == 0 and line.words[-1].end == len(text)
                assert all(text[w.start:w.end] == w.text for w in line.words)
            assert line.record.line == line.line.cl_line or not line.line.cl_line
    except CLError as exc:
        results.append(f"REFUSED: {exc}")
    else:
        results.append(_written(post, traced))
    return results[0], results[1]


@pytest.mark.parametrize(("machine", "cl_path"), corpus_cases())
def test_every_corpus_case_is_traced_as_it_is_written(machine: str, cl_path: Path) -> None:
    post = compiled_post(ROOT / "machines" / f"{machine}.yaml")
    generated, traced = post_both(post, list(api.read_cl(cl_path)))
    assert generated == traced


def test_the_engine_and_the_trace_run_flavours_of_one_generated_module() -> None:
    """No interpreter: the engine runs the post's generated module, the trace its traced
    flavour (the same functions, each block also handing on what it wrote)."""
    post = api.load_post("vmc500")
    assert not hasattr(Engine, "render_block")
    assert not hasattr(codegen, "interpreting")
    plain = Engine(post, now=THESIS_TIME)._generated
    traced = TracingEngine(post, now=THESIS_TIME)._generated
    assert plain is codegen.generated(post) and traced is codegen.generated(post, traced=True)
    assert plain is not traced
    text = codegen.generate(post).source
    traced_text = codegen.generate(post, traced=True).source
    assert "_trace_block" not in text and "_trace_block" in traced_text
    # the traced flavour is the plain one with the recording added, and no text lanes
    assert "def _fields_linear_move" in text and "def _fields_" not in traced_text
    assert traced_text.count("\ndef _b") == text.count("\ndef _b")


_PROGRAMS = [(m, p) for m, p in corpus_cases() if p.suffix == ".jsonl"]


@st.composite
def varied_programs(draw: st.DrawFn) -> tuple[str, list[CLCommand]]:
    """A corpus program with records left out and numbers moved: errors and edge cases."""
    machine, path = draw(st.sampled_from(_PROGRAMS))
    commands = list(api.read_cl(path))
    keep = draw(st.lists(st.booleans(), min_size=len(commands), max_size=len(commands)))
    scale = draw(st.sampled_from([1.0, 0.5, 1.0005, -1.0, 1e-4, 3.0]))
    varied = []
    for command, kept in zip(commands, keep, strict=True):
        if not kept and draw(st.integers(0, 3)) == 0:
            continue
        changes = {}
        for name in ("x", "y", "z", "feed", "depth", "peck", "dwell", "spindle_speed"):
            value = getattr(command, name, None)
            if isinstance(value, (int, float)) and not isinstance(value, bool) and not kept:
                changes[name] = value * scale
        varied.append(dataclasses.replace(command, **changes) if changes else command)
    return machine, varied


@given(varied_programs())
def test_random_programs_are_traced_as_they_are_written(
        case: tuple[str, list[CLCommand]]) -> None:
    machine, commands = case
    generated, traced = post_both(_post(machine), commands)
    assert generated == traced


# --- the text-only path: write_program's plain moves, through the field lanes -----------


def post_streamed(machine: str, commands: list[CLCommand], folder: Path,
                  monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The program (or the refusal) as ``postdsl post`` writes it -- native CL, its plain
    moves read without commands and posted by the lanes on their fields, the text only
    -- then as the engine's full run writes the same file."""
    cl = folder / "job.jsonl"
    cl.write_text("".join(write_native(commands)), encoding="utf-8")
    post = ROOT / "machines" / f"{machine}.yaml"
    monkeypatch.setenv("SOURCE_DATE_EPOCH", str(THESIS_EPOCH))
    # the post compiled once a session: what is compared is how the program is written
    # (write_program is in postdsl.api.files: the name it reads load_post by is there)
    monkeypatch.setattr(api.files, "load_post", compiled_post)
    results = []
    out = folder / "job.nc"
    try:
        # unverified: the paths' texts are compared here (random programs include ones
        # verify refuses; post's verify has its own tests, tests/test_post_verify.py)
        api.write_program(post, cl, out, verify=False)
    except CLError as exc:
        results.append(f"REFUSED: {exc}")
    else:
        results.append(out.read_text(encoding="utf-8"))
    compiled = compiled_post(post)
    try:
        lines = api.post_commands(compiled, api.read_cl(cl), cl_file=str(cl), now=THESIS_TIME)
    except CLError as exc:
        results.append(f"REFUSED: {exc}")
    else:
        results.append(api.post_text(compiled, lines))
    return results


@pytest.mark.parametrize(("machine", "cl_path"), corpus_cases())
def test_every_corpus_case_is_written_to_a_file_as_the_full_run_writes_it(
        machine: str, cl_path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    streamed, run = post_streamed(machine, list(api.read_cl(cl_path)), tmp_path, monkeypatch)
    assert streamed == run


@settings(max_examples=examples(0.6), deadline=None)
@given(varied_programs())
def test_random_programs_are_written_to_a_file_as_the_full_run_writes_them(
        case: tuple[str, list[CLCommand]]) -> None:
    machine, commands = case
    with tempfile.TemporaryDirectory() as folder, pytest.MonkeyPatch.context() as monkeypatch:
        streamed, run = post_streamed(machine, commands, Path(folder), monkeypatch)
    assert streamed == run


def test_the_text_lanes_keep_only_what_the_post_reads() -> None:
    """A post that reads no prev_ value, first_move or given (vmc500) gets a text lane
    without that bookkeeping; one that reads them (heidenhain) keeps it."""
    lean = codegen.generate(_post("vmc500")).source
    lane = lean[lean.index("def _fields_linear_move"):]
    lane = lane.split("\ndef ")[0]
    for kept in ("values['x'] = now_x = in_x", "state._moves_since_tool += 1"):
        assert kept in lane
    for left in ("prev_", "first_move", "given", "moved", "changed.add", "changed = set()",
                 "values['block_number']"):
        assert left not in lane
    # its block is written in: no call, no list of parts, no register saved and put back
    for left in ("(state)", "parts", "saved"):
        assert left not in lane
    full = codegen.generate(_post("heidenhain")).source
    lane = full[full.index("def _fields_linear_move"):]
    lane = lane.split("\ndef ")[0]
    for kept in ("values['prev_x'] = now_x = values.get('x')", "values['first_move'] = first",
                 "moved.add('z')"):
        assert kept in lane
    # linuxcnc's "'x' in given" conditions test the lane's bit, not the values' tuple
    lane = codegen.generate(_post("linuxcnc")).source
    lane = lane[lane.index("def _fields_linear_move"):].split("\ndef ")[0]
    assert "if (given & 1):" in lane and "if (given & 8):" in lane


def _post(machine: str) -> api.CompiledPost:
    return compiled_post(ROOT / "machines" / f"{machine}.yaml")


# --- expressions -------------------------------------------------------------------------


class _Scope:
    def __init__(self, values: dict[str, object], changed: set[str]) -> None:
        self.values = values
        self.changed = changed


def _generated_value(source: str, scope: _Scope) -> object:
    constants: dict[str, object] = {}

    def bind(value: object) -> str:
        name = f"_k{len(constants)}"
        constants[name] = value
        return name

    text = emit_expression(compile_expr(source), bind)
    code = compile(f"def run(state):\n    values = state.values\n    changed = state.changed\n"
                   f"    return {text}\n", "<test>", "exec")
    namespace = {**NAMESPACE, **constants}
    exec(code, namespace)  # the emitter's own text
    try:
        return namespace["run"](scope)
    except KeyError as error:
        raise no_value(error.args[0]) from None


EXPRESSIONS = [
    "x", "changed(x)", "defined(y)", "not changed(x)", "x > 0", "x >= 1.5", "'a' < s",
    "x > 0 and changed(x) and s == 'on'", "x < 0 or y", "s != 'off'", "x == y", "1 < x",
    "x + 1 > 2", "x in [1, 2]", "abs(x) > 1", "min(x, 2)", "round(x, 1)", "-x", "y > 0",
    "missing_name", "missing_name > 0", "s > 0", "x > 'a'", "not (x > 0 and s)",
    "1 + 2 > 2", "true and x", "false or missing_name == 1", "x in [y, 2]", "x / 0 > 1",
    "x <= 2 < 3", "s in 'on'", "changed(y) or defined(x)", "not x == 1",
]


@pytest.mark.parametrize("source", EXPRESSIONS)
@pytest.mark.parametrize("values", [{"x": 2.5, "y": None, "s": "on"},
                                    {"x": -1, "y": 0, "s": "off"},
                                    {"x": True, "y": 3.0, "s": ""}])
def test_expressions_compute_what_the_closures_compute(source: str,
                                                       values: dict[str, object]) -> None:
    scope = _Scope(values, {"x"})
    expression = compile_expr(source)
    try:
        expected: object = ("value", expression.evaluate(scope))
    except ExprEvalError as exc:
        expected = ("error", str(exc))
    try:
        got: object = ("value", _generated_value(source, scope))
    except ExprEvalError as exc:
        got = ("error", str(exc))
    assert got == expected
    if got[0] == "value":
        assert type(got[1]) is type(expected[1])  # type: ignore[index]


def test_the_emitter_compiles_each_node_of_an_expression_once(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The emitter asks for each sub-tree's code on its way down; each node is compiled
    once, not again at every level above it (a deep condition grew quadratically)."""
    from postdsl.lang.expr import nodes
    from postdsl.lang.expr.compiler import Compiler

    compiled: list[int] = []
    real = Compiler._compile

    def counted(self: Compiler, node: nodes.Node) -> object:
        compiled.append(id(node))
        return real(self, node)

    monkeypatch.setattr(Compiler, "_compile", counted)
    expression = compile_expr("not (x > 0 and (y < 1 or changed(x)) and s != 'off')")
    compiled.clear()
    emit_expression(expression, lambda value: "_k")
    assert sorted(compiled) == sorted(set(compiled))
    assert len(compiled) <= sum(1 for _ in nodes.walk(expression.tree))  # type: ignore[arg-type]


# --- the generated text --------------------------------------------------------------

HOSTILE = '''\
postdsl: 1
machine: {name: hostile}
output: {block_numbers: {default: false}}
formats:
  coord: {decimals: 3}
  int: {integer: true}
commands:
  program_start:
    blocks:
      - items: ["'); import os #", {text: "\\"\\"\\" + __import__('os')", modal: m,
                                    mode: changed}]
  program_end:
    blocks: [{items: [" M30"]}]
  tool_change:
    blocks: [{items: [{param: tool_number, prefix: " T", format: int}]}]
    reset: [x]
  rapid_move:
    blocks:
      - items: [{text: G0, modal: motion, mode: changed},
                {param: x, prefix: " X')#", format: coord, mode: changed},
                {expr: "x + 1", prefix: " Q", format: coord, if: "x > 0"}]
'''


def test_post_texts_reach_the_generated_module_only_as_constants(tmp_path: Path) -> None:
    path = tmp_path / "hostile.yaml"
    path.write_text(HOSTILE, encoding="utf-8")
    post = api.load_post(path)
    source = codegen.generate(post).source
    tree = ast.parse(source)
    names = {node.id for node in ast.walk(tree) if isinstance(node, ast.Name)}
    assert "os" not in names and "__import__" not in names
    imports = [node for node in ast.walk(tree) if isinstance(node, ast.Import | ast.ImportFrom)]
    assert imports == []
    strings = {node.value for node in ast.walk(tree) if isinstance(node, ast.Constant)}
    assert "'); import os #" in strings
    lines = api.post_commands(post, api.read_cl_text(
        '{"cmd": "tool_change", "tool_number": 1}\n{"cmd": "rapid_move", "x": 1}\n'
        '{"cmd": "program_end"}\n',
        "t.jsonl"), now=THESIS_TIME)
    assert [line.text for line in lines] == [
        "'); import os #\"\"\" + __import__('os')", " T1", "G0 X')#1.000 Q2.000", " M30"]


# --- the cache ---------------------------------------------------------------------------


def _entries(folder: Path) -> list[Path]:
    return sorted(folder.glob("*.code")) if folder.exists() else []


def _compiles(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    calls: list[str] = []
    real = compile

    def counting(source: str, *args: object, **kwargs: object) -> object:
        calls.append(source)
        return real(source, *args, **kwargs)  # type: ignore[call-overload]

    monkeypatch.setattr(codecache, "compile", counting, raising=False)
    return calls


def test_a_second_load_does_not_compile_again(tmp_path: Path,
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    folder = tmp_path / "cache"
    calls = _compiles(monkeypatch)
    codegen.generated(api.load_post("vmc500"))
    assert len(calls) == 1 and len(_entries(folder)) == 1
    codegen.generated(api.load_post("vmc500"))  # a new compiled post: a new process, say
    assert len(calls) == 1


def test_a_later_run_takes_the_number_formats_from_the_cache(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A post compiles its number formats each run: a later run (no formats compiled in
    the process yet) reads their code from the cache, and writes the same program."""
    program = list(api.read_cl(ROOT / "examples" / "vmc500_cycles.jsonl"))
    format_codegen._compiled.cache_clear()
    first = api.post_commands(api.load_post("vmc500"), program, now=THESIS_TIME)
    kept = sorted((tmp_path / "cache").glob("*.format"))
    assert kept
    format_codegen._compiled.cache_clear()  # as a new process starts
    calls: list[str] = []
    real = compile

    def counting(source: str, *args: object, **kwargs: object) -> object:
        calls.append(source)
        return real(source, *args, **kwargs)  # type: ignore[call-overload]

    monkeypatch.setattr(format_codegen, "compile", counting, raising=False)
    again = api.post_commands(api.load_post("vmc500"), program, now=THESIS_TIME)
    assert calls == [] and [line.text for line in again] == [line.text for line in first]
    assert sorted((tmp_path / "cache").glob("*.format")) == kept


def test_a_corrupt_entry_is_compiled_again_and_replaced(tmp_path: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    folder = tmp_path / "cache"
    codegen.generated(api.load_post("vmc500"))
    (entry,) = _entries(folder)
    good = entry.read_bytes()
    calls = _compiles(monkeypatch)
    for damaged in (b"", good[:-7], good[:-1] + bytes([good[-1] ^ 1]), b"garbage" + good):
        entry.write_bytes(damaged)
        post = api.load_post("vmc500")
        codegen.generated(post)
        assert entry.read_bytes() == good
    assert len(calls) == 4
    lines = api.post_commands(post, api.read_cl(ROOT / "examples" / "vmc500_cycles.jsonl"),
                              now=THESIS_TIME)
    assert lines


def test_an_unwritable_cache_is_left_alone(tmp_path: Path,
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    blocked = tmp_path / "file"
    blocked.write_text("not a folder", encoding="utf-8")
    monkeypatch.setenv(codecache.CACHE_VARIABLE, str(blocked / "cache"))
    post = api.load_post("vmc500")
    assert api.post_commands(post, api.read_cl(ROOT / "examples" / "vmc500_cycles.jsonl"),
                             now=THESIS_TIME)
    assert blocked.read_text(encoding="utf-8") == "not a folder"


def test_an_empty_cache_variable_switches_the_cache_off(tmp_path: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(codecache.CACHE_VARIABLE, "")
    assert codecache.cache_dir() is None
    calls = _compiles(monkeypatch)
    codegen.generated(api.load_post("vmc500"))
    codegen.generated(api.load_post("vmc500"))
    assert len(calls) == 2


def test_the_user_cache_folder_follows_xdg(tmp_path: Path,
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(codecache.CACHE_VARIABLE)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert codecache.cache_dir() == tmp_path / "xdg" / "postdsl"


def test_the_key_is_the_generated_code_and_constants_are_bound_anew(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Formats are constants of the module, not its text: a post differing only in a
    format shares the compiled code and still writes its own digits; a changed word
    is other code."""
    original = (ROOT / "machines" / "vmc500.yaml").read_text(encoding="utf-8")
    zeros = "trailing_zeros: false\n    point: always"
    assert zeros in original and 'prefix: " X"' in original
    variants = {"same": original,
                "format": original.replace(zeros, zeros.replace("false", "true"), 1),
                "word": original.replace('prefix: " X"', 'prefix: " U"')}
    posts, keys, programs = {}, {}, {}
    program = list(api.read_cl(ROOT / "examples" / "vmc500_cycles.jsonl"))
    calls = _compiles(monkeypatch)
    for name, text in variants.items():
        path = tmp_path / f"{name}.yaml"
        path.write_text(text, encoding="utf-8")
        posts[name] = api.load_post(path)
        keys[name] = codecache.source_key(codegen.generate(posts[name]).source)
        programs[name] = post_both(posts[name], program)
    assert keys["same"] == keys["format"] != keys["word"]
    # the format variant found the code of the first, in each flavour (post_both traces)
    assert len(calls) == 4
    for generated, traced in programs.values():
        assert generated == traced
    assert " X40.000 Y20.000 " in programs["format"][0]
    assert " X40. Y20. " in programs["same"][0]
    assert " U40. Y20. " in programs["word"][0]
