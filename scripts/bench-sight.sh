#!/usr/bin/env bash
# Measures the sight distance stage (issue 11) on the bundled Monaco map with its SRTM tile:
# median wall time of N builds with and without the stage (--sight.enabled 0), interleaved so
# that both see the same machine load, and the stage's own time from --json.
# Usage: scripts/bench-sight.sh [runs=5] [build-dir=build/release]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
runs=${1:-5}
build_dir=${2:-build/release}
tool="$build_dir/cli/roadcross-build"
[[ -x "$tool" ]] || { echo "build $tool first (cmake --build --preset release)" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
args=(--osm maps/monaco/monaco.osm.pbf --elevation maps/monaco/N43E007.hgt -o "$out/map.gpkg" --json)

machine_line
with=() without=() stage=()
for ((i = 0; i < runs; i++)); do
  "$tool" "${args[@]}" >"$out/with.json"
  with+=("$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["seconds"])' "$out/with.json")")
  stage+=("$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(sum(s["seconds"] for s in d["stages"] if s["stage"] in ("sight distance", "buildings and walls")))' "$out/with.json")")
  "$tool" "${args[@]}" --sight.enabled 0 >"$out/without.json"
  without+=("$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["seconds"])' "$out/without.json")")
done
w=$(median "${with[@]}") wo=$(median "${without[@]}") s=$(median "${stage[@]}")
printf 'build with the sight stage     %8.2f s (median of %d)\n' "$w" "$runs"
printf 'build without (--sight.enabled 0) %5.2f s\n' "$wo"
printf 'sight stages (obstacles + sight) %6.2f s\n' "$s"
printf 'ratio with / without           %8.2f\n' "$(echo "$w / $wo" | bc -l)"
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); [print("  " + s["stage"] + ": " + s["summary"]) for s in d["stages"] if s["stage"] in ("sight distance", "buildings and walls")]' "$out/with.json"
