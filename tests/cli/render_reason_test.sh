#!/usr/bin/env bash
# render --color-by reason on tests/data/reasons.osm (its comment describes the six roads, one
# deciding reason each): the colour at a known place of every road, read through the world file
# by GDAL, is that reason's colour, derived by hand from the rule of docs/cost-model.md
# ("suitable"): the class first, then a tunnel, an operator's no_crossing, then (under the
# build's thresholds here) the score; force_suitable lifts the score but not the robot's kerb.
# Street names: the long named road carries its name, the 7 m road whose name is longer than
# itself does not, and --no-street-names draws none.
source "$(dirname "$0")/lib.sh"
PIXELS="$(dirname "$0")/png_pixels.py"
cat >"$WORK/overrides.geojson" <<'EOF'
{"type": "FeatureCollection", "features": [
 {"type": "Feature", "geometry": null, "properties": {"osm_way_id": 12, "no_crossing": true}},
 {"type": "Feature", "geometry": null, "properties": {"osm_way_id": 13, "force_suitable": true}},
 {"type": "Feature", "geometry": null, "properties": {"osm_way_id": 15, "force_suitable": true}}]}
EOF
"$ROADCROSS_BUILD" --osm "$ROADCROSS_TEST_DATA_DIR/reasons.osm" --overrides "$WORK/overrides.geojson" \
  --suitability.threshold 1000 --sight.limited_visibility_unsuitable 0 \
  --suitability.max_kerb_height_m 0.1 -o "$WORK/reasons.gpkg" -q
"$ROADCROSS" render --db "$WORK/reasons.gpkg" -o "$WORK/reasons.png" --color-by reason --json \
  >"$WORK/render.json"

# lat lon expected-colour name: a quarter along each road (lon 14.3995), and on way 15 3 m east
# of the crossing node (lon 14.4 + 3 m / 71 556 m per degree at 50 degrees north = 14.400042),
# on the one segment that holds the crossing (4.8 m to either end), so 12 cm kerb > 0.1 m.
cat >"$WORK/places.txt" <<'EOF'
50.00000 14.3995 #000000 NOT_CROSSABLE_CLASS
50.00135 14.3995 #777777 TUNNEL
50.00270 14.3995 #cc79a7 OVERRIDE
50.00405 14.3995 #0072b2 suitable
50.00540 14.3995 #e69f00 LOW_SCORE
50.00675 14.400042 #009e73 KERB_TOO_HIGH
50.00675 14.3993 #0072b2 suitable
EOF
epsg=$(sqlite3 "$WORK/reasons.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'epsg'")
# UTM by GDAL (not by roadcross), then the pixel there through the PNG's world file.
awk '{ print $2, $1 }' "$WORK/places.txt" | gdaltransform -s_srs EPSG:4326 -t_srs "EPSG:$epsg" |
  awk '{ print $1, $2 }' >"$WORK/utm.txt"
gdallocationinfo -geoloc -valonly "$WORK/reasons.png" <"$WORK/utm.txt" | paste - - - >"$WORK/colours.txt"
while read -r lat lon hex name && read -r r g b <&3; do
  got=$(printf '#%02x%02x%02x' "$r" "$g" "$b")
  [[ $got == "$hex" ]] && pass "$name at $lat,$lon is $hex" || fail "$name at $lat,$lon: $got, expected $hex"
done <"$WORK/places.txt" 3<"$WORK/colours.txt"
[[ $(wc -l <"$WORK/colours.txt") == 7 ]] || fail "expected 7 colours, got $(wc -l <"$WORK/colours.txt")"

# The legend lists the reasons present (its swatches are in the strip below the map): the kerb
# green appears beyond the one short segment's few pixels.
read -r kerb_px < <(python3 "$PIXELS" count "$WORK/reasons.png" '#009e73')
read -r kerb_map_px < <(gdal_translate -q -srcwin 0 0 1200 "$(json_field "$WORK/render.json" map_height_px)" \
  "$WORK/reasons.png" "$WORK/map-only.png" && python3 "$PIXELS" count "$WORK/map-only.png" '#009e73')
((kerb_px > kerb_map_px + 40)) && pass "the legend has the KERB_TOO_HIGH swatch" ||
  fail "no KERB_TOO_HIGH swatch in the legend ($kerb_px px in all, $kerb_map_px on the map)"

# Street names: "Long Street" (143 m, about 850 px here) carries its name; the 7 m road does not.
names=$(json_field "$WORK/render.json" street_names)
((names >= 1)) && pass "$names street names drawn" || fail "no street name drawn"
"$ROADCROSS" render --db "$WORK/reasons.gpkg" -o "$WORK/plain.png" --color-by reason --no-street-names \
  --json >"$WORK/plain.json"
[[ $(json_field "$WORK/plain.json" street_names) == 0 ]] && pass "--no-street-names draws none" ||
  fail "--no-street-names drew $(json_field "$WORK/plain.json" street_names)"
# Around the short road (7 m, shorter than its name) no glyph; around Long Street some. Boxes of
# +-30 m (east-west) by +-20 m (north-south) around each road's middle, cut out by GDAL.
glyphs_near() {  # PNG LAT LON: dark pixels (the text, #212121 antialiased) within the box
  read -r e n _ < <(echo "$3 $2" | gdaltransform -s_srs EPSG:4326 -t_srs "EPSG:$epsg")
  gdal_translate -q -projwin "$(bc <<<"$e - 30")" "$(bc <<<"$n + 20")" "$(bc <<<"$e + 30")" \
    "$(bc <<<"$n - 20")" "$1" "$WORK/box.png"
  python3 "$PIXELS" dark "$WORK/box.png"
}
long=$(glyphs_near "$WORK/reasons.png" 50.00405 14.4000)
short=$(glyphs_near "$WORK/reasons.png" 50.00810 14.40005)
long_plain=$(glyphs_near "$WORK/plain.png" 50.00405 14.4000)
((long > 20 && short == 0 && long_plain == 0)) &&
  pass "name glyphs: $long px at Long Street, none at the 7 m road, none with --no-street-names" ||
  fail "name glyphs: $long px at Long Street, $short at the 7 m road, $long_plain with --no-street-names"
finish
