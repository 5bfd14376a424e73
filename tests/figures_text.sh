#!/bin/sh
# The figures drawn from the committed results/ tables, and the panel figures drawn from the
# committed renders in paper_figs/out, at the paper's 7 in text width: every text >= 7 pt
# (footnote >= 6), no overlaps, no legend over data, nothing clipped (paper_figs/check_text.py,
# which exits 1 when a limit is broken). The figures that need the main job's intermediates
# (atlases, marches) are measured by hand (paper_figs/README.md).
#   figures_text.sh REPO_DIR
set -eu
repo=$1
py=/usr/bin/python3
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail=0
check() { # NAME SCRIPT ARGS...: runs the script under check_text.py, needs one measured PNG
  name=$1
  shift
  if ! "$py" "$repo/paper_figs/check_text.py" "$repo/paper_figs/$@" >"$out/$name.log" 2>&1; then
    echo "FAIL $name:"
    cat "$out/$name.log"
    fail=1
  elif ! grep -q " fig  *[0-9.]* in " "$out/$name.log"; then
    echo "FAIL $name: check_text.py measured no figure"
    cat "$out/$name.log"
    fail=1
  else
    echo "ok   $name: $(grep " fig  *[0-9.]* in " "$out/$name.log" | head -n 1)"
  fi
}
check subdiv_time subdiv_time.py "$repo/results/subdiv.csv" "$out/subdiv_time"
check ivy_seeds ivy_seeds.py "$repo/results/fig11.csv" "$repo/results/table2.csv" "$out/ivy_seeds"
check woven_bars woven_bars.py "$repo/results/woven.csv" "$out/woven_bars"
check facade_bench facade_bench.py "$repo/results/facade.csv" "$out/facade_bench"
f="$repo/paper_figs/out"
check ivy_scenes ivy_scenes.py "$out/ivy_scenes" "$f/ivy_fig1a.png" "Fig. 1a: bob, 25 seeds" \
  "$f/ivy_fig1b.png" "Fig. 1b: human, 18 seeds" "$f/ivy_fig10b.png" "Fig. 10b: spot, forbidden" \
  "$f/ivy_fig10c.png" "Fig. 10c: spot, painted paths"
check facade_city facade_panels.py "$out/facade_city" "$f/facade_fig1a.png" "(a) 10K facades" \
  "$f/facade_fig1b.png" "(b) macroscopic details" "$f/facade_fig1c.png" "(c) the paper's grammar" \
  --title "Per-pixel procedural facades with pgt facade, like paper 003 Fig. 1a-c"
exit $fail
