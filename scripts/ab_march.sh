#!/usr/bin/env bash
# A/B timing of two versions of ref_cpu/src/march.c in one process (harness/ab/ab_march.c).
#   scripts/ab_march.sh A B MESH [pgt_ab_march flags: --runs N --walkers W --steps S --step L
#                                  --res R --position --two-views]
# A and B: a git revision (its ref_cpu/src/march.c), a path to a march.c, or WORK (the working
# tree's). Each is compiled as a shared object by march.c's compile command in the build's
# compile_commands.json (build/release: scripts/build.sh Release first; PGT_AB_BUILD names
# another build directory), against that build's source tree's headers. Prints both rates,
# the median ratio B/A over the pairs of runs and whether both left the walkers the same.
# Example: scripts/ab_march.sh HEAD~1 WORK ../shared/datasets/meshes/pizza.obj --runs 30
set -uo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
fail() { echo "ab_march: $*" >&2; exit 2; }
[ $# -ge 3 ] || { sed -n '2,10p' "${BASH_SOURCE[0]}" >&2; exit 2; }
a=$1 b=$2 mesh=$3; shift 3
build=${PGT_AB_BUILD:-$top/build/release}
[ -x "$build/harness/ab/pgt_ab_march" ] || fail "$build/harness/ab/pgt_ab_march missing: run scripts/build.sh Release"
[ -f "$build/compile_commands.json" ] || fail "$build/compile_commands.json missing: configure the build with CMake"
work=$(mktemp -d /tmp/pgt_ab.XXXXXX) || fail "cannot make a temporary directory"
child=
cleanup() { [ -n "$child" ] && kill "$child" 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT
# on INT or TERM: clean up, then die of the same signal, so that a calling loop stops too
for sig in INT TERM; do trap "cleanup; trap - $sig EXIT; kill -$sig \$\$" $sig; done
# march.c's compile command without its -o and -c operands, one argument per NUL-ended item;
# the first is the compiler, the last march.c's directory (its internal headers)
mapfile -d '' cmd < <(/usr/bin/python3 - "$build/compile_commands.json" <<'PY'
import json, os, shlex, sys
for e in json.load(open(sys.argv[1])):
    if e["file"].endswith("ref_cpu/src/march.c"):
        args = e["arguments"] if "arguments" in e else shlex.split(e["command"])
        out, skip = [], False
        for x in args:
            if skip:
                skip = False
                continue
            if x in ("-o", "-c"):
                skip = True
                continue
            if x == e["file"] or x.endswith("ref_cpu/src/march.c"):
                continue
            out.append(x)
        out.append(os.path.dirname(os.path.join(e.get("directory", ""), e["file"])))
        sys.stdout.write("\0".join(out) + "\0")
        break
PY
)
[ ${#cmd[@]} -ge 2 ] || fail "no compile command for march.c in $build/compile_commands.json"
srcdir=${cmd[-1]}
unset 'cmd[-1]'
for side in a b; do
  rev=${!side}
  src=$work/march_$side.c
  if [ "$rev" = WORK ]; then cp "$top/ref_cpu/src/march.c" "$src" || fail "cannot read the working tree's march.c"
  elif [ -f "$rev" ]; then cp "$rev" "$src" || fail "cannot read $rev"
  else git -C "$top" show "$rev:ref_cpu/src/march.c" >"$src" 2>/dev/null || fail "no ref_cpu/src/march.c at revision '$rev'"
  fi
  # -Wno-error: a scratch variant or an older revision may warn where the build's -Werror refuses
  (cd "$build" && "${cmd[@]}" -Wno-error -I"$srcdir" -fPIC -shared -Wl,-Bsymbolic -o "$work/$side.so" "$src" -lm) \
    || fail "$rev: march.c does not compile (see above; its API must match $srcdir/../include/pgt/march.h)"
done
echo "ab_march: A = $a, B = $b, $(basename "$mesh")" >&2
"$build/harness/ab/pgt_ab_march" "$work/a.so" "$work/b.so" "$mesh" "$@" &
child=$!
wait "$child"
status=$?
child=
exit $status
