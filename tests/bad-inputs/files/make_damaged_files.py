#!/usr/bin/env python3
"""Damaged and oversized images of the bad-input corpus (README.md, issue 19 classes 4 and 8),
written byte by byte with the standard library (no image library, so the damage is exactly what
is written): a JPEG cut off after 90 % of its bytes (inside its scan data), a PNG whose pixel chunk fails its CRC, a PNG
whose header claims 16384 x 16384 texels with almost no data, and a GLB of the valid test cube
whose header says version 1. The JPEG starts as a 64 x 64 checker made by oiiotool (tile.jpg,
kept, a valid texture); the GLB from tests/data/scene/cube.glb.
python3 tests/bad-inputs/files/make_damaged_files.py"""

import os
import struct
import subprocess
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "data")


def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def png(width, height, rows, bad_crc=False):
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)  # 8-bit RGB
    idat = chunk(b"IDAT", zlib.compress(rows))
    if bad_crc:
        idat = idat[:-1] + bytes([idat[-1] ^ 0xFF])
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + idat + chunk(b"IEND", b"")


def write(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def main():
    rows = b"".join(b"\x00" + b"\x80\x80\x80" * 4 for _ in range(4))
    write("bad-crc.png", png(4, 4, rows, bad_crc=True))
    # One filter byte of one row: libpng reads the header and would allocate the whole image
    # before finding the data short.
    write("huge-header.png", png(16384, 16384, b"\x00" + b"\x80" * 16))
    subprocess.run(["oiiotool", "--pattern", "checker:width=8:height=8", "64x64", "3", "-d", "uint8",
                    "-o", os.path.join(HERE, "tile.jpg")], check=True)
    with open(os.path.join(HERE, "tile.jpg"), "rb") as f:
        jpeg = f.read()
    write("truncated.jpg", jpeg[: len(jpeg) * 9 // 10])
    with open(os.path.join(DATA, "scene", "cube.glb"), "rb") as f:
        glb = bytearray(f.read())
    glb[4:8] = struct.pack("<I", 1)
    write("version-1.glb", bytes(glb))


if __name__ == "__main__":
    main()
