#!/usr/bin/env python3
"""Writes the scene-loader test fixtures in this folder: a small spectra library (made-up smooth
curves with the library's names; NOT the real CIE or ColorChecker data) and a few glTF files.
Standard library only. Run from anywhere: python3 tests/data/scene/make_fixtures.py"""

import base64
import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(rel, text):
    path = os.path.join(HERE, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="\n") as f:
        f.write(text)


def csv(rel, comment, points):
    lines = ["# " + comment, "wavelength_nm,value"]
    lines += ["%g,%.6g" % (w, v) for w, v in points]
    write(rel, "\n".join(lines) + "\n")


def planck(w_nm, t):
    w = w_nm * 1e-9
    return 1.0 / (w ** 5 * (math.exp(1.4388e-2 / (w * t)) - 1.0))


def blackbody(t, lo, hi, step):
    ref = planck(560, t)
    return [(w, 100.0 * planck(w, t) / ref) for w in range(lo, hi + 1, step)]


def gauss(lo, hi, step, centre, width, peak):
    return [(w, peak * math.exp(-0.5 * ((w - centre) / width) ** 2)) for w in range(lo, hi + 1, step)]


def spectra():
    lib = "spectra/"
    csv(lib + "illuminants/D65.csv", "fixture: 6504 K blackbody, 100 at 560 nm (not CIE D65)",
        blackbody(6504, 300, 780, 10))
    csv(lib + "illuminants/A.csv", "fixture: 2856 K blackbody, 100 at 560 nm", blackbody(2856, 300, 780, 10))
    csv(lib + "colorchecker/dark_skin.csv", "fixture: a smooth brownish ramp",
        [(w, 0.05 + 0.15 * (w - 380) / 400) for w in range(380, 781, 20)])
    csv(lib + "colorchecker/white_9_5.csv", "fixture: flat 0.9", [(380, 0.9), (780, 0.9)])
    csv(lib + "fluorescent/brightener_ex.csv", "fixture: UV absorption band",
        gauss(300, 460, 10, 350, 20, 0.8))
    csv(lib + "fluorescent/brightener_em.csv", "fixture: blue emission band",
        gauss(380, 560, 10, 440, 20, 1.0))
    csv(lib + "metals/gold.csv", "fixture: a gold-like rising reflectance",
        [(w, 0.35 + 0.6 / (1 + math.exp(-(w - 520) / 15))) for w in range(380, 781, 20)])
    # Broken library entry: the loader must name the scene key as well as this file's line.
    write(lib + "broken/bad_value.csv", "wavelength_nm,value\n400,0.5\n500,oops\n")
    # Spectra referenced by path from test scenes.
    csv("local.csv", "fixture: a reflectance given by path", [(400, 0.2), (500, 0.4), (700, 0.6)])
    write("bad.csv", "wavelength_nm,value\n500,0.5\n400,0.6\n")


# ---- glTF ------------------------------------------------------------------------------------

def gltf(name, positions, indices=None, normals=None, nodes=None, mode=None, glb=False):
    """One mesh with one primitive; `nodes` is the node list (the scene's root is node 0)."""
    blob = b""
    views, accessors, attributes = [], [], {}

    def add(data, fmt, count, type_, ctype, target, minmax=None):
        nonlocal blob
        while len(blob) % 4:
            blob += b"\0"
        offset = len(blob)
        blob += struct.pack("<" + fmt * (len(data)), *data)
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(blob) - offset, "target": target})
        acc = {"bufferView": len(views) - 1, "componentType": ctype, "count": count, "type": type_}
        if minmax:
            acc["min"], acc["max"] = minmax
        accessors.append(acc)
        return len(accessors) - 1

    flat = [c for p in positions for c in p]
    lo = [min(p[i] for p in positions) for i in range(3)]
    hi = [max(p[i] for p in positions) for i in range(3)]
    attributes["POSITION"] = add(flat, "f", len(positions), "VEC3", 5126, 34962, (lo, hi))
    if normals:
        attributes["NORMAL"] = add([c for n in normals for c in n], "f", len(normals), "VEC3", 5126, 34962)
    prim = {"attributes": attributes}
    if indices is not None:
        prim["indices"] = add(indices, "H", len(indices), "SCALAR", 5123, 34963)
    if mode is not None:
        prim["mode"] = mode
    doc = {
        "asset": {"version": "2.0", "generator": "metamer tests/data/scene/make_fixtures.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": nodes or [{"mesh": 0}],
        "meshes": [{"primitives": [prim]}],
        "bufferViews": views,
        "accessors": accessors,
    }
    while len(blob) % 4:
        blob += b"\0"
    if glb:
        doc["buffers"] = [{"byteLength": len(blob)}]
        js = json.dumps(doc, separators=(",", ":")).encode()
        js += b" " * (-len(js) % 4)
        body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(blob), 0x004E4942) + blob
        with open(os.path.join(HERE, name), "wb") as f:
            f.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)
    else:
        uri = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
        doc["buffers"] = [{"byteLength": len(blob), "uri": uri}]
        write(name, json.dumps(doc, indent=1) + "\n")


def cube():
    """Unit cube [-0.5, 0.5]^3, 4 vertices per face with the face normal, CCW from outside."""
    positions, normals, indices = [], [], []
    for axis in range(3):
        for sign in (1, -1):
            n = [0, 0, 0]
            n[axis] = sign
            u = [0, 0, 0]
            v = [0, 0, 0]
            u[(axis + 1) % 3] = 1
            v[(axis + 2) % 3] = 1
            # u x v = +axis; swap for the negative face so u x v = n.
            if sign < 0:
                u, v = v, u
            base = len(positions)
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                positions.append([0.5 * n[i] + 0.5 * a * u[i] + 0.5 * b * v[i] for i in range(3)])
                normals.append(n)
            indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return positions, normals, indices


def tetra_soup():
    """A regular-ish tetrahedron as 4 separate triangles (no shared vertices, no indices)."""
    p = [[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]]
    faces = [(0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2)]
    out = []
    for f in faces:
        a, b, c = (p[i] for i in f)
        e1 = [b[i] - a[i] for i in range(3)]
        e2 = [c[i] - a[i] for i in range(3)]
        n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
        centroid_dir = sum(n[i] * (a[i] + b[i] + c[i]) for i in range(3))
        assert centroid_dir > 0, "faces must wind counter-clockwise seen from outside"
        out += [a, b, c]
    return out


def meshes():
    pos, nrm, idx = cube()
    # Parent: translate (1, 2, 3); child: rotate 90° about +y, then scale 2: x -> -z, z -> x.
    s = math.sqrt(0.5)
    nodes = [{"translation": [1, 2, 3], "children": [1]},
             {"rotation": [0, s, 0, s], "scale": [2, 2, 2], "mesh": 0}]
    gltf("cube.gltf", pos, idx, nrm, nodes)
    gltf("cube.glb", pos, idx, nrm, nodes, glb=True)
    # A mirroring node (x -> -x): the loader must reverse the winding to keep it CCW from outside.
    gltf("tetra_mirrored.gltf", tetra_soup(), nodes=[{"scale": [-1, 1, 1], "mesh": 0}])
    gltf("strip.gltf", [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], mode=5)
    write("not_gltf.gltf", "this is not a glTF file\n")
    write("model.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")


def grey_png(rel, width, height, values):
    """An 8-bit greyscale PNG (values 0..255, row by row), written with zlib: a thickness map."""
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    rows = b"".join(b"\0" + bytes(values[y * width:(y + 1) * width]) for y in range(height))
    data = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))
    with open(os.path.join(HERE, rel), "wb") as f:
        f.write(data)


if __name__ == "__main__":
    spectra()
    meshes()
    grey_png("wedge.png", 4, 1, [0, 85, 170, 255])
