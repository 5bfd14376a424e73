#!/usr/bin/python3
"""The city table of paper 003 (results/facade.csv, `pgt bench facade`) as a figure.

usage: facade_bench.py results/facade.csv OUT_PREFIX

Three panels, stacked, against the number of facades (log x), one line per resolution: ms per frame
(median, log; ours solid, the fastest of ours as a tick), Mrays/s of ours and of Embree on the
explicit twin, same rays and threads (the faster of its two modes), and the bytes of the
procedural representation against Embree's (BVH + buffers) and the explicit twin's arrays
(log). Mrays/s: ours without shading (ours_trace_mrays: the same work as Embree's rays, hits
stored per pixel) solid, ours shaded dotted, when the CSV has both. The paper's row (source=paper: 10K facades, 1280x720 on a GTX 480, ~650 KB vs ~400 MB)
is drawn as a star in each panel where it has a number, and the issue's 143 ms target (7 fps)
is dashed. Footnote: machine, commit and date of the CSV's header. Writes OUT_PREFIX.png
(300 dpi, 7 in wide) and OUT_PREFIX.pdf; on stdout the ours / Embree speed and memory ratios
per row. Bad input is a message on stderr and exit status 2.
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figsetup  # noqa: E402  (before matplotlib: config folder, Agg, sizes)
import matplotlib  # noqa: E402

import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import results_csv  # noqa: E402

REQUIRED = ("source", "facades", "width", "height", "ms", "ours_mrays", "embree_mrays",
            "procedural_bytes", "embree_bytes", "explicit_bytes")
# The frame-time target for the 10K-facade city at 1280x720 on 2 cores (the paper's
# 7 fps).
TARGET_MS = 143.0
COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown")


def die(msg):
    results_csv.die("facade_bench", msg)


def num(row, key, path, line):
    v = row.get(key, "")
    if v is None or v.strip() == "":
        return None
    try:
        x = float(v)
    except ValueError:
        die(f"{path}:{line}: column {key}: '{v}' is not a number")
    if not (math.isfinite(x) and x > 0):
        print(f"facade_bench: warning: {path}:{line}: column {key}: '{v}' is not a positive "
              f"number, left out", file=sys.stderr)
        return None
    return x


def read(path):
    meta, _, rows = results_csv.read(path, "facade_bench", REQUIRED)
    ours, paper = [], []
    for ln, row in rows:
        w, h = row["width"].strip(), row["height"].strip()
        if not (w.isdigit() and h.isdigit() and int(w) > 0 and int(h) > 0):
            die(f"{path}:{ln}: width '{w}' and height '{h}' are not whole numbers > 0")
        r = {"line": ln, "source": row["source"].strip(), "res": f"{w}x{h}"}
        for k in REQUIRED[1:]:
            if k not in ("width", "height"):
                r[k] = num(row, k, path, ln)
        r["ms_min"] = num(row, "ms_min", path, ln)
        r["ours_trace_mrays"] = num(row, "ours_trace_mrays", path, ln)
        r["best_over_embree"] = num(row, "best_over_embree", path, ln)
        if r["facades"] is None:
            die(f"{path}:{ln}: no facades")
        (paper if r["source"] == "paper" else ours).append(r)
    if not ours:
        die(f"{path}: no rows of ours (source=ours)")
    if not any(r["ms"] for r in ours):
        die(f"{path}: no ms per frame in any row of ours: nothing to plot")
    return meta, ours, paper


def main(argv):
    if len(argv) != 2:
        die("usage: facade_bench.py results/facade.csv OUT_PREFIX")
    path, out = argv
    meta, ours, paper = read(path)
    resolutions = sorted({r["res"] for r in ours},
                         key=lambda s: int(s.split("x")[0]) * int(s.split("x")[1]))
    # stacked, each legend right of its panel: side by side the figure was 13.5 in wide
    fig, (a_ms, a_mr, a_mem) = plt.subplots(3, 1, figsize=(figsetup.TEXT_WIDTH, 7.8))
    for i, res in enumerate(resolutions):
        rows = sorted((r for r in ours if r["res"] == res), key=lambda r: r["facades"])
        c = COLOURS[i % len(COLOURS)]
        pts = [(r["facades"], r["ms"]) for r in rows if r["ms"]]
        if pts:
            a_ms.plot(*zip(*pts), "-o", color=c, label=f"ours {res}")
        mins = [(r["facades"], r["ms_min"]) for r in rows if r["ms_min"]]
        if mins:
            a_ms.plot(*zip(*mins), "_", color=c, markersize=10)
        traced = any(r["ours_trace_mrays"] for r in rows)
        for key, style, who in (("ours_trace_mrays", "-o", "ours, hits only"),
                                ("ours_mrays", ":.", "ours, shaded" if traced else "ours"),
                                ("embree_mrays", "--s", "Embree")):
            pts = [(r["facades"], r[key]) for r in rows if r[key]]
            if pts:
                a_mr.plot(*zip(*pts), style, color=c, label=f"{who} {res}")
    # memory does not depend on the resolution: one line per city (first row of each)
    seen = {}
    for r in ours:
        seen.setdefault(r["facades"], r)
    cities = [seen[k] for k in sorted(seen)]
    for key, style, c, label in (
            ("procedural_bytes", "-o", "tab:blue", "ours (procedural)"),
            ("explicit_bytes", ":^", "tab:gray", "explicit twin (arrays)"),
            ("embree_bytes", "--s", "tab:red", "Embree (BVH + buffers)")):
        pts = [(r["facades"], r[key]) for r in cities if r[key]]
        if pts:
            a_mem.plot(*zip(*pts), style, color=c, label=label)
    for p in paper:
        tag = f"paper 003 ({p['res']}, GTX 480)"
        if p["ms"]:
            a_ms.plot(p["facades"], p["ms"], "*", color="k", markersize=12, label=tag)
        if p["ours_mrays"]:
            a_mr.plot(p["facades"], p["ours_mrays"], "*", color="k", markersize=12, label=tag)
        if p["procedural_bytes"]:
            a_mem.plot(p["facades"], p["procedural_bytes"], "*", color="k", markersize=12,
                       label="paper: procedural")
        if p["explicit_bytes"]:
            a_mem.plot(p["facades"], p["explicit_bytes"], "*", color="0.5", markersize=12,
                       label="paper: explicit (with normals, UVs)")
    a_ms.axhline(TARGET_MS, color="k", ls="--", lw=0.8)
    a_ms.text(min(r["facades"] for r in ours), TARGET_MS * 1.06,
              "143 ms target (7 fps, 10K facades, 1280x720)", fontsize=figsetup.SMALL_PT)
    a_ms.set(xscale="log", yscale="log", xlabel="facades", ylabel="ms per frame (median)",
             title="frame time, 1 ray per pixel")
    a_mr.set(xscale="log", xlabel="facades", ylabel="Mrays/s",
             title="throughput, same rays and threads")
    a_mem.set(xscale="log", yscale="log", xlabel="facades", ylabel="bytes",
              title="memory")
    # room for the target's label above its line and for the legend below the lines
    lowest = min(v for r in ours for v in (r["ms"], r["ms_min"]) if v)
    a_ms.set_ylim(bottom=lowest / 3.0, top=TARGET_MS * 1.6)
    for a in (a_ms, a_mr, a_mem):
        a.grid(True, which="both", lw=0.3, alpha=0.5)
        # beside the panel: inside it a legend covered the data (the 1000-facade throughput)
        a.legend(loc="center left", bbox_to_anchor=(1.02, 0.5), frameon=False)
    title = figsetup.suptitle(fig, "Per-pixel procedural facades (paper 003 sec. 9) vs Embree "
                              "on the explicit geometry,\ngenerated cities")
    foot = figsetup.footnote(fig, "; ".join(results_csv.footnote(meta)
                                            + [f"pgt bench facade ({path})"]))
    figsetup.layout(fig, foot, title, h_pad=0.8)
    figsetup.save(fig, out, die)
    print(f"{'facades':>8} {'res':>10} {'ms':>9} {'ours Mr/s':>9} {'hits only':>9} "
          f"{'Embree':>8} {'ours/Embree':>11} {'fastest':>7} {'Embree/ours bytes':>17}")
    for r in sorted(ours, key=lambda r: (r["res"], r["facades"])):
        mine = r["ours_trace_mrays"] or r["ours_mrays"]
        sp = mine / r["embree_mrays"] if mine and r["embree_mrays"] else 0
        mem = r["embree_bytes"] / r["procedural_bytes"] if r["embree_bytes"] and \
            r["procedural_bytes"] else 0
        print(f"{r['facades']:8.0f} {r['res']:>10} {r['ms'] or 0:9.1f} "
              f"{r['ours_mrays'] or 0:9.2f} {r['ours_trace_mrays'] or 0:9.2f} "
              f"{r['embree_mrays'] or 0:8.2f} {sp:11.2f} {r['best_over_embree'] or 0:7.2f} "
              f"{mem:17.0f}")


if __name__ == "__main__":
    main(sys.argv[1:])
