"""postdsl as a FreeCAD post: the script `postdsl freecad install` writes, run by FreeCAD.

The slow tests run FreeCAD 0.20 itself (``freecadcmd``, Debian's freecad-python3):
the reference jobs of scripts/freecad_reference.py are posted through FreeCAD's own post
mechanism (scripts/freecad_post_job.py: ``PostProcessor.load`` from the user's macro
folder, ``export`` as the Post Process command calls it), and each NC file must equal
``postdsl post`` on the same job's dump.  A refused job writes no file, and the message
in FreeCAD's report view names the operation.  The other tests run the module with
stand-ins for FreeCAD's objects, without FreeCAD.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest
from click.testing import CliRunner

from postdsl import api, freecad_post
from postdsl.cli import main
from tests.conftest import ROOT

FREECADCMD = shutil.which("freecadcmd")
needs_freecad = pytest.mark.skipif(
    FREECADCMD is None, reason="FreeCAD 0.20's freecadcmd is not installed (Debian: "
    "apt-get install freecad-python3; .ci/run installs it)")

EPOCH = "1700000000"  # SOURCE_DATE_EPOCH: the header's time, the same in both posts

#: the reference jobs (scripts/freecad_reference.py JOBS)
JOBS = ["pocket", "helix", "drilling", "raster", "planes", "modal"]
#: argument strings a Job may give the post
ARGUMENTS = {
    "default": "--machine linuxcnc",
    "numbered_modal": "--machine linuxcnc --option line_numbers=true --option modal=true "
                      "--option axis_modal=true",
    "precision4": "--machine linuxcnc --option 'precision=4' --option comments=false",
}


# --- without FreeCAD ---------------------------------------------------------------------


def test_the_arguments_pick_the_machine_and_options() -> None:
    parsed = freecad_post.parse_arguments("--machine emco --option line_numbers=true "
                                          "--option 'preamble=G17 G90'")
    assert parsed == freecad_post.Arguments("emco", {"line_numbers": "true",
                                                     "preamble": "G17 G90"})


@pytest.mark.parametrize(("argstring", "says"), [
    ("", "--machine"),
    ("--machine emco --option line_numbers", "is not NAME=VALUE"),
    ("--machine emco --speed 3", "unrecognized arguments: --speed 3"),
    ("--machine 'emco", "No closing quotation"),
])
def test_bad_arguments_are_refused_without_exiting(argstring: str, says: str) -> None:
    with pytest.raises(freecad_post.ArgumentError, match=says):
        freecad_post.parse_arguments(argstring)


def test_a_command_keeps_every_digit_of_its_numbers() -> None:
    """The dump post writes five significant digits: 100 mm/min is F:1.6667 there, 100.002
    mm/min once read.  The script writes the double itself."""
    line = freecad_post.command_line("G1", {"X": 1 / 3, "F": 100 / 60, "Y": -4.0})
    assert line == f"Command G1 [ F:{100 / 60!r} X:{1 / 3!r} Y:-4.0 ]"
    assert freecad_post.command_line("(Pocket (2))", {}) == "Command (Pocket (2)) [ ]"


def command(name: str, **parameters: float) -> Any:
    return SimpleNamespace(Name=name, Parameters=parameters)


def path_object(label: str, commands: list[Any], **properties: Any) -> Any:
    return SimpleNamespace(Label=label, Name=label, Path=SimpleNamespace(Commands=commands),
                           **properties)


def job(feed_mm_s: float = 10.0, coolant: str = "None", active: bool = True) -> list[Any]:
    """Fixture, tool controller, one operation: the objects PathPost hands a post."""
    cut = [command("(Profile)"), command("G0", Z=5.0), command("G0", X=0.0, Y=0.0),
           command("G1", Z=-1.0, F=feed_mm_s), command("G1", X=20.0, F=feed_mm_s),
           command("G0", Z=5.0)]
    return [path_object("G54", [command("G54"), command("G0", Z=15.0)]),
            path_object("TC: Endmill", [command("(TC: Endmill)"), command("M6", T=1.0),
                                        command("M3", S=5000.0)]),
            path_object("Profile", cut, CoolantMode=coolant, Active=active),
            path_object("Skipped", [command("G1", X=1.0, F=0.0)], Active=False)]


def test_the_objects_become_the_dump_the_reader_reads() -> None:
    dump = freecad_post.job_dump(job(feed_mm_s=100 / 60, coolant="Flood"))
    assert dump.lines[:3] == ["(Path: G54)", "Command G54 [ ]", "Command G0 [ Z:15.0 ]"]
    assert "(Path: Skipped)" not in dump.lines  # an inactive operation is left out
    start = dump.lines.index("(Path: Profile)")
    assert dump.lines[start + 1] == "Command M8 [ ]" and dump.lines[-1] == "Command M9 [ ]"
    assert dump.origin(start + 6) == "'Profile', command G1 F1.66667 Z-1"  # 1-based


def test_export_writes_what_postdsl_post_writes_of_the_dump(tmp_path: Path) -> None:
    nc = tmp_path / "job.ngc"
    text = freecad_post.export(job(feed_mm_s=100 / 60), str(nc), "--machine linuxcnc "
                               "--option header=false")
    assert text is not None and nc.read_text(encoding="utf-8") == text
    assert "G1 X20.000 F100.000 " in text.splitlines()  # 100/60 mm/s is 100 mm/min exactly
    dump = tmp_path / "job.dump.txt"
    dump.write_text("\n".join(freecad_post.job_dump(job(feed_mm_s=100 / 60)).lines) + "\n")
    assert api.post_file("linuxcnc", dump, options={"header": "false"}) == text


def test_a_file_name_of_dash_returns_the_text_and_writes_nothing(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """FreeCAD 1.1's wrapper of a script post: it writes the returned text itself."""
    monkeypatch.chdir(tmp_path)
    text = freecad_post.export(job(), "-", "--machine linuxcnc")
    assert text is not None and "M2" in text and list(tmp_path.iterdir()) == []


def test_a_refusal_writes_nothing_and_names_the_operation(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    nc = tmp_path / "job.ngc"
    assert freecad_post.export(job(feed_mm_s=0.0), str(nc), "--machine linuxcnc") is None
    assert not nc.exists()
    message = capsys.readouterr().err
    assert message.startswith("postdsl: 'Profile', command G1 F0 Z-1 (dump line ")
    assert "positive feed" in message and "job.dump.txt" not in message


def test_the_coolant_mode_is_read(tmp_path: Path) -> None:
    text = freecad_post.export(job(coolant="Mist"), "-", "--machine linuxcnc")
    assert text is not None and "M7 " in text.splitlines() and "M9 " in text.splitlines()
    assert freecad_post.export(job(coolant="Through"), "-", "--machine linuxcnc") is None


def test_the_default_folder_is_freecads_macro_folder(tmp_path: Path) -> None:
    home = tmp_path / "home"
    assert freecad_post.default_folder(home, {}) == home / ".local/share/FreeCAD/Macro"
    assert freecad_post.default_folder(home, {"XDG_DATA_HOME": str(tmp_path / "data")}) \
        == tmp_path / "data/FreeCAD/Macro"
    (home / ".FreeCAD").mkdir(parents=True)
    assert freecad_post.default_folder(home, {}) == home / ".FreeCAD/Macro"
    config = home / ".config/FreeCAD"
    config.mkdir(parents=True)
    (config / "user.cfg").write_text(
        '<FCParameters><FCParamGroup Name="Root"><FCParamGroup Name="Macro">'
        f'<FCText Name="MacroPath">{tmp_path / "mine"}</FCText>'
        '</FCParamGroup></FCParamGroup></FCParameters>', encoding="utf-8")
    assert freecad_post.default_folder(home, {}) == tmp_path / "mine"


def test_install_writes_a_script_that_finds_this_postdsl(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, ["freecad", "install", "--freecad-dir",
                                       str(tmp_path / "posts")])
    assert result.exit_code == 0, result.output
    script = tmp_path / "posts" / "postdsl_post.py"
    assert str(script) in result.output
    # the script alone, in a Python that has not imported postdsl: it finds it
    probe = ("import importlib.util, sys; from types import SimpleNamespace as N; "
             "spec = importlib.util.spec_from_file_location("
             f"'postdsl_post', {str(script)!r}); m = importlib.util.module_from_spec(spec); "
             "spec.loader.exec_module(m); job = [N(Label='G54', Path=N(Commands=["
             "N(Name='G54', Parameters={}), N(Name='G0', Parameters={'Z': 15.0})]))]; "
             "print(m.export(job, '-', '--machine linuxcnc'))")
    env = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    done = subprocess.run([sys.executable, "-S", "-c", probe], capture_output=True,
                          text=True, cwd=tmp_path, env=env, timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    assert "G21" in done.stdout and "M2" in done.stdout


def test_the_script_refuses_another_python(tmp_path: Path) -> None:
    script = tmp_path / "postdsl_post.py"
    script.write_text(freecad_post.script_text([str(tmp_path)], (2, 7)), encoding="utf-8")
    probe = ("import importlib.util; spec = importlib.util.spec_from_file_location("
             f"'postdsl_post', {str(script)!r}); m = importlib.util.module_from_spec(spec); "
             "spec.loader.exec_module(m); print(m.export([], '-', '--machine linuxcnc'))")
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          timeout=60, check=False)
    assert done.stdout.strip() == "None"
    assert "postdsl was installed for 2.7" in done.stderr


# --- FreeCAD 0.20 itself -------------------------------------------------------------------


def _requests(folder: Path) -> list[dict[str, str]]:
    requests = [{"job": job_name, "post": "postdsl", "args": arguments,
                 "nc": str(folder / f"{job_name}.{name}.ngc"),
                 "dump": str(folder / f"{job_name}.dump.txt")}
                for job_name in JOBS for name, arguments in ARGUMENTS.items()]
    requests += [{"job": refused, "post": "postdsl", "args": ARGUMENTS["default"],
                  "nc": str(folder / f"{refused}.ngc"), "dump": str(folder / f"{refused}.txt")}
                 for refused in ("refused_feed", "refused_tool")]
    return requests


@pytest.fixture(scope="module")
def freecad_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str, str]:
    """Install the post as a user would (the default folder of a fresh home) and let
    FreeCAD post every request in one freecadcmd process: the folder, its standard
    output (the driver's RESULT lines) and its standard error (FreeCAD's report view:
    Console.PrintError writes there without a GUI)."""
    folder = tmp_path_factory.mktemp("freecad")
    home = folder / "home"
    home.mkdir()
    clean = {"HOME": str(home), "XDG_DATA_HOME": None, "XDG_CONFIG_HOME": None}
    installed = CliRunner().invoke(main, ["freecad", "install"], env=clean)
    assert installed.exit_code == 0, installed.output
    assert (home / ".local/share/FreeCAD/Macro/postdsl_post.py").is_file()
    requests = folder / "requests.json"
    requests.write_text(json.dumps(_requests(folder)), encoding="utf-8")
    env = {key: value for key, value in os.environ.items()
           if not key.startswith(("XDG_", "PYTHON"))}
    env.update(HOME=str(home), SOURCE_DATE_EPOCH=EPOCH, POSTDSL_REQUESTS=str(requests))
    assert FREECADCMD is not None
    done = subprocess.run([FREECADCMD, str(ROOT / "scripts" / "freecad_post_job.py")],
                          capture_output=True, text=True, env=env, cwd=folder, timeout=300,
                          check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    return folder, done.stdout, done.stderr


def _postdsl_post(dump: Path, arguments: str, monkeypatch: pytest.MonkeyPatch) -> str:
    parsed = freecad_post.parse_arguments(arguments)
    monkeypatch.setenv("SOURCE_DATE_EPOCH", EPOCH)
    args = ["post", parsed.machine, str(dump)]
    for name, value in parsed.options.items():
        args += ["--option", f"{name}={value}"]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    return result.output


@pytest.mark.slow
@needs_freecad
@pytest.mark.parametrize("arguments", list(ARGUMENTS))
@pytest.mark.parametrize("job_name", JOBS)
def test_freecad_posts_the_job_as_postdsl_post_posts_its_dump(
        freecad_run: tuple[Path, str, str], job_name: str, arguments: str,
        monkeypatch: pytest.MonkeyPatch) -> None:
    folder, output, _ = freecad_run
    assert f"RESULT {folder / f'{job_name}.{arguments}.ngc'} text" in output
    nc = (folder / f"{job_name}.{arguments}.ngc").read_text(encoding="utf-8")
    expected = _postdsl_post(folder / f"{job_name}.dump.txt", ARGUMENTS[arguments], monkeypatch)
    assert nc == expected
    assert nc.splitlines()[-1].endswith("M2")


@pytest.mark.slow
@needs_freecad
@pytest.mark.parametrize(("refused", "names"), [
    ("refused_feed", "postdsl: 'Pocket', command G1 F0 X10 Y10 Z-2 (dump line "),
    ("refused_tool", "postdsl: 'TC: Endmill 6mm', command M6 T1000 (dump line "),
])
def test_freecad_gets_no_file_and_the_operation_named(
        freecad_run: tuple[Path, str, str], refused: str, names: str) -> None:
    folder, output, report = freecad_run
    assert f"RESULT {folder / f'{refused}.ngc'} none" in output
    assert not (folder / f"{refused}.ngc").exists()
    assert names in report, report
    assert "Traceback" not in report
