#!/usr/bin/env python3
"""Per-segment terrain differences between two roadcross GeoPackages of the same OSM input
(issue 8: the terrain cell size that follows the DEM).

Usage: compare-terrain-terms.py OLD.gpkg NEW.gpkg
Prints, over the segments matched by fid: how many changed landform, elevation_cost, rank and
LIMITED_VISIBILITY (gained / lost), and the median and 95th percentile of |new - old| of
elevation_m, slope_deg, grade_percent, tpi_small_m and tpi_large_m (where both are set).
"""
import sqlite3
import sys

COLUMNS = ("elevation_m", "slope_deg", "grade_percent", "tpi_small_m", "tpi_large_m")


def percentile(sorted_values, q):
    """Nearest-rank percentile (q in 0..100) of a sorted list; None when empty."""
    if not sorted_values:
        return None
    k = max(0, min(len(sorted_values) - 1, int(round(q / 100.0 * len(sorted_values) + 0.5)) - 1))
    return sorted_values[k]


def main():
    db = sqlite3.connect(sys.argv[2])
    db.execute("ATTACH ? AS old", (sys.argv[1],))
    join = "FROM old.segments a JOIN main.segments b ON a.fid = b.fid"
    total = db.execute(f"SELECT count(*) {join}").fetchone()[0]
    print(f"segments: {total}")
    for column in ("landform", "elevation_cost", "rank"):
        n = db.execute(f"SELECT count(*) {join} WHERE a.{column} IS NOT b.{column}").fetchone()[0]
        print(f"{column} changed: {n} ({100.0 * n / total:.1f} %)")
    lv = "'%LIMITED_VISIBILITY%'"
    gained = db.execute(
        f"SELECT count(*) {join} WHERE b.reasons LIKE {lv} AND a.reasons NOT LIKE {lv}").fetchone()[0]
    lost = db.execute(
        f"SELECT count(*) {join} WHERE a.reasons LIKE {lv} AND b.reasons NOT LIKE {lv}").fetchone()[0]
    print(f"LIMITED_VISIBILITY gained: {gained}, lost: {lost}")
    for column in COLUMNS:
        values = sorted(r[0] for r in db.execute(
            f"SELECT abs(b.{column} - a.{column}) {join} "
            f"WHERE a.{column} IS NOT NULL AND b.{column} IS NOT NULL"))
        print(f"|d {column}|: median {percentile(values, 50):.3f}, "
              f"p95 {percentile(values, 95):.3f} (n = {len(values)})")


if __name__ == "__main__":
    main()
