"""Reading the tables `pgt bench` writes (results/*.csv) for the figure scripts.

A table is `# key: value` lines (machine, commit, date, and what the bench says about its runs),
then a CSV header and one row per line. `read` returns the header lines as a dict (keys in lower
case; the first of a repeated key wins), the header's names and the rows as (line number, dict);
a missing file, a table without rows, a missing required column or a row whose field count is
not the header's is an error that names the file and line (message on stderr, exit status 2),
so a figure is never drawn from a shifted column. `footnote` is the machine, commit and date a
figure prints under itself.
"""

import csv
import sys


def die(tool, msg):
    print(f"{tool}: error: {msg}", file=sys.stderr)
    sys.exit(2)


def read(path, tool, required=()):
    try:
        with open(path, newline="", encoding="utf-8", errors="replace") as f:
            lines = f.read().splitlines()
    except OSError as e:
        die(tool, f"{path}: {e.strerror}")
    meta, body = {}, []
    for ln, line in enumerate(lines, 1):
        s = line.strip()
        if s.startswith("#"):
            key, sep, val = s[1:].partition(":")
            if sep:
                meta.setdefault(key.strip().lower(), val.strip())
        elif s:
            body.append((ln, line))
    if not body:
        die(tool, f"{path}: no CSV header or rows (empty file, or only '#' lines)")
    hdr_ln, hdr_line = body[0]
    header = [h.strip() for h in next(csv.reader([hdr_line]))]
    missing = [c for c in required if c not in header]
    if missing:
        die(tool, f"{path}:{hdr_ln}: the CSV header has no column {', '.join(missing)}")
    rows = []
    for ln, line in body[1:]:
        cells = next(csv.reader([line]))
        if len(cells) != len(header):
            die(tool, f"{path}:{ln}: {len(cells)} fields, the header has {len(header)}")
        rows.append((ln, {h: c.strip() for h, c in zip(header, cells)}))
    if not rows:
        die(tool, f"{path}: a CSV header but no rows")
    return meta, header, rows


def footnote(meta):
    """["machine: ...", "commit: ...", "date: ..."], those the table has."""
    return [f"{k}: {meta[k]}" for k in ("machine", "commit", "date") if k in meta]
