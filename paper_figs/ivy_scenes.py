#!/usr/bin/python3
"""Ivy scenes of paper 000 (Fig. 1 and 10) as one figure: the renders `pgt render` made of the
`pgt ivy` scenes (scripts/main.sh step 12), side by side with titles.

usage: ivy_scenes.py OUT_PREFIX IMAGE.png TITLE [IMAGE.png TITLE ...]

Each render is trimmed to the bounding box of its non-background pixels (plus a margin) so the
models fill their panels; two panels per row, 7 in wide. Writes OUT_PREFIX.png (300 dpi) and
OUT_PREFIX.pdf. A missing or
unreadable image is an error (exit 2).
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figsetup  # noqa: E402  (before matplotlib: config folder, Agg, sizes)
import matplotlib  # noqa: E402

import matplotlib.image as mpimg  # noqa: E402
import numpy as np  # noqa: E402

# Margin kept around a model when trimming, as a fraction of its larger side.
TRIM_MARGIN = 0.04
# A pixel differs from the background when a channel differs by more than this (8-bit PNG read
# as floats in [0, 1]: 2/255 ignores rounding of the background colour).
BACKGROUND_TOL = 2.0 / 255.0


def die(msg):
    print(f"ivy_scenes: error: {msg}", file=sys.stderr)
    sys.exit(2)


def trimmed(path):
    try:
        img = mpimg.imread(path)
    except (OSError, ValueError) as e:
        die(f"{path}: {e}")
    rgb = img[..., :3]
    bg = rgb[0, 0]
    fg = np.any(np.abs(rgb - bg) > BACKGROUND_TOL, axis=2)
    if not fg.any():
        return img
    ys, xs = np.nonzero(fg)
    m = int(TRIM_MARGIN * max(ys.ptp(), xs.ptp()))
    y0, y1 = max(0, ys.min() - m), min(img.shape[0], ys.max() + m + 1)
    x0, x1 = max(0, xs.min() - m), min(img.shape[1], xs.max() + m + 1)
    return img[y0:y1, x0:x1]


def main():
    args = sys.argv[1:]
    if len(args) < 3 or len(args) % 2 != 1:
        die("usage: ivy_scenes.py OUT_PREFIX IMAGE.png TITLE [IMAGE.png TITLE ...]")
    out, pairs = args[0], list(zip(args[1::2], args[2::2]))
    images = [trimmed(path) for path, _ in pairs]
    # two per row (four in a row at 7 in left each render 1.7 in wide)
    fig, axes, _ = figsetup.image_grid([im.shape for im in images], [t for _, t in pairs],
                                       min(len(pairs), 2))
    for ax, im in zip(axes, images):
        ax.imshow(im)
    figsetup.layout(fig)
    figsetup.save(fig, out, die, pdf_kw={"dpi": figsetup.DPI})
    print(f"ivy_scenes: wrote {out}.png and {out}.pdf")


if __name__ == "__main__":
    main()
