"""`post -o` on hostile targets: never a replaced device, never a lost CL file, no leftovers."""

from __future__ import annotations

import os
import signal
import stat
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from postdsl import api
from postdsl.run import writer
from tests.conftest import DATA, EXAMPLES, ROOT, THESIS_EPOCH

PROGRAM = EXAMPLES / "vmc500_cycles.jsonl"
EXPECTED = (DATA / "vmc500_thesis.nc").read_text(encoding="utf-8")

posix = pytest.mark.skipif(os.name != "posix", reason="FIFOs, device nodes, signals")


def run(*args: str) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "SOURCE_DATE_EPOCH": str(THESIS_EPOCH)}
    return subprocess.run([sys.executable, "-m", "postdsl.cli", *args], capture_output=True,
                          text=True, env=env, cwd=ROOT, check=False, timeout=60)


@posix
def test_a_fifo_without_a_reader_is_neither_replaced_nor_waited_for(tmp_path: Path) -> None:
    fifo = tmp_path / "to_dnc"
    os.mkfifo(fifo)
    result = run("post", "vmc500", str(PROGRAM), "-o", str(fifo))
    assert result.returncode == 2
    assert result.stderr.strip() == (f"{fifo}: cannot write the NC program: it is a FIFO "
                                     f"that no program is reading")
    assert stat.S_ISFIFO(fifo.lstat().st_mode)
    assert [p.name for p in tmp_path.iterdir()] == ["to_dnc"]


@posix
def test_a_fifo_with_a_reader_receives_the_program(tmp_path: Path, monkeypatch) -> None:
    """Writing into a named pipe is streaming to a DNC sender: the program flows through it."""
    monkeypatch.setenv("SOURCE_DATE_EPOCH", str(THESIS_EPOCH))
    fifo = tmp_path / "to_dnc"
    os.mkfifo(fifo)
    received: list[bytes] = []
    reader_fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)

    def read() -> None:
        chunks: list[bytes] = []
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            try:
                chunk = os.read(reader_fd, 65536)
            except BlockingIOError:  # the writer is there, nothing to read yet
                time.sleep(0.01)
                continue
            if chunk:
                chunks.append(chunk)
            elif chunks:  # the writer closed its end after writing
                break
            else:  # no writer yet
                time.sleep(0.01)
        received.append(b"".join(chunks))

    thread = threading.Thread(target=read)
    thread.start()
    try:
        api.post_file("vmc500", PROGRAM, fifo)
    finally:
        thread.join(timeout=40)
        os.close(reader_fd)
    assert received[0].decode("utf-8") == EXPECTED
    assert stat.S_ISFIFO(fifo.lstat().st_mode)
    assert [p.name for p in tmp_path.iterdir()] == ["to_dnc"]


@posix
@pytest.mark.skipif(os.name == "posix" and os.geteuid() != 0,
                    reason="creating a device node needs root")
def test_a_device_node_is_never_replaced(tmp_path: Path) -> None:
    node = tmp_path / "null"
    os.mknod(node, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
    result = run("post", "vmc500", str(PROGRAM), "-o", str(node))
    assert result.returncode == 2
    assert result.stderr.strip() == (f"{node}: cannot write the NC program: it is a "
                                     f"character device, not a file; postdsl only replaces "
                                     f"regular files")
    assert stat.S_ISCHR(node.lstat().st_mode)
    assert [p.name for p in tmp_path.iterdir()] == ["null"]


@posix
def test_a_socket_is_never_replaced(tmp_path: Path) -> None:
    import socket

    path = tmp_path / "s"
    server = socket.socket(socket.AF_UNIX)
    try:
        server.bind(str(path))
        with pytest.raises(api.CLError) as caught:
            api.post_file("vmc500", PROGRAM, path)
        assert "socket" in caught.value.message
        assert stat.S_ISSOCK(path.lstat().st_mode)
    finally:
        server.close()


def test_the_output_cannot_be_the_cl_program(tmp_path: Path) -> None:
    cl = tmp_path / "prog.jsonl"
    cl.write_bytes(PROGRAM.read_bytes())
    result = run("post", "vmc500", str(cl), "-o", str(cl))
    assert result.returncode == 2
    assert result.stderr.strip() == (f"{cl}: cannot write the NC program: it is the CL "
                                     f"program being posted")
    assert cl.read_bytes() == PROGRAM.read_bytes()
    assert [p.name for p in tmp_path.iterdir()] == ["prog.jsonl"]


@posix
def test_the_output_cannot_be_the_file_standard_input_is_redirected_from(
        tmp_path: Path) -> None:
    """``post M - -o in.jsonl < in.jsonl``: the CL program has no path on the command
    line, only standard input; it is compared by descriptor (issue 25)."""
    cl = tmp_path / "prog.jsonl"
    cl.write_bytes(PROGRAM.read_bytes())
    env = {**os.environ, "SOURCE_DATE_EPOCH": str(THESIS_EPOCH)}
    with cl.open("rb") as stdin:
        result = subprocess.run([sys.executable, "-m", "postdsl.cli", "post", "vmc500", "-",
                                 "-o", str(cl)], stdin=stdin, capture_output=True, text=True,
                                env=env, cwd=ROOT, check=False, timeout=60)
    assert result.returncode == 2, result.stderr
    assert result.stderr.strip() == (f"{cl}: cannot write the NC program: it is the CL "
                                     f"program being posted")
    assert cl.read_bytes() == PROGRAM.read_bytes()
    assert [p.name for p in tmp_path.iterdir()] == ["prog.jsonl"]
    # standard input from another file still posts to the target
    target = tmp_path / "prog.nc"
    with cl.open("rb") as stdin:
        result = subprocess.run([sys.executable, "-m", "postdsl.cli", "post", "vmc500", "-",
                                 "-o", str(target)], stdin=stdin, capture_output=True,
                                text=True, env=env, cwd=ROOT, check=False, timeout=60)
    assert result.returncode == 0, result.stderr
    assert target.read_text(encoding="utf-8") == EXPECTED


@posix
@pytest.mark.parametrize("kind", ["symlink", "hardlink"])
def test_the_output_cannot_be_a_link_to_the_cl_program(tmp_path: Path, kind: str) -> None:
    cl = tmp_path / "prog.jsonl"
    cl.write_bytes(PROGRAM.read_bytes())
    link = tmp_path / "prog.nc"
    if kind == "symlink":
        link.symlink_to(cl)
    else:
        os.link(cl, link)
    with pytest.raises(api.CLError) as caught:
        api.post_file("vmc500", cl, link)
    assert "it is the CL program being posted" in caught.value.message
    assert cl.read_bytes() == PROGRAM.read_bytes()


def test_the_output_cannot_be_the_post(tmp_path: Path) -> None:
    post = tmp_path / "mill.yaml"
    post.write_bytes((ROOT / "machines" / "vmc500.yaml").read_bytes())
    with pytest.raises(api.CLError) as caught:
        api.post_file(post, PROGRAM, post)
    assert "it is the post" in caught.value.message
    assert post.read_bytes() == (ROOT / "machines" / "vmc500.yaml").read_bytes()


def test_temporary_files_are_named_so_they_can_be_found(tmp_path: Path, monkeypatch) -> None:
    seen: list[str] = []
    replace = os.replace

    def spy(source: str, target: str) -> None:
        seen.append(Path(source).name)
        replace(source, target)

    monkeypatch.setattr(writer.os, "replace", spy)
    writer.write_atomic(tmp_path / "prog.nc", "G0\n")
    assert len(seen) == 1 and writer.is_temporary_of(seen[0], "prog.nc")
    assert seen[0].startswith(".prog.nc.postdsl-") and seen[0].endswith(".tmp")


def test_a_later_write_removes_only_its_own_stale_temporary_files(tmp_path: Path) -> None:
    old = time.time() - 2 * writer.STALE_AFTER
    stale = tmp_path / f".prog.nc.postdsl-{os.getpid() + 1}-abcd1234.tmp"
    fresh = tmp_path / ".prog.nc.postdsl-77-efgh5678.tmp"
    other_program = tmp_path / ".other.nc.postdsl-77-ijkl9012.tmp"
    someone_elses = tmp_path / ".prog.nc.x1y2z3.tmp"
    for path in (stale, fresh, other_program, someone_elses):
        path.write_text("partial", encoding="utf-8")
    for path in (stale, other_program, someone_elses):
        os.utime(path, (old, old))
    writer.write_atomic(tmp_path / "prog.nc", "G0\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["prog.nc", fresh.name, other_program.name, someone_elses.name])


@posix
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_during_the_write_leaves_no_temporary_file(tmp_path: Path,
                                                            signum: int) -> None:
    target = tmp_path / "prog.nc"
    target.write_text("previous program\n", encoding="utf-8")
    script = (
        "import os, sys, time\n"
        "from postdsl.run import writer\n"
        "def slow(fd):\n"
        "    print('writing', flush=True)\n"
        "    time.sleep(30)\n"
        "writer.os.fsync = slow\n"
        f"writer.write_atomic({str(target)!r}, 'G0 X1\\n' * 1000)\n"
    )
    process = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, cwd=ROOT)
    assert process.stdout is not None
    assert process.stdout.readline().strip() == "writing"
    process.send_signal(signum)
    process.wait(timeout=20)
    assert process.returncode != 0
    assert [p.name for p in tmp_path.iterdir()] == ["prog.nc"]
    assert target.read_text(encoding="utf-8") == "previous program\n"


def test_a_target_named_with_control_characters_is_named_escaped(tmp_path: Path) -> None:
    target = tmp_path / "missing\x1b[2J\n" / "prog.nc"
    result = run("post", "vmc500", str(PROGRAM), "-o", str(target))
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and "\x1b" not in result.stderr
    assert "missing\\x1b[2J\\n/prog.nc: cannot write the NC program" in result.stderr
