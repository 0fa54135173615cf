#!/usr/bin/env bash
# `cpack -G DEB` makes the Debian packages docs/embedding.md names, each with its copyright
# file; the robot's roadcross-cli depends on nothing of the GIS stack; the ROS package's
# layout is one ROS's own tools resolve: rospkg finds roadcross_ros, roslib finds the node
# executable and the generated Python services import (all from the unpacked package, not the
# build tree).
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cpack -G DEB -B "$work" --config "$ROADCROSS_BINARY_DIR/CPackConfig.cmake" >"$work/cpack.log" 2>&1 ||
  { cat "$work/cpack.log" >&2; exit 1; }
expected="roadcross-runtime-dev roadcross-cli"
tools=0
grep -q '^ROADCROSS_RUNTIME_ONLY:BOOL=ON' "$ROADCROSS_BINARY_DIR/CMakeCache.txt" || { tools=1; expected+=" roadcross-tools"; }
grep -q '^ROADCROSS_BUILD_PYTHON:BOOL=ON' "$ROADCROSS_BINARY_DIR/CMakeCache.txt" && expected+=" python3-roadcross"
ros=0
grep -q '^ROADCROSS_BUILD_ROS:BOOL=ON' "$ROADCROSS_BINARY_DIR/CMakeCache.txt" && ros=1 && expected+=" roadcross-ros"
for package in $expected; do
  ls "$work/${package}"_*.deb >/dev/null 2>&1 || { echo "FAIL: no $package package" >&2; ls "$work" >&2; exit 1; }
done

# Every package carries the licence: /usr/share/doc/<package>/copyright, BSD-3-Clause.
for package in $expected; do
  mkdir -p "$work/doc/$package"
  dpkg-deb -x "$work/${package}"_*.deb "$work/doc/$package"
  copyright="$work/doc/$package/usr/share/doc/$package/copyright"
  [[ -f $copyright ]] && grep -q '^License: BSD-3-Clause$' "$copyright" &&
    grep -q 'Copyright: 2026 the roadcross authors' "$copyright" ||
    { echo "FAIL: $package lacks a BSD-3-Clause copyright file" >&2; exit 1; }
done

# The robot's package: roadcross (query, verify, install) and nothing of the workstation's GIS
# stack, neither among the package's Depends (from dpkg-shlibdeps) nor among the libraries the
# program itself names (objdump, independent of the packaging).
cli_deb=$(ls "$work"/roadcross-cli_*.deb)
cli_files=$(dpkg-deb -c "$cli_deb")
grep -q '/usr/bin/roadcross$' <<<"$cli_files" || { echo "FAIL: roadcross-cli lacks usr/bin/roadcross" >&2; exit 1; }
if grep -qE '/usr/bin/roadcross-(build|viz)$' <<<"$cli_files"; then
  echo "FAIL: roadcross-cli carries a workstation program" >&2; exit 1
fi
cli_depends=$(dpkg-deb -f "$cli_deb" Depends)
for needed in libsqlite3 libgeographiclib; do
  grep -q "$needed" <<<"$cli_depends" || { echo "FAIL: roadcross-cli does not depend on $needed: $cli_depends" >&2; exit 1; }
done
heavy='gdal|cairo|cgal|osmium|proj|geos|gmp|mpfr|tbb'
if grep -qiE "$heavy" <<<"$cli_depends"; then
  echo "FAIL: roadcross-cli depends on the GIS stack: $cli_depends" >&2; exit 1
fi
needed_libs=$(objdump -p "$work/doc/roadcross-cli/usr/bin/roadcross" | awk '$1 == "NEEDED" {print $2}')
if grep -qiE "$heavy" <<<"$needed_libs"; then
  echo "FAIL: roadcross links the GIS stack: $needed_libs" >&2; exit 1
fi

if ((tools)); then
  tools_deb=$(ls "$work"/roadcross-tools_*.deb)
  tools_files=$(dpkg-deb -c "$tools_deb")  # (grep -q on the pipe would cut it)
  for program in roadcross-build roadcross-viz; do
    grep -q "/usr/bin/$program\$" <<<"$tools_files" ||
      { echo "FAIL: roadcross-tools lacks usr/bin/$program" >&2; exit 1; }
  done
  grep -q '/usr/lib/roadcross/libroadcross_gdal.so$' <<<"$tools_files" ||
    { echo "FAIL: roadcross-tools lacks usr/lib/roadcross/libroadcross_gdal.so" >&2; exit 1; }
  # The unpacked roadcross-build finds the unpacked GDAL module (not the build tree's) for
  # elevation input.
  root="$work/doc/roadcross-tools/usr"
  LD_DEBUG=files "$root/bin/roadcross-build" --osm "$ROADCROSS_MAPS_DIR/prague/prague_nove_mesto_roads_2017.osm" \
    --elevation "$ROADCROSS_MAPS_DIR/prague/N50E014.hgt" -o "$work/dem.gpkg" -q 2>"$work/ld.log" ||
    { echo "FAIL: the packaged roadcross-build with elevation" >&2; exit 1; }
  grep -q "file=$root/lib/roadcross/libroadcross_gdal.so \[" "$work/ld.log" ||
    { echo "FAIL: the packaged roadcross-build did not load the packaged GDAL module" >&2; exit 1; }
  tools_depends=$(dpkg-deb -f "$tools_deb" Depends)
  grep -q 'roadcross-cli (= ' <<<"$tools_depends" && grep -qi 'gdal' <<<"$tools_depends" ||
    { echo "FAIL: roadcross-tools should depend on roadcross-cli and GDAL: $tools_depends" >&2; exit 1; }
  # Its copyright says what CGAL's GPL means for the distributed roadcross-build.
  copyright="$work/doc/roadcross-tools/usr/share/doc/roadcross-tools/copyright"
  grep -q '^Files: usr/bin/roadcross-build$' "$copyright" && grep -q '^License: GPL-3.0-or-later$' "$copyright" &&
    grep -q 'CGAL' "$copyright" || { echo "FAIL: roadcross-tools' copyright lacks the GPL-3 note" >&2; exit 1; }
fi

if ((ros)); then
  deb=$(ls "$work"/roadcross-ros_*.deb)
  dpkg-deb -f "$deb" Depends | grep -q 'libroscpp' ||
    { echo "FAIL: roadcross-ros does not depend on roscpp: $(dpkg-deb -f "$deb" Depends)" >&2; exit 1; }
  dpkg-deb -x "$deb" "$work/root"
  usr="$work/root/usr"
  CMAKE_PREFIX_PATH="$usr" ROS_PACKAGE_PATH="$usr/share" PYTHONPATH="$usr/lib/python3/dist-packages" \
    /usr/bin/python3 - "$usr" <<'PY'
import sys
import rospkg, roslib.packages
usr = sys.argv[1]
path = rospkg.RosPack().get_path("roadcross_ros")
assert path == usr + "/share/roadcross_ros", path
nodes = roslib.packages.find_node("roadcross_ros", "roadcross_node")
assert nodes == [usr + "/lib/roadcross_ros/roadcross_node"], nodes
import roadcross_ros.srv, roadcross_ros.msg
assert roadcross_ros.srv.Assess.__module__.startswith("roadcross_ros.srv"), roadcross_ros.srv.Assess
PY
fi
echo "ok: $expected"
