#!/usr/bin/env bash
# The viewer's size and time to ready: loads a `roadcross view` folder in headless Chromium RUNS
# times (a fresh profile each time) and reads the time the page's script stamps on <body
# data-ready-ms> once everything is drawn (milliseconds from navigation start: parsing data.js,
# building the page's indices, drawing the network). Prints the folder's size and the median.
#
#   scripts/view_benchmark.sh VIEW_FOLDER [RUNS=5] [PLACE]
#
# PLACE ("lat,lon[,radius]") loads index.html#PLACE, so the time includes one search.
# A page without the stamp (one made before the stamp existed) can be measured by adding, after
# its last <script>: <script>document.body.dataset.readyMs = performance.now().toFixed(0)</script>
set -euo pipefail

folder=${1:?usage: view_benchmark.sh VIEW_FOLDER [RUNS] [PLACE]}
runs=${2:-5}
place=${3:-}
[[ -f $folder/index.html ]] || { echo "view_benchmark: no index.html in $folder" >&2; exit 1; }
chromium=$(command -v chromium || command -v chromium-browser || true)
[[ -n $chromium ]] || { echo "view_benchmark: chromium not installed (scripts/setup.sh)" >&2; exit 1; }
folder=$(cd "$folder" && pwd)
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

bytes=$(find "$folder" -type f -printf '%s\n' | awk '{ total += $1 } END { print total }')
url="file://$folder/index.html${place:+#$place}"
times=()
for ((run = 1; run <= runs; run++)); do
  rm -rf "$scratch/profile"
  timeout 180 "$chromium" --headless --no-sandbox --disable-gpu --hide-scrollbars \
    --window-size=1200,900 --user-data-dir="$scratch/profile" --dump-dom "$url" \
    >"$scratch/dom.html" 2>/dev/null || true
  ms=$(grep -o 'data-ready-ms="[0-9]*"' "$scratch/dom.html" | grep -o '[0-9]*' || true)
  [[ -n $ms ]] || { echo "view_benchmark: run $run: the page never stamped data-ready-ms" >&2; exit 1; }
  times+=("$ms")
done
median=$(printf '%s\n' "${times[@]}" | sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }')
printf 'folder %s: %d bytes (%.1f MB); ready in %s ms (median of %d: %s)\n' \
  "$folder" "$bytes" "$(bc -l <<<"$bytes / 1000000")" "$median" "$runs" "${times[*]}"
