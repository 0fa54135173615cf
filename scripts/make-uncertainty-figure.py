#!/usr/bin/env python3
"""Draws docs/images/uncertainty-junction.png, the picture of docs/runtime.md, "Position
uncertainty": one junction of the bundled Prague map, every fix on a 1 m grid around it coloured
by `roadcross assess` (through `roadcross batch`) under 1, 3 and 6 m of position sigma (panels
left to right), with the 95 % region of one fix drawn in blue in each panel.

Usage: python3 scripts/make-uncertainty-figure.py [BUILD_DIR]   (default build/release; needs
its roadcross and roadcross-build). The PNG is written with zlib alone: no Python dependencies
beyond the standard library.
"""
import json
import math
import os
import pathlib
import sqlite3
import struct
import subprocess
import sys
import tempfile
import zlib

ROOT = pathlib.Path(__file__).resolve().parent.parent
BUILD = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ROOT / "build" / "release")
OUT = ROOT / "docs" / "images" / "uncertainty-junction.png"
OSM = ROOT / "maps" / "prague" / "prague_nove_mesto_roads_2017.osm"
# The T junction of Stepanska (through, SSW-NNE) and V Jame (to the west), UTM 33N metres: a
# graph node of degree 3 whose three segments are all suitable, so that what changes is only
# the uncertainty. The fix whose region is drawn: on Stepanska's west kerb, 6 m south of it.
JUNCTION_UTM_M = (458926.1, 5547652.4)
SHOWN_FIX_OFFSET_M = (-6.0, -4.0)
HALF_SIZE_M = 30.0
STEP_M = 1.0
SIGMAS_M = (1.0, 3.0, 6.0)
COLOURS = {
    "suitable": "#2e9d4a",
    "POSITION_UNCERTAIN": "#f0a020",
    "AMBIGUOUS_ROAD": "#8e44ad",
    "not suitable": "#c9c9c9",
}


def linestring(blob):
    """Points of a GeoPackage LINESTRING blob (header, then little- or big-endian WKB)."""
    flags = blob[3]
    envelope = {0: 0, 1: 32, 2: 48, 3: 48, 4: 64}[(flags >> 1) & 7]
    wkb = blob[8 + envelope:]
    order = "<" if wkb[0] == 1 else ">"
    count = struct.unpack(order + "I", wkb[5:9])[0]
    return [struct.unpack(order + "dd", wkb[9 + 16 * i:25 + 16 * i]) for i in range(count)]


def run(*args, **kwargs):
    return subprocess.run(args, check=True, capture_output=True, text=True, **kwargs).stdout


def category(result):
    if not result["valid"]:
        return None
    if result["suitable"]:
        return "suitable"
    if "AMBIGUOUS_ROAD" in result["reasons"]:
        return "AMBIGUOUS_ROAD"
    if "POSITION_UNCERTAIN" in result["reasons"]:
        return "POSITION_UNCERTAIN"
    return "not suitable"


def main():
    roadcross = BUILD / "cli" / "roadcross"
    with tempfile.TemporaryDirectory() as work:
        db = os.path.join(work, "prague.gpkg")
        run(str(BUILD / "cli" / "roadcross-build"), "--osm", str(OSM), "-o", db, "-q")
        cx, cy = JUNCTION_UTM_M
        with sqlite3.connect(db) as con:
            rows = con.execute(
                "SELECT s.geom FROM segments s JOIN rtree_segments_geom r ON s.fid = r.id "
                "WHERE r.maxx >= ? AND r.minx <= ? AND r.maxy >= ? AND r.miny <= ?",
                (cx - HALF_SIZE_M - 20, cx + HALF_SIZE_M + 20, cy - HALF_SIZE_M - 20,
                 cy + HALF_SIZE_M + 20)).fetchall()
        lines = [linestring(row[0]) for row in rows]
        count = int(2 * HALF_SIZE_M / STEP_M) + 1
        grid = [(cx - HALF_SIZE_M + i * STEP_M, cy - HALF_SIZE_M + j * STEP_M)
                for j in range(count) for i in range(count)]
        panels = []
        for sigma in SIGMAS_M:
            requests = "".join(
                json.dumps({"op": "assess", "easting": x, "northing": y, "sigma_m": sigma}) + "\n"
                for x, y in grid)
            answers = subprocess.run([str(roadcross), "batch", "--db", db], input=requests,
                                     capture_output=True, text=True).stdout.splitlines()
            cells = [category(json.loads(a)["result"]) if json.loads(a)["ok"] else None
                     for a in answers]
            shown = json.loads(run(
                str(roadcross), "assess", "--db", db, "--utm", str(cx + SHOWN_FIX_OFFSET_M[0]),
                str(cy + SHOWN_FIX_OFFSET_M[1]), "--sigma", str(sigma), "--json"))
            panels.append((sigma, cells, shown))
    draw(cx, cy, lines, grid, panels)


def hex_rgb(colour):
    return tuple(int(colour[k:k + 2], 16) for k in (1, 3, 5))


class Canvas:
    """An RGB raster written as PNG with zlib alone (no imaging library needed)."""

    def __init__(self, width, height):
        self.width, self.height = width, height
        self.pixels = bytearray(b"\xff" * (3 * width * height))

    def set(self, x, y, rgb):
        x, y = int(round(x)), int(round(y))
        if 0 <= x < self.width and 0 <= y < self.height:
            k = 3 * (y * self.width + x)
            self.pixels[k:k + 3] = bytes(rgb)

    def rect(self, x0, y0, x1, y1, rgb):
        for y in range(max(0, int(y0)), min(self.height, int(y1))):
            for x in range(max(0, int(x0)), min(self.width, int(x1))):
                k = 3 * (y * self.width + x)
                self.pixels[k:k + 3] = bytes(rgb)

    def dot(self, x, y, radius, rgb):
        r = int(math.ceil(radius))
        for dy in range(-r, r + 1):
            for dx in range(-r, r + 1):
                if dx * dx + dy * dy <= radius * radius:
                    self.set(x + dx, y + dy, rgb)

    def line(self, x0, y0, x1, y1, radius, rgb):
        steps = max(1, int(math.hypot(x1 - x0, y1 - y0) * 2))
        for i in range(steps + 1):
            t = i / steps
            self.dot(x0 + t * (x1 - x0), y0 + t * (y1 - y0), radius, rgb)

    def png(self, path):
        raw = b"".join(b"\x00" + bytes(self.pixels[3 * y * self.width:3 * (y + 1) * self.width])
                       for y in range(self.height))

        def chunk(kind, data):
            return (struct.pack(">I", len(data)) + kind + data +
                    struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff))

        header = struct.pack(">IIBBBBB", self.width, self.height, 8, 2, 0, 0, 0)
        path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) +
                         chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def draw(cx, cy, lines, grid, panels):
    """Three panels left to right (the sigmas in order), each 2 HALF_SIZE_M square."""
    scale = 6  # pixels a metre
    size = int(2 * HALF_SIZE_M * scale)
    margin = 12
    canvas = Canvas(len(panels) * (size + margin) + margin, size + 2 * margin)
    for k, (sigma, cells, shown) in enumerate(panels):
        ox, oy = margin + k * (size + margin), margin

        def px(x, y):
            return ox + (x - cx + HALF_SIZE_M) * scale, oy + (cy + HALF_SIZE_M - y) * scale

        canvas.rect(ox, oy, ox + size, oy + size, (248, 248, 248))
        for (x, y), cell in zip(grid, cells):
            if cell is not None:
                x0, y0 = px(x - STEP_M / 2, y + STEP_M / 2)
                canvas.rect(x0, y0, x0 + STEP_M * scale, y0 + STEP_M * scale,
                            hex_rgb(COLOURS[cell]))
        for line in lines:
            for (xa, ya), (xb, yb) in zip(line, line[1:]):
                canvas.line(*px(xa, ya), *px(xb, yb), 1.2, (0, 0, 0))
        region = shown["region"]
        fx, fy = cx + SHOWN_FIX_OFFSET_M[0], cy + SHOWN_FIX_OFFSET_M[1]
        a, b, t = region["semi_major_m"], region["semi_minor_m"], region["major_axis_yaw_rad"]
        blue = hex_rgb("#1a4fd0")
        for i in range(720):
            u = 2 * math.pi * i / 720
            ex = a * math.cos(u) * math.cos(t) - b * math.sin(u) * math.sin(t)
            ey = a * math.cos(u) * math.sin(t) + b * math.sin(u) * math.cos(t)
            canvas.dot(*px(fx + ex, fy + ey), 1.3, blue)
        canvas.dot(*px(fx, fy), 3.5, blue)
        # Clip what the lines and the ellipse drew outside the panel.
        canvas.rect(ox - margin, 0, ox, canvas.height, (255, 255, 255))
        canvas.rect(ox + size, 0, ox + size + margin, canvas.height, (255, 255, 255))
        canvas.rect(ox, 0, ox + size, oy, (255, 255, 255))
        canvas.rect(ox, oy + size, ox + size, canvas.height, (255, 255, 255))
        print(f"sigma {sigma:g} m: share on suitable places at the blue fix "
              f"{region['suitable_share']:.3f}, reasons {shown['reasons']}")
    OUT.parent.mkdir(parents=True, exist_ok=True)
    canvas.png(OUT)


if __name__ == "__main__":
    main()
