#!/usr/bin/env bash
# Same-run A/B of two roadcross-build binaries on one input: runs them alternately (A B A B ...)
# and prints, for each, the median seconds of every stage (--json), of the whole build and the
# largest peak RSS, plus `osmium tags-filter FILE w/highway` in the same run for the ratio.
# Usage: scripts/bench-ab.sh OLD_BINARY NEW_BINARY INPUT.osm.pbf [runs=3] [build arguments...]
# e.g. scripts/bench-ab.sh /tmp/old-roadcross-build build/release/cli/roadcross-build \
#        /tmp/m50.osm.pbf 3 --sight.enabled 0       (a tiled input: tests/benchmarks/make_tiled_osm)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
[[ $# -ge 3 ]] || { sed -n 2,7p "$0" >&2; exit 2; }
old=$1 new=$2 input=$3 runs=${4:-3}
shift $(($# < 4 ? $# : 4))
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "# $(machine_line)"
osmium_times=()
for ((i = 0; i < runs; i++)); do
  /usr/bin/time -f '%e' -o "$work/time" osmium tags-filter "$input" w/highway -o "$work/f.osm.pbf" --overwrite
  osmium_times+=("$(cat "$work/time")")
  for side in A B; do
    binary=$old; [[ $side == B ]] && binary=$new
    "$binary" --osm "$input" -o "$work/out.gpkg" --json "$@" >"$work/$side.$i.json"
  done
done
osmium_s=$(median "${osmium_times[@]}")
echo "# osmium tags-filter w/highway: median $osmium_s s"
python3 - "$work" "$runs" "$osmium_s" <<'PY'
import json, statistics, sys
work, runs, osmium = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
def low_median(values):
    values = sorted(values)
    return values[(len(values) - 1) // 2]
for side in "AB":
    runs_json = [json.load(open(f"{work}/{side}.{i}.json")) for i in range(runs)]
    stages = {}
    for d in runs_json:
        for s in d["stages"]:
            stages.setdefault(s["stage"], []).append(s["seconds"])
    total = low_median([d["seconds"] for d in runs_json])
    peak = max(d["peak_rss_mib"] for d in runs_json)
    print(f"{side}: build {total:.2f} s (÷ osmium {total / osmium:.2f}), peak {peak:.0f} MiB; " +
          "; ".join(f"{name} {low_median(v):.2f}" for name, v in stages.items()))
PY
