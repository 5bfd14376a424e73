#!/usr/bin/env bash
# The whole test suite: installs missing Debian packages, builds Release, Debug and the
# ASan+UBSan (Sanitize) configuration, and runs every CTest test in each (STYLE.md: all three
# builds run the suite). Name build types to run only those:
#   bash scripts/test.sh [Release|Debug|Sanitize ...]
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$top"
bash scripts/install-deps.sh
types=("$@")
if [ ${#types[@]} -eq 0 ]; then types=(Release Debug Sanitize); fi
export POCL_CACHE_DIR="$top/build/cache/pocl" MESA_SHADER_CACHE_DIR="$top/build/cache/mesa"
export XDG_CACHE_HOME="$top/build/cache/xdg"
# ASan: leaks are errors; UBSan: print the stack, then abort (the build already sets no-recover).
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
status=0
for t in "${types[@]}"; do
  echo "== test.sh: build $t"
  dir=$(bash scripts/build.sh "$t" | tail -n 1)
  echo "== test.sh: ctest $t ($dir)"
  if ! ctest --test-dir "$dir" --output-on-failure -j1 --timeout 3000; then status=1; fi
done
exit $status
