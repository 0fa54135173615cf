#!/usr/bin/env bash
# The installed runtime package works for a consumer outside the tree, with CMake
# (find_package(roadcross)) and with pkg-config (roadcross-runtime.pc).
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
src=$(cd "$(dirname "$0")/.." && pwd)

cmake --install "$ROADCROSS_BINARY_DIR" --prefix "$work/prefix" --component runtime >/dev/null
test -f "$work/prefix/include/roadcross/runtime.hpp"
test -f "$work/prefix/lib/cmake/roadcross/roadcrossConfig.cmake"
test -f "$work/prefix/lib/pkgconfig/roadcross-runtime.pc"
# The runtime's public headers include no GDAL, SQLite or CGAL header.
if grep -rE '#include <(gdal|sqlite3|CGAL|osmium)' "$work/prefix/include/roadcross"; then
  echo "FAIL: a public header includes a heavy dependency" >&2
  exit 1
fi

# A DB with one east-west road from a hand-written OSM file.
"$ROADCROSS_BUILD" --osm "$ROADCROSS_TEST_DATA_DIR/install_straight_road.osm" -o "$work/map.gpkg" -q
read -r easting northing < <("$ROADCROSS" nearest --db "$work/map.gpkg" \
  --lat 50.0 --lon 14.4 --json | python3 -c 'import json,sys; d=json.load(sys.stdin); print(*d["closest_utm_m"])')
north=$(python3 -c "print($northing + 5.0)")
# Expected: perpendicular to the road's chord in the UTM grid, computed independently by
# projecting the two OSM nodes with GDAL. A parallel of latitude is not grid-east in UTM (the
# meridian convergence at lon 14.4 is about 0.46 degrees), so this is not exactly -pi/2.
expected=$(printf '14.399 50.0\n14.401 50.0\n' | gdaltransform -s_srs EPSG:4326 -t_srs EPSG:32633 -output_xy |
  python3 -c 'import math,sys; (x1,y1),(x2,y2)=[map(float,l.split()) for l in sys.stdin]; print(math.atan2(y2-y1,x2-x1)-math.pi/2)')

# A sanitizer build installs instrumented libraries: the consumer must link the runtimes too.
extra_flags=""
if grep -q '^ROADCROSS_SANITIZE:BOOL=ON' "$ROADCROSS_BINARY_DIR/CMakeCache.txt"; then
  extra_flags="-fsanitize=address,undefined"
fi

# CMake consumer.
cmake -S "$src/consumer" -B "$work/cmake-build" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_CXX_FLAGS="$extra_flags" -DCMAKE_EXE_LINKER_FLAGS="$extra_flags" >/dev/null
cmake --build "$work/cmake-build" >/dev/null
out=$("$work/cmake-build/consumer" "$work/map.gpkg" "$easting" "$north")
echo "cmake consumer: $out"
# 5 m north of an east-west road: face south, about -pi/2.
python3 -c "import sys; v=float('$out'.split()[-1]); sys.exit(0 if abs(v - $expected) < 1e-6 else 1)"

# pkg-config consumer.
export PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig"
# shellcheck disable=SC2046
g++ -std=c++20 $extra_flags "$src/consumer/main.cpp" -o "$work/pc-consumer" $(pkg-config --cflags --libs --static roadcross-runtime)
out=$("$work/pc-consumer" "$work/map.gpkg" "$easting" "$north")
echo "pkg-config consumer: $out"
python3 -c "import sys; v=float('$out'.split()[-1]); sys.exit(0 if abs(v - $expected) < 1e-6 else 1)"
echo "install test passed"
