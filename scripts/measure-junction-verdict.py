#!/usr/bin/env python3
"""The verdict near junctions and on crests, per roadcross DB (docs/cost-model.md, issue 23).

Usage: scripts/measure-junction-verdict.py LABEL=DB.gpkg [LABEL=DB.gpkg ...]

For each DB prints one Markdown table row: the segments, those 10-20 m (midpoint, along the
road) from a junction, how many of them reach the suitability threshold (score + context_score
>= param.suitability.threshold, the DB's own), the same over all segments, their mean rank, and
the CREST_OR_DIP segments that reach the threshold. Reads the DB with Python's sqlite3 only.
"""
import sqlite3
import sys


def threshold_of(db):
    row = db.execute(
        "SELECT value FROM roadcross_metadata WHERE key = 'param.suitability.threshold'"
    ).fetchone()
    return float(row[0]) if row else 20.0


def measure(path):
    db = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    t = threshold_of(db)
    reach = f"(score + coalesce(context_score, 0) >= {t})"
    q = lambda sql: db.execute(sql).fetchone()
    total, reaching = q(f"SELECT count(*), sum({reach}) FROM segments WHERE score IS NOT NULL")
    near, near_reaching, near_rank = q(
        f"SELECT count(*), sum({reach}), avg(rank) FROM segments "
        "WHERE junction_distance_m >= 10 AND junction_distance_m < 20 AND score IS NOT NULL")
    crest, crest_reaching = q(
        f"SELECT count(*), sum({reach}) FROM segments WHERE score IS NOT NULL AND "
        "(',' || reasons || ',') LIKE '%,CREST_OR_DIP,%'")
    return total, reaching or 0, near, near_reaching or 0, near_rank, crest, crest_reaching or 0


def share(part, whole):
    return f"{part} ({100.0 * part / whole:.1f} %)" if whole else "0"


def main(argv):
    if len(argv) < 2 or any("=" not in a for a in argv[1:]):
        sys.stderr.write(__doc__)
        return 2
    print("| DB | segments | reach the threshold | 10-20 m from a junction | of them reach "
          "the threshold | their mean rank | CREST_OR_DIP reaching the threshold |")
    print("|---|---|---|---|---|---|---|")
    for arg in argv[1:]:
        label, path = arg.split("=", 1)
        total, reaching, near, near_reaching, near_rank, crest, crest_reaching = measure(path)
        print(f"| {label} | {total} | {share(reaching, total)} | {near} | "
              f"{share(near_reaching, near)} | {near_rank:.2f} | "
              f"{share(crest_reaching, crest)} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
