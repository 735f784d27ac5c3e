#!/usr/bin/env python3
"""Writes scenes/projector/test_card.png: the slide of scenes/projector.toml.

A 256x160 test card with no external dependency: seven colour bars on top, a grey ramp, and
below a checker with a white ring and a large letter F, whose shape shows at once whether a
projected image is mirrored or upside down. Usage: python3 tools/test_card.py [OUT.png]
"""
import math
import struct
import sys
import zlib

W, H = 256, 160
BARS = [(235, 235, 235), (235, 235, 16), (16, 235, 235), (16, 235, 16),
        (235, 16, 235), (235, 16, 16), (16, 16, 235)]


def pixel(x, y):
    if y < 64:
        return BARS[x * len(BARS) // W]
    if y < 80:
        g = 16 + (x * 219) // (W - 1)
        return (g, g, g)
    # The letter F on the left: a stem and two arms.
    fx, fy = x - 24, y - 90
    if 0 <= fx < 48 and 0 <= fy < 62:
        stem = fx < 12
        top = fy < 12
        mid = 25 <= fy < 37 and fx < 36
        return (250, 250, 250) if (stem or top or mid) else (20, 20, 20)
    # A ring on the right.
    r = math.hypot(x - 180, y - 120)
    if 26 <= r <= 34:
        return (250, 200, 40)
    c = ((x // 16) + (y // 16)) % 2
    return (60, 60, 70) if c else (120, 120, 135)


def png(path):
    rows = b"".join(b"\x00" + bytes(v for x in range(W) for v in pixel(x, y)) for y in range(H))

    def chunk(kind, data):
        c = kind + data
        return struct.pack(">I", len(data)) + c + struct.pack(">I", zlib.crc32(c) & 0xFFFFFFFF)

    head = struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", head)
                + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


if __name__ == "__main__":
    png(sys.argv[1] if len(sys.argv) > 1 else "scenes/projector/test_card.png")
