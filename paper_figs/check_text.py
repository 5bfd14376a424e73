#!/usr/bin/python3
"""Measures the text of the figures a figure script writes, for the paper's 7 in text width.

usage: check_text.py SCRIPT.py [ARGS ...]

Runs SCRIPT.py with ARGS in this process (the same command line scripts/main.sh gives it) and,
for every PNG it saves, prints one line:

    NAME  fig W in  saved W in  min P pt (at 7 in: Q)  footnote F pt  overlaps N  legend/data L
    clipped C

- saved W: the PNG's width in pixels / the dpi it was saved at (what bbox_inches leaves);
- min P: the smallest font size of any text drawn, the footnote apart; "at 7 in" is that size
  once a wider figure is scaled to 7 in;
- footnote F: the machine / commit / date line (a Text with gid "footnote", see figsetup.py;
  older scripts' footnotes are recognised by their "commit:" field);
- overlaps N: pairs of drawn texts whose boxes intersect (listed below the line);
- legend/data L: data points (line vertices, scatter points, bar tops) inside a legend's box;
- clipped C: texts reaching outside the saved image.

Only texts that are drawn count (a tick label outside the axis limits is not drawn). Exit
status: the script's own; 1 when a limit is broken (width > 7.0 in, text < 7 pt, footnote
< 6 pt, an overlap, a legend over data, a clipped text), so it can serve as a test.
"""

import os
import re
import runpy
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figsetup  # noqa: E402

import matplotlib.figure  # noqa: E402
import matplotlib.legend  # noqa: E402
import matplotlib.text  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PathCollection  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

# texts and legends of the figure's latest draw (savefig with bbox_inches draws more than once)
drawn = {"texts": [], "legends": [], "points": None}
failed = []


def is_footnote(t):
    return t.get_gid() == figsetup.FOOTNOTE_GID or "commit:" in t.get_text().lower()


def hook_drawing():
    text_draw, legend_draw, figure_draw = (matplotlib.text.Text.draw,
                                           matplotlib.legend.Legend.draw,
                                           matplotlib.figure.Figure.draw)

    def on_text(self, renderer):
        text_draw(self, renderer)
        if self.get_visible() and self.get_text().strip():
            # the text's own box: an Annotation's would include its arrow
            box = matplotlib.text.Text.get_window_extent(self, renderer)
            drawn["texts"].append((self, box))

    def on_legend(self, renderer):
        legend_draw(self, renderer)
        if self.get_visible():
            drawn["legends"].append((self, self.get_window_extent(renderer)))

    def on_figure(self, renderer):
        drawn["texts"].clear()
        drawn["legends"].clear()
        figure_draw(self, renderer)
        # now, while the figure has the dpi it is saved at (the legends' boxes are in it)
        drawn["points"] = data_points(self)

    matplotlib.text.Text.draw = on_text
    matplotlib.legend.Legend.draw = on_legend
    matplotlib.figure.Figure.draw = on_figure


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    return struct.unpack(">II", head[16:24])


def data_points(fig):
    """Display coordinates of the data of every 2D axes, those inside the axes only."""
    pts = []
    for ax in fig.axes:
        if ax.name != "rectilinear":
            continue
        mine = []
        for line in ax.lines:
            xy = line.get_xydata()
            if len(xy):
                mine.append(line.get_transform().transform(xy))
        for c in ax.collections:
            if isinstance(c, PathCollection) and len(c.get_offsets()):
                mine.append(c.get_offset_transform().transform(c.get_offsets()))
        for p in ax.patches:
            if isinstance(p, Rectangle) and p.get_height() != 0:
                b = p.get_window_extent()
                mine.append(np.array([[b.x0, b.y1], [0.5 * (b.x0 + b.x1), b.y1], [b.x1, b.y1]]))
        box = ax.bbox
        pts += [p[(p[:, 0] >= box.x0) & (p[:, 0] <= box.x1) & (p[:, 1] >= box.y0)
                  & (p[:, 1] <= box.y1)] for p in mine]
    return np.concatenate(pts) if pts else np.zeros((0, 2))


def report(fig, path, dpi):
    w_px, h_px = png_size(path)
    saved_w = w_px / dpi
    texts = drawn["texts"]
    body = [t.get_fontsize() for t, _ in texts if not is_footnote(t)]
    foot = [t.get_fontsize() for t, _ in texts if is_footnote(t)]
    overlaps = []
    for i in range(len(texts)):
        for j in range(i + 1, len(texts)):
            a, b = texts[i][1], texts[j][1]
            # half a pixel of tolerance: touching boxes of adjacent tick labels are fine
            if (min(a.x1, b.x1) - max(a.x0, b.x0) > 0.5
                    and min(a.y1, b.y1) - max(a.y0, b.y0) > 0.5):
                overlaps.append((texts[i][0].get_text(), texts[j][0].get_text()))
    clipped = [t.get_text() for t, b in texts
               if b.x0 < -0.5 or b.y0 < -0.5 or b.x1 > w_px + 0.5 or b.y1 > h_px + 0.5]
    pts = drawn["points"]
    covered = sum(int(np.sum((pts[:, 0] >= b.x0) & (pts[:, 0] <= b.x1) & (pts[:, 1] >= b.y0)
                             & (pts[:, 1] <= b.y1))) for _, b in drawn["legends"])
    low = min(body) if body else float("nan")
    at7 = low * min(1.0, figsetup.TEXT_WIDTH / saved_w)
    fpt = min(foot) if foot else float("nan")
    print(f"{os.path.basename(path):28s} fig {fig.get_figwidth():5.2f} in  saved {saved_w:5.2f}"
          f" in  min {low:4.1f} pt (at 7 in: {at7:4.1f})  footnote {fpt:4.1f} pt  overlaps "
          f"{len(overlaps)}  legend/data {covered}  clipped {len(clipped)}")
    for a, b in overlaps:
        print(f"    overlap: {a[:50]!r} / {b[:50]!r}")
    for t in clipped:
        print(f"    clipped: {t[:60]!r}")
    if (saved_w > figsetup.TEXT_WIDTH + 0.005 or low < figsetup.MIN_PT or overlaps or covered
            or clipped or (foot and fpt < figsetup.MIN_FOOTNOTE_PT)):
        failed.append(path)


def hook_saving():
    savefig = matplotlib.figure.Figure.savefig

    def on_save(self, fname, *args, **kw):
        savefig(self, fname, *args, **kw)
        if str(fname).lower().endswith(".png"):
            dpi = kw.get("dpi", "figure")
            report(self, str(fname), self.dpi if dpi == "figure" else float(dpi))

    matplotlib.figure.Figure.savefig = on_save


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help") or not re.search(r"\.py$", argv[1]):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    hook_drawing()
    hook_saving()
    sys.argv = argv[1:]
    status = 0
    try:
        runpy.run_path(argv[1], run_name="__main__")
    except SystemExit as e:
        status = e.code if isinstance(e.code, int) else (0 if e.code is None else 1)
    return status or (1 if failed else 0)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
