#!/usr/bin/env bash
# roadcross render on Prague (with terrain): the PNG is georeferenced by its world file, so GDAL
# (gdallocationinfo) reads the colour at the midpoints of segments whose suitability the test
# decides itself from the DB's columns (the rule of docs/cost-model.md, not the program's code); rank 0
# segments are viridis' yellow; the hillshade shows; bbox, width and bad input.
source "$(dirname "$0")/lib.sh"
PIXELS="$(dirname "$0")/png_pixels.py"
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" --elevation "$ROADCROSS_MAPS_DIR/prague/N50E014.hgt" \
  -o "$WORK/prague.gpkg" -q
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/flat.gpkg" -q

# (without street names, which cover some of the midpoints read below)
"$ROADCROSS" render --db "$WORK/prague.gpkg" -o "$WORK/map.png" --no-street-names --json >"$WORK/render.json"
[[ -s $WORK/map.png && -s $WORK/map.pgw ]] && pass "PNG and world file written" || fail "no PNG/world file"
read -r width height < <(python3 "$PIXELS" size "$WORK/map.png")
[[ $width == 1200 && $height == $(json_field "$WORK/render.json" height_px) ]] &&
  pass "PNG is ${width}x${height}" || fail "PNG size ${width}x${height}"
[[ $(json_field "$WORK/render.json" hillshade) == True ]] && pass "hillshade drawn" || fail "no hillshade"
# The hillshade is grey (r = g = b) under a large part of the picture; without terrain it is not.
grey=$(python3 "$PIXELS" grey "$WORK/map.png")
((grey > width * height / 4)) && pass "$grey grey hillshade pixels" || fail "only $grey grey pixels"
"$ROADCROSS" render --db "$WORK/flat.gpkg" -o "$WORK/flat.png" --width 400 >/dev/null
flat_grey=$(python3 "$PIXELS" grey "$WORK/flat.png")
read -r flat_width flat_height < <(python3 "$PIXELS" size "$WORK/flat.png")
((flat_grey < flat_width * flat_height / 8)) && pass "no hillshade without terrain ($flat_grey grey)" ||
  fail "$flat_grey grey pixels without terrain"

# Midpoints of segments, in UTM, with the suitability decided here from the columns:
# score + context >= threshold, not a motorway/trunk class, not a tunnel, no no_crossing override,
# no LIMITED_VISIBILITY (the default sight.limited_visibility_unsuitable = 1) unless forced.
ogr2ogr -f GeoJSON "$WORK/utm.geojson" "$WORK/prague.gpkg" segments
ogr2ogr -f GeoJSON "$WORK/crossings.geojson" "$WORK/prague.gpkg" crossings
threshold=$(sqlite3 "$WORK/prague.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'param.suitability.threshold'")
python3 - "$WORK" "$threshold" <<'PY'
import json, math, sys
work, threshold = sys.argv[1], float(sys.argv[2])
segments = json.load(open(f'{work}/utm.geojson'))['features']
crossings = [f['geometry']['coordinates'] for f in json.load(open(f'{work}/crossings.geojson'))['features']]
def suitable(p):
    reasons = (p['reasons'] or '').split(',')
    total = (p['score'] or 0) + (p['context_score'] or 0)
    forbidden = 'NOT_CROSSABLE_CLASS' in reasons or p['tunnel'] or p['override_no_crossing']
    hidden = 'LIMITED_VISIBILITY' in reasons
    return not forbidden and (p['score'] is not None and total >= threshold and not hidden
                              or p['override_force_suitable'])
def midpoint(c):
    lengths = [math.dist(a, b) for a, b in zip(c, c[1:])]
    half = sum(lengths) / 2
    for (a, b), l in zip(zip(c, c[1:]), lengths):
        if half <= l:
            t = half / l if l else 0
            return a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])
        half -= l
def near_segment(p, c):
    best = math.inf
    for a, b in zip(c, c[1:]):
        dx, dy = b[0] - a[0], b[1] - a[1]
        l2 = dx * dx + dy * dy
        t = max(0, min(1, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2)) if l2 else 0
        best = min(best, math.dist(p, (a[0] + t * dx, a[1] + t * dy)))
    return best
judged = [(f, suitable(f['properties'])) for f in segments]
# A 20 m grid of the segments' bounding boxes, so that "anything within 10 m" is a local look-up.
grid = {}
for f, ok in judged:
    c = f['geometry']['coordinates']
    xs, ys = [p[0] for p in c], [p[1] for p in c]
    for i in range(int(min(xs) // 20), int(max(xs) // 20) + 1):
        for j in range(int(min(ys) // 20), int(max(ys) // 20) + 1):
            grid.setdefault((i, j), []).append((f, ok))
def neighbours(m):
    i, j = int(m[0] // 20), int(m[1] // 20)
    return [e for di in (-1, 0, 1) for dj in (-1, 0, 1) for e in grid.get((i + di, j + dj), [])]
with open(f'{work}/points.txt', 'w') as points, open(f'{work}/expected.txt', 'w') as expected:
    for f, ok in judged:
        c = f['geometry']['coordinates']
        if f['properties']['length_m'] < 8:
            continue
        m = midpoint(c)
        # Only places where nothing else is drawn near: no crossing symbol within 10 m, no segment of
        # the other verdict within 6 m (a line over it would hide the colour; lines are 7 m wide).
        if any(math.dist(m, x) < 10 for x in crossings):
            continue
        if any(o is not f and s != ok and near_segment(m, o['geometry']['coordinates']) < 6 for o, s in neighbours(m)):
            continue
        rank = f['properties']['rank']
        # For the rank check, also no segment of another rank within 6 m (-1: not checked): the
        # 20 m junction reach puts short runs of other ranks next to many rank-0 segments.
        if any(o is not f and o['properties']['rank'] != rank and near_segment(m, o['geometry']['coordinates']) < 6 for o, _ in neighbours(m)):
            rank = -1
        points.write(f'{m[0]} {m[1]}\n')
        expected.write(f"{int(ok)} {rank}\n")
PY
gdallocationinfo -geoloc -valonly "$WORK/map.png" <"$WORK/points.txt" | paste - - - >"$WORK/colours.txt"
paste -d' ' "$WORK/expected.txt" "$WORK/colours.txt" | awk '
  $1 == 1 { s++; if ($3 == 0 && $4 == 114 && $5 == 178) sok++ }
  $1 == 0 { u++; if ($3 == 213 && $4 == 94 && $5 == 0) uok++ }
  END { printf "%d %d %d %d\n", s, sok, u, uok }' >"$WORK/tally.txt"
read -r s sok u uok <"$WORK/tally.txt"
((s >= 30 && sok * 100 >= s * 95)) && pass "suitable midpoints blue: $sok of $s" ||
  fail "suitable midpoints blue: $sok of $s"
((u >= 10 && uok * 100 >= u * 95)) && pass "unsuitable midpoints vermillion: $uok of $u" ||
  fail "unsuitable midpoints vermillion: $uok of $u"

# --color-by rank: rank 0 is viridis' last stop #fde725, rank 14 its first #440154.
"$ROADCROSS" render --db "$WORK/prague.gpkg" -o "$WORK/rank.png" --color-by rank --no-street-names >/dev/null
gdallocationinfo -geoloc -valonly "$WORK/rank.png" <"$WORK/points.txt" | paste - - - >"$WORK/rank_colours.txt"
read -r r0 r0ok < <(paste -d' ' "$WORK/expected.txt" "$WORK/rank_colours.txt" | awk '
  $2 == 0 { n++; if ($3 == 253 && $4 == 231 && $5 == 37) ok++ } END { print n + 0, ok + 0 }')
# (90 %: the places are away from lines of another rank too, but a crossing symbol or a wide
# junction's lines may still cover a few.)
((r0 >= 10 && r0ok * 100 >= r0 * 90)) && pass "rank 0 midpoints yellow: $r0ok of $r0" ||
  fail "rank 0 midpoints yellow: $r0ok of $r0"
for by in landform context; do
  "$ROADCROSS" render --db "$WORK/prague.gpkg" -o "$WORK/$by.png" --color-by "$by" --width 400 >/dev/null &&
    pass "--color-by $by" || fail "--color-by $by"
done

# --bbox: a part of the map, fewer segments, and the picture covers about that box.
"$ROADCROSS" render --db "$WORK/prague.gpkg" -o "$WORK/part.png" --bbox 14.418,50.074,14.424,50.078 \
  --width 600 --json >"$WORK/part.json"
all=$(json_field "$WORK/render.json" segments)
part=$(json_field "$WORK/part.json" segments)
((part > 10 && part < all / 2)) && pass "bbox: $part of $all segments" || fail "bbox: $part of $all segments"

# Bad input: clear errors, non-zero exit, no output left behind.
expect_failure "unknown --color-by" "unknown --color-by 'speed'" "suitable, rank, landform, context or reason" -- \
  "$ROADCROSS" render --db "$WORK/prague.gpkg" -o "$WORK/x.png" --color-by speed
expect_failure "bbox outside the map" "lies outside the map" -- \
  "$ROADCROSS" render --db "$WORK/prague.gpkg" -o "$WORK/x.png" --bbox 16.0,49.0,16.1,49.1
expect_failure "malformed bbox" "MINLON,MINLAT,MAXLON,MAXLAT" -- \
  "$ROADCROSS" render --db "$WORK/prague.gpkg" -o "$WORK/x.png" --bbox 14.4,50.0
expect_failure "unwritable output" "cannot write /nonexistent/x.png" "does not exist" -- \
  "$ROADCROSS" render --db "$WORK/prague.gpkg" -o /nonexistent/x.png
expect_failure "width out of range" "--width must be in 200..10000" -- \
  "$ROADCROSS" render --db "$WORK/prague.gpkg" -o "$WORK/x.png" --width 50
expect_failure "missing DB" "no-such.gpkg" -- "$ROADCROSS" render --db "$WORK/no-such.gpkg" -o "$WORK/x.png"
cp "$WORK/flat.gpkg" "$WORK/nocrossings.gpkg"
sqlite3 "$WORK/nocrossings.gpkg" "DROP TABLE crossings"
expect_failure "DB without crossings" "no table 'crossings'" -- \
  "$ROADCROSS" render --db "$WORK/nocrossings.gpkg" -o "$WORK/x.png"
[[ ! -e $WORK/x.png ]] && pass "no PNG after a failure" || fail "a PNG was left after a failure"
ls "$WORK" | grep -q '\.tmp\.' && fail "temporary file left behind" || pass "no temporary file left"
finish
