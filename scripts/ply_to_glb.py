#!/usr/bin/env python3
"""Convert a Stanford-zipper ASCII PLY (e.g. bun_zipper.ply) into a glTF 2.0 binary (.glb).

Python 3 standard library only.  The output reproduces, byte for byte, the
test assets described in assets/SOURCES.md (bunny.glb, bunny_on_plane.glb,
bunny_res4.glb) when given the same PLY input:

  * vertices that no face references are dropped; the rest keep their PLY order;
  * faces are kept exactly as in the PLY (polygons with more than 3 corners are
    fan-triangulated, which never happens for the Stanford files);
  * the mesh is only translated (float64 arithmetic, then stored as float32):
    the x/z bounding-box centre goes to the origin and the lowest point to y = 0;
    the translation (rounded to 8 decimals) is recorded in asset.extras;
  * smooth vertex normals = normalised sum of the (un-normalised, i.e.
    area-weighted) face cross products, in float64.  When a vertex's sum cancels
    (back-to-back coincident faces), the normal of its largest incident face
    (first one on ties) is used instead; the count is recorded in asset.extras;
  * POSITION / NORMAL float32 VEC3 (POSITION with min/max), indices UNSIGNED_INT;
    material "bunny_diffuse" (0.8 grey, metallic 0, roughness 1);
  * --ground adds a second node/mesh: a 2-triangle square at y = 0 centred at the
    origin, side = 4 x the larger x/z extent of the mesh, CCW seen from +Y,
    normals +Y, material "ground_diffuse" (0.5 grey).

Usage: ply_to_glb.py INPUT.ply OUTPUT.glb [--ground] [--name NAME]
"""

import argparse
import json
import math
import os
import struct
import sys

GENERATOR = "make_assets.py (steering research; numpy-only GLB writer)"
ARRAY_BUFFER = 34962
ELEMENT_ARRAY_BUFFER = 34963
FLOAT = 5126
UNSIGNED_INT = 5125

_F32 = struct.Struct("<f")


def f32(x):
    """Round a Python float to the nearest float32 value."""
    return _F32.unpack(_F32.pack(x))[0]


class PlyError(Exception):
    pass


def read_ascii_ply(path):
    """Return (vertices [(x, y, z) float64], triangles [[i, j, k]], n_face_records)."""
    with open(path, "r", encoding="ascii", errors="strict") as fh:
        text = fh.read()
    lines = text.split("\n")
    if not lines or lines[0].strip() != "ply":
        raise PlyError("%s: not a PLY file (missing 'ply' magic)" % path)
    elements = []  # [name, count, [props]]
    fmt = None
    i = 1
    while True:
        if i >= len(lines):
            raise PlyError("%s: header has no end_header" % path)
        tok = lines[i].split()
        i += 1
        if not tok:
            continue
        if tok[0] == "end_header":
            break
        if tok[0] == "format":
            fmt = tok[1]
        elif tok[0] == "element":
            elements.append([tok[1], int(tok[2]), []])
        elif tok[0] == "property":
            if not elements:
                raise PlyError("%s: property before any element" % path)
            elements[-1][2].append(tok[1:])
        elif tok[0] in ("comment", "obj_info"):
            pass
        else:
            raise PlyError("%s: unknown header line %r" % (path, lines[i - 1]))
    if fmt != "ascii":
        raise PlyError("%s: only ASCII PLY is supported (format %s)" % (path, fmt))

    verts, faces = [], []
    n_face_records = 0
    for name, count, props in elements:
        block = lines[i:i + count]
        if len(block) < count:
            raise PlyError("%s: file ends inside element '%s'" % (path, name))
        i += count
        if name == "vertex":
            names = [p[-1] for p in props]
            try:
                ix, iy, iz = names.index("x"), names.index("y"), names.index("z")
            except ValueError:
                raise PlyError("%s: vertex element lacks x/y/z" % path)
            if any(p[0] == "list" for p in props):
                raise PlyError("%s: list properties in vertex element unsupported" % path)
            for ln in block:
                t = ln.split()
                verts.append((float(t[ix]), float(t[iy]), float(t[iz])))
        elif name == "face":
            if len(props) != 1 or props[0][0] != "list":
                raise PlyError("%s: face element must be a single list property" % path)
            n_face_records += count
            for ln in block:
                t = ln.split()
                n = int(t[0])
                idx = [int(v) for v in t[1:1 + n]]
                if len(idx) != n or n < 3:
                    raise PlyError("%s: bad face line %r" % (path, ln))
                for k in range(1, n - 1):  # fan (identity for triangles)
                    faces.append([idx[0], idx[k], idx[k + 1]])
        # other elements are skipped
    nv = len(verts)
    for f in faces:
        for v in f:
            if not 0 <= v < nv:
                raise PlyError("%s: face index %d out of range" % (path, v))
    return verts, faces, n_face_records


def build_mesh(verts, faces):
    used = sorted(set(v for f in faces for v in f))
    remap = {old: new for new, old in enumerate(used)}
    P = [verts[o] for o in used]
    F = [[remap[v] for v in f] for f in faces]

    mn = [min(p[k] for p in P) for k in range(3)]
    mx = [max(p[k] for p in P) for k in range(3)]
    t = (-(mn[0] + mx[0]) / 2.0, -mn[1], -(mn[2] + mx[2]) / 2.0)
    T = [(p[0] + t[0], p[1] + t[1], p[2] + t[2]) for p in P]

    # area-weighted vertex normals (float64)
    acc = [[0.0, 0.0, 0.0] for _ in T]
    absacc = [0.0] * len(T)
    fnorm = []
    for a, b, c in F:
        A, B, C = T[a], T[b], T[c]
        e1 = (B[0] - A[0], B[1] - A[1], B[2] - A[2])
        e2 = (C[0] - A[0], C[1] - A[1], C[2] - A[2])
        n = (e1[1] * e2[2] - e1[2] * e2[1],
             e1[2] * e2[0] - e1[0] * e2[2],
             e1[0] * e2[1] - e1[1] * e2[0])
        ln = math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
        fnorm.append((n, ln))
        for v in (a, b, c):
            r = acc[v]
            r[0] += n[0]
            r[1] += n[1]
            r[2] += n[2]
            absacc[v] += ln

    N = [None] * len(T)
    cancelled = []
    for v, r in enumerate(acc):
        ln = math.sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2])
        if ln <= 1e-9 * absacc[v] or ln == 0.0:
            cancelled.append(v)
        else:
            N[v] = (r[0] / ln, r[1] / ln, r[2] / ln)
    if cancelled:
        best = {v: (-1.0, None) for v in cancelled}
        for fi, f in enumerate(F):
            ln = fnorm[fi][1]
            for v in f:
                if v in best and ln > best[v][0]:
                    best[v] = (ln, fi)
        for v in cancelled:
            ln, fi = best[v]
            n = fnorm[fi][0]
            if ln == 0.0:
                raise PlyError("vertex %d: all incident faces are degenerate" % v)
            N[v] = (n[0] / ln, n[1] / ln, n[2] / ln)

    return {
        "positions": T,
        "normals": N,
        "faces": F,
        "translation": t,
        "extent": (mx[0] - mn[0], mx[2] - mn[2]),
        "dropped": len(verts) - len(used),
        "cancelled": len(cancelled),
    }


def pack_vec3(rows):
    flat = [c for r in rows for c in r]
    return struct.pack("<%df" % len(flat), *flat)


def minmax_f32(rows):
    rr = [[f32(c) for c in r] for r in rows]
    return ([min(r[k] for r in rr) for k in range(3)],
            [max(r[k] for r in rr) for k in range(3)])


def write_glb(out_path, ply_name, n_ply_verts, n_ply_faces, mesh, name, ground):
    t = mesh["translation"]
    extras = {
        "source_ply": ply_name,
        "ply_vertices": n_ply_verts,
        "ply_faces": n_ply_faces,
        "unreferenced_vertices_dropped": mesh["dropped"],
        "cancelled_normals_fallback": mesh["cancelled"],
        "translation_applied": [round(x, 8) for x in t],
        "units": "metres (original scan units, no scale applied)",
        "up": "+Y (original scan orientation, no rotation applied)",
        "source": "Stanford 3D Scanning Repository, bunny/reconstruction/%s "
                  "(via github.com/ksnabb/stan_bun)" % ply_name,
    }

    prims = []  # (name, positions, normals, flat indices, material)
    idx = [v for f in mesh["faces"] for v in f]
    prims.append((name, mesh["positions"], mesh["normals"], idx, 0))
    materials = [{
        "name": "bunny_diffuse",
        "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0],
                                 "metallicFactor": 0.0, "roughnessFactor": 1.0},
        "doubleSided": False,
    }]
    if ground:
        side = 4.0 * max(mesh["extent"])
        h = side / 2.0
        extras["ground_plane_side_m"] = round(side, 6)
        extras["ground_plane"] = ("square at y=0 centred on the bunny's x/z bbox centre, "
                                  "side = 4 x max(x,z extent of bunny)")
        gp = [(-h, 0.0, -h), (-h, 0.0, h), (h, 0.0, h), (h, 0.0, -h)]
        gn = [(0.0, 1.0, 0.0)] * 4
        prims.append(("ground", gp, gn, [0, 1, 2, 0, 2, 3], 1))
        materials.append({
            "name": "ground_diffuse",
            "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0],
                                     "metallicFactor": 0.0, "roughnessFactor": 1.0},
            "doubleSided": False,
        })

    nodes, meshes, accessors, views, blobs = [], [], [], [], []
    offset = 0

    def add_view(data, target):
        nonlocal offset
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(data),
                      "target": target})
        blobs.append(data)
        offset += len(data)
        pad = (-len(data)) % 4
        if pad:
            blobs.append(b"\0" * pad)
            offset += pad
        return len(views) - 1

    for pname, pos, nor, ind, mat in prims:
        base = len(accessors)
        mn, mx = minmax_f32(pos)
        accessors.append({"bufferView": add_view(pack_vec3(pos), ARRAY_BUFFER),
                          "componentType": FLOAT, "count": len(pos), "type": "VEC3",
                          "min": mn, "max": mx})
        accessors.append({"bufferView": add_view(pack_vec3(nor), ARRAY_BUFFER),
                          "componentType": FLOAT, "count": len(nor), "type": "VEC3"})
        accessors.append({"bufferView": add_view(struct.pack("<%dI" % len(ind), *ind),
                                                 ELEMENT_ARRAY_BUFFER),
                          "componentType": UNSIGNED_INT, "count": len(ind),
                          "type": "SCALAR"})
        nodes.append({"name": pname, "mesh": len(meshes)})
        meshes.append({"name": pname, "primitives": [{
            "attributes": {"POSITION": base, "NORMAL": base + 1},
            "indices": base + 2, "material": mat, "mode": 4}]})

    doc = {
        "asset": {"version": "2.0", "generator": GENERATOR, "extras": extras},
        "scene": 0,
        "scenes": [{"name": "Scene", "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": offset}],
    }
    js = json.dumps(doc, separators=(",", ":")).encode("utf-8")
    js += b" " * ((-len(js)) % 4)
    binchunk = b"".join(blobs)
    total = 12 + 8 + len(js) + 8 + len(binchunk)
    out = b"".join([
        struct.pack("<4sII", b"glTF", 2, total),
        struct.pack("<I4s", len(js), b"JSON"), js,
        struct.pack("<I4s", len(binchunk), b"BIN\0"), binchunk,
    ])

    tmp = out_path + ".tmp.%d" % os.getpid()
    try:
        with open(tmp, "wb") as fh:
            fh.write(out)
        os.replace(tmp, out_path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return doc


def default_name(ply_path):
    stem = os.path.splitext(os.path.basename(ply_path))[0]
    if stem.startswith("bun_zipper"):
        return "bunny" + stem[len("bun_zipper"):]
    return stem


def main(argv=None):
    ap = argparse.ArgumentParser(
        description="Convert a Stanford-zipper ASCII PLY into a glTF 2.0 binary "
                    "(translation only, area-weighted smooth normals).")
    ap.add_argument("input", help="ASCII PLY file (e.g. bun_zipper.ply)")
    ap.add_argument("output", help="output .glb path (written atomically)")
    ap.add_argument("--ground", action="store_true",
                    help="add a 2-triangle ground square (second node/mesh)")
    ap.add_argument("--name", help="node/mesh name (default: bun_zipper* -> bunny*)")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    try:
        verts, faces, n_faces_ply = read_ascii_ply(a.input)
        mesh = build_mesh(verts, faces)
        doc = write_glb(a.output, os.path.basename(a.input), len(verts), n_faces_ply,
                        mesh, a.name or default_name(a.input), a.ground)
    except (OSError, PlyError, ValueError, UnicodeDecodeError) as e:
        print("ply_to_glb: error converting %s -> %s: %s" % (a.input, a.output, e),
              file=sys.stderr)
        return 1
    if not a.quiet:
        acc = doc["accessors"]
        tris = sum(x["count"] for x in acc if x["type"] == "SCALAR") // 3
        mn = [min(x["min"][k] for x in acc if "min" in x) for k in range(3)]
        mx = [max(x["max"][k] for x in acc if "max" in x) for k in range(3)]
        print("%s: %d vertices, %d triangles, bbox (%.5f, %.5f, %.5f) -> (%.5f, %.5f, %.5f),"
              " %d unreferenced dropped, %d cancelled normals" % (
                  a.output, acc[0]["count"], tris, mn[0], mn[1], mn[2], mx[0], mx[1], mx[2],
                  mesh["dropped"], mesh["cancelled"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
