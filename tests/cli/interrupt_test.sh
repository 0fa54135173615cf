#!/usr/bin/env bash
# An interrupted build (Ctrl-C, SIGTERM) and a build that runs out of space leave no partial
# .gpkg and no temporary file, say so, and exit non-zero; an existing map stays as it was.
source "$(dirname "$0")/lib.sh"
monaco="$ROADCROSS_MAPS_DIR/monaco/monaco.osm.pbf"
mkdir -p "$WORK/out"

interrupt_build() {  # SIGNAL EXPECTED_STATUS
  "$ROADCROSS_BUILD" --osm "$monaco" -o "$WORK/out/map.gpkg" 2>"$WORK/stderr" &
  local pid=$! waited=0
  # The temporary file exists from the start of the build; interrupt once it is there.
  until compgen -G "$WORK/out/map.gpkg.tmp-*" >/dev/null; do
    sleep 0.01
    waited=$((waited + 1))
    ((waited < 500)) || { fail "$1: no temporary file appeared"; return; }
  done
  kill -"$1" "$pid"
  local status=0
  wait "$pid" || status=$?
  [[ $status == "$2" ]] && pass "$1: exit $status" || fail "$1: exit $status, expected $2"
  grep -q "interrupted; removed the partial output" "$WORK/stderr" || fail "$1: message: $(cat "$WORK/stderr")"
}

interrupt_build INT 130
[[ -z $(ls "$WORK/out") ]] && pass "nothing left after SIGINT" || fail "left after SIGINT: $(ls "$WORK/out")"
interrupt_build TERM 143
[[ -z $(ls "$WORK/out") ]] && pass "nothing left after SIGTERM" || fail "left after SIGTERM: $(ls "$WORK/out")"

# An existing map survives an interrupted rebuild.
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/out/map.gpkg" -q
cp "$WORK/out/map.gpkg" "$WORK/before.gpkg"
interrupt_build INT 130
cmp -s "$WORK/out/map.gpkg" "$WORK/before.gpkg" && pass "existing map untouched" || fail "existing map changed"
compgen -G "$WORK/out/*.tmp-*" >/dev/null && fail "temporary file left" || true
rm -f "$WORK/out/"*  # a failure above must not also fail the next case

# Out of space: a 500 KiB file size limit (the Monaco DB is several MB).
status=0
(ulimit -f 500; exec "$ROADCROSS_BUILD" --osm "$monaco" -o "$WORK/out/map.gpkg") 2>"$WORK/stderr" || status=$?
((status != 0)) && pass "file size limit: exit $status" || fail "file size limit: exit 0"
grep -q "$WORK/out/map.gpkg: cannot write the database" "$WORK/stderr" || fail "file size limit message: $(cat "$WORK/stderr")"
[[ -z $(ls "$WORK/out") ]] && pass "nothing left when out of space" || fail "left when out of space: $(ls "$WORK/out")"
finish
