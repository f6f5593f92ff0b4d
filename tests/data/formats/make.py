#!/usr/bin/env python3
"""Writes the small files tests/it/hardening_formats.rs reads (issue 39, item 8): a cube as
plain floats and as gltfpack writes it with KHR_mesh_quantization, unlit and spec-gloss
materials, meshopt cubes (by gltfpack), files the renderer refuses (broken Draco and meshopt, a KTX2 texture without fallback,
glTF 1.0) and files of other formats under model names. Run from anywhere; rewrites the
files beside it. Public domain (CC0), as the files it writes."""

import base64
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))

# A unit cube's 24 vertices (4 per face, outward normals) and 12 triangles.
FACES = [
    ((1, 0, 0), (0, 1, 0), (0, 0, 1)),
    ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
    ((0, 1, 0), (0, 0, 1), (1, 0, 0)),
    ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
    ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
    ((0, 0, -1), (0, 1, 0), (1, 0, 0)),
]


def cube():
    pos, nrm, uv, idx = [], [], [], []
    for n, a, b in FACES:
        base = len(pos)
        for (s, t) in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
            pos.append(tuple(n[k] + s * a[k] + t * b[k] for k in range(3)))
            nrm.append(n)
            uv.append(((s + 1) / 2, (t + 1) / 2))
        idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return pos, nrm, uv, idx


class Doc:
    def __init__(self):
        self.bin = bytearray()
        self.views, self.accessors = [], []

    def view(self, data, stride=None):
        while len(self.bin) % 4:
            self.bin.append(0)
        v = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if stride:
            v["byteStride"] = stride
        self.views.append(v)
        self.bin += data
        return len(self.views) - 1

    def accessor(self, data, fmt, ctype, type_, n, normalized=False, stride=None, minmax=None):
        raw = b"".join(struct.pack("<" + fmt, *e) for e in data)
        a = {"bufferView": self.view(raw, stride), "componentType": ctype, "count": len(data), "type": type_}
        if normalized:
            a["normalized"] = True
        if minmax:
            a["min"], a["max"] = minmax
        self.accessors.append(a)
        return len(self.accessors) - 1

    def write(self, name, rest):
        doc = {"asset": {"version": "2.0", "generator": "tests/data/formats/make.py"}}
        doc.update(rest)
        uri = "data:application/octet-stream;base64," + base64.b64encode(bytes(self.bin)).decode()
        doc["buffers"] = [{"byteLength": len(self.bin), "uri": uri}]
        doc["bufferViews"] = self.views
        doc["accessors"] = self.accessors
        with open(os.path.join(HERE, name), "w") as f:
            json.dump(doc, f, indent=1)


def scene(attributes, indices, material=None, extensions=(), required=(), node=None, materials=None):
    prim = {"attributes": attributes, "indices": indices}
    if material is not None:
        prim["material"] = material
    rest = {
        "meshes": [{"primitives": [prim]}],
        "nodes": [node or {"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }
    if materials:
        rest["materials"] = materials
    if extensions:
        rest["extensionsUsed"] = list(extensions)
    if required:
        rest["extensionsRequired"] = list(required)
    return rest


def plain(name, materials=None, extensions=(), required=(), extra=None):
    pos, nrm, uv, idx = cube()
    d = Doc()
    p = d.accessor(pos, "3f", 5126, "VEC3", 3, minmax=([-1] * 3, [1] * 3))
    n = d.accessor(nrm, "3f", 5126, "VEC3", 3)
    t = d.accessor(uv, "2f", 5126, "VEC2", 2)
    i = d.accessor([(x,) for x in idx], "H", 5123, "SCALAR", 1)
    rest = scene({"POSITION": p, "NORMAL": n, "TEXCOORD_0": t}, i,
                 material=0 if materials else None, materials=materials,
                 extensions=extensions, required=required)
    if extra:
        extra(rest)
    d.write(name, rest)


def quantized(name):
    """gltfpack's default: positions as unsigned shorts (0..2, placed by the node's scale and
    translation), normals as normalized bytes padded to 4, texture coordinates as normalized
    unsigned shorts."""
    pos, nrm, uv, idx = cube()
    d = Doc()
    qp = [tuple(int(c + 1) for c in v) + (0,) for v in pos]
    p = d.accessor([v[:3] for v in qp], "3H2x", 5123, "VEC3", 3, stride=8, minmax=([0] * 3, [2] * 3))
    n = d.accessor([tuple(int(127 * c) for c in v) for v in nrm], "3bx", 5120, "VEC3", 3, normalized=True, stride=4)
    t = d.accessor([tuple(int(round(65535 * c)) for c in v) for v in uv], "2H", 5123, "VEC2", 2, normalized=True)
    i = d.accessor([(x,) for x in idx], "H", 5123, "SCALAR", 1)
    node = {"mesh": 0, "translation": [-1, -1, -1], "scale": [1, 1, 1]}
    d.write(name, scene({"POSITION": p, "NORMAL": n, "TEXCOORD_0": t}, i, node=node, material=0,
                        materials=[BROWN], extensions=["KHR_mesh_quantization"],
                        required=["KHR_mesh_quantization"]))


def draco(name, broken=False):
    """The brown cube as Blender's exporter writes it with Draco compression: the primitive's
    accessors have no buffer view, its KHR_draco_mesh_compression stream holds them (made
    with DracoPy, Google's encoder; `broken`: the stream cut short). Without DracoPy the file
    already here is kept."""
    try:
        import DracoPy
        import numpy as np
    except ImportError:
        print(f"DracoPy not installed: {name} kept as it is")
        return
    pos, nrm, uv, idx = cube()
    stream = DracoPy.encode(np.array(pos, dtype=np.float32), np.array(idx, dtype=np.uint32).reshape(-1, 3),
                            quantization_bits=14, normals=np.array(nrm, dtype=np.float64),
                            tex_coord=np.array(uv, dtype=np.float64), preserve_order=True)
    # Draco's attribute types: 0 position, 1 normal, 3 texture coordinate.
    ids = {a["attribute_type"]: a["unique_id"] for a in DracoPy.decode(stream).attributes}
    if broken:
        stream = stream[: len(stream) // 2]
    d = Doc()
    view = d.view(stream)
    d.accessors = [
        {"componentType": 5126, "count": 24, "type": "VEC3", "min": [-1] * 3, "max": [1] * 3},
        {"componentType": 5126, "count": 24, "type": "VEC3"},
        {"componentType": 5126, "count": 24, "type": "VEC2"},
        {"componentType": 5123, "count": 36, "type": "SCALAR"},
    ]
    rest = scene({"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, 3, material=0, materials=[BROWN],
                 extensions=["KHR_draco_mesh_compression"], required=["KHR_draco_mesh_compression"])
    rest["meshes"][0]["primitives"][0]["extensions"] = {"KHR_draco_mesh_compression": {
        "bufferView": view, "attributes": {"POSITION": ids[0], "NORMAL": ids[1], "TEXCOORD_0": ids[3]}}}
    d.write(name, rest)


def png(path, w, h, rgba):
    raw = b"".join(b"\0" + bytes(rgba) * w for _ in range(h))
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    data = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
    data += chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(data)
    return data


def textured(name, with_fallback, ktx2=True):
    """A base colour texture given only as KTX2 (KHR_texture_basisu), with or without the PNG
    fallback as the texture's `source`; without `ktx2`, the plain PNG texture (the twin)."""
    fallback = png(os.path.join(HERE, "red.png"), 4, 4, (200, 30, 30, 255))
    def extra(rest):
        rest["images"] = [{"uri": "red.ktx2", "mimeType": "image/ktx2", "name": "red_ktx"},
                          {"uri": "data:image/png;base64," + base64.b64encode(fallback).decode()}]
        tex = {"extensions": {"KHR_texture_basisu": {"source": 0}}} if ktx2 else {}
        if with_fallback:
            tex["source"] = 1
        rest["textures"] = [tex]
    required = [] if with_fallback else ["KHR_texture_basisu"]
    plain(name, materials=[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
          extensions=["KHR_texture_basisu"] if ktx2 else [], required=required, extra=extra)


def meshopt():
    """The plain cube through gltfpack (Debian's 0.18, the reference meshoptimizer encoder):
    `-c -noq` float attributes and triangles as meshopt streams, `-cc` quantized with the
    octahedral filter on normals; and the first with its first stream's header byte broken."""
    import shutil
    import subprocess
    if shutil.which("gltfpack") is None:
        print("gltfpack not installed (apt-get install gltfpack): meshopt files kept as they are")
        return
    src = os.path.join(HERE, "cube.gltf")
    for name, flags in [("cube-meshopt.glb", ["-c", "-noq"]), ("cube-meshopt-filters.glb", ["-cc"])]:
        subprocess.run(["gltfpack", "-i", src, "-o", os.path.join(HERE, name)] + flags, check=True)
    with open(os.path.join(HERE, "cube-meshopt.glb"), "rb") as f:
        glb = bytearray(f.read())
    json_len = struct.unpack("<I", glb[12:16])[0]
    glb[20 + json_len + 8] ^= 0xff  # the BIN chunk's first byte: the vertex stream's header
    with open(os.path.join(HERE, "cube-meshopt-broken.glb"), "wb") as f:
        f.write(glb)


BROWN = {"pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.5, 0.4, 1], "metallicFactor": 0}}


def main():
    plain("cube.gltf", materials=[BROWN])
    quantized("cube-quantized.gltf")
    plain("cube-unlit.gltf", materials=[{"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.9, 0.3, 1]},
                                         "extensions": {"KHR_materials_unlit": {}}}],
          extensions=["KHR_materials_unlit"], required=["KHR_materials_unlit"])
    plain("cube-specgloss.gltf", materials=[{"extensions": {"KHR_materials_pbrSpecularGlossiness": {
        "diffuseFactor": [0.6, 0.5, 0.4, 1], "specularFactor": [0.04, 0.04, 0.04], "glossinessFactor": 0.3}}}],
          extensions=["KHR_materials_pbrSpecularGlossiness"], required=["KHR_materials_pbrSpecularGlossiness"])
    draco("cube-draco.gltf")
    draco("cube-draco-broken.gltf", broken=True)
    meshopt()
    textured("cube-ktx2-only.gltf", False)
    textured("cube-ktx2-fallback.gltf", True)
    textured("cube-png.gltf", True, ktx2=False)
    with open(os.path.join(HERE, "duck-1.0.gltf"), "w") as f:
        json.dump({"asset": {"version": "1.0"}, "meshes": {"mesh0": {"primitives": []}},
                   "scene": "defaultScene", "scenes": {"defaultScene": {"nodes": []}}}, f, indent=1)
    with open(os.path.join(HERE, "page.glb"), "w") as f:
        f.write("<!DOCTYPE html>\n<html><head><title>Sketchfab</title></head>\n<body>\nSign in to download\n</body></html>\n")
    with open(os.path.join(HERE, "bunny.ply"), "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    with open(os.path.join(HERE, "cube.obj"), "w") as f:
        f.write("# Blender 4.1.1\nmtllib cube.mtl\no Cube\nv 1 1 -1\nv 1 -1 -1\nv 1 1 1\nf 1 2 3\n")
    with open(os.path.join(HERE, "scene.blend"), "wb") as f:
        f.write(b"BLENDER-v402REND" + bytes(32))


main()
