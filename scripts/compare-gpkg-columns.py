#!/usr/bin/env python3
"""Column-wise comparison of two roadcross GeoPackages (issue 8, fixed-point obstacle vertices).

Usage: compare-gpkg-columns.py REFERENCE.gpkg NEW.gpkg
For every table both files have (rtree shadow tables skipped: they follow the geometries), the
rows are matched by their first column (fid / id) and each column's differing rows are counted.
For the numeric sight columns the largest absolute difference is printed; for `reasons` the
number of segments that gained or lost LIMITED_VISIBILITY. Exit status 0 always (a report).
"""
import sqlite3
import sys

SIGHT_NUMERIC = ("sight_forward_m", "sight_backward_m", "sight_min_m")


def rows(db, table):
    cols = [r[1] for r in db.execute(f'pragma table_info("{table}")')]
    data = {}
    for r in db.execute(f'select * from "{table}"'):
        data[r[0]] = r
    return cols, data


def main():
    ref = sqlite3.connect(sys.argv[1])
    new = sqlite3.connect(sys.argv[2])
    tables = lambda db: {r[0] for r in db.execute("select name from sqlite_master where type='table'")}
    common = sorted(t for t in tables(ref) & tables(new) if not t.startswith("rtree_"))
    for only in sorted(tables(ref) ^ tables(new)):
        print(f"table only in one file: {only}")
    for table in common:
        cols, a = rows(ref, table)
        cols_new, b = rows(new, table)
        if cols != cols_new:
            print(f"{table}: columns differ")
            continue
        keys = set(a) | set(b)
        missing = sum(1 for k in keys if k not in a or k not in b)
        diffs = {}
        for k in keys:
            if k not in a or k not in b:
                continue
            for i, c in enumerate(cols):
                if a[k][i] != b[k][i]:
                    diffs.setdefault(c, []).append(k)
        if not diffs and not missing:
            print(f"{table}: {len(keys)} rows, all columns same")
            continue
        print(f"{table}: {len(keys)} rows, {missing} rows in one file only")
        for c, ks in diffs.items():
            i = cols.index(c)
            line = f"  {c}: {len(ks)} rows differ"
            if c in SIGHT_NUMERIC:
                def delta(k):
                    x, y = a[k][i], b[k][i]
                    return float("inf") if (x is None) != (y is None) else abs((x or 0) - (y or 0))
                worst = max(ks, key=delta)
                line += f", largest |difference| {delta(worst):.6g} m (row {worst}: {a[worst][i]} -> {b[worst][i]})"
            if c == "reasons":
                gained = sum(1 for k in ks if "LIMITED_VISIBILITY" in (b[k][i] or "") and "LIMITED_VISIBILITY" not in (a[k][i] or ""))
                lost = sum(1 for k in ks if "LIMITED_VISIBILITY" in (a[k][i] or "") and "LIMITED_VISIBILITY" not in (b[k][i] or ""))
                line += f" ({gained} gained LIMITED_VISIBILITY, {lost} lost it)"
            if table == "roadcross_metadata":
                line += "".join(f"\n    {a[k]} -> {b[k]}" for k in ks[:5])
            print(line)


if __name__ == "__main__":
    main()
