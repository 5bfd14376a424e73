#!/usr/bin/env bash
# The main job: installs missing Debian packages, builds Release, and regenerates every table
# and figure the project knows on its embedded default data, with a progress line per step and a
# summary of what it wrote.
#   bash scripts/main.sh [--quick]    (--quick: small inputs, for a smoke run; it writes under
#                                      build/quick/ so results/ keeps the real tables)
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$top"
quick=()
res=results figs=paper_figs/out
if [ "${1:-}" = "--quick" ]; then quick=(--quick) res=build/quick/results figs=build/quick/figs; fi
mkdir -p "$res" "$figs"
# GPU kernel caches inside the build folder (PoCL, Mesa), not in the user's home
export POCL_CACHE_DIR="$top/build/cache/pocl" MESA_SHADER_CACHE_DIR="$top/build/cache/mesa"
export XDG_CACHE_HOME="$top/build/cache/xdg"
py=/usr/bin/python3
steps=11
step() { echo "[main $1/$steps] $2"; }
written=()

step 1 "installing missing Debian packages"
bash scripts/install-deps.sh

step 2 "building Release"
dir=$(bash scripts/build.sh Release | tail -n 1)
pgt="$dir/harness/pgt"

step 3 "benchmark: pgt bench subdiv -> $res/subdiv.csv (ours on cpu, OpenCL, Vulkan vs CGAL vs OpenMesh)"
"$pgt" bench subdiv --out "$res/subdiv.csv" "${quick[@]}"
written+=("$res/subdiv.csv")

step 4 "figure: time vs output faces -> $figs/subdiv_time.{png,pdf}"
"$py" paper_figs/subdiv_time.py "$res/subdiv.csv" "$figs/subdiv_time"
written+=("$figs/subdiv_time.png" "$figs/subdiv_time.pdf")

step 5 "figure: spot at k = 0, 1, 2 -> $figs/subdiv_levels.{png,pdf}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
spot="$top/../shared/datasets/meshes/spot.obj"
"$pgt" subdiv "$spot" --iters 0 -o "$work/k0.ply" >/dev/null
"$pgt" subdiv "$spot" --iters 1 -o "$work/k1.ply" >/dev/null
"$pgt" subdiv "$spot" --iters 2 -o "$work/k2.ply" >/dev/null
"$py" paper_figs/mesh_levels.py "$figs/subdiv_levels" "$work/k0.ply" "$work/k1.ply" "$work/k2.ply" \
  --labels "k = 0" "k = 1" "k = 2" --title "sqrt(3) subdivision of spot (Keenan Crane, public domain)" --up y
written+=("$figs/subdiv_levels.png" "$figs/subdiv_levels.pdf")

step 6 "table 1: pgt bench atlas -> $res/table1.csv (atlas build time, with the paper's rows)"
atlas_quick=()
if [ ${#quick[@]} -gt 0 ]; then atlas_quick=(--repeat 1 --meshes cube_sphere_8,spot.obj); fi
"$pgt" bench atlas --out "$res/table1.csv" "${atlas_quick[@]}"
written+=("$res/table1.csv")

step 7 "figure: spot's atlas with its indirection pointers -> $figs/atlas_pointers.{png,pdf}"
"$pgt" atlas "$spot" -o "$work/spot_atlas.exr" --png "$figs/atlas_spot.png" >/dev/null
"$py" paper_figs/atlas_pointers.py "$work/spot_atlas.exr" "$figs/atlas_pointers" \
  --title "Indirection geometry image of spot (1024^2), like paper 000 Fig. 2b-c"
written+=("$figs/atlas_spot.png" "$figs/atlas_pointers.png" "$figs/atlas_pointers.pdf")

step 8 "benchmark: pgt bench march -> $res/march.csv (marching steps per second per core)"
march_quick=()
if [ ${#quick[@]} -gt 0 ]; then march_quick=(--quick); fi
"$pgt" bench march --out "$res/march.csv" "${march_quick[@]}"
written+=("$res/march.csv")

step 9 "figure: a march on spot's atlas and on the mesh -> $figs/march_path.{png,pdf}"
"$pgt" march "$work/spot_atlas.exr" --from 700.5,300.5 --dir -1,0.2 --step 4 --steps 400 \
  -o "$work/path.csv" --with-start --dump "$work/spot_dump" >/dev/null
"$py" paper_figs/march_path.py "$figs/march_path" "$work/path.csv" --dump "$work/spot_dump"
written+=("$figs/march_path.png" "$figs/march_path.pdf")

step 10 "table 2 and figure 11: pgt bench ivy -> $res/table2.csv, $res/fig11.csv (ivy generation time)"
ivy_quick=()
if [ ${#quick[@]} -gt 0 ]; then ivy_quick=(--quick); fi
"$pgt" bench ivy --out "$res/table2.csv" --fig11 "$res/fig11.csv" --save-scenes "$work/ivy" "${ivy_quick[@]}"
written+=("$res/table2.csv" "$res/fig11.csv")

step 11 "figure: time vs seeds and Table 2 -> $figs/ivy_seeds.{png,pdf}"
"$py" paper_figs/ivy_seeds.py "$res/fig11.csv" "$res/table2.csv" "$figs/ivy_seeds"
written+=("$figs/ivy_seeds.png" "$figs/ivy_seeds.pdf")

echo "[main] done; wrote:"
for f in "${written[@]}"; do printf '  %s\n' "$f"; done
