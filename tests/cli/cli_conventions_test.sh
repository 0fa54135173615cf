#!/usr/bin/env bash
# Command-line conventions of roadcross, roadcross-viz (via `roadcross render`) and
# roadcross-build: usage errors exit 2 with the program's name and a "did you mean"; `info --db`;
# every --json answer gives latitude/longitude beside UTM (checked against GDAL's own
# transformation); under --json an error is one JSON object; swapped latitude and longitude get
# a hint.
source "$(dirname "$0")/lib.sh"
db="$WORK/prague.gpkg"
"$ROADCROSS_BUILD" -q --osm "$PRAGUE_OSM" -o "$db"

# expect_usage_error NAME EXPECTED_TEXT... -- CMD...: exit status exactly 2, texts on stderr.
expect_usage_error() {
  local name=$1; shift
  local expected=()
  while [[ $1 != -- ]]; do expected+=("$1"); shift; done
  shift
  local status=0
  "$@" >"$WORK/stdout" 2>"$WORK/stderr" || status=$?
  if ((status != 2)); then fail "$name: exit status $status, expected 2 ($(cat "$WORK/stderr"))"; return; fi
  for text in "${expected[@]}"; do
    grep -qF -- "$text" "$WORK/stderr" || { fail "$name: stderr lacks '$text': $(cat "$WORK/stderr")"; return; }
  done
  pass "$name: $(head -1 "$WORK/stderr")"
}

# --- usage errors: exit 2, the program's name, did you mean ---------------------------------
expect_usage_error "misspelt subcommand" "roadcross: unknown command 'asess'; did you mean 'assess'?" \
  "roadcross --help" -- "$ROADCROSS" asess --db "$db" --lat 50.0755 --lon 14.4186
expect_usage_error "misspelt option" "roadcross assess: unknown option --lonn; did you mean --lon?" -- \
  "$ROADCROSS" assess --db "$db" --lat 50.0755 --lonn 14.4186
expect_usage_error "missing position" "roadcross nearest:" "--lat/--lon or --utm" -- \
  "$ROADCROSS" nearest --db "$db"
expect_usage_error "nothing like a subcommand" "roadcross: unknown command 'frobnicate'" -- \
  "$ROADCROSS" frobnicate
expect_usage_error "misspelt dotted parameter" \
  "roadcross-build: unknown option --segments.max_segmnt_length_m; did you mean --segments.max_segment_length_m?" -- \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/x.gpkg" --segments.max_segmnt_length_m 8
expect_usage_error "misspelt build option" "roadcross-build: unknown option --elevaton; did you mean --elevation?" -- \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/x.gpkg" --elevaton x.hgt
expect_usage_error "build without --osm" "roadcross-build:" "--osm" -- "$ROADCROSS_BUILD" -o "$WORK/x.gpkg"
expect_usage_error "misspelt render option" "roadcross render: unknown option --dbb; did you mean --db?" -- \
  "$ROADCROSS" render --dbb "$db" -o "$WORK/x.png"
[[ ! -e $WORK/x.gpkg && ! -e $WORK/x.png ]] && pass "no output after usage errors" || fail "a usage error left an output"
# A value that is merely out of range stays a usage error too.
expect_usage_error "bad parameter value" "roadcross-build" -- \
  "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/x.gpkg" --segments.max_segment_length_m -3

# --- info --db, and the older positional form ------------------------------------------------
"$ROADCROSS" info --db "$db" >"$WORK/info_db.txt" && "$ROADCROSS" info "$db" >"$WORK/info_pos.txt" &&
  cmp -s "$WORK/info_db.txt" "$WORK/info_pos.txt" && grep -q "UTM zone 33N" "$WORK/info_db.txt" &&
  pass "info --db MAP = info MAP" || fail "info --db"
expect_usage_error "info without a map" "roadcross info:" "--db" -- "$ROADCROSS" info

# --- lat/lon beside UTM, checked with GDAL (PROJ) -------------------------------------------
# json_at FILE KEY|INDEX...: the value at that path (numbers index lists).
json_at() {
  python3 -c 'import json, sys
d = json.load(open(sys.argv[1]))
for k in sys.argv[2:]:
    d = d[int(k)] if k.isdigit() else d[k]
print(d)' "$@"
}
# lonlat_of E N: GDAL's transformation of UTM 33N to WGS84 longitude and latitude.
lonlat_of() { echo "$1 $2" | gdaltransform -s_srs EPSG:32633 -t_srs EPSG:4326 -output_xy; }
check_lat_lon() {  # NAME JSON UTM_KEY... -- LATLON_KEY...
  local name=$1 json=$2; shift 2
  local utm_path=() ll_path=()
  while [[ $1 != -- ]]; do utm_path+=("$1"); shift; done
  shift; ll_path=("$@")
  local e n lat lon
  e=$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1]))
for k in sys.argv[2:]: d=d[int(k)] if k.isdigit() else d[k]
print(d[0], d[1])' "$json" "${utm_path[@]}") || { fail "$name: no ${utm_path[*]}"; return; }
  read -r e n <<<"$e"
  read -r lat lon <<<"$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1]))
for k in sys.argv[2:]: d=d[int(k)] if k.isdigit() else d[k]
print(d[0], d[1])' "$json" "${ll_path[@]}")" || { fail "$name: no ${ll_path[*]}"; return; }
  local gdal_lon gdal_lat
  read -r gdal_lon gdal_lat <<<"$(lonlat_of "$e" "$n")"
  # 1e-6 degrees: 11 cm, well above the 7-decimal rounding and GDAL's printed precision.
  if near "$lat" "$gdal_lat" 1e-6 && near "$lon" "$gdal_lon" 1e-6; then
    pass "$name: $lat, $lon = GDAL's $gdal_lat, $gdal_lon"
  else
    fail "$name: $lat, $lon but GDAL says $gdal_lat, $gdal_lon for E $e N $n"
  fi
}
"$ROADCROSS" nearest --db "$db" --lat 50.0755 --lon 14.4186 --json >"$WORK/nearest.json"
check_lat_lon "nearest closest" "$WORK/nearest.json" closest_utm_m -- closest_lat_lon_deg
check_lat_lon "nearest query" "$WORK/nearest.json" query_utm_m -- query_lat_lon_deg
near "$(json_at "$WORK/nearest.json" query_lat_lon_deg 0)" 50.0755 1e-7 &&
  pass "the query's latitude comes back as given" || fail "query latitude $(json_at "$WORK/nearest.json" query_lat_lon_deg 0)"
"$ROADCROSS" heading --db "$db" --lat 50.0755 --lon 14.4186 --json >"$WORK/heading.json"
check_lat_lon "heading" "$WORK/heading.json" closest_utm_m -- closest_lat_lon_deg
"$ROADCROSS" assess --db "$db" --lat 50.0755 --lon 14.4186 --json >"$WORK/assess.json"
check_lat_lon "assess" "$WORK/assess.json" closest_utm_m -- closest_lat_lon_deg
"$ROADCROSS" better --db "$db" --lat 50.0755 --lon 14.4186 --json >"$WORK/better.json"
if [[ $(python3 -c "import json,sys; print(len(json.load(open(sys.argv[1]))[\"candidates\"]))" "$WORK/better.json") == 0 ]]; then
  fail "better: no candidate to check"
else
  check_lat_lon "better candidate" "$WORK/better.json" candidates 0 point_utm_m -- candidates 0 point_lat_lon_deg
fi
"$ROADCROSS" info --db "$db" --json >"$WORK/info.json"
check_lat_lon "info extent south-west" "$WORK/info.json" extent_utm_m -- extent_lat_lon_deg
e=$(json_at "$WORK/nearest.json" closest_utm_m 0); n=$(json_at "$WORK/nearest.json" closest_utm_m 1)
"$ROADCROSS" monitor --db "$db" --lat 50.0755 --lon 14.4186 --at "$e" "$n" --yaw 0 --json >"$WORK/monitor.json"
check_lat_lon "monitor plan start" "$WORK/monitor.json" plan_start_utm_m -- plan_start_lat_lon_deg
echo '{"op": "nearest", "lat": 50.0755, "lon": 14.4186}' | "$ROADCROSS" batch --db "$db" >"$WORK/batch.jsonl"
python3 -c 'import json,sys; json.dump(json.loads(open(sys.argv[1]).readline())["result"], open(sys.argv[2], "w"))' \
  "$WORK/batch.jsonl" "$WORK/batch.json"
check_lat_lon "batch nearest" "$WORK/batch.json" closest_utm_m -- closest_lat_lon_deg

# --- errors under --json: one JSON object with error and code ------------------------------
# expect_json_error NAME EXIT CODE -- CMD...
expect_json_error() {
  local name=$1 want_status=$2 want_code=$3; shift 4
  local status=0
  "$@" >"$WORK/stdout" 2>"$WORK/stderr" || status=$?
  local code
  code=$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["error"]; print(d["code"])' \
    "$WORK/stdout" 2>/dev/null) || { fail "$name: stdout is no JSON error: $(cat "$WORK/stdout")"; return; }
  [[ $status == "$want_status" && $code == "$want_code" ]] &&
    pass "$name: exit $status, $(cat "$WORK/stdout")" ||
    fail "$name: exit $status code $code, expected $want_status $want_code"
}
expect_json_error "missing map" 1 file_not_found -- "$ROADCROSS" nearest --db "$WORK/none.gpkg" --lat 50.0755 --lon 14.4186 --json
expect_json_error "no road near" 1 not_found -- "$ROADCROSS" nearest --db "$db" --utm 400000 5500000 --json
expect_json_error "usage error" 2 usage -- "$ROADCROSS" asess --db "$db" --json
expect_json_error "info of a missing map" 1 file_not_found -- "$ROADCROSS" info --db "$WORK/none.gpkg" --json
expect_json_error "build usage error" 2 usage -- "$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/x.gpkg" --json --segments.bogus 1
expect_json_error "build error" 1 error -- "$ROADCROSS_BUILD" --osm "$WORK/none.osm" -o "$WORK/x.gpkg" --json
expect_json_error "render error" 1 error -- "$ROADCROSS" render --db "$WORK/none.gpkg" -o "$WORK/x.png" --json

# --- latitude and longitude swapped ------------------------------------------------------------
expect_failure "swapped lat/lon" "are latitude and longitude swapped?" "--lat 50.0755 --lon 14.4186 is inside" -- \
  "$ROADCROSS" nearest --db "$db" --lat 14.4186 --lon 50.0755
expect_failure "swapped lat/lon (heading)" "swapped?" -- "$ROADCROSS" heading --db "$db" --lat 14.4186 --lon 50.0755
# Outside the map either way: no hint.
"$ROADCROSS" nearest --db "$db" --lat 49.0 --lon 13.0 >/dev/null 2>"$WORK/far.txt" || true
grep -q "swapped" "$WORK/far.txt" && fail "a hint for a position that is outside either way" ||
  pass "no swap hint when neither order is inside: $(cat "$WORK/far.txt")"
finish
