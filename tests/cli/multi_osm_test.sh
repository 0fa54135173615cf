#!/usr/bin/env bash
# roadcross-build --osm A --osm B: one map from several extracts, merged by object id. The
# reference is `osmium merge` of the same extracts: the two maps must be identical apart from
# the input metadata (input.N.* rows: file names and hashes of what was read).
source "$(dirname "$0")/lib.sh"
MONACO="$ROADCROSS_MAPS_DIR/monaco/monaco.osm.pbf"

# Two overlapping extracts (7.415..7.425 E in both): objects in the overlap are in both files.
osmium extract -b 7.349,43.71,7.425,43.77 "$MONACO" -o "$WORK/west.osm.pbf" --no-progress
osmium extract -b 7.415,43.71,7.491,43.77 "$MONACO" -o "$WORK/east.osm.pbf" --no-progress
osmium merge "$WORK/west.osm.pbf" "$WORK/east.osm.pbf" -o "$WORK/merged.osm.pbf" --no-progress
shared=$(osmium cat "$WORK/west.osm.pbf" -f opl | cut -d' ' -f1 | sort >"$WORK/west.ids"
         osmium cat "$WORK/east.osm.pbf" -f opl | cut -d' ' -f1 | sort >"$WORK/east.ids"
         comm -12 "$WORK/west.ids" "$WORK/east.ids" | wc -l)
((shared > 1000)) && pass "the extracts share $shared objects" || fail "the extracts share only $shared objects"

"$ROADCROSS_BUILD" --osm "$WORK/west.osm.pbf" --osm "$WORK/east.osm.pbf" -o "$WORK/two.gpkg" -q
"$ROADCROSS_BUILD" --osm "$WORK/merged.osm.pbf" -o "$WORK/merged.gpkg" -q
"$ROADCROSS_BUILD" --osm "$WORK/west.osm.pbf" -o "$WORK/west.gpkg" -q

# The whole database as SQL text, the metadata as key/value pairs without the input rows (their
# row ids shift with the number of inputs) and without what digests them: the metadata table's
# column digests and the map_id (segments' and crossings' digests stay compared).
dump_without_inputs() {
  sqlite3 "$1" .dump | grep -v "^INSERT INTO roadcross_metadata VALUES("
  sqlite3 "$1" "SELECT key, value FROM roadcross_metadata WHERE key NOT LIKE 'input.%'
    AND key NOT LIKE 'content.roadcross_metadata.%' AND key != 'map_id' ORDER BY key"
}
dump_without_inputs "$WORK/two.gpkg" >"$WORK/two.sql"
dump_without_inputs "$WORK/merged.gpkg" >"$WORK/merged.sql"
dump_without_inputs "$WORK/west.gpkg" >"$WORK/west.sql"
if cmp -s "$WORK/two.sql" "$WORK/merged.sql"; then
  pass "--osm west --osm east = osmium merge (apart from the inputs)"
else
  fail "--osm west --osm east differs from osmium merge: $(diff "$WORK/two.sql" "$WORK/merged.sql" | head -5)"
fi
# The comparison can fail: one extract alone gives another map.
cmp -s "$WORK/two.sql" "$WORK/west.sql" && fail "the west extract alone gives the same map" || true
count() { sqlite3 "$1" "SELECT count(*) FROM segments"; }
(( $(count "$WORK/two.gpkg") > $(count "$WORK/west.gpkg") )) &&
  pass "two extracts: $(count "$WORK/two.gpkg") segments, west alone $(count "$WORK/west.gpkg")" ||
  fail "two extracts have no more segments than one"
# The zone is chosen for the whole network, as for one file (Monaco: 32N).
[[ $(sqlite3 "$WORK/two.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'utm_zone'") == 32 ]] &&
  pass "zone 32" || fail "zone"

# Both inputs are recorded, in the order given, with their hashes.
meta() { sqlite3 "$WORK/two.gpkg" "SELECT value FROM roadcross_metadata WHERE key = '$1'"; }
[[ $(meta input.0.file) == west.osm.pbf && $(meta input.1.file) == east.osm.pbf &&
   $(meta input.0.kind) == osm && $(meta input.1.kind) == osm ]] &&
  pass "inputs recorded in order" || fail "inputs: $(meta input.0.file) $(meta input.1.file)"
[[ $(meta input.1.sha256) == $(sha256sum "$WORK/east.osm.pbf" | cut -d' ' -f1) ]] &&
  pass "input.1.sha256" || fail "input.1.sha256"

# The same extract twice: every object in both files, read once: the map of the file alone.
"$ROADCROSS_BUILD" --osm "$WORK/west.osm.pbf" --osm "$WORK/west.osm.pbf" -o "$WORK/twice.gpkg" -q
dump_without_inputs "$WORK/twice.gpkg" | cmp -s - "$WORK/west.sql" &&
  pass "the same extract twice = once" || fail "the same extract twice differs from once"

# An unsorted file cannot be merged: the error names it and the object out of order, and no
# output is left.
cat >"$WORK/unsorted.osm" <<'OSM'
<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6" generator="hand">
  <node id="2" version="1" lat="43.73" lon="7.42"/>
  <node id="1" version="1" lat="43.731" lon="7.42"/>
  <way id="10" version="1"><nd ref="1"/><nd ref="2"/><tag k="highway" v="residential"/></way>
</osm>
OSM
expect_failure "unsorted input" "$WORK/unsorted.osm" "not sorted" "node 1" "osmium sort" -- \
  "$ROADCROSS_BUILD" --osm "$WORK/west.osm.pbf" --osm "$WORK/unsorted.osm" -o "$WORK/bad.gpkg" -q
[[ ! -e $WORK/bad.gpkg ]] && pass "no output after the error" || fail "an output was left"
# A missing second input is named.
expect_failure "missing input" "$WORK/nowhere.osm" -- \
  "$ROADCROSS_BUILD" --osm "$WORK/west.osm.pbf" --osm "$WORK/nowhere.osm" -o "$WORK/bad.gpkg" -q
finish
