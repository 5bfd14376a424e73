#!/usr/bin/env bash
# The cross-backend diff of every algorithm on every test mesh (pgt diff all: sqrt3 on the
# generated default datasets and the shared manifold meshes, k = 1..3, with and without protected
# faces; march on the cube-sphere and the shared meshes with UVs, five option sets).
#   backend_diff.sh API PGT     (API: cl or vk)
# No device of that API: a skip (exit 77) on a developer machine, a failure under CI (CI=true),
# where PoCL and lavapipe must be there.
set -u
api=$1 pgt=$2
if ! "$pgt" devices | grep -q "^  $api 0:"; then
  "$pgt" devices
  if [ "${CI:-}" = "true" ]; then
    echo "FAIL: no $api device under CI (PoCL / lavapipe must be installed: scripts/install-deps.sh)"
    exit 1
  fi
  echo "SKIP: no $api device on this machine (pgt devices lists none)"
  exit 77
fi
out=$(mktemp)
"$pgt" diff all --backend "$api" --profile | tee "$out"
status=${PIPESTATUS[0]}
[ "$status" = 0 ] || { rm -f "$out"; exit "$status"; }
# march: 6 default inputs x 5 option sets
n=$(grep -c "^march .*: ok$" "$out")
[ "$n" = 30 ] || { echo "FAIL: $n march cases passed on $api, expected 30"; rm -f "$out"; exit 1; }
# Long walks: walkers of 3000 steps and one of 100000 (lavapipe ends a shader invocation's loops
# after 65535 iterations in all, so the Vulkan host cuts a call's steps into dispatches: a walker
# there went wrong after 1158-7250 steps before). pgt march on the backend writes the CSV the
# reference does, byte for byte (its steps in chunks of 65536).
"$pgt" diff march --backend "$api" spot.obj --res 512 --walkers 64 --steps 3000 > "$out" \
  || { cat "$out"; echo "FAIL: long walks"; rm -f "$out"; exit 1; }
[ "$(grep -c "^march .*: ok$" "$out")" = 5 ] || { cat "$out"; echo "FAIL: long walks: not 5 ok"; rm -f "$out"; exit 1; }
work=$(mktemp -d)
"$pgt" atlas cube_sphere_8 --res 512 -o "$work/cs.exr" > /dev/null || { rm -rf "$work" "$out"; exit 1; }
for b in cpu "$api"; do # a closed mesh: the walker takes all its steps
  "$pgt" march "$work/cs.exr" --from 100.5,100.5 --dir 1,0.3 --step 1 --steps 100000 \
    --backend "$b" -o "$work/$b.csv" > /dev/null \
    || { echo "FAIL: pgt march --backend $b"; rm -rf "$work" "$out"; exit 1; }
done
cmp "$work/cpu.csv" "$work/$api.csv" || { echo "FAIL: pgt march --backend $api differs from cpu"; rm -rf "$work" "$out"; exit 1; }
echo "pgt march --backend $api: $(($(wc -l < "$work/cpu.csv") - 1)) steps, the reference's CSV byte for byte"
rm -rf "$work"
# Fans (sqrt3): vertex 0 the centre of a closed fan of $1 triangles, vertex 1 of an open fan of
# $2; at k = 2 vertex 1's fan (level 1) has $2 + 1 half-edges to walk on the border. lavapipe
# counts loop iterations for 8 invocations at once and stops them after 65535 in all, so the
# Vulkan shaders stop a walk beyond 21000 (three walks in a row: the worst case, at the bound,
# must come out right) and the call is refused, naming the vertex; before, such a fan came out
# wrong (a closed fan of 66000 triangles, or this mix at 30000). PoCL has no such limit.
fans() {
  awk -v NA="$1" -v NB="$2" 'BEGIN { pi = 3.141592653589793; print "v 0 0 0.5"; print "v 3 0 0.5"
    for (i = 0; i < NA; i++) printf "v %.6f %.6f 0\n", cos(2 * pi * i / NA), sin(2 * pi * i / NA)
    for (i = 0; i < NB; i++) printf "v %.6f %.6f 0\n", 3 + cos(1.8 * pi * i / NB), sin(1.8 * pi * i / NB)
    for (i = 0; i < NA; i++) printf "f 1 %d %d\n", i + 3, (i + 1) % NA + 3
    for (i = 0; i < NB - 1; i++) printf "f 2 %d %d\n", NA + i + 3, NA + i + 4 }'
}
work=$(mktemp -d)
fans 21000 21000 > "$work/fans_at.obj" && fans 21000 21001 > "$work/fans_over.obj"
"$pgt" diff sqrt3 --backend "$api" "$work/fans_at.obj" --iters 2,3 --protected none > "$out" \
  && [ "$(grep -c "^sqrt3 .*: ok$" "$out")" = 2 ] \
  || { cat "$out"; echo "FAIL: fans at lavapipe's bound"; rm -rf "$work" "$out"; exit 1; }
"$pgt" diff sqrt3 --backend "$api" "$work/fans_over.obj" --iters 2 --protected none > "$out" 2>&1
st=$?
if [ "$api" = vk ]; then
  [ "$st" = 2 ] && grep -q "vertex 1 of level 1 (the input of iteration 2) walks a fan of more than 21000 half-edges, more than lavapipe" "$out" \
    || { cat "$out"; echo "FAIL: a fan beyond lavapipe's bound not refused: exit $st"; rm -rf "$work" "$out"; exit 1; }
  # the bound lowered: the first level's smallest vertex is named
  PGT_VK_S3_WALK=20999 "$pgt" diff sqrt3 --backend vk "$work/fans_at.obj" --iters 2 --protected none > "$out" 2>&1
  st=$?
  [ "$st" = 2 ] && grep -q "vertex 0 of level 0 (the input of iteration 1) walks a fan of more than 20999 half-edges, the bound PGT_VK_S3_WALK sets" "$out" \
    || { cat "$out"; echo "FAIL: PGT_VK_S3_WALK=20999: exit $st"; rm -rf "$work" "$out"; exit 1; }
else
  [ "$st" = 0 ] && grep -q "^sqrt3 .*: ok$" "$out" || { cat "$out"; echo "FAIL: fans beyond lavapipe's bound on $api"; rm -rf "$work" "$out"; exit 1; }
fi
rm -rf "$work"
echo "sqrt3 fans: bit-equal at lavapipe's bound$([ "$api" = vk ] && echo ", refused beyond it" || echo " and beyond it")"
# Vulkan's limits, lowered: dispatches cut in ranges of 2 and 3 work-groups (the march's `first`
# push constant, sqrt(3)'s item ranges) give the same result; an array larger than a binding is
# refused with its name (exit 2), not read past its end.
if [ "$api" = vk ]; then
  PGT_VK_MAX_GROUPS=2 "$pgt" diff march --backend vk cube_sphere_8 --res 256 --walkers 1000 \
    --steps 30 --profile > "$out" || { cat "$out"; echo "FAIL: march in ranges"; rm -f "$out"; exit 1; }
  # 16 groups of 64 walkers in dispatches of 2, for each of the 5 option sets
  grep -q "^  march_walk  *40 " "$out" && [ "$(grep -c "^march .*: ok$" "$out")" = 5 ] \
    || { cat "$out"; echo "FAIL: march in ranges: not 40 dispatches or not 5 ok"; rm -f "$out"; exit 1; }
  PGT_VK_MAX_GROUPS=3 "$pgt" diff sqrt3 --backend vk icosphere_l2 > "$out" \
    || { cat "$out"; echo "FAIL: sqrt3 in ranges"; rm -f "$out"; exit 1; }
  PGT_VK_MAX_BINDING_BYTES=1000000 "$pgt" diff march --backend vk cube_sphere_8 --res 512 \
    > /dev/null 2> "$out"
  st=$?
  [ "$st" = 2 ] && grep -q "march on vulkan: the texel codes array is 1048576 bytes, .* allows 1000000 bytes" "$out" \
    || { cat "$out"; echo "FAIL: march over the binding limit: exit $st"; rm -f "$out"; exit 1; }
  echo "vk limits: march and sqrt3 in ranges ok, an array over the binding limit refused"
fi
rm -f "$out"
# pgt bench subdiv fills this backend's columns (device and end-to-end medians)
csv=$(mktemp)
trap 'rm -f "$csv"' EXIT
"$pgt" bench subdiv --quick --no-oracles --backends "$api" --meshes icosphere_l2 --threads 1 \
  --out "$csv" || exit $?
/usr/bin/python3 - "$csv" "$api" <<'PY' || exit 1
import csv, sys
rows = list(csv.DictReader(l for l in open(sys.argv[1]) if not l.startswith("#")))
api = sys.argv[2]
assert rows, "no rows"
for r in rows:
    for c in (f"{api}_device_median_ms", f"{api}_total_median_ms"):
        assert float(r[c]) > 0, (c, r[c])
print(f"bench: {api} columns filled in {len(rows)} rows")
PY
