#!/usr/bin/env bash
# DEM build vs no-DEM build (both --sight.enabled 0), old vs new binary, on tiled inputs: the
# four builds run alternately, RUNS times; prints a Markdown table of the median seconds of the
# whole build and of the terrain stages, and the DEM / no-DEM ratio of each binary (issue 8:
# the terrain cell size that follows the DEM).
# Usage: scripts/bench-cell-size.sh OLD_BINARY NEW_BINARY RUNS INPUT.osm.pbf...
#   (the DEM of X.osm.pbf is X.tif, as tests/benchmarks/make_tiled_osm writes it)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
[[ $# -ge 4 ]] || { sed -n 2,7p "$0" >&2; exit 2; }
old=$1 new=$2 runs=$3
shift 3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "# $(machine_line)"
echo "| input | no DEM old | no DEM new | DEM old (terrain + grid write) | DEM new (terrain + grid write) | DEM / no DEM old | DEM / no DEM new | cell new |"
echo "|---|---|---|---|---|---|---|---|"
for input in "$@"; do
  dem=${input%.osm.pbf}.tif
  for ((i = 0; i < runs; i++)); do
    for side in old new; do
      binary=$old; [[ $side == new ]] && binary=$new
      "$binary" --osm "$input" -o "$work/out.gpkg" --json --sight.enabled 0 >"$work/$side.plain.$i.json"
      "$binary" --osm "$input" -o "$work/out.gpkg" --json --sight.enabled 0 --elevation "$dem" \
        >"$work/$side.dem.$i.json"
    done
  done
  python3 - "$work" "$runs" "$(basename "$input")" <<'PY'
import json, sys
work, runs, name = sys.argv[1], int(sys.argv[2]), sys.argv[3]
def med(v):
    v = sorted(v)
    return v[(len(v) - 1) // 2]
def load(side, kind):
    return [json.load(open(f"{work}/{side}.{kind}.{i}.json")) for i in range(runs)]
def stage(d, prefix):
    return sum(s["seconds"] for s in d["stages"] if s["stage"].startswith(prefix))
cells = {}
row = [name]
for side in ("old", "new"):
    row.append(f"{med([d['seconds'] for d in load(side, 'plain')]):.2f}")
for side in ("old", "new"):
    ds = load(side, "dem")
    row.append(f"{med([d['seconds'] for d in ds]):.2f} ({med([stage(d, 'terrain') for d in ds]):.2f} + "
               f"{med([stage(d, 'writing the terrain grid') for d in ds]):.2f})")
    cells[side] = ds[0]["terrain"]["cell_m"]
for side in ("old", "new"):
    plain = med([d["seconds"] for d in load(side, "plain")])
    dem = med([d["seconds"] for d in load(side, "dem")])
    row.append(f"{dem / plain:.2f}")
row.append(f"{cells['new']:g} m (old {cells['old']:g} m)")
print("| " + " | ".join(row) + " |")
PY
done
echo "# load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
