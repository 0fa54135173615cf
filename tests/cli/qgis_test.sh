#!/usr/bin/env bash
# The map in real QGIS, headless (Debian's python3-qgis, QT_QPA_PLATFORM=offscreen): the layers
# load with their default styles from layer_styles, and rendered pictures have the expected
# colours where the runtime (`roadcross batch`, an independent judge of the style's rule) says a
# segment is suitable or not, at segments of known rank, and at crossings with and without
# traffic signals (from the crossings table). Details in qgis_check.py.
source "$(dirname "$0")/lib.sh"
HERE="$(cd "$(dirname "$0")" && pwd)"
/usr/bin/python3 -c 'import qgis.core' 2>/dev/null ||
  { echo "python3-qgis is missing: run scripts/setup.sh" >&2; exit 1; }
db="$WORK/prague.gpkg"
"$ROADCROSS_BUILD" -q --osm "$PRAGUE_OSM" --elevation "$ROADCROSS_MAPS_DIR/prague/N50E014.hgt" -o "$db"

# Candidates: each segment's middle point (OGR, GEOS) where no other segment's box comes within
# 2 m, so that the picture's centre shows that segment alone; crossings likewise 3 m apart.
/usr/bin/python3 - "$db" "$WORK/candidates.json" <<'PY'
import json, sys
from osgeo import ogr
ds = ogr.Open(sys.argv[1])
segments = ds.GetLayerByName("segments")
out = {"segments": [], "crossings": []}
points = []
for f in segments:
    g = f.GetGeometryRef()
    p = g.Value(g.Length() / 2)
    points.append((f.GetFID(), p.GetX(), p.GetY(), f.GetField("rank")))
for fid, e, n, rank in points:
    segments.SetSpatialFilterRect(e - 2, n - 2, e + 2, n + 2)
    if segments.GetFeatureCount() == 1:
        out["segments"].append({"fid": fid, "e": e, "n": n, "rank": rank})
crossings = ds.GetLayerByName("crossings")
all_crossings = [(f.GetFID(), f.GetGeometryRef().GetX(), f.GetGeometryRef().GetY(),
                  f.GetField("signals"), f.GetField("designated")) for f in crossings]
for fid, e, n, signals, designated in all_crossings:
    crossings.SetSpatialFilterRect(e - 3, n - 3, e + 3, n + 3)
    if crossings.GetFeatureCount() == 1 and (signals or designated):
        out["crossings"].append({"fid": fid, "e": e, "n": n, "signals": bool(signals)})
json.dump(out, open(sys.argv[2], "w"))
PY
# The runtime's verdict at each candidate (its nearest segment must be the candidate itself).
python3 -c 'import json, sys
for s in json.load(open(sys.argv[1]))["segments"]:
    print(json.dumps({"op": "assess", "easting": s["e"], "northing": s["n"]}))' \
  "$WORK/candidates.json" >"$WORK/requests.jsonl"
"$ROADCROSS" batch --db "$db" <"$WORK/requests.jsonl" >"$WORK/answers.jsonl"
python3 - "$WORK/candidates.json" "$WORK/answers.jsonl" "$WORK/verdicts.json" <<'PY'
import json, sys
candidates = json.load(open(sys.argv[1]))
answers = [json.loads(line) for line in open(sys.argv[2])]
suitable, unsuitable, ranked_low, ranked_high = [], [], [], []
for s, a in zip(candidates["segments"], answers):
    r = a["result"]
    if r["segment_id"] != s["fid"] or r["distance_m"] > 0.01:
        continue
    (suitable if r["suitable"] else unsuitable).append(dict(s, suitable=r["suitable"]))
    if s["rank"] is not None and s["rank"] <= 2: ranked_low.append(s)
    if s["rank"] is not None and s["rank"] >= 12: ranked_high.append(s)
# Every 7th, so that the picks spread over the map; 8 of each kind.
pick = lambda items: items[::7][:8]
signals = [c for c in candidates["crossings"] if c["signals"]]
designated = [c for c in candidates["crossings"] if not c["signals"]]
verdicts = {"segments": pick(suitable) + pick(unsuitable),
            "ranked": pick(ranked_low)[:4] + pick(ranked_high)[:4],
            "crossings": signals[:3] + designated[:3]}
print(f"{len(suitable)} suitable, {len(unsuitable)} unsuitable, {len(ranked_low)} rank <= 2, "
      f"{len(ranked_high)} rank >= 12, {len(signals)} signalled and {len(designated)} other "
      "designated crossings to pick from")
assert len(pick(suitable)) >= 4 and len(pick(unsuitable)) >= 4 and len(signals) >= 1 and len(designated) >= 1
json.dump(verdicts, open(sys.argv[3], "w"))
PY
if QT_QPA_PLATFORM=offscreen XDG_RUNTIME_DIR="$WORK" HOME="$WORK" \
    /usr/bin/python3 "$HERE/qgis_check.py" "$db" "$WORK/verdicts.json" "$WORK" >"$WORK/qgis.txt" 2>"$WORK/qgis.err"; then
  cat "$WORK/qgis.txt"
  pass "QGIS: default styles and colours"
else
  cat "$WORK/qgis.txt"
  grep -v "^QStandardPaths\|^Warning\|propagateSizeHints" "$WORK/qgis.err" | tail -5
  fail "QGIS: see the FAIL lines above"
fi
finish
