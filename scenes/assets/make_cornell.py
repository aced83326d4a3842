#!/usr/bin/env python3
"""Generates cornell-box.gltf: the geometry of the Cornell box as the Cornell University Program of
Computer Graphics published it ("Cornell Box Data", www.graphics.cornell.edu/online/box/data.html),
millimetres there, metres here, in its own right-handed frame (y up, the camera at z = -0.8 looking
down +z, so +x is to the left in the picture: the red wall). One glTF mesh per surface group, each
naming its material ("white", "red", "green", "light"), which scenes/cornell-box.json overrides with
the measured spectra (spectra/cornell/). Facts of that dataset, not code from it; two departures,
both said in docs/scene-format.md ("Bundled scenes"):
  * the light sits 0.1 mm below the ceiling (548.7 mm, not 548.8), so that the two are not coplanar;
  * each block gets a bottom face on the floor, so that it is a closed solid, and the floor under
    the blocks is cut away (never seen; interreflection's elements would straddle the blocks'
    footprints, half lit and half buried): the rest of it in trapezoids between the z of the
    footprints' corners (floor_pieces).
Faces are wound so that their normals point into the room (the light's down, the blocks' out),
whatever order the data lists their corners in. No vertex normals, and no vertex shared between faces: the loader gives each face its own normal.
Standard library only: python3 scenes/assets/make_cornell.py"""

import base64
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))

# Quads as published, mm.
FLOOR = [(552.8, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 559.2), (549.6, 0.0, 559.2)]
CEILING = [(556.0, 548.8, 0.0), (556.0, 548.8, 559.2), (0.0, 548.8, 559.2), (0.0, 548.8, 0.0)]
BACK_WALL = [(549.6, 0.0, 559.2), (0.0, 0.0, 559.2), (0.0, 548.8, 559.2), (556.0, 548.8, 559.2)]
GREEN_WALL = [(0.0, 0.0, 559.2), (0.0, 0.0, 0.0), (0.0, 548.8, 0.0), (0.0, 548.8, 559.2)]
RED_WALL = [(552.8, 0.0, 0.0), (549.6, 0.0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0.0)]
LIGHT_Y = 548.7  # published: 548.8, the ceiling's height
LIGHT = [(343.0, LIGHT_Y, 227.0), (343.0, LIGHT_Y, 332.0), (213.0, LIGHT_Y, 332.0), (213.0, LIGHT_Y, 227.0)]
SHORT_TOP = [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0), (290.0, 165.0, 114.0)]
TALL_TOP = [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0), (472.0, 330.0, 406.0)]
ROOM_CENTRE = (278.0, 274.4, 279.6)


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def facing(quad, towards):
    """The polygon's corners (3 or 4, convex) in the order whose normal (right-handed) points at `towards`."""
    n = cross(sub(quad[1], quad[0]), sub(quad[2], quad[0]))
    centre = tuple(sum(c[i] for c in quad) / len(quad) for i in range(3))
    return quad if dot(n, sub(towards, centre)) > 0 else quad[::-1]


def across(polygon, z):
    """The x interval where the plane z crosses a convex polygon in y = 0 (None: it does not)."""
    xs = []
    for a, b in zip(polygon, polygon[1:] + polygon[:1]):
        (xa, _, za), (xb, _, zb) = a, b
        if min(za, zb) <= z <= max(za, zb):
            xs += [xa, xb] if za == zb else [xa + (xb - xa) * (z - za) / (zb - za)]
    return (min(xs), max(xs)) if xs else None


def floor_pieces():
    """The floor less the blocks' footprints, as convex pieces: between consecutive z of the
    footprints' corners no edge ends, so each free x interval is a trapezoid (or a triangle where
    one of its ends closes)."""
    holes = [[(x, 0.0, z) for x, _, z in top] for top in (SHORT_TOP, TALL_TOP)]
    zs = sorted({0.0, 559.2} | {p[2] for h in holes for p in h})
    pieces = []
    for z0, z1 in zip(zs, zs[1:]):
        zm = 0.5 * (z0 + z1)
        # The floor's x interval at z: from the green wall's x = 0 to its slanted edge on the red side.
        def outer(z):
            (xa, _, za), (xb, _, zb) = FLOOR[0], FLOOR[3]
            return xa + (xb - xa) * (z - za) / (zb - za)
        cut = sorted((h for h in holes if across(h, zm)), key=lambda h: across(h, zm)[0])
        # Free intervals at z0 and z1, each end following one edge through the slab.
        ends = lambda z: [0.0] + [v for h in cut for v in across_edge(h, z, zm)] + [outer(z)]
        lo, hi = ends(z0), ends(z1)
        for i in range(0, len(lo), 2):
            corners = [(lo[i], 0.0, z0), (lo[i + 1], 0.0, z0), (hi[i + 1], 0.0, z1), (hi[i], 0.0, z1)]
            unique = [c for k, c in enumerate(corners) if c != corners[k - 1]]
            if len(unique) >= 3:
                pieces.append(unique)
    return pieces


def across_edge(polygon, z, zm):
    """The x where the footprint's left and right edges through the slab (they cross its middle zm)
    meet the plane z: where the free space ends and starts again."""
    edges = []
    for a, b in zip(polygon, polygon[1:] + polygon[:1]):
        (xa, _, za), (xb, _, zb) = a, b
        if za != zb and min(za, zb) <= zm <= max(za, zb):
            edges.append((xa + (xb - xa) * (zm - za) / (zb - za), xa + (xb - xa) * (z - za) / (zb - za)))
    edges.sort()
    return [edges[0][1], edges[-1][1]]


def block(top, outward=True):
    """A block standing on the floor: its top, four sides and a bottom, wound outwards."""
    bottom = [(x, 0.0, z) for x, _, z in top]
    centre = tuple(sum(c[i] for c in top) / 4 for i in range(3))
    centre = (centre[0], top[0][1] / 2, centre[2])
    quads = [top, bottom] + [[bottom[i], bottom[(i + 1) % 4], top[(i + 1) % 4], top[i]] for i in range(4)]
    away = []
    for q in quads:
        c = tuple(sum(p[i] for p in q) / 4 for i in range(3))
        away.append(facing(q, tuple(2 * ci - oi for ci, oi in zip(c, centre))))  # a point beyond the face
    return away


def mesh(quads):
    """Positions (m) and triangle indices; each face (a convex polygon of 3 or 4 corners) its own
    vertices, so that the loader gives each its flat normal (a block's edges stay sharp)."""
    positions, indices = [], []
    for q in quads:
        base = len(positions)
        positions += [tuple(c / 1000.0 for c in p) for p in q]
        for k in range(1, len(q) - 1):
            indices += [base, base + k, base + k + 1]
    return positions, indices


def groups():
    """(mesh name, material, its quads in mm, wound to face the room) — ci/mitsuba_cornell.py reads these too."""
    below = (278.0, 0.0, 279.6)
    return [
        ("room", "white", [facing(q, ROOM_CENTRE) for q in floor_pieces() + [CEILING, BACK_WALL]]),
        ("short_block", "white", block(SHORT_TOP)),
        ("tall_block", "white", block(TALL_TOP)),
        ("red_wall", "red", [facing(RED_WALL, ROOM_CENTRE)]),
        ("green_wall", "green", [facing(GREEN_WALL, ROOM_CENTRE)]),
        ("light", "light", [facing(LIGHT, below)]),
    ]


def main():
    materials = ["white", "red", "green", "light"]
    from gltf_buffer import GltfBuffer  # here: ci/mitsuba_cornell.py loads this file for groups() alone

    buffer = GltfBuffer()
    blob, views, accessors, add = buffer.blob, buffer.views, buffer.accessors, buffer.add
    meshes = []

    for name, material, quads in groups():
        positions, indices = mesh(quads)
        lo = [min(p[i] for p in positions) for i in range(3)]
        hi = [max(p[i] for p in positions) for i in range(3)]
        pos = add([c for p in positions for c in p], "f", len(positions), "VEC3", 5126, 34962, (lo, hi))
        idx = add(indices, "I", len(indices), "SCALAR", 5125, 34963)
        meshes.append({"name": name, "primitives": [{"attributes": {"POSITION": pos}, "indices": idx,
                                                      "material": materials.index(material)}]})
    doc = {
        "asset": {"version": "2.0", "generator": "metamer scenes/assets/make_cornell.py"},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(meshes)))}],
        "nodes": [{"name": m["name"], "mesh": i} for i, m in enumerate(meshes)],
        "materials": [{"name": m} for m in materials],
        "meshes": meshes,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}],
        "bufferViews": views,
        "accessors": accessors,
    }
    with open(os.path.join(HERE, "cornell-box.gltf"), "w", newline="\n") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
