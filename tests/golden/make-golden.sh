#!/usr/bin/env bash
# Writes roadcross's golden outputs (osmium-tool style) into OUT_DIR:
#   print-config.txt           roadcross-build --print-config
#   prague-assess.jsonl        roadcross assess --json at a handful of Prague positions
#   segments-digest.txt        per bundled map: segment and crossing counts and the SHA-256 of
#                              every row of `segments` and `crossings` (geometry as hex)
#
#   bash tests/golden/make-golden.sh BUILD_DIR OUT_DIR
#
# tests/cli/golden_outputs_test.sh compares them with the committed tests/golden/expected/.
# A change that alters the output on purpose updates them with
#   bash tests/golden/make-golden.sh build/release tests/golden/expected
# and says why in its commit (git diff tests/golden/expected shows what moved).
set -euo pipefail
build_dir=$(realpath "$1")
out_dir=$2
maps=$(cd "$(dirname "$0")/../../maps" && pwd)
roadcross_build="$build_dir/cli/roadcross-build"
roadcross="$build_dir/cli/roadcross"
mkdir -p "$out_dir"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$roadcross_build" --print-config >"$out_dir/print-config.txt"

# name|roadcross-build arguments (paths below maps/)
builds=(
  "prague|--osm prague/prague_nove_mesto_roads_2017.osm --elevation prague/N50E014.hgt"
  "prague-flat|--osm prague/prague_nove_mesto_roads_2017.osm"
  "monaco|--osm monaco/monaco.osm.pbf --elevation monaco/N43E007.hgt"
  "bayreuth|--osm bayreuth/north-bayreuth.osm.gz --elevation bayreuth/N49E011.hgt --elevation bayreuth/N50E011.hgt"
  "techobuz|--osm techobuz/techobuz_2018.osm"
)
digest_rows() {  # DB TABLE: sha256 of every row, columns in table order, blobs as hex
  local columns
  columns=$(sqlite3 "$1" "SELECT group_concat(CASE WHEN type = 'BLOB' OR name = 'geom' THEN 'hex(' || name || ')' ELSE '[' || name || ']' END, ', ') FROM pragma_table_info('$2')")
  sqlite3 -separator '|' "$1" "SELECT $columns FROM $2 ORDER BY fid" | sha256sum | cut -d' ' -f1
}
: >"$out_dir/segments-digest.txt"
for entry in "${builds[@]}"; do
  name=${entry%%|*}
  read -r -a args <<<"${entry#*|}"
  for i in "${!args[@]}"; do [[ ${args[$i]} == --* ]] || args[$i]="$maps/${args[$i]}"; done
  (cd "$work" && "$roadcross_build" "${args[@]}" -o "$work/$name.gpkg" -q)
  printf '%s segments %s %s\n' "$name" "$(sqlite3 "$work/$name.gpkg" "SELECT count(*) FROM segments")" \
    "$(digest_rows "$work/$name.gpkg" segments)" >>"$out_dir/segments-digest.txt"
  printf '%s crossings %s %s\n' "$name" "$(sqlite3 "$work/$name.gpkg" "SELECT count(*) FROM crossings")" \
    "$(digest_rows "$work/$name.gpkg" crossings)" >>"$out_dir/segments-digest.txt"
done

# lat lon: Resslova (a four-lane primary road), Apolinářská by a zebra crossing, Karlovo náměstí's
# junction, Ječná, a courtyard 30+ m from any road, and a point outside the map.
positions=(
  "50.075769 14.416015" "50.071507 14.42651" "50.07565 14.41904" "50.07489 14.42322"
  "50.07320 14.42080" "50.06000 14.40000"
)
: >"$out_dir/prague-assess.jsonl"
for position in "${positions[@]}"; do
  read -r lat lon <<<"$position"
  status=0
  answer=$("$roadcross" assess --db "$work/prague.gpkg" --lat "$lat" --lon "$lon" --json 2>&1) || status=$?
  # One line per position; the temporary path of the map is not part of the answer.
  printf '{"lat": %s, "lon": %s, "exit": %d, "answer": %s}\n' "$lat" "$lon" "$status" \
    "$(printf '%s' "$answer" | sed "s|$work/||g" | python3 -c 'import json, sys
text = sys.stdin.read()
try:
    print(json.dumps(json.loads(text), sort_keys=False))
except ValueError:
    print(json.dumps(text))')" >>"$out_dir/prague-assess.jsonl"
done
