#!/usr/bin/env python3
"""icosphere.py LEVELS OUT.glb — a smooth-shaded icosphere of unit radius standing on y = 0:
the icosahedron's 20 faces split into 4 per level (0: 20 faces, 1: 80, 2: 320), every vertex
normal its direction from the centre. The faceted model behind docs/terminator.png (the
shadow-terminator offset; tests/it/terminator.rs builds the same spheres)."""
import json
import math
import struct
import sys


def icosphere(levels):
    t = (1 + math.sqrt(5)) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    unit = lambda p: tuple(c / math.sqrt(sum(x * x for x in p)) for c in p)
    v = [unit(p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        mids = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in mids:
                v.append(unit(tuple(x + y for x, y in zip(v[a], v[b]))))
                mids[key] = len(v) - 1
            return mids[key]

        nf = []
        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return v, f


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__.splitlines()[0])
    v, f = icosphere(int(sys.argv[1]))
    pos = b"".join(struct.pack("<3f", p[0], p[1] + 1, p[2]) for p in v)
    nrm = b"".join(struct.pack("<3f", *p) for p in v)
    idx = b"".join(struct.pack("<3I", *t) for t in f)
    lo = [min(p[k] + (k == 1) for p in v) for k in range(3)]
    hi = [max(p[k] + (k == 1) for p in v) for k in range(3)]
    bin_ = pos + nrm + idx
    doc = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(bin_)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
            {"buffer": 0, "byteOffset": len(pos), "byteLength": len(nrm)},
            {"buffer": 0, "byteOffset": len(pos) + len(nrm), "byteLength": len(idx)},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(v), "type": "VEC3",
             "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5126, "count": len(v), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": 3 * len(f), "type": "SCALAR"},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    bin_ += b"\0" * (-len(bin_) % 4)
    with open(sys.argv[2], "wb") as out:
        out.write(struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(js) + 8 + len(bin_)))
        out.write(struct.pack("<I4s", len(js), b"JSON") + js)
        out.write(struct.pack("<I4s", len(bin_), b"BIN\0") + bin_)


if __name__ == "__main__":
    main()
