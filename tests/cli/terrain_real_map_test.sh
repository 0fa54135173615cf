#!/usr/bin/env bash
# Terrain on the bundled real maps: the SRTM raster path and the XYZ path (points derived from
# the same SRTM tile with GDAL, reprojected to S-JTSK space-separated for Prague and to UTM 32N
# comma-separated for Monaco) agree, segment by segment, to a median of 1 m; the raster path
# agrees with GDAL's own reading of the tile (gdallocationinfo); Monaco's coastal voids are
# filled; bad elevation input fails cleanly.
source "$(dirname "$0")/lib.sh"
SCRIPTS="$(dirname "$0")/../../scripts"
MONACO_OSM="$ROADCROSS_MAPS_DIR/monaco/monaco.osm.pbf"

# median_abs_difference DB_A DB_B COLUMN: median over segments of |A - B| where both are set.
median_abs_difference() {
  sqlite3 "$1" "ATTACH '$2' AS other;
    SELECT abs(a.$3 - b.$3) FROM main.segments a JOIN other.segments b ON a.fid = b.fid
    WHERE a.$3 IS NOT NULL AND b.$3 IS NOT NULL ORDER BY 1" |
    awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}

# --- Prague: raster vs S-JTSK XYZ (detected, no --elevation-crs) --------------------------
"$SCRIPTS/make-derived-xyz.sh" "$ROADCROSS_MAPS_DIR/prague/N50E014.hgt" EPSG:5514 \
  "-745000 -1046000 -741000 -1042500" 30 space "$WORK/prague_sjtsk.xyz"
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/raster.gpkg" \
  --elevation "$ROADCROSS_MAPS_DIR/prague/N50E014.hgt" >"$WORK/raster.txt"
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/xyz.gpkg" --json \
  --elevation "$WORK/prague_sjtsk.xyz" >"$WORK/xyz.json"
[[ $(json_field "$WORK/xyz.json" terrain xyz_crs) == EPSG:5514 ]] && pass "S-JTSK detected" ||
  fail "XYZ CRS: $(json_field "$WORK/xyz.json" terrain xyz_crs)"
[[ $(sqlite3 "$WORK/xyz.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'input.1.crs'") == EPSG:5514 ]] ||
  fail "the DB does not record the XYZ CRS"
median=$(median_abs_difference "$WORK/raster.gpkg" "$WORK/xyz.gpkg" elevation_m)
near "$median" 0 1.0 && pass "Prague raster vs XYZ: median |dz| $median m" ||
  fail "Prague raster vs XYZ: median |dz| $median m > 1 m"
# The same points comma-separated give the same DB contents as space-separated ones.
tr ' ' ',' <"$WORK/prague_sjtsk.xyz" >"$WORK/prague_sjtsk_comma.csv"
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/xyz_comma.gpkg" -q \
  --elevation "$WORK/prague_sjtsk_comma.csv"
same=$(sqlite3 "$WORK/xyz.gpkg" "ATTACH '$WORK/xyz_comma.gpkg' AS c; SELECT count(*) FROM main.segments a
  JOIN c.segments b ON a.fid = b.fid WHERE a.elevation_m = b.elevation_m AND a.landform = b.landform")
[[ $same == $(sqlite3 "$WORK/xyz.gpkg" "SELECT count(*) FROM segments") ]] &&
  pass "comma- and space-separated S-JTSK points agree on all $same segments" ||
  fail "comma vs space: only $same segments agree"
none=$(sqlite3 "$WORK/raster.gpkg" "SELECT count(*) FROM segments WHERE elevation_m IS NULL")
[[ $none == 0 ]] && pass "every Prague segment has elevation" || fail "$none Prague segments lack elevation"

# Independent reading: GDAL's value of the tile's pixel under each segment's midpoint (nearest
# pixel, 90 m: the median over the map must still be within a couple of metres).
sqlite3 -separator ' ' "$WORK/raster.gpkg" \
  "SELECT id, (MinX + MaxX) / 2, (MinY + MaxY) / 2 FROM rtree_segments_geom WHERE id % 20 = 0 ORDER BY id" \
  >"$WORK/mid_utm"
cut -d' ' -f2,3 "$WORK/mid_utm" | gdaltransform -s_srs EPSG:32633 -t_srs EPSG:4326 |
  cut -d' ' -f1,2 | gdallocationinfo -valonly -wgs84 "$ROADCROSS_MAPS_DIR/prague/N50E014.hgt" \
  >"$WORK/gdal_z"
sqlite3 "$WORK/raster.gpkg" "SELECT elevation_m FROM segments WHERE fid % 20 = 0 ORDER BY fid" >"$WORK/our_z"
gdal_median=$(paste "$WORK/our_z" "$WORK/gdal_z" | awk '{ d = $1 - $2; print (d < 0 ? -d : d) }' |
  sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }')
near "$gdal_median" 0 2.0 && pass "raster vs gdallocationinfo: median |dz| $gdal_median m" ||
  fail "raster vs gdallocationinfo: median |dz| $gdal_median m"

# The terrain cell size follows the raster: N50E014.hgt has 3" pixels, at Prague (50.08 N,
# 0.4 degrees from zone 33's central meridian: UTM scale ~0.9996) 3 x 19.88 = 59.6 m east-west
# and 3 x 30.90 = 92.7 m north-south (WGS84: pi/180/3600 N(phi) cos(phi), resp. M(phi)); the
# finer side floored, 59 m, is above the ceiling floor(tpi_small_outer_m 50 / 2) = 25 m. The
# summary names the size and its source; a given value (flag or parameter file) is used as is.
grep -q '^  terrain grid cell size: 25 m (automatic: finest raster N50E014.hgt: 59\.[0-9]* x 92\.[0-9]* m' \
  "$WORK/raster.txt" && pass "Prague: automatic 25 m cells named in the summary" ||
  fail "Prague cell size line: $(grep 'cell size' "$WORK/raster.txt")"
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/given.gpkg" --json --sight.enabled 0 \
  --elevation "$ROADCROSS_MAPS_DIR/prague/N50E014.hgt" --terrain.cell_size_m 10 >"$WORK/given.json"
[[ $(json_field "$WORK/given.json" terrain cell_m) == 10* &&
  $(json_field "$WORK/given.json" terrain cell_size_source) == "given (terrain.cell_size_m)" ]] &&
  grep -q '"terrain grid cell size: 10 m (given (terrain.cell_size_m))"' "$WORK/given.json" &&
  pass "--terrain.cell_size_m 10 is used as given (JSON)" ||
  fail "given cell size: $(json_field "$WORK/given.json" terrain cell_m) $(json_field "$WORK/given.json" terrain cell_size_source)"
printf '[terrain]\ncell_size_m = 12\n' >"$WORK/cell12.toml"
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/given.gpkg" --config "$WORK/cell12.toml" \
  --sight.enabled 0 --elevation "$ROADCROSS_MAPS_DIR/prague/N50E014.hgt" >"$WORK/given.txt"
grep -q '^  terrain grid cell size: 12 m (given' "$WORK/given.txt" &&
  [[ $(sqlite3 "$WORK/given.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'param.terrain.cell_size_m'") == 12 ]] &&
  pass "a parameter file's cell size is used as given" || fail "parameter file cell size: $(grep 'cell size' "$WORK/given.txt")"
[[ $(sqlite3 "$WORK/raster.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'param.terrain.cell_size_m'") == 25 ]] &&
  pass "the DB records the 25 m used" || fail "the DB does not record the cell size used"

# The terrain grid is in the DB as a GeoPackage gridded coverage that GDAL reads: its cell
# under a segment's midpoint holds (to within the grid's local relief) the segment's
# elevation, and gdaldem can shade it.
gdalinfo "GPKG:$WORK/raster.gpkg:terrain" >"$WORK/terrain_info" 2>&1 || fail "gdalinfo cannot open the terrain grid"
grep -q 'Pixel Size = (25.000000000000000,-25.000000000000000)' "$WORK/terrain_info" &&
  pass "terrain grid: 25 m cells" || fail "terrain grid: $(grep 'Pixel Size' "$WORK/terrain_info")"
cut -d' ' -f2,3 "$WORK/mid_utm" | gdallocationinfo -valonly -geoloc "GPKG:$WORK/raster.gpkg:terrain" >"$WORK/grid_z"
grid_median=$(paste "$WORK/our_z" "$WORK/grid_z" | awk '{ d = $1 - $2; print (d < 0 ? -d : d) }' |
  sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }')
near "$grid_median" 0 0.5 && pass "segments vs stored terrain grid: median |dz| $grid_median m" ||
  fail "segments vs stored terrain grid: median |dz| $grid_median m"
gdaldem hillshade -q "GPKG:$WORK/raster.gpkg:terrain" "$WORK/hillshade.tif" && pass "gdaldem shades the grid" ||
  fail "gdaldem hillshade failed"

# --- Monaco: raster with coastal voids vs UTM 32N comma-separated XYZ ----------------------
"$SCRIPTS/make-derived-xyz.sh" "$ROADCROSS_MAPS_DIR/monaco/N43E007.hgt" EPSG:32632 \
  "366000 4840500 379500 4848500" 30 comma "$WORK/monaco_utm.csv"
"$ROADCROSS_BUILD" --osm "$MONACO_OSM" -o "$WORK/monaco_raster.gpkg" --json \
  --elevation "$ROADCROSS_MAPS_DIR/monaco/N43E007.hgt" >"$WORK/monaco.json"
"$ROADCROSS_BUILD" --osm "$MONACO_OSM" -o "$WORK/monaco_xyz.gpkg" -q \
  --elevation "$WORK/monaco_utm.csv" --elevation-crs EPSG:32632
voids=$(json_field "$WORK/monaco.json" terrain voids_filled)
((voids > 0)) && pass "Monaco: $voids void cells filled" || fail "Monaco: no void filled"
missing=$(json_field "$WORK/monaco.json" terrain segments_without_elevation)
total=$(json_field "$WORK/monaco.json" segments)
((missing * 100 < total)) && pass "Monaco: $missing of $total segments without elevation" ||
  fail "Monaco: $missing of $total segments without elevation"
median=$(median_abs_difference "$WORK/monaco_raster.gpkg" "$WORK/monaco_xyz.gpkg" elevation_m)
near "$median" 0 1.0 && pass "Monaco raster vs XYZ: median |dz| $median m" ||
  fail "Monaco raster vs XYZ: median |dz| $median m > 1 m"
# Bridges take their elevation from their ends: a bridge segment lies between the elevations
# of the segments at its ends, never in the valley below (checked over the whole map).
bad_bridges=$(sqlite3 "$WORK/monaco_raster.gpkg" "SELECT count(*) FROM segments
  WHERE bridge = 1 AND tunnel = 0 AND (landform IS NOT 'bridge' OR tpi_small_m IS NOT NULL)")
[[ $bad_bridges == 0 ]] && pass "bridges are not sampled from the DEM" ||
  fail "$bad_bridges bridge segments sampled from the DEM"
crest=$(sqlite3 "$WORK/monaco_raster.gpkg" "SELECT count(*) FROM segments WHERE reasons LIKE '%CREST_OR_DIP%'")
((crest > 0)) && pass "Monaco: $crest segments on crests or in dips" || fail "no CREST_OR_DIP in Monaco"

# --- bad input ----------------------------------------------------------------------------
printf 'X Y Z\n-744985 -1042515 276.1\n-744955 oops 276.2\n' >"$WORK/bad.xyz"
expect_failure "bad XYZ line" "bad.xyz: line 3: expected three numbers" -- \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/bad.gpkg" -q --elevation "$WORK/bad.xyz"
[[ ! -e "$WORK/bad.gpkg" ]] || fail "a DB was left after a bad XYZ file"
head -c 1000 "$ROADCROSS_MAPS_DIR/prague/N50E014.hgt" >"$WORK/N50E014.hgt"
expect_failure "truncated raster" "N50E014.hgt" -- \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/bad.gpkg" -q --elevation "$WORK/N50E014.hgt"
expect_failure "DEM of another place" "does not overlap the roads" -- \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/bad.gpkg" -q \
  --elevation "$ROADCROSS_MAPS_DIR/monaco/N43E007.hgt"
printf '458000 5547000 200\n458010 5547000 201\n458000 5547010 202\n' >"$WORK/utm.xyz"
expect_failure "XYZ CRS not detectable" "utm.xyz: cannot tell the coordinate system" \
  "--elevation-crs" -- \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/bad.gpkg" -q --elevation "$WORK/utm.xyz"
expect_failure "unknown CRS" "--elevation-crs EPSG:999999" -- \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/bad.gpkg" -q --elevation "$WORK/utm.xyz" \
  --elevation-crs EPSG:999999
expect_failure "missing elevation file" "nothing.tif" -- \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/bad.gpkg" -q --elevation "$WORK/nothing.tif"
[[ ! -e "$WORK/bad.gpkg" ]] || fail "a DB was left after bad elevation input"

exit $((FAILURES > 0))
