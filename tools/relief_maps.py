#!/usr/bin/env python3
"""Writes the height and normal maps of the relief scenes (scenes/relief/*.png).

Bricks 64x32 texels with 4-texel mortar joints and 8-texel bevels on a 256x256 tile that
repeats: the height (grey), the tangent-space normal map of the same relief, and the
object-space normal map baked for the `plane` primitive (u along +x, v along +z, normal +y,
so the tangent frame T = +x, B = +z, N = +y). Standard library only.

Usage: python3 tools/relief_maps.py [OUT_DIR]   (default scenes/relief)
"""
import math
import os
import struct
import sys
import zlib

N = 256
BRICK_W, BRICK_H, MORTAR, BEVEL = 64, 32, 4, 8
# Relief of height 1, in texels, for the normal maps' slopes (steep enough to read).
SLOPE = 6.0


def smooth(t):
    t = min(max(t, 0.0), 1.0)
    return t * t * (3.0 - 2.0 * t)


def height(x, y):
    """Bricks: 1 on a brick's face, 0 in the mortar, a smooth bevel between."""
    row = int(y // BRICK_H)
    xs = x + (BRICK_W // 2 if row % 2 else 0)
    fx = xs % BRICK_W
    fy = y % BRICK_H
    d = min(fx, BRICK_W - fx, fy, BRICK_H - fy) - MORTAR / 2.0
    return smooth(d / BEVEL)


def png(path, rows, channels):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    color = {1: 0, 3: 2}[channels]
    h = len(rows)
    w = len(rows[0]) // channels

    def chunk(kind, data):
        c = kind + data
        return struct.pack(">I", len(data)) + c + struct.pack(">I", zlib.crc32(c) & 0xFFFFFFFF)

    out = b"\x89PNG\r\n\x1a\n"
    out += chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, color, 0, 0, 0))
    out += chunk(b"IDAT", zlib.compress(raw, 9))
    out += chunk(b"IEND", b"")
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(out)
    os.replace(tmp, path)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes/relief"
    os.makedirs(out, exist_ok=True)
    # Heights at texel centres, wrapping.
    h = [[height(x + 0.5, y + 0.5) for x in range(N)] for y in range(N)]
    png(os.path.join(out, "bricks_height.png"),
        [[round(255 * v) for v in row] for row in h], 1)
    tangent, obj = [], []
    for y in range(N):
        trow, orow = [], []
        for x in range(N):
            du = (h[y][(x + 1) % N] - h[y][(x - 1) % N]) * 0.5 * SLOPE
            dv = (h[(y + 1) % N][x] - h[(y - 1) % N][x]) * 0.5 * SLOPE
            n = (-du, -dv, 1.0)
            k = 1.0 / math.sqrt(sum(c * c for c in n))
            t = [c * k for c in n]
            enc = lambda v: [round(255 * (c * 0.5 + 0.5)) for c in v]
            trow += enc(t)
            # Object space of the plane primitive: x·T + y·B + z·N = (x, z, y).
            orow += enc((t[0], t[2], t[1]))
        tangent.append(trow)
        obj.append(orow)
    png(os.path.join(out, "bricks_normal.png"), tangent, 3)
    png(os.path.join(out, "bricks_normal_object.png"), obj, 3)


if __name__ == "__main__":
    main()
