#!/usr/bin/env bash
# Wall time of one `roadcross` call (the CLI's start-up and one query) on the bundled Prague map:
# `--version` and `assess` at a kerb, median of 40 runs each, for each roadcross binary given
# (default: the release build's; e.g. also an older build's, or build/runtime-only's).
# Usage: scripts/bench-cli-startup.sh [ROADCROSS...]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
binaries=("$@")
((${#binaries[@]})) || binaries=(build/release/cli/roadcross)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
machine_line
build/release/cli/roadcross-build --osm maps/prague/prague_nove_mesto_roads_2017.osm -o "$work/prague.gpkg" -q --sight.enabled 0
for binary in "${binaries[@]}"; do
  python3 - "$binary" "$work/prague.gpkg" <<'PY'
import statistics, subprocess, sys, time
binary, db = sys.argv[1], sys.argv[2]
def median_ms(args, runs=40):
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run(args, check=True, stdout=subprocess.DEVNULL)
        times.append(time.perf_counter() - start)
    return 1000 * statistics.median(times)
libraries = subprocess.run(["ldd", binary], capture_output=True, text=True).stdout.count("=>")
version = median_ms([binary, "--version"])
assess = median_ms([binary, "assess", "--db", db, "--lat", "50.075769", "--lon", "14.416015"])
print(f"{binary}: {libraries} shared libraries; --version {version:.1f} ms; assess {assess:.1f} ms (medians of 40)")
PY
done
