#!/usr/bin/env python3
"""Reads 8-bit RGB/RGBA PNGs (no dependency beyond the standard library) for the picture tests.

  png_pixels.py size FILE                 -> "WIDTH HEIGHT"
  png_pixels.py count FILE HEX...         -> one count per colour: pixels exactly that colour
  png_pixels.py grey FILE                 -> pixels with r == g == b, neither black nor white
  png_pixels.py dark FILE                 -> pixels with every channel below 90 (text, black lines)
"""
import struct
import sys
import zlib


def read_png(path):
    data = open(path, 'rb').read()
    if data[:8] != b'\x89PNG\r\n\x1a\n':
        raise SystemExit(f'{path}: not a PNG')
    pos, idat = 8, b''
    while pos < len(data):
        length, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b'IHDR':
            width, height, depth, color, _, _, interlace = struct.unpack('>IIBBBBB', body)
        elif kind == b'IDAT':
            idat += body
        pos += 12 + length
    if depth != 8 or color not in (2, 6) or interlace:
        raise SystemExit(f'{path}: only 8-bit non-interlaced RGB/RGBA is read (depth {depth}, colour {color})')
    bpp = 3 if color == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * bpp
    rows, prev = [], bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        kind = raw[start]
        row = bytearray(raw[start + 1:start + 1 + stride])
        if kind == 1:
            for i in range(bpp, stride):
                row[i] = (row[i] + row[i - bpp]) & 255
        elif kind == 2:
            row = bytearray((a + b) & 255 for a, b in zip(row, prev))
        elif kind == 3:
            for i in range(stride):
                left = row[i - bpp] if i >= bpp else 0
                row[i] = (row[i] + ((left + prev[i]) >> 1)) & 255
        elif kind == 4:
            for i in range(stride):
                a = row[i - bpp] if i >= bpp else 0
                b = prev[i]
                c = prev[i - bpp] if i >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                row[i] = (row[i] + pred) & 255
        rows.append(row)
        prev = row
    return width, height, bpp, rows


def pixels(rows, bpp):
    for row in rows:
        for i in range(0, len(row), bpp):
            yield row[i], row[i + 1], row[i + 2]


def main():
    command, path = sys.argv[1], sys.argv[2]
    width, height, bpp, rows = read_png(path)
    if command == 'size':
        print(width, height)
    elif command == 'count':
        wanted = [tuple(int(h.lstrip('#')[i:i + 2], 16) for i in (0, 2, 4)) for h in sys.argv[3:]]
        counts = dict.fromkeys(wanted, 0)
        for p in pixels(rows, bpp):
            if p in counts:
                counts[p] += 1
        print(' '.join(str(counts[w]) for w in wanted))
    elif command == 'grey':
        print(sum(1 for r, g, b in pixels(rows, bpp) if r == g == b and 0 < r < 255))
    elif command == 'dark':
        print(sum(1 for r, g, b in pixels(rows, bpp) if max(r, g, b) < 90))
    else:
        raise SystemExit('unknown command ' + command)


if __name__ == '__main__':
    main()
