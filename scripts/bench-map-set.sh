#!/usr/bin/env bash
# Assess over a set of 10 maps against one map (issue 29: at most 1.5x): the Prague map moved by
# whole degrees of longitude, 10 copies in UTM zones 33 and 34 (tests/benchmarks/map_set_bench.cpp),
# medians of 5 repetitions, interleaved within one run. Usage: scripts/bench-map-set.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
build_dir=${1:-build/release}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
machine_line
ROADCROSS_BENCH_SET_DIR="$work" "$build_dir/tests/benchmarks/map_set_bench" \
  --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true \
  --benchmark_report_aggregates_only=true --benchmark_min_time=0.5 2>&1 | grep -E "median"
