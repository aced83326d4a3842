#!/usr/bin/env python3
"""Writes glTF files whose images are embedded, made from scenes/assets/panel.gltf (its buffer
panel.bin and its images tiles.png and tiles_normal.png), for the texture tests
(tests/textures_test.cpp, "Embedded") and the bad-input corpus:

- panel-embedded.glb: a binary glTF holding the mesh and both PNG images in buffer views;
- panel-datauri.gltf: the same as text, the buffer and both images as base64 data: URIs;
- panel-jpeg.glb: as panel-embedded.glb with the base colour image as a JPEG (tiles.jpg);
- ../../bad-inputs/files/gltf-image-not-an-image.glb: the base colour image's bytes are not an image;
- ../../bad-inputs/files/gltf-image-view-past-end.glb: its buffer view runs past the buffer's end.

The GLB and data-URI encoding uses only the standard library; tiles.jpg (already written) was made
with OpenImageIO (python3-openimageio), quality 95, from tiles.png.
    python3 tests/data/gltf/make_embedded.py
"""

import base64
import copy
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
ASSETS = os.path.join(HERE, "..", "..", "..", "scenes", "assets")
BAD = os.path.join(HERE, "..", "..", "bad-inputs", "files")


def read(path):
    with open(path, "rb") as f:
        return f.read()


def pad(data, byte):
    return data + byte * (-len(data) % 4)


def glb(doc, binary):
    """A GLB 2.0 container: header, JSON chunk (space-padded), BIN chunk (zero-padded)."""
    text = pad(json.dumps(doc, separators=(",", ":")).encode(), b" ")
    binary = pad(binary, b"\0")
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def embed_in_buffer(doc, binary, images):
    """Appends each image's bytes to the buffer as a buffer view and points the image at it."""
    doc = copy.deepcopy(doc)
    binary = bytearray(binary)
    for index, (data, mime) in enumerate(images):
        binary.extend(b"\0" * (-len(binary) % 4))
        doc["bufferViews"].append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(data)})
        binary.extend(data)
        doc["images"][index] = {"bufferView": len(doc["bufferViews"]) - 1, "mimeType": mime,
                                "name": ["tiles", "tiles_normal"][index]}
    doc["buffers"] = [{"byteLength": len(binary)}]
    return doc, bytes(binary)


def main():
    doc = json.loads(read(os.path.join(ASSETS, "panel.gltf")))
    doc["asset"]["generator"] = "metamer tests/data/gltf/make_embedded.py"
    binary = read(os.path.join(ASSETS, "panel.bin"))
    tiles, normal = read(os.path.join(ASSETS, "tiles.png")), read(os.path.join(ASSETS, "tiles_normal.png"))
    jpeg = read(os.path.join(HERE, "tiles.jpg"))

    d, b = embed_in_buffer(doc, binary, [(tiles, "image/png"), (normal, "image/png")])
    with open(os.path.join(HERE, "panel-embedded.glb"), "wb") as f:
        f.write(glb(d, b))

    d = copy.deepcopy(doc)
    d["buffers"] = [{"byteLength": len(binary),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(binary).decode()}]
    d["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(tiles).decode()},
                   {"uri": "data:image/png;base64," + base64.b64encode(normal).decode()}]
    with open(os.path.join(HERE, "panel-datauri.gltf"), "w", newline="\n") as f:
        json.dump(d, f, indent=1)
        f.write("\n")

    d, b = embed_in_buffer(doc, binary, [(jpeg, "image/jpeg"), (normal, "image/png")])
    with open(os.path.join(HERE, "panel-jpeg.glb"), "wb") as f:
        f.write(glb(d, b))

    d, b = embed_in_buffer(doc, binary, [(b"this is not an image, only text" * 4, "image/png"), (normal, "image/png")])
    with open(os.path.join(BAD, "gltf-image-not-an-image.glb"), "wb") as f:
        f.write(glb(d, b))

    d, b = embed_in_buffer(doc, binary, [(tiles, "image/png"), (normal, "image/png")])
    d["bufferViews"][d["images"][0]["bufferView"]]["byteLength"] = len(b) + 4096
    with open(os.path.join(BAD, "gltf-image-view-past-end.glb"), "wb") as f:
        f.write(glb(d, b))


if __name__ == "__main__":
    main()
