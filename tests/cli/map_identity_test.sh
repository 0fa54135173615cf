#!/usr/bin/env bash
# A map's identity: map_id is the SHA-256 content hash docs/embedding.md specifies, recomputed
# here by an independent implementation (Python's hashlib and sqlite3, from the documented
# encoding); the same inputs and parameters give the same id, another parameter another id;
# osm_timestamp is the newest OSM object's timestamp as osmium reads it, and absent when the
# input has no timestamps.
source "$(dirname "$0")/lib.sh"

id_of() { "$ROADCROSS" info --json "$1" | python3 -c 'import json,sys; print(json.load(sys.stdin)["map_id"])'; }

"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/a.gpkg" -q
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/b.gpkg" -q
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/c.gpkg" -q --segments.max_segment_length_m 12
a=$(id_of "$WORK/a.gpkg"); b=$(id_of "$WORK/b.gpkg"); c=$(id_of "$WORK/c.gpkg")
[[ $a =~ ^[0-9a-f]{64}$ ]] && pass "map_id is 64 hex digits: $a" || fail "map_id '$a'"
[[ $a == "$b" ]] && pass "two builds of the same inputs: same map_id" || fail "ids differ: $a $b"
[[ $a != "$c" ]] && pass "one parameter changed: another map_id" || fail "same id $a with 12 m segments"

# The documented encoding, implemented independently. Prints the recomputed map_id, then one
# line per column whose stored content.<table>.<column> digest differs.
recompute() {
  python3 - "$1" <<'PY'
import hashlib, sqlite3, struct, sys
db = sqlite3.connect(sys.argv[1])
tables = [("roadcross_metadata", "WHERE key <> 'map_id' AND key NOT LIKE 'content.%'", "key"),
          ("segments", "", "fid"), ("crossings", "", "fid"),
          ("terrain", "", "id"), ("gpkg_2d_gridded_tile_ancillary", "", "id")]
def sized(b):
    return struct.pack(">Q", len(b)) + b
def encode(v):
    if v is None: return b"N"
    if isinstance(v, int): return b"I" + struct.pack(">q", v)
    if isinstance(v, float): return b"R" + struct.pack(">d", v)
    if isinstance(v, str): return b"T" + sized(v.encode())
    return b"B" + sized(bytes(v))
stored = dict(db.execute("SELECT key, value FROM roadcross_metadata"))
top = hashlib.sha256()
for table, where, order in tables:
    if not db.execute("SELECT 1 FROM sqlite_master WHERE type='table' AND name=?", (table,)).fetchone():
        continue
    cols = [r[1] for r in db.execute(f"PRAGMA table_info('{table}')")]
    hashes = [hashlib.sha256() for _ in cols]
    for row in db.execute(f"SELECT {', '.join(cols)} FROM {table} {where} ORDER BY {order}"):
        for h, v in zip(hashes, row):
            h.update(encode(v))
    for col, h in zip(cols, hashes):
        if stored.get(f"content.{table}.{col}") != h.hexdigest():
            print(f"differs: {table}.{col}", file=sys.stderr)
        top.update(sized(table.encode()) + sized(col.encode()) + h.digest())
print(top.hexdigest())
PY
}
recomputed=$(recompute "$WORK/a.gpkg" 2>"$WORK/differs")
[[ $recomputed == "$a" ]] && pass "map_id recomputed independently from the documented encoding" ||
  fail "recomputed $recomputed, stored $a"
[[ ! -s $WORK/differs ]] && pass "every content.* digest recomputed independently" ||
  fail "digests differ: $(cat "$WORK/differs")"

# With elevation the terrain grid is part of the content too.
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" --elevation "$ROADCROSS_MAPS_DIR/prague/N50E014.hgt" \
  -o "$WORK/dem.gpkg" -q
dem=$(id_of "$WORK/dem.gpkg")
[[ $(recompute "$WORK/dem.gpkg" 2>"$WORK/differs") == "$dem" && ! -s $WORK/differs ]] &&
  grep -q "terrain" <(sqlite3 "$WORK/dem.gpkg" "SELECT key FROM roadcross_metadata WHERE key LIKE 'content.terrain.%'") &&
  pass "with elevation: the terrain table hashed, map_id recomputed independently" ||
  fail "with elevation: recomputed $(recompute "$WORK/dem.gpkg" 2>&1) vs $dem"

# osm_timestamp: the newest timestamp osmium reads in the file, to the second, ISO 8601 UTC.
newest=$(osmium fileinfo -e -g data.timestamp.last "$PRAGUE_OSM")
got=$("$ROADCROSS" info --json "$WORK/a.gpkg" | python3 -c 'import json,sys; print(json.load(sys.stdin)["osm_timestamp"])')
[[ $got == "$newest" ]] && pass "osm_timestamp $got = osmium's newest timestamp" ||
  fail "osm_timestamp $got, osmium says $newest"
text=$("$ROADCROSS" info "$WORK/a.gpkg")  # (read whole: grep -q on the pipe could cut it)
grep -q "^OSM data as of  $newest\$" <<<"$text" && pass "info text: OSM data as of" ||
  fail "info text lacks 'OSM data as of $newest'"
grep -q "^map id          $a\$" <<<"$text" && pass "info text: map id" ||
  fail "info text lacks the map id"
# Without timestamps (osmium writes none with add_metadata=false): no osm_timestamp at all.
osmium cat -f osm,add_metadata=false "$PRAGUE_OSM" -o "$WORK/bare.osm"
"$ROADCROSS_BUILD" --osm "$WORK/bare.osm" -o "$WORK/bare.gpkg" -q
got=$("$ROADCROSS" info --json "$WORK/bare.gpkg" | python3 -c 'import json,sys; print(json.load(sys.stdin)["osm_timestamp"])')
rows=$(sqlite3 "$WORK/bare.gpkg" "SELECT count(*) FROM roadcross_metadata WHERE key = 'osm_timestamp'")
[[ $got == None && $rows == 0 ]] && pass "no timestamps in the input: osm_timestamp absent (JSON null)" ||
  fail "no timestamps: osm_timestamp '$got', $rows rows"
finish
