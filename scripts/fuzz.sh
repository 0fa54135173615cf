#!/usr/bin/env bash
# The fuzzing campaign (docs/reliability.md): builds the libFuzzer targets of tests/fuzz (preset
# `fuzz`: clang, ASan + UBSan), replays the committed regression inputs, then runs each target
# for a bounded time on its seed corpus (tests/fuzz/corpus, plus seeds made from the bundled maps
# here). Any crash, sanitizer report, uncaught exception or hang (> 10 s on one input) fails the
# script; the input is kept in build/fuzz/artifacts/ (make it a regression: copy it into
# tests/fuzz/regressions/TARGET/).
#
#   scripts/fuzz.sh                 every target, ROADCROSS_FUZZ_SECONDS (default 20) s each
#   scripts/fuzz.sh map xyz         only these targets
#   ROADCROSS_FUZZ_SECONDS=600 scripts/fuzz.sh map    a longer campaign
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
seconds=${ROADCROSS_FUZZ_SECONDS:-20}
all_targets=(xyz osm_tags parameter_file overrides pbf_inflate gpkg_geometry gap_line batch_line map)
targets=("${@:-${all_targets[@]}}")
[ $# -eq 0 ] && targets=("${all_targets[@]}")

started=$(date +%s)
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j2 --target fuzz_targets roadcross-build
built=$(date +%s)
bin=$root/build/fuzz/tests/fuzz
artifacts=$root/build/fuzz/artifacts
mkdir -p "$artifacts"
work=$(mktemp -d "${TMPDIR:-/tmp}/roadcross-fuzz.XXXXXX")
trap 'rm -rf "$work"' EXIT

# The small real map the runtime targets query (and damage): context_tags.osm, every tag case.
export ROADCROSS_FUZZ_MAP=$work/small.gpkg
ASAN_OPTIONS=detect_leaks=0 "$root/build/fuzz/cli/roadcross-build" -q \
  --osm tests/data/context_tags.osm -o "$ROADCROSS_FUZZ_MAP"

# Seeds made from the bundled maps, beside the committed ones.
seeds=$work/seeds
mkdir -p "$seeds"/{xyz,osm_tags,parameter_file,pbf_inflate,gpkg_geometry,batch_line}
head -c 4000 maps/zabaged/BILO48_5g_40k.csv >"$seeds/xyz/bilo48.csv"
head -c 4000 maps/zabaged/test_pointcloud.txt >"$seeds/xyz/pointcloud.txt"
ASAN_OPTIONS=detect_leaks=0 "$root/build/fuzz/cli/roadcross-build" --print-config \
  >"$seeds/parameter_file/printed.toml"
python3 - "$seeds" "$ROADCROSS_FUZZ_MAP" maps/prague/prague_nove_mesto_roads_2017.osm \
  maps/techobuz/techobuz_2018.osm <<'PY'
import json, re, sqlite3, sys, zlib
seeds, gpkg, *osm = sys.argv[1:]
# Tag values as the parsers meet them (maxspeed, lanes, width and their variants), NUL-joined.
values = set()
for path in osm:
    text = open(path, encoding="utf-8").read()
    for key, value in re.findall(r'k="((?:max)?speed[^"]*|lanes[^"]*|width[^"]*)" v="([^"]*)"', text):
        values.add(value)
for i, value in enumerate(sorted(values)[:200]):
    open(f"{seeds}/osm_tags/{i}.bin", "wb").write(value.encode() + b"\0" + value.encode())
db = sqlite3.connect(gpkg)
for i, (blob,) in enumerate(db.execute("SELECT geom FROM segments LIMIT 40")):
    open(f"{seeds}/gpkg_geometry/segment{i}.bin", "wb").write(blob)
for i, (blob,) in enumerate(db.execute("SELECT geom FROM crossings LIMIT 10")):
    open(f"{seeds}/gpkg_geometry/crossing{i}.bin", "wb").write(blob)
min_x, min_y, max_x, max_y = db.execute(
    "SELECT min_x, min_y, max_x, max_y FROM gpkg_contents WHERE table_name = 'segments'").fetchone()
# zlib streams as a .pbf holds them (a 2-byte room, then the stream): strings and varints of
# OSM data, whole and with the room one short.
raw = open(osm[0], "rb").read(20000)
for level in (1, 6, 9):
    for cut in (4000, 20000):
        stream = zlib.compress(raw[:cut], level)
        for room in (cut, cut - 1):
            open(f"{seeds}/pbf_inflate/l{level}_{cut}_{room}.bin", "wb").write(
                room.to_bytes(2, "little") + stream)
for i, op in enumerate(["assess", "better", "heading", "nearest"]):
    e, n = min_x + (max_x - min_x) * (i + 1) / 5, min_y + (max_y - min_y) * (i + 1) / 5
    open(f"{seeds}/batch_line/{op}.json", "w").write(
        json.dumps({"op": op, "easting": e, "northing": n, "radius_m": 60}))
PY

status=0
summary=$work/summary.txt
for target in "${targets[@]}"; do
  corpus=$work/corpus/$target
  mkdir -p "$corpus"
  cp tests/fuzz/corpus/"$target"/* "$corpus"/ 2>/dev/null || true
  cp "$seeds/$target"/* "$corpus"/ 2>/dev/null || true
  # First the inputs that once failed: each must pass now.
  if compgen -G "tests/fuzz/regressions/$target/*" >/dev/null; then
    if ! "$bin/${target}_fuzz" tests/fuzz/regressions/"$target"/* >"$work/$target.replay" 2>&1; then
      tail -40 "$work/$target.replay"
      echo "fuzz: $target: a regression input fails again" >&2
      status=1
      continue
    fi
  fi
  log=$work/$target.log
  if ! TMPDIR=$work "$bin/${target}_fuzz" "$corpus" -max_total_time="$seconds" -timeout=10 \
      -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
      -artifact_prefix="$artifacts/$target-" >"$log" 2>&1; then
    grep -E "ERROR|SUMMARY|Test unit written|==[0-9]+==|#0 |#1 |#2 |#3 " "$log" | head -30
    echo "fuzz: $target: FAILED (input kept in $artifacts/)" >&2
    status=1
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  printf '%-15s %10s inputs  %6s coverage points  %s s\n' "$target" "${runs:-?}" "${cov:-?}" \
    "$seconds" | tee -a "$summary"
done
finished=$(date +%s)
echo "fuzz: build $((built - started)) s, seeds and runs $((finished - built)) s, total $((finished - started)) s"
exit $status
