"""`postdsl plot` and the SVG picture: views, styles, escaping, determinism, errors."""

from __future__ import annotations

import itertools
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from click.testing import CliRunner

from postdsl import api
from postdsl.check.svgplot import nice_length, render_svg
from postdsl.check.toolpath import Segment, Toolpath
from postdsl.cli import main
from tests.conftest import EXAMPLES
from tests.test_toolpath import write_square

SVG = "{http://www.w3.org/2000/svg}"


def plot(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["plot", *args])
    return result.exit_code, result.output


def square_path() -> Toolpath:
    corners = [(0.0, 0.0, -1.0), (10.0, 0.0, -1.0), (10.0, 10.0, -1.0), (0.0, 10.0, -1.0),
               (0.0, 0.0, -1.0)]
    feeds = [Segment("feed", (a, b), n + 3, "linear_move", "linear_move", n)
             for n, (a, b) in enumerate(itertools.pairwise(corners))]
    return Toolpath([Segment("rapid", ((0.0, 0.0, 20.0), (0.0, 0.0, 2.0)), 2), *feeds,
                     Segment("hole", ((5.0, 5.0, 2.0), (5.0, 5.0, -8.0), (5.0, 5.0, 2.0)), 9)])


def panels(root: ET.Element) -> list[ET.Element]:
    return [g for g in root.findall(f"{SVG}g") if g.get("transform", "").startswith("translate(")
            and g.find(f"{SVG}rect") is not None]


def test_the_square_from_above() -> None:
    root = ET.fromstring(render_svg(square_path(), ["xy"]))
    (panel,) = panels(root)
    feed = panel.find(f"{SVG}path[@class='feed']")
    assert feed is not None and feed.get("stroke-dasharray") is None
    # one connected outline: a move to the first corner and four lines, closing on itself
    commands = re.findall(r"([ML])(\S+) (\S+)", feed.get("d", ""))
    assert [c[0] for c in commands] == ["M", "L", "L", "L", "L"]
    xs = sorted({float(c[1]) for c in commands})
    ys = sorted({float(c[2]) for c in commands})
    assert len(xs) == len(ys) == 2 and xs[1] - xs[0] == pytest.approx(ys[1] - ys[0])
    assert commands[0][1:] == commands[-1][1:]
    # Y up: the second corner (X10 Y0) is right of the first at the same height
    assert float(commands[1][1]) > float(commands[0][1]) and commands[1][2] == commands[0][2]
    # the rapid is a Z move, seen end-on from above: nothing to draw
    assert panel.find(f"{SVG}path[@class='rapid']") is None
    # the hole is ringed at its position, in the middle of the square
    ring = panel.find(f"{SVG}circle[@class='hole-mark']")
    assert ring is not None
    assert float(ring.get("cx", "")) == pytest.approx((xs[0] + xs[1]) / 2)


def test_the_side_views_show_rapids_dashed_and_the_hole_depth() -> None:
    root = ET.fromstring(render_svg(square_path()))
    assert len(panels(root)) == 3
    titles = [p.find(f"{SVG}text").text for p in panels(root)]  # type: ignore[union-attr]
    assert titles == ["XY (top)", "XZ (front)", "YZ (side)"]
    front = panels(root)[1]
    rapid = front.find(f"{SVG}path[@class='rapid']")
    assert rapid is not None and rapid.get("stroke-dasharray")
    hole = front.find(f"{SVG}path[@class='hole']")
    assert hole is not None
    ys = [float(y) for y in re.findall(r"[ML]\S+ (\S+)", hole.get("d", ""))]
    assert ys[1] > ys[0]  # down to the bottom (SVG y grows downwards) and back
    scale = front.find(f"{SVG}g[@class='scale']")
    assert scale is not None and scale.find(f"{SVG}text").text.endswith(" mm")  # type: ignore[union-attr]


def test_text_in_the_picture_is_escaped_and_output_is_deterministic() -> None:
    title = 'a <b> & "c" ]]>'
    text = render_svg(square_path(), title=title)
    root = ET.fromstring(text)
    assert root.find(f"{SVG}title").text == title  # type: ignore[union-attr]
    assert render_svg(square_path(), title=title) == text


def test_an_empty_path_says_so() -> None:
    root = ET.fromstring(render_svg(Toolpath([])))
    assert any(t.text == "no motion to draw" for t in root.iter(f"{SVG}text"))


@pytest.mark.parametrize(("span", "length"), [(100, 20), (36, 5), (0.4, 0.1), (1000, 200)])
def test_nice_length(span: float, length: float) -> None:
    assert nice_length(span) == pytest.approx(length)


def test_plot_writes_the_picture(tmp_path: Path) -> None:
    out = tmp_path / "pocket.svg"
    status, output = plot("emco", str(EXAMPLES / "emco_pocket.gcode"), "-o", str(out))
    assert status == 0, output
    assert "moves drawn (5 holes)" in output
    root = ET.fromstring(out.read_text())
    assert len(panels(root)) == 3
    assert len(root.findall(f".//{SVG}circle[@class='hole-mark']")) == 15  # 5 holes × 3 views
    assert not list(tmp_path.glob(".*.tmp"))


def test_plot_views_are_chosen(tmp_path: Path) -> None:
    out = tmp_path / "square.svg"
    status, output = plot("vmc500", str(write_square(tmp_path)), "-o", str(out), "--view",
                          "iso", "--view", "xy", "--view", "xy")
    assert status == 0, output
    titles = [p.find(f"{SVG}text").text  # type: ignore[union-attr]
              for p in panels(ET.fromstring(out.read_text()))]
    assert titles == ["isometric (no scale)", "XY (top)"]


def test_plot_into_a_missing_folder_is_a_message(tmp_path: Path) -> None:
    status, output = plot("vmc500", str(write_square(tmp_path)), "-o",
                          str(tmp_path / "nope" / "a.svg"))
    assert status == 2
    assert "cannot write the picture: the folder" in output and "Traceback" not in output


def test_plot_never_overwrites_its_input(tmp_path: Path) -> None:
    cl = write_square(tmp_path)
    before = cl.read_text()
    status, output = plot("vmc500", str(cl), "-o", str(cl))
    assert status == 2 and "cannot write the picture" in output
    assert cl.read_text() == before


def test_plot_stops_where_the_control_refuses(tmp_path: Path) -> None:
    post = tmp_path / "broken.yaml"
    text = Path(api.load_post("vmc500").file).read_text()
    # a linear move written with a word the control does not know
    assert '{text: " G1", modal: motion}' in text
    post.write_text(text.replace('{text: " G1", modal: motion}',
                                 '{text: " G1 Q7", modal: motion}', 1))
    out = tmp_path / "broken.svg"
    status, output = plot(str(post), str(write_square(tmp_path)), "-o", str(out))
    assert status == 4
    assert "the control model stops at NC line" in output
    assert "the control model stops here" in out.read_text()


def test_each_panel_names_its_axes() -> None:
    root = ET.fromstring(render_svg(square_path(), ["xy", "yz", "iso"]))
    names = []
    for panel in panels(root):
        axes = panel.find(f"{SVG}g[@class='axes']")
        assert axes is not None
        names.append([t.text for t in axes.iter(f"{SVG}text")])
    assert names == [["X", "Y"], ["Y", "Z"], ["X", "Y", "Z"]]
    # an isometric view has no single scale: no bar in it
    assert [p.find(f"{SVG}g[@class='scale']") is not None for p in panels(root)] == \
        [True, True, False]


def test_plot_of_a_3plus2_program_counts_its_moves_and_names_the_tilted_axes(
        tmp_path: Path) -> None:
    """The tool axis lines are directions, not moves: counted apart; verify passes."""
    out = tmp_path / "tilted.svg"
    status, output = plot("fanuc_3plus2", str(EXAMPLES / "tilted_planes.jsonl"), "-o", str(out))
    assert status == 0, output
    assert "22 moves drawn (2 holes, the tool axis of 2 tilted planes)" in output
    root = ET.fromstring(out.read_text())
    assert len(root.findall(f".//{SVG}circle[@class='axis-tip']")) == 6  # 2 planes × 3 views
