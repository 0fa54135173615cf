#!/usr/bin/env bash
# roadcross export against GDAL's own conversion of the same table
# (ogr2ogr -f GeoJSON -t_srs EPSG:4326 -lco RFC7946=YES): same features in the same order, same
# coordinates (to 1e-7 degree), same values of every column; `suitable` follows the rule of
# the thesis (docs/cost-model.md) computed here from the columns, and agrees with `roadcross assess` at midpoints.
source "$(dirname "$0")/lib.sh"
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" --elevation "$ROADCROSS_MAPS_DIR/prague/N50E014.hgt" \
  -o "$WORK/prague.gpkg" -q
"$ROADCROSS" export --db "$WORK/prague.gpkg" --format geojson -o "$WORK/export.geojson" >/dev/null
ogr2ogr -f GeoJSON -t_srs EPSG:4326 -lco RFC7946=YES "$WORK/ogr.geojson" "$WORK/prague.gpkg" segments
count=$(sqlite3 "$WORK/prague.gpkg" "SELECT count(*) FROM segments")
threshold=$(sqlite3 "$WORK/prague.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'param.suitability.threshold'")

python3 - "$WORK" "$count" "$threshold" <<'PY' >"$WORK/compare.txt"
import json, sys
work, count, threshold = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
ours = json.load(open(f'{work}/export.geojson'))
ogr = json.load(open(f'{work}/ogr.geojson'))
def check(ok, what):
    print(('ok: ' if ok else 'FAIL: ') + what)
check(len(ours['features']) == count == len(ogr['features']),
      f"{len(ours['features'])} features, DB {count}, ogr2ogr {len(ogr['features'])}")
check('crs' not in ours, 'RFC 7946: no crs member (WGS84 lon/lat)')
worst, mismatched, judged, suitable = 0.0, [], 0, 0
for a, b in zip(ours['features'], ogr['features']):
    pa, pb = a['properties'], b['properties']
    for key, value in pb.items():
        if pa.get(key, 'missing') != value and not (isinstance(value, float) and abs(pa[key] - value) < 1e-9):
            mismatched.append((pa.get('fid'), key, pa.get(key), value))
    for p, q in zip(a['geometry']['coordinates'], b['geometry']['coordinates']):
        worst = max(worst, abs(p[0] - q[0]), abs(p[1] - q[1]))
    reasons = (pb['reasons'] or '').split(',')
    # LIMITED_VISIBILITY makes a place unsuitable (the default sight.limited_visibility_unsuitable
    # = 1 of this build); an operator's force_suitable wins over it and over the score.
    hidden = 'LIMITED_VISIBILITY' in reasons
    expected = (not ('NOT_CROSSABLE_CLASS' in reasons or pb['tunnel'] or pb['override_no_crossing'])
                and ((pb['score'] is not None and pb['score'] + (pb['context_score'] or 0) >= threshold
                      and not hidden)
                     or bool(pb['override_force_suitable'])))
    judged += pa['suitable'] == expected
    suitable += expected
check(not mismatched, f'every column equal to ogr2ogr ({len(mismatched)} differences, first {mismatched[:1]})')
check(worst <= 1.5e-7, f'coordinates within {worst:.2e} degree of ogr2ogr')
check(judged == count, f'suitable as the rule says on {judged} of {count} ({suitable} suitable)')
check([f['properties']['fid'] for f in ours['features']] == list(range(1, count + 1)), 'fid 1..N in order')
check(0 < suitable < count, 'both verdicts occur')
# Places for roadcross assess: midpoints of the middle vertex pair of a few long segments.
with open(f'{work}/places.txt', 'w') as out:
    long = [f for f in ours['features'] if f['properties']['length_m'] > 8][::500]
    for f in long:
        c = f['geometry']['coordinates']
        i = len(c) // 2 - 1 if len(c) > 2 else 0
        lon, lat = (c[i][0] + c[i + 1][0]) / 2, (c[i][1] + c[i + 1][1]) / 2
        out.write(f"{lat:.8f} {lon:.8f} {f['properties']['fid']} {int(f['properties']['suitable'])} {f['properties']['assess_reasons']}\n")
PY
while read -r line; do
  case $line in ok:*) pass "${line#ok: }" ;; *) fail "${line#FAIL: }" ;; esac
done <"$WORK/compare.txt"

# The exported judgement is assess's: on the centreline the same segment, verdict and reasons.
agree=0 total=0
while read -r lat lon fid suitable reasons; do
  "$ROADCROSS" assess --db "$WORK/prague.gpkg" --lat "$lat" --lon "$lon" --json >"$WORK/a.json"
  got=$(python3 -c 'import json,sys; a=json.load(open(sys.argv[1])); print(a["segment_id"], int(a["suitable"]), ",".join(a["reasons"]))' "$WORK/a.json")
  total=$((total + 1))
  [[ $got == "$fid $suitable $reasons" ]] && agree=$((agree + 1)) || echo "differs: $got vs $fid $suitable $reasons"
done <"$WORK/places.txt"
((total >= 10 && agree == total)) && pass "assess agrees at $agree of $total midpoints" ||
  fail "assess agrees at $agree of $total midpoints"

# Crossings layer; a bbox gives a subset.
"$ROADCROSS" export --db "$WORK/prague.gpkg" --layer crossings -o "$WORK/crossings.geojson" >/dev/null
[[ $(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["features"]))' "$WORK/crossings.geojson") == \
   $(sqlite3 "$WORK/prague.gpkg" "SELECT count(*) FROM crossings") ]] && pass "crossings layer complete" ||
  fail "crossings layer count"
"$ROADCROSS" export --db "$WORK/prague.gpkg" -o "$WORK/part.geojson" --bbox 14.418,50.074,14.424,50.078 >/dev/null
part=$(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["features"]))' "$WORK/part.geojson")
((part > 10 && part < count / 2)) && pass "bbox: $part of $count segments" || fail "bbox: $part of $count"

expect_failure "unknown format" "--format 'shapefile'" "geojson" -- \
  "$ROADCROSS" export --db "$WORK/prague.gpkg" --format shapefile -o "$WORK/x.shp"
expect_failure "unknown layer" "--layer 'roads'" -- \
  "$ROADCROSS" export --db "$WORK/prague.gpkg" --layer roads -o "$WORK/x.geojson"
expect_failure "bbox outside the map" "lies outside the map" -- \
  "$ROADCROSS" export --db "$WORK/prague.gpkg" -o "$WORK/x.geojson" --bbox 16.0,49.0,16.1,49.1
expect_failure "unwritable output" "cannot write /nonexistent/x.geojson" -- \
  "$ROADCROSS" export --db "$WORK/prague.gpkg" -o /nonexistent/x.geojson
echo "not a database" >"$WORK/text.gpkg"
expect_failure "not a GeoPackage" "text.gpkg" -- "$ROADCROSS" export --db "$WORK/text.gpkg" -o "$WORK/x.geojson"
[[ ! -e $WORK/x.geojson ]] && pass "no output after a failure" || fail "output left after a failure"
finish
