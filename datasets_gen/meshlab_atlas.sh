#!/bin/sh
# pgt datasets_gen: give a mesh without UVs a multi-chart atlas with MeshLab 2020.09's
# "Parametrization: Voronoi Atlas" filter (vcglib VoronoiAtlas: geodesic Voronoi regions from
# Poisson-disk seeds, each region that is a disk flattened by vcglib's PoissonSolver ("Harmonic
# Mapping" in MeshLab's words), regions that are not disks or fold over more than 10 % of their
# faces split again; the charts packed as oriented rectangles into [0,1]^2, touching: no free band
# between them), run headless through xvfb-run + meshlabserver. The result is deterministic: the
# same input and N give the same bytes (also whichever of OBJ, OFF, PLY or PGT feeds MeshLab).
#
# Usage: meshlab_atlas.sh IN OUT.obj [--regions N] [--keep-log LOG] [--timeout S]
#   IN:   .obj, .off, .ply or .stl; a closed or bordered 2-manifold (the filter refuses
#         non-manifold meshes). meshlabserver cannot import OBJ in this build, so an OBJ is first
#         converted to an ASCII PLY by a small awk converter (`v` and `f` lines only; polygons are
#         fanned into triangles; v/vt/vn and negative indices are understood). With the
#         environment variable PGT set to a pgt binary, `$PGT subdiv IN --iters 0 -o tmp.ply` does
#         that conversion instead.
#   OUT:  the atlased mesh, an OBJ with per-corner texture coordinates (`f v/vt`), written to a
#         temporary file in OUT's folder and renamed: OUT is never left half-written.
#   N:    the filter's regionNum ("Approx. Region Num"), default 50: disk-like charts, no overlap,
#         about half of [0,1]^2 covered on mountain.obj and nefertiti-lowres.obj (see
#         datasets_gen/README.md). MeshLab may generate a few more or fewer regions than asked.
#   LOG:  also write the cleaned MeshLab log (printable ASCII only) to LOG, on success or failure.
#   S:    seconds before meshlabserver is killed, default 300 (a run on these meshes takes 1-3 s;
#         the filter can loop forever, e.g. nefertiti-lowres with --regions 100).
# Prints one line on success:
#   meshlab_atlas: OUT V vertices F faces VT texcoords R regions (N asked) MeshLab VERSION T ms
# (VERSION is the Debian package's, e.g. 2020.09+dfsg1-2; R is what the filter reports.)
#
# What changes: the faces and vertices come out in MeshLab's order (region by region), not the
# input's; vertices with equal positions are merged (MeshLab's RemoveDuplicateVertex), so V can
# be smaller than IN's vertex count when IN has coincident vertices; positions are printed with
# six decimals ("%f"), from floats. The `mtllib`/`usemtl` lines MeshLab writes (a dummy material)
# are dropped and no .mtl file is written. The face count is checked against what MeshLab loaded:
# the filter silently drops a bad region of at most 50 faces (nefertiti-lowres with --regions 150
# loses 6 faces), and that is a failure here (try another --regions).
#
# Exit: 0 success; 2 on any failure (bad arguments, unreadable or unconvertible input,
# meshlabserver failure, output without texture coordinates or with a different face count),
# with one line on stderr, followed for MeshLab failures by the cleaned `LOG:` lines of its log.
set -eu

prog=meshlab_atlas.sh
die() { echo "$prog: $*" >&2; exit 2; }
usage() { echo "usage: $prog IN OUT.obj [--regions N] [--keep-log LOG] [--timeout S]" >&2; exit 2; }

in='' out='' regions=50 keeplog='' limit=300
while [ $# -gt 0 ]; do
    case $1 in
    --regions)
        [ $# -ge 2 ] || usage
        case $2 in '' | *[!0-9]*) die "--regions needs an integer from 1 to 100000" ;; esac
        { [ "${#2}" -le 6 ] && [ "$2" -ge 1 ] && [ "$2" -le 100000 ]; } 2>/dev/null ||
            die "--regions needs an integer from 1 to 100000"
        regions=$(printf '%s' "$2" | sed 's/^0*//')
        shift 2 ;;
    --timeout)
        [ $# -ge 2 ] || usage
        case $2 in '' | *[!0-9]*) die "--timeout needs a number of seconds from 1 to 86400" ;; esac
        { [ "${#2}" -le 5 ] && [ "$2" -ge 1 ] && [ "$2" -le 86400 ]; } 2>/dev/null ||
            die "--timeout needs a number of seconds from 1 to 86400"
        limit=$(printf '%s' "$2" | sed 's/^0*//')
        shift 2 ;;
    --keep-log)
        [ $# -ge 2 ] && [ -n "$2" ] || usage
        keeplog=$2
        shift 2 ;;
    -*) die "unknown option $1 (usage: $prog IN OUT.obj [--regions N] [--keep-log LOG] [--timeout S])" ;;
    *)
        if [ -z "$in" ]; then in=$1; elif [ -z "$out" ]; then out=$1; else usage; fi
        shift ;;
    esac
done
if [ -z "$in" ] || [ -z "$out" ]; then usage; fi

if [ ! -f "$in" ] || [ ! -r "$in" ]; then die "$in: no such readable file"; fi
ein=$(printf '%s' "${in##*.}" | LC_ALL=C tr '[:upper:]' '[:lower:]')
case $ein in
obj | off | ply | stl) ;;
*) die "$in: unsupported extension (use .obj, .off, .ply or .stl)" ;;
esac
eout=$(printf '%s' "${out##*.}" | LC_ALL=C tr '[:upper:]' '[:lower:]')
[ "$eout" = obj ] || die "$out: the output must be an .obj (it carries the texture coordinates)"
outdir=$(dirname "$out")
[ -d "$outdir" ] && [ -w "$outdir" ] || die "$out: folder $outdir does not exist or is not writable"
absin=$(cd "$(dirname "$in")" && pwd)/$(basename "$in")
absout=$(cd "$outdir" && pwd)/$(basename "$out")
[ "$absin" != "$absout" ] || die "$out: the output must not be the input"

for cmd in xvfb-run meshlabserver timeout; do
    command -v "$cmd" >/dev/null 2>&1 || die "$cmd not found (apt-get install meshlab xvfb xauth)"
done

tmp=$(mktemp -d "${TMPDIR:-/tmp}/pgt_atlas.XXXXXX") || die "cannot create a temporary folder"
part=''
cleanup() { rm -rf "$tmp"; if [ -n "$part" ]; then rm -f "$part"; fi; }
trap cleanup EXIT
trap 'exit 2' HUP INT TERM
mkdir -m 700 "$tmp/xdg"

ms_now() { t=$(date +%s%N); echo $((t / 1000000)); }
t0=$(ms_now)

# --- input for MeshLab: OFF/PLY/STL as they are, OBJ converted to PLY -------------------------
if [ "$ein" = obj ]; then
    minput=in.ply
    if [ -n "${PGT:-}" ]; then
        [ -x "$PGT" ] || die "PGT=$PGT is not an executable pgt binary"
        "$PGT" subdiv "$in" --iters 0 -o "$tmp/in.ply" >"$tmp/pgt.txt" 2>&1 ||
            die "$in: '$PGT subdiv --iters 0' could not convert it: $(tail -n 1 "$tmp/pgt.txt")"
    else
        # ASCII PLY; coordinates are copied as text. Errors name the line.
        LC_ALL=C awk -v out="$tmp/in.ply" -v body="$tmp/faces.txt" '
            function bad(msg) { print FILENAME ":" NR ": " msg > "/dev/stderr"; err = 1; exit 1 }
            $1 == "v" {
                if (NF < 4) bad("a v line needs three coordinates")
                for (i = 2; i <= 4; ++i)
                    if ($i !~ /^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$/) bad("bad coordinate " $i)
                vx[++nv] = $2 " " $3 " " $4
                next
            }
            $1 == "f" {
                n = NF - 1
                if (n < 3) bad("a face needs at least three corners")
                for (i = 1; i <= n; ++i) {
                    s = $(i + 1); sub(/\/.*/, "", s)
                    if (s !~ /^-?[0-9]+$/) bad("bad vertex index " $(i + 1))
                    k = s + 0
                    if (k < 0) k = nv + 1 + k
                    if (k < 1 || k > nv) bad("vertex index " s " out of range (" nv " vertices so far)")
                    c[i] = k - 1
                }
                for (i = 2; i < n; ++i) { print "3 " c[1] " " c[i] " " c[i + 1] > body; ++nf }
                next
            }
            END {
                if (err) exit 1
                if (nf == 0) { print FILENAME ": no faces" > "/dev/stderr"; exit 1 }
                close(body)
                printf "ply\nformat ascii 1.0\ncomment pgt meshlab_atlas.sh\n" > out
                printf "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n", nv > out
                printf "element face %d\nproperty list uchar int vertex_indices\nend_header\n", nf > out
                for (i = 1; i <= nv; ++i) print vx[i] > out
                close(out)
            }' "$in" 2>"$tmp/conv.txt" && cat "$tmp/faces.txt" >>"$tmp/in.ply" ||
            die "cannot convert OBJ: $(head -n 1 "$tmp/conv.txt")"
    fi
else
    minput=in.$ein
    ln -s "$absin" "$tmp/$minput"
fi

# --- the filter script ------------------------------------------------------------------------
# XML names from MeshLab's filter_texture plugin (FP_VORONOI_ATLAS): regionNum (RichInt,
# "Approx. Region Num", default 10), overlapFlag (RichBool, default false: true duplicates a ring
# of faces around every region, which would change the face count).
cat >"$tmp/atlas.mlx" <<EOF
<!DOCTYPE FilterScript>
<FilterScript>
 <filter name="Parametrization: Voronoi Atlas">
  <Param name="regionNum" value="$regions" type="RichInt"/>
  <Param name="overlapFlag" value="false" type="RichBool"/>
 </filter>
</FilterScript>
EOF

# The filter writes a new layer (VoroAtlas): `-l x` saves the last layer, `-m wt` its wedge UVs.
# timeout runs inside xvfb-run, so a killed meshlabserver still lets xvfb-run stop its Xvfb.
rc=0
(cd "$tmp" && XDG_RUNTIME_DIR="$tmp/xdg" xvfb-run -a timeout -k 10 "$limit" meshlabserver \
    -i "$minput" -s atlas.mlx -l log.txt -o out.obj -l x -m wt) >"$tmp/out.txt" 2>&1 || rc=$?

# The log carries binary bytes; keep printable ASCII, tabs and line ends.
cat "$tmp/out.txt" "$tmp/log.txt" 2>/dev/null | tr -cd '\11\12\15\40-\176' >"$tmp/clean.txt" || true
if [ -n "$keeplog" ]; then cp "$tmp/clean.txt" "$keeplog" 2>/dev/null || die "$keeplog: cannot write the log"; fi

mlfail() { # one line, then the LOG lines (or the tail when there are none)
    echo "$prog: $in: $*" >&2
    if grep -q 'LOG:' "$tmp/clean.txt"; then
        sed -n 's/.*\(LOG: \)/\1/p' "$tmp/clean.txt" | awk '!seen[$0]++' >&2
    else
        tail -n 15 "$tmp/clean.txt" >&2
    fi
    exit 2
}

# meshlabserver prints its version only with its usage text; the package has it too.
version=$(dpkg-query -W -f '${Version}' meshlab 2>/dev/null) || version=''
# "Mesh /path/in.ply loaded has 25600 vn 50562 fn" (after MeshLab's own import).
fin=$(sed -n 's/.* loaded has \([0-9][0-9]*\) vn \([0-9][0-9]*\) fn.*/\2/p' "$tmp/clean.txt" | head -n 1)
generated=$(sed -n 's/.*Asked [0-9]* generated \([0-9][0-9]*\) regions.*/\1/p' "$tmp/clean.txt" | head -n 1)
[ "$rc" -ne 124 ] && [ "$rc" -ne 137 ] || mlfail "meshlabserver killed after $limit s (the filter may loop forever; try another --regions)"
# e.g. "Assertion `lx>0 && ly>0' failed." in vcglib's rect_packer.h (mountain, --regions 5)
assertion=$(grep -o "Assertion .* failed" "$tmp/clean.txt" | head -n 1) || assertion=''
if [ -n "$assertion" ]; then
    where=$(grep -o "[A-Za-z_0-9]*\.[ch]p*:[0-9]*: .*Assertion" "$tmp/clean.txt" | head -n 1 |
        sed 's/^\([^:]*:[0-9]*\):.*/\1/') || where=''
    assertion="${where:+$where: }$assertion"
fi
[ "$rc" -eq 0 ] || mlfail "meshlabserver failed (exit $rc)${assertion:+: $assertion}"
[ -n "$fin" ] || mlfail "meshlabserver did not load the mesh"
[ -n "$generated" ] || mlfail "the Voronoi Atlas filter did not run"
[ -s "$tmp/out.obj" ] || mlfail "meshlabserver wrote no OBJ"

# --- check and copy the OBJ (without the dummy material lines) --------------------------------
# a short name of its own (OUT's name may be up to 255 bytes, with no room for a suffix)
part=$(mktemp "$outdir/.pgt-meshlab.XXXXXX") || die "$out: cannot create a temporary file"
stats=$(LC_ALL=C awk -v part="$part" '
    $1 == "mtllib" || $1 == "usemtl" { next }
    { print > part }
    $1 == "v" { ++nv } $1 == "vt" { ++nvt }
    $1 == "f" {
        ++nf
        if (NF != 4) { ++nontri; next }
        for (i = 2; i <= 4; ++i) { n = split($i, p, "/"); if (n < 2 || p[2] == "") { ++notex; break } }
    }
    END { if (close(part) != 0) exit 1; printf "%d %d %d %d %d\n", nv, nvt, nf, nontri, notex }
' "$tmp/out.obj") || die "$out: cannot write"
set -- $stats
nv=$1 nvt=$2 nf=$3 nontri=$4 notex=$5
[ "$nvt" -gt 0 ] || mlfail "the output has no texture coordinates (vt lines)"
[ "$nf" -eq "$fin" ] || mlfail "the output has $nf faces, the input $fin (MeshLab drops small regions it cannot parametrize; try another --regions)"
[ "$nontri" -eq 0 ] || mlfail "the output has $nontri faces that are not triangles"
[ "$notex" -eq 0 ] || mlfail "the output has $notex faces without texture coordinates"
chmod 644 "$part" 2>/dev/null || true
mv -f "$part" "$out" || die "$out: cannot rename the temporary file"
part=''
t1=$(ms_now)
echo "meshlab_atlas: $out $nv vertices $nf faces $nvt texcoords $generated regions ($regions asked)" \
    "MeshLab ${version:-unknown} $((t1 - t0)) ms"
