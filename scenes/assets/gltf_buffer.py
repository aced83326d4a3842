"""One glTF 2.0 binary buffer as the asset scripts (make_assets.py, make_textured.py,
make_cornell.py) build it: values packed little-endian, each buffer view 4-byte aligned, one
accessor per view. Standard library only."""

import struct


class GltfBuffer:
    def __init__(self):
        self.blob = bytearray()
        self.views = []
        self.accessors = []

    def add(self, values, fmt, count, type_, ctype, target, minmax=None):
        """Appends `values` (struct format `fmt`) as a view and its accessor; returns the accessor's index."""
        while len(self.blob) % 4:
            self.blob.append(0)
        offset = len(self.blob)
        self.blob.extend(struct.pack("<%d%s" % (len(values), fmt), *values))
        self.views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(self.blob) - offset, "target": target})
        acc = {"bufferView": len(self.views) - 1, "componentType": ctype, "count": count, "type": type_}
        if minmax:
            acc["min"], acc["max"] = minmax
        self.accessors.append(acc)
        return len(self.accessors) - 1
