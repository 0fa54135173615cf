#!/usr/bin/env bash
# Sight columns of two roadcross-build binaries on every bundled map (issue 27): builds each map
# (and each map with its SRTM rasters, where it has them) with REFERENCE and NEW, then compares
# sight_forward_m, sight_backward_m and sight_min_m segment by segment (joined on fid) with
# sqlite3, and counts the segments that gained or lost LIMITED_VISIBILITY. Prints one Markdown
# table row per input: segments, rows whose sight columns differ, the share within 1 m, the
# largest difference, LIMITED_VISIBILITY gained / lost, and whether map_id (the digest of the
# whole content) is the same.
# Usage: scripts/compare-sight.sh REFERENCE-roadcross-build NEW-roadcross-build [extra build args]
# Keep a copy of the reference binary before rebuilding (cp build/release/cli/roadcross-build
# /tmp/roadcross-build.ref): the build directory holds only the newest one.
set -euo pipefail
cd "$(dirname "$0")/.."
(($# >= 2)) || { sed -n '2,13p' "$0" >&2; exit 2; }
reference=$1 new=$2
shift 2
for tool in "$reference" "$new"; do
  [[ -x "$tool" ]] || { echo "compare-sight.sh: $tool is not an executable" >&2; exit 2; }
done
command -v sqlite3 >/dev/null || { echo "compare-sight.sh: needs the sqlite3 command" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# compare LABEL BUILD-ARGS...: one table row.
compare() {
  local label=$1
  shift
  if ! "$reference" "$@" -o "$work/reference.gpkg" -q; then
    echo "compare-sight.sh: $reference failed on $label" >&2
    exit 1
  fi
  if ! "$new" "$@" -o "$work/new.gpkg" -q; then
    echo "compare-sight.sh: $new failed on $label" >&2
    exit 1
  fi
  # A NULL (tunnel, or the stage off) equals only a NULL: IS NOT compares them so.
  local row
  row=$(sqlite3 -separator ' | ' "$work/new.gpkg" <<SQL
ATTACH '$work/reference.gpkg' AS ref;
WITH pairs AS (
  SELECT n.sight_forward_m AS nf, r.sight_forward_m AS rf,
         n.sight_backward_m AS nb, r.sight_backward_m AS rb,
         n.sight_min_m AS nm, r.sight_min_m AS rm,
         instr(n.reasons, 'LIMITED_VISIBILITY') > 0 AS n_limited,
         instr(r.reasons, 'LIMITED_VISIBILITY') > 0 AS r_limited
  FROM main.segments n JOIN ref.segments r ON n.fid = r.fid),
deltas AS (
  SELECT *, max(coalesce(abs(nf - rf), 0), coalesce(abs(nb - rb), 0),
                coalesce(abs(nm - rm), 0)) AS delta_m,
         (nf IS NOT rf) OR (nb IS NOT rb) OR (nm IS NOT rm) AS differs,
         (nf IS NULL) <> (rf IS NULL) OR (nb IS NULL) <> (rb IS NULL) AS null_changed
  FROM pairs)
SELECT count(*),
       sum(differs),
       printf('%.3f %%', 100.0 * sum(NOT null_changed AND delta_m <= 1.0) / count(*)),
       printf('%.3f m', max(delta_m)),
       sum(n_limited AND NOT r_limited) || ' / ' || sum(r_limited AND NOT n_limited),
       (SELECT count(*) FROM main.segments) - count(*),
       (SELECT count(*) FROM ref.segments) - count(*)
FROM deltas;
SQL
)
  local id_new id_ref same_id=no
  id_new=$(sqlite3 "$work/new.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'map_id'")
  id_ref=$(sqlite3 "$work/reference.gpkg" "SELECT value FROM roadcross_metadata WHERE key = 'map_id'")
  [[ "$id_new" == "$id_ref" ]] && same_id=yes
  IFS='|' read -r segments differ within worst flips only_new only_ref <<<"${row// | /|}"
  if ((only_new != 0 || only_ref != 0)); then
    echo "compare-sight.sh: $label: the two builds have different segments ($only_new only in new, $only_ref only in reference)" >&2
    exit 1
  fi
  echo "| $label | $segments | $differ | $within | $worst | $flips | $same_id |"
}

echo "| input | segments | sight columns differ | within 1 m | largest difference | LIMITED_VISIBILITY gained / lost | map_id equal |"
echo "|---|---|---|---|---|---|---|"
compare "prague" --osm maps/prague/prague_nove_mesto_roads_2017.osm "$@"
compare "prague + SRTM" --osm maps/prague/prague_nove_mesto_roads_2017.osm \
  --elevation maps/prague/N50E014.hgt "$@"
compare "monaco" --osm maps/monaco/monaco.osm.pbf "$@"
compare "monaco + SRTM" --osm maps/monaco/monaco.osm.pbf --elevation maps/monaco/N43E007.hgt "$@"
compare "bayreuth" --osm maps/bayreuth/north-bayreuth.osm.gz "$@"
compare "bayreuth + SRTM" --osm maps/bayreuth/north-bayreuth.osm.gz \
  --elevation maps/bayreuth/N49E011.hgt --elevation maps/bayreuth/N50E011.hgt "$@"
compare "techobuz" --osm maps/techobuz/techobuz_2018.osm "$@"
