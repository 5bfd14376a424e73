#!/usr/bin/env bash
# Configures and builds one build type into build/<type> (Release, Debug or Sanitize).
#   scripts/build.sh [Release|Debug|Sanitize]
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
type=${1:-Release}
dir="$top/build/$(echo "$type" | tr '[:upper:]' '[:lower:]')"
cmake -S "$top" -B "$dir" -DCMAKE_BUILD_TYPE="$type" >/dev/null
cmake --build "$dir" -j"$(nproc)"
echo "$dir"
