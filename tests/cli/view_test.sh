#!/usr/bin/env bash
# roadcross view in headless Chromium: the page works offline (no http(s) resource), loads with
# no console message (a broken page proves the check can fail), draws one path per segment over
# the hillshade, and its screenshot shows the network in the render's colours in about the
# render's proportion; the coordinate search gives roadcross assess's segment, verdict and
# reasons.
source "$(dirname "$0")/lib.sh"
PIXELS="$(dirname "$0")/png_pixels.py"
CHROMIUM=$(command -v chromium || command -v chromium-browser || true)
[[ -n $CHROMIUM ]] || { echo "chromium not installed (scripts/setup.sh installs it)" >&2; exit 1; }
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" --elevation "$ROADCROSS_MAPS_DIR/prague/N50E014.hgt" \
  -o "$WORK/prague.gpkg" -q
"$ROADCROSS" view --db "$WORK/prague.gpkg" -o "$WORK/view" >/dev/null
count=$(sqlite3 "$WORK/prague.gpkg" "SELECT count(*) FROM segments")

for f in index.html data.js view.js view.css hillshade.png leaflet/leaflet.js leaflet/leaflet.css leaflet/LICENSE; do
  [[ -s $WORK/view/$f ]] || fail "missing $f"
done
grep -Eq '(src|href)="https?:' "$WORK/view/index.html" && fail "the page loads something from the network" ||
  pass "every resource is local"
grep -q "OpenStreetMap contributors" "$WORK/view/index.html" && pass "attribution on the page" || fail "no attribution"

# browse URL OUTPUT_ARGS...: headless Chromium, console messages on stderr.
browse() {
  local url=$1; shift
  # Its own profile folder: nothing read from or left in $HOME, no clash with another Chromium.
  timeout 60 "$CHROMIUM" --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=1200,900 \
    --user-data-dir="$WORK/chromium-profile" \
    --enable-logging=stderr --v=0 --virtual-time-budget=5000 "$@" "$url"
}
console_messages() { grep -E 'CONSOLE|Uncaught' "$1" || true; }

# The check catches a broken page: an error thrown and a script that is not there.
mkdir -p "$WORK/broken"
printf '<!doctype html><link rel="icon" href="data:,"><script src="gone.js"></script><script>console.error("boom"); missing();</script>' \
  >"$WORK/broken/index.html"
browse "file://$WORK/broken/index.html" --dump-dom >/dev/null 2>"$WORK/broken.log" || true
[[ -n $(console_messages "$WORK/broken.log") ]] && pass "the console check sees a broken page's errors" ||
  fail "the console check misses errors: $(cat "$WORK/broken.log")"

browse "file://$WORK/view/index.html" --screenshot="$WORK/shot.png" --dump-dom >"$WORK/dom.html" 2>"$WORK/dom.log"
messages=$(console_messages "$WORK/dom.log")
[[ -z $messages ]] && pass "no console messages" || fail "console: $messages"
# Leaflet, the data and the page script all ran: one SVG path per segment, subtitle filled in.
paths=$(grep -o '<path class="leaflet-interactive"' "$WORK/dom.html" | wc -l)
crossing_paths=$(sqlite3 "$WORK/prague.gpkg" "SELECT count(*) FROM crossings WHERE designated = 1")
((paths == count + crossing_paths)) && pass "$paths paths: $count segments + $crossing_paths crossings" ||
  fail "$paths paths for $count segments + $crossing_paths crossings"
grep -q "$count segments" "$WORK/dom.html" && pass "subtitle counts $count segments" || fail "subtitle missing"
grep -Eo '<img[^>]*hillshade.png[^>]*>' "$WORK/dom.html" | grep -q leaflet-image-layer && pass "hillshade overlay" ||
  fail "no hillshade overlay"
grey=$(python3 "$PIXELS" grey "$WORK/shot.png")
((grey > 200000)) && pass "screenshot: $grey grey hillshade pixels" || fail "screenshot: only $grey grey pixels"

# The screenshot shows both colours, in about the proportion of the PNG render of the same map.
"$ROADCROSS" render --db "$WORK/prague.gpkg" -o "$WORK/render.png" >/dev/null
read -r shot_blue shot_red < <(python3 "$PIXELS" count "$WORK/shot.png" '#0072b2' '#d55e00')
read -r png_blue png_red < <(python3 "$PIXELS" count "$WORK/render.png" '#0072b2' '#d55e00')
((shot_blue > 2000 && shot_red > 2000)) && pass "screenshot: $shot_blue blue, $shot_red vermillion pixels" ||
  fail "screenshot: $shot_blue blue, $shot_red vermillion pixels"
shot_share=$(bc -l <<<"$shot_blue / ($shot_blue + $shot_red)")
png_share=$(bc -l <<<"$png_blue / ($png_blue + $png_red)")
near "$shot_share" "$png_share" 0.1 && pass "suitable share: page $shot_share, render $png_share" ||
  fail "suitable share: page $shot_share, render $png_share"

# The search: assess's answer on the centreline, beside the road, and too far from it.
python3 - "$WORK/view/data.js" >"$WORK/places.txt" <<'PY'
import json, math, sys
text = open(sys.argv[1]).read()
data = json.loads(text[text.index('{'):text.rindex('}') + 1])
features = [f for f in data['segments']['features'] if f['properties']['length_m'] > 8]
picked = [next(f for f in features if f['properties']['suitable']),
          next(f for f in features if not f['properties']['suitable'])]
for f in picked:
    c = f['geometry']['coordinates']
    i = len(c) // 2 - 1 if len(c) > 2 else 0
    lon, lat = (c[i][0] + c[i + 1][0]) / 2, (c[i][1] + c[i + 1][1]) / 2
    print(f'{lat:.7f} {lon:.7f}')
# A place 15..60 m from the nearest road (TOO_FAR_FROM_ROAD), whose second-nearest segment is
# clearly further (no tie for the page and the runtime to break differently).
kx, ky = 111195 * math.cos(math.radians(50.08)), 111195
def distance(p, coords):
    best = math.inf
    for a, b in zip(coords, coords[1:]):
        ax, ay, bx, by = (a[0] - p[0]) * kx, (a[1] - p[1]) * ky, (b[0] - p[0]) * kx, (b[1] - p[1]) * ky
        dx, dy = bx - ax, by - ay
        l2 = dx * dx + dy * dy
        t = max(0, min(1, -(ax * dx + ay * dy) / l2)) if l2 else 0
        best = min(best, math.hypot(ax + t * dx, ay + t * dy))
    return best
boxes = []
for g in data['segments']['features']:
    c = g['geometry']['coordinates']
    boxes.append((min(x for x, _ in c), min(y for _, y in c), max(x for x, _ in c), max(y for _, y in c), c))
def distances(p, reach_m=100):
    # Only segments whose box comes within reach_m: further ones cannot be among the nearest two.
    rx, ry = reach_m / kx, reach_m / ky
    return sorted(distance(p, c) for x0, y0, x1, y1, c in boxes
                  if x0 - rx <= p[0] <= x1 + rx and y0 - ry <= p[1] <= y1 + ry) + [math.inf, math.inf]
def far_place():
    for f in features[::41]:
        c = f['geometry']['coordinates']
        for dx, dy in ((0, 30), (0, -30), (30, 0), (-30, 0), (0, 50), (0, -50), (50, 0), (-50, 0)):
            p = (c[0][0] + dx / kx, c[0][1] + dy / ky)
            d = distances(p)
            if 15 < d[0] < 60 and d[1] > d[0] + 3:
                return p
    raise SystemExit('no place 15..60 m from a road found')
p = far_place()
print(f'{p[1]:.7f} {p[0]:.7f}')
PY
while read -r lat lon; do
  browse "file://$WORK/view/index.html#$lat,$lon" --dump-dom >"$WORK/search.html" 2>/dev/null
  page=$(python3 -c 'import html, json, re, sys
m = re.search(r"<pre id=\"result-json\"[^>]*>(.*?)</pre>", open(sys.argv[1]).read(), re.S)
a = json.loads(html.unescape(m.group(1)))
print(a["segment_id"], int(a["valid"]), int(a["suitable"]), ",".join(a["reasons"]), round(a["distance_m"], 1))' "$WORK/search.html")
  "$ROADCROSS" assess --db "$WORK/prague.gpkg" --lat "$lat" --lon "$lon" --json >"$WORK/a.json"
  cli=$(python3 -c 'import json, sys; a = json.load(open(sys.argv[1]))
print(a["segment_id"], int(a["valid"]), int(a["suitable"]), ",".join(a["reasons"]), round(a["distance_m"], 1))' "$WORK/a.json")
  # Same segment, validity, verdict and reasons; distance within 0.2 m (local frame vs UTM).
  if [[ ${page% *} == "${cli% *}" ]] && near "${page##* }" "${cli##* }" 0.2; then
    pass "search $lat,$lon: $page"
  else
    fail "search $lat,$lon: page '$page', assess '$cli'"
  fi
done <"$WORK/places.txt"
[[ $(wc -l <"$WORK/places.txt") == 3 ]] || fail "expected 3 search places"
grep -q "TOO_FAR_FROM_ROAD" "$WORK/search.html" && pass "the last search is off the road" ||
  fail "the off-road search did not give TOO_FAR_FROM_ROAD"
# The panel explains it in the runtime's words (describe_reason) and lists the segment's terms.
grep -q "too far from the road centreline to be at the kerb" "$WORK/search.html" &&
  grep -q "<td>score + context</td>" "$WORK/search.html" && pass "the panel shows reasons and terms" ||
  fail "the panel lacks the reason's sentence or the terms table"

expect_failure "bbox outside the map" "lies outside the map" -- \
  "$ROADCROSS" view --db "$WORK/prague.gpkg" -o "$WORK/v2" --bbox 16.0,49.0,16.1,49.1
[[ ! -e $WORK/v2 ]] && pass "no folder after a failure" || fail "a folder was left after a failure"
touch "$WORK/file"
expect_failure "output is a file" "is not a folder" -- "$ROADCROSS" view --db "$WORK/prague.gpkg" -o "$WORK/file"
expect_failure "output cannot be created" "cannot create folder /proc/roadcross-view" -- \
  "$ROADCROSS" view --db "$WORK/prague.gpkg" -o /proc/roadcross-view
finish
