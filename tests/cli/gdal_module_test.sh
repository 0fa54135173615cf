#!/usr/bin/env bash
# GDAL is loaded only for elevation input (libroadcross_gdal.so, opened on demand): a build
# without elevation loads neither the module nor libgdal and needs neither; a build with a
# raster loads both; the module is found beside a copied roadcross-build; a module that is
# missing, or another library in its place, fails the build at once with a message naming the
# path and ROADCROSS_GDAL_MODULE, exit 1, and the existing output untouched.
source "$(dirname "$0")/lib.sh"
dem="$ROADCROSS_MAPS_DIR/prague/N50E014.hgt"
module="$(dirname "$ROADCROSS_BUILD")/libroadcross_gdal.so"
[[ -f $module ]] || fail "no module beside roadcross-build: $module"

# loaded NAME LIBRARY: the dynamic loader's log ($WORK/NAME.ld) shows LIBRARY opened.
loaded() { grep -q "file=$2 \[" "$WORK/$1.ld"; }

LD_DEBUG=files "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/plain.gpkg" -q 2>"$WORK/plain.ld" ||
  fail "plain build: exit $?"
loaded plain 'libgdal.so[^ ]*' && fail "a build without elevation loaded libgdal" ||
  pass "a build without elevation loads no libgdal"
loaded plain '[^ ]*libroadcross_gdal.so' && fail "a build without elevation loaded the module" ||
  pass "a build without elevation loads no module"

LD_DEBUG=files "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" --elevation "$dem" -o "$WORK/dem.gpkg" -q \
  2>"$WORK/dem.ld" || fail "build with elevation: exit $?"
loaded dem 'libgdal.so[^ ]*' && pass "a build with a raster loads libgdal" ||
  fail "a build with a raster did not load libgdal"
loaded dem "$module" && pass "... through the module beside roadcross-build" ||
  fail "the module beside roadcross-build was not the one loaded"
[[ $(sqlite3 "$WORK/dem.gpkg" "SELECT count(*) FROM segments WHERE tpi_small_m IS NOT NULL") -gt 0 ]] &&
  pass "the terrain terms are there" || fail "no segment has a TPI"

# Without elevation the module is not needed at all.
ROADCROSS_GDAL_MODULE="$WORK/missing.so" "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" \
  -o "$WORK/no_module.gpkg" -q || fail "a build without elevation and without module: exit $?"
cmp -s <(sqlite3 "$WORK/plain.gpkg" "SELECT value FROM roadcross_metadata WHERE key='map_id'") \
  <(sqlite3 "$WORK/no_module.gpkg" "SELECT value FROM roadcross_metadata WHERE key='map_id'") &&
  pass "without elevation, no module is needed (same map)" || fail "another map without the module"

# A copy of roadcross-build with the module beside it uses that one.
mkdir "$WORK/bin"
cp "$ROADCROSS_BUILD" "$module" "$WORK/bin/"
LD_DEBUG=files "$WORK/bin/roadcross-build" --osm "$PRAGUE_OSM" --elevation "$dem" \
  -o "$WORK/copy.gpkg" -q 2>"$WORK/copy.ld" || fail "copied build: exit $?"
loaded copy "$WORK/bin/libroadcross_gdal.so" && pass "a copied roadcross-build uses the module beside it" ||
  fail "a copied roadcross-build did not use the module beside it"

# A missing module, or a library that is not one: exit 1 at once, the old output untouched.
echo "an earlier map" >"$WORK/kept.gpkg"
expect_failure "missing module" "$WORK/missing.so" "ROADCROSS_GDAL_MODULE" \
  "elevation input needs" -- env ROADCROSS_GDAL_MODULE="$WORK/missing.so" \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" --elevation "$dem" -o "$WORK/kept.gpkg"
libz=$(ldd "$ROADCROSS_BUILD" | awk '$1 == "libz.so.1" {print $3}')
expect_failure "another library as the module" "$libz" "not a roadcross GDAL module" -- \
  env ROADCROSS_GDAL_MODULE="$libz" "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" --elevation "$dem" \
  -o "$WORK/kept.gpkg"
[[ $(cat "$WORK/kept.gpkg") == "an earlier map" ]] && pass "the earlier output is untouched" ||
  fail "the earlier output was changed"
[[ -z $(compgen -G "$WORK/kept.gpkg.tmp-*") ]] && pass "no temporary file is left" ||
  fail "a temporary file is left"
finish
