"""``postdsl review``: the NC lines a post change alters, read from git; and the hooks.

Every test builds its own git repository (the VMC500 post, corpus.yaml and
three small CL programs from tests/data/review/), commits it, edits the post
in the working tree and reviews.  Expected lines are worked out from the
post's formats by hand, never copied from a review's output.
"""

from __future__ import annotations

import json
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner
from ruamel.yaml import YAML

from postdsl import api, review
from postdsl.cli import main
from tests.conftest import DATA, MACHINES, ROOT

CL = DATA / "review"
BIN = Path(sys.executable).parent

COORD_3 = "  coord:               # 40. / 16.996 : point always, trailing zeros trimmed\n" \
          "    decimals: 3\n"
COORD_4 = COORD_3.replace("decimals: 3", "decimals: 4")


def git(repo: Path, *args: str) -> str:
    done = subprocess.run(["git", "-c", "commit.gpgsign=false", *args], cwd=repo,
                          capture_output=True, text=True, check=True)
    return done.stdout


@pytest.fixture(autouse=True)
def _clean_git_env(monkeypatch: pytest.MonkeyPatch) -> None:
    """Inside a git hook GIT_DIR/GIT_INDEX_FILE point at postdsl's own repository."""
    for name in list(os.environ):
        if name.startswith("GIT_"):
            monkeypatch.delenv(name)
    monkeypatch.delenv("SOURCE_DATE_EPOCH", raising=False)


@pytest.fixture
def repo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    root = tmp_path / "shop"
    (root / "machines").mkdir(parents=True)
    shutil.copy(MACHINES / "vmc500.yaml", root / "machines" / "vmc500.yaml")
    shutil.copytree(CL, root / "cl")
    (root / "corpus.yaml").write_text(
        "vmc500:\n  - cl/mill.jsonl\n  - cl/drill.jsonl\n  - cl/plain.jsonl\n",
        encoding="utf-8")
    git(root, "init", "-q")
    git(root, "config", "user.name", "Test")
    git(root, "config", "user.email", "test@example.invalid")
    git(root, "add", "-A")
    git(root, "commit", "-q", "-m", "machine and corpus")
    monkeypatch.chdir(root)
    return root


def edit_post(repo: Path, old: str, new: str) -> None:
    post = repo / "machines" / "vmc500.yaml"
    text = post.read_text(encoding="utf-8")
    assert text.count(old) == 1, f"the VMC500 post no longer contains {old!r}"
    post.write_text(text.replace(old, new), encoding="utf-8")


def run(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["review", *args])
    if result.exception and not isinstance(result.exception, SystemExit):
        raise result.exception
    return result.exit_code, result.output


def changes(program: dict) -> list[str]:
    """The changed lines of a diff: '-' and '+' lines without the file headers."""
    return [line for line in program["diff"]
            if line[:1] in "+-" and not line.startswith(("---", "+++"))]


def by_program(document: dict) -> dict[str, dict]:
    return {p["program"]: p for p in document["programs"]}


# --- a format change --------------------------------------------------------------------------


def test_decimals_change_reports_exactly_the_changed_lines(repo: Path) -> None:
    edit_post(repo, COORD_3, COORD_4)
    status, output = run("--format", "json", "--jobs", "1")
    # a fourth decimal the machine does not resolve (0.001 mm): the text changes, the
    # replayed motion does not, so the exit status is 4 ("format only"), not 1
    assert status == 4
    document = json.loads(output)
    programs = by_program(document)
    assert set(programs) == {"cl/mill.jsonl", "cl/drill.jsonl", "cl/plain.jsonl"}
    # X 12.34567: 12.346 with 3 decimals, 12.3457 with 4; Y, Z and F are whole numbers
    assert changes(programs["cl/mill.jsonl"]) == [
        "-N40  G1 X12.346 F300.0",
        "+N40  G1 X12.3457 F300.0",
    ]
    # X 33.33333 appears in the header's tool extents, the approach and the cycle
    assert changes(programs["cl/drill.jsonl"]) == [
        "-; pohyb nastroje (XxYxZ): (33.333;33.333) x (20.;20.) x (60.;100.)",
        "+; pohyb nastroje (XxYxZ): (33.3333;33.3333) x (20.;20.) x (60.;100.)",
        "-N30  G0 X33.333 Y20. Z80. M9",
        "+N30  G0 X33.3333 Y20. Z80. M9",
        "-N40 G82 X33.333 Y20. Z10.0 R70.0 F200.0",
        "+N40 G82 X33.3333 Y20. Z10.0 R70.0 F200.0",
    ]
    for name, added in (("cl/mill.jsonl", 1), ("cl/drill.jsonl", 3)):
        assert programs[name]["status"] == "changed"
        assert (programs[name]["added"], programs[name]["removed"]) == (added, added)
    plain = programs["cl/plain.jsonl"]
    assert (plain["status"], plain["diff"], plain["changed"]) == ("unchanged", [], False)
    assert document["exit_status"] == 4
    assert document["verdicts"] == {"format only": 2, "unchanged": 1}
    assert {p["program"]: p["verdict"] for p in document["programs"]} == {
        "cl/mill.jsonl": "format only", "cl/drill.jsonl": "format only",
        "cl/plain.jsonl": "unchanged"}
    assert document["summary"]["changed_programs"] == 2
    assert (document["summary"]["added_lines"], document["summary"]["removed_lines"]) == (4, 4)
    assert document["commit"] == git(repo, "rev-parse", "HEAD").strip()

    # the text report: block numbers kept, NC line numbers in the hunk header, the
    # unaffected program not mentioned at all
    status, text = run("--jobs", "1")
    assert status == 4
    assert text.startswith("verdicts: 2 format only, 1 unchanged\n"
                           "  format only: vmc500  cl/drill.jsonl\n"
                           "  format only: vmc500  cl/mill.jsonl\n\n")
    assert "--- vmc500 @ HEAD: cl/mill.jsonl\n+++ vmc500 @ working tree: cl/mill.jsonl\n" \
        "@@ -13,7 +13,7 @@\n" in text
    assert "\n-N40  G1 X12.346 F300.0\n+N40  G1 X12.3457 F300.0\n" in text
    assert "plain.jsonl" not in text
    assert text.rstrip().endswith("3 programs on 1 machine: 2 changed (+4 -4 lines), "
                                  "1 unchanged")

    git(repo, "commit", "-q", "-am", "coord with 4 decimals")
    status, text = run("--jobs", "1")
    assert status == 0
    assert "0 changed (+0 -0 lines), 3 unchanged" in text


def test_header_date_never_changes(repo: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Both sides post at one fixed time: SOURCE_DATE_EPOCH when set, else a constant."""
    edit_post(repo, COORD_3, COORD_4)
    for epoch in (None, "1611291450"):
        if epoch:
            monkeypatch.setenv("SOURCE_DATE_EPOCH", epoch)
        result = review.review(repo, jobs=1, context=1000, use_cache=False)
        mill = next(p for p in result.programs if p.program == "cl/mill.jsonl")
        # the whole program is context: the header's date is there, unchanged (" ")
        dates = [line[1:] for line in mill.diff if line[1:].startswith("; vytvoreno: ")]
        expected = "; vytvoreno: 22.01.2021 v 4:57:30" if epoch else \
            "; vytvoreno: 01.01.2000 v 0:00:00"
        assert dates == [expected]
        assert not any("vytvoreno" in line for line in mill.diff if line[:1] in "+-")


def test_works_from_a_subdirectory_with_the_installed_command(repo: Path) -> None:
    edit_post(repo, COORD_3, COORD_4)
    done = subprocess.run([str(BIN / "postdsl"), "review", "--machine", "vmc500"],
                          cwd=repo / "cl", capture_output=True, text=True, check=False)
    assert done.returncode == 4, done.stderr  # format only
    assert "+N40  G1 X12.3457 F300.0" in done.stdout
    assert done.stderr == ""  # no progress bar when stderr is not a terminal


# --- renumbering ------------------------------------------------------------------------------


def test_block_number_start_change_is_renumbering_only(repo: Path) -> None:
    edit_post(repo, "    start: 10\n", "    start: 100\n")
    status, output = run("--format", "json", "--jobs", "1")
    assert status == 4  # text changes only
    programs = by_program(json.loads(output))
    # numbered blocks: mill and drill 7 (N10..N70), plain 6 (N10..N60)
    for name, numbered in (("cl/mill.jsonl", 7), ("cl/drill.jsonl", 7),
                           ("cl/plain.jsonl", 6)):
        program = programs[name]
        assert program["status"] == "renumbered"
        assert program["renumbering_only"] is True
        assert (program["added"], program["removed"], program["diff"]) == (0, 0, [])
        assert program["renumbered"] == numbered

    status, text = run("--jobs", "1")
    assert status == 4
    lines = text.splitlines()
    # the verdicts first, then each program's headline
    assert lines[:5] == ["verdicts: 3 renumbering only",
                         "  renumbering only: vmc500  cl/drill.jsonl",
                         "  renumbering only: vmc500  cl/mill.jsonl",
                         "  renumbering only: vmc500  cl/plain.jsonl", ""]
    lines = lines[5:]
    assert lines[:3] == [
        "vmc500  cl/drill.jsonl: renumbering only (7 block numbers; "
        "first: 'N10  T2 M6' -> 'N100  T2 M6')",
        "vmc500  cl/mill.jsonl: renumbering only (7 block numbers; "
        "first: 'N10  T1 M6' -> 'N100  T1 M6')",
        "vmc500  cl/plain.jsonl: renumbering only (6 block numbers; "
        "first: 'N10  T1 M6' -> 'N100  T1 M6')",
    ]
    assert len(lines) == 4  # and the summary; not one line of diff
    assert "0 changed (+0 -0 lines), 3 renumbering only, 0 unchanged" in lines[3]


def test_a_new_numbered_block_is_one_added_line_not_a_renumbered_program(repo: Path) -> None:
    edit_post(repo, '      - number: false\n        items: [" :"]\n',
              '      - number: false\n        items: [" :"]\n      - items: [" G90 G17"]\n')
    result = review.review(repo, jobs=1)
    mill = next(p for p in result.programs if p.program == "cl/mill.jsonl")
    assert mill.status == "changed"
    assert [line for line in mill.diff[2:] if line[:1] in "+-"] == ["+N10  G90 G17"]
    assert (mill.added, mill.removed, mill.renumbered) == (1, 0, 7)
    assert "+1 -0 lines; block numbers also changed on 7 other lines" in \
        review.render_text(result)


def test_without_block_number_only_strips_numbered_blocks() -> None:
    post = api.load_post("vmc500")
    lines = api.post_commands(post, api.read_cl(CL / "mill.jsonl"))
    keys = {line.text: api.without_block_number(post, line) for line in lines}
    assert keys["N40  G1 X12.346 F300.0"] == " G1 X12.346 F300.0"
    assert keys["N10  T1 M6"] == " T1 M6"
    assert keys["; nazev NC programu: MILL"] == "; nazev NC programu: MILL"


# --- markdown and json ------------------------------------------------------------------------


def test_markdown_suits_a_pull_request_comment(repo: Path) -> None:
    edit_post(repo, COORD_3, COORD_4)
    status, text = run("--format", "markdown", "--jobs", "1")
    assert status == 4
    assert text.startswith("### postdsl review: 2 of 3 programs change (+4 −4 lines)\n")
    assert "**verdicts: 2 format only, 1 unchanged**" in text
    assert "| verdict | machine | program | change |\n|---|---|---|---|\n" in text
    assert "| format only | vmc500 | `cl/mill.jsonl` | +1 -1 lines |" in text
    assert "| format only | vmc500 | `cl/drill.jsonl` | +3 -3 lines |" in text
    assert "plain.jsonl" not in text
    # the replay's finding above each diff
    head = ("<details><summary>vmc500 · cl/mill.jsonl (+1 -1)</summary>\n\nThe toolpath is "
            "unchanged: the control model replays the same moves.\n\n```diff\n")
    assert head in text
    block = text.split(head)[1]
    diff = block.split("\n```\n")[0].splitlines()
    assert [line for line in diff[2:] if line[:1] in "+-"] == [
        "-N40  G1 X12.346 F300.0", "+N40  G1 X12.3457 F300.0"]
    assert text.count("<details>") == text.count("</details>") == 2


def test_markdown_and_json_of_an_unchanged_tree(repo: Path) -> None:
    status, text = run("--format", "markdown", "--jobs", "1")
    assert status == 0
    assert "0 of 3 programs change" in text and "<details>" not in text
    status, output = run("--format", "json", "--jobs", "1")
    document = json.loads(output)
    assert (status, document["exit_status"]) == (0, 0)
    assert {p["status"] for p in document["programs"]} == {"unchanged"}
    # the machine file is the same on both sides: nothing needs posting
    assert {p["posted"] for p in document["programs"]} == {False}


# --- machines, corpora and errors -------------------------------------------------------------


def test_new_machine_file_is_all_added(repo: Path) -> None:
    shutil.copy(repo / "machines" / "vmc500.yaml", repo / "machines" / "vmc600.yaml")
    status, output = run("--machine", "vmc600", "--corpus", "cl", "--format", "json",
                         "--jobs", "1")
    assert status == 1
    programs = by_program(json.loads(output))
    mill = programs["cl/mill.jsonl"]
    assert mill["status"] == "added"
    assert mill["removed"] == 0 and mill["added"] == 19  # 12 header lines + N10..N70
    assert all(line.startswith("+") for line in changes(mill))
    assert mill["diff"][2] == "@@ -0,0 +1,19 @@"


def test_corpus_folder_posts_every_program_and_reports_unpostable_pairs(repo: Path,
                                                                       tmp_path: Path) -> None:
    extra = tmp_path / "more"
    extra.mkdir()
    shutil.copy(CL / "mill.jsonl", extra / "mill_again.jsonl")
    # an arc before any move: no machine can post it, whatever its post says
    (extra / "arc_first.jsonl").write_text(
        '{"cmd": "program_start"}\n{"cmd": "arc_move", "x": 1, "y": 1}\n'
        '{"cmd": "program_end"}\n', encoding="utf-8")
    (extra / "README.md").write_text("not a CL program\n", encoding="utf-8")
    edit_post(repo, COORD_3, COORD_4)
    status, output = run("--corpus", str(extra), "--format", "json", "--jobs", "1")
    document = json.loads(output)
    programs = by_program(document)
    assert status == 4  # format only
    assert set(programs) == {str(extra / "arc_first.jsonl"), str(extra / "mill_again.jsonl")}
    arc = programs[str(extra / "arc_first.jsonl")]
    assert arc["status"] == "unpostable" and arc["changed"] is False
    assert re.match(r".*arc_first\.jsonl:2: arc_move before the tool position is known",
                    arc["new_error"])
    assert document["errors"] == []

    # an unpostable program alone changes nothing: exit 0, but it is reported
    git(repo, "commit", "-q", "-am", "4 decimals")
    edit_post(repo, "  int:\n    integer: true\n", "  int:\n    integer: true\n  spare:\n"
              "    decimals: 2\n")
    status, text = run("--corpus", str(extra), "--jobs", "1")
    assert status == 0
    assert "arc_first.jsonl: cannot be posted by either version: " in text
    assert "1 cannot be posted by either version" in text


def test_program_the_new_post_cannot_post_is_a_change(repo: Path) -> None:
    # the new post drops the table for dwell; a program with a dwell fails now
    (repo / "cl" / "dwell.jsonl").write_text(
        '{"cmd": "program_start"}\n{"cmd": "tool_change", "tool_number": 1}\n'
        '{"cmd": "rapid_move", "x": 1, "y": 1, "z": 50}\n{"cmd": "dwell", "dwell": 2}\n'
        '{"cmd": "program_end"}\n', encoding="utf-8")
    edit_post(repo, '  dwell:\n    preview: {dwell: 0.5}\n    blocks:\n'
              '      - items: [" G4", {param: dwell, prefix: " F", format: cycle}]\n', "")
    result = review.review(repo, corpora=["cl"], jobs=1)
    dwell = next(p for p in result.programs if p.program == "cl/dwell.jsonl")
    assert dwell.status == "now_fails"
    assert dwell.new_error is not None and "cl/dwell.jsonl:4: " in dwell.new_error
    assert "-N30  G4 F2.0" in dwell.diff
    assert result.exit_status == 1


def test_errors_exit_2(repo: Path, tmp_path: Path) -> None:
    status, output = run("--against", "no-such-branch")
    assert status == 2 and "unknown revision 'no-such-branch'" in output

    status, output = run("--machine", "nosuch")
    # issue 27: the machine is unknown, corpus.yaml is not to blame
    assert status == 2 and "unknown machine 'nosuch'" in output

    # an unreadable CL file is an error of the review, not a finding
    bad = tmp_path / "bad"
    bad.mkdir()
    (bad / "broken.jsonl").write_text('{"cmd": "program_start"}\n{"cmd": "nonsense"}\n',
                                      encoding="utf-8")
    edit_post(repo, COORD_3, COORD_4)
    status, output = run("--corpus", str(bad), "--jobs", "1")
    assert status == 2
    assert re.search(r"broken\.jsonl:2: .*nonsense", output)

    # an invalid post in the working tree: a located message, exit 2 (not check's 1)
    edit_post(repo, "format: two_digits, prefix: \".\"}", "format: two_digit, prefix: \".\"}")
    status, output = run("--jobs", "1")
    assert status == 2
    assert re.search(r"^machines/vmc500\.yaml:\d+:\d+: .*two_digit", output, re.M)


def test_outside_a_repository(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    status, output = run()
    assert status == 2 and "not inside a git repository" in output
    assert review.corpus_for_machine("vmc500") == []  # an editor then shows no programs


# --- parallel posting -------------------------------------------------------------------------


@pytest.mark.benchmark
def test_parallel_review_equals_serial(tmp_path: Path) -> None:
    """The speed-up itself is asserted by benchmarks/review_parallel.py (timing is flaky
    on a shared 2-core CI box); here: two processes find exactly what one finds."""
    from benchmarks.review_parallel import make_repository

    corpus = make_repository(tmp_path, programs=12, seed=7)
    serial = review.review(tmp_path, corpora=[corpus], jobs=1)
    calls: list[tuple[int, int]] = []
    parallel = review.review(tmp_path, corpora=[corpus], jobs=2,
                             progress=lambda done, total: calls.append((done, total)))
    assert calls == [(done, 12) for done in range(13)]  # what drives the progress bar
    assert len(serial.programs) == 12
    assert {p.status for p in serial.programs} == {"changed"}
    assert parallel.programs == serial.programs
    assert review.render_json(parallel) == review.render_json(serial)


# --- the editor's review (saved file vs unsaved edits) ---------------------------------------


def test_review_texts_diffs_unsaved_edits() -> None:
    saved = (MACHINES / "vmc500.yaml").read_text(encoding="utf-8")
    unsaved = saved.replace(COORD_3, COORD_4)
    diffs = review.review_texts(saved, unsaved, [CL / "mill.jsonl", CL / "plain.jsonl"],
                                machine="vmc500", file="machines/vmc500.yaml")
    mill, plain = diffs
    assert mill.status == "changed" and plain.status == "unchanged"
    assert mill.diff[:2] == [f"--- vmc500 @ saved: {CL / 'mill.jsonl'}",
                             f"+++ vmc500 @ unsaved: {CL / 'mill.jsonl'}"]
    assert [line for line in mill.diff[2:] if line[:1] in "+-"] == [
        "-N40  G1 X12.346 F300.0", "+N40  G1 X12.3457 F300.0"]
    # the editor's corpus: corpus.yaml above the post file it edits
    expected = [review.Program(p, ROOT / p) for p in
                YAML(typ="safe").load((ROOT / "corpus.yaml").read_text())["vmc500"]]
    assert review.corpus_for_machine("vmc500", ROOT) == expected
    assert review.corpus_for_machine(MACHINES / "vmc500.yaml") == expected
    with pytest.raises(api.PostError) as error:
        review.review_texts(saved, unsaved.replace("format: int}", "format: nope}", 1),
                            [CL / "mill.jsonl"], file="machines/vmc500.yaml")
    assert re.match(r"machines/vmc500\.yaml:\d+:\d+: ", str(error.value))


# --- hooks ------------------------------------------------------------------------------------


def hooks(path: Path) -> dict[str, dict]:
    data = YAML(typ="safe").load(path.read_text(encoding="utf-8"))
    if isinstance(data, dict):  # .pre-commit-config.yaml: repos -> hooks
        return {h["id"]: h for r in data["repos"] for h in r["hooks"]}
    return {h["id"]: h for h in data}


def hook_command(hook: dict, files: list[str]) -> list[str]:
    command = shlex.split(hook["entry"]) + list(hook.get("args", []))
    return command + (files if hook.get("pass_filenames", True) else [])


def env_with_venv() -> dict[str, str]:
    """The hook environment pre-commit would make: postdsl and python on PATH."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("GIT_")}
    env["PATH"] = f"{BIN}{os.pathsep}{env.get('PATH', '')}"
    return env


@pytest.mark.parametrize("config", [".pre-commit-hooks.yaml", ".pre-commit-config.yaml"])
def test_check_hook_fails_on_a_broken_machine_with_a_located_message(config: str,
                                                                    tmp_path: Path) -> None:
    hook = hooks(ROOT / config)["postdsl-check"]
    assert re.search(hook["files"], "machines/vmc500.yaml")
    assert re.search(hook["files"], "machines/lathe.yml")
    assert not re.search(hook["files"], "examples/vmc500_cycles.jsonl")
    machines = tmp_path / "machines"
    machines.mkdir()
    good = machines / "vmc500.yaml"
    shutil.copy(MACHINES / "vmc500.yaml", good)
    broken = machines / "broken.yaml"
    broken.write_text(good.read_text(encoding="utf-8").replace(
        "{param: tool_number, prefix: \" T\", format: int}",
        "{param: tool_number, prefix: \" T\", format: integer}"), encoding="utf-8")
    ok = subprocess.run(hook_command(hook, ["machines/vmc500.yaml"]), cwd=tmp_path,
                        env=env_with_venv(), capture_output=True, text=True, check=False)
    assert ok.returncode == 0, ok.stderr
    failed = subprocess.run(hook_command(hook, ["machines/vmc500.yaml", "machines/broken.yaml"]),
                            cwd=tmp_path, env=env_with_venv(), capture_output=True, text=True,
                            check=False)
    assert failed.returncode != 0
    line = next(i for i, text in enumerate(broken.read_text().splitlines(), 1)
                if "format: integer}" in text)
    assert re.search(rf"^machines/broken\.yaml:{line}:\d+: .*integer", failed.stderr, re.M), \
        failed.stderr


def test_hook_configurations_agree() -> None:
    published = hooks(ROOT / ".pre-commit-hooks.yaml")
    local = hooks(ROOT / ".pre-commit-config.yaml")
    assert set(published) == set(local) == {"postdsl-check", "postdsl-snapshots"}
    assert published["postdsl-check"]["files"] == local["postdsl-check"]["files"]
    for hooks_ in (published, local):
        snapshots = hooks_["postdsl-snapshots"]
        assert snapshots["pass_filenames"] is False
        assert snapshots["args"] == ["tests/test_snapshots.py"]
        for path in ("machines/vmc500.yaml", "corpus.yaml",
                     "tests/__snapshots__/test_snapshots/test_nc_output[vmc500-x].nc"):
            assert re.search(snapshots["files"], path)


@pytest.mark.slow  # git and the snapshot suite in subprocesses
def test_snapshot_hook_fails_when_a_post_change_lacks_its_snapshots(tmp_path: Path) -> None:
    """Run the published snapshot hook in a copy of the project, before and after a change."""
    copy = tmp_path / "postdsl"
    copy.mkdir()
    for name in ("postdsl", "schemas", "machines", "examples", "tests/data"):
        shutil.copytree(ROOT / name, copy / name,
                        ignore=shutil.ignore_patterns("__pycache__", "_data"))
    for name in ("pyproject.toml", "tests/__init__.py", "tests/conftest.py",
                 "tests/test_snapshots.py"):
        shutil.copy(ROOT / name, copy / name)
    # the VMC500 cases only, so machines still being added elsewhere do not matter here
    programs = YAML(typ="safe").load((ROOT / "corpus.yaml").read_text())["vmc500"]
    (copy / "corpus.yaml").write_text("vmc500:\n" + "".join(f"  - {p}\n" for p in programs),
                                      encoding="utf-8")
    snapshots = copy / "tests" / "__snapshots__" / "test_snapshots"
    snapshots.mkdir(parents=True)
    for snapshot in (ROOT / "tests" / "__snapshots__" / "test_snapshots").iterdir():
        if "[vmc500-" in snapshot.name:
            shutil.copy(snapshot, snapshots / snapshot.name)
    hook = hooks(ROOT / ".pre-commit-hooks.yaml")["postdsl-snapshots"]
    command = hook_command(hook, ["machines/vmc500.yaml"])
    env = env_with_venv()
    env.pop("PYTHONPATH", None)
    passed = subprocess.run(command, cwd=copy, env=env, capture_output=True, text=True,
                            check=False)
    assert passed.returncode == 0, passed.stdout + passed.stderr
    post = copy / "machines" / "vmc500.yaml"
    post.write_text(post.read_text(encoding="utf-8").replace(COORD_3, COORD_4),
                    encoding="utf-8")
    failed = subprocess.run(command, cwd=copy, env=env, capture_output=True, text=True,
                            check=False)
    assert failed.returncode != 0
    assert "snapshot" in failed.stdout.lower()


@pytest.mark.skipif(shutil.which("pre-commit") is None, reason="pre-commit is not installed")
def test_pre_commit_accepts_the_hook_files() -> None:
    for command in (["pre-commit", "validate-manifest", ".pre-commit-hooks.yaml"],
                    ["pre-commit", "validate-config", ".pre-commit-config.yaml"]):
        done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, check=False)
        assert done.returncode == 0, done.stdout + done.stderr


def test_a_block_number_removed_is_a_change_not_renumbering() -> None:
    """``N20 G0 X5.`` -> ``G0 X5.``: the control receives other text (no block to jump to)."""
    old = review._Output(lines=["N10 T1 M6", "N20 G0 X5."], keys=["T1 M6", "G0 X5."],
                         text="N10 T1 M6\nN20 G0 X5.\n")
    new = review._Output(lines=["N10 T1 M6", "G0 X5."], keys=["T1 M6", "G0 X5."],
                         text="N10 T1 M6\nG0 X5.\n")
    removed = review.compare_outputs("m", "p", old, new, old_label="HEAD", new_label="tree")
    assert removed.status == review.CHANGED
    assert (removed.added, removed.removed, removed.renumbered) == (1, 1, 0)
    assert [line for line in removed.diff[2:] if line[:1] in "+-"] == ["-N20 G0 X5.",
                                                                      "+G0 X5."]
    added = review.compare_outputs("m", "p", new, old, old_label="HEAD", new_label="tree")
    assert added.status == review.CHANGED and (added.added, added.removed) == (1, 1)
    # a number that only changed its value stays renumbering
    moved = review._Output(lines=["N10 T1 M6", "N30 G0 X5."], keys=["T1 M6", "G0 X5."],
                           text="N10 T1 M6\nN30 G0 X5.\n")
    renumbered = review.compare_outputs("m", "p", old, moved, old_label="HEAD",
                                        new_label="tree")
    assert renumbered.status == review.RENUMBERED and renumbered.renumbered == 1


def test_a_post_change_that_makes_wrong_nc_is_a_refusal_not_a_change(repo: Path) -> None:
    """Review posts as ``postdsl post`` does, verified: whole millimetres (X12.346 written
    X12.) is the refusal post would give, with the diff that causes it shown."""
    edit_post(repo, COORD_3, COORD_3.replace("decimals: 3", "decimals: 0"))
    result = review.review(repo, jobs=1)
    [program] = [p for p in result.programs
                 if p.machine == "vmc500" and p.program == "cl/mill.jsonl"]
    assert program.status == review.NOW_FAILS
    assert program.new_error is not None
    assert "does not do what the CL says" in program.new_error
    assert any(line.startswith("+") and "X12." in line for line in program.diff)
