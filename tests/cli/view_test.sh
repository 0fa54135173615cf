#!/usr/bin/env bash
# roadcross view in headless Chromium: the page works offline (no http(s) resource), loads with
# no console message (a broken page proves the check can fail), draws the network on one canvas
# over the hillshade, and its screenshot shows the network in the render's colours in about the
# render's proportion. For places on Prague the page's own answers (assess, road_heading and
# better_place, computed in its script from data.js) equal the runtime's, from roadcross assess,
# heading and better --json: the same segments, verdicts, reasons and candidates, distances and
# headings within what data.js's rounding (positions to 0.01 m, sight distances to 0.1 m) allows.
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
# Leaflet, the data and the page script all ran: the network canvas, the stamp the script sets
# once everything is drawn, the subtitle filled in.
grep -q '<canvas class="roadcross-network' "$WORK/dom.html" && pass "the network is one canvas" || fail "no network canvas"
paths=$(grep -o '<path class="leaflet-interactive"' "$WORK/dom.html" | wc -l || true)
((paths == 0)) && pass "no SVG path per segment" || fail "$paths SVG paths"
grep -q 'data-ready-ms="[0-9]*"' "$WORK/dom.html" && pass "the page stamped its ready time" || fail "no data-ready-ms"
grep -q "$count segments" "$WORK/dom.html" && pass "subtitle counts $count segments" || fail "subtitle missing"
grep -Eo '<img[^>]*hillshade.png[^>]*>' "$WORK/dom.html" | grep -q leaflet-image-layer && pass "hillshade overlay" ||
  fail "no hillshade overlay"
grey=$(python3 "$PIXELS" grey "$WORK/shot.png")
((grey > 200000)) && pass "screenshot: $grey grey hillshade pixels" || fail "screenshot: only $grey grey pixels"

# The screenshot shows both colours, in about the proportion of the PNG render of the same map.
"$ROADCROSS" render --db "$WORK/prague.gpkg" -o "$WORK/render.png" --no-street-names >/dev/null
read -r shot_blue shot_red < <(python3 "$PIXELS" count "$WORK/shot.png" '#0072b2' '#d55e00')
read -r png_blue png_red < <(python3 "$PIXELS" count "$WORK/render.png" '#0072b2' '#d55e00')
((shot_blue > 2000 && shot_red > 2000)) && pass "screenshot: $shot_blue blue, $shot_red vermillion pixels" ||
  fail "screenshot: $shot_blue blue, $shot_red vermillion pixels"
shot_share=$(bc -l <<<"$shot_blue / ($shot_blue + $shot_red)")
png_share=$(bc -l <<<"$png_blue / ($png_blue + $png_red)")
near "$shot_share" "$png_share" 0.1 && pass "suitable share: page $shot_share, render $png_share" ||
  fail "suitable share: page $shot_share, render $png_share"

# Places: Resslova (the README's example) with the default search radius and with 300 m, 3 m
# beside the middle of an edge of ten segments longer than 8 m spread over the map (alternately left and
# right of it), and one 15..60 m from any road (TOO_FAR_FROM_ROAD). Chosen from GDAL's WGS84
# export of the map, not from the page's data.
ogr2ogr -f GeoJSON -t_srs EPSG:4326 "$WORK/wgs84.geojson" "$WORK/prague.gpkg" segments
python3 - "$WORK/wgs84.geojson" >"$WORK/places.txt" <<'PY'
import json, math, sys
features = json.load(open(sys.argv[1]))['features']
kx, ky = 111195 * math.cos(math.radians(50.08)), 111195
print('50.0757 14.4160 100')
print('50.0757 14.4160 300')
long_ones = [f for f in features if f['properties']['length_m'] > 8]
for k, f in enumerate(long_ones[::max(1, len(long_ones) // 10)]):
    c = f['geometry']['coordinates']
    i = (len(c) - 1) // 2
    (x0, y0), (x1, y1) = c[i], c[i + 1]
    dx, dy = (x1 - x0) * kx, (y1 - y0) * ky
    norm = math.hypot(dx, dy) or 1
    side = 1 if k % 2 else -1
    lon = (x0 + x1) / 2 - side * 3 * dy / norm / kx
    lat = (y0 + y1) / 2 + side * 3 * dx / norm / ky
    print(f'{lat:.7f} {lon:.7f} 200')
def distance(p, coords):
    best = math.inf
    for a, b in zip(coords, coords[1:]):
        ax, ay, bx, by = (a[0] - p[0]) * kx, (a[1] - p[1]) * ky, (b[0] - p[0]) * kx, (b[1] - p[1]) * ky
        dx, dy = bx - ax, by - ay
        l2 = dx * dx + dy * dy
        t = max(0, min(1, -(ax * dx + ay * dy) / l2)) if l2 else 0
        best = min(best, math.hypot(ax + t * dx, ay + t * dy))
    return best
for f in features[::41]:
    c = f['geometry']['coordinates']
    found = None
    for dx, dy in ((0, 30), (0, -30), (30, 0), (-30, 0), (0, 50), (0, -50)):
        p = (c[0][0] + dx / kx, c[0][1] + dy / ky)
        d = sorted(distance(p, g['geometry']['coordinates']) for g in features
                   if abs(g['geometry']['coordinates'][0][0] - p[0]) * kx < 400 and
                   abs(g['geometry']['coordinates'][0][1] - p[1]) * ky < 400) + [math.inf, math.inf]
        if 15 < d[0] < 60 and d[1] > d[0] + 3:
            found = p
            break
    if found:
        print(f'{found[1]:.7f} {found[0]:.7f} 100')
        break
PY
places=$(wc -l <"$WORK/places.txt")
((places >= 8)) && pass "$places places to compare" || fail "only $places places"

# compare PAGE_JSON ASSESS HEADING BETTER: the page's answers against the runtime's.
compare() {
  python3 - "$@" <<'PY'
import html, json, math, re, sys
text = open(sys.argv[1]).read()
m = re.search(r'<pre id="result-json"[^>]*>(.*?)</pre>', text, re.S)
page = json.loads(html.unescape(m.group(1)))
assess, heading, better = (json.load(open(p)) for p in sys.argv[2:5])
problems = []
def same(what, a, b):
    if a != b: problems.append(f'{what}: page {a!r}, runtime {b!r}')
def close(what, a, b, tolerance):
    if a is None or b is None:
        same(what, a, b)
    elif abs(a - b) > tolerance:
        problems.append(f'{what}: page {a}, runtime {b}')
def close_angle(what, a, b, tolerance):
    close(what, abs(math.remainder(a - b, 2 * math.pi)), 0, tolerance)
pa = page['assess']
for key in ('segment_id', 'valid', 'suitable', 'reasons', 'score', 'context_score', 'rank', 'robot_side'):
    same('assess ' + key, pa[key], assess[key])
close('assess distance_m', pa['distance_m'], assess['distance_m'], 0.02)
for key in ('sight_forward_m', 'sight_backward_m', 'required_sight_m'):
    close('assess ' + key, pa[key], assess[key], 0.05)
ph = page['heading']
same('heading segment_id', ph['segment_id'], heading['segment_id'])
same('heading on_centreline', ph['on_centreline'], heading['on_centreline'])
# 0.01 rad: the direction of an edge whose ends data.js rounds to 0.01 m turns by up to
# 0.014 m / length, 0.01 rad on a 1.4 m edge (maps have edges that short at a road's bend).
for key in ('road_heading_rad', 'crossing_heading_rad'):
    close_angle('heading ' + key, ph[key], heading[key], 0.01)
pb = page['better']
same('better reason', pb['reason'], better['reason'])
same('better segments', [c['segment_id'] for c in pb['candidates']], [c['segment_id'] for c in better['candidates']])
for c, r in zip(pb['candidates'], better['candidates']):
    for key in ('suitable', 'score_plus_context', 'designated_crossing', 'reasons'):
        same(f'better {r["segment_id"]} {key}', c[key], r[key])
    close(f'better {r["segment_id"]} walking_distance_m', c['walking_distance_m'], r['walking_distance_m'], 0.1)
    close(f'better {r["segment_id"]} point', math.dist(c['point_utm_m'], r['point_utm_m']), 0, 0.05)
    close_angle(f'better {r["segment_id"]} crossing_heading_rad', c['crossing_heading_rad'], r['crossing_heading_rad'], 0.01)
if problems:
    print('; '.join(problems))
    sys.exit(1)
print(f"segment {pa['segment_id']}, {'suitable' if pa['suitable'] else 'not suitable'} ({','.join(pa['reasons'])}), "
      f"sight {pa['sight_forward_m']}/{pa['sight_backward_m']} of {pa['required_sight_m']} m, "
      f"crossing {math.degrees(ph['crossing_heading_rad']):.1f} deg, {len(pb['candidates'])} better places")
PY
}
candidates_seen=0
while read -r lat lon radius; do
  browse "file://$WORK/view/index.html#$lat,$lon,$radius" --dump-dom >"$WORK/search.html" 2>/dev/null
  place=(--db "$WORK/prague.gpkg" --lat "$lat" --lon "$lon" --json)
  "$ROADCROSS" assess "${place[@]}" >"$WORK/assess.json"
  "$ROADCROSS" heading "${place[@]}" >"$WORK/heading.json"
  "$ROADCROSS" better "${place[@]}" --radius "$radius" >"$WORK/better.json"
  if result=$(compare "$WORK/search.html" "$WORK/assess.json" "$WORK/heading.json" "$WORK/better.json"); then
    pass "$lat,$lon (radius $radius m): $result"
  else
    fail "$lat,$lon (radius $radius m): $result"
  fi
  candidates_seen=$((candidates_seen + $(python3 -c 'import json, sys; print(len(json.load(open(sys.argv[1]))["candidates"]))' "$WORK/better.json")))
done <"$WORK/places.txt"
((candidates_seen >= 10)) && pass "$candidates_seen better places compared" || fail "only $candidates_seen better places compared"
grep -q "TOO_FAR_FROM_ROAD" "$WORK/search.html" && pass "the last search is off the road" ||
  fail "the off-road search did not give TOO_FAR_FROM_ROAD"
# The panel explains it in the runtime's words (describe_reason), lists the segment's terms and
# its sight distances.
grep -q "too far from the road centreline to be at the kerb" "$WORK/search.html" &&
  grep -q "<td>score + context</td>" "$WORK/search.html" && grep -q "Sight along the road" "$WORK/search.html" &&
  pass "the panel shows reasons, terms and sight" || fail "the panel lacks the reason's sentence, the terms or the sight"
# Resslova: the sight behind its LIMITED_VISIBILITY, its heading and a better place drawn.
browse "file://$WORK/view/index.html#50.0757,14.4160,300" --dump-dom >"$WORK/resslova.html" 2>/dev/null
grep -q "LIMITED_VISIBILITY" "$WORK/resslova.html" && grep -q "m short" "$WORK/resslova.html" &&
  grep -q "Heading</b>: cross towards" "$WORK/resslova.html" && grep -q 'leaflet-marker-icon candidate' "$WORK/resslova.html" &&
  pass "Resslova: the short sight, the heading and the better places on the map" ||
  fail "Resslova's panel or markers are missing"

expect_failure "bbox outside the map" "lies outside the map" -- \
  "$ROADCROSS" view --db "$WORK/prague.gpkg" -o "$WORK/v2" --bbox 16.0,49.0,16.1,49.1
[[ ! -e $WORK/v2 ]] && pass "no folder after a failure" || fail "a folder was left after a failure"
touch "$WORK/file"
expect_failure "output is a file" "is not a folder" -- "$ROADCROSS" view --db "$WORK/prague.gpkg" -o "$WORK/file"
expect_failure "output cannot be created" "cannot create folder /proc/roadcross-view" -- \
  "$ROADCROSS" view --db "$WORK/prague.gpkg" -o /proc/roadcross-view
finish
