#!/usr/bin/env bash
# render, export and view run in roadcross-viz: roadcross lists them and hands every argument on,
# so that roadcross itself loads neither Cairo nor GDAL (their loading took ~80 ms of every query).
source "$(dirname "$0")/lib.sh"

# roadcross links neither library; roadcross-viz, beside it, does.
viz="$(dirname "$ROADCROSS")/roadcross-viz"
# (ldd's output read whole: grep -q on its pipe would stop it with SIGPIPE under pipefail)
roadcross_libraries=$(ldd "$ROADCROSS")
viz_libraries=$(ldd "$viz")
if grep -Eq 'libgdal|libcairo' <<<"$roadcross_libraries"; then fail "roadcross links GDAL or Cairo"; else pass "roadcross links neither GDAL nor Cairo"; fi
grep -q libgdal <<<"$viz_libraries" && pass "roadcross-viz links GDAL" || fail "roadcross-viz lacks GDAL"

# Each drawing command's own help (its options), through roadcross.
grep -q -- '--color-by' <("$ROADCROSS" render --help) && pass "render --help is render's" || fail "render --help"
grep -q -- '--layer' <("$ROADCROSS" export --help) && pass "export --help is export's" || fail "export --help"
grep -q 'Usage: roadcross view' <("$ROADCROSS" view --help) && pass "view --help names roadcross view" || fail "view --help"

# Arguments and the exit status pass through: a missing DB is named, and the call fails.
expect_failure "render of a missing DB" "$WORK/none.gpkg" "no such file" -- \
  "$ROADCROSS" render --db "$WORK/none.gpkg" -o "$WORK/x.png"
# A whole drawing through roadcross: the PNG is written.
"$ROADCROSS_BUILD" --osm "$ROADCROSS_TEST_DATA_DIR/install_straight_road.osm" -o "$WORK/map.gpkg" -q
"$ROADCROSS" render --db "$WORK/map.gpkg" -o "$WORK/map.png" --width 300 >/dev/null &&
  [[ $(head -c 8 "$WORK/map.png" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] &&
  pass "render through roadcross writes a PNG" || fail "render through roadcross"

# Without roadcross-viz beside it, roadcross says what is missing.
cp "$ROADCROSS" "$WORK/roadcross"
expect_failure "render without roadcross-viz" "cannot run $WORK/roadcross-viz" "full build" -- \
  "$WORK/roadcross" render --db "$WORK/map.gpkg" -o "$WORK/y.png"
finish
