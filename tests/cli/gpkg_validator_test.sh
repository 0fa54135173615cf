#!/usr/bin/env bash
# GDAL's own GeoPackage validator (validate_gpkg.py -k, from Debian's python3-gdal) accepts the
# maps roadcross-build writes: with and without the terrain coverage, the bundled Prague map and
# the small hand-written test maps. -k also checks the extensions (R*Tree, gridded coverage,
# schema) and the layer_styles table.
source "$(dirname "$0")/lib.sh"
VALIDATOR=/usr/lib/python3/dist-packages/osgeo_utils/samples/validate_gpkg.py
[[ -f $VALIDATOR ]] || { echo "no $VALIDATOR: run scripts/setup.sh (python3-gdal)" >&2; exit 1; }

# validate NAME BUILD_ARGS...: builds a map and runs the validator on it.
validate() {
  local name=$1; shift
  "$ROADCROSS_BUILD" -q -o "$WORK/$name.gpkg" "$@"
  if python3 "$VALIDATOR" -k "$WORK/$name.gpkg" >"$WORK/$name.txt" 2>&1; then
    pass "$name: validate_gpkg.py -k accepts it"
  else
    fail "$name: validate_gpkg.py -k: $(cat "$WORK/$name.txt")"
  fi
}

validate prague-dem --osm "$PRAGUE_OSM" --elevation "$ROADCROSS_MAPS_DIR/prague/N50E014.hgt"
validate prague-flat --osm "$PRAGUE_OSM"
validate context-tags --osm "$ROADCROSS_TEST_DATA_DIR/context_tags.osm"
validate straight-road --osm "$ROADCROSS_TEST_DATA_DIR/install_straight_road.osm"

# The metadata table keeps its key readable by name (the runtime and scripts look rows up by key).
[[ $(sqlite3 "$WORK/prague-dem.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'utm_zone'") == 33 ]] &&
  pass "roadcross_metadata is read by key" || fail "roadcross_metadata: no utm_zone row by key"
"$ROADCROSS" info --db "$WORK/prague-dem.gpkg" >/dev/null 2>&1 || "$ROADCROSS" info "$WORK/prague-dem.gpkg" >/dev/null &&
  pass "the runtime opens the validated map" || fail "the runtime cannot open the validated map"
finish
