#!/usr/bin/python3
"""Frames of `pgt facade` side by side with labels: the Fig. 1a-c panel of paper 003 now, and
the four levels of detail of its Fig. 11 (`pgt facade --detail`, main job step 18).

usage: facade_panels.py OUT_PREFIX FRAME TITLE [FRAME TITLE ...] [--columns C] [--title T]

Each FRAME is a PNG (shown as stored) or an EXR written by `pgt facade` (its linear R, G, B
encoded to sRGB as pgt's --png does). Panels keep their aspect ratio, C per row (default: as
many as stay 2.3 in wide in the 7 in figure, i.e. 3), each titled (wrapped to the panel's
width); --title puts a title over the whole figure. Writes OUT_PREFIX.png (300 dpi) and
OUT_PREFIX.pdf. A missing or unreadable frame is an error (exit 2).

For Fig. 11 (flat buildings, macroscopic geometry and shadowing, normal mapping, relief
mapping) scripts/main.sh's step 18 runs, in short:
  facade_panels.py paper_figs/out/facade_lod facade_lod_flat.png "(a) flat ..." \
      facade_lod_geometry.png "(b) ..." facade_lod_normal.png "(c) ..." \
      facade_lod_relief.png "(d) ..." --columns 2 --title "..."
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exrread import ExrError, read_exr  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figsetup  # noqa: E402  (before matplotlib: config folder, Agg, sizes)
import matplotlib  # noqa: E402

import matplotlib.image as mpimg  # noqa: E402


def die(msg):
    print(f"facade_panels: error: {msg}", file=sys.stderr)
    sys.exit(2)


def load(path):
    if path.lower().endswith(".exr"):
        try:
            ch = read_exr(path)
        except ExrError as e:
            die(str(e))
        if not all(k in ch for k in "RGB"):
            die(f"{path}: no R, G, B channels (is it a pgt facade frame?)")
        c = np.clip(np.stack([ch["R"], ch["G"], ch["B"]], axis=2), 0.0, 1.0)
        return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)
    try:
        return mpimg.imread(path)
    except (OSError, ValueError, SyntaxError) as e:
        die(f"{path}: {e}")


def main(argv):
    args, columns, title = [], None, None
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("--columns", "--title"):
            if i + 1 >= len(argv):
                die(f"{a}: missing value")
            if a == "--columns":
                if not argv[i + 1].isdigit() or int(argv[i + 1]) < 1:
                    die(f"--columns: expected a positive number, got '{argv[i + 1]}'")
                columns = int(argv[i + 1])
            else:
                title = argv[i + 1]
            i += 2
            continue
        args.append(a)
        i += 1
    if len(args) < 3 or len(args) % 2 != 1:
        die("usage: facade_panels.py OUT_PREFIX FRAME TITLE [FRAME TITLE ...] [--columns C] "
            "[--title T]")
    out, pairs = args[0], list(zip(args[1::2], args[2::2]))
    imgs = [load(p) for p, _ in pairs]
    # by default as many per row as stay at least 2.3 in wide (three 16:9 frames in a row)
    cols = min(columns or max(int(figsetup.TEXT_WIDTH // 2.3), 1), len(imgs))
    fig, axes, fig_title = figsetup.image_grid([im.shape for im in imgs],
                                               [t for _, t in pairs], cols, title)
    for ax, im in zip(axes, imgs):
        ax.imshow(im, interpolation="lanczos")

    def unresampled():
        # the PDF embeds each frame at its own resolution (resampled at 200 dpi it lost a
        # third of the pixels); the viewer scales it
        for ax in axes:
            for image in ax.get_images():
                image.set_interpolation("none")

    figsetup.fit_images(fig, axes, title=fig_title)
    figsetup.save(fig, out, die, pdf_kw={"dpi": figsetup.DPI}, before_pdf=unresampled)

if __name__ == "__main__":
    main(sys.argv[1:])
