#!/usr/bin/env bash
# roadcross-build runs itself again with glibc's malloc on transparent huge pages
# (GLIBC_TUNABLES=glibc.malloc.hugetlb=1): its --json summary says so (malloc_huge_pages), the
# running image's environment shows it, a hugetlb setting of the user's is kept, other
# tunables are kept beside it, ROADCROSS_NO_RELAUNCH=1 turns it off; the map is the same.
source "$(dirname "$0")/lib.sh"
monaco="$ROADCROSS_MAPS_DIR/monaco/monaco.osm.pbf"

# build NAME [VAR=VALUE...]: Monaco under that environment (GLIBC_TUNABLES and
# ROADCROSS_NO_RELAUNCH unset unless given); its JSON summary in $WORK/NAME.json.
build() {
  local name=$1
  shift
  env -u GLIBC_TUNABLES -u ROADCROSS_NO_RELAUNCH "$@" "$ROADCROSS_BUILD" --osm "$monaco" \
    -o "$WORK/$name.gpkg" --json >"$WORK/$name.json" || fail "$name: exit $?"
}

expect_huge_pages() {  # NAME True|False
  local seen
  seen=$(json_field "$WORK/$1.json" malloc_huge_pages)
  [[ $seen == "$2" ]] && pass "$1: malloc_huge_pages $seen" || fail "$1: malloc_huge_pages $seen"
}

build default
expect_huge_pages default True
build other GLIBC_TUNABLES=glibc.malloc.tcache_count=0
expect_huge_pages other True
build users_off GLIBC_TUNABLES=glibc.malloc.hugetlb=0
expect_huge_pages users_off False
build users_off_last GLIBC_TUNABLES=glibc.malloc.hugetlb=1:glibc.malloc.hugetlb=0
expect_huge_pages users_off_last False
build off ROADCROSS_NO_RELAUNCH=1
expect_huge_pages off False
build off_zero ROADCROSS_NO_RELAUNCH=0
expect_huge_pages off_zero True

for name in other users_off users_off_last off off_zero; do
  [[ $(json_field "$WORK/$name.json" map_id) == $(json_field "$WORK/default.json" map_id) ]] &&
    pass "$name: the same map_id" || fail "$name: another map_id"
done

# The image that runs the build started with the tunable: /proc/PID/environ (the exec's own
# copy) once the build's temporary output exists. (With other tunables before it, glibc's
# loader cuts that copy at the first one while parsing: only the lone tunable is checked.)
seen=""
for attempt in 1 2 3 4 5; do
  rm -f "$WORK/env.gpkg"*
  env -u GLIBC_TUNABLES -u ROADCROSS_NO_RELAUNCH "$ROADCROSS_BUILD" --osm "$monaco" \
    --elevation "$ROADCROSS_MAPS_DIR/monaco/N43E007.hgt" -o "$WORK/env.gpkg" -q &
  pid=$! waited=0
  until compgen -G "$WORK/env.gpkg.tmp-*" >/dev/null || ((waited >= 2000)); do
    sleep 0.005
    waited=$((waited + 1))
  done
  seen=$(tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep '^GLIBC_TUNABLES=' || true)
  wait "$pid" || fail "environment case: exit $?"
  [[ -n $seen ]] && break
done
[[ $seen == "GLIBC_TUNABLES=glibc.malloc.hugetlb=1" ]] && pass "the running image has $seen" ||
  fail "the running image's environment: '$seen'"
finish
