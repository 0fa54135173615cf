#!/usr/bin/env bash
# Golden test: a gentle curve of a rural road drawn with sparse vertices keeps its radius.
# North of Bayreuth, way 14178471 (tertiary KU 11, traced from aerial images with vertices
# 15-130 m apart) bends at node 21606005 between nodes 347309470 and 2192060357, each about
# 30 m away. Both arms are between the 10 m baseline and the 50 m maximum arm, so the radius
# there is the circumradius of exactly these three OSM nodes, computed here with osmium,
# GDAL/PROJ and python, not with roadcross: about 122 m, curvature level 2 (90..150 m), not a
# sharp bend. (Resampling to 20 m before measuring, as the thesis did, halved it to 61 m.)
source "$(dirname "$0")/lib.sh"
bayreuth="$ROADCROSS_MAPS_DIR/bayreuth/north-bayreuth.osm.gz"
"$ROADCROSS_BUILD" --osm "$bayreuth" -o "$WORK/bayreuth.gpkg" -q

node_lonlat() { osmium getid "$1" "n$2" -f opl -o - 2>/dev/null | awk '{for (i=1;i<=NF;i++) {if ($i ~ /^x/) x=substr($i,2); if ($i ~ /^y/) y=substr($i,2)}} END {print x, y}'; }

parents=$(osmium getparents "$bayreuth" n21606005 -f opl 2>/dev/null | awk '{print $1}' | tr '\n' ' ')
[[ "$parents" == "w14178471 " ]] || fail "node 21606005 is not on way 14178471 alone: $parents"

pts=""
for n in 347309470 21606005 2192060357; do pts+="$(node_lonlat "$bayreuth" $n)"$'\n'; done
read -r arm_a arm_b expected_radius expected_level <<<"$(printf '%s' "$pts" |
  gdaltransform -s_srs EPSG:4326 -t_srs EPSG:32632 -output_xy | python3 -c '
import math, sys
p = [tuple(map(float, l.split())) for l in sys.stdin if l.strip()]
a, b, c = math.dist(p[0], p[1]), math.dist(p[1], p[2]), math.dist(p[0], p[2])
s = (a + b + c) / 2
r = a * b * c / (4 * math.sqrt(s * (s - a) * (s - b) * (s - c)))
level = next((lv for lv, limit in ((4, 40), (3, 90), (2, 150), (1, 220)) if r < limit), 0)
print(a, b, r, level)')"
python3 -c "import sys; sys.exit(0 if 10 <= $arm_a <= 50 and 10 <= $arm_b <= 50 else 1)" ||
  fail "arms $arm_a m, $arm_b m are not within the 10..50 m the test relies on"

read -r lon lat <<<"$(node_lonlat "$bayreuth" 21606005)"
"$ROADCROSS" nearest --db "$WORK/bayreuth.gpkg" --lat "$lat" --lon "$lon" --json >"$WORK/nearest.json"
seg=$(json_field "$WORK/nearest.json" segment_id)
row=$(sqlite3 -separator ' ' "$WORK/bayreuth.gpkg" \
  "SELECT osm_way_id, radius_m, curvature_level, coalesce(reasons, '') FROM segments WHERE fid = $seg")
read -r way radius level reasons <<<"$row"
[[ $way == 14178471 ]] || fail "nearest segment is on way $way"
near "$radius" "$expected_radius" "$(python3 -c "print(0.02 * $expected_radius)")" &&
  pass "radius $radius m at node 21606005 (its nodes say $expected_radius m)" ||
  fail "radius $radius m, the three nodes say $expected_radius m"
[[ $level == "$expected_level" ]] || fail "curvature level $level, expected $expected_level"
[[ $reasons != *SHARP_BEND* ]] || fail "a $expected_radius m curve is flagged SHARP_BEND"
finish
