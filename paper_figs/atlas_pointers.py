#!/usr/bin/python3
"""An indirection geometry image with its pointers, like Fig. 2b-c of paper 000.

usage: atlas_pointers.py ATLAS.exr OUT_PREFIX [--zoom X0,Y0,SIZE] [--arrows N] [--title T]

ATLAS.exr is an atlas written by `pgt atlas` (11 float channels, ref_cpu/include/pgt/atlas.h).
Left (b): the whole atlas, inner texels coloured by chart and shaded by the normal, indirection
texels white, dead ends red, background black; the zoom window is outlined, and up to N
(default 40) of its indirection texels are joined to the texels they point to. Right (c): the
zoom, texel by texel: inner texels in their chart's colour, each indirection texel in the colour
of the chart it points INTO (so the inner border of each neighbour shows up replicated around
the chart, as in the paper's Fig. 2c), dead ends red, with short arrows towards the targets.
Without --zoom, the window (SIZE = 1/24 of the atlas side) is the one whose indirection texels
point into the most different charts. Writes OUT_PREFIX.png (300 dpi, 7 in wide) and
OUT_PREFIX.pdf; bad input is a message on stderr and exit status 2.

The EXR reader below handles what pgt_image_write_exr writes (single-part scanline, FLOAT or
HALF channels, NONE / ZIPS / ZIP compression); Debian's python3 has no OpenEXR module.
"""

import os
import struct
import sys
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figsetup  # noqa: E402  (before matplotlib: config folder, Agg, sizes)
import matplotlib  # noqa: E402

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import exrread  # noqa: E402

CHANNELS = ("P.x", "P.y", "P.z", "N.x", "N.y", "N.z", "chart", "kind", "ptr.u", "ptr.v", "rot")
INNER, INDIRECTION, DEAD_END = 1, 2, 3


def die(msg):
    print(f"atlas_pointers: error: {msg}", file=sys.stderr)
    sys.exit(2)


def read_exr(path):
    """{channel name: H x W float32} of a single-part scanline OpenEXR file (exrread.py)."""
    try:
        return exrread.read_exr(path)
    except exrread.ExrError as e:
        die(str(e))


def chart_colours(n):
    """A stable bright colour per chart id."""
    rng = np.random.RandomState(12345)
    return 0.3 + 0.65 * rng.rand(max(n, 1), 3)


def pick_zoom(a, size):
    k, ch = a["kind"], a["chart"]
    tu, tv = a["ptr.u"].astype(int), a["ptr.v"].astype(int)
    H, W = k.shape
    ys, xs = np.nonzero(k == INDIRECTION)
    if len(xs) == 0:
        return 0, 0
    target = ch[np.clip(tv[ys, xs], 0, H - 1), np.clip(tu[ys, xs], 0, W - 1)].astype(int)
    best, where = (-1, -1), (0, 0)
    step = max(size // 2, 1)
    for y0 in range(0, max(H - size, 0) + 1, step):
        for x0 in range(0, max(W - size, 0) + 1, step):
            m = (xs >= x0) & (xs < x0 + size) & (ys >= y0) & (ys < y0 + size)
            score = (len(np.unique(target[m])), int(m.sum()))
            if score > best:
                best, where = score, (x0, y0)
    return where


def main(argv):
    args = argv[1:]
    if len(args) < 2 or args[0] in ("-h", "--help"):
        print(__doc__)
        sys.exit(0 if args and args[0] in ("-h", "--help") else 2)
    path, prefix = args[0], args[1]
    zoom, arrows, title = None, 40, None
    i = 2
    while i < len(args):
        if args[i] in ("--zoom", "--arrows", "--title") and i + 1 >= len(args):
            die(f"{args[i]} needs a value")
        if args[i] == "--zoom":
            try:
                zoom = tuple(int(v) for v in args[i + 1].split(","))
                if len(zoom) != 3 or zoom[2] <= 0 or min(zoom) < 0:
                    raise ValueError
            except ValueError:
                die(f"--zoom: expected X0,Y0,SIZE (texels), got '{args[i + 1]}'")
        elif args[i] == "--arrows":
            try:
                arrows = int(args[i + 1])
                if arrows < 0:
                    raise ValueError
            except ValueError:
                die(f"--arrows: expected a whole number, got '{args[i + 1]}'")
        elif args[i] == "--title":
            title = args[i + 1]
        else:
            die(f"unknown argument '{args[i]}'")
        i += 2

    a = read_exr(path)
    k, ch = a["kind"], a["chart"]
    H, W = k.shape
    nch = int(ch.max()) + 1 if (k == INNER).any() else 1
    cols = chart_colours(nch)
    N = np.stack([a["N.x"], a["N.y"], a["N.z"]], -1)
    light = np.array([0.4, 0.5, 0.7663])
    shade = 0.45 + 0.55 * np.abs(N @ light)
    inner = k == INNER
    img = np.zeros((H, W, 3))
    img[inner] = cols[ch[inner].astype(int) % nch] * shade[inner, None]
    img[k == INDIRECTION] = 1.0
    img[k == DEAD_END] = (1.0, 0.0, 0.0)

    size = zoom[2] if zoom else max(W // 24, 8)
    x0, y0 = (zoom[0], zoom[1]) if zoom else pick_zoom(a, size)
    x1, y1 = min(x0 + size, W), min(y0 + size, H)
    if x0 >= W or y0 >= H:
        die(f"--zoom: the window starts outside the {W}x{H} atlas")

    tu, tv = a["ptr.u"], a["ptr.v"]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(figsetup.TEXT_WIDTH, 4.1))
    panel = figsetup.TEXT_WIDTH / 2  # in, for the titles' line breaks
    ax1.imshow(img, interpolation="none", extent=(0, W, H, 0))  # PDF: texels kept
    ax1.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, ec="yellow", lw=1.2))
    ys, xs = np.nonzero(k[y0:y1, x0:x1] == INDIRECTION)
    ys, xs = ys + y0, xs + x0
    if len(xs) and arrows:
        pick = np.linspace(0, len(xs) - 1, min(arrows, len(xs))).astype(int)
        for j in pick:
            x, y = xs[j], ys[j]
            ax1.annotate("", (tu[y, x] + 0.5, tv[y, x] + 0.5), (x + 0.5, y + 0.5),
                         arrowprops=dict(arrowstyle="->", lw=0.5, color="yellow", alpha=0.8))
    ax1.set_title(figsetup.wrap("(b) atlas: charts, indirection texels (white), dead ends (red)",
                                panel))
    ax1.set_xticks([]), ax1.set_yticks([])

    z = np.zeros((y1 - y0, x1 - x0, 3))
    zk, zc = k[y0:y1, x0:x1], ch[y0:y1, x0:x1]
    zi = zk == INNER
    z[zi] = cols[zc[zi].astype(int) % nch] * 0.75
    for y, x in zip(ys, xs):
        ty, tx = int(tv[y, x]), int(tu[y, x])
        z[y - y0, x - x0] = cols[int(ch[ty, tx]) % nch]
    z[zk == DEAD_END] = (1.0, 0.0, 0.0)
    ax2.imshow(z, interpolation="none", extent=(x0, x1, y1, y0))
    for y, x in zip(ys, xs):
        d = np.array([tu[y, x] - x, tv[y, x] - y], float)
        n = np.hypot(*d)
        if n == 0:
            continue
        d *= min(0.45 * size / 12.0, n) / n
        ax2.annotate("", (x + 0.5 + d[0], y + 0.5 + d[1]), (x + 0.5, y + 0.5),
                     arrowprops=dict(arrowstyle="->", lw=0.4, color="k"))
    ax2.set_title(figsetup.wrap(f"(c) zoom [{x0}, {x1}) x [{y0}, {y1}): indirection texels in "
                                "the colour of the chart they point into", panel))
    heading = figsetup.suptitle(fig, figsetup.wrap(
        title or f"{os.path.basename(path)}: {W}x{H}, {nch} charts, "
        f"{int((k == INDIRECTION).sum())} indirection and "
        f"{int((k == DEAD_END).sum())} dead-end texels", figsetup.TEXT_WIDTH, figsetup.TITLE_PT))
    figsetup.layout(fig, title=heading)
    figsetup.save(fig, prefix, die)
    print(f"atlas_pointers: wrote {prefix}.png and {prefix}.pdf (zoom {x0},{y0},{size})")


if __name__ == "__main__":
    main(sys.argv)
