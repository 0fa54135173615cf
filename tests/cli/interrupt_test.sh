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

# Interrupted while the writer's second thread fills its side database (<temp>-rows): that
# file goes too. A 10x tiled Monaco (make_tiled_osm, in builds with the benchmarks) makes the
# writing last seconds; without it the 1x map's ~0.2 s window may be missed, which is reported.
tiled="$ROADCROSS_BINARY_DIR/tests/benchmarks/make_tiled_osm"
input="$monaco"
if [[ -x $tiled ]]; then
  "$tiled" "$monaco" 10 "$WORK/m10.osm.pbf" >/dev/null
  input="$WORK/m10.osm.pbf"
fi
"$ROADCROSS_BUILD" --osm "$input" -o "$WORK/out/map.gpkg" --sight.enabled 0 2>"$WORK/stderr" &
pid=$!
until compgen -G "$WORK/out/map.gpkg.tmp-*-rows" >/dev/null || ! kill -0 "$pid" 2>/dev/null; do
  sleep 0.002
done
if kill -INT "$pid" 2>/dev/null; then
  status=0
  wait "$pid" || status=$?
  if [[ $status == 130 ]]; then
    pass "SIGINT while writing the side database: exit 130"
    [[ -z $(ls "$WORK/out") ]] && pass "nothing left after SIGINT while writing" ||
      fail "left after SIGINT while writing: $(ls "$WORK/out")"
  elif [[ -x $tiled ]]; then
    fail "SIGINT while writing: exit $status"
  else
    echo "note: the 1x build finished before the side database appeared (no make_tiled_osm)"
  fi
else
  wait "$pid" || true
  [[ -x $tiled ]] && fail "the 10x build ended before its side database appeared"
fi
rm -f "$WORK/out/"*

# Out of space: a 500 KiB file size limit (the Monaco DB is several MB).
status=0
(ulimit -f 500; exec "$ROADCROSS_BUILD" --osm "$monaco" -o "$WORK/out/map.gpkg") 2>"$WORK/stderr" || status=$?
((status != 0)) && pass "file size limit: exit $status" || fail "file size limit: exit 0"
grep -q "$WORK/out/map.gpkg: cannot write the database" "$WORK/stderr" || fail "file size limit message: $(cat "$WORK/stderr")"
[[ -z $(ls "$WORK/out") ]] && pass "nothing left when out of space" || fail "left when out of space: $(ls "$WORK/out")"
finish
