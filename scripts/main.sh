#!/usr/bin/env bash
# The main job: installs missing Debian packages, builds Release, and regenerates every table
# and figure the project knows on its embedded default data, with a progress line per step and a
# summary of what it wrote.
#   bash scripts/main.sh [--quick]    (--quick: small inputs, for a smoke run; it writes under
#                                      build/quick/ so results/ keeps the real tables)
set -Eeuo pipefail # -E: the ERR trap below also fires inside functions
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
steps=18
current=0
step() { current=$1; echo "[main $1/$steps] $2"; }
# set -e stops at the first failing command: say where, and that the files of the steps before
# are already rewritten while the later ones are as they were
trap 'echo "[main] FAILED at step $current/$steps (see the message above); the outputs of steps 1-$((current - 1)) are new, the rest untouched" >&2' ERR
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
# The shared meshes without UVs get MeshLab's Voronoi atlas (datasets_gen/meshlab_atlas.sh, the
# same bytes every run): automatic multi-chart parametrizations like the paper's Table 1 meshes,
# benchmarked after the UV meshes in tables 1 and march.csv. Without MeshLab the rows are
# missing and the job says so.
voronoi=()
for m in mountain nefertiti-lowres; do
  if sh datasets_gen/meshlab_atlas.sh "$top/../shared/datasets/meshes/$m.obj" \
    "$work/${m}_voronoi.obj" >"$work/$m.meshlab.log" 2>&1; then
    voronoi+=("$work/${m}_voronoi.obj")
  else
    echo "main: MeshLab's Voronoi atlas of $m failed ($(tail -n 1 "$work/$m.meshlab.log")):" \
      "no $m rows in table 1 and march.csv" >&2
  fi
done
voronoi_add=()
if [ ${#voronoi[@]} -gt 0 ]; then voronoi_add=(--add "$(IFS=,; echo "${voronoi[*]}")"); fi
atlas_quick=()
if [ ${#quick[@]} -gt 0 ]; then atlas_quick=(--quick); fi
"$pgt" bench atlas --out "$res/table1.csv" "${atlas_quick[@]}" "${voronoi_add[@]}"
written+=("$res/table1.csv")

step 7 "figure: spot's atlas with its indirection pointers -> $figs/atlas_pointers.{png,pdf} (and nefertiti's Voronoi atlas -> atlas_pointers_voronoi)"
"$pgt" atlas "$spot" -o "$work/spot_atlas.exr" --png "$figs/atlas_spot.png" >/dev/null
"$py" paper_figs/atlas_pointers.py "$work/spot_atlas.exr" "$figs/atlas_pointers" \
  --title "Indirection geometry image of spot (1024^2), like paper 000 Fig. 2b-c"
written+=("$figs/atlas_spot.png" "$figs/atlas_pointers.png" "$figs/atlas_pointers.pdf")
# the same for an automatic atlas (MeshLab's Voronoi atlas of nefertiti-lowres, step 6)
nef="$work/nefertiti-lowres_voronoi.obj"
if [ -s "$nef" ]; then
  "$pgt" atlas "$nef" -o "$work/nefertiti_atlas.exr" >/dev/null
  "$py" paper_figs/atlas_pointers.py "$work/nefertiti_atlas.exr" "$figs/atlas_pointers_voronoi" \
    --title "Indirection geometry image of nefertiti-lowres (MeshLab Voronoi atlas, 1024^2)"
  written+=("$figs/atlas_pointers_voronoi.png" "$figs/atlas_pointers_voronoi.pdf")
else # MeshLab failed (step 6 said why): no figure rather than an older run's
  rm -f "$figs/atlas_pointers_voronoi.png" "$figs/atlas_pointers_voronoi.pdf"
  echo "main: no atlas_pointers_voronoi figure: MeshLab's atlas of nefertiti-lowres failed (step 6)" >&2
fi

step 8 "benchmark: pgt bench march -> $res/march.csv (marching steps per second per core)"
march_quick=()
if [ ${#quick[@]} -gt 0 ]; then march_quick=(--quick); fi
"$pgt" bench march --out "$res/march.csv" "${march_quick[@]}" "${voronoi_add[@]}"
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

step 12 "figure: the ivy scenes grown (pgt ivy) and ray traced (pgt render) -> $figs/ivy_scenes.{png,pdf}"
# the scenes pgt bench ivy saved (step 10), grown again with pgt ivy from their saved commands;
# Fig. 10b: the first 3 strokes of fig10c painted as forbidden areas, 10 random seeds
side=1000
if [ ${#quick[@]} -gt 0 ]; then side=400; fi
meshes="$top/../shared/datasets/meshes"
ivy_scene() { # NAME MESH VIEW EXTRA_ARGS...: grows $work/ivy/NAME.cmd's scene and renders it
  local name=$1 mesh=$2 view=$3; shift 3
  local -a args
  read -r -a args <"$work/ivy/$name.cmd"
  "$pgt" ivy "${args[@]:2}" -o "$work/$name.ply" "$@" >/dev/null
  local extra=()
  if [ -s "$work/$name.paint.ply" ]; then extra=("$work/$name.paint.ply@0.8,0.1,0.1"); fi
  "$pgt" render "$meshes/$mesh" "$work/$name.ply@0.25,0.55,0.2" "${extra[@]}" \
    -o "$figs/ivy_$name.png" --width "$side" --height "$side" --view "$view" >/dev/null
  written+=("$figs/ivy_$name.png")
}
ivy_scene fig1a bob_tri.obj 30,20
ivy_scene fig1b human_neutral.obj 20,10 --mask-mesh "$work/fig1b.paint.ply"
ivy_scene fig10c spot.obj 210,20 --mask-mesh "$work/fig10c.paint.ply"
read -r -a args10c <"$work/ivy/fig10c.cmd"
awk '/^stroke/ { n++ } n <= 3' "$work/ivy/fig10c.strokes" >"$work/ivy/fig10b.strokes" # 3 forbidden areas
forbid=()
for ((k = 3; k < ${#args10c[@]}; ++k)); do
  case "${args10c[k]}" in
    --seed-file) k=$((k + 1)) ;;
    --paint) forbid+=(--forbid "$work/ivy/fig10b.strokes"); k=$((k + 1)) ;;
    *) forbid+=("${args10c[k]}") ;;
  esac
done
printf 'pgt ivy spot.obj %s\n' "${forbid[*]}" >"$work/ivy/fig10b.cmd"
ivy_scene fig10b spot.obj 210,20 --mask-mesh "$work/fig10b.paint.ply"
"$py" paper_figs/ivy_scenes.py "$figs/ivy_scenes" \
  "$figs/ivy_fig1a.png" "Fig. 1a: bob, 25 seeds, recursive branching" \
  "$figs/ivy_fig1b.png" "Fig. 1b: human, 18 seeds along painted paths" \
  "$figs/ivy_fig10b.png" "Fig. 10b: spot, 10 seeds, red areas forbidden" \
  "$figs/ivy_fig10c.png" "Fig. 10c: spot, 10 seeds along painted paths"
written+=("$figs/ivy_scenes.png" "$figs/ivy_scenes.pdf")

step 13 "table: pgt bench woven -> $res/woven.csv (woven sphere, paper 002 Fig. 4.11, ms per frame)"
woven_quick=()
if [ ${#quick[@]} -gt 0 ]; then woven_quick=(--quick); fi
"$pgt" bench woven --out "$res/woven.csv" "${woven_quick[@]}"
written+=("$res/woven.csv")

step 14 "figure: woven sphere ms per frame, ours vs the paper's -> $figs/woven_bars.{png,pdf}; the 179k sphere rendered -> $figs/woven_sphere.png"
"$py" paper_figs/woven_bars.py "$res/woven.csv" "$figs/woven_bars"
written+=("$figs/woven_bars.png" "$figs/woven_bars.pdf")
"$pgt" woven --res 179k --frames 1 -o "$work/woven.ply" >/dev/null
"$pgt" render "$work/woven.ply@0.75,0.45,0.2" -o "$figs/woven_sphere.png" --width "$side" --height "$side" \
  --view 30,25 >/dev/null
written+=("$figs/woven_sphere.png")

step 15 "table: pgt bench facade -> $res/facade.csv (procedural facades vs Embree on the explicit city, paper 003 sec. 9)"
facade_quick=()
if [ ${#quick[@]} -gt 0 ]; then facade_quick=(--quick); fi
"$pgt" bench facade --out "$res/facade.csv" "${facade_quick[@]}"
written+=("$res/facade.csv")

step 16 "figure: the city table, ms per frame, Mrays/s and bytes vs Embree -> $figs/facade_bench.{png,pdf}"
"$py" paper_figs/facade_bench.py "$res/facade.csv" "$figs/facade_bench"
written+=("$figs/facade_bench.png" "$figs/facade_bench.pdf")

step 17 "figure: renders like paper 003 Fig. 1a-c (pgt facade) -> $figs/facade_city.{png,pdf}"
# one facade_fig1*.png per view, pgt's own frame beside it (.pgt.png) and its command (.cmd)
"$py" paper_figs/facade_city.py "$pgt" "$figs" "${facade_quick[@]}"
"$py" paper_figs/facade_panels.py "$figs/facade_city" \
  "$figs/facade_fig1a.png" "(a) 10K facades (--city 2500), self-shadowing" \
  "$figs/facade_fig1b.png" "(b) macroscopic details: facade_rich.grammar" \
  "$figs/facade_fig1c.png" "(c) the paper's grammar (sec. 3), one building" \
  --title "Per-pixel procedural facades with pgt facade, like paper 003 Fig. 1a-c (ground composited)"
for v in fig1a fig1b fig1c; do
  written+=("$figs/facade_$v.png" "$figs/facade_$v.pgt.png" "$figs/facade_$v.cmd")
done
written+=("$figs/facade_city.png" "$figs/facade_city.pdf")

step 18 "figure: the four levels of detail of paper 003 Fig. 11 (pgt facade --detail) -> $figs/facade_lod.{png,pdf}"
# one building (paper_figs/scenes/facade_one.scene), the same view at each level: flat (LOD 0),
# macroscopic geometry and self-shadowing, normal mapping, relief mapping in terminal space
lod_size=(--width 960 --height 600)
if [ ${#quick[@]} -gt 0 ]; then lod_size=(--width 480 --height 300); fi
for d in flat geometry normal relief; do
  lod_cmd=("$pgt" facade --scene paper_figs/scenes/facade_one.scene
           --camera 3,4.5,19,12,5.5,12,0,1,0,45 --light -40,30,40 --shadows --detail "$d"
           "${lod_size[@]}" -o "$figs/facade_lod_$d.exr" --png "$figs/facade_lod_$d.png")
  "${lod_cmd[@]}" > "$figs/facade_lod_$d.cmd.out"
  { echo "pgt ${lod_cmd[*]:1}"; cat "$figs/facade_lod_$d.cmd.out"; } > "$figs/facade_lod_$d.cmd"
  rm -f "$figs/facade_lod_$d.cmd.out" "$figs/facade_lod_$d.exr"
  written+=("$figs/facade_lod_$d.png" "$figs/facade_lod_$d.cmd")
done
"$py" paper_figs/facade_panels.py "$figs/facade_lod" \
  "$figs/facade_lod_flat.png" "(a) flat: thickness 0, material pattern only" \
  "$figs/facade_lod_geometry.png" "(b) macroscopic geometry, self-shadowing" \
  "$figs/facade_lod_normal.png" "(c) + normal mapping (terminal space)" \
  "$figs/facade_lod_relief.png" "(d) + relief mapping, shadows in the relief" \
  --columns 2 --title "The four levels of detail of paper 003 sec. 7 / Fig. 11 (pgt facade --detail)"
written+=("$figs/facade_lod.png" "$figs/facade_lod.pdf")

echo "[main] done; wrote:"
for f in "${written[@]}"; do printf '  %s\n' "$f"; done
