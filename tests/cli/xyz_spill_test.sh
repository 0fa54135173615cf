#!/usr/bin/env bash
# XYZ points past terrain.xyz_memory_mib are spilled to a temporary file next to the output
# (issue 8 item 3): on the Monaco map with points derived from its SRTM tile, a build with a
# tiny budget spills and gives the same terrain terms and stored grid as one that holds every
# point; and the spill file is gone after success, after an error and after Ctrl-C (it is
# unnamed from the start: only the running process can see it, in /proc/PID/fd).
source "$(dirname "$0")/lib.sh"
SCRIPTS="$(dirname "$0")/../../scripts"
MONACO_OSM="$ROADCROSS_MAPS_DIR/monaco/monaco.osm.pbf"
"$SCRIPTS/make-derived-xyz.sh" "$ROADCROSS_MAPS_DIR/monaco/N43E007.hgt" EPSG:32632 \
  "366000 4840500 379500 4848500" 30 comma "$WORK/monaco.csv"
common=(--osm "$MONACO_OSM" --elevation "$WORK/monaco.csv" --elevation-crs EPSG:32632
  --sight.enabled 0)
mkdir -p "$WORK/held" "$WORK/split" "$WORK/error" "$WORK/interrupted"

# --- success: same result, nothing left ----------------------------------------------------
"$ROADCROSS_BUILD" "${common[@]}" -o "$WORK/held/map.gpkg" --json >"$WORK/held.json"
"$ROADCROSS_BUILD" "${common[@]}" -o "$WORK/split/map.gpkg" --json \
  --terrain.xyz_memory_mib 0.2 >"$WORK/split.json"
[[ $(json_field "$WORK/held.json" terrain xyz_spilled_points) == 0 ]] ||
  fail "the default budget spilled"
spilled=$(json_field "$WORK/split.json" terrain xyz_spilled_points)
((spilled > 50000)) && pass "0.2 MiB budget: $spilled points spilled" || fail "spilled only $spilled"
differ=$(sqlite3 "$WORK/held/map.gpkg" "ATTACH '$WORK/split/map.gpkg' AS s;
  SELECT count(*) FROM main.segments a JOIN s.segments b USING (fid)
  WHERE a.elevation_m IS NOT b.elevation_m OR a.slope_deg IS NOT b.slope_deg
     OR a.grade_percent IS NOT b.grade_percent OR a.tpi_small_m IS NOT b.tpi_small_m
     OR a.tpi_large_m IS NOT b.tpi_large_m OR a.landform IS NOT b.landform
     OR a.elevation_cost IS NOT b.elevation_cost OR a.rank IS NOT b.rank")
with_z=$(sqlite3 "$WORK/split/map.gpkg" "SELECT count(*) FROM segments WHERE elevation_m IS NOT NULL")
[[ $differ == 0 && $with_z -gt 30000 ]] && pass "split = held on all $with_z segments with elevation" ||
  fail "$differ segments differ between the split and the held build ($with_z with elevation)"
tiles=$(sqlite3 "$WORK/held/map.gpkg" "ATTACH '$WORK/split/map.gpkg' AS s;
  SELECT count(*) FROM (SELECT tile_column, tile_row, tile_data FROM main.terrain
  EXCEPT SELECT tile_column, tile_row, tile_data FROM s.terrain)")
[[ $tiles == 0 ]] && pass "stored terrain grids identical" || fail "$tiles stored tiles differ"
[[ $(ls -A "$WORK/split") == map.gpkg ]] && pass "only the map left after success" ||
  fail "left after success: $(ls -A "$WORK/split")"

# --- an error after spilling: a bad line at the end of the file (points are read in chunks
# of 65 536, so the first chunk has been binned and spilled by then) ---------------------
cp "$WORK/monaco.csv" "$WORK/bad.csv"
echo "372000,4844000,not-a-number" >>"$WORK/bad.csv"
expect_failure "bad line after spilling" "bad.csv" "line $(wc -l <"$WORK/bad.csv")" -- \
  "$ROADCROSS_BUILD" --osm "$MONACO_OSM" --elevation "$WORK/bad.csv" --elevation-crs EPSG:32632 \
  -o "$WORK/error/map.gpkg" --terrain.xyz_memory_mib 0.2
[[ -z $(ls -A "$WORK/error") ]] && pass "nothing left after the error" ||
  fail "left after the error: $(ls -A "$WORK/error")"

# --- Ctrl-C while the spill file is open ---------------------------------------------------
"$ROADCROSS_BUILD" "${common[@]}" -o "$WORK/interrupted/map.gpkg" \
  --terrain.xyz_memory_mib 0.2 2>"$WORK/stderr" &
pid=$!
seen=""
for ((i = 0; i < 2000; i++)); do
  # The spill file: an fd into the output's directory of a file without a name.
  seen=$(find "/proc/$pid/fd" -lname "$WORK/interrupted/*(deleted)" 2>/dev/null | head -1) || true
  [[ -n $seen ]] && break
  sleep 0.005
done
[[ -n $seen ]] && pass "spill file open while running: $(readlink "$seen")" ||
  fail "no open spill file seen in /proc/$pid/fd"
kill -INT "$pid"
status=0
wait "$pid" || status=$?
[[ $status == 130 ]] && pass "SIGINT: exit 130" || fail "SIGINT: exit $status"
[[ -z $(ls -A "$WORK/interrupted") ]] && pass "nothing left after SIGINT" ||
  fail "left after SIGINT: $(ls -A "$WORK/interrupted")"
finish
