#!/usr/bin/env bash
# roadcross verify: a whole map passes (exit 0); one changed value in any column of segments,
# a changed metadata value, a wrong or missing R*Tree box, a cut file, a wrong --expect-id each
# fail with exit 1 and a message naming what is wrong.
source "$(dirname "$0")/lib.sh"

"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/map.gpkg" -q
id=$(sqlite3 "$WORK/map.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'map_id'")
if "$ROADCROSS" verify --db "$WORK/map.gpkg" >"$WORK/out" 2>&1 && grep -q "ok, map_id $id" "$WORK/out"; then
  pass "a fresh map verifies: $(cat "$WORK/out")"
else
  fail "a fresh map: $(cat "$WORK/out")"
fi
"$ROADCROSS" verify --db "$WORK/map.gpkg" --expect-id "$id" >/dev/null && pass "--expect-id its own id" ||
  fail "--expect-id its own id"
other=$(printf '%064d' 0)
expect_failure "--expect-id another id" "expected $other" -- "$ROADCROSS" verify --db "$WORK/map.gpkg" --expect-id "$other"
status=0; "$ROADCROSS" verify --db "$WORK/map.gpkg" --expect-id 1234 >/dev/null 2>&1 || status=$?
((status != 0 && status != 1)) && pass "--expect-id 1234 is a usage error (exit $status)" || fail "--expect-id 1234: exit $status"
expect_failure "missing file" "missing.gpkg: not a regular file" -- "$ROADCROSS" verify --db "$WORK/missing.gpkg"
"$ROADCROSS" verify --db "$WORK/map.gpkg" --json | python3 -c '
import json, sys; d = json.load(sys.stdin); sys.exit(0 if d["ok"] and d["problems"] == [] and len(d["map_id"]) == 64 else 1)' &&
  pass "--json: ok, no problems" || fail "--json"

# mutate SQL...: a copy of the map with the SQL applied by Python's sqlite3, whose no-op ST_*
# functions let the GeoPackage R*Tree triggers run (they only move boxes, which verify checks).
mutate() {
  cp "$WORK/map.gpkg" "$WORK/mutant.gpkg"
  python3 - "$WORK/mutant.gpkg" "$1" <<'PY'
import sqlite3, sys
db = sqlite3.connect(sys.argv[1])
db.create_function("ST_IsEmpty", 1, lambda g: 0)
for f in ("ST_MinX", "ST_MaxX", "ST_MinY", "ST_MaxY"):
    db.create_function(f, 1, lambda g: 0.0)
cur = db.execute(sys.argv[2])
assert cur.rowcount != 0, f"{sys.argv[2]}: no row changed"  # (-1 for ALTER TABLE)
db.commit()
PY
}

# Every column of segments: one value of one row changed, type kept where the column has one.
first=$(sqlite3 "$WORK/map.gpkg" "SELECT min(fid) FROM segments WHERE name IS NOT NULL AND sight_min_m IS NOT NULL")
columns=$(sqlite3 "$WORK/map.gpkg" "SELECT name || ' ' || type FROM pragma_table_info('segments') ORDER BY cid")
count=0
while read -r column type; do
  case $column:$type in
    fid:*) change="fid = (SELECT max(fid) + 1 FROM segments)" ;;
    geom:*) change="geom = (SELECT geom FROM segments WHERE fid = $first + 1)" ;;
    *:TEXT) change="$column = coalesce($column, '') || 'x'" ;;
    *:INTEGER) change="$column = coalesce($column, 0) + 1" ;;
    *:BOOLEAN) change="$column = 1 - coalesce($column, 0)" ;;
    *:REAL) change="$column = coalesce($column, 0) + 0.5" ;;
    *) fail "column $column has type '$type' this test does not know"; continue ;;
  esac
  mutate "UPDATE segments SET $change WHERE fid = $first"
  expect_failure "segments.$column changed" "segments.$column differs" -- "$ROADCROSS" verify --db "$WORK/mutant.gpkg"
  count=$((count + 1))
done <<<"$columns"
expected_columns=$(sqlite3 "$WORK/map.gpkg" "SELECT count(*) FROM pragma_table_info('segments')")
((count == expected_columns && count >= 39)) && pass "all $count columns of segments mutated" ||
  fail "mutated $count of $expected_columns columns"

mutate "UPDATE roadcross_metadata SET value = '7' WHERE key = 'param.suitability.threshold'"
expect_failure "a parameter changed" "roadcross_metadata.value differs" -- "$ROADCROSS" verify --db "$WORK/mutant.gpkg"
mutate "UPDATE crossings SET signals = 1 - signals WHERE fid = (SELECT min(fid) FROM crossings)"
expect_failure "a crossing changed" "crossings.signals differs" -- "$ROADCROSS" verify --db "$WORK/mutant.gpkg"
mutate "UPDATE roadcross_metadata SET value = '$other' WHERE key = 'map_id'"
expect_failure "map_id changed" "map_id $other does not match the content" -- "$ROADCROSS" verify --db "$WORK/mutant.gpkg"
mutate "DELETE FROM roadcross_metadata WHERE key = 'map_id'"
expect_failure "no map_id" "has no map_id" -- "$ROADCROSS" verify --db "$WORK/mutant.gpkg"
mutate "UPDATE rtree_segments_geom SET minx = minx - 50 WHERE id = $first"
expect_failure "an R*Tree box moved" "R*Tree rtree_segments_geom: segments fid $first: box differs" -- "$ROADCROSS" verify --db "$WORK/mutant.gpkg"
mutate "DELETE FROM rtree_segments_geom WHERE id = $first"
expect_failure "an R*Tree box removed" "segments fid $first has no box" -- "$ROADCROSS" verify --db "$WORK/mutant.gpkg"
mutate "INSERT INTO rtree_segments_geom VALUES (999999999, 0, 1, 0, 1)"
expect_failure "an R*Tree box without a segment" "box 999999999 has no row in segments" -- "$ROADCROSS" verify --db "$WORK/mutant.gpkg"
mutate "ALTER TABLE segments RENAME COLUMN rank TO ranking"
expect_failure "a column renamed" "schema: table segments column" "ranking" -- "$ROADCROSS" verify --db "$WORK/mutant.gpkg"

# A file cut short (a copy interrupted): SQLite's integrity check or the read fails.
head -c $(($(stat -c %s "$WORK/map.gpkg") / 2)) "$WORK/map.gpkg" >"$WORK/cut.gpkg"
expect_failure "a file cut in half" "cut.gpkg" -- "$ROADCROSS" verify --db "$WORK/cut.gpkg"
# A page overwritten in the middle of the file.
cp "$WORK/map.gpkg" "$WORK/garbled.gpkg"
page=$(sqlite3 "$WORK/map.gpkg" "PRAGMA page_size")
pages=$(($(stat -c %s "$WORK/map.gpkg") / page))
python3 -c 'import random, sys
f = open(sys.argv[1], "r+b"); f.seek(int(sys.argv[2])); f.write(random.Random(1).randbytes(int(sys.argv[3])))' \
  "$WORK/garbled.gpkg" $((pages / 2 * page)) "$page"
expect_failure "a page of random bytes" "garbled.gpkg" -- "$ROADCROSS" verify --db "$WORK/garbled.gpkg"
finish
