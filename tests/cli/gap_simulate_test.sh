#!/usr/bin/env bash
# roadcross gap and roadcross simulate end to end on a hand-made map: a straight east-west
# residential road at 50.0 N, 6 m wide, 2 lanes, 50 km/h. The robot stands 5 m north of the
# centreline and crosses south. Vehicles are given in the robot's ENU frame (east_m, north_m),
# without speed uncertainty, 4 m long.
#
# Across the road (d = distance from the robot southwards): centreline d = 5, near edge 2,
# lane 0 = [2, 5] (centre north_m = -3.5), lane 1 = [5, 8] (centre -6.5). Robot 1 m/s, 1 s
# start-up, radius 0.5: lane 0 taken from 1 + 1.5 = 2.5 s to 1 + 5.5 = 6.5 s, lane 1 from 5.5 s
# to 9.5 s. Buffer 0.5 m: corridor half-width 1.0; a 4 m car is in it within 3 m of the line.
source "$(dirname "$0")/lib.sh"
cat >"$WORK/map.osm" <<'OSM'
<?xml version='1.0' encoding='UTF-8'?>
<osm version="0.6">
  <node id="1" version="1" lat="50.0" lon="14.40"/>
  <node id="2" version="1" lat="50.0" lon="14.4083"/>
  <way id="10" version="1"><nd ref="1"/><nd ref="2"/><tag k="highway" v="residential"/>
    <tag k="lanes" v="2"/><tag k="width" v="6"/><tag k="maxspeed" v="50"/></way>
</osm>
OSM
"$ROADCROSS_BUILD" --osm "$WORK/map.osm" -o "$WORK/map.gpkg" -q
# 5 m north of the road's middle: 5 / 111 013 m per degree of latitude (UTM distance 5.000 m).
place=(--db "$WORK/map.gpkg" --lat 50.00004504 --lon 14.40415)
robot=(--speed 1 --startup 1 --radius 0.5 --min-pet 1 --buffer 0.5)
# Lane 0, 80 m east, driving west at 10 m/s: in the corridor from (80 - 3) / 10 = 7.7 s to 8.3 s;
# PET 7.7 - 6.5 = 1.2 s >= 1 -> GO. Unseen car: 50 / 3.6 * 1.2 = 16.667 m/s needs
# 16.667 * (9.5 + 1) + 1 = 176 m of sight (200 m sensor range).
car0='{"east_m": 80, "north_m": -3.5, "vx_mps": -10, "vy_mps": 0, "length_m": 4, "speed_uncertainty_mps": 0}'
echo "$car0" | "$ROADCROSS" gap "${place[@]}" "${robot[@]}" --json >"$WORK/go.json"
[[ $(json_field "$WORK/go.json" decision) == GO ]] && pass "gap: GO" || fail "gap: $(cat "$WORK/go.json")"
near "$(json_field "$WORK/go.json" margin_s)" 1.2 0.01 || fail "gap: margin $(json_field "$WORK/go.json" margin_s)"
near "$(json_field "$WORK/go.json" required_sight_m)" 176.0 0.1 || fail "gap: required sight"
[[ $(json_field "$WORK/go.json" limiting_line) == 1 && $(json_field "$WORK/go.json" lanes) == 2 ]] || fail "gap: limiting line / lanes"

# Plus lane 1, 60 m west, driving east: in 5.7 s .. 6.3 s while the robot is in lane 1 from 5.5 s:
# PET max(5.7 - 9.5, 5.5 - 6.3) = -0.8 -> WAIT. Forbidden starts: (5.7-1-9.5, 6.3+1-5.5) =
# (-4.8, 1.8) and for car 0 (7.7-1-6.5, 8.3+1-2.5) = (0.2, 6.8): earliest GO in 6.8 s.
car1='{"east_m": -60, "north_m": -6.5, "vx_mps": 10, "vy_mps": 0, "length_m": 4, "speed_uncertainty_mps": 0}'
printf '%s\n\n%s\n' "$car0" "$car1" | "$ROADCROSS" gap "${place[@]}" "${robot[@]}" --json >"$WORK/wait.json"
[[ $(json_field "$WORK/wait.json" decision) == WAIT && $(json_field "$WORK/wait.json" reason) == VEHICLE_CONFLICT ]] &&
  pass "gap: WAIT for the far-lane car" || fail "gap: $(cat "$WORK/wait.json")"
near "$(json_field "$WORK/wait.json" margin_s)" -0.8 0.01 || fail "gap: margin"
near "$(json_field "$WORK/wait.json" earliest_start_in_s)" 6.8 0.01 || fail "gap: earliest start"
[[ $(json_field "$WORK/wait.json" limiting_line) == 3 ]] || fail "gap: limiting line (blank line 2 skipped)"
printf '%s\n%s\n' "$car0" "$car1" | "$ROADCROSS" gap "${place[@]}" "${robot[@]}" | grep -q "^WAIT  VEHICLE_CONFLICT" ||
  fail "gap: text output"

# HCM: t_c = 6 / 1 + 3 = 9 s; car 0 arrives in 7.7 s -> WAIT until it has left at 8.3 s.
echo "$car0" | "$ROADCROSS" gap "${place[@]}" "${robot[@]}" --policy hcm --json >"$WORK/hcm.json"
[[ $(json_field "$WORK/hcm.json" reason) == GAP_TOO_SHORT ]] && pass "gap --policy hcm: WAIT" || fail "hcm"
near "$(json_field "$WORK/hcm.json" critical_gap_s)" 9.0 1e-9 || fail "hcm: t_c"
near "$(json_field "$WORK/hcm.json" earliest_start_in_s)" 8.3 0.01 || fail "hcm: earliest"

# A sensor range of 150 m < 176 m: WAIT, the road is not seen far enough.
"$ROADCROSS" gap "${place[@]}" "${robot[@]}" --sensor-range 150 --json </dev/null >"$WORK/sight.json"
[[ $(json_field "$WORK/sight.json" reason) == INSUFFICIENT_SIGHT ]] && pass "gap: insufficient sight" || fail "sight"

expect_failure "gap: negative age" "future" -- \
  bash -c "echo '{\"east_m\": 80, \"north_m\": -3.5, \"vx_mps\": -10, \"vy_mps\": 0, \"age_s\": -1}' | \"$ROADCROSS\" gap ${place[*]}"
expect_failure "gap: velocity not a number" "stdin line 1" "vx_mps" -- \
  bash -c "echo '{\"east_m\": 80, \"north_m\": -3.5, \"vx_mps\": \"fast\", \"vy_mps\": 0}' | \"$ROADCROSS\" gap ${place[*]}"
expect_failure "gap: broken JSON" "stdin line 1" -- bash -c "echo '{broken' | \"$ROADCROSS\" gap ${place[*]}"
expect_failure "gap: negative speed" "speed" -- bash -c "\"$ROADCROSS\" gap ${place[*]} --speed -1 </dev/null"

# simulate: the DB's road (2 lanes, 6 m, 50 km/h; straight, no junction: sight = sensor range),
# and the same seed gives the same bytes.
sim=(simulate "${place[@]}" --runs 20 --volume 300 --policy ours,naive --naive-distance 30 --json)
"$ROADCROSS" "${sim[@]}" --seed 5 >"$WORK/s1.json"
"$ROADCROSS" "${sim[@]}" --seed 5 >"$WORK/s2.json"
"$ROADCROSS" "${sim[@]}" --seed 6 >"$WORK/s3.json"
cmp -s "$WORK/s1.json" "$WORK/s2.json" && pass "simulate: same seed, same output" || fail "simulate: not deterministic"
cmp -s "$WORK/s1.json" "$WORK/s3.json" && fail "simulate: the seed changes nothing" || pass "simulate: seed matters"
python3 - "$WORK/s1.json" <<'PY' && pass "simulate: road from the DB, ours safe" || fail "simulate: $(cat "$WORK/s1.json")"
import json, sys
d = json.load(open(sys.argv[1]))
road = {k: d["road"][k] for k in ("lanes", "width_m", "maxspeed_kmh", "sight_m")}
assert road == {"lanes": 2, "width_m": 6.0, "maxspeed_kmh": 50.0, "sight_m": 200.0}, d["road"]
rows = {r["policy"]: r for r in d["rows"]}
assert set(rows) == {"ours", "naive30"}, rows
assert rows["ours"]["runs"] == 20 and rows["ours"]["collisions"] == 0, rows["ours"]
PY
# --per-run: one line per run, with the summary's seeds: the per-run counts add up to it.
"$ROADCROSS" "${sim[@]}" --seed 5 --per-run >"$WORK/runs.jsonl"
python3 - "$WORK/s1.json" "$WORK/runs.jsonl" <<'PY' && pass "simulate --per-run adds up to the summary" || fail "per-run"
import json, sys
summary = {r["policy"]: r for r in json.load(open(sys.argv[1]))["rows"]}
runs = [json.loads(line) for line in open(sys.argv[2])]
assert len(runs) == 40, len(runs)
for policy, row in summary.items():
    mine = [r for r in runs if r["policy"] == policy]
    assert len(mine) == 20, policy
    for key, field in (("collisions", "collision"), ("conflicts", "conflict"), ("crossed", "crossed")):
        assert sum(r[field] for r in mine) == row[key], (policy, key)
    assert abs(sum(r["waiting_s"] for r in mine) / 20 - row["mean_wait_s"]) < 1e-9, policy
PY
"$ROADCROSS" simulate --lanes 1 --width 3.5 --runs 3 --volume 0 --policy ours | grep -q "^ours" &&
  pass "simulate: synthetic road, table" || fail "simulate: table"

# Issue 11 item 3: the gap decision takes the DB's sight distance. The same road with a 2 m wall
# built across it 0.0014 deg (100 m) east of the robot: the build's sight stage stops the view
# there (forward sight ~95-100 m from the segment's midpoint), the sensor range (200 m) does
# not matter any more, and 176 m are needed -> WAIT, INSUFFICIENT_SIGHT, with no vehicle at all.
sed 's#</osm>#  <node id="3" version="1" lat="49.9999" lon="14.40555"/>\
  <node id="4" version="1" lat="50.0001" lon="14.40555"/>\
  <way id="20" version="1"><nd ref="3"/><nd ref="4"/><tag k="barrier" v="wall"/></way>\
</osm>#' "$WORK/map.osm" >"$WORK/wall.osm"
"$ROADCROSS_BUILD" --osm "$WORK/wall.osm" -o "$WORK/wall.gpkg" -q
wall=(--db "$WORK/wall.gpkg" --lat 50.00004504 --lon 14.40415)
"$ROADCROSS" assess "${wall[@]}" --json >"$WORK/wall_assess.json"
sight_min=$(json_field "$WORK/wall_assess.json" sight_min_m)
python3 -c "import sys; s = float(sys.argv[1]); assert 90 <= s <= 101, s" "$sight_min" ||
  fail "wall: sight_min_m $sight_min, expected 90..101 m"
"$ROADCROSS" gap "${wall[@]}" "${robot[@]}" --json </dev/null >"$WORK/wall_gap.json"
[[ $(json_field "$WORK/wall_gap.json" reason) == INSUFFICIENT_SIGHT ]] &&
  pass "gap: the DB's sight distance (wall) means WAIT" || fail "wall gap: $(cat "$WORK/wall_gap.json")"
near "$(json_field "$WORK/wall_gap.json" visible_road_m)" "$sight_min" 1e-9 || fail "wall gap: visible road"
near "$(json_field "$WORK/go.json" visible_road_m)" 200 1e-9 || fail "open road: visible road is the sensor range"
# margin = (visible - 1) / 16.667 - crossing time (9.5 s; negative: the hidden car would hit)
crossing_s=$(json_field "$WORK/wall_gap.json" crossing_time_s)
near "$crossing_s" 9.5 0.01 || fail "wall gap: crossing time $crossing_s"
near "$(json_field "$WORK/wall_gap.json" margin_s)" \
  "$(python3 -c "print(($sight_min - 1) / (50 / 3.6 * 1.2) - $crossing_s)")" 1e-6 || fail "wall gap: margin"
"$ROADCROSS" simulate "${wall[@]}" --runs 2 --json >"$WORK/wall_sim.json"
near "$(json_field "$WORK/wall_sim.json" road sight_m)" "$sight_min" 1e-9 || fail "simulate: road sight from the DB"
expect_failure "simulate: --db without a place" "needs a place" -- "$ROADCROSS" simulate --db "$WORK/map.gpkg"
finish
