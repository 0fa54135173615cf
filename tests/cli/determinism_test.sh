#!/usr/bin/env bash
# The same inputs and parameters give a byte-identical DB, wherever the input lives.
source "$(dirname "$0")/lib.sh"
for input in "$PRAGUE_OSM" "$ROADCROSS_MAPS_DIR/monaco/monaco.osm.pbf" "$ROADCROSS_MAPS_DIR/bayreuth/north-bayreuth.osm.gz"; do
  name=$(basename "$input")
  "$ROADCROSS_BUILD" --osm "$input" -o "$WORK/a.gpkg" -q
  "$ROADCROSS_BUILD" --osm "$input" -o "$WORK/b.gpkg" -q
  mkdir -p "$WORK/elsewhere"
  cp "$input" "$WORK/elsewhere/$name"
  "$ROADCROSS_BUILD" --osm "$WORK/elsewhere/$name" -o "$WORK/c.gpkg" -q
  cmp -s "$WORK/a.gpkg" "$WORK/b.gpkg" && pass "$name: two builds identical" || fail "$name: two builds differ"
  cmp -s "$WORK/a.gpkg" "$WORK/c.gpkg" && pass "$name: copy elsewhere identical" || fail "$name: copy elsewhere differs"
  # A different parameter must change the output (so the comparison above can fail).
  "$ROADCROSS_BUILD" --osm "$input" -o "$WORK/d.gpkg" -q --segments.max_segment_length_m 12
  cmp -s "$WORK/a.gpkg" "$WORK/d.gpkg" && fail "$name: a parameter change did not change the output" || true
done
finish
