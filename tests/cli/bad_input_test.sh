#!/usr/bin/env bash
# Bad input: a clear message naming the file (or parameter) and the problem, a non-zero exit,
# and no output file or temporary file left behind.
source "$(dirname "$0")/lib.sh"
out="$WORK/out/map.gpkg"
mkdir -p "$WORK/out"

no_output_left() {
  if compgen -G "$WORK/out/*" >/dev/null; then fail "$1: left $(ls "$WORK/out")"; rm -f "$WORK"/out/*; fi
}

expect_failure "missing file" "$WORK/missing.osm" "No such file" -- "$ROADCROSS_BUILD" --osm "$WORK/missing.osm" -o "$out"
no_output_left "missing file"

: >"$WORK/empty.osm"
expect_failure "empty file" "$WORK/empty.osm" "empty" -- "$ROADCROSS_BUILD" --osm "$WORK/empty.osm" -o "$out"
no_output_left "empty file"

head -c 300000 "$ROADCROSS_MAPS_DIR/monaco/monaco.osm.pbf" >"$WORK/truncated.osm.pbf"
expect_failure "truncated pbf" "$WORK/truncated.osm.pbf" "not readable as OSM data" -- \
  "$ROADCROSS_BUILD" --osm "$WORK/truncated.osm.pbf" -o "$out"
no_output_left "truncated pbf"

echo "easting northing altitude" >"$WORK/text.osm"
expect_failure "text named .osm" "$WORK/text.osm" "XML parsing error at line 1" -- \
  "$ROADCROSS_BUILD" --osm "$WORK/text.osm" -o "$out"
no_output_left "text named .osm"

head -c 4096 /dev/urandom >"$WORK/garbage.osm.pbf"
expect_failure "garbage named .pbf" "$WORK/garbage.osm.pbf" "not readable as OSM data" -- \
  "$ROADCROSS_BUILD" --osm "$WORK/garbage.osm.pbf" -o "$out"
no_output_left "garbage named .pbf"

head -c 20000 "$PRAGUE_OSM" >"$WORK/truncated.osm"
expect_failure "truncated xml" "$WORK/truncated.osm" "XML parsing error" -- \
  "$ROADCROSS_BUILD" --osm "$WORK/truncated.osm" -o "$out"
no_output_left "truncated xml"

cat >"$WORK/footways.osm" <<'OSM'
<?xml version='1.0' encoding='UTF-8'?>
<osm version="0.6">
  <node id="1" version="1" lat="50.0" lon="14.4"/>
  <node id="2" version="1" lat="50.0" lon="14.401"/>
  <way id="10" version="1"><nd ref="1"/><nd ref="2"/><tag k="highway" v="footway"/></way>
</osm>
OSM
expect_failure "no roads" "$WORK/footways.osm" "none is a road" -- "$ROADCROSS_BUILD" --osm "$WORK/footways.osm" -o "$out"
no_output_left "no roads"

expect_failure "output in a missing directory" "$WORK/nowhere/map.gpkg" "folder $WORK/nowhere does not exist" -- \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/nowhere/map.gpkg"
: >"$WORK/a_file"
expect_failure "output under a file" "$WORK/a_file/map.gpkg" "$WORK/a_file is not a folder" -- \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/a_file/map.gpkg"

expect_failure "negative segment length" "segments.max_segment_length_m" "-1" -- \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$out" --segments.max_segment_length_m -1
expect_failure "garbage number" "segments.max_segment_length_m" -- \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$out" --segments.max_segment_length_m ten
no_output_left "bad parameters"

# An existing map is left as it was when a rebuild fails.
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$out" -q
cp "$out" "$WORK/before.gpkg"
expect_failure "failed rebuild" "$WORK/empty.osm" -- "$ROADCROSS_BUILD" --osm "$WORK/empty.osm" -o "$out"
cmp -s "$out" "$WORK/before.gpkg" && pass "existing map untouched" || fail "existing map changed by a failed build"
compgen -G "$WORK/out/*.tmp-*" >/dev/null && fail "temporary file left" || true

# Runtime side.
expect_failure "info on a missing DB" "$WORK/none.gpkg" "no such file" -- "$ROADCROSS" info "$WORK/none.gpkg"
expect_failure "info on a text file" "$WORK/text.osm" "not an SQLite database" -- "$ROADCROSS" info "$WORK/text.osm"
sqlite3 "$WORK/plain.sqlite" "CREATE TABLE t (x)"
expect_failure "info on plain SQLite" "not a GeoPackage" -- "$ROADCROSS" info "$WORK/plain.sqlite"
cp "$out" "$WORK/newer.gpkg"
sqlite3 "$WORK/newer.gpkg" "UPDATE roadcross_metadata SET value = '999' WHERE key = 'schema_version'"
expect_failure "DB from a newer version" "schema version 999" "newer" -- "$ROADCROSS" info "$WORK/newer.gpkg"
expect_failure "heading with no position" "--lat/--lon or --utm" -- "$ROADCROSS" heading --db "$out"
expect_failure "latitude out of range" "latitude 95" -- "$ROADCROSS" heading --db "$out" --lat 95 --lon 14.4
expect_failure "nothing near" "no road within 50" -- "$ROADCROSS" nearest --db "$out" --utm 400000 5500000 --max-distance 50
finish
