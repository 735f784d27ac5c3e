#!/usr/bin/env python3
"""Writes the small images of the surface-detail scenes (scenes/detail/): a tileable detail
map, a baked light map, a decal with alpha, a toon ramp and grey stripes. Standard library
only; the output is the same on every run. Usage: python3 tools/surface_detail_images.py"""

import math
import os
import random
import struct
import zlib

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "detail")


def png(name, width, height, channels, pixel):
    """Writes an 8-bit PNG whose pixel (x, y) is pixel(x, y): a tuple of `channels` 0..255."""
    color_type = {1: 0, 2: 4, 3: 2, 4: 6}[channels]
    raw = bytearray()
    for y in range(height):
        raw.append(0)
        for x in range(width):
            raw.extend(max(0, min(255, int(round(v)))) for v in pixel(x, y))

    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    head = struct.pack(">IIBBBBB", width, height, 8, color_type, 0, 0, 0)
    data = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", head)
    data += chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b"")
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(data)


def tileable_noise(size, cells, seed):
    """Value noise on a `cells`-periodic lattice, smoothstep-interpolated, in [0, 1]."""
    rnd = random.Random(seed)
    lattice = [[rnd.random() for _ in range(cells)] for _ in range(cells)]

    def at(x, y):
        fx, fy = x * cells / size, y * cells / size
        ix, iy = int(fx), int(fy)
        tx, ty = fx - ix, fy - iy
        tx, ty = tx * tx * (3 - 2 * tx), ty * ty * (3 - 2 * ty)
        g = lambda i, j: lattice[j % cells][i % cells]
        a = g(ix, iy) * (1 - tx) + g(ix + 1, iy) * tx
        b = g(ix, iy + 1) * (1 - tx) + g(ix + 1, iy + 1) * tx
        return a * (1 - ty) + b * ty

    return at


def main():
    os.makedirs(OUT, exist_ok=True)
    # Detail: grey, centred on 128 (0.5 linear), two octaves of tileable noise, ±35%.
    n1, n2 = tileable_noise(64, 8, 1), tileable_noise(64, 16, 2)
    png("detail.png", 64, 64, 1,
        lambda x, y: (128 + 90 * ((n1(x, y) - 0.5) + 0.6 * (n2(x, y) - 0.5)),))
    # Light map: a warm pool of light from the back left, a cool fill, the soft shadow of a
    # box in the middle (baked irradiance, sRGB-encoded).
    def light(x, y):
        u, v = (x + 0.5) / 64, (y + 0.5) / 64
        d = math.hypot(u - 0.3, v - 0.3)
        pool = math.exp(-d * d / 0.15)
        # The box's shadow: a soft rectangle towards the lower right of its centre.
        sx = min(max((0.17 - abs(u - 0.64)) * 12, 0), 1)
        sy = min(max((0.17 - abs(v - 0.64)) * 12, 0), 1)
        shade = 1 - 0.7 * sx * sy
        warm = (1.0, 0.85, 0.6)
        cool = (0.04, 0.05, 0.08)
        lin = [cool[i] + warm[i] * pool * shade for i in range(3)]
        return tuple(255 * (c ** (1 / 2.2)) for c in lin)
    png("lightmap.png", 64, 64, 3, light)
    # Decal: a gold ring and dot with antialiased alpha on transparent black.
    def decal(x, y):
        r = math.hypot(x + 0.5 - 32, y + 0.5 - 32)
        ring = min(max(1 - abs(r - 22) / 4, 0), 1)
        dot = min(max(9 - r, 0), 1)
        a = max(ring, dot)
        return (230, 180, 40, 255 * a) if a > 0 else (0, 0, 0, 0)
    png("decal.png", 64, 64, 4, decal)
    # Toon ramp: dark blue shadow, a mid band, a warm lit band (64×1).
    def ramp(x, y):
        u = (x + 0.5) / 64
        if u < 0.45:
            return (40, 45, 90)
        if u < 0.7:
            return (150, 140, 170)
        return (255, 240, 210)
    png("ramp.png", 64, 1, 3, ramp)
    # Stripes: a grey luminance ramp in bands, for blend with a constant colour.
    png("stripes.png", 32, 32, 1, lambda x, y: (255 * ((x // 4) % 2) * (0.5 + 0.5 * y / 31),))


if __name__ == "__main__":
    main()
