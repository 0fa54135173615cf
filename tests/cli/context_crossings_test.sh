#!/usr/bin/env bash
# Context stage end to end: each bundled map's crossings table against an independent count
# from osmium tags-filter on the same file; --print-config / --config round trip; bad
# parameter files; the shipped profiles; a bad overrides file.
source "$(dirname "$0")/lib.sh"
classes=motorway,motorway_link,trunk,trunk_link,primary,primary_link,secondary,secondary_link,tertiary,tertiary_link,unclassified,residential,service,busway,road,living_street

# expected_crossings MAP: "nodes ways" computed from osmium's OPL output, not from roadcross:
#   nodes = crossing nodes (highway=crossing, crossing=*, crossing:markings, crossing:signals,
#           crossing_ref) used by a road way (kept classes, not area=yes);
#   ways  = per footway=crossing / cycleway=crossing way, its nodes on a road that are not
#           crossing nodes, plus the points where its edges cross road edges without a shared
#           node (planar test in local metres, hits within 0.5 m of a shared node dropped).
expected_crossings() {
  local map=$1
  osmium tags-filter -R "$map" n/highway=crossing n/crossing n/crossing:markings n/crossing:signals n/crossing_ref -f opl -o "$WORK/cn.opl" --overwrite
  osmium tags-filter -R "$map" "w/highway=$classes" -f opl -o "$WORK/roads.opl" --overwrite
  osmium tags-filter -R "$map" w/footway=crossing w/cycleway=crossing -f opl -o "$WORK/cw.opl" --overwrite
  osmium cat "$map" -t node -f opl -o "$WORK/nodes.opl" --overwrite
  python3 - "$WORK" <<'PY'
import math, sys
work = sys.argv[1]
def fields(line):
    parts = line.split(' ')
    return parts[0], {p[0]: p[1:] for p in parts[1:] if p}
def tags(t):
    return dict(kv.split('=', 1) for kv in t.split(',') if '=' in kv) if t else {}
loc = {}
for line in open(f'{work}/nodes.opl'):
    oid, f = fields(line.strip())
    if f.get('x'): loc[int(oid[1:])] = (float(f['x']), float(f['y']))
crossing_nodes = {int(fields(l.strip())[0][1:]) for l in open(f'{work}/cn.opl') if l.startswith('n')}
roads = []
for line in open(f'{work}/roads.opl'):
    oid, f = fields(line.strip())
    if not oid.startswith('w') or tags(f.get('T', '')).get('area') == 'yes': continue
    refs = [int(r[1:]) for r in f.get('N', '').split(',') if r]
    if sum(r in loc for r in refs) >= 2: roads.append(refs)
road_nodes = {r for refs in roads for r in refs if r in loc}
lat0 = math.radians(sum(y for x, y in loc.values()) / max(len(loc), 1))
def xy(n): x, y = loc[n]; return (x * 111320 * math.cos(lat0), y * 110574)
edges = []
for refs in roads:
    pts = [r for r in refs if r in loc]
    edges += [(xy(a), xy(b)) for a, b in zip(pts, pts[1:]) if a != b]
def hit(p1, p2, q1, q2):
    rx, ry, sx, sy = p2[0]-p1[0], p2[1]-p1[1], q2[0]-q1[0], q2[1]-q1[1]
    d = rx*sy - ry*sx
    if abs(d) < 1e-12: return None
    qx, qy = q1[0]-p1[0], q1[1]-p1[1]
    t, u = (qx*sy - qy*sx)/d, (qx*ry - qy*rx)/d
    return (p1[0]+t*rx, p1[1]+t*ry) if 0 <= t <= 1 and 0 <= u <= 1 else None
nodes = len(crossing_nodes & road_nodes)
ways = 0
for line in open(f'{work}/cw.opl'):
    oid, f = fields(line.strip())
    if not oid.startswith('w') or tags(f.get('T', '')).get('area') == 'yes': continue
    refs = [int(r[1:]) for r in f.get('N', '').split(',') if r]
    taken = []
    for r in dict.fromkeys(refs):
        if r in road_nodes:
            taken.append(xy(r))
            if r not in crossing_nodes: ways += 1
    pts = [r for r in refs if r in loc]
    for a, b in zip(pts, pts[1:]):
        for e in edges:
            p = hit(e[0], e[1], xy(a), xy(b))
            if p and all(math.dist(p, t) >= 0.5 for t in taken):
                taken.append(p); ways += 1
print(nodes, ways)
PY
}

for map in "$PRAGUE_OSM" "$ROADCROSS_MAPS_DIR/monaco/monaco.osm.pbf" \
           "$ROADCROSS_MAPS_DIR/bayreuth/north-bayreuth.osm.gz" "$ROADCROSS_MAPS_DIR/techobuz/techobuz_2018.osm"; do
  name=$(basename "$map")
  "$ROADCROSS_BUILD" --osm "$map" -o "$WORK/map.gpkg" -q
  read -r want_nodes want_ways < <(expected_crossings "$map")
  got_nodes=$(sqlite3 "$WORK/map.gpkg" "SELECT count(*) FROM crossings WHERE osm_type = 'node'")
  got_ways=$(sqlite3 "$WORK/map.gpkg" "SELECT count(*) FROM crossings WHERE osm_type = 'way'")
  [[ "$got_nodes $got_ways" == "$want_nodes $want_ways" ]] &&
    pass "$name: $got_nodes crossing nodes, $got_ways crossing-way points (osmium agrees)" ||
    fail "$name: DB has $got_nodes nodes / $got_ways way points, osmium count $want_nodes / $want_ways"
  [[ $(sqlite3 "$WORK/map.gpkg" "SELECT count(*) FROM rtree_crossings_geom") == $((got_nodes + got_ways)) ]] ||
    fail "$name: crossings R*Tree size"
  [[ $(sqlite3 "$WORK/map.gpkg" "SELECT count(*) FROM segments WHERE context_score IS NULL OR maxspeed_kmh IS NULL") == 0 ]] ||
    fail "$name: segments without context"
done
# Prague: 529 crossing nodes (526 highway=crossing + 3 with crossing=* only), GDAL opens the layer.
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/prague.gpkg" -q
ogrinfo -ro -so "$WORK/prague.gpkg" crossings >"$WORK/ogr" 2>&1 && grep -q "Geometry: Point" "$WORK/ogr" &&
  grep -q "Feature Count: 529" "$WORK/ogr" && pass "ogrinfo: crossings point layer, 529 features" ||
  fail "ogrinfo crossings: $(cat "$WORK/ogr")"

# --print-config is a valid TOML and INI file that --config reads back to the same text.
"$ROADCROSS_BUILD" --print-config >"$WORK/a.ini"
"$ROADCROSS_BUILD" --config "$WORK/a.ini" --print-config >"$WORK/b.ini"
cmp -s "$WORK/a.ini" "$WORK/b.ini" && pass "--print-config round trip" || fail "--print-config round trip differs"
python3 -c "import sys, tomllib, configparser
tomllib.load(open(sys.argv[1], 'rb')); c = configparser.ConfigParser(); c.read(sys.argv[1])
assert c['suitability']['threshold'] == '20' and c['context']['crossing_points'] == '10'" "$WORK/a.ini" &&
  pass "--print-config parses as TOML and INI" || fail "--print-config is not valid TOML/INI"
# A flag beats the file.
"$ROADCROSS_BUILD" --config "$ROADCROSS_TEST_DATA_DIR/../../docs/profiles/thesis-code.ini" \
  --context.motorway_points -20 --print-config >"$WORK/c.ini"
grep -qx "crossing_points = 100" "$WORK/c.ini" && grep -qx "motorway_points = -20" "$WORK/c.ini" &&
  pass "--config then flags" || fail "flag did not override the file"

# Bad files: exit 2 naming file, line and key.
printf '[context]\ncrossing_points = 10\nfoo = 1\n' >"$WORK/bad1.ini"
expect_failure "unknown key" "bad1.ini:3: context.foo: unknown parameter" -- "$ROADCROSS_BUILD" --config "$WORK/bad1.ini" --osm "$PRAGUE_OSM" -o "$WORK/x.gpkg"
printf '[contxt]\n' >"$WORK/bad2.ini"
expect_failure "unknown section" "bad2.ini:1: [contxt]: unknown section" -- "$ROADCROSS_BUILD" --config "$WORK/bad2.ini" --print-config
printf '[suitability]\nthreshold = high\n' >"$WORK/bad3.ini"
expect_failure "non-numeric" "bad3.ini:2: suitability.threshold: 'high' is not a number" -- "$ROADCROSS_BUILD" --config "$WORK/bad3.ini" --print-config
printf '[context]\nassume_urban = 2\n' >"$WORK/bad4.ini"
expect_failure "out of range" "bad4.ini:2: context.assume_urban: 2 is out of range [0, 1]" -- "$ROADCROSS_BUILD" --config "$WORK/bad4.ini" --print-config
[[ ! -e "$WORK/x.gpkg" ]] || fail "output written despite a bad config"

# The profiles build, and their values are recorded in the DB metadata.
for profile in thesis-text thesis-code; do
  "$ROADCROSS_BUILD" --config "$ROADCROSS_TEST_DATA_DIR/../../docs/profiles/$profile.ini" --osm "$PRAGUE_OSM" -o "$WORK/$profile.gpkg" -q
done
[[ $(sqlite3 "$WORK/thesis-code.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'param.context.crossing_points'") == 100 ]] &&
  [[ $(sqlite3 "$WORK/thesis-text.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'param.context.motorway_points'") == -10 ]] &&
  pass "profiles build and are recorded" || fail "profile values not in the metadata"

# Overrides: a bad feature names itself; --country must be known.
printf '{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": null, "properties": {"osm_way_id": 1, "no_crossing": 1}}]}' >"$WORK/bad.geojson"
expect_failure "bad override" "bad.geojson: feature 0: no_crossing must be true or false" -- "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/y.gpkg" --overrides "$WORK/bad.geojson"
expect_failure "unknown country" "--country XX" -- "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/y.gpkg" --country XX
finish
