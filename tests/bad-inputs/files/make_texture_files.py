#!/usr/bin/env python3
"""Texture files of the bad-input corpus (README.md, `texture-` cases): a valid 4 x 4 sRGB tile,
a two-channel PNG, an emissive (S0) spectral EXR, a reflective one with a NaN texel, and a glTF
whose material has a baseColorFactor of 2. Needs numpy and OpenImageIO (python3-numpy,
python3-openimageio): python3 tests/bad-inputs/files/make_texture_files.py"""

import json
import os

import numpy as np
import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, pixels, fmt, channels=None):
    h, w, n = pixels.shape
    spec = oiio.ImageSpec(w, h, n, fmt)
    if channels:
        spec.channelnames = tuple(channels)
    out = oiio.ImageOutput.create(os.path.join(HERE, name))
    out.open(os.path.join(HERE, name), spec)
    out.write_image(np.ascontiguousarray(pixels, dtype=np.float32))
    out.close()


def main():
    write("tile.png", np.full((4, 4, 3), 0.5), "uint8")
    write("two-channel.png", np.full((4, 4, 2), 0.5), "uint8")
    nm = [400, 500, 600, 700]
    write("emissive.exr", np.full((2, 2, 4), 0.5), "float", ["S0.%dnm" % l for l in nm])
    bad = np.full((2, 2, 4), 0.5)
    bad[1, 0, 2] = np.nan
    write("nan-texel.exr", bad, "float", ["T.%dnm" % l for l in nm])
    with open(os.path.join(HERE, "bad-factor.gltf")) as f:
        doc = json.load(f)
    doc["materials"] = [{"name": "hot", "pbrMetallicRoughness": {"baseColorFactor": [2.0, 0.5, 0.5, 1.0]}}]
    doc["meshes"][0]["primitives"][0]["material"] = 0
    with open(os.path.join(HERE, "bad-factor.gltf"), "w") as f:
        json.dump(doc, f, indent=1)


if __name__ == "__main__":
    main()
