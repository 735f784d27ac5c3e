#!/usr/bin/env python3
"""Writes the synthetic panorama texmap's environment tests and examples use: a blue sky
darkening to a warm horizon, coloured bands around the horizon, a checker ground and a small
sun of radiance 60 (linear radiance, Mitsuba's equirectangular convention: rows at
theta = pi * i / (H - 1)).

  synthetic_env.py WIDTH OUT.{hdr,exr}       (height = WIDTH / 2)

Run with ../shared/peers/.venv/bin/python (it writes through Mitsuba's Bitmap). The file
scenes/env/synthetic_sky.hdr is `synthetic_env.py 512 scenes/env/synthetic_sky.hdr`.
"""
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")
W = int(sys.argv[1])
H = W // 2
u = (np.arange(W) + 0.5) / W
v = np.arange(H) / (H - 1)
U, V = np.meshgrid(u, v)
th, ph = V * np.pi, U * 2 * np.pi
d = np.stack([np.sin(ph) * np.sin(th), np.cos(th), -np.cos(ph) * np.sin(th)], -1)
y = np.clip(d[..., 1], 0, 1)[..., None]
sky = np.array([0.25, 0.45, 0.9]) * (0.4 + 0.6 * y) + np.array([0.9, 0.8, 0.6]) * (1 - y) ** 8
cx, cz = np.floor(4 * ph / np.pi), np.floor(8 * th / np.pi)
ground = np.where(((cx + cz) % 2 == 0)[..., None], [0.5, 0.45, 0.4], [0.08, 0.1, 0.12])
img = np.where(d[..., 1:2] > 0, sky, ground)
band = np.stack([0.5 + 0.5 * np.sin(3 * ph), 0.5 + 0.5 * np.sin(3 * ph + 2.1),
                 0.5 + 0.5 * np.sin(3 * ph + 4.2)], -1)
img = np.where((np.abs(d[..., 1]) < 0.12)[..., None], band, img)
sun = np.array([0.4, 0.5, 0.77])
sun /= np.linalg.norm(sun)
img = img + (d @ sun > np.cos(np.radians(2.5)))[..., None] * 60.0
mi.Bitmap(img.astype(np.float32)).write(sys.argv[2])
if sys.argv[2].lower().endswith(".hdr"):
    # Mitsuba signs Radiance files "#?RGBE"; the image crate texmap decodes with accepts only
    # "#?RADIANCE" (the signature Radiance itself writes).
    with open(sys.argv[2], "rb") as f:
        data = f.read()
    if data.startswith(b"#?RGBE\n"):
        with open(sys.argv[2], "wb") as f:
            f.write(b"#?RADIANCE\n" + data[len(b"#?RGBE\n"):])
