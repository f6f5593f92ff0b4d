#!/usr/bin/env python3
"""Writes the seeds of the `draco` fuzz target into fuzz/seeds/draco/ (run from the repository
root; needs DracoPy and numpy). Each seed is the target's input: two bytes (little-endian) of
the largest count a primitive's accessors would declare, then a Draco stream. The streams cover
the decoder's paths: sequential and edgebreaker connectivity (standard and valence), quantized
and lossless attributes, normals (octahedral), texture coordinates, colours, a generic
attribute, a point cloud (which a mesh decoder refuses), and the two streams of
tests/data/formats/ (the cube, and the cube cut short)."""

import base64
import json
import math
import struct
from pathlib import Path

import DracoPy
import numpy as np

OUT = Path("fuzz/seeds/draco")


def cube():
    pos = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    return np.array(pos, dtype=np.float32), np.array(tris, dtype=np.uint32)


def sphere(rings=8, segments=12):
    pos = []
    for i in range(rings + 1):
        t = math.pi * i / rings
        for j in range(segments):
            p = 2 * math.pi * j / segments
            pos.append((math.sin(t) * math.cos(p), math.cos(t), math.sin(t) * math.sin(p)))
    tris = []
    for i in range(rings):
        for j in range(segments):
            a, b = i * segments + j, i * segments + (j + 1) % segments
            c, d = a + segments, b + segments
            tris += [(a, c, b), (b, c, d)]
    return np.array(pos, dtype=np.float32), np.array(tris, dtype=np.uint32)


def write(name, stream, points, faces):
    largest = max(points, faces * 3)
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / name).write_bytes(struct.pack("<H", largest) + stream)


def main():
    pos, tris = cube()
    write("cube-sequential.drc", DracoPy.encode(pos, tris, preserve_order=True), 8, 12)
    write("cube-level0.drc", DracoPy.encode(pos, tris, compression_level=0), 8, 12)
    pos, tris = sphere()
    n = len(pos)
    normals = pos.astype(np.float64)
    uvs = np.stack([np.linspace(0, 1, n), np.linspace(1, 0, n)], axis=1)
    colors = (np.arange(n * 3).reshape(n, 3) % 256).astype(np.uint8)
    for level, name in [(7, "edgebreaker"), (10, "valence")]:
        stream = DracoPy.encode(pos, tris, quantization_bits=14, compression_level=level,
                                normals=normals, tex_coord=uvs, colors=colors,
                                tex_coord_quantization_bits=10, normal_quantization_bits=8)
        decoded = DracoPy.decode(stream)
        write(f"sphere-{name}.drc", stream, len(decoded.points), len(decoded.faces))
    stream = DracoPy.encode(pos, tris, quantization_bits=20, compression_level=5,
                            tex_coord=uvs, normals=normals,
                            generic_attributes={7: np.arange(n, dtype=np.float32).reshape(n, 1)})
    decoded = DracoPy.decode(stream)
    write("sphere-lossless-generic.drc", stream, len(decoded.points), len(decoded.faces))
    write("points.drc", DracoPy.encode(pos, quantization_bits=8), n, 0)
    for name in ["cube-draco.gltf", "cube-draco-broken.gltf"]:
        doc = json.loads((Path("tests/data/formats") / name).read_text())
        data = base64.b64decode(doc["buffers"][0]["uri"].split(",", 1)[1])
        ext = doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]
        view = doc["bufferViews"][ext["bufferView"]]
        at = view.get("byteOffset", 0)
        stream = data[at:at + view["byteLength"]]
        primitive = doc["meshes"][0]["primitives"][0]
        ids = list(primitive["attributes"].values()) + [primitive["indices"]]
        largest = max(doc["accessors"][i]["count"] for i in ids)
        write(name.replace(".gltf", ".drc"), stream, largest, 0)


if __name__ == "__main__":
    main()
