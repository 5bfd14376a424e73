#!/usr/bin/python3
"""One object at several subdivision levels, side by side, as in a paper figure.

usage: mesh_levels.py OUT_PREFIX MESH0 MESH1 [MESH2 ...] [--labels L0 L1 ...] [--title T]
                      [--elev DEG] [--azim DEG] [--up {x,y,z}]

MESHi are .off or .ply files (see meshread.py). Every panel uses the same camera and the same
axis limits (the common bounding box, equal aspect), so sizes compare across levels. Faces are
flat-shaded with a Lambert term from a light fixed relative to the camera:
colour = base * (0.25 + 0.75 * max(0, n.l)). Edges are drawn thin and get thinner as the face
count grows; above EDGE_FACE_LIMIT faces no edges are drawn. Writes OUT_PREFIX.png (300 dpi)
and OUT_PREFIX.pdf. Bad input is an error on stderr and exit status 2.
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figsetup  # noqa: E402  (before matplotlib: config folder, Agg, sizes)
import matplotlib  # noqa: E402

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.transforms import Bbox  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from meshread import MeshError, read_mesh  # noqa: E402

BASE_COLOUR = np.array([0.62, 0.74, 0.88])
# Back faces seen through the boundary of an open mesh: lit with the flipped normal (two-sided
# lighting) in a warm grey, so the inside reads as inside instead of a flat ambient-dark blob.
BACK_COLOUR = np.array([0.86, 0.76, 0.62])
EDGE_COLOUR = (0.12, 0.12, 0.15)
AMBIENT = 0.25
# Light in camera coordinates (right, up, towards the viewer): upper left, in front.
LIGHT_CAM = np.array([-0.45, 0.55, 0.70])
# Beyond this many faces edges only darken the picture into a grey mass.
EDGE_FACE_LIMIT = 20000
# Above this many faces the PDF gets the panel as an image: vector polygons would make a
# multi-megabyte file that viewers draw slowly.
PDF_RASTER_FACES = 20000


def die(msg):
    print(f"mesh_levels: error: {msg}", file=sys.stderr)
    sys.exit(2)


def camera_frame(elev, azim):
    """(right, up, eye) unit vectors of matplotlib's view for (elev, azim) in degrees."""
    e, a = np.radians(elev), np.radians(azim)
    eye = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    right = np.array([-np.sin(a), np.cos(a), 0.0])
    up = np.cross(eye, right)
    return right, up, eye


def is_closed(F):
    """True when every directed edge has its reverse: a closed, consistently oriented mesh,
    whose back faces can never be seen and may be culled."""
    if len(F) == 0:
        return False
    e = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    fwd = np.unique(e[:, 0] * (F.max() + 1) + e[:, 1])
    rev = np.unique(e[:, 1] * (F.max() + 1) + e[:, 0])
    return len(fwd) == len(e) and np.array_equal(fwd, rev)


def edge_width(nf):
    """Edge line width in points: ~0.5 for a few hundred faces, falling with sqrt(faces) so
    the ink per area stays roughly constant."""
    return float(np.clip(0.5 * np.sqrt(300.0 / max(nf, 1)), 0.06, 0.5))


def parse_args(argv):
    p = argparse.ArgumentParser(
        prog="mesh_levels.py", description="Meshes at subdivision levels, side by side.")
    p.add_argument("out_prefix", metavar="OUT_PREFIX")
    p.add_argument("meshes", metavar="MESH", nargs="+", help=".off or .ply files")
    p.add_argument("--labels", nargs="+", metavar="L",
                   help='one label per mesh (default "k = 0", "k = 1", ...)')
    p.add_argument("--title", default=None)
    p.add_argument("--elev", type=float, default=20.0, help="camera elevation, degrees")
    p.add_argument("--azim", type=float, default=-60.0, help="camera azimuth, degrees")
    p.add_argument("--up", choices=("x", "y", "z"), default="z",
                   help="the model's up axis (y for Y-up files)")
    args = p.parse_args(argv)
    if args.labels is None:
        args.labels = [f"k = {i}" for i in range(len(args.meshes))]
    if len(args.labels) != len(args.meshes):
        die(f"{len(args.labels)} labels for {len(args.meshes)} meshes")
    return args


def main(argv):
    args = parse_args(argv)
    to_z_up = {"z": np.eye(3),
               "y": np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]]),  # (x, y, z) -> (x, -z, y)
               "x": np.array([[0.0, 0, -1], [0, 1, 0], [1, 0, 0]])}[args.up]
    meshes = []
    for path in args.meshes:
        try:
            V, F = read_mesh(path)
        except MeshError as e:
            die(str(e))
        except OSError as e:
            die(f"{path}: {e.strerror}")
        if len(V) == 0 or len(F) == 0:
            die(f"{path}: no vertices or no faces")
        if not np.isfinite(V).all():
            die(f"{path}: non-finite vertex coordinates")
        meshes.append((V @ to_z_up.T, F))

    # Common box over all panels; box aspect = its extents gives equal scale on x, y, z.
    lo = np.min([V.min(axis=0) for V, _ in meshes], axis=0)
    hi = np.max([V.max(axis=0) for V, _ in meshes], axis=0)
    ext = np.maximum(hi - lo, 1e-9 * max(float((hi - lo).max()), 1e-30))
    lo, hi = lo - 0.01 * ext, hi + 0.01 * ext

    right, up, eye = camera_frame(args.elev, args.azim)
    light = LIGHT_CAM[0] * right + LIGHT_CAM[1] * up + LIGHT_CAM[2] * eye
    light /= np.linalg.norm(light)

    n = len(meshes)
    # 2.4 in per panel, less when that would make the figure wider than the text
    pw = min(2.4, figsetup.TEXT_WIDTH / n)
    fig = plt.figure(figsize=(pw * n, 2.6 * pw / 2.4))
    axes = []
    for i, (V, F) in enumerate(meshes):
        ax = fig.add_axes([i / n, 0.0, 1.0 / n, 1.0], projection="3d")
        ax.computed_zorder = False  # layers below are ordered by zorder, not by depth
        tri = V[F]
        nrm = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        length = np.linalg.norm(nrm, axis=1)
        nrm /= np.where(length > 0, length, 1.0)[:, None]
        # Orthographic view: a face is seen from behind iff its normal points away from the eye.
        front = nrm @ eye >= 0
        if is_closed(F):
            tri, nrm, front = tri[front], nrm[front], front[front]
        nrm = np.where(front[:, None], nrm, -nrm)
        shade = AMBIENT + (1 - AMBIENT) * np.maximum(0.0, nrm @ light)
        base = np.where(front[:, None], BASE_COLOUR[None, :], BACK_COLOUR[None, :])
        colours = np.clip(base * shade[:, None], 0, 1)
        nf = len(F)
        if nf > EDGE_FACE_LIMIT:
            # Anti-aliased faces leave light seams between neighbours that add up to moire on
            # dense meshes, and face-coloured edges to hide them smear at the silhouette. So:
            # an anti-aliased layer for a smooth outline, covered by an aliased one for the
            # interior.
            layers = [Poly3DCollection(tri, facecolors=colours, edgecolors=colours,
                                       linewidths=0.15, zorder=1),
                      Poly3DCollection(tri, facecolors=colours, edgecolors="none",
                                       linewidths=0, antialiased=False, zorder=2)]
        else:
            layers = [Poly3DCollection(tri, facecolors=colours, edgecolors=EDGE_COLOUR,
                                       linewidths=edge_width(nf), zorder=1)]
        for pc in layers:
            pc.set_zsort("average")  # painter's order by mean projected depth
            if nf > PDF_RASTER_FACES:
                pc.set_rasterized(True)
            ax.add_collection3d(pc)
        ax.set_proj_type("ortho")
        ax.view_init(elev=args.elev, azim=args.azim)
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_zlim(lo[2], hi[2])
        ax.set_box_aspect(hi - lo, zoom=1.25)
        ax.set_axis_off()
        axes.append((ax, layers[0], nf))

    # Put the labels just under the lowest drawn face of any panel and the title just above
    # the highest, then crop to faces and text: the 3D axes themselves leave a wide empty
    # margin, which bbox_inches="tight" would keep. Everything here is in display pixels.
    fig.canvas.draw()
    pts = np.concatenate([ax.transData.transform(np.concatenate([p.vertices
                                                                 for p in pc.get_paths()]))
                          for ax, pc, _ in axes])
    (x_lo, y_lo), (x_hi, y_hi) = pts.min(axis=0), pts.max(axis=0)
    gap = 0.06 * fig.dpi  # inches -> pixels
    to_fig = fig.transFigure.inverted()
    texts = []
    for i, ((ax, _, nf), label) in enumerate(zip(axes, args.labels)):
        y = to_fig.transform((0, y_lo - gap))[1]
        texts.append(fig.text((i + 0.5) / n, y, f"{label}\n{nf:,} faces", ha="center",
                              va="top", fontsize=figsetup.TEXT_PT, linespacing=1.35))
    if args.title:
        y = to_fig.transform((0, y_hi + gap))[1]
        texts.append(fig.text(0.5, y, args.title, ha="center", va="bottom",
                              fontsize=figsetup.TITLE_PT))
    renderer = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(renderer) for t in texts] + [Bbox([[x_lo, y_lo],
                                                                     [x_hi, y_hi]])]
    crop = Bbox.union(boxes).padded(0.04 * fig.dpi)
    crop = Bbox(crop.get_points() / fig.dpi)  # savefig wants inches
    out_dir = os.path.dirname(args.out_prefix)
    if out_dir:
        os.makedirs(out_dir, exist_ok=True)
    for ext, kw in (("png", {"dpi": figsetup.DPI}), ("pdf", {"dpi": 300})):
        fig.savefig(f"{args.out_prefix}.{ext}", bbox_inches=crop, **kw)
    plt.close(fig)
    print(f"wrote {args.out_prefix}.png and {args.out_prefix}.pdf", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
