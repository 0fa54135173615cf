#!/usr/bin/env bash
# Sets up, builds and runs roadcross-build on the bundled Prague map (New Town around Karlovo
# namesti, where the method was first tested) with its SRTM elevation tile, then asks the map a sample question.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release -j"$(nproc)" --target roadcross-build roadcross

mkdir -p out
./build/release/cli/roadcross-build \
  --osm maps/prague/prague_nove_mesto_roads_2017.osm \
  --elevation maps/prague/N50E014.hgt \
  -o out/prague.gpkg

echo
echo "== roadcross info out/prague.gpkg"
./build/release/cli/roadcross info out/prague.gpkg
echo
echo "== A robot 5 m north of Resslova street, west of Karlovo namesti: may it cross here?"
./build/release/cli/roadcross assess --db out/prague.gpkg --lat 50.075769 --lon 14.416015
echo
echo "== Where is a better place nearby, walking along the road on its side (200 m)?"
./build/release/cli/roadcross better --db out/prague.gpkg --lat 50.075769 --lon 14.416015 --radius 200
echo
echo "== And which way would it face to cross here?"
./build/release/cli/roadcross heading --db out/prague.gpkg --lat 50.075769 --lon 14.416015
echo
echo "== A robot on quiet Apolinarska street, by a zebra crossing:"
./build/release/cli/roadcross assess --db out/prague.gpkg --lat 50.071507 --lon 14.42651
