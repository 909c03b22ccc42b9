"""A toolpath as an SVG picture: plain text, built with the standard library, deterministic.

One panel per view (XY from above, XZ from the front, YZ from the side, or
an isometric view), side by side at one common scale so lengths compare
across panels.  Rapids are dashed grey, feeds solid blue, holes red with a
ring at the bottom of each, a tilted tool axis (3+2) green with a dot at the
tip; every panel has its axis names, the program zero axes where they fall
inside the picture, and a scale bar.  Numbers are written with two decimals
and elements in program order, so the same path always gives the same bytes
(snapshots and diffs of pictures work).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from xml.sax.saxutils import escape

from postdsl.check.toolpath import VIEW_AXES, XYZ, Segment, Toolpath, projector

#: the largest side of the largest panel's drawing, px
DRAWING = 360.0
MARGIN = 36.0
TITLE = 28.0

STYLE = {
    "rapid": 'fill="none" stroke="#8a8a8a" stroke-width="0.8" stroke-dasharray="4 3"',
    "feed": 'fill="none" stroke="#1f5fbf" stroke-width="1.2"',
    "hole": 'fill="none" stroke="#c0392b" stroke-width="1.2"',
    "axis": 'fill="none" stroke="#2e8b57" stroke-width="1.6"',
}
VIEW_TITLES = {"xy": "XY (top)", "xz": "XZ (front)", "yz": "YZ (side)",
               "iso": "isometric (no scale)"}
ALL_VIEWS = ("xy", "xz", "yz")


def _num(value: float) -> str:
    text = f"{value:.2f}"
    return "0.00" if text == "-0.00" else text


def _coord(value: float) -> str:
    """A path coordinate, to a tenth of a pixel: points closer than that merge.

    A finely flattened arc has many points per pixel; a tenth keeps the
    picture exact to the eye and a 200 000-move program's file small.
    """
    text = f"{value:.1f}"
    return "0.0" if text == "-0.0" else text


def nice_length(span: float) -> float:
    """A round length (1, 2 or 5 times a power of ten) of about a quarter of ``span`` mm."""
    target = max(span / 4, 1e-6)
    power: float = 10 ** math.floor(math.log10(target))
    for factor in (5, 2, 1):
        if factor * power <= target:
            return factor * power
    return power


class _Frame:
    """A view's extent in mm and the mapping of mm to panel pixels (y grows downwards)."""

    def __init__(self, view: str, segments: Sequence[Segment]) -> None:
        self.view = view
        self.project: Callable[[XYZ], tuple[float, float]] = projector(view)
        hs: list[float] = []
        vs: list[float] = []
        for segment in segments:
            for point in segment.points:
                h, v = self.project(point)
                hs.append(h)
                vs.append(v)
        self.h0, self.h1 = (min(hs), max(hs)) if hs else (0.0, 1.0)
        self.v0, self.v1 = (min(vs), max(vs)) if vs else (0.0, 1.0)

    def widen(self, least: float) -> None:
        """Give a flat extent (every hole at one Y) some room, centred on it."""
        for lo, hi in (("h0", "h1"), ("v0", "v1")):
            a, b = getattr(self, lo), getattr(self, hi)
            if b - a < least:
                middle = (a + b) / 2
                setattr(self, lo, middle - least / 2)
                setattr(self, hi, middle + least / 2)

    @property
    def span(self) -> float:
        return max(self.h1 - self.h0, self.v1 - self.v0)

    def size(self, scale: float) -> tuple[float, float]:
        return ((self.h1 - self.h0) * scale + 2 * MARGIN,
                (self.v1 - self.v0) * scale + 2 * MARGIN + TITLE)

    def px(self, h: float, v: float, scale: float) -> tuple[float, float]:
        return (MARGIN + (h - self.h0) * scale, TITLE + MARGIN + (self.v1 - v) * scale)


def _path_data(frame: _Frame, segments: Sequence[Segment], kind: str, scale: float) -> str:
    """One SVG path for every segment of a kind: joined where one ends where the next starts."""
    parts: list[str] = []
    last: tuple[str, str] | None = None
    for segment in segments:
        if segment.kind != kind:
            continue
        seen: list[tuple[str, str]] = []
        for point in segment.points:
            x, y = frame.px(*frame.project(point), scale)
            here = (_coord(x), _coord(y))
            if not seen or here != seen[-1]:
                seen.append(here)
        if len(seen) < 2:
            continue  # a move along the line of sight (a Z move seen from above)
        if seen[0] != last:
            parts.append(f"M{seen[0][0]} {seen[0][1]}")
        parts += [f"L{x} {y}" for x, y in seen[1:]]
        last = seen[-1]
    return " ".join(parts)


def _panel(frame: _Frame, segments: Sequence[Segment], scale: float, left: float) -> list[str]:
    width, height = frame.size(scale)
    h_name, v_name = VIEW_AXES[frame.view]  # ("", "Z") for iso, which names its own
    out = [f'<g transform="translate({_num(left)} 0)">',
           f'<rect x="0.50" y="0.50" width="{_num(width - 1)}" height="{_num(height - 1)}" '
           f'fill="#ffffff" stroke="#cccccc"/>',
           f'<text x="{_num(MARGIN)}" y="18" font-size="13">'
           f'{escape(VIEW_TITLES[frame.view])}</text>']
    # the program zero's axes, where they cross the picture
    if frame.view != "iso":
        top, bottom = TITLE + MARGIN, height - MARGIN
        if frame.h0 <= 0 <= frame.h1:
            x, _ = frame.px(0, 0, scale)
            out.append(f'<line x1="{_num(x)}" y1="{_num(top)}" x2="{_num(x)}" '
                       f'y2="{_num(bottom)}" stroke="#e0e0e0"/>')
        if frame.v0 <= 0 <= frame.v1:
            _, y = frame.px(0, 0, scale)
            out.append(f'<line x1="{_num(MARGIN)}" y1="{_num(y)}" x2="{_num(width - MARGIN)}" '
                       f'y2="{_num(y)}" stroke="#e0e0e0"/>')
    for kind in ("rapid", "feed", "hole", "axis"):
        data = _path_data(frame, segments, kind, scale)
        if data:
            out.append(f'<path class="{kind}" {STYLE[kind]} d="{data}"/>')
    for segment in segments:  # a ring at the bottom of every hole
        if segment.kind == "hole":
            x, y = frame.px(*frame.project(segment.points[1]), scale)
            out.append(f'<circle class="hole-mark" cx="{_num(x)}" cy="{_num(y)}" r="3" '
                       f'fill="none" stroke="#c0392b"/>')
    for segment in segments:  # a dot where a tilted tool axis stands on the tip
        if segment.kind == "axis":
            x, y = frame.px(*frame.project(segment.points[0]), scale)
            out.append(f'<circle class="axis-tip" cx="{_num(x)}" cy="{_num(y)}" r="2" '
                       f'fill="#2e8b57"/>')
    # axis arrows in the lower left corner, named
    ox, oy = 10.0, height - 10.0
    if frame.view == "iso":  # X to the upper right, Y to the upper left, Z up, as drawn
        ox += 18
        directions = [("X", 0.866, -0.5), ("Y", -0.866, -0.5), ("Z", 0.0, -1.0)]
    else:
        directions = [(h_name, 1.0, 0.0), (v_name, 0.0, -1.0)]
    out.append('<g class="axes" stroke="#333333" font-size="10">')
    for name, dx, dy in directions:
        out += [f'<line x1="{_num(ox)}" y1="{_num(oy)}" x2="{_num(ox + 20 * dx)}" '
                f'y2="{_num(oy + 20 * dy)}"/>',
                f'<text x="{_num(ox + 24 * dx - 3)}" y="{_num(oy + 24 * dy + 3)}" '
                f'stroke="none">{name}</text>']
    out.append("</g>")
    if frame.view == "iso":
        return [*out, "</g>"]  # lengths in an isometric view depend on the direction: no bar
    # the scale bar, lower right
    length = nice_length(frame.h1 - frame.h0)
    bar = length * scale
    x1, y = width - MARGIN, height - 12.0
    out += [f'<g class="scale" stroke="#333333" font-size="10">'
            f'<line x1="{_num(x1 - bar)}" y1="{_num(y)}" x2="{_num(x1)}" y2="{_num(y)}"/>'
            f'<line x1="{_num(x1 - bar)}" y1="{_num(y - 3)}" x2="{_num(x1 - bar)}" '
            f'y2="{_num(y + 3)}"/>'
            f'<line x1="{_num(x1)}" y1="{_num(y - 3)}" x2="{_num(x1)}" y2="{_num(y + 3)}"/>'
            f'<text x="{_num(x1 - bar)}" y="{_num(y - 5)}" stroke="none">{length:g} mm</text>'
            f'</g>', "</g>"]
    return out


def render_svg(path: Toolpath, views: Sequence[str] = ALL_VIEWS, title: str = "") -> str:
    """The toolpath drawn in each view, side by side, as SVG text."""
    segments = path.segments
    frames = [_Frame(view, segments) for view in views]
    largest = max((f.span for f in frames), default=1.0) or 1.0
    for frame in frames:
        frame.widen(largest / 20)
    scale = DRAWING / max(f.span for f in frames)
    sizes = [f.size(scale) for f in frames]
    gap = 12.0
    # at least as wide as the legend line and its title
    width = max(sum(w for w, _ in sizes) + gap * (len(sizes) - 1), 240.0 + 7.0 * len(title))
    height = max(h for _, h in sizes) + 40.0
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           f'<svg xmlns="http://www.w3.org/2000/svg" width="{_num(width)}" '
           f'height="{_num(height)}" viewBox="0 0 {_num(width)} {_num(height)}" '
           f'font-family="sans-serif">']
    if title:
        out.append(f"<title>{escape(title)}</title>")
    left = 0.0
    for frame, (w, _) in zip(frames, sizes, strict=True):
        out += _panel(frame, segments, scale, left)
        left += w + gap
    legend_y = height - 22.0
    out += [f'<g font-size="11" transform="translate(4 {_num(legend_y)})">',
            f'<line x1="0" y1="0" x2="24" y2="0" {STYLE["rapid"]}/>'
            '<text x="28" y="4">rapid</text>',
            f'<line x1="70" y1="0" x2="94" y2="0" {STYLE["feed"]}/>'
            '<text x="98" y="4">feed</text>',
            '<circle cx="138" cy="0" r="3" fill="none" stroke="#c0392b"/>'
            '<text x="145" y="4">hole bottom</text>']
    title_x = 230
    if any(s.kind == "axis" for s in segments):  # only a 3+2 program has one to name
        out.append(f'<line x1="230" y1="0" x2="254" y2="0" {STYLE["axis"]}/>'
                   '<text x="258" y="4">tool axis</text>')
        title_x = 320
    if title:
        out.append(f'<text x="{title_x}" y="4">{escape(title)}</text>')
    out.append("</g>")
    note = "no motion to draw" if not segments else ""
    if path.stopped is not None:
        note = f"the control model stops here: {path.stopped}"
    if note:
        out.append(f'<text x="4" y="{_num(height - 4)}" font-size="11" fill="#c0392b">'
                   f"{escape(note)}</text>")
    out.append("</svg>")
    return "\n".join(out) + "\n"


__all__ = ["ALL_VIEWS", "nice_length", "render_svg"]
