#!/usr/bin/env bash
# Golden test on the bundled Prague map: GDAL opens the output, the road network matches what
# independent tools (GDAL's OSM driver, osmium) read from the same file, and a known street's
# heading matches its OSM geometry.
source "$(dirname "$0")/lib.sh"
db="$WORK/prague.gpkg"
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$db" -q

# GDAL opens it as a GeoPackage with the segments layer in EPSG:32633.
ogrinfo -ro -so "$db" segments >"$WORK/ogrinfo" 2>&1 || fail "ogrinfo cannot open the output"
grep -q "using driver \`GPKG' successful" "$WORK/ogrinfo" || fail "not opened by the GPKG driver"
grep -q 'ID\["EPSG",32633\]' "$WORK/ogrinfo" || fail "layer CRS is not EPSG:32633"
ogr_count=$(sed -n 's/^Feature Count: //p' "$WORK/ogrinfo")
sql_count=$(sqlite3 "$db" "SELECT count(*) FROM segments")
[[ "$ogr_count" == "$sql_count" && "$sql_count" -gt 0 ]] && pass "feature count $ogr_count" ||
  fail "ogrinfo count $ogr_count vs sqlite $sql_count"
rtree_count=$(sqlite3 "$db" "SELECT count(*) FROM rtree_segments_geom")
[[ "$rtree_count" == "$sql_count" ]] || fail "R*Tree has $rtree_count entries for $sql_count segments"
[[ $(sqlite3 "$db" "SELECT rtreecheck('rtree_segments_geom')") == ok ]] || fail "rtreecheck"
[[ $(sqlite3 "$db" "PRAGMA integrity_check") == ok ]] || fail "integrity_check"

# The same road ways as osmium selects for the kept classes (653 in this file).
classes=motorway,motorway_link,trunk,trunk_link,primary,primary_link,secondary,secondary_link,tertiary,tertiary_link,unclassified,residential,service,busway,road,living_street
osmium tags-filter -R "$PRAGUE_OSM" "w/highway=$classes" -o "$WORK/roads.osm" --overwrite
osmium_ways=$(osmium fileinfo -e "$WORK/roads.osm" | sed -n 's/^ *Number of ways: //p')
db_ways=$(sqlite3 "$db" "SELECT count(DISTINCT osm_way_id) FROM segments")
[[ "$osmium_ways" == "$db_ways" && "$db_ways" == 653 ]] && pass "653 road ways" ||
  fail "osmium finds $osmium_ways road ways, the DB has $db_ways"

# Total length: GDAL's OSM driver + PROJ measure the same ways in EPSG:32633.
gdal_length=$(ogrinfo -q -ro -dialect SQLite -sql "SELECT sum(ST_Length(ST_Transform(geometry, 32633))) AS len FROM lines WHERE highway IN ('${classes//,/\',\'}')" "$PRAGUE_OSM" | sed -n 's/.*len (Real) = //p')
db_length=$(sqlite3 "$db" "SELECT sum(length_m) FROM segments")
near "$gdal_length" "$db_length" 0.01 && pass "total length $db_length m" ||
  fail "total length $db_length m, GDAL says $gdal_length m"
# No segment longer than the 10 m default.
[[ $(sqlite3 "$db" "SELECT count(*) FROM segments WHERE length_m > 10.000001") == 0 ]] || fail "segment over 10 m"

# Resslova (way 109248212) runs from node 25936560 (50.0757619, 14.4165932) west to node
# 21456616 (50.0756926, 14.4155482). A robot 5 m north of it must face across it, southwards:
# crossing yaw = road yaw + pi/2 for a westward road seen from its right-hand (north) side.
coords=$(printf '14.4165932 50.0757619\n14.4155482 50.0756926\n' |
  gdaltransform -s_srs EPSG:4326 -t_srs EPSG:32633 -output_xy | tr '\n' ' ')
read -r x1 y1 x2 y2 <<<"$coords"
expected=$(python3 -c "import math; r=math.atan2($y2-$y1,$x2-$x1); c=r+math.pi/2; print(math.atan2(math.sin(c),math.cos(c)))")
"$ROADCROSS" heading --db "$db" --lat 50.075769 --lon 14.416015 --json >"$WORK/heading.json"
[[ $(json_field "$WORK/heading.json" osm_way_id) == 109248212 ]] || fail "nearest way is not Resslova's 109248212"
[[ $(json_field "$WORK/heading.json" name) == Resslova ]] || fail "name is not Resslova"
near "$(json_field "$WORK/heading.json" distance_m)" 5.0 0.1 || fail "distance is not 5 m"
crossing=$(json_field "$WORK/heading.json" crossing_heading_rad)
near "$crossing" "$expected" 1e-6 && pass "Resslova crossing heading $crossing rad (expected $expected)" ||
  fail "crossing heading $crossing, expected $expected"
near "$crossing" -1.5708 0.2 || fail "crossing heading is not southwards"

# info --json: zone, EPSG, the input's SHA-256 as sha256sum computes it, the attribution.
"$ROADCROSS" info "$db" --json >"$WORK/info.json"
[[ $(json_field "$WORK/info.json" utm_zone) == 33 ]] || fail "zone"
[[ $(json_field "$WORK/info.json" epsg) == 32633 ]] || fail "epsg"
sha=$(sha256sum "$PRAGUE_OSM" | cut -d' ' -f1)
[[ $(json_field "$WORK/info.json" metadata input.0.sha256) == "$sha" ]] || fail "input sha256"
json_field "$WORK/info.json" metadata attribution | grep -q OpenStreetMap || fail "attribution"
finish
