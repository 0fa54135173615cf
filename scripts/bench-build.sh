#!/usr/bin/env bash
# Measures roadcross-build on the bundled maps: median wall time of N runs and peak memory
# (max RSS). Usage: scripts/bench-build.sh [runs=5] [build-dir=build/release]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
runs=${1:-5}
build_dir=${2:-build/release}
tool="$build_dir/cli/roadcross-build"
[[ -x "$tool" ]] || { echo "build $tool first (cmake --build --preset release)" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

machine_line
printf '%-48s %10s %12s\n' "input (extra arguments)" "median s" "peak RSS MiB"
bench() {
  local label=$1; shift
  local times=() rss=0
  for ((i = 0; i < runs; i++)); do
    /usr/bin/time -f '%e %M' -o "$out/time" "$tool" "$@" -o "$out/map.gpkg" -q
    read -r seconds kib <"$out/time"
    times+=("$seconds")
    ((kib > rss)) && rss=$kib
  done
  printf '%-48s %10s %12.1f\n' "$label" "$(median "${times[@]}")" "$(echo "$rss / 1024" | bc -l)"
}
# Each map without and with its SRTM raster, interleaved so that the ratio compares like with like.
bench "prague (osm xml, 651 kB)" --osm maps/prague/prague_nove_mesto_roads_2017.osm "${@:3}"
bench "prague + SRTM raster" --osm maps/prague/prague_nove_mesto_roads_2017.osm \
  --elevation maps/prague/N50E014.hgt "${@:3}"
bench "monaco (pbf, 1.8 MB)" --osm maps/monaco/monaco.osm.pbf "${@:3}"
bench "monaco + SRTM raster" --osm maps/monaco/monaco.osm.pbf --elevation maps/monaco/N43E007.hgt "${@:3}"
bench "bayreuth (osm.gz, 1.4 MB)" --osm maps/bayreuth/north-bayreuth.osm.gz "${@:3}"
bench "bayreuth + 2 SRTM rasters" --osm maps/bayreuth/north-bayreuth.osm.gz \
  --elevation maps/bayreuth/N49E011.hgt --elevation maps/bayreuth/N50E011.hgt "${@:3}"
# The XYZ path: points derived from the Monaco tile (30 m, UTM 32N, comma-separated).
scripts/make-derived-xyz.sh maps/monaco/N43E007.hgt EPSG:32632 "366000 4840500 379500 4848500" 30 \
  comma "$out/monaco.csv" 2>/dev/null
bench "monaco + XYZ (120 k points, TIN)" --osm maps/monaco/monaco.osm.pbf \
  --elevation "$out/monaco.csv" --elevation-crs EPSG:32632 "${@:3}"
