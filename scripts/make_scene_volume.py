#!/usr/bin/env python3
"""Writes scenes/volumes/cell.nrrd, the small synthetic volume of scenes/volume.toml.

A 48x48x40 uint8 grid (spacing 1, 1, 1.25: anisotropic on purpose), gzip-encoded NRRD:
a cell of radius 19 mm (~120 inside, rippled ±12, soft edge) and a nucleus off the centre
(~235). Python standard library only; the same bytes on every
run (gzip mtime 0).

    python3 scripts/make_scene_volume.py
"""
import gzip
import math
import os

NX, NY, NZ = 48, 48, 40
SPACING = (1.0, 1.0, 1.25)


def value(x, y, z):
    # World-space position (mm), centred.
    px = (x - (NX - 1) / 2) * SPACING[0]
    py = (y - (NY - 1) / 2) * SPACING[1]
    pz = (z - (NZ - 1) / 2) * SPACING[2]
    r = math.sqrt(px * px + py * py + pz * pz)
    # A filled cell (~120 inside, rippled) with a soft edge at r = 19 mm: the gradient keeps
    # one direction through the edge, so shading has a normal to work with.
    inside = 1.0 / (1.0 + math.exp((r - 19.0) / 1.2))
    cell = inside * (120.0 + 12.0 * math.sin(px * 0.5) * math.cos(pz * 0.4))
    rn = math.sqrt((px - 5.0) ** 2 + (py + 3.0) ** 2 + (pz - 2.0) ** 2)
    nucleus = 235.0 / (1.0 + math.exp((rn - 7.0) / 0.9))
    return max(cell, nucleus)


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    out = os.path.join(root, "scenes", "volumes", "cell.nrrd")
    data = bytearray()
    for z in range(NZ):
        for y in range(NY):
            for x in range(NX):
                data.append(max(0, min(255, int(round(value(x, y, z))))))
    header = (
        "NRRD0004\n"
        "# texmap example volume: scripts/make_scene_volume.py\n"
        "type: uchar\n"
        "dimension: 3\n"
        f"sizes: {NX} {NY} {NZ}\n"
        f"spacings: {SPACING[0]} {SPACING[1]} {SPACING[2]}\n"
        "encoding: gzip\n"
        "\n"
    ).encode()
    with open(out, "wb") as f:
        f.write(header)
        f.write(gzip.compress(bytes(data), compresslevel=9, mtime=0))
    print(f"wrote {out} ({os.path.getsize(out)} bytes)")


if __name__ == "__main__":
    main()
