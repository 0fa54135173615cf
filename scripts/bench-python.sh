#!/usr/bin/env bash
# Cost of the Python bindings per call: the same queries timed in Python (roadcross module,
# Debian's /usr/bin/python3) and in C++ (tests/benchmarks/runtime_bench), in one run on the
# bundled Prague map (no elevation, as runtime_bench builds it). Positions: random points of the
# extent kept when a road is within 15 m. Python: 5 repetitions of 20 000 calls, median of the
# per-repetition means of CPU time (time.process_time, comparable with Google Benchmark's CPU
# column under load); C++: Google Benchmark, median of 5 repetitions.
# Usage: scripts/bench-python.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
build_dir=${1:-build/release}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
machine_line
"$build_dir/cli/roadcross-build" --osm maps/prague/prague_nove_mesto_roads_2017.osm -o "$work/prague.gpkg" -q

echo "== C++ (runtime_bench: real time, CPU time per call)"
ROADCROSS_BENCH_DB="$work/prague.gpkg" "$build_dir/tests/benchmarks/runtime_bench" \
  --benchmark_filter='BM_(Nearest|Assess/.*threads:1)$' --benchmark_repetitions=5 \
  --benchmark_report_aggregates_only=true --benchmark_min_time=0.5 2>&1 | grep -E "median"

echo "== Python (CPU time per call)"
PYTHONPATH="$build_dir/python/module" /usr/bin/python3 - "$work/prague.gpkg" <<'PY'
import math, random, statistics, sys, time
import roadcross

m = roadcross.Map(sys.argv[1])
e0, n0, e1, n1 = m.info.extent_utm_m
rng = random.Random(7)
positions = []
while len(positions) < 4096:
    e, n = rng.uniform(e0, e1), rng.uniform(n0, n1)
    try:
        m.nearest(easting=e, northing=n, max_distance_m=15.0)
        positions.append((e, n))
    except roadcross.NoRoadError:
        pass
plan = roadcross.CrossingPlan(start=roadcross.PlanePoint(easting_m=0.0, northing_m=0.0),
                              target=roadcross.PlanePoint(easting_m=0.0, northing_m=10.0),
                              heading_rad=math.pi / 2, road_width_m=6.0)

def per_call_us(call, count=20000, repetitions=5):
    means = []
    for _ in range(repetitions):
        start = time.process_time()
        for i in range(count):
            call(*positions[i % len(positions)])
        means.append((time.process_time() - start) / count * 1e6)
    return statistics.median(means)

print(f"nearest   {per_call_us(lambda e, n: m.nearest(easting=e, northing=n)):7.2f} us")
print(f"assess    {per_call_us(lambda e, n: m.assess(easting=e, northing=n)):7.2f} us")
print(f"monitor   {per_call_us(lambda e, n: roadcross.monitor(plan, easting=0.3, northing=5.0, yaw_rad=1.5)):7.2f} us")
print(f"(empty Python loop with the same lambda call: {per_call_us(lambda e, n: None):.2f} us)")
PY
