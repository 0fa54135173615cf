#!/usr/bin/env bash
# render, export and view write like the build (issue 24, docs/reliability.md): never onto a
# device node or FIFO, never a truncated file on a full disk (the old file stays), and a view that
# fails leaves no half-written folder. The full disk is a private 1 MiB tmpfs, unmounted on exit;
# a private 6 MiB one fills during a build.
source "$(dirname "$0")/lib.sh"
map="$WORK/small.gpkg"
"$ROADCROSS_BUILD" -q --osm "$ROADCROSS_TEST_DATA_DIR/context_tags.osm" -o "$map"

mknod "$WORK/null" c 1 3
mkfifo "$WORK/fifo"
expect_failure "render -o device" "a character device, not a regular file" -- "$ROADCROSS" render --db "$map" -o "$WORK/null"
expect_failure "export -o device" "a character device, not a regular file" -- "$ROADCROSS" export --db "$map" -o "$WORK/null"
expect_failure "export -o FIFO" "a FIFO, not a regular file" -- "$ROADCROSS" export --db "$map" -o "$WORK/fifo"
expect_failure "export -o ''" "no output path given" -- "$ROADCROSS" export --db "$map" -o ''
mkdir "$WORK/view"
mknod "$WORK/view/index.html" c 1 3
expect_failure "view onto a folder holding a device" "a character device, not a regular file" -- \
  "$ROADCROSS" view --db "$map" -o "$WORK/view"
[[ -c "$WORK/null" && -p "$WORK/fifo" && -c "$WORK/view/index.html" ]] && pass "the nodes are untouched" ||
  fail "a node was replaced"
[[ $(ls "$WORK/view") == index.html ]] && pass "view wrote nothing beside the node" || fail "view left $(ls "$WORK/view")"

# --- a full disk ---------------------------------------------------------------------------------
full="$WORK/full"
mkdir "$full"
if ! mount -t tmpfs -o size=1m tmpfs "$full" 2>/dev/null; then
  echo "SKIPPED: the full-disk checks need to mount a tmpfs (root)"
  finish
fi
trap 'umount "$full" 2>/dev/null; rm -rf "$WORK"' EXIT
echo '{"old": true}' >"$full/map.geojson"
dd if=/dev/zero of="$full/filler" bs=4k 2>/dev/null || true  # until the disk is full
expect_failure "export onto a full disk" "$full/map.geojson" "No space left on device" -- \
  "$ROADCROSS" export --db "$map" -o "$full/map.geojson"
[[ $(cat "$full/map.geojson") == '{"old": true}' ]] && pass "the old export is intact" || fail "old file changed"
expect_failure "render onto a full disk" "$full/map.png" -- "$ROADCROSS" render --db "$map" -o "$full/map.png"
expect_failure "view onto a full disk" "$full/view" -- "$ROADCROSS" view --db "$map" -o "$full/view"
[[ ! -e "$full/view" ]] && pass "no half-written view folder" || fail "view left $(ls -R "$full/view")"
leftover=$(ls "$full" | grep -v -x -e map.geojson -e filler || true)
[[ -z $leftover ]] && pass "no temporary file left" || fail "left: $leftover"

# A build onto a disk that fills while the GeoPackage is written (Monaco's is 12 MB): its SQLite
# writes go out 124 KiB a call (mapcheck/bulk_io_vfs.hpp), and a failed one is the build's error.
small="$WORK/small"
mkdir "$small"
if mount -t tmpfs -o size=6m tmpfs "$small" 2>/dev/null; then
  trap 'umount "$full" 2>/dev/null; umount "$small" 2>/dev/null; rm -rf "$WORK"' EXIT
  expect_failure "build onto a disk that fills" "$small/monaco.gpkg" "disk is full" -- \
    "$ROADCROSS_BUILD" -q --osm "$ROADCROSS_MAPS_DIR/monaco/monaco.osm.pbf" -o "$small/monaco.gpkg"
  [[ -z $(ls "$small") ]] && pass "the build left nothing" || fail "the build left: $(ls "$small")"
  umount "$small"
  # 3 MiB: the schema and the segments' R*Tree fit, the first batch of segment rows does not. The
  # rows are written out batch by batch while the sight stage computes the later segments, so
  # the disk fills during that stage (or just after it, should the stage end first): the writer's
  # error stops the stage and is the build's.
  if mount -t tmpfs -o size=3m tmpfs "$small" 2>/dev/null; then
    expect_failure "build onto a disk that fills beside the sight stage" "$small/monaco.gpkg" \
      "disk is full" -- "$ROADCROSS_BUILD" -q --osm "$ROADCROSS_MAPS_DIR/monaco/monaco.osm.pbf" \
      -o "$small/monaco.gpkg"
    [[ -z $(ls "$small") ]] && pass "the build left nothing" || fail "the build left: $(ls "$small")"
  fi
fi
finish
