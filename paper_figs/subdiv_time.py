#!/usr/bin/python3
"""sqrt(3) subdivision timing figure from results/subdiv.csv (written by `pgt bench subdiv`).

usage: subdiv_time.py RESULTS_CSV OUT_PREFIX

Plots median time (ms, log) against output faces (log) for ours at 1 thread, ours at the
largest thread count in the file, CGAL and OpenMesh; colour = implementation, marker = mesh.
Legends under the axes. Writes OUT_PREFIX.png (300 dpi, 7 in wide) and OUT_PREFIX.pdf, and
prints the speedups at each mesh's largest output to stdout. Missing optional columns and empty cells are skipped with a warning
on stderr; an empty or malformed file is an error (exit 2).
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figsetup  # noqa: E402  (before matplotlib: config folder, Agg, sizes)
import matplotlib  # noqa: E402

import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import results_csv  # noqa: E402

REQUIRED = ("mesh", "faces_out", "threads", "ours_median_ms")
ORACLES = (("cgal_median_ms", "CGAL"), ("openmesh_median_ms", "OpenMesh"))
# the GPU backends, whole call (upload, kernels, download) as a user sees it; optional columns
GPUS = (("cl_total_median_ms", "OpenCL"), ("vk_total_median_ms", "Vulkan"))
# colour-blind-safe (Okabe-Ito); one per implementation, so the same colour means the same
# code in every panel of the paper
COLOURS = {"ours1": "#56B4E9", "oursN": "#0072B2", "CGAL": "#D55E00", "OpenMesh": "#009E73",
           "OpenCL": "#CC79A7", "Vulkan": "#E69F00"}
MARKERS = "osD^v<>pPX*h"


def die(msg):
    results_csv.die("subdiv_time", msg)


def warn(msg):
    print(f"subdiv_time: warning: {msg}", file=sys.stderr)


def read_results(path):
    """Returns (meta dict from '# key: value' lines, header list, list of (line, row dict))."""
    return results_csv.read(path, "subdiv_time", REQUIRED)


def num(row, col, ln, path, empty, positive=True):
    """Float value of a cell, or None (empty, missing, bad, or <= 0 on a log axis)."""
    s = row.get(col, "")
    if s == "" or s.lower() in ("nan", "na", "n/a", "-"):
        empty.setdefault(col, set()).add(family(row.get("mesh", "")) or f"line {ln}")
        return None
    try:
        v = float(s)
    except ValueError:
        warn(f"{path}: line {ln}: column {col}: not a number {s!r}; skipped")
        return None
    if not math.isfinite(v) or (positive and v <= 0):
        warn(f"{path}: line {ln}: column {col}: {s} cannot go on a log axis; skipped")
        return None
    return v


def family(name):
    """Legend name of a mesh: a path or file name loses its directory and extension."""
    base = os.path.basename(name.replace("\\", "/"))
    root, ext = os.path.splitext(base)
    return root if ext.lower() in (".off", ".ply", ".obj") else base


def collect(path, header, rows):
    """series[key][mesh] = {faces_out: ms}; key in ours1, oursN, CGAL, OpenMesh."""
    empty = {}
    recs = []
    for ln, r in rows:
        mesh = r["mesh"]
        if not mesh:
            warn(f"{path}: line {ln}: empty mesh name; skipped")
            continue
        fo = num(r, "faces_out", ln, path, empty)
        th = num(r, "threads", ln, path, empty)
        if fo is None or th is None:
            continue
        recs.append((ln, r, family(mesh), fo, int(th)))
    if not recs:
        die(f"{path}: no row has usable mesh, faces_out and threads")

    tmax = max(t for *_, t in recs)
    series = {"ours1": {}, "oursN": {}, "CGAL": {}, "OpenMesh": {}, "OpenCL": {}, "Vulkan": {}}
    for ln, r, fam, fo, th in recs:
        if th in (1, tmax):
            ms = num(r, "ours_median_ms", ln, path, empty)
            if ms is not None:
                if th == 1:
                    series["ours1"].setdefault(fam, {})[fo] = ms
                if th == tmax and tmax != 1:
                    series["oursN"].setdefault(fam, {})[fo] = ms
        for col, key in ORACLES + GPUS:
            if col not in header:
                continue
            # the oracle time is repeated on every thread count's row: keep the first
            ms = num(r, col, ln, path, empty)
            if ms is not None:
                series[key].setdefault(fam, {}).setdefault(fo, ms)
    for col, key in ORACLES:
        if col not in header:
            warn(f"{path}: no column {col}; {key} not plotted")
    for col, where in sorted(empty.items()):
        warn(f"{path}: empty cells in column {col} (mesh {', '.join(sorted(where))}); "
             f"those points skipped")
    if not series["ours1"]:
        warn(f"{path}: no rows with threads = 1; the single-thread series is not plotted")
    if tmax == 1:
        warn(f"{path}: only 1-thread rows; no multi-thread series")
    return series, tmax


def plot(series, tmax, meta, out_prefix):
    fams = sorted({f for s in series.values() for f in s},
                  key=lambda f: max(max(s.get(f, {0: 0})) for s in series.values()))
    gpu_names = {"OpenCL": meta.get("cl", ""), "Vulkan": meta.get("vk", "")}
    labels = {"ours1": "ours, 1 thread", "oursN": f"ours, {tmax} threads",
              "CGAL": "CGAL", "OpenMesh": "OpenMesh"}
    for k, name in gpu_names.items():
        # "cl 0: Portable Computing Language / pthread-..." -> "ours, OpenCL (Portable ...)"
        dev = name.split(":", 1)[-1].split("/")[0].strip()
        # PoCL's pthread device and Mesa's llvmpipe/lavapipe run on the CPU: the label says so,
        # so that nobody reads them as GPU times
        on_cpu = any(w in name.lower() for w in ("pthread", "llvmpipe", "lavapipe", "cpu"))
        labels[k] = f"ours, {k}" + (f" ({dev[:28]}{', on the CPU' if on_cpu else ''})"
                                    if dev else "")
    styles = {"ours1": "-", "oursN": "-", "CGAL": "--", "OpenMesh": ":", "OpenCL": "-.",
              "Vulkan": "-."}

    fig, ax = plt.subplots(figsize=(figsetup.TEXT_WIDTH, 5.2))
    for key, per_mesh in series.items():
        for i, fam in enumerate(fams):
            pts = sorted(per_mesh.get(fam, {}).items())
            if not pts:
                continue
            x, y = zip(*pts)
            ax.plot(x, y, linestyle=styles[key], color=COLOURS[key],
                    marker=MARKERS[i % len(MARKERS)], markersize=4, linewidth=1.2,
                    markeredgecolor="white", markeredgewidth=0.5)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("Output faces")
    ax.set_ylabel("Median time (ms)")
    ax.set_title(r"$\sqrt{3}$ subdivision: time vs output faces")
    ax.grid(True, which="major", color="0.85", linewidth=0.6)
    ax.grid(True, which="minor", color="0.93", linewidth=0.4)
    ax.set_axisbelow(True)

    impl = [Line2D([], [], color=COLOURS[k], linestyle=styles[k], linewidth=1.4,
                   label=labels[k]) for k in series if series[k]]
    meshes = [Line2D([], [], color="0.35", linestyle="none", marker=MARKERS[i % len(MARKERS)],
                     markersize=4, label=f) for i, f in enumerate(fams)]
    # both legends under the axes (inside they hid points; beside them the figure was 9.7 in
    # wide): implementations in 3 columns, then the meshes in 4; the pads are in font sizes,
    # so they clear the tick labels and the x label whatever the axes' height
    leg1 = ax.legend(handles=impl, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=3,
                     title="Implementation", frameon=False, borderaxespad=4.0,
                     columnspacing=1.5)
    ax.add_artist(leg1)
    fig.canvas.draw()
    below = 4.0 + leg1.get_window_extent().height * 72 / fig.dpi / figsetup.SMALL_PT + 0.3
    ax.legend(handles=meshes, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=4,
              title="Mesh", frameon=False, borderaxespad=below, columnspacing=1.5)
    foot = [f[0].upper() + f[1:] for f in results_csv.footnote(meta)]
    if foot:
        foot = figsetup.footnote(fig, "    ".join(foot))
    else:
        foot = None
        warn("no '# machine:' or '# commit:' header lines; figure has no footnote")
    figsetup.layout(fig, foot)
    figsetup.save(fig, out_prefix, die)
    plt.close(fig)


def speedup_table(series, tmax):
    def fmt(v, spec):
        return "-" if v is None else format(v, spec)

    def ratio(other, ours):
        return "-" if other is None or ours is None else f"{other / ours:.2f}x"

    fams = sorted({f for s in series.values() for f in s})
    cols = ["mesh", "faces_out", "ours_1t_ms"]
    if tmax != 1:
        cols.append(f"ours_{tmax}t_ms")
    cols += ["cgal_ms", "openmesh_ms", "cgal/ours_1t", "openmesh/ours_1t"]
    if tmax != 1:
        cols += [f"cgal/ours_{tmax}t", f"openmesh/ours_{tmax}t"]
    out = []
    for fam in fams:
        fo = max(f for s in series.values() for f in s.get(fam, {}))
        o1 = series["ours1"].get(fam, {}).get(fo)
        oN = series["oursN"].get(fam, {}).get(fo)
        cg = series["CGAL"].get(fam, {}).get(fo)
        om = series["OpenMesh"].get(fam, {}).get(fo)

        row = [fam, f"{int(fo)}", fmt(o1, ".3g")]
        if tmax != 1:
            row.append(fmt(oN, ".3g"))
        row += [fmt(cg, ".3g"), fmt(om, ".3g"), ratio(cg, o1), ratio(om, o1)]
        if tmax != 1:
            row += [ratio(cg, oN), ratio(om, oN)]
        out.append(row)
    widths = [max(len(c), *(len(r[i]) for r in out)) for i, c in enumerate(cols)]
    print("Speedup at each mesh's largest output (other time / our time; >1 means ours is "
          "faster):")
    print("  ".join(c.rjust(w) if i else c.ljust(w) for i, (c, w) in enumerate(zip(cols, widths))))
    for r in out:
        print("  ".join(v.rjust(w) if i else v.ljust(w)
                        for i, (v, w) in enumerate(zip(r, widths))))


def main(argv):
    if len(argv) != 3 or argv[1] in ("-h", "--help"):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    path, out_prefix = argv[1], argv[2]
    meta, header, rows = read_results(path)
    series, tmax = collect(path, header, rows)
    if not any(series.values()):
        die(f"{path}: no plottable values")
    out_dir = os.path.dirname(out_prefix)
    if out_dir:
        os.makedirs(out_dir, exist_ok=True)
    plot(series, tmax, meta, out_prefix)
    speedup_table(series, tmax)
    print(f"wrote {out_prefix}.png and {out_prefix}.pdf", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
