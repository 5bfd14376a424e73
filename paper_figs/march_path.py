#!/usr/bin/python3
"""A march drawn on the atlas and on the surface, as in paper 000's Fig. 4.

usage: march_path.py OUT_PREFIX PATH.csv --dump PREFIX [--title T] [--elev DEG] [--azim DEG]
                     [--up {x,y,z}] [--labels N]

PATH.csv is what `pgt march ... -o PATH.csv` writes (step,u,v,chart,x,y,z,event; u,v in texels,
row 0 of the atlas at the top); PREFIX is the `--dump PREFIX` of the same run: PREFIX.atlas.png
(the atlas, one pixel per texel, charts in colours) and PREFIX.texels.csv (u,v,chart,x,y,z,
nx,ny,nz of a grid of inner texels). No EXR reader is needed.

Left panel: the atlas in texel space with the march: white dots are the walker's positions after
each step, joined inside a chart; green arrows are the steps that jumped across charts, numbered
in marching order (the paper's green arrows); a star marks the start, a red cross a stop.
Right panel: the same march on the surface (its x,y,z), over a light point cloud of the atlas
texels; texels facing away from the camera are left out and the part of the path behind the
surface is drawn faint and dashed. By default the camera looks at the path from outside (from the
cloud's centre through the path's centroid); --elev/--azim override it.

Writes OUT_PREFIX.png (300 dpi, 7 in wide) and OUT_PREFIX.pdf. Bad input is an error on stderr
and exit status 2.
"""

import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figsetup  # noqa: E402  (before matplotlib: config folder, Agg, sizes)
import matplotlib  # noqa: E402

import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.dont_write_bytecode = True

PATH_COLUMNS = ("step", "u", "v", "chart", "x", "y", "z", "event")
TEXEL_COLUMNS = ("u", "v", "chart", "x", "y", "z", "nx", "ny", "nz")
EVENTS = ("start", "inner", "jump", "search", "stop")
JUMP_COLOUR = "#1a9641"
CLOUD_COLOUR = (0.55, 0.58, 0.62)
# Above this many jumps the arrow numbers only clutter the atlas panel.
# jump labels (label_jumps), as fractions of the atlas width: jumps whose ends lie within
# LABEL_MERGE of each other share a label; a label stands LABEL_OFFSET beside its arrow
LABEL_MERGE = 0.012
LABEL_OFFSET = 0.03  # 7 pt labels on a 3.4 in panel (0.018 was for 6 pt on 4.8 in)
MAX_NUMBERED_JUMPS = 40
# Path points whose nearest texel's normal faces away from the camera by more than this cosine
# are drawn as hidden (a small margin so that silhouettes do not flicker).
HIDDEN_COS = -0.05
# Positions on the atlas picture's background allowed before the inputs are called mismatched
# (none are on the atlas the march was made on: the walker stands on inner texels only).
MAX_OFF_ATLAS = 0.01
# Magnification of the 3D panel: matplotlib leaves a wide margin around a 3D box; 1.8 makes the
# mesh's bounding cube (its largest side, from any view) fill the panel without clipping it.
SURFACE_ZOOM = 1.8


def die(msg):
    print(f"march_path: error: {msg}", file=sys.stderr)
    sys.exit(2)


def read_csv(path, columns):
    """Rows of a CSV with a header line, as a dict of column -> list of strings."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        die(f"{path}: {e.strerror}")
    if not rows:
        die(f"{path}: empty file")
    header = [h.strip() for h in rows[0]]
    missing = [c for c in columns if c not in header]
    if missing:
        die(f"{path}: no column {', '.join(missing)} (header: {','.join(header)})")
    idx = {c: header.index(c) for c in columns}
    out = {c: [] for c in columns}
    for n, row in enumerate(rows[1:], start=2):
        if not row:
            continue
        if len(row) < len(header):
            die(f"{path}:{n}: {len(row)} fields, the header has {len(header)}")
        for c in columns:
            out[c].append(row[idx[c]].strip())
    if not out[columns[0]]:
        die(f"{path}: no data rows")
    return out


def floats(path, col, values):
    try:
        a = np.array([float(v) for v in values])
    except ValueError:
        die(f"{path}: column {col}: not a number")
    if not np.all(np.isfinite(a)):
        die(f"{path}: column {col}: a value is not finite")
    return a


def read_path(path):
    d = read_csv(path, PATH_COLUMNS)
    events = d["event"]
    bad = sorted(set(events) - set(EVENTS))
    if bad:
        die(f"{path}: unknown event {bad[0]!r} (expected one of {', '.join(EVENTS)})")
    uv = np.stack([floats(path, c, d[c]) for c in ("u", "v")], axis=1)
    xyz = np.stack([floats(path, c, d[c]) for c in ("x", "y", "z")], axis=1)
    return uv, xyz, np.array(events)


def read_texels(path):
    d = read_csv(path, TEXEL_COLUMNS)
    xyz = np.stack([floats(path, c, d[c]) for c in ("x", "y", "z")], axis=1)
    nrm = np.stack([floats(path, c, d[c]) for c in ("nx", "ny", "nz")], axis=1)
    return xyz, nrm


def up_permutation(up):
    """Column order that puts the chosen up axis last (matplotlib's z is up)."""
    return {"x": [1, 2, 0], "y": [2, 0, 1], "z": [0, 1, 2]}[up]


def camera_eye(elev, azim):
    e, a = np.radians(elev), np.radians(azim)
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def parse_args(argv):
    p = argparse.ArgumentParser(
        prog="march_path.py",
        description="A march of pgt march drawn on the atlas and on the surface (Fig. 4).")
    p.add_argument("out_prefix", metavar="OUT_PREFIX")
    p.add_argument("path_csv", metavar="PATH.csv", help="pgt march -o output")
    p.add_argument("--dump", required=True, metavar="PREFIX",
                   help="the --dump PREFIX of the same pgt march run")
    p.add_argument("--title", default=None)
    p.add_argument("--elev", type=float, default=None, help="camera elevation, degrees")
    p.add_argument("--azim", type=float, default=None, help="camera azimuth, degrees")
    p.add_argument("--up", choices=("x", "y", "z"), default="y",
                   help="the surface's up axis (default y: the OBJ convention)")
    return p.parse_args(argv)


def label_jumps(ax, uv, jumps, w):
    """Numbers the jumps beside their arrows. Jumps whose ends nearly coincide (the same seam
    crossed both ways, or twice) share one label ("6, 10"); each label stands off its arrow's
    middle along the arrow's normal, pushed further while it would touch an earlier label, with
    a thin leader line (at its middle a number covered the path's dots)."""
    merge, off = LABEL_MERGE * w, LABEL_OFFSET * w
    groups = []  # [from, to, [jump numbers]]
    for k, i in enumerate(jumps, start=1):
        a, b = uv[i - 1], uv[i]
        for g in groups:
            same = np.linalg.norm(a - g[0]) < merge and np.linalg.norm(b - g[1]) < merge
            back = np.linalg.norm(a - g[1]) < merge and np.linalg.norm(b - g[0]) < merge
            if same or back:
                g[2].append(k)
                break
        else:
            groups.append([a, b, [k]])
    placed = []
    for a, b, numbers in groups:
        mid = 0.5 * (a + b)
        d = b - a
        n = np.array([-d[1], d[0]])
        n = n / np.linalg.norm(n) if np.linalg.norm(n) > 0 else np.array([0.0, -1.0])
        pos = mid + off * n
        for _ in range(12):
            if all(np.linalg.norm(pos - q) >= 1.6 * off for q in placed):
                break
            pos = pos + 0.8 * off * n
        placed.append(pos)
        ax.annotate(", ".join(map(str, numbers)), xy=mid, xytext=pos, color=JUMP_COLOUR,
                    fontsize=figsetup.SMALL_PT, fontweight="bold", ha="center", va="center",
                    zorder=5,
                    bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.85),
                    arrowprops=dict(arrowstyle="-", color=JUMP_COLOUR, lw=0.4, shrinkA=0,
                                    shrinkB=0))


def draw_atlas(ax, atlas, uv, events):
    h, w = atlas.shape[0], atlas.shape[1]
    ax.imshow(atlas, extent=(0, w, h, 0), interpolation="none")  # PDF: texels kept
    jump = np.isin(events, ("jump", "search"))
    # runs of consecutive positions inside one chart: split before every jump step
    starts = [0] + [i for i in range(1, len(uv)) if jump[i]] + [len(uv)]
    for a, b in zip(starts[:-1], starts[1:]):
        if b - a >= 2:
            ax.plot(uv[a:b, 0], uv[a:b, 1], color="black", lw=0.6, zorder=2)
    ax.scatter(uv[:, 0], uv[:, 1], s=7, c="white", edgecolors="black", linewidths=0.4, zorder=3)
    jumps = np.nonzero(jump)[0]
    for k, i in enumerate(jumps, start=1):
        ax.annotate("", xy=uv[i], xytext=uv[i - 1], zorder=4,
                    arrowprops=dict(arrowstyle="-|>", color=JUMP_COLOUR, lw=1.0,
                                    shrinkA=1, shrinkB=1, mutation_scale=8))
    if len(jumps) <= MAX_NUMBERED_JUMPS:
        label_jumps(ax, uv, jumps, w)
    ax.scatter(uv[:1, 0], uv[:1, 1], s=60, marker="*", c="gold", edgecolors="black",
               linewidths=0.5, zorder=6)
    if events[-1] == "stop":
        ax.scatter(uv[-1:, 0], uv[-1:, 1], s=40, marker="x", c="red", zorder=6)
    ax.set_xlim(0, w)
    ax.set_ylim(h, 0)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(f"atlas ({w} x {h} texels)")


def draw_surface(ax, cloud, normals, path, events, elev, azim):
    centre = 0.5 * (cloud.min(axis=0) + cloud.max(axis=0))
    # normals pointing inwards (a mesh oriented the other way): flip them for the culling
    if np.mean(np.sum((cloud - centre) * normals, axis=1)) < 0.0:
        normals = -normals
    if elev is None or azim is None:
        eye = path.mean(axis=0) - centre
        n = np.linalg.norm(eye)
        eye = eye / n if n > 0 else np.array([1.0, 0.0, 0.0])
        if elev is None:
            elev = float(np.degrees(np.arcsin(np.clip(eye[2], -1.0, 1.0))))
        if azim is None:
            azim = float(np.degrees(np.arctan2(eye[1], eye[0])))
    view = camera_eye(elev, azim)
    front = normals @ view > 0.0
    ax.scatter(cloud[front, 0], cloud[front, 1], cloud[front, 2], s=0.4, c=[CLOUD_COLOUR],
               alpha=0.35, linewidths=0, depthshade=False)
    # facing of each path point: the normal of its nearest cloud texel
    facing = np.empty(len(path))
    for a in range(0, len(path), 256):
        d2 = ((path[a:a + 256, None, :] - cloud[None, :, :]) ** 2).sum(axis=2)
        facing[a:a + 256] = normals[np.argmin(d2, axis=1)] @ view
    visible = facing > HIDDEN_COS
    jump = np.isin(events, ("jump", "search"))
    for i in range(1, len(path)):
        seg = path[i - 1:i + 1]
        vis = visible[i - 1] and visible[i]
        colour = JUMP_COLOUR if jump[i] else "black"
        ax.plot(seg[:, 0], seg[:, 1], seg[:, 2], color=colour, lw=1.1 if vis else 0.6,
                ls="-" if vis else "--", alpha=1.0 if vis else 0.35)
    ax.scatter(path[visible, 0], path[visible, 1], path[visible, 2], s=5, c="white",
               edgecolors="black", linewidths=0.3, depthshade=False)
    ax.scatter(path[:1, 0], path[:1, 1], path[:1, 2], s=60, marker="*", c="gold",
               edgecolors="black", linewidths=0.5, depthshade=False)
    lo, hi = cloud.min(axis=0), cloud.max(axis=0)
    mid, half = 0.5 * (lo + hi), 0.5 * float(np.max(hi - lo))
    ax.set_xlim(mid[0] - half, mid[0] + half)
    ax.set_ylim(mid[1] - half, mid[1] + half)
    ax.set_zlim(mid[2] - half, mid[2] + half)
    ax.set_box_aspect((1, 1, 1), zoom=SURFACE_ZOOM)
    ax.view_init(elev=elev, azim=azim)
    ax.set_axis_off()
    ax.set_title("surface")


def main(argv):
    args = parse_args(argv)
    uv, xyz, events = read_path(args.path_csv)
    png, texels_csv = args.dump + ".atlas.png", args.dump + ".texels.csv"
    try:
        atlas = mpimg.imread(png)
    except (OSError, ValueError, SyntaxError) as e:
        die(f"{png}: cannot read it as a PNG ({e})")
    if atlas.ndim not in (2, 3):
        die(f"{png}: not an image")
    cloud, normals = read_texels(texels_csv)
    h, w = atlas.shape[0], atlas.shape[1]
    if np.any(uv < 0) or np.any(uv[:, 0] > w) or np.any(uv[:, 1] > h):
        die(f"{args.path_csv}: positions outside the {w} x {h} atlas of {png}: another atlas?")
    # every position lies in an inner texel, never on the white background of the picture
    px = atlas[np.clip(uv[:, 1].astype(int), 0, h - 1), np.clip(uv[:, 0].astype(int), 0, w - 1)]
    rgb = px[:, :3] if px.ndim == 2 else np.stack([px] * 3, axis=1)
    white = np.all(rgb >= (1.0 if rgb.dtype.kind == "f" else 255), axis=1)
    if np.mean(white) > MAX_OFF_ATLAS:
        die(f"{args.path_csv}: {np.mean(white):.0%} of the positions lie on the background of "
            f"{png}: the march was made on another atlas")
    perm = up_permutation(args.up)
    path3, cloud3, normals3 = xyz[:, perm], cloud[:, perm], normals[:, perm]

    fig = plt.figure(figsize=(figsetup.TEXT_WIDTH, 3.9))
    ax2 = fig.add_subplot(1, 2, 1)
    ax3 = fig.add_subplot(1, 2, 2, projection="3d")
    draw_atlas(ax2, atlas, uv, events)
    draw_surface(ax3, cloud3, normals3, path3, events, args.elev, args.azim)
    n_jump = int(np.sum(np.isin(events, ("jump", "search"))))
    steps = len(events) - 1
    note = (f"{os.path.basename(args.path_csv)}: {steps} steps, {n_jump} across charts"
            + (", stopped" if events[-1] == "stop" else ""))
    note = fig.text(0.005, 0.005, note, fontsize=figsetup.SMALL_PT, color="0.35", va="bottom")
    heading = figsetup.suptitle(fig, args.title) if args.title else None
    # the top margin keeps the panel titles whole (tight_layout does not see the 3D axes' title)
    figsetup.layout(fig, note, heading, top=0.95)
    out_dir = os.path.dirname(args.out_prefix)
    if out_dir:
        os.makedirs(out_dir, exist_ok=True)
    figsetup.save(fig, args.out_prefix, die)
    print(f"march_path: wrote {args.out_prefix}.png and .pdf ({steps} steps, {n_jump} jumps)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
