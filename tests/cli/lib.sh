# Shared helpers for the end-to-end tests (sourced, not run). Each test runs in its own
# temporary directory, removed on exit.
set -euo pipefail
: "${ROADCROSS_BUILD:?}" "${ROADCROSS:?}" "${ROADCROSS_MAPS_DIR:?}" "${ROADCROSS_TEST_DATA_DIR:?}"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
PRAGUE_OSM="$ROADCROSS_MAPS_DIR/prague/prague_nove_mesto_roads_2017.osm"
FAILURES=0

fail() { echo "FAIL: $*" >&2; FAILURES=$((FAILURES + 1)); }
pass() { echo "ok: $*"; }

# expect_failure NAME EXPECTED_TEXT... -- CMD...: CMD exits non-zero and stderr contains every
# EXPECTED_TEXT.
expect_failure() {
  local name=$1; shift
  local expected=()
  while [[ $1 != -- ]]; do expected+=("$1"); shift; done
  shift
  local status=0
  "$@" >"$WORK/stdout" 2>"$WORK/stderr" || status=$?
  if ((status == 0)); then fail "$name: exit status 0"; return; fi
  for text in "${expected[@]}"; do
    if ! grep -qF -- "$text" "$WORK/stderr"; then
      fail "$name: stderr lacks '$text': $(cat "$WORK/stderr")"
      return
    fi
  done
  pass "$name (exit $status): $(head -c 200 "$WORK/stderr")"
}

# near A B TOLERANCE: |A - B| <= TOLERANCE
near() { python3 -c "import sys; sys.exit(0 if abs(float('$1') - float('$2')) <= float('$3') else 1)"; }

# json_field FILE KEY [KEY...]: the value at that key path of a JSON file.
json_field() {
  python3 -c 'import json, sys
d = json.load(open(sys.argv[1]))
for key in sys.argv[2:]:
    d = d[key]
print(d)' "$@"
}

finish() {
  if ((FAILURES > 0)); then echo "$FAILURES check(s) failed" >&2; exit 1; fi
  echo "all checks passed"
}
