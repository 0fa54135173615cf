#!/usr/bin/env bash
# Runtime benchmarks (issue 7): open, nearest, assess (1 and 2 threads), better_place and a bare
# R*Tree lookup, on the bundled Prague map and on a DB 100x larger (Prague tiled 100 times by
# make_tiled_osm), medians of 5 repetitions. Usage: scripts/bench-runtime.sh [build-dir]
# ROADCROSS_BENCH_ANYWHERE=1 queries anywhere in the extent instead of within 15 m of a road.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
build_dir=${1:-build/release}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
machine_line
run() {
  "$build_dir/tests/benchmarks/runtime_bench" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
    --benchmark_min_time=0.5 2>&1 | grep -E "median"
}
echo "== bundled Prague map (6 049 segments)"
run
"$build_dir/tests/benchmarks/make_tiled_osm" maps/prague/prague_nove_mesto_roads_2017.osm 100 "$work/p100.osm.pbf" >/dev/null
"$build_dir/cli/roadcross-build" --osm "$work/p100.osm.pbf" -o "$work/p100.gpkg" -q
echo "== Prague tiled 100x ($(sqlite3 "$work/p100.gpkg" 'SELECT count(*) FROM segments') segments)"
ROADCROSS_BENCH_DB="$work/p100.gpkg" run
