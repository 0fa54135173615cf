#!/usr/bin/env bash
# Start-up of roadcross-build (the dynamic loader, the libraries' initialisers, the huge-page
# restart), for each roadcross-build binary given (default: the release build's; e.g. also a
# copy of an older build's): its shared libraries, `--version` with the restart and without it
# (ROADCROSS_NO_RELAUNCH=1), and a whole build of the smallest test map (tests/data/reasons.osm)
# with the default options; medians of 40, 40 and 20 runs, the binaries alternating.
# Usage: scripts/bench-build-startup.sh [ROADCROSS_BUILD...]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bench-common.sh
binaries=("$@")
((${#binaries[@]})) || binaries=(build/release/cli/roadcross-build)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
machine_line
python3 - "$work" "${binaries[@]}" <<'PY'
import os, statistics, subprocess, sys, time
work, binaries = sys.argv[1], sys.argv[2:]
plain = {k: v for k, v in os.environ.items() if k not in ("ROADCROSS_NO_RELAUNCH", "GLIBC_TUNABLES")}
no_restart = dict(plain, ROADCROSS_NO_RELAUNCH="1")
cases = [("--version", ["--version"], plain, 40),
         ("--version, no restart", ["--version"], no_restart, 40),
         ("build of reasons.osm", ["--osm", "tests/data/reasons.osm", "-o", work + "/m.gpkg", "-q"], plain, 20)]
for name, args, env, runs in cases:
    times = {b: [] for b in binaries}
    for _ in range(runs):
        for b in binaries:
            start = time.perf_counter()
            subprocess.run([b] + args, check=True, stdout=subprocess.DEVNULL, env=env)
            times[b].append(time.perf_counter() - start)
    for b in binaries:
        print(f"{b}: {name}: {1000 * statistics.median(times[b]):.1f} ms (median of {runs})")
for b in binaries:
    libraries = subprocess.run(["ldd", b], capture_output=True, text=True).stdout.count("=>")
    print(f"{b}: {libraries} shared libraries")
PY
