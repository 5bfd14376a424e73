"""Matplotlib for the figure scripts: imported before pyplot, it gives matplotlib a private
config folder (removed at exit: one per run was left in /tmp before) unless MPLCONFIGDIR is set,
and selects the Agg backend, so the scripts run without a display or a writable home.

It also holds what every figure shares, so that one number changes them all: the paper's text
width (no figure is wider: it is placed at 100 %, so a point in the script is a point on the
page), the font sizes (set as matplotlib's defaults by importing this module), the PNG
resolution, the footnote (machine, commit, date) and the layout-and-save step. check_text.py
measures the figures against TEXT_WIDTH, MIN_PT and MIN_FOOTNOTE_PT.
"""

import atexit
import math
import os
import shutil
import tempfile
import textwrap

if "MPLCONFIGDIR" not in os.environ:
    _config = tempfile.mkdtemp(prefix="pgt_mpl_")
    atexit.register(shutil.rmtree, _config, True)
    os.environ["MPLCONFIGDIR"] = _config

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

# The paper's text width, the widest a figure may be (figsize width); a figure that needs more
# room grows in height (panels stacked) instead.
TEXT_WIDTH = 7.0  # in
# Font sizes in points at that width: axis labels and panel titles, the figure's title, and the
# smaller text (tick labels, legends, bar labels, annotations), which is the smallest allowed.
TEXT_PT = 8.0
TITLE_PT = 9.0
SMALL_PT = 7.0
FOOTNOTE_PT = 6.5
# The limits check_text.py holds the figures to (the footnote may be smaller than the rest).
MIN_PT = 7.0
MIN_FOOTNOTE_PT = 6.0
FOOTNOTE_GID = "footnote"  # how check_text.py tells the footnote from the other text
# PNG resolution: 300 dpi keeps the image panels (1000-2560 px renders) sharp at 7 in; the PDFs
# embed images at their own resolution whatever this is.
DPI = 300

plt.rcParams.update({
    "font.size": TEXT_PT, "axes.titlesize": TEXT_PT, "axes.labelsize": TEXT_PT,
    "figure.titlesize": TITLE_PT, "xtick.labelsize": SMALL_PT, "ytick.labelsize": SMALL_PT,
    "legend.fontsize": SMALL_PT, "legend.title_fontsize": SMALL_PT,
    "pdf.fonttype": 42, "ps.fonttype": 42,  # TrueType in the PDF: text stays text
})


def footnote(fig, text):
    """The machine / commit / date line at the bottom left, marked for check_text.py; broken
    into lines that fit the figure's width (a long machine name ran off the page): first at
    wrap()'s estimate of characters per line, then, measured as drawn, at fewer until the
    widest line fits (capitals and digits are wider than the estimate's average)."""
    room = 0.99 * fig.get_figwidth()
    chars = max(int(room * 72 / (0.55 * FOOTNOTE_PT)), 16)
    t = fig.text(0.005, 0.005, textwrap.fill(text, chars, break_on_hyphens=False),
                 fontsize=FOOTNOTE_PT, color="0.3", ha="left", va="bottom", gid=FOOTNOTE_GID)
    renderer = fig.canvas.get_renderer()
    while chars > 16 and t.get_window_extent(renderer).width > (room - 0.005) * fig.dpi:
        chars = max(int(chars * 0.9), 16)
        t.set_text(textwrap.fill(text, chars, break_on_hyphens=False))
    return t


def suptitle(fig, text):
    """The figure's title, centred at the top, as a plain figure text for layout() to keep room
    for (matplotlib's fig.suptitle gets room from tight_layout too: twice the room, then)."""
    return fig.text(0.5, 1.0 - 0.03 / fig.get_figheight(), text, fontsize=TITLE_PT,
                    ha="center", va="top")


def layout(fig, foot=None, title=None, top=1.0, **kw):
    """tight_layout over the figure minus the footnote's height at the bottom and the title's
    at the top (figure texts that tight_layout does not see), and below top (a fraction of the
    height: room for what tight_layout misses, e.g. a 3D axes' title). kw (h_pad, w_pad) go to
    tight_layout."""
    bottom = 0.0
    if foot is not None or title is not None:
        fig.canvas.draw()
        gap = 0.04 * fig.dpi  # pixels
        if foot is not None:
            bottom = (foot.get_window_extent().y1 + gap) / fig.bbox.height
        if title is not None:
            top = min(top, (title.get_window_extent().y0 - gap) / fig.bbox.height)
    fig.tight_layout(pad=0.3, rect=(0, bottom, 1, top), **kw)


def wrap(text, width, pt=TEXT_PT):
    """text broken into lines that fit width inches at pt points: DejaVu Sans averages about
    0.55 em per character. No breaks at hyphens: "--city" and "self-shadowing" stay whole."""
    return textwrap.fill(text, max(int(width * 72 / (0.55 * pt)), 16), break_on_hyphens=False)


def image_grid(shapes, titles, cols, title=None):
    """A figure TEXT_WIDTH wide for images of shapes (rows, columns, ...) in rows of cols, each
    under its title wrapped to the panel's width; its height is what the images need at that
    width (a figure with more panels grows down, never wider). Returns (fig, axes, title text
    or None); the caller draws the images and calls layout(fig, title=...)."""
    n = len(shapes)
    rows = math.ceil(n / cols)
    pw = TEXT_WIDTH / cols
    titles = [wrap(t, pw) for t in titles]
    # a title line with its leading, and the margin of a row (tight_layout's pads around each
    # panel, more than the images need)
    line, margin = 1.5 * TEXT_PT / 72, 0.2  # in
    height = 0.0
    for r in range(rows):
        row = range(r * cols, min(n, (r + 1) * cols))
        height += (max(shapes[i][0] / shapes[i][1] for i in row) * (pw - 0.1)
                   + max(titles[i].count("\n") + 1 for i in row) * line + margin)
    fig_title = None
    if title:
        title = wrap(title, TEXT_WIDTH, TITLE_PT)
        height += (title.count("\n") + 1) * 1.5 * TITLE_PT / 72 + 0.05
    fig, axes = plt.subplots(rows, cols, figsize=(TEXT_WIDTH, height), squeeze=False)
    for ax in axes.flat:
        ax.axis("off")
    for ax, t in zip(axes.flat, titles):
        ax.set_title(t, fontsize=TEXT_PT)
    if title:
        fig_title = suptitle(fig, title)
    return fig, list(axes.flat)[:n], fig_title


def fit_images(fig, axes, title=None):
    """layout() for an image_grid of images of one aspect (facade_panels.py's frames), at the
    least figure height where the images still fill their panels' width: an image keeps its
    aspect, so image_grid's estimate of the pads (generous: up to 0.2 in of blank per row)
    left blank under the images. The layout's pads do not scale with the height, so the height
    is found by bisection (a figure too low makes the images height-bound: narrower than their
    panels). Rows mixing tall and wide images (ivy_scenes.py) keep layout(): a height-bound
    image has no blank to remove there."""
    def width_bound(height):
        fig.set_figheight(height)
        layout(fig, title=title)
        fig.canvas.draw()
        return all(a.get_position().width >= a.get_position(original=True).width - 1e-6
                   for a in axes)
    hi = fig.get_figheight()
    if not width_bound(hi):  # the estimate was already short: keep it
        return
    lo = 0.5 * hi
    for _ in range(7):  # to 1/256 of the estimate (under 0.01 in)
        mid = 0.5 * (lo + hi)
        if width_bound(mid):
            hi = mid
        else:
            lo = mid
    width_bound(hi)


def save(fig, prefix, die, pdf_kw=None, before_pdf=None):
    """OUT_PREFIX.png at DPI and OUT_PREFIX.pdf (before_pdf() called between the two, e.g. to
    embed images unresampled); a failed write is die(message) (exit 2)."""
    try:
        fig.savefig(prefix + ".png", dpi=DPI)
        if before_pdf:
            before_pdf()
        fig.savefig(prefix + ".pdf", **(pdf_kw or {}))
    except OSError as e:
        die(f"{prefix}: {e.strerror}")
