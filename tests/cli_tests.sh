#!/usr/bin/env bash
# Tests of the pgt program itself: documented flags, exit codes (0 ok, 2 bad flag/value/input),
# one-line errors naming the file and line, outputs written atomically, inputs never overwritten.
#   cli_tests.sh PGT PGT_DATASETS SOURCE_DIR WORK_DIR
set -u
pgt=$1 gen=$2 src=$3 work=$4
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
pass=0 fail=0
# no progress lines (the long-running verbs print one every 5 s of work): a run under the
# sanitizers may pass the first period, and many tests count stderr's lines; the progress
# tests below set the period themselves
export PGT_PROGRESS_SECONDS=0
ok() { pass=$((pass + 1)); echo "PASS $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1: $2"; }
# expect NAME CODE CMD...: exit code is CODE; stderr kept in err.txt, stdout in out.txt
expect() {
  local name=$1 code=$2; shift 2
  "$@" >out.txt 2>err.txt
  local got=$?
  if [ "$got" -eq "$code" ]; then ok "$name"; else bad "$name" "exit $got, want $code; stderr: $(head -c 300 err.txt)"; fi
}
# one_line NAME PATTERN: stderr is exactly one line and matches PATTERN
one_line() {
  local n; n=$(wc -l <err.txt)
  if [ "$n" -eq 1 ] && grep -q -- "$2" err.txt; then ok "$1"; else bad "$1" "stderr: $(cat err.txt)"; fi
}
# progress_lines NAME VERB PATTERN [OTHER]: stderr has a line matching PATTERN (extended regular
# expression) and every line is a progress line, "pgt VERB: STAGE[: DONE of TOTAL UNIT (P %)],
# S s" (harness/progress_line.c), or matches OTHER
progress_lines() {
  local form="^pgt $2: [A-Za-z][^:]*(: [0-9]+ of [0-9]+ [a-z]+ \([0-9]+ %\))?, [0-9]+ s\$"
  [ -n "${4:-}" ] && form="$form|$4"
  if grep -Eq -- "$3" err.txt && ! grep -Ev -- "$form" err.txt >/dev/null; then ok "$1"; else bad "$1" "$(head -c 400 err.txt)"; fi
}

# fields_match NAME CSV: every line that is not a '#' comment has as many fields as the header
fields_match() {
  local counts; counts=$(grep -v '^#' "$2" | awk -F, '{print NF}' | sort -u | tr '\n' ' ')
  case $counts in *" "?*) bad "$1" "field counts in $2: $counts" ;; "") bad "$1" "$2: no lines" ;; *) ok "$1" ;; esac
}

"$gen" "$work/data" >/dev/null || { echo "cannot generate datasets"; exit 1; }
"$gen" "$work/data" --only cube_sphere_8 --format ply >/dev/null
ico="$work/data/icosphere_l1.off"

expect help 0 "$pgt" --help
grep -q "subdiv" out.txt && ok help_lists_subdiv || bad help_lists_subdiv "no subdiv in --help"
expect subdiv_help 0 "$pgt" subdiv --help
for flag in --iters -o --protect --group --threads --backend --device --profile --json --precise; do
  grep -q -- "$flag" out.txt && ok "subdiv_help_documents_$flag" || bad "subdiv_help_documents_$flag" "missing"
done
expect bench_help 0 "$pgt" bench --help
expect no_verb 2 "$pgt"
expect unknown_verb 2 "$pgt" frobnicate
one_line unknown_verb_one_line "unknown verb"
expect unknown_flag 2 "$pgt" subdiv "$ico" --iters 1 -o x.off --bogus
one_line unknown_flag_one_line "unknown flag '--bogus'"
expect bad_iters 2 "$pgt" subdiv "$ico" --iters two -o x.off
one_line bad_iters_one_line "\-\-iters: expected a whole number"
expect negative_iters 2 "$pgt" subdiv "$ico" --iters -1 -o x.off
expect too_many_iters 2 "$pgt" subdiv "$ico" --iters 13 -o x.off
expect bad_threads 2 "$pgt" subdiv "$ico" --threads 0 -o x.off
expect missing_value 2 "$pgt" subdiv "$ico" --iters
one_line missing_value_one_line "needs a value"
expect no_output 2 "$pgt" subdiv "$ico" --iters 1
expect bad_extension 2 "$pgt" subdiv "$ico" --iters 1 -o x.xyz
expect gpu_no_such_device 2 "$pgt" subdiv "$ico" --iters 1 -o x.off --backend cl --device 999
one_line gpu_no_such_device_one_line "device 999"
expect unknown_backend 2 "$pgt" subdiv "$ico" --iters 1 -o x.off --backend cuda

# pgt devices, pgt diff (the backends' own diffs are the diff_cl / diff_vk tests)
expect devices 0 "$pgt" devices
grep -q "^OpenCL:" out.txt && grep -q "^Vulkan:" out.txt && ok devices_lists_both_apis || bad devices_lists_both_apis "$(cat out.txt)"
expect devices_json 0 "$pgt" devices --json
/usr/bin/python3 -c 'import json,sys; d=json.load(open("out.txt")); assert set(d)=={"cl","vk"}' \
  && ok devices_json_parses || bad devices_json_parses "$(cat out.txt)"
expect diff_help 0 "$pgt" diff --help
for flag in --backend --device --iters --protected --walkers --steps --step --res --shared --profile --json; do
  grep -q -- "$flag" out.txt && ok "diff_help_documents_$flag" || bad "diff_help_documents_$flag" "missing"
done
expect diff_no_backend 2 "$pgt" diff sqrt3 "$ico"
one_line diff_no_backend_one_line "no backend"
expect diff_unknown_algorithm 2 "$pgt" diff frobnicate --backend cl
one_line diff_unknown_algorithm_one_line "unknown algorithm"
expect diff_bad_pattern 2 "$pgt" diff sqrt3 --backend cpu "$ico" --protected some
expect diff_missing_input 2 "$pgt" diff sqrt3 --backend cpu nothere.off
one_line diff_missing_input_names_file "nothere.off"
# a case both sides refuse compares nothing: exit 2 (it was 'ok', exit 0)
printf 'OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n' >both_refuse.off
expect diff_both_refuse 2 "$pgt" diff sqrt3 --backend cpu both_refuse.off --iters 1 --protected none
one_line diff_both_refuse_one_line "1 of 1 cases were refused by both sides"
grep -q "both refuse (non_manifold)" out.txt && grep -q "1 refused by both" out.txt \
  && ok diff_both_refuse_reported || bad diff_both_refuse_reported "$(cat out.txt)"
# the reference against itself: every element equal, exit 0, JSON lines that parse
expect diff_cpu_self 0 "$pgt" diff sqrt3 --backend cpu "$ico" grid_16x16 --iters 1,2 --json
/usr/bin/python3 -c '
import json
rows=[json.loads(l) for l in open("out.txt")]
cases=[r for r in rows if "case" in r]
assert len(cases)==8 and all(r["pass"] and r["positions"]["max_ulp"]==0 for r in cases), rows
assert rows[-1]["summary"] and rows[-1]["cases"]==8 and rows[-1]["failed"]==0' \
  && ok diff_cpu_self_json || bad diff_cpu_self_json "$(head -c 400 out.txt)"
# march: the reference against itself on a built atlas and on an atlas file, five option sets
expect diff_march_cpu_self 0 "$pgt" diff march --backend cpu cube_sphere_8 --res 128 --walkers 64 --steps 20 --json
/usr/bin/python3 -c '
import json
rows=[json.loads(l) for l in open("out.txt")]
cases=[r for r in rows if "case" in r]
assert len(cases)==5 and all(r["pass"] and r["algorithm"]=="march" and r["state"]["max_ulp"]==0
                             and r["discrete_mismatches"]==0 and r["steps"]>0 for r in cases), rows
assert rows[-1]["summary"] and rows[-1]["cases"]==5 and rows[-1]["failed"]==0' \
  && ok diff_march_cpu_self_json || bad diff_march_cpu_self_json "$(head -c 400 out.txt)"
expect diff_march_atlas_written 0 "$pgt" atlas cube_sphere_8 --res 128 -o march_diff_atlas.exr
expect diff_march_exr_input 0 "$pgt" diff march --backend cpu march_diff_atlas.exr --walkers 16 --steps 5
grep -c "^march march_diff_atlas.exr 128x128 .*: ok$" out.txt | grep -qx 5 \
  && ok diff_march_exr_five_cases || bad diff_march_exr_five_cases "$(cat out.txt)"
expect diff_march_no_uvs 2 "$pgt" diff march --backend cpu "$ico"
one_line diff_march_no_uvs_one_line "march needs UVs"
expect diff_march_bad_walkers 2 "$pgt" diff march --backend cpu cube_sphere_8 --walkers 0
one_line diff_march_bad_walkers_one_line "--walkers"
expect diff_march_bad_step 2 "$pgt" diff march --backend cpu cube_sphere_8 --step 0
# under all, an input march cannot take is skipped with a note, sqrt3 still runs on it
expect diff_all_skips_for_march 0 "$pgt" diff all --backend cpu "$ico" --iters 1 --protected none
grep -q "^march .*: skipped (no UVs" out.txt && grep -q "^sqrt3 .*: ok$" out.txt \
  && ok diff_all_skip_note || bad diff_all_skip_note "$(cat out.txt)"

# pgt atlas, pgt march (their algorithms are test_atlas / test_march)
expect atlas_help 0 "$pgt" atlas --help
for flag in -o --res --band --k --png --angles --dead-end --threads --json; do
  grep -q -- "$flag" out.txt && ok "atlas_help_documents_$flag" || bad "atlas_help_documents_$flag" "missing"
done
expect march_help 0 "$pgt" march --help
for flag in --from --dir --step --steps --mask --density --seed --no-best-pointer --no-rotation -o; do
  grep -q -- "$flag" out.txt && ok "march_help_documents_$flag" || bad "march_help_documents_$flag" "missing"
done
expect atlas_no_uvs 2 "$pgt" atlas "$ico" -o a.exr
one_line atlas_no_uvs_one_line "UV"
# --dead-end beyond 64 texel sizes is refused: the search grows as its square (1000 on a grid
# sheet took 17.7 s at --res 512, 1e6 did not end)
expect atlas_dead_end_too_far 2 "$pgt" atlas "$work/data/cube_sphere_8.ply" -o a.exr --dead-end 65
one_line atlas_dead_end_too_far_one_line "dead-end: '65' .*(0, 64]"
expect atlas_dead_end_largest 0 "$pgt" atlas "$work/data/cube_sphere_8.ply" -o a.exr --res 64 --dead-end 64
# --angles: 5.2's tangents (default) or fitted to the Jacobians (test_march checks the fit); the
# count fitted is printed and in the JSON alike, and the tangents' atlas has no such line
expect atlas_angles_bad 2 "$pgt" atlas "$work/data/cube_sphere_8.ply" -o a.exr --angles jacobians
one_line atlas_angles_bad_one_line "\-\-angles: 'jacobians' is not tangents or jacobian"
expect atlas_angles_tangents 0 "$pgt" atlas "$work/data/cube_sphere_8.ply" -o a.exr --res 128 --angles tangents
grep -q "fitted" out.txt && bad atlas_angles_tangents_no_fit "$(cat out.txt)" || ok atlas_angles_tangents_no_fit
expect atlas_angles_jacobian 0 "$pgt" atlas "$work/data/cube_sphere_8.ply" -o a.exr --res 128 --angles jacobian
text_fit=$(sed -n 's/^  angles fitted to the Jacobians at \([0-9]*\) of \([0-9]*\) indirection texels.*/\1 \2/p' out.txt)
expect atlas_angles_jacobian_json 0 "$pgt" atlas "$work/data/cube_sphere_8.ply" -o a.exr --res 128 --angles jacobian --json
json_fit=$(/usr/bin/python3 -c 'import json; r=json.load(open("out.txt")); assert r["angles"]=="jacobian"; print(r["fitted_angles"], r["indirection_texels"])')
if [ -n "$text_fit" ] && [ "$text_fit" = "$json_fit" ] && [ "${text_fit% *}" -gt 0 ] &&
   [ "${text_fit% *}" -le "${text_fit#* }" ]; then ok atlas_angles_jacobian_reported
else bad atlas_angles_jacobian_reported "text '$text_fit', json '$json_fit'"; fi
expect atlas_bad_res 2 "$pgt" atlas "$work/data/cube_sphere_8.ply" -o a.exr --res 1
one_line atlas_bad_res_one_line "\-\-res"
# the range named is the one --help gives
for r in 0 4 4940; do
  expect "atlas_res_$r" 2 "$pgt" atlas "$work/data/cube_sphere_8.ply" -o a.exr --res $r
  one_line "atlas_res_${r}_one_line" "\-\-res: expected a whole number from 5 to 4939, got '$r'"
done
expect atlas_cube_sphere 0 "$pgt" atlas "$work/data/cube_sphere_8.ply" -o cs.exr --res 128 --png cs.png
[ -s cs.exr ] && [ -s cs.png ] && ok atlas_writes_exr_and_png || bad atlas_writes_exr_and_png "missing outputs"
# the own-chart fallback's pointers (bob_tri at 128: the closed end of a slit) are printed and in
# the JSON alike, as a part of the pointers into their own chart
bob="$src/../shared/datasets/meshes/bob_tri.obj"
if [ -f "$bob" ]; then
  expect atlas_own_chart_text 0 "$pgt" atlas "$bob" -o bob.exr --res 128
  text_own=$(sed -n 's/.*(\([0-9]*\) into their own chart, \([0-9]*\) of them with nothing across).*/\1 \2/p' out.txt)
  expect atlas_own_chart_json 0 "$pgt" atlas "$bob" -o bob.exr --res 128 --json
  json_own=$(sed -n 's/.*"self_seam_pointers":\([0-9]*\),"own_chart_pointers":\([0-9]*\),.*/\1 \2/p' out.txt)
  if [ -n "$text_own" ] && [ "$text_own" = "$json_own" ] && [ "${text_own#* }" -gt 0 ] &&
     [ "${text_own#* }" -le "${text_own% *}" ]; then ok atlas_own_chart_reported
  else bad atlas_own_chart_reported "text '$text_own', json '$json_own'"; fi
else
  bad atlas_own_chart_reported "no $bob"
fi
# repeated faces (charts at one place: 150,000 copies of a triangle ran for minutes) are refused
# by atlas and ivy at once, naming the faces and the repeat's line (the 8th: 6 v/vt lines, then f)
{ printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n'; for i in $(seq 2000); do echo 'f 1/1 2/2 3/3'; done; } > rep.obj
expect atlas_repeated_faces 2 timeout 20 "$pgt" atlas rep.obj -o rep.exr --res 2048
one_line atlas_repeated_faces_one_line "rep.obj:8: face 1 (0-based) repeats face 0.*(1999 such faces)"
expect ivy_repeated_faces 2 timeout 20 "$pgt" ivy rep.obj --seeds 1 -o rep.ply
one_line ivy_repeated_faces_one_line "rep.obj:8: face 1 (0-based) repeats face 0"
# an empty mesh name is refused as such (it named the shared folder's path)
expect atlas_empty_name 2 "$pgt" atlas "" -o e.exr
one_line atlas_empty_name_one_line "no mesh named (an empty name)"
# meshes without vertices whose faces name one say so (it was 'outside 0..-1')
printf 'ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n3 0 1 2\n' > nov.ply
expect ply_no_vertices 2 "$pgt" subdiv nov.ply --iters 1 -o nov.off
one_line ply_no_vertices_one_line "nov.ply:10: .*vertex index 0, but the file has no vertices"
printf 'OFF\n0 1 0\n3 0 1 2\n' > nov.off
expect off_no_vertices 2 "$pgt" subdiv nov.off --iters 1 -o nov2.off
one_line off_no_vertices_one_line "nov.off:3: face 0: vertex index 0, but the file has no vertices"
# a PLY element count beyond int64 is shown as written
printf 'ply\nformat ascii 1.0\nelement vertex 1000000000000000000000000000000\nproperty float x\nend_header\n' > huge_count.ply
expect ply_count_beyond_int64 2 "$pgt" subdiv huge_count.ply --iters 1 -o hc.off
one_line ply_count_beyond_int64_one_line "huge_count.ply:3: element 'vertex' count 1000000000000000000000000000000 is above"
# a folder given where a text file is read says so (it was 'read error' / 'cannot read')
mkdir -p dir_in.grammar dir_in.txt dir_in.obj
expect grammar_folder 2 "$pgt" grammar dir_in.grammar
one_line grammar_folder_one_line "dir_in.grammar: cannot read: Is a directory"
expect protect_folder 2 "$pgt" subdiv "$ico" --iters 1 --protect dir_in.txt -o pf.off
one_line protect_folder_one_line "dir_in.txt: read error: Is a directory"
expect scene_folder 2 "$pgt" facade --scene dir_in.txt -o sf.exr
one_line scene_folder_one_line "dir_in.txt: read error: Is a directory"
expect quad_mesh_folder 2 "$pgt" facade --mesh dir_in.obj -o qf.exr
one_line quad_mesh_folder_one_line "dir_in.obj: read error: Is a directory"
# a non-manifold vertex of valence 19 (two fans: the adjacency's sorted path for long buckets)
# is named at its first face, line 25, as before the buckets were sorted
{ echo OFF; echo "22 19 0"; echo "0 0 0"
  for i in $(seq 1 21); do awk -v i=$i 'BEGIN { printf "%.6f %.6f %.1f\n", cos(i), sin(i), 0.1 * i }'; done
  for i in $(seq 11 20); do echo "3 0 $i $((i + 1))"; done
  for i in $(seq 1 9); do echo "3 0 $i $((i + 1))"; done; } > bowtie19.off
expect bowtie_valence_19 2 "$pgt" subdiv bowtie19.off --iters 1 -o bt.off
one_line bowtie_valence_19_one_line "bowtie19.off:25: sqrt3 input: non-manifold vertex 0"
# a coordinate beyond the subdivision's limit (1e18) names the vertex's line, or for a UV the
# line it was read from (OBJ vt, a PLY vertex's u v, a PLY face's texcoord list), or in binary PLY
# the record's byte offset (header bytes + 12 per vertex)
printf 'v 0 0 0\nv 1 0 0\n# c\nv 0 1 2e18\nf 1 2 3\n' >far.obj
expect subdiv_far_vertex 2 "$pgt" subdiv far.obj --iters 1 -o fo.obj
one_line subdiv_far_vertex_line "^pgt subdiv: far.obj:4: sqrt3 input: vertex 2 (0-based): coordinate 2e+18 is beyond"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 3e18 1\n\nf 1/1 2/2 3/3\n' >far_uv.obj
expect subdiv_far_uv 2 "$pgt" subdiv far_uv.obj --iters 1 -o fo.obj
one_line subdiv_far_uv_line "^pgt subdiv: far_uv.obj:6: sqrt3 input: face 0 (0-based), corner 2: UV 3e+18 is beyond"
# the GPU backends do not carry UVs (a note says so): a UV they never read is not refused
for b in cl vk; do
  expect subdiv_far_uv_$b 0 "$pgt" subdiv far_uv.obj --iters 1 -o fo_$b.obj --backend $b
  one_line subdiv_far_uv_${b}_note "note: the $b backend does not carry UVs"
  grep -q '^vt' fo_$b.obj && bad subdiv_far_uv_${b}_no_vt "$(cat fo_$b.obj)" || ok subdiv_far_uv_${b}_no_vt
done
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float u\nproperty float v\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n1 1 0 1 -4e18\n3 0 1 2\n3 1 3 2\n' >far_uv_vertex.ply
expect subdiv_far_uv_ply_vertex 2 "$pgt" subdiv far_uv_vertex.ply --iters 1 -o fo.obj
one_line subdiv_far_uv_ply_vertex_line "^pgt subdiv: far_uv_vertex.ply:15: sqrt3 input: face 1 (0-based), corner 1: UV -4e+18 is beyond"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 6 0 0 1 0 0 1\n3 0 2 1 6 0 0 0 1 5e18 0\n' >far_uv_face.ply
expect subdiv_far_uv_ply_face 2 "$pgt" subdiv far_uv_face.ply --iters 1 -o fo.obj
one_line subdiv_far_uv_ply_face_line "^pgt subdiv: far_uv_face.ply:15: sqrt3 input: face 1 (0-based), corner 2: UV 5e+18 is beyond"
/usr/bin/python3 -c '
import struct, sys
h = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
v = struct.pack("<9f", 0, 0, 0, 1, 0, -5e18, 0, 1, 0)
open("far.ply", "wb").write(h + v + struct.pack("<B3i", 3, 0, 1, 2))
print(len(h) + 12)' >far_at.txt
# the coordinates are checked before the output's size: at 12 iterations this torus's 2304 faces
# would pass the face limit, but the message is about vertex 37 (the OFF's line 40, its y)
awk 'NR == 40 { $2 = "-3e18" } { print }' "$work/data/noisy_torus_48x24.off" >far_torus.off
expect subdiv_far_before_size 2 "$pgt" subdiv far_torus.off --iters 12 -o fo.obj
one_line subdiv_far_before_size_line "^pgt subdiv: far_torus.off:40: sqrt3 input: vertex 37 (0-based): coordinate -3e+18 is beyond"
expect subdiv_far_binary 2 "$pgt" subdiv far.ply --iters 1 -o fo.obj
one_line subdiv_far_binary_offset "^pgt subdiv: far.ply: byte offset $(cat far_at.txt): sqrt3 input: vertex 1 (0-based)"
expect march_not_an_atlas 2 "$pgt" march "$ico" --from 1,1 --dir 1,0 --step 1 --steps 1 -o p.csv
# an atlas that is a fifo without a writer is refused at once (its open() blocked before the
# regular-file check); timeout's 124 would fail the check
rm -f fifo.exr && mkfifo fifo.exr
expect march_fifo_atlas 2 timeout 20 "$pgt" march fifo.exr --from 1,1 --dir 1,0 --step 1 --steps 1 -o p.csv
one_line march_fifo_atlas_one_line "fifo.exr: cannot read: not a regular file"
rm -f fifo.exr
expect march_bad_dir 2 "$pgt" march cs.exr --from 10,10 --dir one,0 --step 1 --steps 1 -o p.csv
expect march_on_atlas 0 "$pgt" march cs.exr --from 20.5,20.5 --dir 1,0 --step 2 --steps 50 -o p.csv
# --dump needs a file name prefix: "" or "dir/" would write hidden .atlas.png / .texels.csv
for d in "" "dumpdir/" "." "dumpdir/.."; do
  expect "march_dump_no_prefix_'$d'" 2 "$pgt" march cs.exr --from 20.5,20.5 --dir 1,0 --step 2 --steps 5 -o p.csv --dump "$d"
  one_line "march_dump_no_prefix_'$d'_one_line" "\-\-dump: '$d' is no file name prefix"
done

# progress lines of pgt atlas (its steps by name, then the EXR), pgt march (steps counted) and
# pgt subdiv (iterations counted): stderr holds them only, and the outputs are the same bytes
PGT_PROGRESS_SECONDS=0.001 expect atlas_progress 0 "$pgt" atlas "$work/data/cube_sphere_8.ply" -o csp1.exr --res 1024 --threads 1
progress_lines atlas_progress_lines atlas "^pgt atlas: writing csp1.exr, [0-9]+ s$"
progress_lines atlas_progress_build_steps atlas "^pgt atlas: (raster|pointers), [0-9]+ s$"
expect atlas_progress_off 0 "$pgt" atlas "$work/data/cube_sphere_8.ply" -o csp0.exr --res 1024 --threads 1
[ ! -s err.txt ] && cmp -s csp0.exr csp1.exr && ok atlas_progress_same_bytes || bad atlas_progress_same_bytes "stderr $(head -c 200 err.txt); $(cmp csp0.exr csp1.exr 2>&1)"
rm -f csp0.exr csp1.exr
PGT_PROGRESS_SECONDS=0.001 expect march_progress 0 "$pgt" march cs.exr --from 20.5,20.5 --dir 1,0.3 --step 2 --steps 300000 -o mp1.csv
progress_lines march_progress_lines march "^pgt march: marching and writing: [1-9][0-9]* of 300000 steps \([0-9]+ %\), [0-9]+ s$"
expect march_progress_off 0 "$pgt" march cs.exr --from 20.5,20.5 --dir 1,0.3 --step 2 --steps 300000 -o mp0.csv
[ ! -s err.txt ] && cmp -s mp0.csv mp1.csv && ok march_progress_same_bytes || bad march_progress_same_bytes "stderr $(head -c 200 err.txt); $(cmp mp0.csv mp1.csv 2>&1)"
rm -f mp0.csv mp1.csv
PGT_PROGRESS_SECONDS=0.001 expect subdiv_progress 0 "$pgt" subdiv "$work/data/cube_sphere_8.ply" --iters 7 --threads 1 -o sdp1.ply
progress_lines subdiv_progress_lines subdiv "^pgt subdiv: sqrt\(3\): [1-9] of 7 iterations \([0-9]+ %\), [0-9]+ s$"
expect subdiv_progress_off 0 "$pgt" subdiv "$work/data/cube_sphere_8.ply" --iters 7 --threads 1 -o sdp0.ply
[ ! -s err.txt ] && cmp -s sdp0.ply sdp1.ply && ok subdiv_progress_same_bytes || bad subdiv_progress_same_bytes "stderr $(head -c 200 err.txt); $(cmp sdp0.ply sdp1.ply 2>&1)"
rm -f sdp0.ply sdp1.ply
# a denormal heading is a heading (strtof's underflow is no error); one that rounds to zero is none
expect march_denormal_dir 0 "$pgt" march cs.exr --from 20.5,20.5 --dir 1e-45,0 --step 2 --steps 1 -o pn.csv
sed -n 2p pn.csv | grep -q "^1,22.5,20.5," && ok march_denormal_dir_heads_right || bad march_denormal_dir_heads_right "$(cat pn.csv)"
expect march_zero_dir 2 "$pgt" march cs.exr --from 20.5,20.5 --dir 1e-50,0 --step 2 --steps 1 -o pn.csv
one_line march_zero_dir_one_line "^pgt march: --dir: the direction 0,0 has no heading"
head -1 p.csv | grep -q "^step,u,v,chart,x,y,z,event" && ok march_csv_header || bad march_csv_header "$(head -1 p.csv)"
# one row per step (the issue's contract): steps 1..N, events inner/jump/search/stop only
/usr/bin/python3 -c 'import csv,sys; r=list(csv.DictReader(open("p.csv"))); s=[int(x["step"]) for x in r]
sys.exit(0 if s==list(range(1,len(r)+1)) and 1<=len(r)<=50 and {x["event"] for x in r}<={"inner","jump","search","stop"} else 1)' \
  && ok march_csv_one_row_per_step || bad march_csv_one_row_per_step "$(head -3 p.csv)"
expect march_with_start 0 "$pgt" march cs.exr --from 20.5,20.5 --dir 1,0 --step 2 --steps 50 -o p0.csv --with-start
sed -n 2p p0.csv | grep -q "^0,20.5,20.5,.*,start$" && [ "$(tail -n +3 p0.csv)" = "$(tail -n +2 p.csv)" ] \
  && ok march_with_start_row_0 || bad march_with_start_row_0 "$(sed -n 2p p0.csv)"
# --density: constant 8-bit grey PNGs of the atlas's size (0, 128 and 255 of 255) and a smaller one
png() { /usr/bin/python3 -c 'import sys,zlib,struct
w,h,v=int(sys.argv[2]),int(sys.argv[3]),int(sys.argv[4])
c=lambda t,d: struct.pack(">I",len(d))+t+d+struct.pack(">I",zlib.crc32(t+d))
raw=b"".join(b"\0"+bytes([v])*w for _ in range(h))
open(sys.argv[1],"wb").write(b"\x89PNG\r\n\x1a\n"+c(b"IHDR",struct.pack(">IIBBBBB",w,h,8,0,0,0,0))+c(b"IDAT",zlib.compress(raw))+c(b"IEND",b""))' "$@"; }
png d0.png 128 128 0 && png d128.png 128 128 128 && png d255.png 128 128 255 && png d_small.png 64 64 255
march=(march cs.exr --from 20.5,20.5 --dir 1,0 --step 2 --steps 50)
expect march_density_zero 0 "$pgt" "${march[@]}" -o pd0.csv --density d0.png
grep -q "0 of 50 steps.*stopped at step 1 (rejected)" out.txt && [ "$(wc -l <pd0.csv)" -eq 2 ] \
  && ok march_density_zero_stops_at_once || bad march_density_zero_stops_at_once "$(cat out.txt)"
expect march_density_one 0 "$pgt" "${march[@]}" -o pd1.csv --density d255.png
cmp -s pd1.csv p.csv && ok march_density_one_never_stops || bad march_density_one_never_stops "$(cat out.txt)"
expect march_density_seed_a 0 "$pgt" "${march[@]}" -o pa.csv --density d128.png --seed 7
expect march_density_seed_b 0 "$pgt" "${march[@]}" -o pb.csv --density d128.png --seed 7
cmp -s pa.csv pb.csv && ok march_density_same_seed_same_bytes || bad march_density_same_seed_same_bytes "differ"
expect march_density_wrong_size 2 "$pgt" "${march[@]}" -o px.csv --density d_small.png
one_line march_density_wrong_size_one_line "\-\-density d_small.png: 64 x 64 pixels, the atlas is 128 x 128"
expect march_density_atlas_channels 2 "$pgt" "${march[@]}" -o px.csv --density cs.exr
one_line march_density_atlas_channels_one_line "no channel 'density', 'Y' or 'R'"
expect march_density_overwrite 2 "$pgt" "${march[@]}" -o d128.png --density d128.png
one_line march_density_overwrite_one_line "never overwrites an input"
expect march_bad_seed 2 "$pgt" "${march[@]}" -o px.csv --density d128.png --seed -1
# --backend: cpu is the default's output; a GPU backend refuses --density (a host function)
# before reading anything, and an unknown backend is a bad flag (tests/backend_diff.sh compares
# the cl and vk CSVs with the reference's)
expect march_backend_cpu 0 "$pgt" "${march[@]}" -o pbc.csv --backend cpu
cmp -s pbc.csv p.csv && ok march_backend_cpu_is_default || bad march_backend_cpu_is_default "differ"
expect march_density_on_gpu 2 "$pgt" "${march[@]}" -o pbg.csv --density d128.png --backend vk
[ ! -e pbg.csv ] && one_line march_density_on_gpu_says_why \
  "density is a host function.*--backend cpu only, not vk"
expect march_bad_backend 2 "$pgt" "${march[@]}" -o pbb.csv --backend gpu
expect march_bad_device 2 "$pgt" "${march[@]}" -o pbd.csv --backend cl --device x
# --dump's two files are outputs too: they may not replace an input or -o (both ran, exit 0)
cp d128.png dm.atlas.png
expect march_dump_over_input 2 "$pgt" "${march[@]}" -o pdm.csv --density dm.atlas.png --dump dm
one_line march_dump_over_input_one_line "dm.atlas.png is an input file; pgt never overwrites an input"
cmp -s d128.png dm.atlas.png && ok march_dump_input_kept || bad march_dump_input_kept "changed"
expect march_dump_over_out 2 "$pgt" "${march[@]}" -o dd.texels.csv --dump dd
one_line march_dump_over_out_one_line "dd.texels.csv is named for two outputs"
# a failed --png leaves no new atlas (the EXR was renamed into place before the PNG was tried)
rm -f nopng.exr
expect atlas_png_fails 2 "$pgt" atlas "$work/data/cube_sphere_8.ply" -o nopng.exr --res 64 --png no_such_dir/x.png
[ ! -e nopng.exr ] && [ -z "$(ls nopng.exr* 2>/dev/null)" ] && ok atlas_png_fails_writes_nothing \
  || bad atlas_png_fails_writes_nothing "$(ls nopng.exr*)"
# ... nor a failed -o a new PNG (pgt_cli_stage: every output appears once all are written)
rm -f nopng.png; mkdir -p adir.exr
expect atlas_exr_fails 2 "$pgt" atlas "$work/data/cube_sphere_8.ply" -o adir.exr --res 64 --png nopng.png
one_line atlas_exr_fails_one_line "cannot write adir.exr: it is a folder, not a regular file"
[ -z "$(ls nopng.png* adir.exr.* 2>/dev/null)" ] && ok atlas_exr_fails_writes_nothing \
  || bad atlas_exr_fails_writes_nothing "$(ls nopng.png* adir.exr.*)"
# a failed march leaves no --dump files; an output that is a fifo or device is refused, not
# replaced by a regular file (as root a rename would replace /dev/null)
rm -f dpf.atlas.png dpf.texels.csv; mkdir -p mdir.csv
expect march_fails_no_dump 2 "$pgt" "${march[@]}" -o mdir.csv --dump dpf
[ -z "$(ls dpf.* mdir.csv.* 2>/dev/null)" ] && ok march_fails_writes_nothing || bad march_fails_writes_nothing "$(ls dpf.*)"
rm -f fifo.csv; mkfifo fifo.csv
expect march_fifo_out 2 "$pgt" "${march[@]}" -o fifo.csv
one_line march_fifo_out_one_line "cannot write fifo.csv: it is a device, fifo or socket, not a regular file"
[ -p fifo.csv ] && ok march_fifo_kept || bad march_fifo_kept "$(ls -l fifo.csv)"
rm -f fifo.csv
# so do the single-output writers, here pgt subdiv: before the work (pgt_cli_check_outputs; the
# writer's own refusal, pgt_replace_file, is test_mesh_io's)
mkfifo fifo.obj
expect subdiv_fifo_out 2 "$pgt" subdiv "$work/data/cube_sphere_8.ply" --iters 1 -o fifo.obj
one_line subdiv_fifo_out_one_line "cannot write fifo.obj: it is a device, fifo or socket, not a regular file"
[ -p fifo.obj ] && [ -z "$(ls fifo.obj.* 2>/dev/null)" ] && ok subdiv_fifo_kept || bad subdiv_fifo_kept "$(ls -l fifo.obj*)"
rm -f fifo.obj
# a benchmark's --out may not be one of its input meshes
cp "$work/data/cube_sphere_8.obj" bin.obj
expect bench_atlas_out_is_input 2 "$pgt" bench atlas --meshes ./bin.obj --out bin.obj --repeat 1 --threads 1 --res 64
one_line bench_atlas_out_is_input_one_line "\-\-out bin.obj is the input mesh ./bin.obj"
expect bench_march_out_is_input 2 "$pgt" bench march --meshes ./bin.obj --out ./bin.obj --threads 1 --walkers 16 --steps 10 --res 64 --repeat 1
cmp -s bin.obj "$work/data/cube_sphere_8.obj" && ok bench_out_inputs_kept || bad bench_out_inputs_kept "changed"
# --position picks the rows: no (the marching rule alone), yes (with the 3D position) or both
expect bench_march_position_bad 2 "$pgt" bench march --meshes ./bin.obj --position maybe --out res/mp.csv
one_line bench_march_position_bad_one_line "\-\-position: 'maybe' is not no, yes or no,yes"
expect bench_march_position_no 0 "$pgt" bench march --meshes ./bin.obj --position no --out res/mp.csv --threads 1 --walkers 16 --steps 10 --res 64 --repeat 1
[ "$(grep -v '^#' res/mp.csv | cut -d, -f9 | tr '\n' ' ')" = "position no " ] && ok bench_march_position_no_rows \
  || bad bench_march_position_no_rows "$(grep -v '^#' res/mp.csv | cut -d, -f9 | tr '\n' ' ')"
# --backends: GPU rows after ours, marching the same walkers to the same steps (the bench checks
# every walker's end and step count against ours); a device asked for must open
expect bench_march_bad_backends 2 "$pgt" bench march --meshes ./bin.obj --backends cuda --out res/mg.csv
one_line bench_march_bad_backends_one_line "\-\-backends: expected cl, vk, both or none, got 'cuda'"
expect bench_march_no_device 2 "$pgt" bench march --meshes ./bin.obj --backends vk --device 999 --out res/mg.csv
[ ! -e res/mg.csv ] && grep -q "device 999" err.txt && ok bench_march_no_device_named \
  || bad bench_march_no_device_named "$(cat err.txt)"
if "$pgt" devices | grep -q "^  cl 0:" && "$pgt" devices | grep -q "^  vk 0:"; then
  expect bench_march_backends 0 "$pgt" bench march --meshes ./bin.obj --backends both --position no --out res/mg.csv --threads 1 --walkers 100 --steps 300 --res 128 --repeat 1
  # backend (column 19) and steps (10) of each row: ours, then cl and vk with the same steps
  rows=$(grep -v '^#' res/mg.csv | tail -n +2 | cut -d, -f10,19 | tr '\n' ' ')
  steps=$(grep -v '^#' res/mg.csv | sed -n 2p | cut -d, -f10)
  [ "$rows" = "$steps,cpu $steps,cl $steps,vk " ] && [ "$steps" -gt 1000 ] && ok bench_march_backend_rows \
    || bad bench_march_backend_rows "$rows"
  grep -v '^#' res/mg.csv | awk -F, 'NR > 1 && $19 != "cpu" && !($20 > 0 && $8 == "" && $16 == "") { bad = 1 }
    END { exit bad }' && ok bench_march_backend_fields || bad bench_march_backend_fields "$(grep -v '^#' res/mg.csv)"
  fields_match bench_march_backend_field_counts res/mg.csv
fi
# a '"' in a mesh's name is one CSV field (RFC 4180: quoted, the quote doubled), not a broken row
cp "$work/data/cube_sphere_8.obj" 'q"x.obj'
expect bench_subdiv_quoted_name 0 "$pgt" bench subdiv --quick --no-oracles --backends none --meshes './q"x.obj' --threads 1 --out res/sq.csv
grep -q '^"./q""x.obj",' res/sq.csv && ok bench_subdiv_quoted_name_field || bad bench_subdiv_quoted_name_field "$(grep -v '^#' res/sq.csv)"
# a bench's --out leaves room for OUT.failed (written when a mesh fails): at most 248 bytes
expect bench_atlas_out_failed_too_long 2 "$pgt" bench atlas --quick --meshes ./bin.obj --out "res/$(printf 'L%.0s' $(seq 245)).csv" --threads 1 --repeat 1 --res 64
one_line bench_atlas_out_failed_too_long_one_line "\-\-out res/L*\.csv: a file name of at most 248 bytes"
l248="res/$(printf 'L%.0s' $(seq 244)).csv"
expect bench_atlas_out_248 2 "$pgt" bench atlas --quick --meshes ./bin.obj,no_such_mesh.obj --out "$l248" --threads 1 --repeat 1 --res 64
[ -s "$l248.failed" ] && [ ! -e "$l248" ] && ok bench_atlas_out_248_failed_written || bad bench_atlas_out_248_failed_written "$(ls res | cut -c 1-20)"
rm -f "$l248.failed"
expect bench_march_quoted_name 0 "$pgt" bench march --meshes './q"x.obj' --position no --out res/mq.csv --threads 1 --walkers 16 --steps 10 --res 64 --repeat 1
grep -q '^"q""x.obj",' res/mq.csv && ok bench_march_quoted_name_field || bad bench_march_quoted_name_field "$(grep -v '^#' res/mq.csv)"
expect bench_atlas_quoted_name 0 "$pgt" bench atlas --meshes './q"x.obj' --out res/tq.csv --threads 1 --repeat 1 --res 64
grep -q '^ours,"q""x.obj",' res/tq.csv && ok bench_atlas_quoted_name_field || bad bench_atlas_quoted_name_field "$(grep -v '^#' res/tq.csv)"
rm -f 'q"x.obj'
# a bench whose mesh cannot be read: exit 2 naming the file; the other rows go to OUT.failed and
# OUT is left as it was (pgt_cli_bench_close: a run with failures never replaces a whole table)
echo "old table" > res/t1.csv
expect bench_atlas_missing_mesh 2 "$pgt" bench atlas --meshes no_such_mesh.obj --threads 1 --repeat 1 --out res/t1.csv
grep -q "no_such_mesh.obj" err.txt && grep -q "^paper,Hebe" res/t1.csv.failed && ok bench_atlas_missing_mesh_named \
  || bad bench_atlas_missing_mesh_named "$(cat err.txt)"
[ "$(cat res/t1.csv)" = "old table" ] && grep -q "res/t1.csv left as it was" err.txt && ok bench_atlas_failed_keeps_table \
  || bad bench_atlas_failed_keeps_table "$(cat res/t1.csv | head -3)"
fields_match bench_atlas_fields res/t1.csv.failed
expect bench_march_missing_mesh 2 "$pgt" bench march --meshes no_such_mesh.obj --threads 1 --out res/m.csv
grep -q "no_such_mesh.obj" err.txt && ok bench_march_missing_mesh_named || bad bench_march_missing_mesh_named "$(cat err.txt)"

# an input that never ends (a link to /dev/zero named like a mesh) is read up to 1 GiB, then refused
ln -sfn /dev/zero zero.obj
expect mesh_endless_input 2 "$pgt" subdiv zero.obj --iters 1 -o zero_out.off
one_line mesh_endless_input_one_line "^pgt subdiv: zero.obj: more than 1073741824 bytes from a pipe or device"
rm -f zero.obj
# a PNG whose header declares more pixels than its bytes can hold is refused before they are
# allocated (16384^2 RGBA 16-bit: 2 GiB for a 60-byte file)
/usr/bin/python3 -c '
import struct, zlib
def chunk(t, d): return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
open("huge.png", "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 16384, 16384, 16, 6, 0, 0, 0))
    + chunk(b"IDAT", zlib.compress(b"\0" * 64)) + chunk(b"IEND", b""))'
expect png_declared_too_big 2 "$pgt" march cs.exr --from 10.5,10.5 --dir 1,0 --step 1 --steps 1 -o hp.csv --mask huge.png
one_line png_declared_too_big_one_line "huge.png: declares 16384 x 16384 pixels, more than its [0-9]* bytes can hold"
# pgt ivy (the algorithms are test_expand, test_bezier, test_terminals, test_ivy)
expect ivy_help 0 "$pgt" ivy --help
for flag in --grammar --seeds --seed-file --mask --density --paint --no-leaves --no-secondary --threads -o --curves --brush --param; do
  grep -q -- "$flag" out.txt && ok "ivy_help_documents_$flag" || bad "ivy_help_documents_$flag" "missing"
done
short=(--param maxMainSteps=30)
expect ivy_no_seeds 2 "$pgt" ivy cs.exr -o ivy.ply
one_line ivy_no_seeds_one_line "\-\-seeds"
expect ivy_no_output 2 "$pgt" ivy cs.exr --seeds 2
expect ivy_overwrite_input 2 "$pgt" ivy cs.exr --seeds 2 -o cs.exr
one_line ivy_overwrite_input_one_line "never overwrites"
# the input named as a shared mesh (no spot.obj here: the shared folder's) is refused as an output
# too, also through a link to it; were it not, the rename would replace the link, not the mesh
rm -f spot.obj && ln -sfn "$src/../shared/datasets/meshes/spot.obj" spot_link.ply
expect ivy_named_input_output 2 "$pgt" ivy spot.obj --seeds 1 -o spot_link.ply
one_line ivy_named_input_output_one_line "^pgt ivy: -o spot_link.ply is the input mesh spot.obj; pgt never overwrites an input$"
[ -L spot_link.ply ] && ok ivy_named_input_link_kept || bad ivy_named_input_link_kept "spot_link.ply is no longer a link"
expect ivy_named_input_curves 2 "$pgt" ivy spot.obj --seeds 1 -o ivn.ply --curves spot_link.ply
one_line ivy_named_input_curves_one_line "\-\-curves spot_link.ply is the input mesh spot.obj"
rm -f spot_link.ply
# progress lines (PGT_PROGRESS_SECONDS): with a period of 1 ms every stage prints, one line each
# of the form "pgt ivy: STAGE[: DONE of TOTAL UNIT (P %)], S s" and nothing else on stderr; the
# output is the same bytes as without them; a period that is not a number is refused
PGT_PROGRESS_SECONDS=0.001 expect ivy_progress 0 "$pgt" ivy cs.exr --seeds 2 --param maxMainSteps=20 -o ivp1.ply
progress_lines ivy_progress_lines ivy "^pgt ivy: "
expect ivy_progress_off 0 "$pgt" ivy cs.exr --seeds 2 --param maxMainSteps=20 -o ivp0.ply
[ ! -s err.txt ] && cmp -s ivp0.ply ivp1.ply && ok ivy_progress_same_bytes || bad ivy_progress_same_bytes "stderr $(head -c 200 err.txt); cmp $(cmp ivp0.ply ivp1.ply 2>&1)"
PGT_PROGRESS_SECONDS=soon expect ivy_progress_bad 2 "$pgt" ivy cs.exr --seeds 2 --param maxMainSteps=20 -o ivp2.ply
one_line ivy_progress_bad_one_line "^pgt ivy: the environment variable PGT_PROGRESS_SECONDS is 'soon': give seconds between progress lines, 0.001 to 86400 (0: none)$"
PGT_PROGRESS_SECONDS=1e-9 expect ivy_progress_too_short 2 "$pgt" ivy cs.exr --seeds 2 --param maxMainSteps=20 -o ivp2.ply
[ ! -e ivp2.ply ] && ok ivy_progress_bad_writes_nothing || bad ivy_progress_bad_writes_nothing "ivp2.ply written"
# an error stays stderr's last line: the lines stop before it is printed (an error raised while
# the lines run: the terminals' memory bound, after about 0.1 s of earlier stages)
PGT_PROGRESS_SECONDS=0.001 PGT_MEMORY_AVAILABLE=20000000 expect ivy_progress_error 2 "$pgt" ivy cs.exr --seeds 64 -o ivp3.ply
head -n 1 err.txt | grep -Eq "^pgt ivy: [a-z]+(: [0-9]+ of [0-9]+ seeds \([0-9]+ %\))?, [0-9]+ s$" && tail -n 1 err.txt | grep -q "^pgt ivy: terminals: [0-9]* vertices and" &&
  ok ivy_progress_error_last || bad ivy_progress_error_last "$(tail -n 3 err.txt)"
rm -f ivp0.ply ivp1.ply
# bark and leaves beyond the memory available (PGT_MEMORY_AVAILABLE: 2 * 10^7 bytes) are refused
# before they are allocated
PGT_MEMORY_AVAILABLE=20000000 expect ivy_memory 2 "$pgt" ivy cs.exr --seeds 2 -o ivm.ply
one_line ivy_memory_one_line "^pgt ivy: terminals: [0-9]* vertices and [0-9]* triangles (.*) would take 0.[0-9]* GiB, more than the 0.02 GiB allowed now (--seeds 2;"
[ ! -e ivm.ply ] && ok ivy_memory_writes_nothing || bad ivy_memory_writes_nothing "ivm.ply written"
# a grammar running 2^25 items a seed over 2^20 seeds is stopped by the total bound (each seed
# gets 2^31 / 2^20 = 2048 items) instead of running for weeks; the flag's range is checked
printf 'Ivy --> B(0)\nB(n) --> case n < 24 : Branch(2) {B(n + 1), B(n + 1)} else : NIL\n' >tree.grammar
expect ivy_total_items 2 "$pgt" ivy cs.exr --grammar tree.grammar --seeds 1048576 -o ivt.ply
one_line ivy_total_items_one_line "^pgt ivy: tree.grammar:2:45: seed 0 (id 1): more than 2048 grammar items run (option max_total_items: 2147483648 over all 1048576 seeds, 2048 a seed)"
expect ivy_total_items_flag 2 "$pgt" ivy cs.exr --grammar tree.grammar --seeds 4 -o ivt.ply --max-total-items 4000
one_line ivy_total_items_flag_one_line "more than 1000 grammar items run (option max_total_items: 4000 over all 4 seeds, 1000 a seed)"
expect ivy_total_items_zero 2 "$pgt" ivy cs.exr --seeds 1 -o ivt.ply --max-total-items 0
one_line ivy_total_items_zero_one_line "^pgt ivy: \-\-max-total-items: expected a whole number from 1 to 70368744177664, got '0'$"
# binary outputs are named for their format (the PLY and PNG writers do not follow the name)
expect ivy_out_not_ply 2 "$pgt" ivy cs.exr --seeds 1 -o ive.obj
one_line ivy_out_not_ply_one_line "^pgt ivy: -o ive.obj: the output is a PLY file (name it \*.ply)$"
expect ivy_mask_mesh_not_ply 2 "$pgt" ivy cs.exr --seeds 1 -o ive.ply --mask-mesh ive.off
one_line ivy_mask_mesh_not_ply_one_line "\-\-mask-mesh ive.off: the output is a PLY file"
expect ivy_mask_out_not_png 2 "$pgt" ivy cs.exr --seeds 1 -o ive.PLY --mask-out ive.jpg
one_line ivy_mask_out_not_png_one_line "\-\-mask-out ive.jpg: the picture is a .png file"
[ -z "$(ls ive.* 2>/dev/null)" ] && ok ivy_wrong_names_write_nothing || bad ivy_wrong_names_write_nothing "$(ls ive.*)"
# a failed run leaves none of its outputs: --mask-out was written before the expansion failed,
# -o before --curves was tried
rm -f ivf.ply ivf.png; mkdir -p ivdir.csv
expect ivy_fail_expand 2 "$pgt" ivy cs.exr --seeds 1 --param stepLength=1e30 --mask-out ivf.png -o ivf.ply
expect ivy_fail_curves 2 "$pgt" ivy cs.exr --seeds 2 -o ivf.ply --curves ivdir.csv --mask-out ivf.png "${short[@]}"
one_line ivy_fail_curves_one_line "cannot write ivdir.csv: it is a folder, not a regular file"
[ -z "$(ls ivf.* ivdir.csv.* 2>/dev/null)" ] && ok ivy_fail_writes_nothing || bad ivy_fail_writes_nothing "$(ls ivf.*)"
# two names of one new file are refused before anything is written; a writer's error names the
# user's path, not the staging name
expect ivy_same_new_output 2 "$pgt" ivy cs.exr --seeds 2 -o ivs.ply --mask-mesh ./ivs.ply "${short[@]}"
one_line ivy_same_new_output_one_line "./ivs.ply is named for two outputs"
expect ivy_missing_folder 2 "$pgt" ivy cs.exr --seeds 2 -o ivs.ply --curves nodir/c.csv "${short[@]}"
one_line ivy_missing_folder_one_line "^pgt ivy: cannot write nodir/c.csv: No such file or directory$"
[ -z "$(ls -d ivs.ply .pgt-stage.* 2>/dev/null)" ] && ok ivy_same_writes_nothing || bad ivy_same_writes_nothing "$(ls -d ivs.ply .pgt-stage.*)"
expect ivy_one_thread 0 "$pgt" ivy cs.exr --seeds 3 -o ivy1.ply --curves c1.csv --threads 1 "${short[@]}"
expect ivy_two_threads 0 "$pgt" ivy cs.exr --seeds 3 -o ivy2.ply --curves c2.csv --threads 2 "${short[@]}"
cmp -s ivy1.ply ivy2.ply && cmp -s c1.csv c2.csv && ok ivy_same_bytes_any_threads || bad ivy_same_bytes_any_threads "outputs differ"
head -c 400 ivy1.ply | grep -a -q "property float nx" && head -c 400 ivy1.ply | grep -a -q "property float u" \
  && ok ivy_ply_has_normals_uvs || bad ivy_ply_has_normals_uvs "$(head -c 300 ivy1.ply)"
[ "$(head -1 c1.csv)" = "branch,segment,p0x,p0y,p0z,b1x,b1y,b1z,b2x,b2y,b2z,p1x,p1y,p1z,n0x,n0y,n0z,n1x,n1y,n1z" ] \
  && ok ivy_curves_header || bad ivy_curves_header "$(head -1 c1.csv)"
segs=$(sed -n 's/.* points, \([0-9]*\) segments.*/\1/p' out.txt)
[ -n "$segs" ] && [ "$segs" -gt 0 ] && [ "$(($(wc -l <c1.csv) - 1))" -eq "$segs" ] \
  && ok ivy_curves_one_row_per_segment || bad ivy_curves_one_row_per_segment "segments '$segs', rows $(wc -l <c1.csv)"
expect ivy_no_leaves 0 "$pgt" ivy cs.exr --seeds 3 -o ivy3.ply --no-leaves "${short[@]}"
grep -q " 0 leaves" out.txt && ok ivy_no_leaves_counts || bad ivy_no_leaves_counts "$(cat out.txt)"
expect ivy_no_secondary 0 "$pgt" ivy cs.exr --seeds 3 -o ivy4.ply --no-secondary "${short[@]}"
b1=$(sed -n 's/.* segments, \([0-9]*\) branches.*/\1/p' out.txt)
[ "$b1" = 3 ] && ok ivy_no_secondary_one_branch_per_seed || bad ivy_no_secondary_one_branch_per_seed "$(cat out.txt)"
printf 'A --> Marching(1, 0, 1) { NIL, NIL }\n' >plain.grammar
expect ivy_no_secondary_needs_param 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply --grammar plain.grammar --no-secondary
one_line ivy_no_secondary_names_param "^pgt ivy: --no-secondary sets the param secondaryBranches to 0: plain.grammar: no param"
expect ivy_no_secondary_and_param 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply --param secondaryBranches=3 --no-secondary
one_line ivy_no_secondary_and_param_one_line "^pgt ivy: \-\-param secondaryBranches=3 and \-\-no-secondary both set secondaryBranches"
# nothing grows past the seed: a PLY without faces, said on stderr (render and subdiv refuse it)
expect ivy_nothing_grew 0 "$pgt" ivy cs.exr --seeds 1 -o empty.ply --no-leaves --param maxMainSteps=0
grep -q "^pgt ivy: note: no polygons (0 segments grew): empty.ply has no faces" err.txt \
  && head -c 400 empty.ply | grep -a -q "^element face 0" && ok ivy_nothing_grew_said || bad ivy_nothing_grew_said "$(cat err.txt)"
printf '# seeds\ntexel 20.5 20.5 1 0\nbogus 1 2\n' >seeds_bad.txt
expect ivy_seed_file_bad_line 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply --seed-file seeds_bad.txt
one_line ivy_seed_file_names_line "seeds_bad.txt:3:"
printf 'texel 20.5 20.5 1 0\n\000point 1 0 0\n' >seeds_nul.txt
expect ivy_seed_file_nul 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply --seed-file seeds_nul.txt
one_line ivy_seed_file_nul_one_line "seeds_nul.txt:2:1: a NUL byte"
printf 'texel 0.5 0.5\n' >seeds_bg.txt
expect ivy_seed_not_inner 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply --seed-file seeds_bg.txt
one_line ivy_seed_not_inner_one_line "seeds_bg.txt:1: texel 0.5 0.5 is not on an inner texel"
printf 'point 5 5 5\n' >seeds_far.txt
expect ivy_seed_off_surface 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply --seed-file seeds_far.txt
one_line ivy_seed_off_surface_one_line "seeds_far.txt:1: .*not on the surface"
printf 'texel 20.5 20.5 1 0\npoint 1 0 0\n' >seeds.txt
expect ivy_seed_file 0 "$pgt" ivy cs.exr --seeds 2 -o x.ply --seed-file seeds.txt "${short[@]}"
expect ivy_seed_file_too_few 2 "$pgt" ivy cs.exr --seeds 3 -o x.ply --seed-file seeds.txt
# a UTF-8 byte order mark (Notepad) before the first line is read past: the same ivy
{ printf '\357\273\277'; cat seeds.txt; } >seeds_bom.txt
expect ivy_seed_file_bom 0 "$pgt" ivy cs.exr --seeds 2 -o xb.ply --seed-file seeds_bom.txt "${short[@]}"
cmp -s x.ply xb.ply && ok ivy_seed_file_bom_same || bad ivy_seed_file_bom_same "x.ply and xb.ply differ"
# ... and columns count from the text after it
printf '\357\273\277texel 20.5\000 20.5 1 0\n' >seeds_bom_nul.txt
expect ivy_seed_file_bom_nul 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply --seed-file seeds_bom_nul.txt
one_line ivy_seed_file_bom_nul_column "seeds_bom_nul.txt:1:11: a NUL byte"
printf 'stroke\npoint 1 0 0\npoint 0.9 0.43 0\npoint 0.7 0.71 0\nstroke\npoint 0 0 1\n' >strokes.txt
expect ivy_paint 0 "$pgt" ivy cs.exr --seeds 2 -o x.ply --paint strokes.txt --mask-out m.png "${short[@]}"
grep -q "painted 2 strokes, 4 points" out.txt && [ -s m.png ] && ok ivy_paint_reports || bad ivy_paint_reports "$(cat out.txt)"
# --mask-out writes what --mask reads: the mask read back and written again is the same picture
expect ivy_mask_out_read_back 0 "$pgt" ivy cs.exr --seeds 2 -o x.ply --mask m.png --mask-out m2.png "${short[@]}"
cmp -s m.png m2.png && ok ivy_mask_out_same || bad ivy_mask_out_same "m.png and m2.png differ"
expect ivy_forbid 0 "$pgt" ivy cs.exr --seeds 2 -o x.ply --forbid strokes.txt --mask-mesh red.ply "${short[@]}"
grep -q "forbidden 2 strokes, 4 points" out.txt && head -c 300 red.ply | grep -a -q "element face [1-9]" \
  && ok ivy_forbid_mask_mesh || bad ivy_forbid_mask_mesh "$(cat out.txt)"
expect ivy_stroke_in_seed_file 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply --seed-file strokes.txt
one_line ivy_stroke_in_seed_file_one_line "strokes.txt:1: 'stroke' belongs in a --paint file"
"$pgt" atlas "$work/data/cube_sphere_8.ply" -o small.exr --res 64 --png small.png >/dev/null 2>&1
expect ivy_mask_wrong_size 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply --mask small.png
one_line ivy_mask_wrong_size_one_line "small.png: 64 x 64 pixels, the atlas is 128 x 128"

# --density feeds the grammar's context.density(texCoord): 20 steps per seed where it reads
# more than 0.5 (128 / 255 = 0.502 too), none where it reads 0 or without --density
# terminal values are checked where the grammar gives them (line:col), before the mesh is built;
# a finite but huge radius used to write non-finite vertices with exit 0
printf 'Ivy --> M(0)\nM(n) --> Marching(4, 0, n < 5) {M(n + 1), Bark(-0.01, C1)}\n' >neg_bark.grammar
expect ivy_bark_negative 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply --grammar neg_bark.grammar
one_line ivy_bark_negative_names_place "neg_bark.grammar:2:43: seed 0 (id 1): Bark radius -0.01 is not in"
expect ivy_bark_huge 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply --param barkRadius=3e38 "${short[@]}"
one_line ivy_bark_huge_names_place "ivy.grammar:[0-9]*:[0-9]*: seed 0 (id 1): Bark radius 3e+38 is not in"
# the terminal builder's bound of 256 Leaves records a segment, checked where the grammar emits them
for n in 256 257; do
  printf 'Ivy --> M(0)\nM(n) --> Marching(4, 0, n < 1) {M(n + 1), L(0)}\nL(k) --> case k < %d : Leaves(1, 0.01) L(k + 1)\n         else : Bark(0.01, C1)\n' $n >leaves$n.grammar
done
expect ivy_256_leaves_records 0 "$pgt" ivy cs.exr --seeds 1 -o x.ply --grammar leaves256.grammar
expect ivy_257_leaves_records 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply --grammar leaves257.grammar
one_line ivy_257_leaves_names_place "leaves257.grammar:3:25: seed 0 (id 1): more than 256 Leaves records on one segment"
printf 'A --> B(0)\nB(n) --> Marching(2, 0, n < 20 && context.density(texCoord) > 0.5) { B(n + 1), NIL }\n' >dens.grammar
for d in d255 d128 d0 none; do
  if [ $d = none ]; then dens=(); else dens=(--density $d.png); fi
  expect "ivy_density_$d" 0 "$pgt" ivy cs.exr --seeds 3 -o x.ply --grammar dens.grammar "${dens[@]}"
  want=60; case $d in d0 | none) want=0 ;; esac
  grep -q "  $((want + 3)) points, $want segments" out.txt && ok "ivy_density_${d}_segments" \
    || bad "ivy_density_${d}_segments" "$(sed -n 2p out.txt)"
done
expect ivy_density_wrong_size 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply --grammar dens.grammar --density d_small.png
one_line ivy_density_wrong_size_one_line "\-\-density d_small.png: 64 x 64 pixels"

# pgt grammar (the language is test_grammar's)
expect grammar_help 0 "$pgt" grammar --help
for flag in --dump --param; do
  grep -q -- "$flag" out.txt && ok "grammar_help_documents_$flag" || bad "grammar_help_documents_$flag" "missing"
done
# --param values are decimal numbers as a grammar file writes them: no hex, blanks or inf
for v in 0x10 " 3" inf; do
  expect "grammar_param_not_decimal_'$v'" 2 "$pgt" grammar "$src/grammars/ivy.grammar" --param "stepLength=$v"
  one_line "grammar_param_not_decimal_'$v'_one_line" "expected NAME=VALUE with a finite decimal number"
done
expect grammar_param_decimal 0 "$pgt" grammar "$src/grammars/ivy.grammar" --param stepLength=.5e1
expect grammar_ivy 0 "$pgt" grammar "$src/grammars/ivy.grammar"
grep -q "maxMainSteps" out.txt && ok grammar_ivy_lists_params || bad grammar_ivy_lists_params "$(cat out.txt)"
expect grammar_param 0 "$pgt" grammar "$src/grammars/ivy.grammar" --param maxMainSteps=20
grep -q "maxMainSteps=20" out.txt && ok grammar_param_applied || bad grammar_param_applied "$(cat out.txt)"
expect grammar_unknown_param 2 "$pgt" grammar "$src/grammars/ivy.grammar" --param nope=1
one_line grammar_unknown_param_one_line "nope"
many=(); for i in $(seq 257); do many+=(--param maxMainSteps=$i); done
expect grammar_too_many_params 2 "$pgt" grammar "$src/grammars/ivy.grammar" "${many[@]}"
one_line grammar_too_many_params_one_line "\-\-param given more than 256 times"
expect ivy_too_many_params 2 "$pgt" ivy cs.exr --seeds 1 -o x.ply "${many[@]}"
one_line ivy_too_many_params_one_line "\-\-param given more than 256 times"
printf 'A --> Marching(1, 0, 1) { B }\nB --> NIL\n' >bad.grammar
expect grammar_bad 2 "$pgt" grammar bad.grammar
one_line grammar_bad_names_file_line_col "bad.grammar:1:"
"$pgt" grammar "$src/grammars/ivy.grammar" --dump >dump.grammar 2>err.txt
expect grammar_dump_compiles 0 "$pgt" grammar dump.grammar
# --help: the dump "compiles to the same listing": for every shipped grammar (terminals without
# arguments keep their parentheses)
for g in "$src"/grammars/*.grammar; do
  b=$(basename "$g" .grammar)
  "$pgt" grammar "$g" --dump >"dump_$b.grammar" 2>err.txt
  if "$pgt" grammar "$g" 2>&1 | sed "s|$g|G|" >list_a.txt &&
     "$pgt" grammar "dump_$b.grammar" 2>&1 | sed "s|dump_$b.grammar|G|" >list_b.txt &&
     cmp -s list_a.txt list_b.txt; then
    ok "grammar_dump_same_listing_$b"
  else
    bad "grammar_dump_same_listing_$b" "$(diff list_a.txt list_b.txt | head -3)"
  fi
done
# the dump of a grammar with --param overrides compiles to the same values (the overridden param
# as its value, the params after it from their expressions, re-evaluated alike)
printf 'param n = 2\nparam m = n * 2\nparam q = m + 1\nA --> Branch(n) {B, B}\nB --> NIL\n' >ov.grammar
"$pgt" grammar ov.grammar --param m=7 --dump >ov_dump.grammar 2>err.txt
expect grammar_dump_override 0 "$pgt" grammar ov_dump.grammar
grep -q "3 params (n=2, m=7, q=8)" out.txt && ok grammar_dump_override_values || bad grammar_dump_override_values "$(cat out.txt)"
# a param may not take the name of a rule's parameter above it (the dump lists params first)
printf 'S --> A(1)\nA(n) --> Marching(n, 0, n < 3) {NIL, NIL}\nparam n = 2\n' >pclash.grammar
expect grammar_param_after_rule 2 "$pgt" grammar pclash.grammar
one_line grammar_param_after_rule_one_line "^pgt grammar: pclash.grammar:3:7: found the param 'n', the name of a rule's parameter above"

# pgt render (the pictures themselves are test_render's)
expect render_help 0 "$pgt" render --help
for flag in -o --width --height --camera --view --up --spp --no-shadows --background --threads; do
  grep -q -- "$flag" out.txt && ok "render_help_documents_$flag" || bad "render_help_documents_$flag" "missing"
done
grep -q "render" <("$pgt" --help) && ok help_lists_render || bad help_lists_render "no render in pgt --help"
# a colour that is not three numbers after a mesh file's name is named as the colour (it was
# "unknown mesh file extension" of the whole argument)
expect render_colour_not_numbers 2 "$pgt" render "$ico@nan,0,0" -o rc.png --width 16 --height 16
one_line render_colour_not_numbers_one_line "colour 'nan,0,0': expected three numbers in \[0,1\]"
expect render_ok 0 "$pgt" render "$ico" -o r.png --width 64 --height 48 --spp 1 --threads 2
/usr/bin/python3 -c 'import struct,sys; d=open("r.png","rb").read(24)
sys.exit(0 if d[:8]==b"\x89PNG\r\n\x1a\n" and struct.unpack(">II",d[16:24])==(64,48) else 1)' \
  && ok render_png_size || bad render_png_size "$(head -c 24 r.png | od -c | head -2)"
one_line render_timing_line "^render: 64x48, 1 spp, 1 mesh, 80 triangles: .*BVH .* ms, trace .* ms"
cam=$(sed -n 's/^camera: --camera //p' out.txt)
[ -n "$cam" ] && ok render_prints_camera || bad render_prints_camera "$(cat out.txt)"
# the printed camera reproduces the picture byte for byte, with any thread count
expect render_camera_reproduces 0 "$pgt" render "$ico" -o r2.png --width 64 --height 48 --spp 1 --camera "$cam" --threads 1
cmp -s r.png r2.png && ok render_same_bytes || bad render_same_bytes "r.png and r2.png differ"
# progress lines: the rays counted in rows, and the timing line still last; the same picture
PGT_PROGRESS_SECONDS=0.001 expect render_progress 0 "$pgt" render "$ico" -o r3.png --width 256 --height 192 --spp 4 --camera "$cam"
progress_lines render_progress_lines render "^pgt render: rays: [0-9]+ of 192 rows \([0-9]+ %\), [0-9]+ s$" "^render: "
tail -n 1 err.txt | grep -q "^render: 256x192" && ok render_progress_timing_last || bad render_progress_timing_last "$(tail -n 2 err.txt)"
expect render_progress_off 0 "$pgt" render "$ico" -o r4.png --width 256 --height 192 --spp 4 --camera "$cam"
cmp -s r3.png r4.png && ok render_progress_same_bytes || bad render_progress_same_bytes "r3.png and r4.png differ"
ls ./*.tmp.* >/dev/null 2>&1 && bad render_no_temporary_left "$(ls ./*.tmp.*)" || ok render_no_temporary_left
# a PLY with extra vertex and face properties (skipped by the reader)
expect render_ply_extra_properties 0 "$pgt" render "$src/tests/data/valid/groups_extra.ply" -o rx.png --width 32 --height 32
expect render_no_mesh 2 "$pgt" render -o r.png
one_line render_no_mesh_one_line "no input mesh"
expect render_no_output 2 "$pgt" render "$ico"
one_line render_no_output_one_line "no output"
expect render_missing_file 2 "$pgt" render "$ico" nothere.off -o r.png
one_line render_missing_file_named "nothere.off"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1\n3 0 1 2\n' >rtrunc.off
expect render_malformed 2 "$pgt" render rtrunc.off -o r.png
one_line render_malformed_names_file_and_line "rtrunc.off:5"
expect render_not_png 2 "$pgt" render "$ico" -o r.jpg
one_line render_not_png_names_flag "\-o r.jpg"
expect render_bad_width 2 "$pgt" render "$ico" -o r.png --width 0
one_line render_bad_width_names_flag "\-\-width"
expect render_bad_height 2 "$pgt" render "$ico" -o r.png --height big
one_line render_bad_height_names_flag "\-\-height"
expect render_bad_spp 2 "$pgt" render "$ico" -o r.png --spp 17
one_line render_bad_spp_names_flag "\-\-spp"
expect render_bad_threads 2 "$pgt" render "$ico" -o r.png --threads 0
expect render_camera_count 2 "$pgt" render "$ico" -o r.png --camera 1,2,3
one_line render_camera_count_names_flag "\-\-camera: expected 10 numbers"
expect render_camera_eye_at 2 "$pgt" render "$ico" -o r.png --camera 1,1,1,1,1,1,0,1,0,40
one_line render_camera_eye_at_names_flag "\-\-camera .*look-at"
expect render_camera_up_parallel 2 "$pgt" render "$ico" -o r.png --camera 0,5,0,0,0,0,0,1,0,40
one_line render_camera_up_parallel_names_flag "\-\-camera .*parallel"
expect render_camera_fov 2 "$pgt" render "$ico" -o r.png --camera 0,5,5,0,0,0,0,1,0,180
one_line render_camera_fov_names_flag "\-\-camera .*field of view"
# Embree (assertions on in Debian's build) aborted on ray origins beyond ~1.8e18: refused first
expect render_camera_far 2 "$pgt" render "$ico" -o r.png --camera 0,0,2e18,0,0,0,0,1,0,30
one_line render_camera_far_names_flag "\-\-camera .*eye's coordinate 2e+18 is beyond"
awk '/^v /{printf "v %.9g %.9g %.9g\n", $2 * 1e16, $3 * 1e16, $4 * 1e16; next} {print}' "$work/data/cube_sphere_8.obj" >huge.obj
expect render_mesh_far 2 "$pgt" render huge.obj -o r.png
one_line render_mesh_far_names_file "^pgt render: huge.obj:$(grep -n -m1 '^v ' huge.obj | cut -d: -f1): vertex 0 (0-based): coordinate .* is beyond"
awk 'NR == 5 { $2 = "-3e15" } { print }' "$work/data/noisy_torus_48x24.off" >far_torus_r.off
expect render_mesh_far_y 2 "$pgt" render far_torus_r.off -o r.png
one_line render_mesh_far_y_line "^pgt render: far_torus_r.off:5: vertex 2 (0-based): coordinate -3e+15 is beyond"
# atlas and ivy (a mesh given) name the line too, at their limit (1e18: squared distances)
printf 'v 0 0 0\nv 1 0 0\nv 0 1 3e18\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n' >far_at.obj
expect atlas_far_vertex 2 "$pgt" atlas far_at.obj -o fa.exr
one_line atlas_far_vertex_line "^pgt atlas: far_at.obj:3: vertex 2 (0-based): coordinate 3e+18 is beyond +-1e+18"
expect bench_atlas_far_vertex 2 "$pgt" bench atlas --quick --meshes ./far_at.obj --out res/fat.csv --threads 1 --repeat 1 --res 64
grep -q "^pgt bench atlas: skipping ./far_at.obj:3: vertex 2 (0-based): coordinate 3e+18 is beyond" err.txt && ok bench_atlas_far_vertex_line \
  || bad bench_atlas_far_vertex_line "$(cat err.txt)"
expect ivy_far_vertex 2 "$pgt" ivy far_at.obj --seeds 1 -o fa.ply
one_line ivy_far_vertex_line "^pgt ivy: far_at.obj:3: vertex 2 (0-based): coordinate 3e+18 is beyond +-1e+18"
# the shading does not depend on the mesh's scale (the normal's length was squared in float:
# edges of 1e10 or 1e-13 lost their lambert term)
for s in 1 1e10 1e-13; do
  printf 'v 0 0 0\nv %s 0 0\nv 0 %s 0\nf 1 2 3\n' $s $s >scale_$s.obj
  expect "render_scale_$s" 0 "$pgt" render scale_$s.obj -o scale_$s.png --width 32 --height 32 --view 0,0 --no-shadows
done
cmp -s scale_1.png scale_1e10.png && cmp -s scale_1.png scale_1e-13.png && ok render_scale_invariant \
  || bad render_scale_invariant "pictures differ"
expect render_camera_and_view 2 "$pgt" render "$ico" -o r.png --camera 0,5,5,0,0,0,0,1,0,40 --view 10,10
one_line render_camera_and_view_one_line "\-\-camera"
expect render_bad_view 2 "$pgt" render "$ico" -o r.png --view 0,90
one_line render_bad_view_names_flag "\-\-view"
expect render_bad_up 2 "$pgt" render "$ico" -o r.png --up w
one_line render_bad_up_names_flag "\-\-up"
expect render_bad_background 2 "$pgt" render "$ico" -o r.png --background 2,0,0
one_line render_bad_background_names_flag "\-\-background"
expect render_bad_colour 2 "$pgt" render "$ico@0.5,1.5,0" -o r.png
one_line render_bad_colour_one_line "colour"
# a file name may hold '@': split at the last one only when three numbers follow
cp "$ico" 'at@1.off'
expect render_at_in_name 0 "$pgt" render 'at@1.off' -o at1.png --width 32 --height 32 --spp 1
expect render_at_in_name_coloured 0 "$pgt" render 'at@1.off@0.2,0.3,0.9' -o at2.png --width 32 --height 32 --spp 1
cmp -s at1.png at2.png && bad render_colour_applied "same picture with another colour" || ok render_colour_applied
# never overwrites an input, also through a link named like a picture; a failed run keeps the old output
cp "$ico" rin.off && ln -sf rin.off rlink.png
sum0=$(md5sum <rin.off)
expect render_output_is_input 2 "$pgt" render rin.off -o rlink.png
one_line render_output_is_input_one_line "never overwrites an input"
expect render_output_is_input_off 2 "$pgt" render rin.off -o rin.off
[ "$(md5sum <rin.off)" = "$sum0" ] && ok render_input_unchanged || bad render_input_unchanged "input modified"
echo "keep me" >keep.png
expect render_failed_keeps_output 2 "$pgt" render nothere.off -o keep.png
grep -q "keep me" keep.png && ok render_existing_output_kept || bad render_existing_output_kept "overwritten"
# pgt woven, pgt bench woven (the model is test_woven's)
expect woven_help 0 "$pgt" woven --help
for flag in --res --params --frames --threads -o --seed 5k 22k 50k 89k 179k; do
  grep -q -- "$flag" out.txt && ok "woven_help_documents_$flag" || bad "woven_help_documents_$flag" "missing"
done
# progress lines: the frames counted
PGT_PROGRESS_SECONDS=0.001 expect woven_progress 0 "$pgt" woven --res 5k --frames 400 --threads 1
progress_lines woven_progress_lines woven "^pgt woven: frames: [0-9]+ of 400 frames \([0-9]+ %\), [0-9]+ s$"
expect woven_no_model 2 "$pgt" woven
one_line woven_no_model_one_line "\-\-res NAME or \-\-params"
expect woven_res_and_params 2 "$pgt" woven --res 5k --params 10,4,2,8,9
one_line woven_res_and_params_one_line "only one"
expect woven_bad_res 2 "$pgt" woven --res 7k
one_line woven_bad_res_one_line "\-\-res: unknown resolution '7k'"
expect woven_params_k3 2 "$pgt" woven --params 10,3,5,8,25
one_line woven_params_k3_one_line "\-\-params 10,3,5,8,25: K = 3"
# arrays beyond the memory available (PGT_MEMORY_AVAILABLE in place of the machine's: 10^10
# bytes) are refused before any allocation, 96 GiB within the 32-bit limits and 1.3 GiB alike
PGT_MEMORY_AVAILABLE=10000000000 expect woven_params_memory 2 "$pgt" woven --params 1000,4,33000,256,256 -o wm.ply
one_line woven_params_memory_one_line "^pgt woven: --params 1000,4,33000,256,256: the model's arrays take 96.4 GiB, more than the 9.3 GiB of memory available now$"
PGT_MEMORY_AVAILABLE=1000000000 expect woven_params_memory_small 2 "$pgt" woven --params 1000,4,450,256,256 -o wm.ply
one_line woven_params_memory_small_one_line "take 1.3 GiB, more than the 954 MiB of memory available now"
[ ! -e wm.ply ] && ok woven_params_memory_writes_nothing || bad woven_params_memory_writes_nothing "wm.ply written"
expect woven_params_zero 2 "$pgt" woven --params 10,4,0,8,25
one_line woven_params_zero_one_line "\-\-params 10,4,0,8,25: C = 0"
expect woven_params_negative 2 "$pgt" woven --params 10,4,5,8,-1
one_line woven_params_negative_one_line "\-\-params: expected a whole number"
expect woven_params_count 2 "$pgt" woven --params 10,4,5
one_line woven_params_count_one_line "expected 5 values P,K,C,U,V, got 3"
expect woven_params_overflow 2 "$pgt" woven --params 10,4,1048576,4096,2
one_line woven_params_overflow_one_line "C\*U\*V (vertices) = 8589934592 exceeds 2^32 - 1"
expect woven_bad_frames 2 "$pgt" woven --res 5k --frames 0
one_line woven_bad_frames_one_line "\-\-frames"
expect woven_not_ply 2 "$pgt" woven --res 5k -o w.obj
one_line woven_not_ply_one_line "PLY"
expect woven_5k 0 "$pgt" woven --res 5k --frames 3 -o w5k.ply
grep -q "5000 vertices, 8400 triangles" out.txt && grep -q "median .* ms per frame, min" out.txt \
  && ok woven_prints_counts_and_times || bad woven_prints_counts_and_times "$(cat out.txt)"
# the PLY: header counts, normals, and exactly the bytes they promise (x y z nx ny nz floats;
# uchar 3 + 3 uint per face)
ply_counts() {
  /usr/bin/python3 -c '
import sys
b = open(sys.argv[1], "rb").read()
end = b.index(b"end_header\n") + len(b"end_header\n")
h = b[:end].decode().split("\n")
v = int([l for l in h if l.startswith("element vertex ")][0].split()[2])
f = int([l for l in h if l.startswith("element face ")][0].split()[2])
assert "property float nx" in h and "format binary_little_endian 1.0" in h, h
assert len(b) - end == 24 * v + 13 * f, (len(b) - end, v, f)
print(v, f)' "$1"
}
[ "$(ply_counts w5k.ply)" = "5000 8400" ] && ok woven_ply_counts || bad woven_ply_counts "$(ply_counts w5k.ply 2>&1 | tail -1)"
expect woven_params_odd 0 "$pgt" woven --params 7,5,3,5,7 --frames 2 -o wodd.ply --seed 9
[ "$(ply_counts wodd.ply)" = "105 144" ] && ok woven_params_ply_counts || bad woven_params_ply_counts "$(ply_counts wodd.ply 2>&1 | tail -1)"
expect woven_one_thread 0 "$pgt" woven --res 179k --frames 2 --threads 1 -o w1.ply
expect woven_two_threads 0 "$pgt" woven --res 179k --frames 2 --threads 2 -o w2.ply
cmp -s w1.ply w2.ply && ok woven_same_bytes_any_threads || bad woven_same_bytes_any_threads "outputs differ"
[ "$(ply_counts w1.ply)" = "179000 318978" ] && ok woven_179k_counts || bad woven_179k_counts "$(ply_counts w1.ply 2>&1 | tail -1)"
expect bench_woven_help 0 "$pgt" bench woven --help
for flag in --out --frames --repeat --threads --res --seed --quick; do
  grep -q -- "$flag" out.txt && ok "bench_woven_help_documents_$flag" || bad "bench_woven_help_documents_$flag" "missing"
done
# --quick without --out would overwrite the committed results/woven.csv with a smoke run
expect bench_woven_quick_no_out 2 "$pgt" bench woven --quick
one_line bench_woven_quick_no_out_one_line "\-\-quick without \-\-out would replace results/woven.csv"
[ ! -e results/woven.csv ] && ok bench_woven_quick_no_out_writes_nothing || bad bench_woven_quick_no_out_writes_nothing "written"
expect bench_woven_bad_res 2 "$pgt" bench woven --res 7k
one_line bench_woven_bad_res_one_line "\-\-res: unknown resolution '7k'"
# an empty list is an error, not an empty table over the old one
for empty in "" ","; do
  expect "bench_woven_empty_res_'$empty'" 2 "$pgt" bench woven --res "$empty" --out res/woven_empty.csv
  one_line "bench_woven_empty_res_'$empty'_one_line" "\-\-res: empty list"
done
[ ! -e res/woven_empty.csv ] && ok bench_woven_empty_res_writes_nothing || bad bench_woven_empty_res_writes_nothing "written"
# an --out that cannot be written is refused before the benchmark runs (it was after it)
expect bench_woven_out_device 2 timeout 20 "$pgt" bench woven --out /dev/null
one_line bench_woven_out_device_one_line "cannot write /dev/null: it is a device, fifo or socket"
expect bench_woven 0 "$pgt" bench woven --res 5k,22k --frames 2 --threads 2 --out res/woven.csv
grep -q "^# machine: " res/woven.csv && grep -q "^# commit: " res/woven.csv && grep -q "^# date: " res/woven.csv \
  && ok bench_woven_header || bad bench_woven_header "$(head -5 res/woven.csv)"
/usr/bin/python3 -c '
import csv
rows = list(csv.DictReader(l for l in open("res/woven.csv") if not l.startswith("#")))
assert [(r["res"], r["threads"]) for r in rows] == [("5k", "1"), ("5k", "2"), ("22k", "1"), ("22k", "2")], rows
assert rows[0]["vertices"] == "5000" and rows[2]["triangles"] == "36960", rows
assert rows[3]["paper_baseline_ms"] == "10" and rows[3]["paper_luna_ms"] == "22", rows
for r in rows:
    assert None not in r and all(r.values()), r
    assert abs(float(r["luna_ratio"]) * float(r["median_ms"]) - float(r["paper_luna_ms"])) < 0.01 * float(r["paper_luna_ms"]), r' \
  && ok bench_woven_rows || bad bench_woven_rows "$(cat res/woven.csv)"
fields_match bench_woven_fields res/woven.csv

# pgt facade, pgt bench facade (the algorithms are test_facade, the Embree check test_facade_embree)
# a frame whose EXR exceeds the image limit is refused before the render (it rendered 20 s and
# 12.6 GB first); the largest that fits (16384 x 1638 x 10 channels <= 2^28) is accepted by it
expect facade_frame_too_large 2 timeout 20 "$pgt" facade --city 2 -o big.exr --width 16384 --height 2000
one_line facade_frame_too_large_one_line "^pgt facade: --width 16384 --height 2000: .*image limit"
[ ! -e big.exr ] && ok facade_frame_too_large_no_output || bad facade_frame_too_large_no_output "big.exr written"
# PGT_MEMORY_AVAILABLE that is not a whole number of bytes is refused (it was ignored silently)
PGT_MEMORY_AVAILABLE=abc expect memory_env_malformed 2 "$pgt" facade --city 2 -o me.exr --width 16 --height 16
one_line memory_env_malformed_one_line "PGT_MEMORY_AVAILABLE is 'abc': give a whole number of bytes"
PGT_MEMORY_AVAILABLE=1000000000 expect memory_env_given 0 "$pgt" facade --city 2 -o me.exr --width 16 --height 16
expect facade_help 0 "$pgt" facade --help
for flag in --city --scene --camera --width --height -o --png --threads --explicit --embree-check --grammar --seed --light --save-scene --single-rays --max-triangles PGT_MEMORY_AVAILABLE; do
  grep -q -- "$flag" out.txt && ok "facade_help_documents_$flag" || bad "facade_help_documents_$flag" "missing"
done
grep -q "facade" <("$pgt" --help) && ok help_lists_facade || bad help_lists_facade "no facade in pgt --help"
# the memo of developed rules keys arguments bit for bit: A(0) and A(-0) lay out differently (1 / a),
# and keying them as equal made the frame depend on which was met first, so on the thread count,
# and disagree with the explicit geometry
printf 'param protrusion = 0.3\nparam recess = 0.3\nF --> split(x) { '"'"'0.5 : A(0) | '"'"'0.5 : A(-0) }\nA(a) --> split(y) { (1 / a > 0) * 6 + 1 : Wall() | ~1 : Ledge(0.2) }\n' >negzero.grammar
printf 'grammar g negzero.grammar\nbuilding g 0 12 7 E6D2B4 : 0 0 0 12 22 12 22 0\n' >negzero.scene
nz=(facade --scene negzero.scene --camera 11,6,40,11,6,12,0,1,0,40 --width 128 --height 80 --embree-check)
expect facade_signed_zero_args_1 0 "$pgt" "${nz[@]}" -o nz1.exr --threads 1
expect facade_signed_zero_args_2 0 "$pgt" "${nz[@]}" -o nz2.exr --threads 2
cmp -s nz1.exr nz2.exr && ok facade_signed_zero_args_threads || bad facade_signed_zero_args_threads "frames differ"
# a chain of 40 rule calls in tail position takes one frame in the renderer and in the explicit
# twin alike (the twin once took a frame per call, past PGT_FACADE_MAX_DEPTH, and refused it)
{ printf 'param protrusion = 0.3\nparam recess = 0.3\nF --> R1\n'
  for k in $(seq 1 39); do printf 'R%d --> R%d\n' "$k" $((k + 1)); done
  printf 'R40 --> Wall()\n'; } >chain.grammar
printf 'grammar g chain.grammar\nbuilding g 0 12 7 E6D2B4 : 0 0 0 12 22 12 22 0\n' >chain.scene
expect facade_chain_renders 0 "$pgt" facade --scene chain.scene --width 32 --height 24 -o ch.exr
expect facade_chain_check 0 "$pgt" facade --scene chain.scene --width 32 --height 24 -o ch.exr --embree-check
grep -q "agreement 100.0000 %" out.txt && ok facade_chain_check_agrees || bad facade_chain_check_agrees "$(cat out.txt)"
# an error of the explicit twin names the flag that asked for it: 40 calls each followed by a
# Wall take 40 frames, more than PGT_FACADE_MAX_DEPTH; the camera looks away, so no ray develops
# the grammar and only the explicit expansion (every facade, whole) meets the limit
{ printf 'param protrusion = 0.3\nparam recess = 0.3\nF --> R1\n'
  for k in $(seq 1 39); do printf 'R%d --> R%d Wall()\n' "$k" $((k + 1)); done
  printf 'R40 --> Wall()\n'; } >deep.grammar
printf 'grammar g deep.grammar\nbuilding g 0 12 7 E6D2B4 : 0 0 0 12 22 12 22 0\n' >deep.scene
away=(facade --scene deep.scene --camera 11,6,40,11,6,100,0,1,0,40 --width 32 --height 24 -o dp.exr)
expect facade_deep_away_renders 0 "$pgt" "${away[@]}"
expect facade_deep_away_check 2 "$pgt" "${away[@]}" --embree-check
one_line facade_deep_check_names_flag "^pgt facade: --embree-check: deep.scene: .*deep.grammar:[0-9]*:[0-9]*: .*PGT_FACADE_MAX_DEPTH"
# an eye on a roof or wall plane: a hit at t = 0 is no hit (Embree's rule too); the ray develops on
for cam in 11,12,6,11,12,-20 11,12,6,40,12,-20 11,6,12,11,6,40 11,6,12,30,6,-20; do
  printf 'param protrusion = 0.3\nparam recess = 0.3\nF --> split(y) { ~1 : Wall() | 2 : Ledge(0.2) }\n' >onplane.grammar
  printf 'grammar g onplane.grammar\nbuilding g 0 12 7 E6D2B4 : 0 0 0 12 22 12 22 0\n' >onplane.scene
  expect "facade_eye_on_plane_$cam" 0 "$pgt" facade --scene onplane.scene --camera "$cam,0,1,0,60" \
    --width 64 --height 48 -o op.exr --embree-check
done
expect facade_no_output 2 "$pgt" facade --city 4
one_line facade_no_output_one_line "no output: give -o FRAME.exr"
expect facade_city_zero 2 "$pgt" facade --city 0 -o f.exr
one_line facade_city_zero_one_line "\-\-city: expected a whole number"
expect facade_no_input 2 "$pgt" facade -o f.exr
one_line facade_no_input_one_line "exactly one of \-\-city N, \-\-scene FILE and \-\-mesh MESH.obj"
expect facade_not_exr 2 "$pgt" facade --city 4 -o f.png
one_line facade_not_exr_one_line "\-o f.png"
expect facade_camera_count 2 "$pgt" facade --city 4 -o f.exr --camera 1,2,3
one_line facade_camera_count_one_line "\-\-camera: expected 10 finite numbers"
expect facade_camera_eye_at 2 "$pgt" facade --city 4 -o f.exr --camera 1,1,1,1,1,1,0,1,0,40
one_line facade_camera_eye_at_one_line "\-\-camera 1,1,1,1,1,1,0,1,0,40: "
expect facade_camera_fov 2 "$pgt" facade --city 4 -o f.exr --camera 0,5,5,0,0,0,0,1,0,180
one_line facade_camera_fov_one_line "\-\-camera 0,5,5,0,0,0,0,1,0,180: "
# an eye at 1e19 aborted Embree in the --embree-check twin (ray origins within ~1.8e18); 1e30 was
# "eye and at coincide" (a squared length overflowed)
for far in 1e19 1e30; do
  expect "facade_camera_far_$far" 2 "$pgt" facade --city 4 -o f.exr --camera "$far,5,5,0,0,0,0,1,0,40" --width 16 --height 16 --embree-check
  one_line "facade_camera_far_${far}_one_line" "coordinates must be within +-1e+09"
done
expect facade_camera_up 2 "$pgt" facade --city 4 -o f.exr --camera 0,5,0,0,0,0,0,1,0,40
one_line facade_camera_up_one_line "\-\-camera 0,5,0,0,0,0,0,1,0,40: "
expect facade_bad_width 2 "$pgt" facade --city 4 -o f.exr --width 0
one_line facade_bad_width_one_line "\-\-width"
# a run that fails leaves no output at all (pgt_cli_stage), and an older output as it was; a
# grammar whose split size is NaN fails while rendering, and its explicit expansion names the
# grammar's line and column of the function that made the NaN (not the expression's start)
printf 'param floorHeight = 3.2\nparam doorWidth = 1.6\nparam windowWidth = 2.2\nparam protrusion = 0.3\nparam recess = 0.3\nF --> split(x) { 1 + sqrt(-1) : Wall() }\n' >nanf.grammar
rm -f nf.exr nf.png nf.ply nf.scene; echo older >nf_old.scene
expect facade_fail_render 2 "$pgt" facade --city 1 --grammar nanf.grammar --width 16 --height 16 -o nf.exr --png nf.png --save-scene nf.scene
one_line facade_fail_render_names_token "while rendering on building 0, footprint edge 0: an expression gave NaN or infinity (building 0 facade 0: nanf.grammar:6:22: the expression evaluates to NaN (sqrt gives NaN here))"
expect facade_fail_render_old 2 "$pgt" facade --city 1 --grammar nanf.grammar --width 16 --height 16 -o nf.exr --save-scene nf_old.scene
[ "$(cat nf_old.scene)" = older ] && ok facade_fail_keeps_older || bad facade_fail_keeps_older "$(head -c 80 nf_old.scene)"
# the camera looks away, so the frame renders and the explicit expansion meets the NaN
expect facade_fail_explicit 2 "$pgt" facade --city 1 --grammar nanf.grammar --width 16 --height 16 -o nf.exr --explicit nf.ply --camera 0,0,-1000,0,0,-2000,0,1,0,45
one_line facade_fail_explicit_names_token "^pgt facade: --explicit: --city: building 0 facade 0: nanf.grammar:6:22: "
mkdir -p nfdir.png
expect facade_fail_png_folder 2 "$pgt" facade --city 1 --width 16 --height 16 -o nf.exr --png nfdir.png
one_line facade_fail_png_folder_one_line "cannot write nfdir.png: it is a folder, not a regular file"
ls -d nf.exr nf.png nf.ply nf.scene .pgt-stage.* 2>/dev/null | grep -q . && bad facade_fail_no_output "$(ls -d nf.* .pgt-stage.* 2>/dev/null)" || ok facade_fail_no_output
expect facade_city 0 "$pgt" facade --city 4 -o f.exr --png f.png --width 96 --height 64 --threads 2 \
  --explicit f.ply --save-scene f.scene
grep -q "^scene: 4 buildings, 16 facades" out.txt && grep -q "nodes developed per ray" out.txt \
  && grep -q "Mrays/s" out.txt && grep -q "^memory: procedural [0-9]* bytes" out.txt \
  && grep -q "^explicit: [0-9]* triangles" out.txt && ok facade_city_prints || bad facade_city_prints "$(cat out.txt)"
# the EXR's channel list (the header is uncompressed: attribute 'channels', type 'chlist')
/usr/bin/python3 -c '
import sys
b = open("f.exr", "rb").read()
assert b[:4] == b"\x76\x2f\x31\x01", b[:4]
i = b.index(b"channels\0chlist\0") + len(b"channels\0chlist\0") + 4
names = []
while b[i] != 0:
    j = b.index(b"\0", i); names.append(b[i:j].decode()); i = j + 1 + 16
want = {"R", "G", "B", "depth", "terminal", "N.x", "N.y", "N.z", "facade", "developed"}
sys.exit(0 if want <= set(names) else "channels: %s" % names)' && ok facade_exr_channels || bad facade_exr_channels "$(head -c 300 f.exr | tr -c "[:print:]" .)"
/usr/bin/python3 -c 'import struct,sys; d=open("f.png","rb").read(24)
sys.exit(0 if d[:8]==b"\x89PNG\r\n\x1a\n" and struct.unpack(">II",d[16:24])==(96,64) else 1)' \
  && ok facade_png_size || bad facade_png_size "$(head -c 24 f.png | od -c | head -2)"
/usr/bin/python3 -c '
import sys
b = open("f.ply", "rb").read()
end = b.index(b"end_header\n") + len(b"end_header\n")
h = b[:end].decode().split("\n")
v = int([l for l in h if l.startswith("element vertex ")][0].split()[2])
f = int([l for l in h if l.startswith("element face ")][0].split()[2])
for p in ("facade", "node", "kind", "surface"): assert "property uint " + p in h, h
assert "format binary_little_endian 1.0" in h and f > 0
assert len(b) - end == 12 * v + 29 * f, (len(b) - end, v, f)' && ok facade_ply_layout || bad facade_ply_layout "$(head -c 400 f.ply)"
ntri=$(sed -n 's/^explicit: \([0-9]*\) triangles.*/\1/p' out.txt)
cam=$(sed -n 's/^camera: --camera //p' out.txt)
expect facade_scene_file 0 "$pgt" facade --scene f.scene -o f2.exr --width 96 --height 64 --threads 1 --camera "$cam"
cmp -s f.exr f2.exr && ok facade_scene_file_same_frame || bad facade_scene_file_same_frame "f.exr and f2.exr differ"
{ printf '\357\273\277'; cat f.scene; } >f_bom.scene
expect facade_scene_file_bom 0 "$pgt" facade --scene f_bom.scene -o f4.exr --width 96 --height 64 --threads 1 --camera "$cam"
cmp -s f.exr f4.exr && ok facade_scene_file_bom_same_frame || bad facade_scene_file_bom_same_frame "f.exr and f4.exr differ"
grep -q "^scene: 4 buildings, 16 facades" out.txt && ok facade_scene_file_counts || bad facade_scene_file_counts "$(cat out.txt)"
expect facade_embree_check 0 "$pgt" facade --city 4 -o f3.exr --width 96 --height 64 --embree-check
grep -q "^check: agreement .* -> PASS" out.txt && grep -q "^embree: BVH build" out.txt && grep -q "Embree / ours" out.txt \
  && ok facade_embree_check_prints || bad facade_embree_check_prints "$(cat out.txt)"
# packets (the default) and every ray alone give the same frame, shaded with shadows
expect facade_single_rays 0 "$pgt" facade --scene f.scene -o f4.exr --width 96 --height 64 --camera "$cam" \
  --shadows --single-rays
expect facade_packets 0 "$pgt" facade --scene f.scene -o f5.exr --width 96 --height 64 --camera "$cam" --shadows
cmp -s f4.exr f5.exr && ok facade_single_rays_same_frame || bad facade_single_rays_same_frame "f4.exr and f5.exr differ"
expect facade_overwrite_scene 2 "$pgt" facade --scene f.scene -o f.exr --save-scene f.scene
one_line facade_overwrite_scene_one_line "never overwrites an input"
# a geometry image (Mesh) that leaves the facade volume fails the render as a rectangle does,
# naming the grammar's place (the oculus's glass lies 0.15 m deep; recess 0.05): the coverage
# polygon and the ray's slab would cut it (paper 003 sec. 8); with recess 0.15 it renders
printf 'param protrusion = 0.3\nparam recess = 0.05\nF --> split(x) { ~3 : M }*\nM --> Mesh(0)\n' >gvol.grammar
printf 'grammar g gvol.grammar\nbuilding g 0 10 1 FFFFFF : 0 0 0 10 10 10 10 0\n' >gvol.scene
expect facade_gimage_volume 2 "$pgt" facade --scene gvol.scene -o gv.exr --width 64 --height 64 --camera -6,5,-2,0,5,3,0,1,0,60
one_line facade_gimage_volume_one_line "a terminal reaches outside the facade volume .*gvol.grammar:4:7: building 0 facade 0: Mesh triangle [0-9]* reaches z -0.15 outside"
sed -i 's/recess = 0.05/recess = 0.15/' gvol.grammar
expect facade_gimage_volume_fits 0 "$pgt" facade --scene gvol.scene -o gv.exr --width 64 --height 64 --camera -6,5,-2,0,5,3,0,1,0,60 --embree-check
# a scene file cannot name a grammar whose path has a space or '#' (its tokens end there): the
# save refuses it rather than write a file its reader refuses, and writes nothing
mkdir -p "sp dir" && cp "$src/grammars/facade.grammar" "sp dir/"
expect facade_save_space 2 "$pgt" facade --city 2 --grammar "sp dir/facade.grammar" -o sps.exr --width 16 --height 16 --save-scene sps.scene
one_line facade_save_space_one_line "^pgt facade: --save-scene sps.scene: grammar facade's path 'sp dir/facade.grammar' has a space"
[ -z "$(ls -d sps.* 2>/dev/null)" ] && ok facade_save_space_writes_nothing || bad facade_save_space_writes_nothing "$(ls -d sps.*)"
# a balcony's underside lying on a 40-cornered roof: coincident faces, ties; the check finds the
# roof's every triangle (38, one key) and its outline (it kept 4 triangles a key: "neither", FAIL)
printf 'param protrusion = 0.6\nparam recess = 0.3\nF --> split(y) { 3 : GF | ~3 : W }\nGF --> Wall() Balcony(0.6, 0.2, 1.0)\nW --> Wall()\n' >balc.grammar
/usr/bin/python3 -c '
import math
c = " ".join("%.6f %.6f" % (15 * math.cos(-2 * math.pi * k / 40), 15 * math.sin(-2 * math.pi * k / 40)) for k in range(40))
print("grammar a '"$src"'/grammars/facade.grammar\ngrammar b balc.grammar\nbuilding a 0 10 1 DDDDDD : " + c + "\nbuilding b 10 6 2 AAAAFF : -5 -5 -5 5 5 5 5 -5")' >roof.scene
expect facade_roof_ties 0 "$pgt" facade --scene roof.scene -o rf.exr --width 64 --height 64 --threads 1 --camera 0,2,0,5.3,10,0,0,1,0,30 --embree-check
grep -q "([1-9][0-9]* ties: .*, 0 neither).* -> PASS$" out.txt && ok facade_roof_ties_counted || bad facade_roof_ties_counted "$(grep check: out.txt)"
# progress lines of pgt facade: every stage, Embree's BVH counted in triangles
PGT_PROGRESS_SECONDS=0.001 expect facade_progress 0 "$pgt" facade --city 4 -o fp.exr --width 64 --height 48 --embree-check
progress_lines facade_progress_lines facade "^pgt facade: Embree's BVH: [0-9]+ of [0-9]+ triangles \([0-9]+ %\), [0-9]+ s$"
# a roof's diagonal: at 3840 x 2160 one ray of this camera passes through the edge between the
# roof's two triangles, and Embree (not watertight without its robust flag) misses both and hits
# a window behind; the building is pgt facade --city 1000's building 703 (the check failed on
# that city with 1 "neither" before such cracks were told apart; on another CPU's Embree kernels
# the ray may hit the roof, and the check passes all the same)
printf 'grammar facade %s/grammars/facade.grammar\nbuilding facade 0 12.9581203 2276901059 9D9CA1 floorHeight=3.23953009 doorWidth=1.73225355 windowWidth=2.67413259 protrusion=0.390506566 recess=0.404749691 : 934.687317 632.032837 934.687317 649.166138 953.846375 649.166138 953.846375 632.032837\n' "$src" >crack.scene
expect facade_roof_crack 0 "$pgt" facade --scene crack.scene -o crack.exr --width 3840 --height 2160 --camera 1215.5186,1054.3705,1754.4445,477.99637,21.53326,477.0185,0,1,0,45 --embree-check
grep -Eq "^check: .* 0 neither\), [0-9]+ of those near an edge inside a rectangle .* -> PASS$" out.txt && ok facade_roof_crack_told || bad facade_roof_crack_told "$(grep check: out.txt)"
# street level, the eye inside a building (pgt facade --city 248 --seed 31's buildings 154 and
# 155): with Embree's coherent flag its packets and streams missed 59 and 43 of the rays that
# meet a window frame's back 0.52 m away (rtcIntersect1 finds them), and rays nearly parallel to
# a wall (89.85 degrees) hit it 5 mm apart in depth and along the wall; the check traces its rays
# without the flag and counts such hits in float epsilons of the coordinates along the normal
printf 'grammar facade %s/grammars/facade.grammar\n%s\n%s\n' "$src" \
  'building facade 0 23.2051849 3989550082 A7C6CB floorHeight=2.90064812 doorWidth=1.36515915 windowWidth=2.30441499 protrusion=0.330867112 recess=0.323477328 : 307.765015 277.490112 307.765015 291.989441 324.411316 291.989441 324.411316 277.490112' \
  'building facade 0 13.9974508 479634527 E9BFDE floorHeight=3.49936271 doorWidth=1.35259497 windowWidth=2.2370491 protrusion=0.231471449 recess=0.342519283 : 339.484375 272.549927 339.484375 288.441101 352.868683 288.441101 352.868683 272.549927' >inside.scene
expect facade_inside_building 0 "$pgt" facade --scene inside.scene -o inside.exr --width 1920 --height 1080 --camera 340,2,286,118,13,98,0,1,0,78 --embree-check
grep -Eq "^check: .*, 0 neither\).* -> PASS$" out.txt && ok facade_inside_building_agrees || bad facade_inside_building_agrees "$(grep check: out.txt)"
# a door 5.5 m away at 89.4 degrees (pgt facade --city 266 --seed 43's building 163): depths
# 2.7e-4 t apart, 0.4 float epsilons of the coordinates along the door's normal: agreement
printf 'grammar facade %s/grammars/facade.grammar\n%s\n' "$src" \
  'building facade 0 26.2050762 2376614734 9AEABB floorHeight=3.27563453 doorWidth=1.3465246 windowWidth=2.74723005 protrusion=0.401866555 recess=0.270849794 : 309.607727 273.899048 309.607727 293.519989 323.265411 293.519989 323.265411 273.899048' >door.scene
expect facade_grazing_door 0 "$pgt" facade --scene door.scene -o door.exr --width 1920 --height 1080 --camera 315,4,275,96,13,255,0,1,0,38 --embree-check
grep -Eq "^check: .*, 0 neither\).*\(relative 0\.000[1-9][0-9]*\) -> PASS$" out.txt && ok facade_grazing_door_agrees || bad facade_grazing_door_agrees "$(grep check: out.txt)"
# the explicit twin's limit: exactly its triangles give the same twin, one fewer fails naming the
# flag and writes nothing; without a flag the limit is what fits in the memory available
# (PGT_MEMORY_AVAILABLE in place of the machine's), so a grammar that instantiates billions of
# terminals (a repeat of 1e-30 m: about 30 million triangles a facade) fails at once, naming it
expect facade_max_triangles_exact 0 "$pgt" facade --city 4 -o fm.exr --width 96 --height 64 --explicit fm.ply --max-triangles "$ntri"
cmp -s f.ply fm.ply && ok facade_max_triangles_same_twin || bad facade_max_triangles_same_twin "f.ply and fm.ply differ ($ntri triangles)"
rm -f fm.exr fm.ply
expect facade_max_triangles_one_fewer 2 "$pgt" facade --city 4 -o fm.exr --width 96 --height 64 --explicit fm.ply --max-triangles $((ntri - 1))
one_line facade_max_triangles_one_fewer_one_line "^pgt facade: --explicit: --city: explicit facades: more than $((ntri - 1)) triangles (--max-triangles $((ntri - 1)))$"
[ -z "$(ls -d fm.* .pgt-stage.* 2>/dev/null)" ] && ok facade_max_triangles_writes_nothing || bad facade_max_triangles_writes_nothing "$(ls -d fm.* .pgt-stage.*)"
expect facade_max_triangles_needs_twin 2 "$pgt" facade --city 4 -o fm.exr --max-triangles 10
one_line facade_max_triangles_needs_twin_one_line "only with --explicit or --embree-check"
expect facade_max_triangles_zero 2 "$pgt" facade --city 4 -o fm.exr --explicit fm.ply --max-triangles 0
expect facade_max_triangles_over 2 "$pgt" facade --city 4 -o fm.exr --explicit fm.ply --max-triangles 536870913
printf 'param floorHeight = 3.2\nparam doorWidth = 1.6\nparam windowWidth = 2.2\nparam protrusion = 0.3\nparam recess = 0.3\nF --> split(x) { { ~1e-30 : Wall() }* }\n' >tiny.grammar
PGT_MEMORY_AVAILABLE=100000000 expect facade_twin_memory 2 "$pgt" facade --city 1 --grammar tiny.grammar --width 16 --height 16 -o fm.exr --explicit fm.ply --camera 0,0,-1000,0,0,-2000,0,1,0,45
one_line facade_twin_memory_one_line "^pgt facade: --explicit: --city: explicit facades: more than 1442307 triangles (what fits in 75 % of the 95 MiB of memory available; pgt facade --max-triangles sets another limit)$"
PGT_MEMORY_AVAILABLE=100000000 expect facade_twin_memory_embree 2 "$pgt" facade --city 1 --grammar tiny.grammar --width 16 --height 16 -o fm.exr --embree-check --camera 0,0,-1000,0,0,-2000,0,1,0,45
one_line facade_twin_memory_embree_one_line "more than 297619 triangles (what fits in 75 % of the 95 MiB of memory available with Embree's scene of it;"
[ -z "$(ls -d fm.* .pgt-stage.* 2>/dev/null)" ] && ok facade_twin_memory_writes_nothing || bad facade_twin_memory_writes_nothing "$(ls -d fm.* .pgt-stage.*)"
# malformed scene files: each names FILE:LINE, exit 2
g="$src/grammars/facade.grammar"
scene_case() { # NAME PATTERN LINES...: the scene of LINES fails with FILE:PATTERN
  local name=$1 pat=$2; shift 2
  printf '%s\n' "$@" >"$name.scene"
  expect "facade_scene_$name" 2 "$pgt" facade --scene "$name.scene" -o x.exr
  one_line "facade_scene_${name}_names_line" "$name.scene:$pat"
}
B=": 0 0 0 10 10 10 10 0"
scene_case unknown_statement "2: unknown statement 'house'" "grammar g $g" "house g 0 10 1 FFFFFF $B"
scene_case undeclared "1: grammar 'g' is not declared" "building g 0 10 1 FFFFFF $B"
scene_case grammar_args "1: expected 'grammar NAME PATH'" "grammar g"
scene_case grammar_missing "1: grammar nothere.grammar: " "grammar g nothere.grammar"
scene_case grammar_twice "2: grammar 'g' is already declared" "grammar g $g" "grammar g $g"
scene_case short "2: expected 'building" "grammar g $g" "building g 0 10"
scene_case bad_base "2: BASE 'x' is not a finite number" "grammar g $g" "building g x 10 1 FFFFFF $B"
scene_case bad_height "2: HEIGHT '-3'" "grammar g $g" "building g 0 -3 1 FFFFFF $B"
scene_case bad_seed "2: SEED '1.5'" "grammar g $g" "building g 0 10 1.5 FFFFFF $B"
# a NUL byte: line 2 was once "longer than 65536 characters", and text after a NUL on the last
# line (no newline) was dropped without a word
printf 'grammar g %s\nbuil\000ding g 0 10 1 FFFFFF %s\n' "$g" "$B" >nul.scene
expect facade_scene_nul 2 "$pgt" facade --scene nul.scene -o x.exr
one_line facade_scene_nul_names_column "nul.scene:2:5: a NUL byte"
printf 'grammar g %s\nbuilding g 0 10 1 FFFFFF %s\000 10 0' "$g" "$B" >nul_end.scene
expect facade_scene_nul_last_line 2 "$pgt" facade --scene nul_end.scene -o x.exr
one_line facade_scene_nul_last_line_one_line "nul_end.scene:2:$((26 + ${#B})): a NUL byte"
scene_case bad_colour "2: colour 'FFFFF'" "grammar g $g" "building g 0 10 1 FFFFF $B"
# a param that makes rays run out of nodes (1e21 floors) is found while rendering: the message
# names the building (once only the file)
printf 'grammar g %s\nbuilding g 0 10 1 FFFFFF %s\nbuilding g 0 10 1 FFFFFF floorHeight=1e-20 : 20 0 20 10 30 10 30 0\n' "$g" "$B" >floors.scene
expect facade_render_error_building 2 "$pgt" facade --scene floors.scene -o x.exr --width 32 --height 32
one_line facade_render_error_names_building "floors.scene: the grammar failed while rendering on building 1 (line 3), footprint edge [0-3]: a ray developed more than PGT_FACADE_NODE_BUDGET"
scene_case unknown_param "2: grammar 'g' has no param 'nope'" "grammar g $g" "building g 0 10 1 FFFFFF nope=3 $B"
scene_case param_twice "2: param 'recess' given twice" "grammar g $g" "building g 0 10 1 FFFFFF recess=0.1 recess=0.2 $B"
scene_case param_value "2: recess=abc: not a finite number" "grammar g $g" "building g 0 10 1 FFFFFF recess=abc $B"
scene_case no_colon "2: '0' is not PARAM=VALUE (or the ':' before the footprint)" "grammar g $g" "building g 0 10 1 FFFFFF 0 0 0 10 10 10"
scene_case odd_footprint "2: the footprint needs X Z pairs" "grammar g $g" "building g 0 10 1 FFFFFF : 0 0 0 10 10"
scene_case two_corners "2: the footprint needs X Z pairs" "grammar g $g" "building g 0 10 1 FFFFFF : 0 0 0 10"
scene_case bad_corner "3: footprint value 3 'y'" "grammar g $g" "# comment" "building g 0 10 1 FFFFFF : 0 0 y 10 10 10"
scene_case wrong_order "2" "grammar g $g" "building g 0 10 1 FFFFFF : 0 0 10 0 10 10 0 10"
scene_case no_building "" "grammar g $g" "# nothing else"
printf 'param a = 1\nA --> Wall()\n' >novol.grammar
scene_case not_facade_grammar "1: grammar novol.grammar has no param 'protrusion'" "grammar g novol.grammar"
# pgt_datasets city writes a scene file pgt facade reads
expect datasets_city 0 "$gen" city 3 5 -o gen.scene
[ "$(grep -c '^building ' gen.scene)" = 3 ] && grep -q "^grammar facade .*facade.grammar$" gen.scene \
  && ok datasets_city_scene || bad datasets_city_scene "$(head -3 gen.scene)"
expect datasets_city_renders 0 "$pgt" facade --scene gen.scene -o gen.exr --width 32 --height 32
# facades on a generic mesh (paper 003 sec. 10): pgt_datasets tower writes a quad OBJ that pgt
# facade --mesh renders and checks against Embree; malformed meshes name FILE:LINE
expect datasets_tower 0 "$gen" tower -o tower.obj 10 7 20 30 16 5
grep -q "^tower 102 vertices 80 quads tower.obj" out.txt && ok datasets_tower_counts || bad datasets_tower_counts "$(cat out.txt)"
expect facade_mesh 0 "$pgt" facade --mesh tower.obj -o tower.exr --width 64 --height 48 --threads 2 --embree-check
grep -q "^scene: mesh of 80 quads, 102 vertices: 80 facades" out.txt && grep -q "^check: .* -> PASS" out.txt \
  && ok facade_mesh_prints || bad facade_mesh_prints "$(cat out.txt)"
{ printf '\357\273\277'; cat tower.obj; } >tower_bom.obj
expect facade_mesh_bom 0 "$pgt" facade --mesh tower_bom.obj -o tower_bom.exr --width 64 --height 48 --threads 2
expect facade_mesh_nobom 0 "$pgt" facade --mesh tower.obj -o tower_nobom.exr --width 64 --height 48 --threads 2
cmp -s tower_bom.exr tower_nobom.exr && ok facade_mesh_bom_same_frame || bad facade_mesh_bom_same_frame "tower_bom.exr and tower_nobom.exr differ"
# geometry-image terminals (Mesh(0)) on the quads: clipped to each quad's window, Embree agrees
expect facade_mesh_gimage 0 "$pgt" facade --mesh tower.obj --grammar "$src/grammars/facade_gimage.grammar" -o tower_gi.exr --width 64 --height 48 --threads 2 --embree-check
grep -q "^check: .* -> PASS" out.txt && ok facade_mesh_gimage_check || bad facade_mesh_gimage_check "$(cat out.txt)"
# quads 0.6 m wide: facade_rich's ledges and frames, which protrude past a quad's sides, overlap
# their neighbours' and rays meet two coincident faces (ties, counted apart; this failed the
# check with 66 such rays "not near an edge" before ties were told apart)
"$gen" tower -o thin.obj 14 9 42 45 128 2 >/dev/null
expect facade_mesh_ties 0 "$pgt" facade --mesh thin.obj --grammar "$src/grammars/facade_rich.grammar" -o thin.exr --width 160 --height 90 --threads 2 --embree-check
grep -Eq "^check: .*disagreements \([1-9][0-9]* ties: coincident faces at one distance, [0-9]+ near an edge, 0 neither\).* -> PASS" out.txt \
  && ok facade_mesh_ties_counted || bad facade_mesh_ties_counted "$(grep check: out.txt)"
# split boundaries on the quads' borders (3.5 m rows on the default tower's 3.5 m quad rows): a
# child that only touches a quad's window belongs to the next quad, for the rays and for the
# explicit twin alike (81 rays disagreed, "neither", when the twin kept it and 7 when a rounded
# entry point entered it)
"$gen" tower -o border.obj >/dev/null
printf 'param protrusion = 0.5\nparam recess = 0.5\nF --> split(y) { { 3.5 : Row }* }\nRow --> split(y) { 0.5 : Ledge(0.3) | ~1 : Wall() }\n' >border.grammar
expect facade_mesh_window_border 0 "$pgt" facade --mesh border.obj --grammar border.grammar -o border.exr --width 160 --height 180 --threads 2 --embree-check
grep -Eq "^check: .*, [0-9]+ near an edge, 0 neither\).* -> PASS" out.txt \
  && ok facade_mesh_window_border_agrees || bad facade_mesh_window_border_agrees "$(grep check: out.txt)"
# a valid grammar that generates nothing: the Embree check compares misses with misses (it
# refused the empty explicit mesh as bad input)
printf 'param protrusion = 0.2\nparam recess = 0.5\nF --> split(x) { 0 : Wall() }\n' >nothing.grammar
expect facade_mesh_nothing_checked 0 "$pgt" facade --mesh border.obj --grammar nothing.grammar -o nothing.exr --width 32 --height 24 --embree-check
grep -q "^check: agreement 100.0000 % .* -> PASS" out.txt && ok facade_mesh_nothing_agrees || bad facade_mesh_nothing_agrees "$(grep check: out.txt)"
# a terminal that reaches outside the facade volume: the rays showed it cut open (exit 0) while
# the explicit twin refused it; now both refuse, naming the grammar's place
printf 'param protrusion = 0.2\nparam recess = 0.5\nF --> split(y) { { 3 : L }* }\nL --> Ledge(0.5)\n' >outvol.grammar
printf 'grammar out outvol.grammar\nbuilding out 0 19.2 7 E6D2B4 : 0 0 0 12 22 12 22 0\n' >outvol.scene
expect facade_terminal_outside_volume 2 "$pgt" facade --scene outvol.scene --camera 3,4.5,19,12,5.5,12,0,1,0,45 --width 64 --height 48 -o outvol.exr
one_line facade_terminal_outside_volume_one_line "outvol.grammar:4:7: .*outside the facade volume"
[ ! -e outvol.exr ] && ok facade_terminal_outside_volume_writes_nothing || bad facade_terminal_outside_volume_writes_nothing "written"
# malformed quad OBJs: each names FILE:LINE (or the quad), exit 2
mesh_case() { # NAME FILE PATTERN PRINTF-FORMAT: the OBJ printed by FORMAT fails with FILE+PATTERN
  printf "$4" >"$2"
  expect "facade_mesh_$1" 2 "$pgt" facade --mesh "$2" -o x.exr
  one_line "facade_mesh_$1_one_line" "$2$3"
}
mesh_case triangle tri.obj ":4: a face of 3 corners" 'v 0 0 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 1/1/1 1/1/1\n'
# values: a normal of any length is a direction; UVs and positions beyond +-1e6 metres, and
# numbers that overflow float, name the line; a bow-tie quad names the quad
q='v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n'
printf "${q}vn 0 0 1e30\nf 1/1/1 2/2/1 3/3/1 4/4/1\n" >vn_long.obj
expect facade_mesh_long_normal 0 "$pgt" facade --mesh vn_long.obj -o x.exr --width 8 --height 8
mesh_case normal_overflow vn_inf.obj ":9: vn value '1e39' is not a finite float" "${q}vn 0 0 1e39\nf 1/1/1 2/2/1 3/3/1 4/4/1\n"
mesh_case uv_far vt_far.obj ":9: vt value 1e30 beyond +-1e+06 metres" "${q}vt 1e30 0\nvn 0 0 1\nf 1/1/1 2/9/1 3/3/1 4/4/1\n"
mesh_case bowtie bowtie.obj ": quad mesh: quad 0: two opposite sides cross in UV" "${q}vn 0 0 1\nf 1/1/1 2/2/1 4/4/1 3/3/1\n"
mesh_case nul nul.obj ":1:8: a NUL byte" 'v 0 0 0\000\nvt 0 0\n'
expect facade_mesh_save_scene 2 "$pgt" facade --mesh tower.obj -o x.exr --save-scene x.scene
one_line facade_mesh_save_scene_one_line "\-\-save-scene is for \-\-city and \-\-scene"
expect facade_mesh_and_city 2 "$pgt" facade --mesh tower.obj --city 3 -o x.exr
one_line facade_mesh_and_city_one_line "exactly one of"
expect datasets_city_zero 2 "$gen" city 0 5 -o gen0.scene
expect datasets_city_missing_grammar 2 "$gen" city 2 1 -o gm.scene --grammar nothere.grammar
one_line datasets_city_missing_grammar_one_line "nothere.grammar: cannot open"
# an -o that cannot be written is refused before the city or tower is generated (exit 2; the
# write at the end would fail with 1), naming the path and why
expect datasets_city_out_missing_folder 2 "$gen" city 1000 1 -o nofolder/c.scene
one_line datasets_city_out_missing_folder_one_line "^pgt_datasets: city: cannot write nofolder/c.scene: No such file or directory$"
expect datasets_city_out_long_name 2 "$gen" city 2 1 -o "$(printf 'c%.0s' $(seq 250)).scene"
one_line datasets_city_out_long_name_one_line "cannot write c*\.scene: File name too long$"
expect datasets_tower_out_empty 2 "$gen" tower -o ''
one_line datasets_tower_out_empty_one_line "^pgt_datasets: tower: cannot write : No such file or directory$"
mkdir -p tower_dir.obj
expect datasets_tower_out_folder 2 "$gen" tower -o tower_dir.obj
one_line datasets_tower_out_folder_one_line "^pgt_datasets: tower: cannot write tower_dir.obj: it is a folder, not a regular file$"
# outputs never replace inputs or each other: a grammar the scene names, -o as --save-scene,
# bench facade's --out as its --grammar; pgt_datasets tower writes through a temporary file
printf 'grammar g own_fc.grammar\nbuilding g 0 19.2 7 E6D2B4 : 0 0 0 12 22 12 22 0\n' >own_fc.scene
cp "$src/grammars/facade.grammar" own_fc.grammar
expect facade_save_over_grammar 2 "$pgt" facade --scene own_fc.scene --save-scene own_fc.grammar -o ofc.exr --width 32 --height 32
one_line facade_save_over_grammar_one_line "\-\-save-scene own_fc.grammar is the grammar g of own_fc.scene"
expect facade_save_is_frame 2 "$pgt" facade --scene own_fc.scene --save-scene ofc.exr -o ofc.exr --width 32 --height 32
one_line facade_save_is_frame_one_line "\-\-save-scene ofc.exr is also \-o's output"
expect bench_facade_out_is_grammar 2 "$pgt" bench facade --grammar own_fc.grammar --out own_fc.grammar --buildings 1 --res 32x32 --frames 1 --threads 1
cmp -s own_fc.grammar "$src/grammars/facade.grammar" && ok facade_inputs_kept || bad facade_inputs_kept "overwritten"
# a --grammar path with a line end stays inside its '#' comment line; a malformed
# PGT_MEMORY_AVAILABLE is refused before --out's folder is made
cp "$src/grammars/facade.grammar" $'nl\nfc.grammar'
expect bench_facade_grammar_line_end 0 "$pgt" bench facade --grammar $'nl\nfc.grammar' --out res/fnl.csv --buildings 1 --res 32x32 --frames 1 --threads 1
fields_match bench_facade_grammar_line_end_fields res/fnl.csv
grep -q '^# runs: .* with nl?fc.grammar; ' res/fnl.csv && ok bench_facade_grammar_line_end_comment \
  || bad bench_facade_grammar_line_end_comment "$(head -8 res/fnl.csv)"
expect bench_facade_memory_env_no_folder 2 env PGT_MEMORY_AVAILABLE=bogus "$pgt" bench facade --quick --out nfd/x.csv
[ ! -e nfd ] && ok bench_facade_memory_env_no_folder_left || bad bench_facade_memory_env_no_folder_left "nfd left"
"$gen" tower -o keep_tower.obj >/dev/null 2>&1 && cp keep_tower.obj keep_tower.ref
( trap '' XFSZ; ulimit -f 10; "$gen" tower -o keep_tower.obj >/dev/null 2>&1 )
[ $? -ne 0 ] && cmp -s keep_tower.obj keep_tower.ref && ok datasets_tower_failed_write_keeps_file \
  || bad datasets_tower_failed_write_keeps_file "$(wc -c <keep_tower.obj) bytes"
# protrusion and recess within the coordinates' bound (1.2e9 lost hits to rounding in t)
printf 'grammar g own_fc.grammar\nbuilding g 0 19.2 7 E6D2B4 recess=1e10 protrusion=1e10 : 0 0 0 12 22 12 22 0\n' >deep_fc.scene
expect facade_protrusion_huge 2 "$pgt" facade --scene deep_fc.scene -o ofc.exr --width 32 --height 32
one_line facade_protrusion_huge_one_line "protrusion 1e+10 and recess 1e+10 must be in \[0, 1e+06\]"
# a vertex shared by 600 quads (1200 neighbours): refused before the quadratic pair search
/usr/bin/python3 -c '
import math
n = 600
print("v 0 0 0\nvt 0 0\nvn 0 0 1")
for i in range(3 * n):
    a = 2 * math.pi * i / (3 * n); r = 10 + (i % 3)
    print("v %.6f %.6f 0\nvt %.6f %.6f\nvn 0 0 1" % (r * math.cos(a), r * math.sin(a), r * math.cos(a), r * math.sin(a)))
for q in range(n):
    a, b, c = 2 + 3 * q, 3 + 3 * q, 4 + 3 * q
    print("f 1/1/1 %d/%d/%d %d/%d/%d %d/%d/%d" % (a, a, a, b, b, b, c, c, c))' >fan.obj
expect facade_mesh_fan 2 "$pgt" facade --mesh fan.obj -o ofc.exr --width 32 --height 32
one_line facade_mesh_fan_one_line "vertex 0 has 1200 neighbours (at most 1024"
cp "$src/grammars/facade.grammar" own.grammar
expect datasets_city_over_grammar 2 "$gen" city 2 1 -o own.grammar --grammar own.grammar
cmp -s own.grammar "$src/grammars/facade.grammar" && ok datasets_city_grammar_kept || bad datasets_city_grammar_kept "overwritten"
expect datasets_tower_tiny 2 "$gen" tower -o tiny.obj 1e-300 1e-300 1e-300 0 3 1
[ ! -e tiny.obj ] && ok datasets_tower_tiny_writes_nothing || bad datasets_tower_tiny_writes_nothing "$(head -c 200 tiny.obj)"
expect bench_facade_help 0 "$pgt" bench facade --help
for flag in --out --buildings --res --threads --frames --grammar --seed --quick; do
  grep -q -- "$flag" out.txt && ok "bench_facade_help_documents_$flag" || bad "bench_facade_help_documents_$flag" "missing"
done
expect bench_facade_bad_res 2 "$pgt" bench facade --res 512
one_line bench_facade_bad_res_one_line "\-\-res"
expect bench_facade 0 "$pgt" bench facade --buildings 2,4 --res 64x48 --frames 1 --out res/facade.csv
grep -q "^# machine: " res/facade.csv && grep -q "^# commit: " res/facade.csv && ok bench_facade_header || bad bench_facade_header "$(head -5 res/facade.csv)"
/usr/bin/python3 -c '
import csv
rows = list(csv.DictReader(l for l in open("res/facade.csv") if not l.startswith("#")))
assert [(r["source"], r["facades"], r["width"]) for r in rows] == [("paper", "10000", "1280"), ("ours", "8", "64"), ("ours", "16", "64")], rows
assert rows[0]["ms"] == "143" and rows[0]["procedural_bytes"] == "650000", rows[0]
for r in rows[1:]:
    assert None not in r and all(r.values()), r
    assert float(r["agreement_pct"]) >= 99.0 and float(r["memory_ratio"]) > 1, r
    f = lambda k: float(r[k])
    # ours / Embree is the hits-only frame against Embree, the shaded ratio beside it (the
    # columns have 3 decimals: a loose tolerance, the definitions are what is checked)
    assert abs(f("ours_over_embree") - f("ours_trace_mrays") / f("embree_mrays")) <= 1e-2 * f("ours_over_embree") + 2e-3, r
    assert abs(f("shaded_over_embree") - f("ours_mrays") / f("embree_mrays")) <= 1e-2 * f("shaded_over_embree") + 2e-3, r
    assert abs(f("ours_trace_mrays") - f("width") * f("height") / (f("trace_ms") * 1e3)) <= 1e-2 * f("ours_trace_mrays") + 2e-3, r
    assert f("best_over_embree") > 0, r
    assert abs(f("packet_speedup") - f("single_trace_ms") / f("trace_ms")) <= 1e-2 * f("packet_speedup") + 2e-3, r' \
  && ok bench_facade_rows || bad bench_facade_rows "$(cat res/facade.csv)"
fields_match bench_facade_fields res/facade.csv

# pgt bench ivy --quick: Table 2's three scenes and Figure 11 at 1, 2, 4, ... 64 seeds
expect bench_ivy 0 "$pgt" bench ivy --quick --threads 2 --out res/table2.csv --fig11 res/fig11.csv
fields_match bench_ivy_table2_fields res/table2.csv
fields_match bench_ivy_fig11_fields res/fig11.csv
/usr/bin/python3 -c '
import csv
rd = lambda p: list(csv.DictReader(l for l in open(p) if not l.startswith("#")))
t2, f11 = rd("res/table2.csv"), rd("res/fig11.csv")
assert [r["scene"] for r in t2] == ["fig1b", "fig10c", "fig1a"], t2
assert [(r["scenario"], r["seeds"]) for r in f11] == [(s, str(1 << k)) for s in ("main", "full") for k in range(7)], f11
for r in t2 + f11:
    assert None not in r and all(r.values()), r
    assert r["threads"] == "2", r
    assert float(r["cold_ms"]) > 0 and 0 < float(r["best_ms"]) <= float(r["total_ms"]), r
    assert all(float(r[k]) >= 0 for k in ("expand_ms", "bezier_ms", "terminals_ms")), r
    assert int(r["polygons"]) > 0, r' \
  && ok bench_ivy_rows || bad bench_ivy_rows "$(head -c 600 res/fig11.csv)"

# bench ivy's two outputs are checked together before it runs: a refused --fig11 leaves no folder
# made for --out; --quick without --fig11 names that flag
expect bench_ivy_fig11_refused 2 "$pgt" bench ivy --quick --out newdir/t2.csv --fig11 /dev/null
one_line bench_ivy_fig11_refused_one_line "cannot write /dev/null"
[ ! -e newdir ] && ok bench_ivy_fig11_refused_no_folder || bad bench_ivy_fig11_refused_no_folder "newdir left"
mkdir emptyd
expect bench_ivy_fig11_refused_folder_kept 2 "$pgt" bench ivy --quick --out emptyd/t2.csv --fig11 /dev/null
[ -d emptyd ] && ok bench_ivy_fig11_refused_folder_kept_there || bad bench_ivy_fig11_refused_folder_kept_there "emptyd removed"
rmdir emptyd
expect bench_ivy_same_outputs 2 "$pgt" bench ivy --quick --out same.csv --fig11 ./same.csv
one_line bench_ivy_same_outputs_one_line "is named for two outputs"
[ ! -e same.csv ] && ok bench_ivy_same_outputs_nothing || bad bench_ivy_same_outputs_nothing "same.csv written"
# one missing folder level, counted from what existed before the run, whatever the flags' order
expect bench_ivy_two_levels 2 "$pgt" bench ivy --quick --out lv/t2.csv --fig11 lv/b/f.csv
expect bench_ivy_two_levels_swapped 2 "$pgt" bench ivy --quick --fig11 lv/t2.csv --out lv/b/f.csv
[ ! -e lv ] && ok bench_ivy_two_levels_no_folder || bad bench_ivy_two_levels_no_folder "lv left"
expect bench_ivy_quick_no_fig11 2 "$pgt" bench ivy --quick --out newdir/t2.csv
one_line bench_ivy_quick_no_fig11_one_line "\-\-quick without \-\-fig11 would replace results/fig11.csv"
[ ! -e newdir ] && ok bench_ivy_quick_no_fig11_no_folder || bad bench_ivy_quick_no_fig11_no_folder "newdir left"

expect missing_input 2 "$pgt" subdiv nothere.off --iters 1 -o x.off
one_line missing_input_names_file "nothere.off"

printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1\n3 0 1 2\n' >trunc.off
expect malformed_input 2 "$pgt" subdiv trunc.off --iters 1 -o x.off
one_line malformed_input_names_file_and_line "trunc.off:5"
[ ! -e x.off ] && ok no_output_on_failure || bad no_output_on_failure "x.off exists"

# topology errors name the line (binary PLY: the byte offset) of the face record they are about:
# the OBJ's quad is fan-triangulated, so face numbers after reading are not the file's (its note
# comes first on stderr); the edge's first face is the OFF's second, the bowtie vertex's first
# face the PLY's second (13 bytes a face record after 6 x 12 bytes of vertices)
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 -1 0\n# a quad, then a face repeating a vertex\nf 1 2 4 3\n\nf 1 5 5\n' >degenerate.obj
expect degenerate_input 2 "$pgt" subdiv degenerate.obj --iters 1 -o x.off
grep -q "^pgt subdiv: degenerate.obj:9: sqrt3 input: face 2 (0-based) repeats a vertex" err.txt \
  && ok degenerate_names_line || bad degenerate_names_line "stderr: $(cat err.txt)"
printf 'OFF\n8 4 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n5 5 5\n6 5 5\n5 6 5\n3 5 6 7\n3 0 1 2\n3 1 0 3\n3 0 1 4\n' >fin.off
expect non_manifold_edge_input 2 "$pgt" subdiv fin.off --iters 1 -o x.off
one_line non_manifold_edge_names_line "^pgt subdiv: fin.off:12: sqrt3 input: non-manifold edge (0, 1)"
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\nelement face 3\nproperty list uchar uint vertex_indices\nend_header\n' >bowtie.ply
header_bytes=$(wc -c <bowtie.ply)
/usr/bin/python3 -c 'import struct,sys; sys.stdout.buffer.write(struct.pack("<18f", 0,0,0, 1,0,0, 0,1,0, -1,0,0, 0,-1,0, 1,1,0) + struct.pack("<B3I", 3, 2,1,5) + struct.pack("<B3I", 3, 0,1,2) + struct.pack("<B3I", 3, 0,3,4))' >>bowtie.ply
expect non_manifold_vertex_input 2 "$pgt" subdiv bowtie.ply --iters 1 -o x.off
one_line non_manifold_vertex_names_offset "^pgt subdiv: bowtie.ply: byte offset $((header_bytes + 72 + 13)): sqrt3 input: non-manifold vertex 0"

cp "$ico" same.off
sum0=$(md5sum <same.off)
expect never_overwrites_input 2 "$pgt" subdiv same.off --iters 1 -o same.off
[ "$(md5sum <same.off)" = "$sum0" ] && ok input_unchanged || bad input_unchanged "input modified"
echo "keep me" >existing.off
expect failed_run_keeps_existing_output 2 "$pgt" subdiv trunc.off --iters 1 -o existing.off
grep -q "keep me" existing.off && ok existing_output_kept || bad existing_output_kept "overwritten"

expect subdiv_ok 0 "$pgt" subdiv "$ico" --iters 2 -o out.off --threads 2
grep -q "80 faces) -> out.off (.* 720 faces)" out.txt && ok summary_counts || bad summary_counts "$(cat out.txt)"
head -2 out.off | tail -1 | grep -q "^362 720 0" && ok output_counts || bad output_counts "$(head -2 out.off)"
expect subdiv_json 0 "$pgt" subdiv "$ico" --iters 1 -o out.ply --json
/usr/bin/python3 -c 'import json,sys; d=json.load(open("out.txt")); sys.exit(0 if d["faces_out"]==240 and d["vertices_out"]==122 else 1)' \
  && ok json_summary || bad json_summary "$(cat out.txt)"

printf '0 1\n# a comment\n2, 3\n' >prot.txt
expect protect_file 0 "$pgt" subdiv "$ico" --iters 1 -o p.off --protect prot.txt --json
/usr/bin/python3 -c 'import json,sys; d=json.load(open("out.txt")); sys.exit(0 if d["faces_out"]==76*3+4 and d["protected_faces"]==4 else 1)' \
  && ok protect_counts || bad protect_counts "$(cat out.txt)"
# a UTF-8 byte order mark (Notepad) before the first index is skipped: the same output
{ printf '\357\273\277'; cat prot.txt; } >prot_bom.txt
expect protect_file_bom 0 "$pgt" subdiv "$ico" --iters 1 -o p_bom.off --protect prot_bom.txt
expect protect_file_again 0 "$pgt" subdiv "$ico" --iters 1 -o p_nobom.off --protect prot.txt
cmp -s p_bom.off p_nobom.off && ok protect_file_bom_same || bad protect_file_bom_same "p_bom.off and p_nobom.off differ"
printf '\357x0 1\n' >prot_ef.txt
expect protect_file_ef 2 "$pgt" subdiv "$ico" --iters 1 -o p.off --protect prot_ef.txt
one_line protect_file_ef_one_line "prot_ef.txt:1:1: a byte 0xEF that does not start a UTF-8 byte order mark"
printf '0 1\n2 99\n' >prot_bad.txt
expect protect_out_of_range 2 "$pgt" subdiv "$ico" --iters 1 -o p.off --protect prot_bad.txt
one_line protect_out_of_range_names_line "prot_bad.txt:2"
printf 'OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n' >pillow.off
expect subdiv_pillow 2 "$pgt" subdiv pillow.off --iters 1 -o pillow_out.off
one_line subdiv_pillow_names_line "^pgt subdiv: pillow.off:6: sqrt3 input: faces 0 and 1 (0-based) share two edges"
cp prot.txt prot_keep.off # a list under a mesh's extension, so that -o accepts the name
expect protect_is_output 2 "$pgt" subdiv "$ico" --iters 1 --protect prot_keep.off -o prot_keep.off
one_line protect_is_output_one_line "\-o prot_keep.off is the \-\-protect file; pgt never overwrites an input"
cmp -s prot.txt prot_keep.off && ok protect_file_kept || bad protect_file_kept "overwritten"
printf '1\0005\n' >prot_nul.txt # strtoull read '1' and dropped the '5'
expect protect_nul 2 "$pgt" subdiv "$ico" --iters 1 -o p.off --protect prot_nul.txt
one_line protect_nul_names_line "prot_nul.txt:1:2: a NUL byte (expected text)"
printf '0 1\n2,\n3,,4\n' >prot_comma.txt # a trailing comma is a separator, an empty entry a typo
expect protect_empty_entry 2 "$pgt" subdiv "$ico" --iters 1 -o p.off --protect prot_comma.txt
one_line protect_empty_entry_names_column "prot_comma.txt:3:3: ',' without a face index before it"
printf '0 x1\n' >prot_tok.txt
expect protect_bad_token 2 "$pgt" subdiv "$ico" --iters 1 -o p.off --protect prot_tok.txt
one_line protect_bad_token_names_line "prot_tok.txt:1"
expect group_needs_labels 2 "$pgt" subdiv "$ico" --iters 1 -o g.off --group 1
expect group_ok 0 "$pgt" subdiv "$work/data/cube_sphere_8.ply" --iters 1 -o g.ply --group 4 --json
/usr/bin/python3 -c 'import json,sys; d=json.load(open("out.txt")); f=128; sys.exit(0 if d["faces_out"]==f*3+5*f and d["protected_faces"]==5*f else 1)' \
  && ok group_counts || bad group_counts "$(cat out.txt)"
expect group_absent 2 "$pgt" subdiv "$work/data/cube_sphere_8.ply" --iters 1 -o g.ply --group 9
expect protect_and_group 2 "$pgt" subdiv "$work/data/cube_sphere_8.ply" --iters 1 -o g.ply --group 4 --protect prot.txt

expect bench_unknown 2 "$pgt" bench nothing
expect bench_bad_flag 2 "$pgt" bench subdiv --repeat zero
expect bench_bad_backends 2 "$pgt" bench subdiv --backends cuda
# (GPU columns: tests/backend_diff.sh, which runs with the drivers' test environment)
expect bench_quick 0 "$pgt" bench subdiv --quick --no-oracles --backends none --meshes icosphere_l2,grid_16x16 --threads 1,2 --out res/subdiv.csv
grep -q "^# machine: " res/subdiv.csv && grep -q "^# commit: " res/subdiv.csv && grep -q "^# date: " res/subdiv.csv \
  && ok bench_header || bad bench_header "$(head -5 res/subdiv.csv)"
fields_match bench_rows_match_header res/subdiv.csv
rows=$(grep -vc '^#' res/subdiv.csv)
[ "$rows" -eq $((1 + 2 * 2 * 2)) ] && ok bench_rows || bad bench_rows "$rows lines"

# A run stopped by SIGTERM (timeout, kill) while it writes leaves no temporary file or staging
# folder and the old output as it was, and ends by the signal (exit 143): subdiv writes
# PATH.tmp.PID beside its output, atlas stages its EXR and PNG in .pgt-stage.PID. Killed as soon
# as the temporary name exists (polled every 10 ms, for at most 30 s).
killed_while_writing() { # NAME PATTERN OUTPUT COMMAND...
  local name=$1 pattern=$2 output=$3; shift 3
  rm -rf sig && mkdir sig && (
    cd sig && echo old > "$output" || exit 1
    "$@" > /dev/null 2>&1 & pid=$!
    n=0
    until compgen -G "$pattern" > /dev/null; do
      sleep 0.01; n=$((n + 1))
      if [ $n -gt 3000 ] || ! kill -0 $pid 2> /dev/null; then echo "no $pattern while it ran"; exit 1; fi
    done
    kill -TERM $pid; wait $pid; rc=$?
    left=$(ls -A | grep -E '\.tmp\.|\.pgt-stage\.' | tr '\n' ' ')
    [ $rc -eq 143 ] && [ -z "$left" ] && [ "$(cat "$output")" = old ] ||
      { echo "exit $rc, left: '$left', $output: $(head -c 20 "$output")"; exit 1; }
  ) > sig.txt 2>&1 && ok "$name" || bad "$name" "$(cat sig.txt)"
}
"$gen" sig_data --only icosphere_l1 > /dev/null
# started with stdout and stderr closed (cron, a daemon), a run does its work: the signal pipe
# must not become fd 1 or 2 (what pgt printed was read as a signal: exit 240, nothing written)
(cd sig_data && echo old > closed.ply && PGT_PROGRESS_SECONDS=0.001 "$pgt" subdiv icosphere_l1.off --iters 6 -o closed.ply 1>&- 2>&-; echo "$?" > closed.rc)
[ "$(cat sig_data/closed.rc)" = 0 ] && [ "$(head -c 3 sig_data/closed.ply)" = ply ] && ok run_with_closed_stdio ||
  bad run_with_closed_stdio "exit $(cat sig_data/closed.rc), $(head -c 3 sig_data/closed.ply)"
killed_while_writing subdiv_killed_while_writing 's.ply.tmp.*' s.ply \
  "$pgt" subdiv ../sig_data/icosphere_l1.off --iters 10 -o s.ply
killed_while_writing atlas_killed_while_writing '.pgt-stage.*' a.exr \
  "$pgt" atlas "$work/data/cube_sphere_8.ply" -o a.exr --res 2048 --png a.png
# an output's file name of up to 255 bytes is written (the temporary name is cut to fit and
# carries a hash: NAME-CUT~HASH.tmp.PID), and removed when a signal stops the run; a longer one is
# refused before any work
long=$(printf 'L%.0s' $(seq 250)).ply
killed_while_writing long_name_killed_while_writing 'LLL*~*.tmp.*' "$long" \
  "$pgt" subdiv ../sig_data/icosphere_l1.off --iters 10 -o "$long"
expect long_name_written 0 "$pgt" subdiv "$ico" --iters 1 -o "$long"
[ "$(head -c 3 "$long")" = ply ] && [ -z "$(ls -A | grep -F '.tmp.')" ] && ok long_name_written_whole \
  || bad long_name_written_whole "$(ls -A | cut -c 1-30)"
rm -f "$long"
expect long_name_refused 2 "$pgt" subdiv "$ico" --iters 9 -o "${long%.ply}LLLLLL.ply"
one_line long_name_refused_one_line "^pgt subdiv: cannot write L*\.ply: File name too long"
[ -z "$(ls -A | grep '^LLL')" ] && ok long_name_refused_nothing_left || bad long_name_refused_nothing_left "$(ls -A | cut -c 1-30)"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
