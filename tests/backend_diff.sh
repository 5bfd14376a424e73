#!/usr/bin/env bash
# The cross-backend diff of every algorithm on every test mesh (pgt diff all: sqrt3 on the
# generated default datasets and the shared manifold meshes, k = 1..3, with and without protected
# faces; march, on cl, on the cube-sphere and the shared meshes with UVs, five option sets).
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
# march: 6 default inputs x 5 option sets on cl; vk has no version yet and says so
if [ "$api" = cl ]; then
  n=$(grep -c "^march .*: ok$" "$out")
  [ "$n" = 30 ] || { echo "FAIL: $n march cases passed on cl, expected 30"; rm -f "$out"; exit 1; }
else
  grep -q "^march: no vk version yet (skipped)$" "$out" \
    || { echo "FAIL: pgt diff all --backend vk did not say march was skipped"; rm -f "$out"; exit 1; }
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
