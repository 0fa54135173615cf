#!/usr/bin/env bash
# Scale benchmark (issue 8): tiles the bundled Monaco extract (full OSM data: buildings,
# footways, tunnels) 1x, 10x, 50x and 200x with fresh ids and a matching DEM mosaic, then times
# `osmium tags-filter FILE w/highway` and roadcross-build (without and with the DEM) on each, in
# the same run, and the build without the sight stage (--sight.enabled 0). Writes docs/scale.csv
# and docs/scale.png (gnuplot); prints each build's per-stage seconds and peak memory (--json)
# and the load average.
# Usage: scripts/bench-scale.sh [sizes="1 10 50 200"] [build-dir=build/release]
# BENCH_DEM=0 skips the builds with the DEM (their columns stay empty). The DEM build runs with
# --sight.enabled 0 and is compared with the build without the sight stage: the terrain stage's
# cost alone (the sight stage dominates both builds and is timed by the default build).
# BENCH_REPEAT=N (default 1): each size's runs N times, osmium and the builds alternating; the
# table has each time's median and each peak's maximum, and a comment line lists every time.
# build_per_osmium: the median over the rounds of each round's default build time over that
# round's osmium time (the two run one after the other): on a machine whose speed drifts between
# rounds it moves less than the ratio of the two medians.
# BENCH_BUILD_ARGS: extra arguments for every roadcross-build run. BENCH_NO_DOCS=1: print the
# table, leave docs/ alone. Another map: BENCH_MAP (an OSM file, default the Monaco extract),
# BENCH_DEM_IN (its elevation files, space-separated; several are mosaicked with gdalbuildvrt)
# and BENCH_NAME (docs/BENCH_NAME.csv and .png; default scale).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
sizes=${1:-"1 10 50 200"}
build_dir=${2:-build/release}
tool="$build_dir/cli/roadcross-build"
make_tiled="$build_dir/tests/benchmarks/make_tiled_osm"
for f in "$tool" "$make_tiled"; do [[ -x "$f" ]] || { echo "build $f first" >&2; exit 1; }; done
work=${BENCH_WORK_DIR:-$(mktemp -d)}
trap '[[ -z "${BENCH_WORK_DIR:-}" ]] && rm -rf "$work"' EXIT
map=${BENCH_MAP:-maps/monaco/monaco.osm.pbf}
name=${BENCH_NAME:-scale}
read -r -a dem_files <<<"${BENCH_DEM_IN:-maps/monaco/N43E007.hgt}"
dem_in=${dem_files[0]}
if ((${#dem_files[@]} > 1)); then
  dem_in="$work/dem_in.vrt"
  gdalbuildvrt -q "$dem_in" "${dem_files[@]}"
fi
with_dem=0
# no -q: an early exit of grep would fail the pipe under pipefail
if [[ "${BENCH_DEM:-1}" != 0 ]] && "$tool" --help | grep -- '--elevation' >/dev/null; then with_dem=1; fi

# measure CMD...: prints "seconds peak_kib" of one run; its stdout goes to $work/stdout. The page
# cache is synced first: at 200x the builds before it leave ~5 GB of output to write back, over
# the kernel's dirty limit, and the next build's writing stage would wait for it.
measure() {
  sync
  /usr/bin/time -f '%e %M' -o "$work/time" "$@" >"$work/stdout" 2>"$work/stderr" || { cat "$work/stderr" >&2; return 1; }
  cat "$work/time"
}
# stages LABEL: the per-stage lines of the --json summary in $work/stdout (to stderr).
stages() {
  python3 -c 'import json,sys
d = json.load(open(sys.argv[1]))
print("#   " + sys.argv[2] + ": " + "; ".join("%s %.2f s %.0f MiB" % (s["stage"], s["seconds"], s["peak_rss_mib"]) for s in d["stages"]))' "$work/stdout" "$1" >&2
}

echo "# $(machine_line)"
echo "copies,pbf_bytes,osmium_s,osmium_kib,build_s,build_kib,build_dem_s,build_dem_kib,segments,no_sight_s,no_sight_kib,build_per_osmium" | tee "$work/scale.csv"
repeats=${BENCH_REPEAT:-1}
# max VALUE...: the largest.
max() { printf '%s\n' "$@" | sort -g | tail -n 1; }
for n in $sizes; do
  "$make_tiled" "$map" "$n" "$work/m$n.osm.pbf" "$dem_in" "$work/m$n.tif" >/dev/null
  echo "# $n copies, load average before: $(cut -d' ' -f1-3 /proc/loadavg)" >&2
  osmium_runs=() osmium_peaks=() build_runs=() build_peaks=() no_sight_runs=() no_sight_peaks=()
  ratio_runs=()
  dem_runs=() dem_peaks=()
  for ((run = 1; run <= repeats; run++)); do
    read -r s kib < <(measure osmium tags-filter "$work/m$n.osm.pbf" w/highway -o "$work/f.osm.pbf" --overwrite)
    osmium_runs+=("$s") osmium_peaks+=("$kib")
    # shellcheck disable=SC2086
    read -r s kib < <(measure "$tool" --osm "$work/m$n.osm.pbf" -o "$work/m$n.gpkg" --json ${BENCH_BUILD_ARGS:-})
    build_runs+=("$s") build_peaks+=("$kib")
    ratio_runs+=("$(awk -v b="$s" -v o="${osmium_runs[-1]}" 'BEGIN { if (o > 0) printf "%.3f", b / o; else print "inf" }')")
    stages "build"
    segments=$(sqlite3 "$work/m$n.gpkg" "SELECT count(*) FROM segments")
    rm -f "$work/m$n.gpkg"  # each output goes as soon as it is measured (see measure)
    # shellcheck disable=SC2086
    read -r s kib < <(measure "$tool" --osm "$work/m$n.osm.pbf" -o "$work/m${n}ns.gpkg" --sight.enabled 0 --json ${BENCH_BUILD_ARGS:-})
    no_sight_runs+=("$s") no_sight_peaks+=("$kib")
    stages "--sight.enabled 0"
    rm -f "$work/m${n}ns.gpkg"
    if ((with_dem)); then
      # shellcheck disable=SC2086
      read -r s kib < <(measure "$tool" --osm "$work/m$n.osm.pbf" --elevation "$work/m$n.tif" -o "$work/m${n}dem.gpkg" --sight.enabled 0 --json ${BENCH_BUILD_ARGS:-})
      dem_runs+=("$s") dem_peaks+=("$kib")
      stages "--elevation --sight.enabled 0"
      rm -f "$work/m${n}dem.gpkg"
    fi
  done
  dem_s="" dem_kib=""
  if ((with_dem)); then dem_s=$(median "${dem_runs[@]}") dem_kib=$(max "${dem_peaks[@]}"); fi
  echo "# load average after: $(cut -d' ' -f1-3 /proc/loadavg)" >&2
  if ((repeats > 1)); then
    echo "# $n copies, every run's seconds: osmium ${osmium_runs[*]}; build ${build_runs[*]}; no sight ${no_sight_runs[*]}${dem_runs:+; dem ${dem_runs[*]}}; build / osmium by round ${ratio_runs[*]}" >&2
  fi
  echo "$n,$(stat -c %s "$work/m$n.osm.pbf"),$(median "${osmium_runs[@]}"),$(max "${osmium_peaks[@]}"),$(median "${build_runs[@]}"),$(max "${build_peaks[@]}"),$dem_s,$dem_kib,$segments,$(median "${no_sight_runs[@]}"),$(max "${no_sight_peaks[@]}"),$(median "${ratio_runs[@]}")" | tee -a "$work/scale.csv"
  rm -f "$work/m$n.gpkg" "$work/m${n}dem.gpkg" "$work/m${n}ns.gpkg"
done
[[ -n ${BENCH_NO_DOCS:-} ]] && { cat "$work/scale.csv"; exit 0; }  # a comparison run: keep docs/
cp "$work/scale.csv" "docs/$name.csv"
if command -v gnuplot >/dev/null; then
  gnuplot <<GNUPLOT
set terminal pngcairo size 900,420 font ",10"
set output "docs/$name.png"
set datafile separator ","
set key autotitle columnhead left top
set multiplot layout 1,2
set logscale xy
set xlabel "copies of $(basename "$map")"
set ylabel "wall time, s"
set grid
plot "docs/$name.csv" using 1:5 with linespoints title "roadcross-build", \
     "" using 1:10 with linespoints title "roadcross-build --sight.enabled 0", \
     "" using 1:3 with linespoints title "osmium tags-filter w/highway", \
     "" using 1:7 with linespoints title "roadcross-build --elevation --sight.enabled 0"
set ylabel "peak RSS, MiB"
plot "docs/$name.csv" using 1:(\$6/1024) with linespoints title "roadcross-build", \
     "" using 1:(\$11/1024) with linespoints title "roadcross-build --sight.enabled 0", \
     "" using 1:(\$4/1024) with linespoints title "osmium tags-filter", \
     "" using 1:(\$8/1024) with linespoints title "roadcross-build --elevation --sight.enabled 0"
unset multiplot
GNUPLOT
fi
