#!/usr/bin/env bash
# Hostile and unlucky inputs to roadcross-build (issue 24, docs/reliability.md): never an abort,
# never a replaced device node, never minutes of work on a small file, and what a killed build
# left is cleaned by the next one.
source "$(dirname "$0")/lib.sh"
SMALL="$ROADCROSS_TEST_DATA_DIR/context_tags.osm"
out="$WORK/out/map.gpkg"
mkdir -p "$WORK/out"

# --- output path and parameter file -----------------------------------------------------------
expect_usage() {  # exit status 2 (a usage error), never 134 (an uncaught exception)
  local name=$1 text=$2; shift 2
  local status=0
  "$@" >"$WORK/stdout" 2>"$WORK/stderr" || status=$?
  if ((status == 2)) && grep -qF -- "$text" "$WORK/stderr"; then
    pass "$name (exit 2): $(head -c 160 "$WORK/stderr")"
  else
    fail "$name: exit $status, stderr: $(head -c 300 "$WORK/stderr")"
  fi
}
expect_usage "-o ''" "an empty name" "$ROADCROSS_BUILD" --osm "$SMALL" -o ''
expect_usage "--config /dev/zero" "not a regular file" "$ROADCROSS_BUILD" --osm "$SMALL" -o "$out" --config /dev/zero
expect_usage "--config DIRECTORY" "is a folder" "$ROADCROSS_BUILD" --osm "$SMALL" -o "$out" --config "$WORK"
head -c 2000000 /dev/zero | tr '\0' '#' >"$WORK/huge.toml"
expect_usage "--config of 2 MB" "larger than 1048576 bytes" "$ROADCROSS_BUILD" --osm "$SMALL" -o "$out" --config "$WORK/huge.toml"

# --- never rename over what is not a regular file (a private node, never the machine's own) ----
mknod "$WORK/out/null" c 1 3
expect_failure "-o character device" "$WORK/out/null" "a character device, not a regular file" -- \
  "$ROADCROSS_BUILD" -q --osm "$SMALL" -o "$WORK/out/null"
[[ -c "$WORK/out/null" ]] && pass "the device node is still a device node" || fail "device node replaced"
mkfifo "$WORK/out/fifo"
expect_failure "-o FIFO" "a FIFO, not a regular file" -- "$ROADCROSS_BUILD" -q --osm "$SMALL" -o "$WORK/out/fifo"
[[ -p "$WORK/out/fifo" ]] && pass "the FIFO is still a FIFO" || fail "FIFO replaced"
echo keep >"$WORK/target.txt"
ln -s "$WORK/target.txt" "$WORK/out/link.gpkg"
expect_failure "-o symbolic link" "a symbolic link" -- "$ROADCROSS_BUILD" -q --osm "$SMALL" -o "$WORK/out/link.gpkg"
[[ -L "$WORK/out/link.gpkg" && $(cat "$WORK/target.txt") == keep ]] && pass "the link and its file are untouched" || fail "link replaced"
if compgen -G "$WORK/out/*.tmp-*" >/dev/null; then fail "temporary files left: $(ls "$WORK/out")"; fi
rm -f "$WORK/out/null" "$WORK/out/fifo" "$WORK/out/link.gpkg"

# --- what a killed build left: removed by the next build, and only that -------------------------
"$ROADCROSS_BUILD" -q --osm "$SMALL" -o "$out"
cp "$out" "$WORK/out/old.gpkg.tmp-Dead01"      # a dead build's GeoPackage (no lock held)
cp "$out" "$WORK/out/old.gpkg.tmp-Dead01-rows"  # ... and its side file
cp "$out" "$WORK/out/live.gpkg.tmp-Live01"      # a running build's: locked below
echo "a user's file" >"$WORK/out/notes.tmp-abcdef"  # the same name pattern, not a GeoPackage
flock "$WORK/out/live.gpkg.tmp-Live01" sleep 60 &
holder=$!
sleep 0.5
"$ROADCROSS_BUILD" --osm "$SMALL" -o "$out" >"$WORK/stdout" 2>"$WORK/stderr"
kill "$holder" 2>/dev/null || true
wait "$holder" 2>/dev/null || true
[[ ! -e "$WORK/out/old.gpkg.tmp-Dead01" && ! -e "$WORK/out/old.gpkg.tmp-Dead01-rows" ]] &&
  pass "a dead build's files removed" || fail "dead build's files kept: $(ls "$WORK/out")"
grep -qF "removed $WORK/out/old.gpkg.tmp-Dead01, left by a build that was killed" "$WORK/stdout" &&
  pass "the build says what it removed" || fail "no note of the removal: $(cat "$WORK/stdout")"
[[ -e "$WORK/out/live.gpkg.tmp-Live01" ]] && pass "a running build's (locked) file kept" || fail "a locked file was removed"
[[ -e "$WORK/out/notes.tmp-abcdef" ]] && pass "a file that is no GeoPackage kept" || fail "a user's file was removed"
rm -f "$WORK/out/live.gpkg.tmp-Live01" "$WORK/out/notes.tmp-abcdef"

# A real SIGKILL during a build, then a build in the same folder. Monaco with its DEM: its
# temporary file holds pages for a few tenths of a second before the rename (Prague's for ~50 ms,
# too short to catch under load); a build that still finishes first is tried again.
MONACO_OSM="$ROADCROSS_MAPS_DIR/monaco/monaco.osm.pbf"
MONACO_DEM="$ROADCROSS_MAPS_DIR/monaco/N43E007.hgt"
for attempt in 1 2 3 4 5; do
  "$ROADCROSS_BUILD" -q --osm "$MONACO_OSM" --elevation "$MONACO_DEM" -o "$WORK/out/killed.gpkg" &
  builder=$!
  for _ in $(seq 1 600); do
    # killed once the writer has written into its temporary file
    if compgen -G "$WORK/out/killed.gpkg.tmp-*" >/dev/null &&
       [[ -n $(find "$WORK/out" -name 'killed.gpkg.tmp-*' -size +0) ]]; then
      break
    fi
    sleep 0.02
  done
  kill -KILL "$builder" 2>/dev/null || true
  wait "$builder" 2>/dev/null || true
  compgen -G "$WORK/out/killed.gpkg.tmp-*" >/dev/null && break
  rm -f "$WORK/out/killed.gpkg"
done
if compgen -G "$WORK/out/killed.gpkg.tmp-*" >/dev/null; then
  pass "SIGKILL left $(cd "$WORK/out" && ls killed.gpkg.tmp-* | tr '\n' ' ')(attempt $attempt)"
  "$ROADCROSS_BUILD" -q --osm "$SMALL" -o "$out"
  compgen -G "$WORK/out/*.tmp-*" >/dev/null && fail "the next build left them: $(ls "$WORK/out")" ||
    pass "the next build removed them"
else
  fail "the build finished before it could be killed, 5 times (no temporary file seen)"
fi

# --- elevation rasters out of range -------------------------------------------------------------
# Prague's OSM lies in N50E014: a .hgt of that name holding random bytes (SRTM3: 1201 x 1201
# big-endian int16, so nearly every pixel is outside [-500, 9000] m).
head -c 2884802 /dev/urandom >"$WORK/N50E014.hgt"
expect_failure "random-byte .hgt" "$WORK/N50E014.hgt" "outside [-500, 9000] m" -- \
  "$ROADCROSS_BUILD" -q --osm "$PRAGUE_OSM" -o "$out.hgt.gpkg" --elevation "$WORK/N50E014.hgt"
# A raster of 1e38 m over Prague (a float GeoTIFF made from an ASCII grid).
python3 - "$WORK/huge.asc" <<'PY'
import sys
with open(sys.argv[1], "w") as f:
    f.write("ncols 20\nnrows 20\nxllcorner 14.40\nyllcorner 50.06\ncellsize 0.003\n")
    for _ in range(20):
        f.write(" ".join(["1e38"] * 20) + "\n")
PY
gdal_translate -q -a_srs EPSG:4326 -ot Float32 "$WORK/huge.asc" "$WORK/huge.tif"
expect_failure "raster of 1e38 m" "$WORK/huge.tif" "outside [-500, 9000] m" -- \
  "$ROADCROSS_BUILD" -q --osm "$PRAGUE_OSM" -o "$out.tif.gpkg" --elevation "$WORK/huge.tif"
[[ ! -e "$out.hgt.gpkg" && ! -e "$out.tif.gpkg" ]] && pass "no map written from them" || fail "a map was written"

# --- overrides ----------------------------------------------------------------------------------
feature() {  # feature PROPERTIES [GEOMETRY]
  printf '{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": %s, "properties": %s}]}' \
    "${2:-null}" "$1"
}
feature '{"osm_way_id": 1, "context_delta": 18446744073709551615}' >"$WORK/wrap.geojson"
expect_failure "context_delta 2^64-1" "$WORK/wrap.geojson" "feature 0" "context_delta must be an integer in [-1000, 1000]" -- \
  "$ROADCROSS_BUILD" -q --osm "$SMALL" -o "$out" --overrides "$WORK/wrap.geojson"
feature "{\"osm_way_id\": 1, \"context_delta\": 1, \"note\": \"$(head -c 5000000 /dev/zero | tr '\0' 'x')\"}" >"$WORK/note.geojson"
expect_failure "5 MB note" "$WORK/note.geojson" "feature 0" "note is 5000000 bytes long; at most 500" -- \
  "$ROADCROSS_BUILD" -q --osm "$SMALL" -o "$out" --overrides "$WORK/note.geojson"
feature '{"no_crossing": true}' '{"type": "Polygon", "coordinates": [[[100, 10], [100.1, 10], [100.1, 10.1], [100, 10]]]}' >"$WORK/far.geojson"
expect_failure "polygon outside the UTM zone" "$WORK/far.geojson" "feature 0" "outside the map's UTM zone" -- \
  "$ROADCROSS_BUILD" -q --osm "$SMALL" -o "$out" --overrides "$WORK/far.geojson"
# A number beyond a double (found by the overrides fuzz target): an error, not an abort.
feature '{"osm_way_id": 999E99999}' >"$WORK/overflow.geojson"
expect_failure "number overflow" "$WORK/overflow.geojson" "not valid JSON" "number overflow" -- \
  "$ROADCROSS_BUILD" -q --osm "$SMALL" -o "$out" --overrides "$WORK/overflow.geojson"
# 1 100 features of +1000 on way 1: the context score would be ~1.1e6 above its base; it is
# clamped at 1 000 000 (an int stays far from overflow wherever score + context is summed).
python3 - "$WORK/many.geojson" <<'PY'
import json, sys
features = [{"type": "Feature", "geometry": None,
             "properties": {"osm_way_id": 1, "context_delta": 1000, "note": "n%d" % i}}
            for i in range(1100)]
json.dump({"type": "FeatureCollection", "features": features}, open(sys.argv[1], "w"))
PY
"$ROADCROSS_BUILD" -q --osm "$SMALL" -o "$WORK/many.gpkg" --overrides "$WORK/many.geojson"
read -r max_score max_note < <(sqlite3 -separator ' ' "$WORK/many.gpkg" \
  "SELECT max(context_score), max(length(override_note)) FROM segments WHERE osm_way_id = 1")
[[ $max_score == 1000000 ]] && pass "context score clamped at 1000000" || fail "context score $max_score"
((max_note <= 2000)) && pass "segment note bounded ($max_note bytes)" || fail "segment note $max_note bytes"

# --- a way that retraces two nodes 100 000 times -------------------------------------------------
python3 - "$WORK/retrace.osm" <<'PY'
import sys
with open(sys.argv[1], "w") as f:
    f.write('<?xml version="1.0"?>\n<osm version="0.6">\n'
            '<node id="1" lat="50.08" lon="14.42" version="1"/>\n'
            '<node id="2" lat="50.0801" lon="14.4201" version="1"/>\n<way id="10" version="1">\n')
    f.write('<nd ref="1"/>\n<nd ref="2"/>\n' * 100000)
    f.write('<tag k="highway" v="residential"/>\n</way>\n</osm>\n')
PY
status=0
timeout 60 "$ROADCROSS_BUILD" -q --osm "$WORK/retrace.osm" -o "$WORK/retrace.gpkg" || status=$?
if ((status == 0)); then
  # One road between the nodes: 0.0001 deg of latitude (11.13 m) and of longitude at 50.08 deg
  # (7.15 m) apart, 13.2 m, cut into ceil(13.2 / 8) = 2 segments of at most 8 m.
  read -r count length < <(sqlite3 -separator ' ' "$WORK/retrace.gpkg" "SELECT count(*), round(sum(length_m), 1) FROM segments")
  [[ $count == 2 && $length == 13.2 ]] && pass "retraced way: one road of 13.2 m in 2 segments, in under 60 s" ||
    fail "retraced way: $count segments, $length m"
else
  fail "retraced way: exit $status (124: still working after 60 s)"
fi
finish
