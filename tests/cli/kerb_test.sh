#!/usr/bin/env bash
# Kerbs, refuge islands and pavements end to end on tests/data/kerbs.osm (its comment describes
# the three roads): the DB columns read back with sqlite3, assess on both sides of a road with
# --max-kerb-height, a robot profile's default, gap's stages and simulate --island.
source "$(dirname "$0")/lib.sh"
OSM="$ROADCROSS_TEST_DATA_DIR/kerbs.osm"
PROFILES="$ROADCROSS_TEST_DATA_DIR/../../docs/profiles"
"$ROADCROSS_BUILD" --osm "$OSM" -o "$WORK/k.gpkg" -q
db() { sqlite3 "$WORK/k.gpkg" "$1"; }

[[ $(db "SELECT value FROM roadcross_metadata WHERE key = 'schema_version'") == 4 ]] &&
  pass "schema version 4" || fail "schema version"
# The crossing of way 10 (kerb nodes: lowered 3 cm, lowered but measured 12 cm, and the
# crossing node's lowered: the measured 0.12 m counts) and the flush kerb node of way 11; no
# other segment has any.
got=$(db "SELECT osm_way_id || '|' || kerb || '|' || kerb_height_m || '|' || ifnull(crossing_island, 'NULL') FROM segments WHERE kerb IS NOT NULL ORDER BY fid")
[[ $got == $'10|lowered|0.12|1\n11|flush|0.0|NULL' ]] && pass "kerb columns" || fail "kerb columns: $got"
[[ $(db "SELECT count(*) FROM segments WHERE kerb IS NULL AND (kerb_height_m IS NOT NULL OR crossing_island IS NOT NULL)") == 0 ]] ||
  fail "kerb facts without a kerb"
# Pavements: way 10 sidewalk=right; 11 a footway=sidewalk 4 m to its south (right); 12
# sidewalk=both + sidewalk:left=no.
got=$(db "SELECT osm_way_id || ':' || group_concat(DISTINCT ifnull(sidewalk_left, 'NULL') || '/' || ifnull(sidewalk_right, 'NULL')) FROM segments GROUP BY osm_way_id ORDER BY osm_way_id")
[[ $got == $'10:0/1\n11:NULL/1\n12:0/1' ]] && pass "sidewalk columns" || fail "sidewalk columns: $got"
[[ $(db "SELECT designated FROM crossings WHERE osm_id = 23") == 1 ]] && pass "tactile_paving crossing" ||
  fail "tactile_paving=yes is no designated crossing"

# assess at the crossing, 3.3 m north (left of the way, the far side has the pavement), every
# score good enough (--threshold -1000) so that only the robot rules decide.
north=(--db "$WORK/k.gpkg" --lat 50.00003 --lon 14.4 --threshold -1000)
"$ROADCROSS" assess "${north[@]}" --max-kerb-height 0.1 --json >"$WORK/low.json"
[[ $(json_field "$WORK/low.json" suitable) == False ]] && grep -q KERB_TOO_HIGH "$WORK/low.json" &&
  pass "0.12 m kerb, robot climbs 0.1 m: KERB_TOO_HIGH" || fail "kerb too high: $(cat "$WORK/low.json")"
"$ROADCROSS" assess "${north[@]}" --max-kerb-height 0.15 --json >"$WORK/ok.json"
[[ $(json_field "$WORK/ok.json" suitable) == True && $(json_field "$WORK/ok.json" pavement_far_side) == True &&
   $(json_field "$WORK/ok.json" robot_side) == 1 ]] &&
  pass "robot climbs 0.15 m: suitable" || fail "kerb ok: $(cat "$WORK/ok.json")"
"$ROADCROSS" assess "${north[@]}" --max-kerb-height 0.1 | grep -q "^kerb        lowered, 0.12 m high (robot climbs 0.1 m)   island yes   pavement far side yes" &&
  pass "assess prints the kerb line" || fail "assess text: $("$ROADCROSS" assess "${north[@]}" --max-kerb-height 0.1)"
expect_failure "negative kerb height" "max-kerb-height" -- "$ROADCROSS" assess "${north[@]}" --max-kerb-height -0.1
# South of it the far side (north, left) is tagged without a pavement.
"$ROADCROSS" assess --db "$WORK/k.gpkg" --lat 49.99997 --lon 14.4 --threshold -1000 --json >"$WORK/south.json"
[[ $(json_field "$WORK/south.json" suitable) == False && $(json_field "$WORK/south.json" pavement_far_side) == False ]] &&
  grep -q NO_PAVEMENT_FAR_SIDE "$WORK/south.json" && pass "south side: NO_PAVEMENT_FAR_SIDE" ||
  fail "south side: $(cat "$WORK/south.json")"

# A Husky profile: its 0.10 m is the map's default capability.
"$ROADCROSS_BUILD" --config "$PROFILES/husky.ini" --osm "$OSM" -o "$WORK/husky.gpkg" -q
[[ $(sqlite3 "$WORK/husky.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'param.suitability.max_kerb_height_m'") == 0.1 ]] &&
  "$ROADCROSS" assess --db "$WORK/husky.gpkg" --lat 50.00003 --lon 14.4 --threshold -1000 --json | grep -q KERB_TOO_HIGH &&
  pass "husky profile: KERB_TOO_HIGH by default" || fail "husky profile"

# gap at the island crossing: robot speed 1.2 m/s, start-up 1 s, radius 0.4 m, 6 m road (two
# 3 m lanes). From the kerb at distance d from the centreline, stage 1 leaves the near lane at
# 1 + (d + 0.4) / 1.2; from the island at d' (< 1.5 m = a quarter of the width), stage 2 leaves
# the far lane at 1 + (d' + 3 + 0.4) / 1.2.
: | "$ROADCROSS" gap --db "$WORK/k.gpkg" --lat 50.00003 --lon 14.4 --json >"$WORK/g1.json"
d=$(json_field "$WORK/ok.json" distance_m)
[[ $(json_field "$WORK/g1.json" stage) == 1 && $(json_field "$WORK/g1.json" refuge_island) == True ]] &&
  near "$(json_field "$WORK/g1.json" crossing_time_s)" "$(python3 -c "print(1 + ($d + 0.4) / 1.2)")" 1e-6 &&
  pass "gap at the kerb: stage 1 of 2" || fail "gap stage 1: $(cat "$WORK/g1.json")"
"$ROADCROSS" assess --db "$WORK/k.gpkg" --lat 50.00001 --lon 14.4 --json >"$WORK/island.json"
d2=$(json_field "$WORK/island.json" distance_m)
: | "$ROADCROSS" gap --db "$WORK/k.gpkg" --lat 50.00001 --lon 14.4 --json >"$WORK/g2.json"
[[ $(json_field "$WORK/g2.json" stage) == 2 ]] &&
  near "$(json_field "$WORK/g2.json" crossing_time_s)" "$(python3 -c "print(1 + ($d2 + 3.4) / 1.2)")" 1e-6 &&
  pass "gap on the island: stage 2 of 2" || fail "gap stage 2: $(cat "$WORK/g2.json")"
: | "$ROADCROSS" gap --db "$WORK/k.gpkg" --lat 50.00103 --lon 14.4 --json >"$WORK/g0.json"
[[ $(json_field "$WORK/g0.json" stage) == 0 ]] && pass "no island: one stage" || fail "gap stage 0"

# simulate on an empty synthetic road (7 m, 2 lanes): one stage walks 1 + 7.9 / 1.2 = 7.583 s;
# with --island (1 + 4 / 1.2) + (1 + 3.9 / 1.2) = 8.583 s.
sim=(simulate --volume 0 --runs 3 --policy ours --json)
"$ROADCROSS" "${sim[@]}" >"$WORK/s1.json"
"$ROADCROSS" "${sim[@]}" --island >"$WORK/s2.json"
python3 - "$WORK/s1.json" "$WORK/s2.json" <<'PY' && pass "simulate --island: two walks" || fail "simulate --island"
import json, sys
one, two = (json.load(open(p)) for p in sys.argv[1:])
assert not one["road"]["refuge_island"] and two["road"]["refuge_island"]
assert abs(one["rows"][0]["mean_crossing_s"] - (1 + 7.9 / 1.2)) < 1e-9, one
assert abs(two["rows"][0]["mean_crossing_s"] - (2 + 7.9 / 1.2)) < 1e-9, two
PY
finish
