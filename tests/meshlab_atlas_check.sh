#!/bin/sh
# Check of datasets_gen/meshlab_atlas.sh (issue 4 item 8): MeshLab's "Parametrization: Voronoi
# Atlas" on the two shared meshes without UVs (mountain.obj, nefertiti-lowres.obj).
#
# Usage: meshlab_atlas_check.sh [MESH_DIR] [--regions N] [--keep DIR]
#   MESH_DIR  default $PGT_SHARED_MESH_DIR, else ../shared/datasets/meshes beside the repo
#   N         passed to the wrapper (default: the wrapper's default)
#   DIR       keep the atlased OBJs there (default: a temporary folder, removed)
# For each mesh, asserts with /usr/bin/python3 + numpy on the OBJ the wrapper writes:
#   - as many faces as the input, every face with three vt indices, every UV in [0,1];
#   - 2..500 UV charts (faces joined across an edge whose two corners carry the same vt pair);
#   - no two charts overlap: the UV triangles rasterized at 512x512, counting a texel for a
#     triangle only when its centre is strictly inside, so charts that merely share a boundary
#     do not count; no texel may belong to two charts;
#   - total UV area (sum of |UV triangle areas|) > 20 % of [0,1]^2.
# and prints INFO lines that are not asserted: mirrored charts, flipped faces, non-disk charts,
# texels covered twice inside one chart (fold-overs), the spread of the UV/3D area ratio.
# A negative check: a missing input gives exit 2 and exactly one line on stderr.
# Then pgt on the two atlased meshes (with PGT_CLI, PGT_TEST_ATLAS, PGT_TEST_MARCH set; see below):
# pgt atlas through the CLI, test_atlas voronoi_atlases and test_march real_random_marches.
# Prints PASS/FAIL lines and TIME lines (wall ms of the wrapper per mesh); exit 0 if all pass,
# 1 otherwise, 77 (skip) when meshlabserver or xvfb-run is missing, except under CI=true where
# that is a failure.
set -u

here=$(cd "$(dirname "$0")" && pwd)
wrapper=$here/../datasets_gen/meshlab_atlas.sh
meshes=${PGT_SHARED_MESH_DIR:-$here/../../shared/datasets/meshes}
regions_opt='' keep=''
while [ $# -gt 0 ]; do
    case $1 in
    --regions) [ $# -ge 2 ] || { echo "usage: $0 [MESH_DIR] [--regions N] [--keep DIR]" >&2; exit 1; }
        regions_opt=$2; shift 2 ;;
    --keep) [ $# -ge 2 ] || { echo "usage: $0 [MESH_DIR] [--regions N] [--keep DIR]" >&2; exit 1; }
        keep=$2; shift 2 ;;
    -*) echo "usage: $0 [MESH_DIR] [--regions N] [--keep DIR]" >&2; exit 1 ;;
    *) meshes=$1; shift ;;
    esac
done

for cmd in xvfb-run meshlabserver; do
    if ! command -v "$cmd" >/dev/null 2>&1; then
        if [ "${CI:-}" = "true" ]; then echo "FAIL: $cmd not found under CI"; exit 1; fi
        echo "SKIP: $cmd not found (apt-get install meshlab xvfb xauth)"
        exit 77
    fi
done
if ! /usr/bin/python3 -c 'import numpy' 2>/dev/null; then
    echo "FAIL: /usr/bin/python3 with numpy is needed"
    exit 1
fi

tmp=$(mktemp -d "${TMPDIR:-/tmp}/pgt_atlas_check.XXXXXX") || exit 1
trap 'rm -rf "$tmp"' EXIT
trap 'exit 1' HUP INT TERM
outdir=${keep:-$tmp}
mkdir -p "$outdir" || exit 1

fails=0
pass() { echo "PASS: $*"; }
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
ms_now() { t=$(date +%s%N); echo $((t / 1000000)); }

# --- negative check: a missing input ----------------------------------------------------------
rc=0
"$wrapper" "$tmp/no_such_mesh.obj" "$tmp/never.obj" >"$tmp/neg.out" 2>"$tmp/neg.err" || rc=$?
nerr=$(wc -l <"$tmp/neg.err")
if [ "$rc" -eq 2 ] && [ "$nerr" -eq 1 ] && [ ! -s "$tmp/neg.out" ] && [ ! -e "$tmp/never.obj" ]; then
    pass "missing input: exit 2, one line on stderr ($(cat "$tmp/neg.err"))"
else
    fail "missing input: exit $rc, $nerr stderr lines (want exit 2 and 1 line)"
    cat "$tmp/neg.err"
fi

# --- the analyzer (also self-tests its rasterizer on a synthetic atlas) ------------------------
cat >"$tmp/check.py" <<'PY'
import sys
import numpy as np

RES = 512


def load_obj(path):
    v, vt, f, ft = [], [], [], []
    with open(path) as fh:
        for line in fh:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                v.append(t[1:4])
            elif t[0] == "vt":
                vt.append(t[1:3])
            elif t[0] == "f":
                c = [x.split("/") for x in t[1:]]
                f.append([int(x[0]) for x in c])
                ft.append([int(x[1]) if len(x) > 1 and x[1] else 0 for x in c])
    return np.array(v, float).reshape(-1, 3), np.array(vt, float).reshape(-1, 2), f, ft


def input_faces(path):
    n = 0
    with open(path) as fh:
        for line in fh:
            if line.startswith("f "):
                n += len(line.split()) - 3  # a polygon fans into n-2 triangles
    return n


def charts_of(F, FT):
    """Union-find over faces; two faces join across an edge when they share the position edge and
    carry the same vt index at each of its two ends."""
    n = len(F)
    parent = list(range(n))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    seen = {}
    for fi in range(n):
        for k in range(3):
            a, b = F[fi][k], F[fi][(k + 1) % 3]
            ta, tb = FT[fi][k], FT[fi][(k + 1) % 3]
            key = (a, b, ta, tb) if a < b else (b, a, tb, ta)
            g = seen.setdefault(key, fi)
            if g != fi:
                ra, rb = find(fi), find(g)
                if ra != rb:
                    parent[ra] = rb
    roots = np.array([find(i) for i in range(n)])
    _, chart = np.unique(roots, return_inverse=True)
    return chart


def raster(uv, sa, chart, res=RES):
    """(texel, chart) pairs and (texel, face) pairs for texel centres strictly inside a
    non-degenerate UV triangle."""
    P = uv * res
    x0 = np.maximum(np.floor(P[:, :, 0].min(1) - 0.5).astype(np.int64) + 1, 0)
    x1 = np.minimum(np.ceil(P[:, :, 0].max(1) - 0.5).astype(np.int64) - 1, res - 1)
    y0 = np.maximum(np.floor(P[:, :, 1].min(1) - 0.5).astype(np.int64) + 1, 0)
    y1 = np.minimum(np.ceil(P[:, :, 1].max(1) - 0.5).astype(np.int64) - 1, res - 1)
    w, h = x1 - x0 + 1, y1 - y0 + 1
    m = np.maximum(w, h)
    good = (w > 0) & (h > 0) & (sa != 0)
    texs, faces = [], []
    lo = 0
    K = 1
    while lo < res:
        idx = np.nonzero(good & (m > lo) & (m <= K))[0]
        ox, oy = np.meshgrid(np.arange(K), np.arange(K))
        ox, oy = ox.ravel(), oy.ravel()
        step = max(1, 4000000 // (K * K))
        for s in range(0, len(idx), step):
            i = idx[s:s + step]
            cx, cy = x0[i, None] + ox, y0[i, None] + oy
            ok = (cx <= x1[i, None]) & (cy <= y1[i, None])
            px, py = cx + 0.5, cy + 0.5
            A = P[i]
            sg = np.sign(sa[i])[:, None]
            for (p, q) in ((0, 1), (1, 2), (2, 0)):
                ax, ay = A[:, p, 0][:, None], A[:, p, 1][:, None]
                bx, by = A[:, q, 0][:, None], A[:, q, 1][:, None]
                ok &= ((bx - ax) * (py - ay) - (by - ay) * (px - ax)) * sg > 0
            texs.append((cy * res + cx)[ok])
            faces.append(np.broadcast_to(i[:, None], ok.shape)[ok])
        lo, K = K, K * 2
    tex = np.concatenate(texs) if texs else np.zeros(0, np.int64)
    fac = np.concatenate(faces) if faces else np.zeros(0, np.int64)
    return tex, fac


def overlap_stats(uv, sa, chart, res=RES):
    nc = int(chart.max()) + 1
    tex, fac = raster(uv, sa, chart, res)
    pairs = np.unique(tex * (nc + 1) + chart[fac])
    per_texel = np.bincount(pairs // (nc + 1), minlength=res * res)
    covered = int((per_texel > 0).sum())
    between = int((per_texel > 1).sum())
    hits = np.bincount(tex, minlength=res * res)
    within = int(((hits > 1) & (per_texel == 1)).sum())  # one chart, two of its triangles
    return covered, between, within


def free_band(uv, sa, chart, res):
    tex, fac = raster(uv, sa, chart, res)
    ids = np.full(res * res, -1, np.int64)
    ids[tex] = chart[fac]
    ids = ids.reshape(res, res)
    for d in range(1, 6):  # another chart within Chebyshev distance d -> band d-1
        for dy in range(-d, d + 1):
            for dx in range(-d, d + 1):
                if max(abs(dx), abs(dy)) != d:
                    continue
                a = ids[max(dy, 0):res + min(dy, 0), max(dx, 0):res + min(dx, 0)]
                b = ids[max(-dy, 0):res + min(-dy, 0), max(-dx, 0):res + min(-dx, 0)]
                if ((a >= 0) & (b >= 0) & (a != b)).any():
                    return d - 1
    return 5


def signed_area(uv):
    return 0.5 * ((uv[:, 1, 0] - uv[:, 0, 0]) * (uv[:, 2, 1] - uv[:, 0, 1])
                  - (uv[:, 2, 0] - uv[:, 0, 0]) * (uv[:, 1, 1] - uv[:, 0, 1]))


def selftest():
    # two unit-ish squares (2 triangles each): side by side sharing an edge -> no overlap;
    # shifted onto each other -> overlap.
    def quad(x, y, s):
        a, b, c, d = (x, y), (x + s, y), (x + s, y + s), (x, y + s)
        return [[a, b, c], [a, c, d]]
    chart = np.array([0, 0, 1, 1])
    uv = np.array(quad(0.0, 0.0, 0.5) + quad(0.5, 0.0, 0.5), float)
    c1 = overlap_stats(uv, signed_area(uv), chart)
    uv2 = np.array(quad(0.0, 0.0, 0.5) + quad(0.25, 0.25, 0.5), float)
    c2 = overlap_stats(uv2, signed_area(uv2), chart)
    # one clockwise chart must rasterize like its mirror
    uv3 = uv.copy()
    uv3[2:, :, 0] = 1.5 - uv3[2:, :, 0]
    c3 = overlap_stats(uv3, signed_area(uv3), chart)
    # texel centres on a quad's diagonal are inside neither triangle: 2 x 256 of them in c1
    return (c1 == (RES * RES // 2 - RES, 0, 0) and c2[1] == (RES // 4) ** 2 - RES // 4
            and c3 == c1)


def main():
    inp, outp, name = sys.argv[1], sys.argv[2], sys.argv[3]
    res = []

    def check(ok, what):
        res.append(ok)
        print(("PASS" if ok else "FAIL") + ": " + name + ": " + what)

    check(selftest(), "rasterizer self-test (shared edge: no overlap; shifted copy: overlap)")
    nin = input_faces(inp)
    V, VT, F, FT = load_obj(outp)
    check(len(F) == nin, f"faces {len(F)} == input {nin}")
    tri = all(len(x) == 3 for x in F) and all(len(x) == 3 and min(x) >= 1 for x in FT)
    check(tri and len(VT) > 0, f"every face has 3 vt indices ({len(VT)} vt)")
    if not tri or len(VT) == 0 or len(F) == 0:
        return 1
    F = np.array(F, np.int64) - 1
    FT = np.array(FT, np.int64) - 1
    if FT.max() >= len(VT) or F.max() >= len(V):
        check(False, "indices in range")
        return 1
    uv = VT[FT]
    lo, hi = uv.min(axis=(0, 1)), uv.max(axis=(0, 1))
    check(bool((lo >= 0).all() and (hi <= 1).all()),
          f"UVs in [0,1] (u {lo[0]:.6f}..{hi[0]:.6f}, v {lo[1]:.6f}..{hi[1]:.6f})")
    chart = charts_of(F.tolist(), FT.tolist())
    nc = int(chart.max()) + 1
    sizes = np.bincount(chart)
    check(2 <= nc <= 500, f"charts {nc} in [2, 500] (faces per chart min {sizes.min()} "
          f"median {int(np.median(sizes))} max {sizes.max()})")
    sa = signed_area(uv)
    covered, between, within = overlap_stats(uv, sa, chart)
    check(between == 0, f"no texel of {RES}x{RES} in two charts ({between} overlapping texels)")
    area = float(np.abs(sa).sum())
    check(area > 0.20, f"UV area coverage {100 * area:.1f} % > 20 % "
          f"(rasterized: {100 * covered / RES / RES:.1f} % of texels)")
    # information, not asserted
    carea = np.bincount(chart, sa, nc)
    p = V[F]
    a3 = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    ratio = np.abs(sa) / np.where(a3 > 0, a3, np.nan)
    ratio = ratio[np.isfinite(ratio) & (ratio > 0)]
    r = ratio / np.median(ratio) if len(ratio) else ratio
    # chart topology: corners = (position, vt) pairs, edges = (position pair, vt pair)
    nondisk = 0
    ekeys = {}
    for fi in range(len(F)):
        for k in range(3):
            a, b = F[fi, k], F[fi, (k + 1) % 3]
            ta, tb = FT[fi, k], FT[fi, (k + 1) % 3]
            key = (a, b, ta, tb) if a < b else (b, a, tb, ta)
            ekeys.setdefault(key, chart[fi])
    ne = np.bincount(np.array(list(ekeys.values()), np.int64), minlength=nc)
    corners = np.unique(np.stack([np.repeat(chart, 3), F.ravel(), FT.ravel()], 1), axis=0)
    nvc = np.bincount(corners[:, 0], minlength=nc)
    euler = nvc - ne + sizes
    nondisk = int((euler != 1).sum())
    print(f"INFO: {name}: {len(V)} positions, {len(VT)} vt; mirrored charts "
          f"{int((carea < 0).sum())}, flipped faces {int((sa < 0).sum())}, zero-area UV faces "
          f"{int((sa == 0).sum())}, charts with Euler characteristic != 1: {nondisk}, "
          f"texels covered twice inside one chart: {within}")
    if len(r):
        q = np.percentile(r, [1, 5, 95, 99])
        print(f"INFO: {name}: UV/3D area ratio over its median: 1% {q[0]:.2f} 5% {q[1]:.2f} "
              f"95% {q[2]:.2f} 99% {q[3]:.2f}")
    # free band at 1024x1024 (issue 4 item 2): the smallest Chebyshev gap, in texels, between
    # texels (centre-sampled) of two different charts; 0 = they touch at that resolution
    band = free_band(uv, sa, chart, 1024)
    print(f"INFO: {name}: free band between charts at 1024x1024 (centre-sampled): "
          f"{band if band <= 4 else '> 4'} texel(s)")
    print(f"METRIC: {name} charts={nc} coverage={100 * area:.1f} overlap_texels={between} "
          f"within_chart_texels={within} faces={len(F)} positions={len(V)} vt={len(VT)}")
    return 0 if all(res) else 1


sys.exit(main())
PY

# --- the two meshes ---------------------------------------------------------------------------
made=''
for m in mountain nefertiti-lowres; do
    in=$meshes/$m.obj
    out=$outdir/$m.atlas.obj
    if [ ! -r "$in" ]; then fail "$m: $in not found"; continue; fi
    rm -f "$out"
    t0=$(ms_now)
    rc=0
    # shellcheck disable=SC2086 # regions_opt is empty or one word
    "$wrapper" "$in" "$out" ${regions_opt:+--regions $regions_opt} >"$tmp/$m.out" 2>"$tmp/$m.err" ||
        rc=$?
    t1=$(ms_now)
    if [ "$rc" -ne 0 ] || [ ! -s "$out" ]; then
        fail "$m: wrapper exit $rc"
        cat "$tmp/$m.err"
        continue
    fi
    pass "$m: wrapper exit 0: $(cat "$tmp/$m.out")"
    echo "TIME: $m $((t1 - t0)) ms (wrapper wall time: conversion, xvfb-run, MeshLab, checks)"
    /usr/bin/python3 "$tmp/check.py" "$in" "$out" "$m" >"$tmp/$m.py" 2>&1
    prc=$?
    cat "$tmp/$m.py"
    n=$(grep -c '^FAIL' "$tmp/$m.py")
    fails=$((fails + n))
    if [ "$prc" -ne 0 ] && [ "$n" -eq 0 ]; then fail "$m: analyzer exit $prc"; fi
    made=${made:+$made:}$out
done

# --- pgt on the atlased meshes ("so nefertiti-lowres and mountain get atlases too") -------------
# With PGT_CLI, PGT_TEST_ATLAS and PGT_TEST_MARCH set to the pgt, test_atlas and test_march binaries
# (ctest sets them, tests/CMakeLists.txt): pgt atlas builds each geometry image through the CLI,
# test_atlas's voronoi_atlases case checks the contract, the symmetry and the rotations, and
# test_march's real_random_marches case marches thousands of random walkers on them (the checks
# the shared UV meshes get). Unset (a run by hand): skipped with a line saying so.
if [ -z "$made" ]; then
    fail "no atlased mesh to give to pgt"
elif [ -z "${PGT_CLI:-}" ] || [ -z "${PGT_TEST_ATLAS:-}" ] || [ -z "${PGT_TEST_MARCH:-}" ]; then
    echo "INFO: PGT_CLI, PGT_TEST_ATLAS or PGT_TEST_MARCH not set: pgt atlas and the atlas and march" \
        "checks on the atlased meshes skipped"
else
    for out in $(echo "$made" | tr ':' ' '); do
        rc=0
        "$PGT_CLI" atlas "$out" -o "$tmp/atlas.exr" >"$tmp/pgt.out" 2>&1 || rc=$?
        if [ "$rc" -eq 0 ] && [ -s "$tmp/atlas.exr" ]; then
            pass "pgt atlas $(basename "$out"): $(grep -E '^  (charts|texels)' "$tmp/pgt.out" | tr -s ' ' | tr '\n' ';')"
        else
            fail "pgt atlas $(basename "$out"): exit $rc"
            cat "$tmp/pgt.out"
        fi
    done
    for t in "$PGT_TEST_ATLAS voronoi_atlases" "$PGT_TEST_MARCH real_random_marches"; do
        rc=0
        # shellcheck disable=SC2086 # a binary and a case name
        PGT_TEST_MESHES=$made $t >"$tmp/case.out" 2>&1 || rc=$?
        sed 's/^/  /' "$tmp/case.out"
        if [ "$rc" -eq 0 ]; then pass "$(basename "${t%% *}") ${t##* } on the atlased meshes"; else
            fail "$(basename "${t%% *}") ${t##* } on the atlased meshes: exit $rc"; fi
    done
fi

if [ "$fails" -eq 0 ]; then
    echo "PASS: meshlab_atlas_check"
    exit 0
fi
echo "FAIL: meshlab_atlas_check ($fails failures)"
exit 1
