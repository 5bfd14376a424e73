#!/usr/bin/python3
"""Figure 11 of paper 000 (ivy generation time vs number of seeds) from results/fig11.csv, and
Table 2 beside the paper's numbers from results/table2.csv (both written by `pgt bench ivy`).

usage: ivy_seeds.py FIG11_CSV TABLE2_CSV OUT_PREFIX

Top panel: median generation time (expand + Bezier + terminals, ms) against seeds 1..64 for the
two scenarios (main branch only, guided by painting; with secondary branches and leaves), with
the polygon count on a second axis. Bottom panel: Table 2, ours against the paper's GPU times
(a GTX 480 is named for Fig. 11 only) per scene, with the polygon counts as labels. Legends
under the panels. Writes OUT_PREFIX.png (300 dpi, 7 in wide) and OUT_PREFIX.pdf and prints the
growth of time with seeds (ms per added seed, least squares) to stdout. An empty or malformed
file is an error (exit 2).
"""

import os
import re
import sys
import textwrap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figsetup  # noqa: E402  (before matplotlib: config folder, Agg, sizes)
import matplotlib  # noqa: E402

import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import results_csv  # noqa: E402

# Okabe-Ito, colour-blind safe
COLOURS = {"main": "#0072B2", "full": "#D55E00", "paper": "#999999"}
LABELS = {"main": "main branch only (painted guidance)",
          "full": "with secondary branches and leaves"}


def die(msg):
    results_csv.die("ivy_seeds", msg)


def read_rows(path, required):
    meta, _, rows = results_csv.read(path, "ivy_seeds", required)
    return meta, [r for _, r in rows]


def fnum(row, col, path):
    try:
        return float(row[col])
    except (TypeError, ValueError):
        die(f"{path}: column {col}: not a number: {row.get(col)!r}")


def slope(xs, ys):
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx else 0.0


def main():
    if len(sys.argv) != 4:
        die("usage: ivy_seeds.py FIG11_CSV TABLE2_CSV OUT_PREFIX")
    f11, t2, out = sys.argv[1:]
    meta, rows = read_rows(f11, ("scenario", "seeds", "total_ms", "polygons", "threads"))
    _, table = read_rows(t2, ("scene", "mesh", "seeds", "polygons", "paper_polygons", "total_ms",
                              "paper_ms", "threads"))
    # stacked: side by side at 7 in, Table 2's scene names ran into each other
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(figsetup.TEXT_WIDTH, 7.2),
                                 gridspec_kw={"height_ratios": [3, 2]})
    ax2 = ax.twinx()
    for sc in ("main", "full"):
        pts = sorted((fnum(r, "seeds", f11), fnum(r, "total_ms", f11), fnum(r, "polygons", f11))
                     for r in rows if r["scenario"] == sc)
        if not pts:
            print(f"ivy_seeds: warning: {f11}: no rows of scenario '{sc}'", file=sys.stderr)
            continue
        xs, ts, ps = zip(*pts)
        ax.plot(xs, ts, "o-", ms=3, color=COLOURS[sc], label=LABELS[sc])
        ax2.plot(xs, [p / 1e6 for p in ps], ":", color=COLOURS[sc], lw=1,
                 label=f"{LABELS[sc]}: polygons (right axis)")
        print(f"ivy_seeds: {sc}: {slope(xs, ts):.2f} ms per added seed "
              f"({ts[0]:.1f} ms at {xs[0]:.0f} seed(s), {ts[-1]:.1f} ms at {xs[-1]:.0f})")
    threads = rows[0]["threads"]
    ax.set_xlabel("number of seeds")
    ax.set_ylabel(f"generation time (ms)\nmedian, {threads} CPU threads")
    ax2.set_ylabel("output polygons (millions, dotted)")
    ax.set_xlim(0, None)
    ax.set_ylim(0, None)
    ax2.set_ylim(0, None)
    ax.grid(alpha=0.3)
    lines, texts = ax.get_legend_handles_labels()
    lines2, texts2 = ax2.get_legend_handles_labels()
    # under the axes, the pad (in font sizes) clearing the x label: inside it lay on the lines
    ax.legend(lines + lines2, texts + texts2, loc="upper center", bbox_to_anchor=(0.5, 0.0),
              borderaxespad=4.0, ncol=2, frameon=False)
    ax.set_title("Generation time vs seeds (paper 000 Fig. 11)")

    # ours ran on a stand-in mesh; the paper's scene is named under it
    def paper_scene(r):  # "Fig. 1b (shack; painted guidance)" -> "Fig. 1b, shack"
        m = re.match(r"(.*?) \((.*?)[;)]", r.get("figure") or "")
        return f"{m.group(1)}, {m.group(2)}" if m else (r.get("figure") or r["scene"])

    names = [f"{r['mesh'].replace('.obj', '')}, {r['seeds']} seeds\n"
             + textwrap.fill(f"(paper: {paper_scene(r)})", 24) for r in table]
    ours = [fnum(r, "total_ms", t2) for r in table]
    paper = [fnum(r, "paper_ms", t2) for r in table]
    x = range(len(table))
    w = 0.38
    bx.bar([i - w / 2 for i in x], paper, w, color=COLOURS["paper"], label="paper (GPU; a GTX 480 is named for Fig. 11)")
    bx.bar([i + w / 2 for i in x], ours, w, color=COLOURS["full"],
           label=f"ours ({table[0]['threads']} CPU threads)")
    for i, r in enumerate(table):
        bx.text(i + w / 2, ours[i], f"{fnum(r, 'polygons', t2) / 1e6:.2f}M", ha="center",
                va="bottom", fontsize=figsetup.SMALL_PT)
        bx.text(i - w / 2, paper[i], f"{fnum(r, 'paper_polygons', t2) / 1e6:.2f}M", ha="center",
                va="bottom", fontsize=figsetup.SMALL_PT)
    bx.set_xticks(list(x))
    bx.set_xticklabels(names)
    bx.set_ylabel("generation time (ms)")
    bx.set_ylim(top=bx.get_ylim()[1] * 1.08)  # room for the tallest bar's label
    # under the axes too, clearing the three-line scene names
    bx.legend(frameon=False, loc="upper center", bbox_to_anchor=(0.5, 0.0), borderaxespad=4.6,
              ncol=2)
    bx.set_title("Table 2 (labels: output polygons)")
    foot = results_csv.footnote(meta)
    figsetup.layout(fig, figsetup.footnote(fig, ", ".join(foot)) if foot else None, h_pad=1.2)
    figsetup.save(fig, out, die)
    print(f"ivy_seeds: wrote {out}.png and {out}.pdf")


if __name__ == "__main__":
    main()
