"""The editor's program preview is verified as ``postdsl post`` verifies.

The preview shows what ``post`` would write; a post edited into writing wrong NC says so
next to the lines (the program view's message), not only when the user posts.
"""

from __future__ import annotations

from datetime import UTC, datetime

from tests.conftest import EXAMPLES, MACHINES
from tui.posting import Job, Outcome, run_job

COORD_3 = "  coord:               # 40. / 16.996 : point always, trailing zeros trimmed\n" \
          "    decimals: 3\n"


def outcome(post_text: str) -> tuple[Outcome, int]:
    job = Job(post_text, str(MACHINES / "vmc500.yaml"), EXAMPLES / "emco_pocket.gcode",
              "emco_pocket.gcode", datetime(2021, 1, 22, tzinfo=UTC))
    lines, last = 0, None
    for message in run_job(job, lambda: False):
        if isinstance(message, Outcome):
            last = message
        else:
            lines += len(message[0])
    assert last is not None
    return last, lines


def test_the_bundled_post_previews_verified() -> None:
    text = (MACHINES / "vmc500.yaml").read_text(encoding="utf-8")
    result, lines = outcome(text)
    assert result.error is None and lines > 20


def test_a_post_writing_wrong_nc_says_so_beside_its_lines() -> None:
    text = (MACHINES / "vmc500.yaml").read_text(encoding="utf-8")
    assert COORD_3 in text
    result, lines = outcome(text.replace(COORD_3, COORD_3.replace("decimals: 3",
                                                                  "decimals: 0")))
    assert lines > 20  # the program is still shown
    assert result.error is not None
    assert result.error.startswith("postdsl post refuses this program:")
    assert "CL says" in result.error
