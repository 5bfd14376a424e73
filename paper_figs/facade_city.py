#!/usr/bin/python3
"""Renders like Fig. 1a-c of paper 003 (per-pixel procedural facades) made with `pgt facade`.

usage: facade_city.py PGT OUT_DIR [--quick] [--threads N] [--raw]

Runs PGT (the pgt program) three times, from the repository root's grammars and
paper_figs/scenes/, with fixed cameras and lights chosen from the scenes' known layout
(pgt_gen_city: lots of 30 m, datasets_gen/gen.h):

  fig1a  the 10K-facade city (--city 2500, grammars/facade.grammar, seed 1), high oblique view
         from beyond the corner (0, 0) of the 1.5 km square, self-shadowing on;
  fig1b  macroscopic details: grammars/facade_rich.grammar on --city 25, street level in the
         street z = 25 between lot rows 0 and 1, looking west past building 6 (balconies,
         pilasters, ledges) with a low light from the north-east so they cast shadows;
  fig1c  the paper's own grammar (sec. 3) on one building (paper_figs/scenes/facade_one.scene),
         frontal, light from the upper left so windows, sills, door and plinth cast shadows.

For each NAME it writes OUT_DIR/facade_NAME.png (the figure) and OUT_DIR/facade_NAME.cmd (the
exact pgt command, paths relative to the repository root, plus the pgt summary it printed).
pgt facade renders facades and roofs but no ground (misses are sky), so unless --raw is given
the figure composites, behind the buildings by the EXR's depth channel, a ground plane y = 0,
shaded with pgt's own rule (albedo * (ambient + (1 - ambient) max(0, n.l)), the same point light, no
shadows) and encoded to sRGB as pgt does; pgt's own PNG is kept as OUT_DIR/facade_NAME.pgt.png.
Figures are rendered at 2x the size (2560x1440, 2 x 2 rays per pixel) and box-filtered down in
linear light against the moire of distant windows; --quick renders once at 640x360. About 14 s
of pgt time on 2 cores plus ~5 s of compositing. Bad input is a message on stderr and exit
status 2; a failing pgt run is reported with its stderr and exit status 1.
"""

import os
import shlex
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exrread import ExrError, read_exr  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figsetup  # noqa: E402,F401  (before matplotlib: config folder, Agg)
import matplotlib  # noqa: E402

import matplotlib.image as mpimg  # noqa: E402

TOP = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The views. camera: eye, look-at, up, vertical fov (pgt facade --camera); light: the point
# light (--light). Chosen on the saved scenes (pgt facade --save-scene) of each source.
VIEWS = [
    {
        "name": "fig1a",
        "title": "(a) 10K facades: --city 2500, paper grammar, self-shadowing",
        "source": ["--city", "2500", "--grammar", "grammars/facade.grammar", "--seed", "1"],
        # 260 m up, 170 m beyond the city's corner (0, 0), looking at lot (16, 16): the near
        # blocks fill the bottom, the far edge of the 1.5 km square meets the sky at the top
        "camera": "-120,260,-120,500,0,500,0,1,0,50",
        # far to the south-west and high: lights the -x and -z facades the camera sees
        "light": "-1000,1400,-500",
    },
    {
        "name": "fig1b",
        "title": "(b) macroscopic details: facade_rich.grammar at street level",
        "source": ["--city", "25", "--grammar", "grammars/facade_rich.grammar", "--seed", "1"],
        # eye 1.7 m up in the street z = 25 east of building 6 (x 30.6..51.6, z 30.7..53.9),
        # looking west and up: its +x and street facades on the left, buildings 1 and 2 of row 0
        # on the right, sky between
        "camera": "66,1.7,25,20,15,32,0,1,0,60",
        # north-east, 45 m up: grazing on building 6's +x facade, balconies and pillars cast
        # shadows towards the street
        "light": "80,45,70",
    },
    {
        "name": "fig1c",
        "title": "(c) the paper's grammar (sec. 3) on one building, frontal",
        "source": ["--scene", "paper_figs/scenes/facade_one.scene"],
        # 30 m in front of the facade z = 12 (x 0..22, 19.2 m high), at mid height
        "camera": "11,9.6,42,11,9.6,12,0,1,0,40",
        # upper left, in front: sills, frames and the plinth cast shadows down and to the right
        "light": "-30,40,30",
    },
]

# pgt facade's shading (ref_cpu/src/facade_render.c: PGT_FACADE_DEFAULT_AMBIENT, SKY).
AMBIENT = 0.25
SKY = np.array([0.62, 0.74, 0.88], np.float32)
# Composited context (linear albedo): the ground in asphalt.
GROUND = np.array([0.30, 0.30, 0.28], np.float32)


# Rays per pixel along each axis of the figures (not of --quick).
SUPERSAMPLE = 2


def die(msg, code=2):
    print(f"facade_city: error: {msg}", file=sys.stderr)
    sys.exit(code)


def camera_rays(cam, w, h):
    """Unit ray directions (h, w, 3) and the eye of pgt_facade_camera_ray (ref_cpu/src/facade.c)."""
    v = np.array([float(x) for x in cam.split(",")], np.float64)
    eye, at, up, fov = v[0:3], v[3:6], v[6:9], v[9]
    wv = eye - at
    wv /= np.linalg.norm(wv)
    u = np.cross(up, wv)
    u /= np.linalg.norm(u)
    vv = np.cross(wv, u)
    t = np.tan(np.radians(fov) * 0.5)
    sx = (2.0 * (np.arange(w) + 0.5) / w - 1.0) * t * (w / h)
    sy = (1.0 - 2.0 * (np.arange(h) + 0.5) / h) * t
    d = -wv[None, None, :] + sx[None, :, None] * u[None, None, :] + sy[:, None, None] * vv
    d /= np.linalg.norm(d, axis=2, keepdims=True)
    return eye, d


def read_scene(path):
    """[(base, height, footprint (k, 2) as x, z)] of a facade scene file (harness/README.md)."""
    out = []
    try:
        with open(path) as fh:
            for ln, line in enumerate(fh, 1):
                f = line.split("#", 1)[0].split()
                if not f or f[0] != "building":
                    continue
                colon = f.index(":")
                xz = np.array([float(x) for x in f[colon + 1:]], np.float64).reshape(-1, 2)
                out.append((float(f[2]), float(f[3]), xz))
    except (OSError, ValueError) as e:
        die(f"{path}: {e}")
    if not out:
        die(f"{path}: no buildings")
    return out


def inside(px, pz, poly):
    """Points (px, pz) inside the simple polygon poly (k, 2) (even-odd crossings)."""
    res = np.zeros(px.shape, bool)
    k = len(poly)
    for i in range(k):
        x0, z0 = poly[i]
        x1, z1 = poly[(i + 1) % k]
        cross = (z0 > pz) != (z1 > pz)
        with np.errstate(divide="ignore", invalid="ignore"):
            xi = x0 + (pz - z0) * (x1 - x0) / (z1 - z0)
        res ^= cross & (px < xi)
    return res


def shade(albedo, points, normal, light):
    lv = light[None, :] - points
    lv /= np.linalg.norm(lv, axis=1, keepdims=True)
    ndl = np.maximum(0.0, lv @ normal)
    return albedo[None, :] * (AMBIENT + (1.0 - AMBIENT) * ndl)[:, None]


def composite(exr, scene, cam, light):
    """Linear RGB (h, w, 3): pgt's frame with the ground wherever it is nearer (pgt renders the
    roofs itself; `scene` is kept for the layout's bounds)."""
    rgb = np.stack([exr["R"], exr["G"], exr["B"]], axis=2).astype(np.float64)
    depth = exr["depth"].astype(np.float64)
    h, w = depth.shape
    eye, d = camera_rays(cam, w, h)
    light = np.array([float(x) for x in light.split(",")], np.float64)
    up = np.array([0.0, 1.0, 0.0])
    best = depth.copy()
    best[~np.isfinite(best)] = np.inf
    out = rgb.copy()

    def plane(y, box, poly, albedo):
        # rays of the pixel box (x0, x1, y0, y1) meeting the plane at height y inside poly (None:
        # everywhere) in front of what is already there
        x0, x1, y0, y1 = box
        sd, sb = d[y0:y1, x0:x1], best[y0:y1, x0:x1]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (y - eye[1]) / sd[..., 1]
        m = (t > 0.0) & (t < sb)
        if not m.any():
            return
        ys, xs = np.nonzero(m)
        tt = t[ys, xs]
        p = eye[None, :] + tt[:, None] * sd[ys, xs]
        if poly is not None:
            ok = inside(p[:, 0], p[:, 2], poly)
            ys, xs, tt, p = ys[ok], xs[ok], tt[ok], p[ok]
        sb[ys, xs] = tt
        out[y0:y1, x0:x1][ys, xs] = shade(albedo, p, up, light)

    if eye[1] > 0.0:
        plane(0.0, (0, w, 0, h), None, GROUND)
    return out


def to_srgb8(c):
    c = np.clip(c, 0.0, 1.0)
    s = np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)
    return (255.0 * s + 0.5).astype(np.uint8)


def rel(path):
    return os.path.relpath(path, TOP) if os.path.isabs(path) else path


def main(argv):
    args, quick, raw, threads = [], False, False, None
    it = iter(argv)
    for a in it:
        if a == "--quick":
            quick = True
        elif a == "--raw":
            raw = True
        elif a == "--threads":
            threads = next(it, None)
            if threads is None or not threads.isdigit():
                die("--threads: expected a number")
        elif a.startswith("-"):
            die(f"unknown flag {a} (usage: facade_city.py PGT OUT_DIR [--quick] [--threads N] "
                "[--raw])")
        else:
            args.append(a)
    if len(args) != 2:
        die("usage: facade_city.py PGT OUT_DIR [--quick] [--threads N] [--raw]")
    pgt, out_dir = os.path.abspath(args[0]), os.path.abspath(args[1])
    if not os.access(pgt, os.X_OK):
        die(f"{pgt}: not an executable")
    os.makedirs(out_dir, exist_ok=True)
    w, h = (640, 360) if quick else (1280, 720)
    # pgt facade casts one ray per pixel; the figure is rendered at SUPERSAMPLE x the size and
    # box-filtered down in linear light (2 x 2 rays per pixel), against the moire of distant
    # windows; pgt's own PNG (facade_NAME.pgt.png) is the large frame as pgt wrote it
    ss = 1 if quick else SUPERSAMPLE
    w, h = w * ss, h * ss
    work = tempfile.mkdtemp(prefix="pgt_facade_city_")
    for v in VIEWS:
        name = v["name"]
        exr = os.path.join(work, f"{name}.exr")
        png = os.path.join(out_dir, f"facade_{name}.pgt.png")
        cmd = ["facade", *v["source"], "--camera", v["camera"], "--light", v["light"],
               "--shadows", "--width", str(w), "--height", str(h), "-o", exr, "--png", png]
        if threads:
            cmd += ["--threads", threads]
        scene_path = None
        if v["source"][0] == "--city":
            scene_path = os.path.join(work, f"{name}.scene")
            cmd += ["--save-scene", scene_path]
        else:
            scene_path = os.path.join(TOP, v["source"][1])
        run = subprocess.run([pgt, *cmd], cwd=TOP, capture_output=True, text=True)
        if run.returncode != 0:
            sys.stderr.write(run.stderr)
            die(f"pgt {' '.join(cmd)}: exit status {run.returncode}", 1)
        # temporary files by their base names, the rest relative to the repository root
        shown = ["pgt"] + [os.path.basename(c) if c.startswith(work + os.sep) else
                           rel(c) if os.path.isabs(c) else c for c in cmd]
        with open(os.path.join(out_dir, f"facade_{name}.cmd"), "w") as fh:
            fh.write(f"# {v['title']}\n# run from the repository root; the figure composites "
                     "ground (paper_figs/facade_city.py)\n")
            fh.write(" ".join(shlex.quote(c) for c in shown) + "\n")
            fh.write("".join(f"# {ln}\n" for ln in run.stdout.splitlines()))
        try:
            frame = read_exr(exr)
        except ExrError as e:
            die(str(e))
        if raw:
            rgb = np.stack([frame["R"], frame["G"], frame["B"]], axis=2)
        else:
            rgb = composite(frame, read_scene(scene_path), v["camera"], v["light"])
        if ss > 1:
            rgb = rgb.reshape(h // ss, ss, w // ss, ss, 3).mean(axis=(1, 3))
        mpimg.imsave(os.path.join(out_dir, f"facade_{name}.png"), to_srgb8(rgb))
        print(f"facade_city: {name}: {run.stdout.splitlines()[2] if run.stdout else ''}")
    for f in os.listdir(work):
        os.remove(os.path.join(work, f))
    os.rmdir(work)


if __name__ == "__main__":
    main(sys.argv[1:])
