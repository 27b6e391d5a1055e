#!/usr/bin/env python3
"""Writes the README's ground-truth picture: a render's object IDs and forward flow as PNGs,
to be put beside its colour image with scripts/png-strip.py.

    python3 scripts/ground-truth-picture.py RENDER.exr IDS.png FLOW.png

RENDER.exr is `vkpath render ... --aov object_id,motion -o RENDER.exr`. Needs numpy and the
OpenEXR module (`pip install numpy OpenEXR`). IDs are coloured by a fixed palette (0, where
nothing is hit, is black); the flow as optical-flow pictures usually are: the hue its
direction, the saturation its length over the longest in the image, white where it is 0.
"""
import colorsys
import struct
import sys
import zlib

import numpy as np
import OpenEXR

PALETTE = [(230, 159, 0), (86, 180, 233), (0, 158, 115), (240, 228, 66), (0, 114, 178),
           (213, 94, 0), (204, 121, 167), (120, 120, 120)]


def write_png(path, rgb):
    """An 8-bit RGB PNG of an (H, W, 3) uint8 array."""
    height, width, _ = rgb.shape
    raw = b"".join(b"\0" + rgb[y].tobytes() for y in range(height))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    with open(path, "wb") as out:
        out.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
                  + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main(exr, ids_png, flow_png):
    channels = OpenEXR.File(exr).parts[0].channels
    ids = channels["object_id.Z"].pixels.astype(np.int64)
    rgb = np.zeros(ids.shape + (3,), np.uint8)
    for value in np.unique(ids):
        if value > 0:
            rgb[ids == value] = PALETTE[(value - 1) % len(PALETTE)]
    write_png(ids_png, rgb)
    flow = channels["motion_forward"].pixels
    du, dv = flow[..., 0], flow[..., 1]
    length = np.hypot(du, dv)
    longest = max(float(length.max()), 1e-6)
    picture = np.zeros(ids.shape + (3,), np.uint8)
    for y, x in np.ndindex(ids.shape):
        hue = (np.arctan2(-dv[y, x], du[y, x]) / (2 * np.pi)) % 1.0
        r, g, b = colorsys.hsv_to_rgb(hue, length[y, x] / longest, 1.0)
        picture[y, x] = (int(255 * r), int(255 * g), int(255 * b))
    write_png(flow_png, picture)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
