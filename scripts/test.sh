#!/usr/bin/env bash
# Sets up, builds and runs every test (ctest). With --asan, the same tests under ASan+UBSan;
# with --runtime-only, the runtime-only build (SQLite + GeographicLib, no GIS stack) and its tests;
# with --tsan, that runtime-only build under ThreadSanitizer (its multi-thread tests).
set -euo pipefail
cd "$(dirname "$0")/.."

preset=release
case "${1:-}" in
  --asan) preset=asan ;;
  --runtime-only) preset=runtime-only ;;
  --tsan) preset=tsan ;;
  "") ;;
  *) echo "usage: scripts/test.sh [--asan | --runtime-only | --tsan]" >&2; exit 2 ;;
esac

bash scripts/setup.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" -j"$(nproc)"
ctest --preset "$preset" -j"$(nproc)" --timeout 600 --output-on-failure
