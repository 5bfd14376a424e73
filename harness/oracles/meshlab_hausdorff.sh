#!/bin/sh
# pgt oracle: symmetric Hausdorff distance between two meshes by MeshLab 2020.09's "Hausdorff
# Distance" filter (vcglib HausdorffSampler), run headless through xvfb-run + meshlabserver.
#
# Usage: meshlab_hausdorff.sh A B [--samples N]
#   A, B: .off, .ply or .stl (MeshLab's OBJ importer asserts on every file in this build).
#   N:    face samples per direction; default 10 x the sampled mesh's face count. Every vertex
#         of the sampled mesh is also a sample.
# Prints one line:
#   hausdorff max=M ab_max=.. ba_max=.. ab_mean=.. ba_mean=.. diag=D
# where ab_* samples A and measures to B, ba_* the reverse, M = max(ab_max, ba_max) and D is A's
# bounding-box diagonal as MeshLab reports it.
# Exit: 0 success; 2 bad arguments or unreadable input; 1 meshlabserver failed (the cleaned tail
# of its log goes to stderr).
#
# Precision: MeshLab stores coordinates in float and prints these numbers with "%f", i.e. six
# decimals in the units of the mesh. Distances below about 1e-6 (or below float rounding of the
# coordinates) read as 0: this oracle checks shape, not last-bit agreement.
set -eu

prog=meshlab_hausdorff.sh
usage() { echo "usage: $prog A B [--samples N]" >&2; exit 2; }

a='' b='' samples=''
while [ $# -gt 0 ]; do
    case $1 in
    --samples)
        [ $# -ge 2 ] || usage
        case $2 in '' | *[!0-9]*) echo "$prog: --samples needs a positive integer" >&2; exit 2 ;; esac
        [ "$2" -ge 1 ] 2>/dev/null || { echo "$prog: --samples needs a positive integer" >&2; exit 2; }
        samples=$2
        shift 2 ;;
    -*) echo "$prog: unknown option $1" >&2; usage ;;
    *)
        if [ -z "$a" ]; then a=$1; elif [ -z "$b" ]; then b=$1; else usage; fi
        shift ;;
    esac
done
if [ -z "$a" ] || [ -z "$b" ]; then usage; fi

for cmd in xvfb-run meshlabserver; do
    command -v "$cmd" >/dev/null 2>&1 || { echo "$prog: $cmd not found (apt-get install meshlab xvfb xauth)" >&2; exit 1; }
done

# Lower-case extension of a path; refuses formats MeshLab cannot read here.
ext_of() {
    e=$(printf '%s' "${1##*.}" | LC_ALL=C tr '[:upper:]' '[:lower:]')
    case $e in
    off | ply | stl) printf '%s' "$e" ;;
    obj) echo "$prog: $1: MeshLab 2020.09 cannot import OBJ here; convert to OFF or PLY" >&2; exit 2 ;;
    *) echo "$prog: $1: unsupported extension (use .off, .ply or .stl)" >&2; exit 2 ;;
    esac
}

# Face count from the header (OFF counts line, PLY "element face"); empty if unknown (STL).
faces_of() {
    case $2 in
    off) LC_ALL=C head -c 65536 "$1" | LC_ALL=C awk '
        { sub(/#.*/, "") } NF == 0 { next }
        !hdr { hdr = 1; if ($1 != "OFF" && $1 !~ /OFF$/) exit; if (NF >= 3) { print $3; exit } next }
        { print $2; exit }' ;;
    ply) LC_ALL=C head -c 65536 "$1" | LC_ALL=C awk '
        $1 == "element" && $2 == "face" { print $3; exit } $1 == "end_header" { exit }' ;;
    esac
}

for f in "$a" "$b"; do
    if [ ! -f "$f" ] || [ ! -r "$f" ]; then echo "$prog: $f: no such readable file" >&2; exit 2; fi
done
ea=$(ext_of "$a") || exit 2
eb=$(ext_of "$b") || exit 2

samples_for() { # $1 file, $2 ext
    if [ -n "$samples" ]; then echo "$samples"; return; fi
    n=$(faces_of "$1" "$2")
    case $n in
    '' | *[!0-9]*) echo 100000 ;; # STL or an odd header: MeshLab will complain if it is broken
    *) [ "$n" -gt 0 ] && echo $((n * 10)) || echo 1000 ;;
    esac
}
na=$(samples_for "$a" "$ea")
nb=$(samples_for "$b" "$eb")

tmp=$(mktemp -d "${TMPDIR:-/tmp}/pgt_hausdorff.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
trap 'exit 1' HUP INT TERM
mkdir -m 700 "$tmp/xdg"

# MeshLab labels layers by file name and logs "on <sampled> searched closest on <target>": fixed
# link names make the two directions unambiguous even when A and B share a name.
ln -s "$(cd "$(dirname "$a")" && pwd)/$(basename "$a")" "$tmp/a.$ea"
ln -s "$(cd "$(dirname "$b")" && pwd)/$(basename "$b")" "$tmp/b.$eb"

# One filter per direction. MaxDist (an absolute-or-percent value that needs min and max) is huge
# so that no sample is clipped; edge samples are off because vertices and faces cover the surface.
filter() { # $1 sampled layer, $2 target layer, $3 samples
    cat <<EOF
 <filter name="Hausdorff Distance">
  <Param name="SampledMesh" value="$1" type="RichMesh"/>
  <Param name="TargetMesh" value="$2" type="RichMesh"/>
  <Param name="SaveSample" value="false" type="RichBool"/>
  <Param name="SampleVert" value="true" type="RichBool"/>
  <Param name="SampleEdge" value="false" type="RichBool"/>
  <Param name="SampleFauxEdge" value="false" type="RichBool"/>
  <Param name="SampleFace" value="true" type="RichBool"/>
  <Param name="SampleNum" value="$3" type="RichInt"/>
  <Param name="MaxDist" value="1e+30" min="0" max="1e+30" type="RichAbsPerc"/>
 </filter>
EOF
}
{
    echo '<!DOCTYPE FilterScript>'
    echo '<FilterScript>'
    filter 0 1 "$na"
    filter 1 0 "$nb"
    echo '</FilterScript>'
} >"$tmp/hausdorff.mlx"

rc=0
(cd "$tmp" && XDG_RUNTIME_DIR="$tmp/xdg" xvfb-run -a meshlabserver -i "a.$ea" -i "b.$eb" \
    -s hausdorff.mlx -l log.txt) >"$tmp/out.txt" 2>&1 || rc=$?

# The log carries binary bytes; keep printable ASCII, tabs and line ends.
cat "$tmp/log.txt" "$tmp/out.txt" 2>/dev/null | tr -cd '\11\12\15\40-\176' >"$tmp/clean.txt" || true

# Result blocks: "Sampled N pts (rng: 0) on a.off searched closest on b.off", then
# "min : x max y mean : z RMS : w", then "Values w.r.t. BBox Diag (d)" for the sampled mesh.
# The log repeats blocks; every copy is the same, the last one wins.
result=$(awk -v la="a.$ea" -v lb="b.$eb" '
    function num(s) { return s ~ /^[-+]?[0-9.]+([eE][-+]?[0-9]+)?$/ }
    /Sampled [0-9]+ pts/ && / searched closest on / {
        dir = ""
        if (index($0, " on " la " searched closest on " lb)) dir = "ab"
        else if (index($0, " on " lb " searched closest on " la)) dir = "ba"
        want = dir; next
    }
    want != "" && /min :/ && / max / && /mean :/ {
        for (i = 1; i < NF; ++i) {
            if ($i == "max" && num($(i + 1))) mx[want] = $(i + 1)
            if ($i == "mean" && $(i + 1) == ":" && num($(i + 2))) mean[want] = $(i + 2)
        }
        diagfor = want; want = ""; next
    }
    diagfor != "" && /Values w\.r\.t\. BBox Diag \(/ {
        s = $0; sub(/.*BBox Diag \(/, "", s); sub(/\).*/, "", s)
        if (num(s)) diag[diagfor] = s
        diagfor = ""
    }
    END {
        if (!("ab" in mx) || !("ba" in mx) || !("ab" in mean) || !("ba" in mean)) exit 1
        m = (mx["ab"] + 0 >= mx["ba"] + 0) ? mx["ab"] : mx["ba"]
        line = "hausdorff max=" m " ab_max=" mx["ab"] " ba_max=" mx["ba"] " ab_mean=" mean["ab"] \
               " ba_mean=" mean["ba"]
        if ("ab" in diag) line = line " diag=" diag["ab"]
        print line
    }' "$tmp/clean.txt") || result=

if [ "$rc" -ne 0 ] || [ -z "$result" ]; then
    echo "$prog: meshlabserver failed (exit $rc) or printed no Hausdorff result" \
        "(a.$ea is $a, b.$eb is $b); log tail:" >&2
    tail -n 25 "$tmp/clean.txt" >&2 || true
    exit 1
fi
echo "$result"
