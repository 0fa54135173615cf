#!/usr/bin/env bash
# Golden test of the geometry cost on three real places, each checked against what the raw OSM
# geometry says (computed here with osmium, GDAL/PROJ and python, not with roadcross):
#  1. Monaco, the Fairmont hairpin on Avenue des Spelugues (way 4230007): the circumradius of
#     its nodes 1720684398, 1720684322, 1720684310 is about 17.6 m -> a sharp bend.
#  2. Monaco, node 21914666 where way 156242239 meets the interior of way 4230007: a junction.
#  3. North of Bayreuth, the unclassified road of way 24157024 near 50.04213 N 11.57979 E:
#     straight for more than 100 m each way and over 600 m from any junction.
source "$(dirname "$0")/lib.sh"
monaco="$ROADCROSS_MAPS_DIR/monaco/monaco.osm.pbf"
bayreuth="$ROADCROSS_MAPS_DIR/bayreuth/north-bayreuth.osm.gz"
"$ROADCROSS_BUILD" --osm "$monaco" -o "$WORK/monaco.gpkg" -q
"$ROADCROSS_BUILD" --osm "$bayreuth" -o "$WORK/bayreuth.gpkg" -q

# segment_at DB LAT LON: id of the segment nearest to a position.
segment_at() {
  "$ROADCROSS" nearest --db "$1" --lat "$2" --lon "$3" --json >"$WORK/nearest.json"
  json_field "$WORK/nearest.json" segment_id
}
column() { sqlite3 "$1" "SELECT $3 FROM segments WHERE fid = $2"; }
node_lonlat() { osmium getid "$1" "n$2" -f opl -o - 2>/dev/null | awk '{for (i=1;i<=NF;i++) {if ($i ~ /^x/) x=substr($i,2); if ($i ~ /^y/) y=substr($i,2)}} END {print x, y}'; }

# 1. The hairpin: independent circumradius of three of its nodes.
pts=""
for n in 1720684398 1720684322 1720684310; do pts+="$(node_lonlat "$monaco" $n)"$'\n'; done
expected_radius=$(printf '%s' "$pts" | gdaltransform -s_srs EPSG:4326 -t_srs EPSG:32632 -output_xy | python3 -c '
import math, sys
p = [tuple(map(float, l.split())) for l in sys.stdin if l.strip()]
a, b, c = math.dist(p[0], p[1]), math.dist(p[1], p[2]), math.dist(p[0], p[2])
s = (a + b + c) / 2
print(a * b * c / (4 * math.sqrt(s * (s - a) * (s - b) * (s - c))))')
read -r lon lat <<<"$(node_lonlat "$monaco" 1720684322)"
seg=$(segment_at "$WORK/monaco.gpkg" "$lat" "$lon")
radius=$(column "$WORK/monaco.gpkg" "$seg" radius_m)
near "$radius" "$expected_radius" "$(python3 -c "print(0.15 * $expected_radius)")" &&
  pass "hairpin radius $radius m (nodes say $expected_radius m)" || fail "hairpin radius $radius, expected $expected_radius"
[[ $(column "$WORK/monaco.gpkg" "$seg" curvature_level) -ge 4 ]] || fail "hairpin curvature level < 4"
column "$WORK/monaco.gpkg" "$seg" reasons | grep -q SHARP_BEND || fail "hairpin lacks SHARP_BEND"
[[ $(column "$WORK/monaco.gpkg" "$seg" curvature_cost) -ge 10 ]] || fail "hairpin curvature cost < 10"

# 2. The junction: node 21914666 is in way 4230007 (not at its ends) and in way 156242239.
parents=$(osmium getparents "$monaco" n21914666 -f opl 2>/dev/null | awk '{print $1}' | sort | tr '\n' ' ')
[[ "$parents" == *w156242239* && "$parents" == *w4230007* ]] || fail "node 21914666 parents: $parents"
read -r lon lat <<<"$(node_lonlat "$monaco" 21914666)"
seg=$(segment_at "$WORK/monaco.gpkg" "$lat" "$lon")
jd=$(column "$WORK/monaco.gpkg" "$seg" junction_distance_m)
python3 -c "import sys; sys.exit(0 if $jd <= 5.0 else 1)" && pass "junction distance $jd m" || fail "junction distance $jd > 5 m"
[[ $(column "$WORK/monaco.gpkg" "$seg" curvature_level) == 5 ]] || fail "junction segment not level 5"
column "$WORK/monaco.gpkg" "$seg" reasons | grep -q NEAR_JUNCTION || fail "junction lacks NEAR_JUNCTION"

# 3. The straight: every road vertex within 110 m of the point (read with GDAL's OSM driver,
#    whichever ways they belong to) lies within 1 m of one straight line.
ogr2ogr -q --config CPL_VSIL_GZIP_WRITE_PROPERTIES NO -f CSV "$WORK/near.csv" "/vsigzip/$bayreuth" lines -spat 11.5776 50.0409 11.5820 50.0433 \
  -where "highway IS NOT NULL" -lco GEOMETRY=AS_WKT -select highway 2>/dev/null
deviation=$(python3 - "$WORK/near.csv" <<'PY' | gdaltransform -s_srs EPSG:4326 -t_srs EPSG:32632 -output_xy | python3 -c '
import math, sys
p = [tuple(map(float, l.split())) for l in sys.stdin if l.strip()]
here, pts = p[0], [q for q in p[1:] if math.dist(q, p[0]) < 110]
assert len(pts) >= 2, "fewer than two road vertices near the point"
a, b = max(((u, v) for u in pts for v in pts), key=lambda uv: math.dist(*uv))
dx, dy = b[0] - a[0], b[1] - a[1]
print(max(abs((q[0] - a[0]) * dy - (q[1] - a[1]) * dx) / math.hypot(dx, dy) for q in pts + [here]))'
import csv, re, sys
print("11.5797930 50.0421268")
for row in csv.DictReader(open(sys.argv[1])):
    for x, y in re.findall(r"([-\d.]+) ([-\d.]+)", row["WKT"]):
        print(x, y)
PY
)
python3 -c "import sys; sys.exit(0 if $deviation < 1.0 else 1)" || fail "the test stretch is not straight ($deviation m)"
seg=$(segment_at "$WORK/bayreuth.gpkg" 50.0421268 11.5797930)
[[ $(column "$WORK/bayreuth.gpkg" "$seg" osm_way_id) == 24157024 ]] || fail "nearest way is not 24157024"
[[ $(column "$WORK/bayreuth.gpkg" "$seg" "CAST(radius_m AS INTEGER)") == 10000 ]] || fail "straight radius"
[[ $(column "$WORK/bayreuth.gpkg" "$seg" curvature_level) == 0 ]] || fail "straight level"
[[ $(column "$WORK/bayreuth.gpkg" "$seg" curvature_cost) == 0 ]] || fail "straight cost"
[[ $(column "$WORK/bayreuth.gpkg" "$seg" "junction_distance_m > 600") == 1 ]] || fail "straight far from junctions"
[[ $(column "$WORK/bayreuth.gpkg" "$seg" reasons) == NO_ELEVATION ]] || fail "straight has reasons besides NO_ELEVATION (built without a DEM)"
# Unclassified class cost 1, no curvature, no elevation: rank floor(15 * 1 / 75) = 0.
[[ $(column "$WORK/bayreuth.gpkg" "$seg" "class_cost || '/' || rank || '/' || score") == "1/0/15" ]] || fail "straight rank"
pass "straight: road vertices within 110 m deviate $deviation m from a line; level 0, cost 0, rank 0"
finish
