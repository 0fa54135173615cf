#!/usr/bin/env bash
# The query subcommands end to end on a hand-made map whose answers are derived in
# tests/preprocess/assess_test.cpp (a quiet straight residential road at 50.0 N is suitable 3 m
# off it), and the batch mode's line protocol.
source "$(dirname "$0")/lib.sh"
cat >"$WORK/map.osm" <<'OSM'
<?xml version='1.0' encoding='UTF-8'?>
<osm version="0.6">
  <node id="1" version="1" lat="50.0" lon="14.40"/>
  <node id="2" version="1" lat="50.0" lon="14.4083"/>
  <way id="10" version="1"><nd ref="1"/><nd ref="2"/><tag k="highway" v="residential"/></way>
</osm>
OSM
"$ROADCROSS_BUILD" --osm "$WORK/map.osm" -o "$WORK/map.gpkg" -q
# 3 m north of the road's middle: 50.0 + 3 / 111 229 m per degree of latitude at 50 N.
lat=50.000027 lon=14.40415

"$ROADCROSS" assess --db "$WORK/map.gpkg" --lat $lat --lon $lon --json >"$WORK/a.json"
[[ $(json_field "$WORK/a.json" suitable) == True ]] && pass "assess: suitable" || fail "assess: not suitable"
near "$(json_field "$WORK/a.json" distance_m)" 3.0 0.1 || fail "assess: distance"
[[ $(json_field "$WORK/a.json" score) == 15 && $(json_field "$WORK/a.json" context_score) == 10 ]] || fail "assess: score/context"
"$ROADCROSS" assess --db "$WORK/map.gpkg" --lat $lat --lon $lon --threshold 26 --json >"$WORK/b.json"
[[ $(json_field "$WORK/b.json" suitable) == False ]] && pass "assess --threshold 26: not suitable" || fail "threshold override"
"$ROADCROSS" assess --db "$WORK/map.gpkg" --lat $lat --lon $lon | grep -q "^SUITABLE" || fail "assess text output"
# Position uncertainty: on the straight road's middle a 3 m sigma changes nothing (one road, all
# of it suitable: share 1, region radius 2.4477 x 3 = 7.343 m); sigma 0, a negative one and NaN
# are usage errors (non-zero exit, before the map is opened) that name the option.
"$ROADCROSS" assess --db "$WORK/map.gpkg" --lat $lat --lon $lon --sigma 3 --json >"$WORK/s.json"
python3 - "$WORK/s.json" <<'PY' && pass "assess --sigma 3: suitable over the region, share 1" || fail "assess --sigma"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["suitable"] and d["region"]["suitable_share"] == 1.0 and d["region"]["same_road"], d
assert abs(d["region"]["semi_major_m"] - 7.343) < 0.001, d["region"]
assert "POSITION_UNCERTAIN" not in d["reasons"] and "AMBIGUOUS_ROAD" not in d["reasons"], d
PY
"$ROADCROSS" assess --db "$WORK/map.gpkg" --lat $lat --lon $lon --sigma 3 | grep -q "^region .*100 % on suitable" \
  && pass "assess --sigma: text region line" || fail "assess --sigma text output"
for bad in 0 -1 nan inf; do
  status=0
  "$ROADCROSS" assess --db "$WORK/map.gpkg" --lat $lat --lon $lon --sigma=$bad >"$WORK/out" 2>"$WORK/err" || status=$?
  [[ $status != 0 ]] && grep -q -- "--sigma" "$WORK/err" && pass "--sigma $bad: usage error" || fail "--sigma $bad: exit $status $(cat "$WORK/err")"
done
status=0
"$ROADCROSS" assess --db "$WORK/map.gpkg" --lat $lat --lon $lon --sigma 1 --region-probability 1 >"$WORK/out" 2>"$WORK/err" || status=$?
[[ $status != 0 ]] && pass "--region-probability 1: usage error" || fail "--region-probability 1: exit $status"
"$ROADCROSS" heading --db "$WORK/map.gpkg" --lat $lat --lon $lon --sigma 3 --json >"$WORK/h.json"
python3 -c "import json,sys; d=json.load(open('$WORK/h.json')); sys.exit(0 if d['heading_spread_rad'] < 1e-6 else 1)" \
  && pass "heading --sigma: no spread on a straight road" || fail "heading --sigma"

"$ROADCROSS" better --db "$WORK/map.gpkg" --lat $lat --lon $lon --radius 50 --json >"$WORK/c.json"
python3 - "$WORK/c.json" <<'PY' && pass "better: candidates within 50 m, suitable, facing south" || fail "better"
import json, math, sys
d = json.load(open(sys.argv[1]))
c = d["candidates"]
assert c and all(x["walking_distance_m"] <= 50 and x["suitable"] for x in c), c
# North of an east-west road: cross southwards, about -pi/2.
assert all(abs(x["crossing_heading_rad"] + math.pi / 2) < 0.05 for x in c), c
PY

printf '%s\n' "{\"op\":\"assess\",\"lat\":$lat,\"lon\":$lon}" "" "{broken" "{\"op\":\"heading\",\"lat\":$lat,\"lon\":$lon}" \
  "{\"op\":\"nearest\",\"lat\":95,\"lon\":14}" \
  "{\"op\":\"assess\",\"lat\":$lat,\"lon\":$lon,\"sigma_m\":2}" \
  "{\"op\":\"assess\",\"lat\":$lat,\"lon\":$lon,\"sigma_m\":0}" \
  "{\"op\":\"assess\",\"lat\":$lat,\"lon\":$lon,\"covariance_enu_m2\":[4,0,1]}" >"$WORK/requests"
status=0
"$ROADCROSS" batch --db "$WORK/map.gpkg" <"$WORK/requests" >"$WORK/answers" || status=$?
[[ $status == 3 ]] && pass "batch exit 3 when some requests fail" || fail "batch exit $status"
python3 - "$WORK/answers" <<'PY' && pass "batch: one answer per request, numbered, errors per line" || fail "batch answers"
import json, sys, math
lines = [json.loads(l) for l in open(sys.argv[1])]
assert [l["line"] for l in lines] == [1, 3, 4, 5, 6, 7, 8], lines  # the blank line 2 is skipped
# sigma_m 2: region radius 2.4477 x 2; sigma_m 0: an error naming the uncertainty; an ENU
# covariance diag(4, 1): semi-axes 2.4477 x 2 and x 1.
assert lines[4]["ok"] and abs(lines[4]["result"]["region"]["semi_major_m"] - 4.8955) < 1e-3
assert not lines[5]["ok"] and "position uncertainty" in lines[5]["error"], lines[5]
r = lines[6]["result"]["region"]
assert abs(r["semi_major_m"] - 4.8955) < 1e-3 and abs(r["semi_minor_m"] - 2.4477) < 1e-3, r
assert lines[0]["ok"] and lines[0]["result"]["suitable"]
assert not lines[1]["ok"] and lines[1]["error"].startswith("line 3:")
assert lines[2]["ok"] and abs(lines[2]["result"]["crossing_heading_rad"] + math.pi / 2) < 0.05
assert not lines[3]["ok"] and "latitude 95" in lines[3]["error"]
PY
# monitor: the plan from 3 m north crosses southwards to 3.5 m south of the centreline (width
# 6 m by default): 6.5 m long. Halfway along it, facing south, the robot is on track at 50 %.
"$ROADCROSS" nearest --db "$WORK/map.gpkg" --lat $lat --lon $lon --json >"$WORK/n.json"
read -r qe qn <<<"$(python3 -c "import json; d=json.load(open('$WORK/n.json')); print(*d['query_utm_m'])")"
read -r ce cn <<<"$(python3 -c "import json; d=json.load(open('$WORK/n.json')); print(*d['closest_utm_m'])")"
read -r me mn <<<"$(python3 -c "
import math
qe, qn, ce, cn = $qe, $qn, $ce, $cn
d = math.hypot(ce - qe, cn - qn); ux, uy = (ce - qe) / d, (cn - qn) / d
L = d + 3.5
print(qe + ux * L / 2, qn + uy * L / 2)")"
"$ROADCROSS" monitor --db "$WORK/map.gpkg" --lat $lat --lon $lon --at "$me" "$mn" --yaw -1.5708 --json >"$WORK/m.json"
[[ $(json_field "$WORK/m.json" state) == ON_TRACK ]] || fail "monitor state $(cat "$WORK/m.json")"
near "$(json_field "$WORK/m.json" progress)" 0.5 0.01 && pass "monitor: halfway, on track" || fail "monitor progress"
"$ROADCROSS" monitor --db "$WORK/map.gpkg" --lat $lat --lon $lon --at "$me" "$(python3 -c "print($mn + 0)")" --yaw 0 --json >"$WORK/m2.json"
[[ $(json_field "$WORK/m2.json" state) == DRIFTING ]] && pass "monitor: facing east mid-crossing is DRIFTING" || fail "monitor drifting"
finish
