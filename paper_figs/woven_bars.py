#!/usr/bin/python3
"""The woven sphere's timing table (paper 002, Figure 4.11) as a bar chart, from results/woven.csv
(written by `pgt bench woven`).

usage: woven_bars.py WOVEN_CSV OUT_PREFIX

Grouped bars (log y) of evaluation ms per frame for each resolution (5k .. 179k vertices): ours
at 1 thread and at the file's largest thread count (median; the minimum as a tick), and the
paper's four (direct C baseline, Houdini naive, Houdini suggested, LUNA; the paper names no
machine, the work is from 2010), with the issue's target (4 ms at 179k) as a dashed line over
that group (named in the legend, under the axes). Writes OUT_PREFIX.png (300 dpi, 7 in wide)
and OUT_PREFIX.pdf, and prints the ratios paper / ours (our median at the largest thread count, and at 1 thread) per resolution to stdout. A
missing, empty or malformed file is an error (exit 2).
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figsetup  # noqa: E402  (before matplotlib: config folder, Agg, sizes)
import matplotlib  # noqa: E402

import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import results_csv  # noqa: E402

REQUIRED = ("res", "vertices", "threads", "median_ms", "min_ms", "paper_baseline_ms",
            "paper_houdini_naive_ms", "paper_houdini_suggested_ms", "paper_luna_ms")
PAPER = (("paper_baseline_ms", "paper: baseline C"),
         ("paper_houdini_naive_ms", "paper: Houdini naive"),
         ("paper_houdini_suggested_ms", "paper: Houdini suggested"),
         ("paper_luna_ms", "paper: LUNA"))
# issue 7's performance target: the 179k model in at most 4 ms per frame on 2 cores
TARGET_RES, TARGET_MS = "179k", 4.0
# Okabe-Ito, colour-blind safe; ours in blues, the paper's in the other hues
COLOURS = {"ours1": "#56B4E9", "oursN": "#0072B2", "paper_baseline_ms": "#999999",
           "paper_houdini_naive_ms": "#D55E00", "paper_houdini_suggested_ms": "#E69F00",
           "paper_luna_ms": "#009E73"}


def die(msg):
    results_csv.die("woven_bars", msg)


def read_rows(path):
    """Returns (meta dict from '# key: value' lines, list of row dicts, numbers as floats)."""
    meta, _, lines = results_csv.read(path, "woven_bars", REQUIRED)
    rows = [r for _, r in lines]
    for r in rows:
        for col in REQUIRED[1:]:
            try:
                v = float(r[col])
            except (TypeError, ValueError):
                die(f"{path}: resolution {r.get('res')}: column {col}: not a number: "
                    f"{r.get(col)!r}")
            if col.endswith("_ms") and not v > 0:
                die(f"{path}: resolution {r['res']}: column {col}: {v} is not > 0")
            r[col] = v
    return meta, rows


def main():
    if len(sys.argv) != 3:
        die("usage: woven_bars.py WOVEN_CSV OUT_PREFIX")
    path, out = sys.argv[1:]
    meta, rows = read_rows(path)
    order = []
    for r in rows:
        if r["res"] not in order:
            order.append(r["res"])
    order.sort(key=lambda name: next(r["vertices"] for r in rows if r["res"] == name))
    tmax = max(r["threads"] for r in rows)
    ours = {}  # (res, threads) -> row
    for r in rows:
        ours[(r["res"], r["threads"])] = r
    series = [("ours1", "ours, 1 thread", 1.0)]
    if tmax > 1:
        series.append(("oursN", f"ours, {tmax:.0f} threads", tmax))
    n_bars = len(series) + len(PAPER)
    width = 0.8 / n_bars
    fig, ax = plt.subplots(figsize=(figsetup.TEXT_WIDTH, 4.6))
    xs = range(len(order))
    for k, (key, label, threads) in enumerate(series):
        pos, med, low = [], [], []
        for i, name in enumerate(order):
            r = ours.get((name, threads))
            if r is None:
                continue
            pos.append(i - 0.4 + width * (k + 0.5))
            med.append(r["median_ms"])
            low.append(r["min_ms"])
        if not pos:  # no legend entry for bars that are not there
            print(f"woven_bars: warning: {path}: no rows with {threads:g} thread(s)",
                  file=sys.stderr)
            continue
        ax.bar(pos, med, width, color=COLOURS[key], label=label + " (median; tick: min)")
        ax.scatter(pos, low, marker="_", color="black", s=40, lw=1, zorder=3)
        for x, y in zip(pos, med):
            ax.text(x, y * 1.08, f"{y:.2g}", ha="center", va="bottom", fontsize=figsetup.SMALL_PT,
                    rotation=90)
    for k, (col, label) in enumerate(PAPER, start=len(series)):
        pos = [i - 0.4 + width * (k + 0.5) for i in xs]
        vals = [next(r[col] for r in rows if r["res"] == name) for name in order]
        ax.bar(pos, vals, width, color=COLOURS[col], label=label)
    if TARGET_RES in order:  # the target, drawn over its resolution's group only
        i = order.index(TARGET_RES)
        # named in the legend: a label beside the line lay on the paper's bars
        ax.hlines(TARGET_MS, i - 0.45, i + 0.45, colors="black", linestyles="dashed", lw=0.8,
                  label=f"target: {TARGET_MS:g} ms at {TARGET_RES}")
    ax.set_yscale("log")
    ax.set_xticks(list(xs))
    ax.set_xticklabels([f"{name}\n{next(r['vertices'] for r in rows if r['res'] == name):,.0f} "
                        f"vertices" for name in order])
    ax.set_ylabel("evaluation time per frame (ms, log)")
    ax.set_title("Woven sphere (paper 002, App. A): ours vs Figure 4.11\n(log scale; the "
                 "paper's 2010 machine is not named)")
    ax.grid(axis="y", which="both", alpha=0.3)
    # under the axes (inside, at 7 in wide, it would cover the bars); the pad (in font sizes)
    # clears the two-line tick labels
    ax.legend(frameon=False, ncol=3, loc="upper center", bbox_to_anchor=(0.5, 0.0),
              borderaxespad=3.6, columnspacing=1.2)
    ax.set_ylim(top=ax.get_ylim()[1] * 2)  # room for the rotated labels of the tallest bars
    foot = ", ".join(results_csv.footnote(meta))
    figsetup.layout(fig, figsetup.footnote(fig, foot) if foot else None)
    figsetup.save(fig, out, die)

    cols = [label.replace("paper: ", "") for _, label in PAPER]
    print("woven_bars: ratios paper / ours (our median ms per frame; > 1: ours is faster)")
    print(f"  {'res':>5} {'threads':>7} {'ours ms':>8} " + " ".join(f"{c:>17}" for c in cols))
    for name in order:
        for _, _, threads in series:
            r = ours.get((name, threads))
            if r is None:
                continue
            ratios = " ".join(f"{r[col] / r['median_ms']:>16.1f}x" for col, _ in PAPER)
            print(f"  {name:>5} {threads:>7.0f} {r['median_ms']:>8.3f} {ratios}")
    print(f"woven_bars: wrote {out}.png and {out}.pdf")


if __name__ == "__main__":
    main()
