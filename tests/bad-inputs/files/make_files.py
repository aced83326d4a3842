#!/usr/bin/env python3
"""Writes the binary and glTF helper files of the bad-input corpus (tests/bad-inputs/README.md):
a PNG under other names, a truncated GLB, glTF files that are valid JSON but wrong inside and
bispectral OpenEXR files that are valid images but wrong Donaldson matrices.
Standard library only. Run from anywhere: python3 tests/bad-inputs/files/make_files.py"""

import base64
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, data):
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(os.path.join(HERE, name), mode) as f:
        f.write(data)


def png():
    """A 2×2 grey 8-bit PNG."""
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    raw = b"".join(b"\x00" + b"\x80\x80" for _ in range(2))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 0, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


DEEP = 20000

# One triangle: 3 float positions then 3 uint16 indices (padded to 4 bytes).
TRIANGLE = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<3H", 0, 1, 2) + b"\x00\x00"


def gltf(buffer_uri, position_count=3, index_values=None, nodes=None, byte_length=None):
    data = TRIANGLE if index_values is None else TRIANGLE[:36] + struct.pack("<3H", *index_values) + b"\x00\x00"
    return {
        "asset": {"version": "2.0", "generator": "metamer tests/bad-inputs/files/make_files.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": nodes or [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"uri": buffer_uri if buffer_uri is not None else
                     "data:application/octet-stream;base64," + base64.b64encode(data).decode(),
                     "byteLength": byte_length or len(data)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": position_count, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
    }


def glb(doc, data):
    body = json.dumps(doc).encode()
    body += b" " * (-len(body) % 4)
    data += b"\x00" * (-len(data) % 4)
    chunks = (struct.pack("<II", len(body), 0x4E4F534A) + body + struct.pack("<II", len(data), 0x004E4942) + data)
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def exr(channels, width=1, height=1):
    """An uncompressed scanline OpenEXR of float32 channels {name: [values, row by row]}: magic,
    version 2, the required header attributes, the offset table and one block per scanline."""
    def attribute(name, kind, data):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(data)) + data
    names = sorted(channels, key=lambda n: n.encode())  # OpenEXR keeps channels sorted by name
    chlist = b"".join(n.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for n in names) + b"\0"
    box = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    header = (attribute("channels", "chlist", chlist) + attribute("compression", "compression", b"\0") +
              attribute("dataWindow", "box2i", box) + attribute("displayWindow", "box2i", box) +
              attribute("lineOrder", "lineOrder", b"\0") + attribute("pixelAspectRatio", "float", struct.pack("<f", 1)) +
              attribute("screenWindowCenter", "v2f", struct.pack("<ff", 0, 0)) +
              attribute("screenWindowWidth", "float", struct.pack("<f", 1)) + b"\0")
    start = 8 + len(header) + 8 * height
    blocks = b""
    offsets = []
    for y in range(height):
        data = b"".join(struct.pack(f"<{width}f", *channels[n][y * width:(y + 1) * width]) for n in names)
        offsets.append(start + len(blocks))
        blocks += struct.pack("<ii", y, len(data)) + data
    return struct.pack("<ii", 20000630, 2) + header + struct.pack(f"<{height}Q", *offsets) + blocks


def main():
    image = png()
    write("binary.csv", image)  # a PNG named .csv
    write("image.glb", image)  # a PNG named .glb
    write("text.gltf", "solid cube\n  facet normal 0 0 1\n    outer loop\n")  # an STL, not glTF

    doc = gltf(None)
    doc["buffers"][0] = {"byteLength": len(TRIANGLE)}
    whole = glb(doc, TRIANGLE)
    write("truncated.glb", whole[: len(whole) // 2])

    write("missing-buffer.gltf", json.dumps(gltf("no-such-buffer.bin"), indent=1))
    # A buffer URI of 5 000 bytes (issue 51, class 10): the loader's message names it; the line stays short.
    write("long-uri.gltf", json.dumps(gltf("u" * 5000 + ".bin"), indent=1))
    # A buffer beside the scene folder: tests/bad-inputs/files/../../data/... is outside the
    # scene's folder tree (tests/bad-inputs), so loading it needs --allow-outside-paths.
    write("outside-buffer.gltf", json.dumps(gltf("../../data/scene/cube.glb", byte_length=1484), indent=1))
    # 2^62 positions: count × 12-byte stride wraps around 2^64 to a small number.
    write("huge-count.gltf", json.dumps(gltf(None, position_count=2 ** 62), indent=1))
    write("index-out-of-range.gltf", json.dumps(gltf(None, index_values=(0, 1, 7)), indent=1))
    write("node-cycle.gltf", json.dumps(gltf(None, nodes=[{"mesh": 0, "children": [1]}, {"children": [0]}]),
                                        indent=1))
    # A child listed 1000 times under one node, itself with a child listed 1000 times: 10^6
    # instances from a file of a few KB, unless a node reached twice is refused.
    write("node-shared.gltf", json.dumps(gltf(None, nodes=[{"mesh": 0, "children": [1] * 1000},
                                                          {"mesh": 0, "children": [2] * 1000}, {"mesh": 0}]),
                                         indent=1))
    # Indices stored as floats: named as such, not as a buffer overrun.
    doc = gltf(None)
    doc["accessors"][1]["componentType"] = 5126
    write("float-indices.gltf", json.dumps(doc, indent=1))
    doc = gltf(None)
    doc["extensionsRequired"] = ["KHR_draco_mesh_compression"]
    doc["extensionsUsed"] = ["KHR_draco_mesh_compression"]
    write("requires-draco.gltf", json.dumps(doc, indent=1))
    # 20 000 levels of arrays in "extras": tinygltf converts extras recursively.
    doc = gltf(None)
    doc["meshes"][0]["extras"] = "@@"
    write("deep-extras.gltf", json.dumps(doc).replace('"@@"', "[" * DEEP + "]" * DEEP))
    doc = gltf(None)
    doc["meshes"][0]["primitives"][0]["mode"] = 1
    doc["accessors"][1]["count"] = 2
    write("lines.gltf", json.dumps(doc, indent=1))


    # Bispectral images (Donaldson matrices): a texture, a NaN, reflective channels only, and two
    # names for one (λin, λout) pair.
    four = ["T.400nm.500nm", "T.400nm.600nm", "T.450nm.500nm", "T.450nm.600nm"]
    write("donaldson-texture.exr", exr({n: [0.001, 0.002] for n in four}, width=2))
    write("donaldson-nan.exr", exr(dict(zip(four, [[0.001], [float("nan")], [0.002], [0.003]]))))
    write("donaldson-reflective.exr", exr({"T.400nm": [0.5], "T.500nm": [0.6]}))
    write("donaldson-duplicate.exr", exr({"T.400nm.500nm": [0.001], "T.400,0nm.500nm": [0.002],
                                          "T.450nm.600nm": [0.003]}))

    # A scene nesting 20 000 levels deep (the case itself lives beside this folder).
    with open(os.path.join(HERE, "..", "syntax-deep-nesting.json"), "w") as f:
        f.write('{"description": ' + "[" * DEEP + "]" * DEEP + ',\n "camera": {"position": [0, 0, 3], "target": [0, 0, 0]}}\n')


if __name__ == "__main__":
    main()
