#!/usr/bin/env bash
# Every bundled map, with and without its SRTM rasters: the map_id roadcross-build stamps (the
# segments' digests computed from the rows it wrote, the other tables read back) is the one
# `roadcross verify` recomputes from the written file alone, and verify passes.
source "$(dirname "$0")/lib.sh"
M=$ROADCROSS_MAPS_DIR

# check LABEL BUILD-ARGS...
check() {
  local label=$1
  shift
  "$ROADCROSS_BUILD" "$@" -o "$WORK/map.gpkg" -q
  local stamped
  stamped=$(sqlite3 "$WORK/map.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'map_id'")
  if "$ROADCROSS" verify --db "$WORK/map.gpkg" >"$WORK/out" 2>&1 &&
    grep -q "ok, map_id $stamped," "$WORK/out"; then
    pass "$label: verify recomputes the stamped map_id $stamped"
  else
    fail "$label: stamped $stamped; verify: $(cat "$WORK/out")"
  fi
}

check "prague" --osm "$PRAGUE_OSM"
check "prague + SRTM" --osm "$PRAGUE_OSM" --elevation "$M/prague/N50E014.hgt"
check "monaco" --osm "$M/monaco/monaco.osm.pbf"
check "monaco + SRTM" --osm "$M/monaco/monaco.osm.pbf" --elevation "$M/monaco/N43E007.hgt"
check "bayreuth" --osm "$M/bayreuth/north-bayreuth.osm.gz"
check "bayreuth + SRTM" --osm "$M/bayreuth/north-bayreuth.osm.gz" \
  --elevation "$M/bayreuth/N49E011.hgt" --elevation "$M/bayreuth/N50E011.hgt"
check "techobuz" --osm "$M/techobuz/techobuz_2018.osm"
finish
