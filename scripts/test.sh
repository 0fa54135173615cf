#!/usr/bin/env bash
# Sets up, builds and runs every test (ctest). With --asan, the same tests under ASan+UBSan.
set -euo pipefail
cd "$(dirname "$0")/.."

preset=release
if [[ "${1:-}" == "--asan" ]]; then preset=asan; fi

bash scripts/setup.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" -j"$(nproc)"
ctest --preset "$preset" -j"$(nproc)" --timeout 600
