#!/usr/bin/env bash
# `cpack -G DEB` makes the Debian packages docs/embedding.md names, and the ROS package's
# layout is one ROS's own tools resolve: rospkg finds roadcross_ros, roslib finds the node
# executable and the generated Python services import (all from the unpacked package, not the
# build tree).
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cpack -G DEB -B "$work" --config "$ROADCROSS_BINARY_DIR/CPackConfig.cmake" >"$work/cpack.log" 2>&1 ||
  { cat "$work/cpack.log" >&2; exit 1; }
expected="roadcross-runtime-dev roadcross-tools"
grep -q '^ROADCROSS_BUILD_PYTHON:BOOL=ON' "$ROADCROSS_BINARY_DIR/CMakeCache.txt" && expected+=" python3-roadcross"
ros=0
grep -q '^ROADCROSS_BUILD_ROS:BOOL=ON' "$ROADCROSS_BINARY_DIR/CMakeCache.txt" && ros=1 && expected+=" roadcross-ros"
for package in $expected; do
  ls "$work/${package}"_*.deb >/dev/null 2>&1 || { echo "FAIL: no $package package" >&2; ls "$work" >&2; exit 1; }
done
tools_files=$(dpkg-deb -c "$work"/roadcross-tools_*.deb)  # (grep -q on the pipe would cut it)
for program in roadcross roadcross-build roadcross-viz; do
  grep -q "/usr/bin/$program\$" <<<"$tools_files" ||
    { echo "FAIL: roadcross-tools lacks usr/bin/$program" >&2; exit 1; }
done

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
