#!/usr/bin/env python3
"""Generates the glTF meshes of the bundled scenes: torus.gltf (smooth, with analytic normals)
and gem.gltf (faceted, no NORMAL attribute: the loader computes flat normals from the unshared
vertices). Geometry is procedural; buffers are embedded as base64 data URIs. Also
paint_wedge.png, the thickness map of scenes/paints.json's drawdown: 256 x 1 texels, 16-bit grey,
a linear ramp from 0 (left) to 1 (right).
Standard library only: python3 scenes/assets/make_assets.py"""

import base64
import json
import math
import os
import struct

from gltf_buffer import GltfBuffer

HERE = os.path.dirname(os.path.abspath(__file__))


def write_gltf(name, positions, indices, normals=None, node=None):
    buffer = GltfBuffer()
    blob, views, accessors, add = buffer.blob, buffer.views, buffer.accessors, buffer.add

    lo = [min(p[i] for p in positions) for i in range(3)]
    hi = [max(p[i] for p in positions) for i in range(3)]
    attributes = {"POSITION": add([c for p in positions for c in p], "f", len(positions), "VEC3", 5126, 34962,
                                  (lo, hi))}
    if normals:
        attributes["NORMAL"] = add([c for n in normals for c in n], "f", len(normals), "VEC3", 5126, 34962)
    index_acc = add(indices, "I", len(indices), "SCALAR", 5125, 34963)
    node = dict(node or {})
    node["mesh"] = 0
    doc = {
        "asset": {"version": "2.0", "generator": "metamer scenes/assets/make_assets.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [node],
        "meshes": [{"name": name, "primitives": [{"attributes": attributes, "indices": index_acc}]}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}],
        "bufferViews": views,
        "accessors": accessors,
    }
    with open(os.path.join(HERE, name + ".gltf"), "w", newline="\n") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def torus(major=0.6, minor=0.25, rings=64, sides=32):
    """Torus about the y axis; vertex normals are exact: from the tube's centre line outwards."""
    positions, normals, indices = [], [], []
    for i in range(rings):
        u = 2 * math.pi * i / rings
        cu, su = math.cos(u), math.sin(u)
        for j in range(sides):
            v = 2 * math.pi * j / sides
            cv, sv = math.cos(v), math.sin(v)
            n = (cv * su, sv, cv * cu)  # u grows from +z towards +x; v from outward towards +y
            positions.append(((major + minor * cv) * su, minor * sv, (major + minor * cv) * cu))
            normals.append(n)
    for i in range(rings):
        for j in range(sides):
            a = i * sides + j
            b = ((i + 1) % rings) * sides + j
            c = ((i + 1) % rings) * sides + (j + 1) % sides
            d = i * sides + (j + 1) % sides
            # Seen from outside, u runs right and v runs up on the outer equator: a b c d is CCW.
            indices += [a, b, c, a, c, d]
    return positions, normals, indices


def gem(sides=8, table_r=0.30, table_y=0.20, girdle_r=0.50, girdle_y=0.05, culet_y=-0.35):
    """A faceted stone: flat table, crown quads, pavilion triangles to the culet. Each facet has
    its own vertices so smooth normals computed by the loader come out flat."""
    positions, indices = [], []

    def ring(r, y, k, twist=0.0):
        a = 2 * math.pi * (k + twist) / sides
        return (r * math.sin(a), y, r * math.cos(a))

    def tri(p, q, r):
        base = len(positions)
        positions.extend([p, q, r])
        indices.extend([base, base + 1, base + 2])

    top = (0.0, table_y, 0.0)
    culet = (0.0, culet_y, 0.0)
    for k in range(sides):
        t0, t1 = ring(table_r, table_y, k), ring(table_r, table_y, k + 1)
        g0, g1 = ring(girdle_r, girdle_y, k), ring(girdle_r, girdle_y, k + 1)
        tri(top, t0, t1)  # table
        tri(t0, g0, g1)  # crown facet as two triangles
        tri(t0, g1, t1)
        tri(g0, culet, g1)  # pavilion
    # Make every facet face outwards (away from the stone's axis or up/down at the ends).
    for t in range(0, len(indices), 3):
        p, q, r = (positions[indices[t + i]] for i in range(3))
        e1 = [q[i] - p[i] for i in range(3)]
        e2 = [r[i] - p[i] for i in range(3)]
        n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
        c = [(p[i] + q[i] + r[i]) / 3 for i in range(3)]
        out = (c[0], c[1] - (table_y + culet_y) / 2, c[2])
        if sum(n[i] * out[i] for i in range(3)) < 0:
            indices[t + 1], indices[t + 2] = indices[t + 2], indices[t + 1]
    return positions, indices


def grey16_png(name, values):
    """A one-row 16-bit greyscale PNG of `values` (0..65535)."""
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    row = b"\0" + b"".join(struct.pack(">H", v) for v in values)
    data = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", len(values), 1, 16, 0, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(row, 9)) + chunk(b"IEND", b""))
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


if __name__ == "__main__":
    grey16_png("paint_wedge.png", [round(65535 * i / 255) for i in range(256)])
    p, n, i = torus()
    write_gltf("torus", p, i, n)
    p, i = gem()
    # The node lifts the stone so its culet rests at y = 0 in the file's coordinates.
    write_gltf("gem", p, i, node={"translation": [0.0, 0.35, 0.0]})
