#!/usr/bin/env bash
# The query subcommands and batch over a set of maps (--db repeated, or a directory): two
# hand-written maps on both sides of the border of UTM zones 33 and 34 (18 deg E) at 49.5 N.
# Expected distances from gdaltransform (see tests/preprocess/map_set_test.cpp, same roads):
#   (49.5001, 17.995): West Road (zone 33) 11.1121 m; (49.4999, 18.008): East Road (zone 34)
#   11.1335 m; (49.5, 18.0002), in zone 34: West Road's end 21.7349 m, East Road 202.86 m.
source "$(dirname "$0")/lib.sh"
road() {  # road FILE WAY_ID NAME LAT LON1 LON2
  cat >"$1" <<OSM
<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6" generator="hand">
  <node id="1" version="1" lat="$4" lon="$5"/>
  <node id="2" version="1" lat="$4" lon="$6"/>
  <way id="$2" version="1"><nd ref="1"/><nd ref="2"/><tag k="highway" v="residential"/><tag k="name" v="$3"/></way>
</osm>
OSM
}
road "$WORK/west.osm" 100 "West Road" 49.5 17.990 17.9999
road "$WORK/east.osm" 200 "East Road" 49.5 18.003 18.012
mkdir "$WORK/fleet"
"$ROADCROSS_BUILD" --osm "$WORK/west.osm" -o "$WORK/fleet/west.gpkg" -q
"$ROADCROSS_BUILD" --osm "$WORK/east.osm" -o "$WORK/fleet/east.gpkg" -q
W=$WORK/fleet/west.gpkg
E=$WORK/fleet/east.gpkg

"$ROADCROSS" nearest --db "$W" --db "$E" --lat 49.4999 --lon 18.008 --json >"$WORK/n.json"
[[ $(json_field "$WORK/n.json" map path) == "$E" && $(json_field "$WORK/n.json" osm_way_id) == 200 ]] &&
  near "$(json_field "$WORK/n.json" distance_m)" 11.1335 0.01 &&
  pass "nearest in zone 34 from East" || fail "nearest: $(cat "$WORK/n.json")"

"$ROADCROSS" assess --db "$WORK/fleet" --lat 49.5 --lon 18.0002 --json >"$WORK/a.json"
[[ $(json_field "$WORK/a.json" map path) == "$W" && $(json_field "$WORK/a.json" osm_way_id) == 100 ]] &&
  near "$(json_field "$WORK/a.json" distance_m)" 21.7349 0.01 &&
  pass "assess near the border from a directory: West (zone 33) is nearer" || fail "assess: $(cat "$WORK/a.json")"

"$ROADCROSS" heading --db "$E" --db "$W" --lat 49.5001 --lon 17.995 >"$WORK/h.txt"
grep -q "^map       $W" "$WORK/h.txt" && grep -q "West Road" "$WORK/h.txt" &&
  pass "heading text names the map" || fail "heading: $(cat "$WORK/h.txt")"

"$ROADCROSS" better --db "$W" --db "$E" --utm 283371.402976411 5487332.52222129 --utm-zone 34N --json >"$WORK/b.json"
[[ $(json_field "$WORK/b.json" map path) == "$E" ]] && pass "better with a zoned UTM position" ||
  fail "better: $(cat "$WORK/b.json")"

# One map: the answer as before, without a map member.
"$ROADCROSS" nearest --db "$W" --lat 49.5001 --lon 17.995 --json >"$WORK/one.json"
python3 -c 'import json,sys; sys.exit("map" in json.load(open(sys.argv[1])))' "$WORK/one.json" &&
  pass "one map: no map member" || fail "one map: $(cat "$WORK/one.json")"

expect_failure "a bare UTM position in a set" "--utm-zone" -- \
  "$ROADCROSS" nearest --db "$W" --db "$E" --utm 283371.4 5487332.5
expect_failure "a bad zone" "'99X' is not a UTM zone" -- \
  "$ROADCROSS" nearest --db "$W" --utm 283371.4 5487332.5 --utm-zone 99X

printf '%s\n' '{"op": "nearest", "lat": 49.4999, "lon": 18.008}' \
  '{"op": "assess", "easting": 717221.770812755, "northing": 5487367.26290318, "utm_zone": "33N"}' \
  '{"op": "nearest", "easting": 1, "northing": 2}' |
  "$ROADCROSS" batch --db "$WORK/fleet" >"$WORK/batch.jsonl" && status=0 || status=$?
python3 - "$WORK/batch.jsonl" "$W" "$E" <<'PY' && pass "batch over a directory" || fail "batch: $(cat "$WORK/batch.jsonl")"
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
assert lines[0]["ok"] and lines[0]["result"]["map"]["path"] == sys.argv[3], lines[0]
assert lines[1]["ok"] and lines[1]["result"]["map"]["path"] == sys.argv[2], lines[1]
assert abs(lines[1]["result"]["distance_m"] - 21.7349) < 0.01, lines[1]
assert not lines[2]["ok"] and "zone" in lines[2]["error"], lines[2]
PY
((status == 3)) && pass "batch exit 3 (one request failed)" || fail "batch exit $status"

# A directory with a file that is not a map: the error names it.
echo "not a map" >"$WORK/fleet/README.txt"
expect_failure "a non-map file in the directory" "$WORK/fleet/README.txt" -- \
  "$ROADCROSS" assess --db "$WORK/fleet" --lat 49.5 --lon 18.0002
expect_failure "monitor takes one map" "one map file" -- \
  "$ROADCROSS" monitor --db "$W" --db "$E" --lat 49.5 --lon 18.0 --at 1 2 --yaw 0
finish
