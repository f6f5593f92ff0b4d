"""Writes samplers.gltf: a small glTF whose animation uses every sampler kind on every path.

Node channels: translation STEP (cube A), rotation CUBICSPLINE and scale LINEAR (cube B, under a
parent that is itself scaled and turned), morph weights LINEAR on a cube with two targets
(positions and normals) and a non-zero default weight, and a skinned bar whose vertices follow
up to four joints through JOINTS_0/WEIGHTS_0 and JOINTS_1/WEIGHTS_1, the joints turned by
LINEAR rotations and moved by a CUBICSPLINE translation. Written by us for the playback tests
(tests/it/animation_playback.rs); CC0, as the rest of the file's folder says.

    python3 make-samplers.py   (from this folder)
"""

import base64
import json
import math
import struct

blob = bytearray()
views, accessors = [], []


def add(values, fmt, count, kind, comp, minmax=False, target=None):
    while len(blob) % 4:
        blob.append(0)
    start = len(blob)
    blob.extend(struct.pack("<%d%s" % (len(values), fmt), *values))
    view = {"buffer": 0, "byteOffset": start, "byteLength": len(blob) - start}
    if target:
        view["target"] = target
    views.append(view)
    acc = {"bufferView": len(views) - 1, "componentType": comp, "count": count, "type": kind}
    if minmax:
        n = {"SCALAR": 1, "VEC3": 3}[kind]
        acc["min"] = [min(values[i::n]) for i in range(n)]
        acc["max"] = [max(values[i::n]) for i in range(n)]
    accessors.append(acc)
    return len(accessors) - 1


def floats(values, kind, minmax=False):
    n = {"SCALAR": 1, "VEC3": 3, "VEC4": 4, "MAT4": 16}[kind]
    return add(values, "f", len(values) // n, kind, 5126, minmax)


def cube(size):
    """24 vertices (4 per face, with face normals) and 36 indices."""
    pos, nor, idx = [], [], []
    for axis in range(3):
        for sign in (-1, 1):
            n = [0, 0, 0]
            n[axis] = sign
            u, v = [(axis + 1) % 3, (axis + 2) % 3]
            base = len(pos) // 3
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0, 0, 0]
                p[axis] = sign * size
                p[u] = a * size
                p[v] = b * size
                pos += p
                nor += n
            quad = [0, 1, 2, 0, 2, 3] if sign > 0 else [0, 2, 1, 0, 3, 2]
            idx += [base + q for q in quad]
    return pos, nor, idx


def mesh(pos, nor, idx, extra=None, targets=None, weights=None):
    attrs = {"POSITION": floats(pos, "VEC3", True), "NORMAL": floats(nor, "VEC3")}
    attrs.update(extra or {})
    prim = {"attributes": attrs, "indices": add(idx, "H", len(idx), "SCALAR", 5123, target=34963)}
    if targets:
        prim["targets"] = targets
    m = {"primitives": [prim]}
    if weights:
        m["weights"] = weights
    return m


def quat(axis, deg):
    s = math.sin(math.radians(deg) / 2)
    return [axis[0] * s, axis[1] * s, axis[2] * s, math.cos(math.radians(deg) / 2)]


meshes = []
pos, nor, idx = cube(0.25)
meshes.append(mesh(pos, nor, idx))
# Morph cube: target 0 stretches +Y, target 1 shears x by y (normals tilted to match).
t0 = [d for i in range(24) for d in (0.0, 0.5 if pos[3 * i + 1] > 0 else 0.0, 0.0)]
t1 = [d for i in range(24) for d in (0.4 * pos[3 * i + 1], 0.0, 0.0)]
n1 = [d for i in range(24) for d in (0.0, -0.3 * nor[3 * i], 0.0)]
targets = [
    {"POSITION": floats(t0, "VEC3", True)},
    {"POSITION": floats(t1, "VEC3", True), "NORMAL": floats(n1, "VEC3")},
]
meshes.append(mesh(pos, nor, idx, targets=targets, weights=[0.25, 0.0]))
# Skinned bar along +X: 11 rings of 4 vertices, each ring weighted over four joints.
bpos, bnor, bidx, j0, w0, j1, w1 = [], [], [], [], [], [], []
for r in range(11):
    x = r * 0.2
    for k, (y, z) in enumerate(((-0.1, -0.1), (0.1, -0.1), (0.1, 0.1), (-0.1, 0.1))):
        bpos += [x, y, z]
        bnor += [0.0, y * 10 / math.sqrt(2), z * 10 / math.sqrt(2)]
        c = x / 2.0 * 3.0  # 0 .. 3 along the joints
        ws = [max(0.0, 1.0 - abs(c - j)) for j in range(4)]
        s = sum(ws)
        ws = [w / s for w in ws]
        j0 += [0, 1, 0, 0]
        w0 += [ws[0], ws[1], 0.0, 0.0]
        j1 += [2, 3, 0, 0]
        w1 += [ws[2], ws[3], 0.0, 0.0]
for r in range(10):
    for k in range(4):
        a, b = r * 4 + k, r * 4 + (k + 1) % 4
        bidx += [a, b, b + 4, a, b + 4, a + 4]
extra = {
    "JOINTS_0": add(j0, "B", 44, "VEC4", 5121),
    "WEIGHTS_0": floats(w0, "VEC4"),
    "JOINTS_1": add(j1, "B", 44, "VEC4", 5121),
    "WEIGHTS_1": floats(w1, "VEC4"),
}
meshes.append(mesh(bpos, bnor, bidx, extra=extra))

ibm = []
for j in range(4):
    ibm += [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -j * 2.0 / 3.0, 0, 0, 1]
nodes = [
    {"name": "step cube", "mesh": 0, "translation": [-1.0, 0.5, 0.0]},
    {"name": "parent", "children": [2], "translation": [0.0, 0.5, -1.0],
     "rotation": quat([0, 1, 0], 30), "scale": [1.5, 1.5, 1.5]},
    {"name": "cubic cube", "mesh": 0},
    {"name": "morph cube", "mesh": 1, "translation": [1.0, 0.5, 0.0]},
    {"name": "bar", "mesh": 2, "skin": 0},
    {"name": "joint 0", "children": [6], "translation": [-1.0, 0.2, 1.0]},
    {"name": "joint 1", "children": [7], "translation": [2.0 / 3.0, 0, 0]},
    {"name": "joint 2", "children": [8], "translation": [2.0 / 3.0, 0, 0]},
    {"name": "joint 3", "translation": [2.0 / 3.0, 0, 0]},
]
skins = [{"joints": [5, 6, 7, 8], "inverseBindMatrices": floats(ibm, "MAT4")}]

times = [0.0, 0.5, 1.0, 1.5, 2.0]
tin = floats(times, "SCALAR", True)
samplers, channels = [], []


def channel(node, path, interpolation, values, kind):
    samplers.append({"input": tin, "interpolation": interpolation, "output": floats(values, kind)})
    channels.append({"sampler": len(samplers) - 1, "target": {"node": node, "path": path}})


channel(0, "translation", "STEP",
        [v for k in range(5) for v in (-1.0, 0.5 + 0.3 * (k % 2), 0.2 * k)], "VEC3")
cub = []
for k in range(5):
    q = quat([0, 0.6, 0.8], 40 * k)
    cub += [0.3, -0.2, 0.1, 0.0] + q + [-0.1, 0.2, 0.0, 0.1]
channel(2, "rotation", "CUBICSPLINE", cub, "VEC4")
channel(2, "scale", "LINEAR", [v for k in range(5) for v in (1 + 0.2 * k, 1.0, 1 - 0.1 * k)], "VEC3")
channel(3, "weights", "LINEAR", [0.25, 0.0, 1.0, 0.0, 0.5, 0.5, 0.0, 1.0, 0.25, 0.0], "SCALAR")
for j in (5, 6, 7):
    channel(j, "rotation", "LINEAR",
            [v for k in range(5) for v in quat([0, 0, 1], 25 * math.sin(k * 1.3 + j))], "VEC4")
ct = []
for k in range(5):
    ct += [0.0, 0.5, 0.0] + [-1.0, 0.2 + 0.1 * k, 1.0] + [0.0, -0.3, 0.2]
channel(5, "translation", "CUBICSPLINE", ct, "VEC3")

# A second animation of the samplers Blender's importer keeps exactly between keys (STEP and
# LINEAR on translation, scale and weights): compared at any time, not only at the keys.
first = (samplers, channels)
samplers, channels = [], []
channel(0, "translation", "STEP",
        [v for k in range(5) for v in (-1.0 + 0.1 * k, 0.5, -0.2 * k)], "VEC3")
channel(2, "scale", "LINEAR", [v for k in range(5) for v in (1.0, 1 + 0.3 * k, 1.0)], "VEC3")
channel(3, "weights", "LINEAR", [0.0, 0.0, 0.6, 0.2, 0.1, 0.9, 1.0, 1.0, 0.3, 0.0], "SCALAR")
channel(5, "translation", "LINEAR", [v for k in range(5) for v in (-1.0, 0.2 * k, 1.0 + 0.1 * k)], "VEC3")
second = (samplers, channels)

gltf = {
    "asset": {"version": "2.0", "generator": "envshadow make-samplers.py", "copyright": "CC0"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 3, 4, 5]}],
    "nodes": nodes,
    "meshes": meshes,
    "skins": skins,
    "animations": [
        {"name": "every sampler", "samplers": first[0], "channels": first[1]},
        {"name": "step and linear", "samplers": second[0], "channels": second[1]},
    ],
    "accessors": accessors,
    "bufferViews": views,
    "buffers": [{"byteLength": len(blob),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
}
with open("samplers.gltf", "w") as f:
    json.dump(gltf, f, indent=1)
