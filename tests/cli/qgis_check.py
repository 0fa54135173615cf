"""Loads a roadcross map in headless QGIS (run by qgis_test.sh with Debian's /usr/bin/python3).

argv: MAP VERDICTS_JSON OUT_DIR. VERDICTS_JSON lists segments with the runtime's own verdict
({"fid", "e", "n", "suitable"}, from `roadcross batch`) and crossings ({"fid", "e", "n",
"signals"}). Prints "ok: ..." / "FAIL: ..." lines; exits 1 on any failure.
"""
import json
import os
import sqlite3
import sys

from qgis.core import (QgsApplication, QgsMapRendererSequentialJob, QgsMapSettings,
                       QgsRasterLayer, QgsRectangle, QgsVectorLayer)
from qgis.PyQt.QtCore import QSize
from qgis.PyQt.QtGui import QColor
from qgis.PyQt.QtXml import QDomDocument

SUITABLE = (26, 150, 65)
UNSUITABLE = (215, 25, 28)
SIGNALS = (43, 131, 186)
DESIGNATED = (255, 255, 255)

failures = 0


def check(condition, what):
    global failures
    print(("ok: " if condition else "FAIL: ") + what)
    if not condition:
        failures += 1


def render_centre(layer, e, n, half_width_m=4.0, size_px=81):
    """The colour at the centre of a picture of `layer` around (e, n): a 8 m square, 0.1 m/px."""
    settings = QgsMapSettings()
    settings.setLayers([layer])
    settings.setDestinationCrs(layer.crs())
    settings.setBackgroundColor(QColor(0, 0, 0))
    settings.setOutputSize(QSize(size_px, size_px))
    settings.setExtent(QgsRectangle(e - half_width_m, n - half_width_m, e + half_width_m,
                                    n + half_width_m))
    job = QgsMapRendererSequentialJob(settings)
    job.start()
    job.waitForFinished()
    image = job.renderedImage()
    colour = QColor(image.pixel(size_px // 2, size_px // 2))
    return (colour.red(), colour.green(), colour.blue()), image


def close(a, b, tolerance=12):
    return all(abs(x - y) <= tolerance for x, y in zip(a, b))


def main():
    path, verdicts_path, out_dir = sys.argv[1:4]
    verdicts = json.load(open(verdicts_path))
    app = QgsApplication([], False)
    app.initQgis()

    segments = QgsVectorLayer(f"{path}|layername=segments", "segments", "ogr")
    check(segments.isValid(), "segments layer loads")
    renderer = segments.renderer()
    check(renderer.type() == "RuleRenderer",
          f"segments come with their default style (renderer {renderer.type()})")
    labels = [rule.label() for rule in renderer.rootRule().children()]
    check(labels == ["suitable to cross", "not suitable"], f"segments style rules {labels}")
    # The other stored style, by rank, is listed and loads.
    count, ids, names, descriptions, error = segments.listStylesInDatabase()
    check({"suitable", "rank"} <= set(names), f"styles in the database: {names} {error}")
    if "rank" in names:
        qml, error = segments.getStyleFromDatabase(ids[names.index("rank")])
        ranked = QgsVectorLayer(f"{path}|layername=segments", "ranked", "ogr")
        doc = QDomDocument()
        doc.setContent(qml)
        ok, message = ranked.importNamedStyle(doc)
        rank_labels = [rule.label() for rule in ranked.renderer().rootRule().children()]
        check(ok and len(rank_labels) == 6 and rank_labels[0] == "rank 0-2 (best)",
              f"the rank style applies: {rank_labels} {message}")
        # fid order = build order; rank 14 is red, rank <= 2 dark green (as the PNG renders).
        for fid_rank in verdicts["ranked"]:
            colour, _ = render_centre(ranked, fid_rank["e"], fid_rank["n"])
            want = SUITABLE if fid_rank["rank"] <= 2 else UNSUITABLE
            check(close(colour, want),
                  f"rank {fid_rank['rank']} segment {fid_rank['fid']}: colour {colour}, want {want}")

    # Rendered colours at segments whose verdict the runtime gave.
    for s in verdicts["segments"]:
        colour, image = render_centre(segments, s["e"], s["n"])
        want = SUITABLE if s["suitable"] else UNSUITABLE
        good = close(colour, want)
        if not good:
            image.save(os.path.join(out_dir, f"segment-{s['fid']}.png"))
        check(good, f"segment {s['fid']} ({'suitable' if s['suitable'] else 'not suitable'} "
                    f"by roadcross assess): rendered {colour}, want {want}")

    crossings = QgsVectorLayer(f"{path}|layername=crossings", "crossings", "ogr")
    check(crossings.isValid() and crossings.renderer().type() == "RuleRenderer",
          f"crossings come with their default style ({crossings.renderer().type()})")
    for c in verdicts["crossings"]:
        colour, _ = render_centre(crossings, c["e"], c["n"])
        want = SIGNALS if c["signals"] else DESIGNATED
        check(close(colour, want), f"crossing {c['fid']} (signals={c['signals']}): rendered "
                                   f"{colour}, want {want}")

    # The terrain's stored style is QML QGIS accepts (3.22 does not load it by itself).
    terrain = QgsRasterLayer(f"GPKG:{path}:terrain", "terrain", "gdal")
    check(terrain.isValid(), "terrain layer loads")
    qml = sqlite3.connect(path).execute(
        "SELECT styleQML FROM layer_styles WHERE f_table_name = 'terrain'").fetchone()[0]
    doc = QDomDocument()
    doc.setContent(qml)
    ok, message = terrain.importNamedStyle(doc)
    check(ok and terrain.renderer().type() == "hillshade",
          f"the terrain's stored style is a hillshade QGIS applies ({terrain.renderer().type()})")
    # Booleans come as booleans.
    field = segments.fields().field("tunnel")
    check(field.typeName().lower().startswith("bool") or field.type() == 1,
          f"tunnel is a boolean field ({field.typeName()})")
    return 1 if failures else 0


if __name__ == "__main__":
    status = main()
    sys.stdout.flush()
    # Not app.exitQgis(): QGIS 3.22's Python teardown crashes (SIGSEGV) after a render.
    os._exit(status)
