#!/usr/bin/env bash
# Maps as untrusted input (docs/reliability.md, "Maps as untrusted input"): a hand-made map, copied and damaged with
# sqlite3 one way at a time, must give the exact status (corrupt segment, hostile schema, bad
# metadata) and never a verdict, a hang or an abort; text that is not UTF-8 must not abort any
# JSON output; out-of-range query options must be clear errors.
#
# The map: one straight residential road along lat 50.0 from lon 14.40 to 14.4083 (about 595 m,
# cut into segments of about 10 m). 3 m north of its middle it is SUITABLE (score 15 + context
# 10 >= 20; tests/cli/runtime_cli_test.sh derives it).
source "$(dirname "$0")/lib.sh"
cat >"$WORK/map.osm" <<'OSM'
<?xml version='1.0' encoding='UTF-8'?>
<osm version="0.6">
  <node id="1" version="1" lat="50.0" lon="14.40"/>
  <node id="2" version="1" lat="50.0" lon="14.4083"/>
  <way id="10" version="1"><nd ref="1"/><nd ref="2"/><tag k="highway" v="residential"/></way>
</osm>
OSM
"$ROADCROSS_BUILD" --osm "$WORK/map.osm" -o "$WORK/map.gpkg" -q
lat=50.000027 lon=14.40415
here=(--lat $lat --lon $lon)
"$ROADCROSS" assess --db "$WORK/map.gpkg" "${here[@]}" --json >"$WORK/base.json"
[[ $(json_field "$WORK/base.json" suitable) == True ]] || fail "the undamaged map is not SUITABLE"
# The segment the position is on, which the damage below hits.
fid=$(json_field "$WORK/base.json" segment_id)

# damaged NAME SQL: a copy of the map with SQL applied (the R*Tree triggers dropped first: they
# call GeoPackage functions plain sqlite3 lacks, and the runtime never needs them).
damaged() {
  cp "$WORK/map.gpkg" "$WORK/$1.gpkg"
  sqlite3 "$WORK/$1.gpkg" "$(for t in insert update1 update2 update3 update4 delete; do
    echo "DROP TRIGGER rtree_segments_geom_$t;"; done) $2" >/dev/null
  echo "$WORK/$1.gpkg"
}

# corrupt_segment CASE SQL EXPECTED: assess and better at the position fail naming the segment
# and the problem; no SUITABLE/NOT SUITABLE verdict is printed.
corrupt_segment() {
  local db
  db=$(damaged "$1" "$2")
  for command in assess better; do
    expect_failure "$1: $command" "segment $fid" "$3" "map is damaged there" -- \
      timeout 20 "$ROADCROSS" $command --db "$db" "${here[@]}"
    if grep -q "SUITABLE" "$WORK/stdout"; then fail "$1: $command printed a verdict"; fi
  done
}

corrupt_segment tunnel_bit_cleared "UPDATE segments SET reasons = 'TUNNEL' WHERE fid = $fid" \
  "the tunnel flag contradicts its reasons"
corrupt_segment tunnel_bit_set "UPDATE segments SET tunnel = 1 WHERE fid = $fid" \
  "the tunnel flag contradicts its reasons"
corrupt_segment unknown_reason "UPDATE segments SET reasons = 'NO_ELEVATION,SAFE' WHERE fid = $fid" \
  "unknown reason code 'SAFE'"
corrupt_segment highway_flipped "UPDATE segments SET highway = 'trunk' WHERE fid = $fid" \
  "highway=trunk contradicts NOT_CROSSABLE_CLASS"
corrupt_segment no_crossing_without_override \
  "UPDATE segments SET override_no_crossing = 1 WHERE fid = $fid" \
  "override_no_crossing is set but OVERRIDE is not among its reasons"
corrupt_segment negative_length "UPDATE segments SET length_m = -10 WHERE fid = $fid" \
  "length_m must be a finite number >= 0"
corrupt_segment infinite_radius "UPDATE segments SET radius_m = 9e999 WHERE fid = $fid" \
  "radius_m must be a finite number >= 0"
corrupt_segment text_for_width "UPDATE segments SET width_m = 'wide' WHERE fid = $fid" \
  "width_m must be a finite number >= 0"
corrupt_segment score_out_of_range "UPDATE segments SET score = 99 WHERE fid = $fid" \
  "score must be an integer in 1..15"
corrupt_segment score_not_15_minus_rank "UPDATE segments SET score = 14 WHERE fid = $fid" \
  "score must be 15 - rank"
# INT_MAX: score + context_score would overflow int.
corrupt_segment context_overflow "UPDATE segments SET context_score = 2147483647 WHERE fid = $fid" \
  "context_score must be an integer in -1000000..1000000"
corrupt_segment tunnel_flag_two "UPDATE segments SET tunnel = 2 WHERE fid = $fid" \
  "tunnel must be an integer in 0..1"
# A NaN coordinate (GeoPackage blob: 8-byte header, 32-byte XY envelope, then WKB: byte order,
# type, point count, then the first x at offset 49). SQLite cannot store NaN as REAL, but a blob
# carries any bytes.
corrupt_segment nan_coordinate \
  "UPDATE segments SET geom = substr(geom, 1, 49) || X'000000000000F87F' || substr(geom, 58) WHERE fid = $fid" \
  "a geometry coordinate is not finite"
# The R*Tree box of the road's west end moved onto the position: the index would answer about a
# segment 300 m away.
west=$(sqlite3 "$WORK/map.gpkg" "SELECT fid FROM segments ORDER BY fid LIMIT 1")
read -r qe qn <<<"$(python3 -c "import json; d=json.load(open('$WORK/base.json')); print(*d['closest_utm_m'])")"
db=$(damaged box_moved "UPDATE rtree_segments_geom SET minx = $qe - 5, maxx = $qe + 5, miny = $qn - 5, maxy = $qn + 5 WHERE id = $west")
expect_failure "box_moved: assess" "segment $west" "its R*Tree box" "does not contain its point" -- \
  "$ROADCROSS" assess --db "$db" "${here[@]}"

# hostile_schema CASE SQL EXPECTED: the map is refused at open, by every command.
hostile_schema() {
  local db
  db=$(damaged "$1" "$2")
  for command in "info $db" "assess --db $db ${here[*]}"; do
    expect_failure "$1: ${command%% *}" "$3" "altered after roadcross-build wrote it" -- \
      timeout 20 "$ROADCROSS" $command
  done
}
# segments as an endless view: the table renamed away, a recursive view in its place.
hostile_schema endless_segments_view \
  "ALTER TABLE segments RENAME TO segments_data;
   CREATE VIEW segments AS WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n)
   SELECT s.* FROM n, segments_data s;" \
  "a view 'segments'"
hostile_schema extra_view "CREATE VIEW anything AS SELECT 1" "a view 'anything'"
hostile_schema foreign_trigger \
  "CREATE TRIGGER audit AFTER INSERT ON roadcross_metadata BEGIN SELECT 1; END" \
  "a trigger 'audit'"
hostile_schema fts_table "CREATE VIRTUAL TABLE notes USING fts5(text)" \
  "a virtual table 'notes' that is not a GeoPackage R*Tree"
db=$(damaged segments_missing "DROP TABLE segments")
expect_failure "segments_missing" "lacks an ordinary 'segments' table" -- "$ROADCROSS" info "$db"

# Metadata thresholds that are not finite numbers.
for value in inf nan 1e999 abc; do
  db=$(damaged "threshold_$value" "UPDATE roadcross_metadata SET value = '$value' WHERE key = 'param.suitability.threshold'")
  expect_failure "metadata threshold '$value'" "metadata param.suitability.threshold is '$value'" -- \
    "$ROADCROSS" assess --db "$db" "${here[@]}"
done
db=$(damaged valid_distance_negative "UPDATE roadcross_metadata SET value = '-1' WHERE key = 'param.suitability.valid_distance_m'")
expect_failure "metadata valid_distance_m -1" "param.suitability.valid_distance_m is '-1'" -- \
  "$ROADCROSS" info "$db"

# A 20 MB name (SQLite's length limit for a map is 16 MiB).
db=$(damaged huge_name "UPDATE segments SET name = CAST(zeroblob(20000000) AS TEXT) WHERE fid = $fid")
expect_failure "20 MB name" "longer than 16777216 bytes" -- "$ROADCROSS" assess --db "$db" "${here[@]}"

# WAL journal mode: with nothing pending the map opens (read as immutable) and answers as before,
# and no -wal or -shm file is left next to it.
db=$(damaged wal "PRAGMA journal_mode = WAL")
"$ROADCROSS" assess --db "$db" "${here[@]}" --json >"$WORK/wal.json" &&
  [[ $(json_field "$WORK/wal.json" suitable) == True && ! -e "$db-wal" && ! -e "$db-shm" ]] &&
  pass "WAL map without pending changes: opens, SUITABLE, no -wal/-shm left" || fail "WAL map"
# With changes only in the -wal file (a writer still has it open): a clear error, not a stale
# answer and not "disk I/O error".
python3 - "$db" "$WORK/wal_pending.gpkg" <<'PY'
import shutil, sqlite3, sys
db, copy = sys.argv[1], sys.argv[2]
c = sqlite3.connect(db)
c.execute("PRAGMA wal_autocheckpoint = 0")
c.execute("INSERT INTO roadcross_metadata (key, value) VALUES ('pending', 'x')")
c.commit()
shutil.copy(db, copy)
shutil.copy(db + "-wal", copy + "-wal")
c.close()
PY
expect_failure "WAL map with pending changes" "in WAL journal mode with changes not yet merged" \
  "wal_pending.gpkg-wal" "PRAGMA journal_mode = DELETE" -- \
  "$ROADCROSS" assess --db "$WORK/wal_pending.gpkg" "${here[@]}"

# Text that is not UTF-8 in JSON output: a damaged name in the map (bytes 41 42 FF 43), a binary
# line on batch's stdin, a path in another encoding, a simulate label. Each prints valid JSON
# (U+FFFD in place of the bad byte) and exits as it would with clean text.
db=$(damaged latin1_name "UPDATE segments SET name = CAST(X'4142FF43' AS TEXT) WHERE fid = $fid")
"$ROADCROSS" assess --db "$db" "${here[@]}" --json >"$WORK/name.json" &&
  [[ $(python3 -c "import json; print(json.load(open('$WORK/name.json'))['name'] == 'AB\ufffdC')") == True ]] &&
  pass "non-UTF-8 name: valid JSON, U+FFFD in place of the byte" || fail "non-UTF-8 name"
printf '%s\n' "{\"op\":\"assess\",\"lat\":$lat,\"lon\":$lon}" $'\xff\xfe{"op"' \
  "{\"op\":\"nearest\",\"lat\":$lat,\"lon\":$lon}" >"$WORK/requests"
status=0
"$ROADCROSS" batch --db "$db" <"$WORK/requests" >"$WORK/answers" || status=$?
python3 - "$WORK/answers" <<'PY' && [[ $status == 3 ]] &&
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1], encoding="utf-8")]
assert [l["line"] for l in lines] == [1, 2, 3], lines
assert lines[0]["ok"] and not lines[1]["ok"] and lines[2]["ok"], lines
assert lines[1]["error"].startswith("line 2:"), lines[1]
PY
  pass "batch: a binary line is one failed request, the batch goes on (exit 3)" || fail "batch binary line (exit $status)"
odd="$WORK/caf"$'\xe9'".gpkg"
cp "$WORK/map.gpkg" "$odd"
"$ROADCROSS" info "$odd" --json >"$WORK/info.json" &&
  python3 -c "import json; assert json.load(open('$WORK/info.json'))['path'].endswith('caf\ufffd.gpkg')" &&
  pass "info --json on a Latin-1 path" || fail "info --json on a Latin-1 path"
"$ROADCROSS" simulate --label $'\xff' --runs 2 --json >"$WORK/sim.json" &&
  python3 -c "import json; assert json.load(open('$WORK/sim.json'))['place'] == '\ufffd'" &&
  pass "simulate --label with a non-UTF-8 byte" || fail "simulate --label"

# Thresholds per call must be finite.
for option in "--valid-distance inf" "--valid-distance nan" "--valid-distance -1" "--threshold inf" "--threshold nan"; do
  expect_failure "assess $option" "must be a finite number" -- \
    "$ROADCROSS" assess --db "$WORK/map.gpkg" "${here[@]}" $option
done

# Unbounded work on the query side: each ends within seconds with a clear error.
# (CLI11 refuses "1e6" for an integer option; the same numbers written out reach the check.)
expect_failure "simulate --lanes 1000000" "lanes is 1e+06, must be in [1, 16]" -- \
  timeout 20 "$ROADCROSS" simulate --lanes 1000000 --runs 1
expect_failure "simulate --lanes 2000000000" "lanes is 2e+09, must be in [1, 16]" -- \
  timeout 20 "$ROADCROSS" simulate --lanes 2000000000 --runs 1
expect_failure "simulate --speed 1e-9" "robot speed (m/s) is 1e-09, must be in [0.1, 10]" -- \
  timeout 20 "$ROADCROSS" simulate --speed 1e-9 --runs 1
expect_failure "simulate --runs 1e9" "--runs is 1000000000, must be in [1, 100000]" -- \
  timeout 20 "$ROADCROSS" simulate --runs 1000000000
# 200 000 metadata rows: info --json in seconds, every row in the output.
db=$(damaged many_metadata "WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < 200000)
  INSERT INTO roadcross_metadata (key, value) SELECT printf('zz.%06d', i), 'x' FROM n")
start=$(date +%s)
timeout 60 "$ROADCROSS" info "$db" --json >"$WORK/many.json" &&
  python3 -c "import json; m = json.load(open('$WORK/many.json'))['metadata']; assert len(m) > 200000 and m['zz.200000'] == 'x'" &&
  pass "info --json, 200 000 metadata rows: $(($(date +%s) - start)) s" || fail "info --json with 200 000 metadata rows"
finish
