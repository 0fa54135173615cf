#!/usr/bin/env bash
# Regenerates the pictures of the bundled maps shown in docs/user-guide.md (docs/images/), with
# the commands the guide quotes. Needs a release build (cmake --preset release && cmake --build
# build/release) and, for the viewer screenshot, chromium.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/release/cli
out=docs/images
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
"$bin/roadcross-build" --osm maps/prague/prague_nove_mesto_roads_2017.osm \
  --elevation maps/prague/N50E014.hgt -o "$tmp/prague.gpkg" -q
"$bin/roadcross-build" --osm maps/monaco/monaco.osm.pbf --elevation maps/monaco/N43E007.hgt \
  -o "$tmp/monaco.gpkg" -q
"$bin/roadcross" render --db "$tmp/prague.gpkg" -o "$out/prague-suitable.png" --width 1000
"$bin/roadcross" render --db "$tmp/prague.gpkg" -o "$out/prague-rank.png" --width 1000 --color-by rank
"$bin/roadcross" render --db "$tmp/prague.gpkg" -o "$out/prague-reason.png" --width 1000 --color-by reason
"$bin/roadcross" render --db "$tmp/monaco.gpkg" -o "$out/monaco-suitable.png" --width 1000
"$bin/roadcross" render --db "$tmp/monaco.gpkg" -o "$out/monaco-landform.png" --width 1000 \
  --color-by landform
"$bin/roadcross" view --db "$tmp/prague.gpkg" -o "$tmp/prague-view"
chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=1200,800 \
  --user-data-dir="$tmp/chromium-profile" \
  --virtual-time-budget=5000 --screenshot="$out/prague-view.png" \
  "file://$tmp/prague-view/index.html#50.0757,14.4160,300" 2>/dev/null
rm -f "$out"/*.pgw  # the world files georeference the PNGs; the guide does not need them
