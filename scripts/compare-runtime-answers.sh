#!/usr/bin/env bash
# Compares the answers of two roadcross binaries (e.g. before and after a change to the runtime)
# on the same map: assess exact and under ten position uncertainties (circular sigmas and ENU
# covariances along and across, with two option sets), heading and better_place, at COUNT random
# positions of the map's extent (fixed seed), through `roadcross batch`. Prints the number of
# requests and of differing answers, and the first differences; exit 1 when any differ.
# Usage: scripts/compare-runtime-answers.sh OLD_BINARY NEW_BINARY [MAP=maps' Prague build] [COUNT=3000]
set -euo pipefail
old=$1 new=$2
map=${3:-/tmp/roadcross-bench-prague.gpkg}
count=${4:-3000}
[[ -f "$map" ]] || { echo "$map: no such map (build it: roadcross-build --osm maps/prague/... -o $map)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$new" info --db "$map" --json >"$work/info.json"
python3 - "$work/info.json" "$count" >"$work/requests.jsonl" <<'PY'
import json, random, sys
extent = json.load(open(sys.argv[1]))["extent_utm_m"]
count = int(sys.argv[2])
random.seed(30)
uncertainties = [{}, {"sigma_m": 0.5}, {"sigma_m": 1}, {"sigma_m": 2}, {"sigma_m": 3},
                 {"sigma_m": 4}, {"sigma_m": 6}, {"sigma_m": 10},
                 {"covariance_enu_m2": [16, 0, 1]}, {"covariance_enu_m2": [1, 0, 16]},
                 {"covariance_enu_m2": [9, 6, 9], "region_probability": 0.5}]
options = [{}, {"threshold": 12, "valid_distance_m": 10}]
for i in range(count):
    e = random.uniform(extent[0], extent[2])
    n = random.uniform(extent[1], extent[3])
    where = {"easting": round(e, 3), "northing": round(n, 3)}
    for u in uncertainties:
        for o in options:
            print(json.dumps({"op": "assess", **where, **u, **o}))
    if i % 10 == 0:
        for u in ({}, {"sigma_m": 3}):
            print(json.dumps({"op": "heading", **where, **u}))
            print(json.dumps({"op": "better", **where, "radius_m": 60, **u}))
PY
"$old" batch --db "$map" <"$work/requests.jsonl" >"$work/old.jsonl" || true
"$new" batch --db "$map" <"$work/requests.jsonl" >"$work/new.jsonl" || true
python3 - "$work/requests.jsonl" "$work/old.jsonl" "$work/new.jsonl" <<'PY'
import sys
requests = open(sys.argv[1]).read().splitlines()
old = open(sys.argv[2]).read().splitlines()
new = open(sys.argv[3]).read().splitlines()
if len(old) != len(requests) or len(new) != len(requests):
    sys.exit(f"answers: {len(old)} old, {len(new)} new for {len(requests)} requests")
differ = [i for i in range(len(requests)) if old[i] != new[i]]
print(f"{len(requests)} requests, {len(differ)} answers differ")
for i in differ[:5]:
    print(f"request {requests[i]}\n  old {old[i][:600]}\n  new {new[i][:600]}")
sys.exit(1 if differ else 0)
PY
