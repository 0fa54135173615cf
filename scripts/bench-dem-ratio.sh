#!/usr/bin/env bash
# Issue 8's DEM target in one run: the build with a raster DEM against the build without
# elevation (both --sight.enabled 0), for an old and a new binary, run round-robin (old no-DEM,
# old DEM, new no-DEM, new DEM, then again) so that all four see the same load. Prints, per
# binary, the median seconds of both builds, their ratio and the median seconds of the stages
# that differ (terrain, writing, terrain grid). Each output is deleted as soon as it is measured
# and the page cache synced before each build: a build must not pay for writing back the
# previous one's gigabytes.
# Usage: scripts/bench-dem-ratio.sh OLD_BINARY NEW_BINARY INPUT.osm.pbf DEM.tif [runs=3]
# e.g. scripts/bench-dem-ratio.sh /tmp/old-roadcross-build build/release/cli/roadcross-build \
#        /tmp/scale/m50.osm.pbf /tmp/scale/m50.tif 3      (tiled inputs: scripts/bench-scale.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
[[ $# -ge 4 ]] || { sed -n 2,11p "$0" >&2; exit 2; }
old=$1 new=$2 input=$3 dem=$4 runs=${5:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "# $(machine_line)"
for ((i = 0; i < runs; i++)); do
  for side in old new; do
    binary=$old; [[ $side == new ]] && binary=$new
    for mode in plain dem; do
      args=(); [[ $mode == dem ]] && args=(--elevation "$dem")
      sync
      "$binary" --osm "$input" "${args[@]}" -o "$work/out.gpkg" --sight.enabled 0 --json \
        >"$work/$side.$mode.$i.json"
      rm -f "$work/out.gpkg"
    done
  done
done
echo "# load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
python3 - "$work" "$runs" <<'PY'
import json, sys
work, runs = sys.argv[1], int(sys.argv[2])
def low_median(values):
    values = sorted(values)
    return values[(len(values) - 1) // 2]
def stage(d, name):
    return sum(s["seconds"] for s in d["stages"] if s["stage"] == name)
for side in ("old", "new"):
    runs_of = {m: [json.load(open(f"{work}/{side}.{m}.{i}.json")) for i in range(runs)]
               for m in ("plain", "dem")}
    plain = low_median([d["seconds"] for d in runs_of["plain"]])
    dem = low_median([d["seconds"] for d in runs_of["dem"]])
    ratios = [d["seconds"] / p["seconds"] for d, p in zip(runs_of["dem"], runs_of["plain"])]
    parts = [f"{name} {low_median([stage(d, name) for d in runs_of[mode]]):.2f}"
             for mode, name in (("dem", "terrain"), ("plain", "writing the GeoPackage"),
                                ("dem", "writing the GeoPackage"),
                                ("dem", "writing the terrain grid"))]
    peak = max(d["peak_rss_mib"] for d in runs_of["dem"])
    print(f"{side}: no DEM {plain:.2f} s, DEM {dem:.2f} s, ratio of medians {dem / plain:.2f} "
          f"(per round: {', '.join(f'{r:.2f}' for r in ratios)}); DEM peak {peak:.0f} MiB; "
          f"DEM terrain, no-DEM writing, DEM writing, DEM terrain grid: " + "; ".join(parts))
PY
