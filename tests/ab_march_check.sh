#!/usr/bin/env bash
# scripts/ab_march.sh on a small atlas: a build against itself takes the same steps (with one
# view and with a view per build); --two-views gives B its own view and without it B reads A's;
# a build from before the ring masks gets a view per build by itself; a build whose marching
# differs (PGT_MARCH_MAX_LENGTH_RATIO 8 -> 2 where march.c uses it: spot's seams join texels
# 3-6x apart in size) is reported as taking other steps; a missing mesh is an error.
#   ab_march_check.sh SOURCE_DIR BUILD_DIR SHARED_MESH_DIR
set -u
src=$1 build=$2 meshes=$3
mesh=$meshes/spot.obj
[ -f "$mesh" ] || { echo "SKIP: no $mesh"; exit 77; }
work=$(mktemp -d /tmp/pgt_ab_check.XXXXXX)
trap 'rm -rf "$work"' EXIT
fails=0
run() { PGT_AB_BUILD=$build bash "$src/scripts/ab_march.sh" "$@" --runs 3 --walkers 256 --steps 60 --res 256 >"$work/out.txt" 2>"$work/err.txt"; }
check() { if eval "$2"; then echo "PASS $1"; else echo "FAIL $1: $(cat "$work/out.txt" "$work/err.txt")"; fails=$((fails + 1)); fi; }
run WORK WORK "$mesh"
check self_same '[ $? -eq 0 ] && grep -q "the same: yes" "$work/out.txt"'
run WORK WORK "$mesh" --two-views
check self_same_two_views '[ $? -eq 0 ] && grep -q "the same: yes" "$work/out.txt"'
# B's view with every ring mask zeroed: B marches otherwise on its own view, as A on A's
sed 's/^    out->rings = rings;/    memset(rings, 0, n * sizeof(uint16_t));\n    out->rings = rings;/' \
  "$src/ref_cpu/src/march.c" >"$work/zero_rings.c"
cmp -s "$work/zero_rings.c" "$src/ref_cpu/src/march.c" && { echo "FAIL: the rings sed changed nothing"; exit 1; }
run WORK "$work/zero_rings.c" "$mesh" --two-views
check two_views_used '[ $? -eq 0 ] && grep -q "the same: no" "$work/out.txt"'
run WORK "$work/zero_rings.c" "$mesh"
check one_view_shared '[ $? -eq 0 ] && grep -q "the same: yes" "$work/out.txt"'
# A from before the ring masks (a80c078), when the source tree has that history: a view per
# build without being asked, the same steps (the masks changed no result)
if git -C "$src" cat-file -e a80c078:ref_cpu/src/march.c 2>/dev/null; then
  run a80c078 WORK "$mesh"
  check old_layout_two_views '[ $? -eq 0 ] && grep -q "the same: yes" "$work/out.txt" && grep -q "a view per build" "$work/err.txt"'
else
  echo "SKIP old_layout_two_views: no git history with a80c078 in $src"
fi
sed 's/ld \* PGT_MARCH_MAX_LENGTH_RATIO > lv/ld * 2.0f > lv/' "$src/ref_cpu/src/march.c" >"$work/other.c"
cmp -s "$work/other.c" "$src/ref_cpu/src/march.c" && { echo "FAIL: the sed changed nothing"; exit 1; }
run WORK "$work/other.c" "$mesh"
check other_differs '[ $? -eq 0 ] && grep -q "the same: no" "$work/out.txt"'
run WORK "$work/other.c" "$mesh" --position
check other_differs_position '[ $? -eq 0 ] && grep -q "and position sums the same: no" "$work/out.txt"'
echo "int broken =" >"$work/broken.c"
run WORK "$work/broken.c" "$mesh"
check broken_build '[ $? -eq 2 ] && grep -q "does not compile" "$work/err.txt"'
run WORK WORK "$work/no_such_mesh.obj"
check missing_mesh '[ $? -eq 2 ] && grep -q "no_such_mesh.obj" "$work/err.txt"'
echo "$fails failed"
[ $fails -eq 0 ]
