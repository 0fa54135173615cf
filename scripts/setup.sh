#!/usr/bin/env bash
# Installs the Debian 12 packages roadcross needs. Non-interactive and idempotent:
# when every package is already installed it only checks (well under a second).
set -euo pipefail

packages=(
  build-essential cmake pkg-config ccache
  # preprocess (roadcross-build)
  libosmium2-dev libprotozero-dev libbz2-dev libexpat1-dev zlib1g-dev liblz4-dev
  libdeflate-dev  # .pbf blobs inflated about twice as fast as by zlib (src/osm/pbf_inflate.cpp)
  libgdal-dev libcgal-dev libeigen3-dev libboost-dev
  libssl-dev  # OpenSSL libcrypto: SHA-256 of the input files
  # runtime
  libsqlite3-dev libgeographiclib-dev
  # map identity (mapcheck: SHA-256 of a map's content for roadcross-build, verify, install)
  libssl-dev
  # Python bindings (built for Debian's /usr/bin/python3)
  pybind11-dev python3-dev
  # cli and tests
  libcli11-dev nlohmann-json3-dev libgtest-dev libgmock-dev libbenchmark-dev
  # render (Cairo draws the PNG; its text needs a font)
  libcairo2-dev fonts-dejavu-core
  # checking tools used by tests and benchmarks
  osmium-tool gdal-bin sqlite3 time bc gnuplot-nox
  # the fuzzing campaign (scripts/fuzz.sh): clang with libFuzzer's runtime (libclang_rt.fuzzer)
  clang libclang-rt-14-dev
  # GDAL's GeoPackage validator (osgeo_utils/samples/validate_gpkg.py) checks every test map
  python3-gdal
  # type-checks the Python examples of docs/embedding.md against python/roadcross.pyi
  python3-mypy
  # the viewer's test loads the page in headless Chromium
  chromium
  # the QGIS test loads a map with its default styles in headless QGIS (python3-qgis brings
  # QGIS's core library; qgis-providers reads GeoPackages); about 165 packages with
  # --no-install-recommends, installed here once rather than in the test so that the test
  # stays fast and works offline
  python3-qgis qgis-providers
  # `pip install .` of the Python module, offline, with Debian's build front end
  python3-build python3-venv python3-pip python3-setuptools python3-wheel
  # ROS1 node (ros/): roscpp, the message packages it uses (headers and .msg definitions),
  # gencpp/genpy to generate the node's C++ and Python messages, and for its test rosmaster,
  # roslaunch and rospy with the Python sensor/geometry messages
  libroscpp-dev libstd-msgs-dev libsensor-msgs-dev libgeometry-msgs-dev libnav-msgs-dev
  ros-std-msgs ros-geometry-msgs python3-gencpp python3-genpy python3-genmsg python3-rosmaster
  python3-roslaunch python3-rosparam python3-rospy python3-rosservice python3-std-msgs
  python3-sensor-msgs python3-geometry-msgs python3-nav-msgs
  # the node publishes its map's identity on /diagnostics (diagnostic_msgs/DiagnosticArray);
  # the Python messages for its test
  libdiagnostic-msgs-dev python3-diagnostic-msgs
)

missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$package")
done

if ((${#missing[@]} == 0)); then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
