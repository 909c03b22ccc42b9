"""`post -o` on hostile targets: a whole program or a located error, and nothing else changed.

Each case makes a fresh folder holding the CL program and one target of a hostile kind
(a FIFO nobody reads, a device node, a folder, links to the input, to a folder or to
nowhere, a read-only folder, names with control characters or too long for the file
system), posts a good or a broken program to it, and checks what a machinist relies on:
the target is a complete program or is as it was, a non-regular file is never replaced,
the CL program is never touched, and no temporary file is left behind.
"""

from __future__ import annotations

import os
import stat
import tempfile
from functools import cache
from pathlib import Path
from unittest.mock import patch

import pytest
from hypothesis import given
from hypothesis import strategies as st

from postdsl import api
from tests.conftest import EXAMPLES, THESIS_EPOCH

pytestmark = [pytest.mark.fuzz,
              pytest.mark.skipif(os.name != "posix", reason="FIFOs, device nodes, links")]

GOOD = (EXAMPLES / "vmc500_cycles.jsonl").read_text(encoding="utf-8")
BROKEN = GOOD.replace('"cmd": "rapid_move"', '"cmd": "rapid_move", "x": "forty"', 1)

KINDS = ["missing", "regular", "fifo", "device", "folder", "link_to_input", "hardlink_to_input",
         "link_to_regular", "link_to_folder", "dangling_link", "read_only_folder", "dot",
         "dotdot"]
NAMES = st.one_of(
    st.sampled_from(["prog.nc", "-o", " ", "prog\n.nc", "prog\r.nc", "\x1b[31m.nc", "é.nc",
                     "a" * 300, ".prog.nc.postdsl-1-x.tmp", "prog.nc.tmp"]),
    st.text(alphabet=st.characters(blacklist_characters="/\x00",
                                   blacklist_categories=("Cs",)), min_size=1, max_size=40)
    .filter(lambda n: n not in (".", "..")),
)


def _make(folder: Path, kind: str, name: str, cl: Path) -> Path:
    """The target of one case, made in ``folder``."""
    target = folder / name
    if kind == "regular":
        target.write_text("previous program\n", encoding="utf-8")
    elif kind == "fifo":
        os.mkfifo(target)
    elif kind == "device":
        if os.geteuid() != 0:
            os.mkfifo(target)  # device nodes need root; a FIFO is the nearest kind
        else:
            os.mknod(target, 0o600 | stat.S_IFCHR, os.makedev(1, 3))
    elif kind == "folder":
        target.mkdir()
    elif kind == "link_to_input":
        target.symlink_to(cl)
    elif kind == "hardlink_to_input":
        os.link(cl, target)
    elif kind == "link_to_regular":
        (folder / "elsewhere.nc").write_text("other program\n", encoding="utf-8")
        target.symlink_to(folder / "elsewhere.nc")
    elif kind == "link_to_folder":
        (folder / "sub").mkdir()
        target.symlink_to(folder / "sub")
    elif kind == "dangling_link":
        target.symlink_to(folder / "nowhere" / "prog.nc")
    elif kind == "read_only_folder":
        (folder / "locked").mkdir()
        (folder / "locked").chmod(0o555)
        target = folder / "locked" / name
    elif kind == "dot":
        target = folder / "."
    elif kind == "dotdot":
        target = folder / "sub" / ".."
        (folder / "sub").mkdir(exist_ok=True)
    return target


_load_post = api.load_post


@cache
def _post() -> api.CompiledPost:
    return _load_post("vmc500")


def _state(folder: Path) -> dict[str, tuple[int, bytes | None]]:
    """Every entry below ``folder``: its type and, for regular files, its content."""
    found: dict[str, tuple[int, bytes | None]] = {}
    for root, dirs, files in os.walk(folder):
        for entry in dirs + files:
            path = Path(root) / entry
            mode = path.lstat().st_mode
            content = path.read_bytes() if stat.S_ISREG(mode) else None
            found[str(path.relative_to(folder))] = (stat.S_IFMT(mode), content)
    return found


@given(kind=st.sampled_from(KINDS), name=NAMES, broken=st.booleans())
def test_post_o_on_hostile_targets(kind: str, name: str, broken: bool) -> None:
    os.environ["SOURCE_DATE_EPOCH"] = str(THESIS_EPOCH)
    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(temporary)
        cl = folder / "input.jsonl"
        cl.write_text(BROKEN if broken else GOOD, encoding="utf-8")
        try:
            target = _make(folder, kind, name, cl)
        except OSError:
            return  # the file system refuses the name itself (too long): nothing to test
        before = _state(folder)
        resolved = Path(os.path.realpath(target))
        try:
            # the post is loaded once, not for every example
            with patch.object(api, "load_post", lambda machine, options=None: _post()):
                text = api.post_file("vmc500", cl, target)
        except api.CLError as exc:
            assert exc.location is not None
            assert exc.location.file in (str(cl), str(target)), str(exc)
            assert _state(folder) == before, str(exc)  # nothing written, nothing left
            return
        finally:
            if kind == "read_only_folder":
                (folder / "locked").chmod(0o755)
        after = _state(folder)
        assert not broken
        assert stat.S_ISREG(resolved.lstat().st_mode)
        assert resolved.read_text(encoding="utf-8") == text
        assert cl.read_text(encoding="utf-8") == GOOD
        written = str(resolved.relative_to(folder))
        # only the target changed (or appeared); every other entry is as it was
        assert {k: v for k, v in after.items() if k != written} == \
            {k: v for k, v in before.items() if k != written}
        assert before.get(written, (stat.S_IFREG, None))[0] == stat.S_IFREG
