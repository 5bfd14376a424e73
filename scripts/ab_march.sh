#!/usr/bin/env bash
# A/B timing of two versions of ref_cpu/src/march.c in one process (harness/ab/ab_march.c).
#   scripts/ab_march.sh A B MESH [pgt_ab_march flags: --runs N --walkers W --steps S --step L
#                                  --res R --position]
# A and B: a git revision (its ref_cpu/src/march.c), a path to a march.c, or WORK (the working
# tree's). Each is compiled as a shared object with the Release flags of march.c in
# build/release/compile_commands.json (scripts/build.sh Release first; PGT_AB_BUILD names
# another build directory). Prints both rates,
# the median ratio B/A over the pairs of runs and whether both took the same steps.
# Example: scripts/ab_march.sh HEAD~1 WORK ../shared/datasets/meshes/pizza.obj --runs 30
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
[ $# -ge 3 ] || { sed -n '2,10p' "${BASH_SOURCE[0]}" >&2; exit 2; }
a=$1 b=$2 mesh=$3; shift 3
build=${PGT_AB_BUILD:-$top/build/release}
[ -x "$build/harness/ab/pgt_ab_march" ] && [ -f "$build/compile_commands.json" ] \
  || { echo "ab_march: $build/harness/ab/pgt_ab_march missing: run scripts/build.sh Release" >&2; exit 2; }
work=$(mktemp -d /tmp/pgt_ab.XXXXXX)
trap 'rm -rf "$work"' EXIT
# march.c's compile command, without its -o and -c operands
flags=$(/usr/bin/python3 - "$build/compile_commands.json" <<'PY'
import json, shlex, sys
for e in json.load(open(sys.argv[1])):
    if e["file"].endswith("ref_cpu/src/march.c"):
        args = shlex.split(e["command"])[1:]
        out = []
        skip = False
        for x in args:
            if skip: skip = False; continue
            if x in ("-o", "-c"): skip = True; continue
            out.append(x)
        print(" ".join(shlex.quote(x) for x in out))
PY
)
[ -n "$flags" ] || { echo "ab_march: no compile command for march.c in $build" >&2; exit 2; }
for side in a b; do
  rev=${!side}
  src=$work/march_$side.c
  if [ "$rev" = WORK ]; then cp "$top/ref_cpu/src/march.c" "$src"
  elif [ -f "$rev" ]; then cp "$rev" "$src"
  else git -C "$top" show "$rev:ref_cpu/src/march.c" >"$src" || { echo "ab_march: no march.c at '$rev'" >&2; exit 2; }
  fi
  # the includes of march.c resolve against the working tree's headers (march.h, the internals)
  eval cc $flags -I"$top/ref_cpu/src" -fPIC -shared -Wl,-Bsymbolic -o "$work/$side.so" "$src" -lm
done
echo "ab_march: A = $a, B = $b, $(basename "$mesh")" >&2
"$build/harness/ab/pgt_ab_march" "$work/a.so" "$work/b.so" "$mesh" "$@"
