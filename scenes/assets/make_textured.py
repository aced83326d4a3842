#!/usr/bin/env python3
"""Generates the textured assets of scenes/textured.json (docs/scene-format.md, "Textures"):

- colorchecker_texture.exr: a reflective spectral texture (Fichet 2021 layout, channels
  T.<λ>nm, 380-780 nm every 10 nm, float32) of the 24 ColorChecker patches, 6 x 4 patches of
  12 x 12 texels with 2-texel black (black_2) borders; spectra from spectra/colorchecker/.
- panel.gltf (+ panel.bin): a curved panel (a 100° cylinder section, TEXCOORD_0, no TANGENT: the
  loader derives tangents from the UVs) with two primitives and two glTF materials: "tiles"
  (baseColorTexture tiles.png, sRGB; normalTexture tiles_normal.png; roughness 0.6) and "brass"
  (baseColorFactor only, metallic 1, roughness 0.7) on a bar across the panel's foot.
- tiles.png, tiles_normal.png: 128 x 128 glazed tiles and their bevel normals.
- ripples.png: a 128 x 128 height field of ripples (a bump map, 16-bit grey).
Procedural; uses numpy and OpenImageIO (Debian: python3-numpy, python3-openimageio):
    python3 scenes/assets/make_textured.py
"""

import json
import math
import os

import numpy as np
import OpenImageIO as oiio

from gltf_buffer import GltfBuffer

HERE = os.path.dirname(os.path.abspath(__file__))
SPECTRA = os.path.join(HERE, "..", "..", "spectra", "colorchecker")
PATCHES = ("dark_skin light_skin blue_sky foliage blue_flower bluish_green orange purplish_blue moderate_red "
           "purple yellow_green orange_yellow blue green red yellow magenta cyan white_9_5 neutral_8 "
           "neutral_6_5 neutral_5 neutral_3_5 black_2").split()


def read_spectrum(name):
    rows = [line.strip().split(",") for line in open(os.path.join(SPECTRA, name + ".csv"))]
    data = [(float(a), float(b)) for a, b in rows[1:] if a and not a.startswith("#")]
    return dict(data)


def channel_name(nm):
    return "T.%snm" % ("%g" % nm).replace(".", ",")


def write_colorchecker(path):
    nm = list(range(380, 781, 10))
    cell, border = 12, 2
    w, h = 6 * cell, 4 * cell
    black = read_spectrum("black_2")
    img = np.zeros((h, w, len(nm)), dtype=np.float32)
    img[:, :, :] = [black[l] for l in nm]
    for i, name in enumerate(PATCHES):
        s = read_spectrum(name)
        r, c = divmod(i, 6)
        img[r * cell + border:(r + 1) * cell - border, c * cell + border:(c + 1) * cell - border, :] = [s[l] for l in nm]
    spec = oiio.ImageSpec(w, h, len(nm), "float")
    spec.channelnames = tuple(channel_name(l) for l in nm)
    spec.attribute("spectralLayoutVersion", "1.0")
    spec.attribute("compression", "zip")
    out = oiio.ImageOutput.create(path)
    out.open(path, spec)
    out.write_image(img)
    out.close()


def write_png(path, array, bits=8):
    if array.ndim == 2:
        # Debian's OpenImageIO 2.4 garbles a 2-D array in write_image (the ripples came out as
        # diagonal stripes and half black); a grey image goes in as h x w x 1.
        array = array[:, :, None]
    h, w, n = array.shape
    spec = oiio.ImageSpec(w, h, n, "uint8" if bits == 8 else "uint16")
    out = oiio.ImageOutput.create(path)
    out.open(path, spec)
    out.write_image(np.ascontiguousarray(array, dtype=np.float32))
    out.close()
    # Read it back: a garbled write is otherwise only seen in a render.
    back = oiio.ImageInput.open(path).read_image("float")
    step = 1.0 / (255 if bits == 8 else 65535)
    assert back.shape == array.shape and np.abs(back - array).max() <= step, path


def tiles(n=128, count=4, bevel=0.12):
    """Glazed tiles: a colour per tile (sRGB-encoded), grout lines, and the bevel's normals."""
    colours = [(0.80, 0.55, 0.30), (0.25, 0.45, 0.65), (0.85, 0.80, 0.65), (0.35, 0.55, 0.35)]
    u = (np.arange(n) + 0.5) / n * count
    fu = u - np.floor(u)
    iu = np.floor(u).astype(int)
    rgb = np.zeros((n, n, 3))
    height = np.zeros((n, n))
    for y in range(n):
        for x in range(n):
            tile = (iu[x] + 2 * iu[y]) % len(colours)
            edge = min(fu[x], 1 - fu[x], fu[y], 1 - fu[y])
            grout = edge < 0.04
            rgb[y, x] = (0.55, 0.53, 0.50) if grout else colours[tile]
            height[y, x] = 0.0 if grout else min(1.0, (edge - 0.04) / bevel)
    # Normals from the height's slope (per texel, scaled so the bevel tilts ~40°), +y up the image.
    gx = (np.roll(height, -1, 1) - np.roll(height, 1, 1)) * 0.5
    gy = (np.roll(height, 1, 0) - np.roll(height, -1, 0)) * 0.5
    s = 6.0
    nvec = np.dstack([-s * gx, -s * gy, np.ones_like(height)])
    nvec /= np.linalg.norm(nvec, axis=2, keepdims=True)
    return rgb, (nvec + 1) / 2


def ripples(n=128):
    y, x = np.mgrid[0:n, 0:n] / n
    r = np.hypot(x - 0.35, y - 0.4)
    return 0.5 + 0.5 * np.cos(2 * math.pi * 6 * r) * np.exp(-2 * r)


def write_panel(name):
    """A cylinder section (radius 1.2, 100°, 1.4 high) facing +z, and a brass bar at its foot."""
    buffer = GltfBuffer()
    blob, views, accessors, add = buffer.blob, buffer.views, buffer.accessors, buffer.add
    prims = []

    def primitive(positions, normals, uvs, indices, material):
        lo = [min(p[i] for p in positions) for i in range(3)]
        hi = [max(p[i] for p in positions) for i in range(3)]
        attributes = {
            "POSITION": add([c for p in positions for c in p], "f", len(positions), "VEC3", 5126, 34962, (lo, hi)),
            "NORMAL": add([c for v in normals for c in v], "f", len(normals), "VEC3", 5126, 34962),
        }
        if uvs:
            attributes["TEXCOORD_0"] = add([c for t in uvs for c in t], "f", len(uvs), "VEC2", 5126, 34962)
        prims.append({"attributes": attributes, "indices": add(indices, "I", len(indices), "SCALAR", 5125, 34963),
                      "material": material})

    radius, angle, height, cols, rows = 1.2, math.radians(100), 1.4, 40, 2
    positions, normals, uvs, indices = [], [], [], []
    for j in range(rows + 1):
        for i in range(cols + 1):
            a = -angle / 2 + angle * i / cols
            n = (-math.sin(a), 0.0, math.cos(a))  # facing the centre of curvature at +z
            positions.append((radius * math.sin(a), 0.2 + height * j / rows, radius * (1 - math.cos(a))))
            normals.append(n)
            uvs.append((2.0 * i / cols, 1.0 - j / rows))  # the tile image twice across, upright
    for j in range(rows):
        for i in range(cols):
            a, b = j * (cols + 1) + i, j * (cols + 1) + i + 1
            c, d = a + cols + 1, b + cols + 1
            indices += [a, b, c, b, d, c]  # counter-clockwise seen from the normal side
    primitive(positions, normals, uvs, indices, 0)
    # The brass bar: a box 0.12 high and deep along the panel's chord at its foot.
    positions, normals, indices = [], [], []
    x0, x1 = -radius * math.sin(angle / 2), radius * math.sin(angle / 2)
    for (nx, ny, nz), corners in (
            ((0, 0, 1), [(x0, 0, 0.5), (x1, 0, 0.5), (x1, 0.12, 0.5), (x0, 0.12, 0.5)]),
            ((0, 1, 0), [(x0, 0.12, 0.5), (x1, 0.12, 0.5), (x1, 0.12, 0.38), (x0, 0.12, 0.38)])):
        base = len(positions)
        positions += corners
        normals += [(nx, ny, nz)] * 4
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    primitive(positions, normals, None, indices, 1)

    doc = {
        "asset": {"version": "2.0", "generator": "metamer scenes/assets/make_textured.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"name": name, "primitives": prims}],
        "materials": [
            {"name": "tiles", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0,
                                                       "roughnessFactor": 0.6},
             "normalTexture": {"index": 1, "scale": 1.0}},
            {"name": "brass", "pbrMetallicRoughness": {"baseColorFactor": [0.91, 0.73, 0.38, 1.0],
                                                       "metallicFactor": 1.0, "roughnessFactor": 0.7}},
        ],
        "textures": [{"source": 0}, {"source": 1}],
        "images": [{"uri": "tiles.png"}, {"uri": "tiles_normal.png"}],
        "buffers": [{"byteLength": len(blob), "uri": name + ".bin"}],
        "bufferViews": views,
        "accessors": accessors,
    }
    with open(os.path.join(HERE, name + ".bin"), "wb") as f:
        f.write(bytes(blob))
    with open(os.path.join(HERE, name + ".gltf"), "w", newline="\n") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    write_colorchecker(os.path.join(HERE, "colorchecker_texture.exr"))
    rgb, normal = tiles()
    write_png(os.path.join(HERE, "tiles.png"), rgb)
    write_png(os.path.join(HERE, "tiles_normal.png"), normal)
    write_png(os.path.join(HERE, "ripples.png"), ripples(), bits=16)
    write_panel("panel")
