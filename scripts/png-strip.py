#!/usr/bin/env python3
"""Puts PNGs of one height side by side, 4 white pixels apart, as one 8-bit RGB PNG.

Made for the README's strips of frames (docs/*-strip.png):
    python3 scripts/png-strip.py OUT.png frame_0.png frame_1.png ...
Needs only the standard library: it reads non-interlaced 8-bit greyscale, RGB and RGBA PNGs
(what `vkpath render -o x.png` writes), undoing each row's filter (PNG spec, section 9).
"""
import struct
import sys
import zlib

GAP = 4
WHITE = (255, 255, 255)


def paeth(a, b, c):
    """The Paeth predictor of PNG filter type 4."""
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def read_png(path):
    """(width, height, rows of RGB tuples) of an 8-bit non-interlaced PNG."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"{path}: not a PNG")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    channels = {0: 1, 2: 3, 6: 4}.get(colour)
    if depth != 8 or channels is None or interlace:
        sys.exit(f"{path}: only 8-bit non-interlaced grey, RGB or RGBA PNGs are read")
    raw = zlib.decompress(idat)
    stride = width * channels
    previous = bytearray(stride)
    rows = []
    for y in range(height):
        start = y * (stride + 1)
        kind, line = raw[start], bytearray(raw[start + 1:start + 1 + stride])
        for x in range(stride):
            a = line[x - channels] if x >= channels else 0
            b = previous[x]
            c = previous[x - channels] if x >= channels else 0
            line[x] = (line[x] + (0, a, b, (a + b) // 2, paeth(a, b, c))[kind]) & 255
        previous = line
        pixels = [tuple(line[x:x + channels]) for x in range(0, stride, channels)]
        rows.append([p * 3 if channels == 1 else p[:3] for p in pixels])
    return width, height, rows


def write_png(path, rows):
    """Writes rows of RGB tuples as an 8-bit RGB PNG (filter 0 on every row)."""
    width, height = len(rows[0]), len(rows)
    raw = b"".join(b"\0" + bytes(c for p in row for c in p) for row in rows)

    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body
                + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    with open(path, "wb") as out:
        out.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
                  + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: png-strip.py OUT.png IN.png [IN.png ...]")
    images = [read_png(p) for p in sys.argv[2:]]
    height = images[0][1]
    if any(h != height for _, h, _ in images):
        sys.exit("the PNGs must have one height")
    rows = []
    for y in range(height):
        row = []
        for i, (_, _, pixels) in enumerate(images):
            if i:
                row.extend([WHITE] * GAP)
            row.extend(pixels[y])
        rows.append(row)
    write_png(sys.argv[1], rows)


if __name__ == "__main__":
    main()
