"""Renders an `envshadow export` frame with Mitsuba 3 (LLVM variant) exactly as envshadow's
`brute` method does, times it against envshadow on the same frame at the same samples per
pixel in the same run, and compares the images. Run through scripts/compare-mitsuba.sh,
which makes the venv and export.

Materials (exports with surface.f32, from envshadow's glTF metallic-roughness materials):
every light at every sample is shaded twice, by Mitsuba 3's own `principled` BSDF
(`bsdf.eval`, its parameters per sample: base colour, metallic, roughness as envshadow's
textures gave them) and by the glTF 2.0 BRDF written here in Dr.Jit from the specification's
formulas (h normalised, D and Vis apart; GGX's denominator as |n x h|^2 + (n.h)^2 a^2, which
keeps a mirror's peak in f32) -- an independent implementation of what envshadow computes.
Mitsuba intersects the primary and shadow rays itself; the shading normal is Mitsuba's
interpolated one, or envshadow's where a normal map bent it. Occlusion scales and emission
adds as in envshadow. envshadow renders with --glossy-env=false, the exact sum over the
lights, which is what both references evaluate. Relative RMSE is reported per material, over
the pixels whose every sample hits that material in both renderers (and the same material in
Mitsuba as in envshadow). `principled` is the Disney model, not glTF's: its diffuse lobe has
retro-reflection and no (1 - F) weight, its Fresnel is the exact dielectric one and its Smith
term separable, so it differs from glTF's BRDF by the models' own difference; the glTF column
checks envshadow's implementation. Then the float64 check: the same glTF BRDF in numpy float64
over the lights Mitsuba found visible, at each side's own shading normal, against which
envshadow, the Dr.Jit BRDF and the Dr.Jit BRDF with the plain f32 formula
((n.h)^2 (a^2 - 1) + 1) are measured: which side of a difference is off.

Cut-outs (alpha MASK and BLEND): camera and shadow rays go on through the surface where its
alpha says it is not there (Cutouts: materials.json's alpha mode, cutoff and alpha texture,
read with Dr.Jit's texture lookup at the PLY's texture coordinates), as envshadow's BVH does.

The samples: `spp` from frame.json (1 when absent: an export from before samples per pixel),
and primary.f32 holds every sample's direction, pixel by pixel, each pixel's k x k samples in
stratum order (an array (height, width, spp, 3)) -- the very directions envshadow traces, so
both renderers see the same sample positions. envshadow is rendered with the export's
`--spp`, `--filter` and `--filter-width`. A pixel is the plain mean of its samples, in both.

The integrator: one primary ray per sample, Lambertian
B = albedo/pi * sum_j V_j E_j max(0, N.w_j) over every light, shading normal = normalised
interpolated vertex normal (the facet normal where it points away from the facet's visible
side), both normals turned towards the camera, shadow rays from the hit point moved along
the geometric normal by its floating-point error bound (as envshadow's src/offset.rs), t in
(0, inf). Only pixels whose every sample hits
the scene are compared: where a sample misses, envshadow shows the environment and this
integrator returns 0 (it does not look the map up), so a pixel with any missing sample --
the background and the silhouette's edge -- is left out.
"""

import argparse
import csv
import json
import os
import subprocess
import sys
import time

import numpy as np
import mitsuba as mi
import drjit as dr

mi.set_variant("llvm_ad_rgb")


def read_ply(path):
    """scene.ply as envshadow export writes it: float vertex properties (position, normal,
    texture coordinates, COLOR_0 alpha), and faces of three indices with float r, g, b and an
    int material. Returns (vertex columns by name, faces, face rgb, face material)."""
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii").strip()
            header.append(line)
            if line == "end_header":
                break
        nv = int(next(l for l in header if l.startswith("element vertex")).split()[2])
        nf = int(next(l for l in header if l.startswith("element face")).split()[2])
        face_at = next(i for i, l in enumerate(header) if l.startswith("element face"))
        vprops = [l.split()[2] for l in header[:face_at] if l.startswith("property float")]
        fprops = [tuple(l.split()[1:]) for l in header[face_at:] if l.startswith("property")]
        verts = np.frombuffer(f.read(nv * 4 * len(vprops)), dtype="<f4").reshape(nv, -1)
        kinds = {"float": "<f4", "int": "<i4"}
        face_t = np.dtype([("n", "u1"), ("i", "<i4", 3)] + [
            (p[1], kinds[p[0]]) for p in fprops if p[0] != "list"])
        faces = np.frombuffer(f.read(nf * face_t.itemsize), dtype=face_t)
    if not np.all(faces["n"] == 3):
        sys.exit(f"{path}: only triangles are expected")
    columns = {name: verts[:, i] for i, name in enumerate(vprops)}
    rgb = np.stack([faces["r"], faces["g"], faces["b"]], axis=1)
    material = faces["material"] if "material" in faces.dtype.names else np.zeros(nf, "<i4")
    return columns, faces["i"].astype(np.uint32), rgb, material


def build_scene(export):
    v, f, rgb, material = read_ply(os.path.join(export, "scene.ply"))
    p = np.stack([v["x"], v["y"], v["z"]], axis=1)
    n = np.stack([v["nx"], v["ny"], v["nz"]], axis=1)
    mesh = mi.Mesh("scene", len(p), len(f), has_vertex_normals=True)
    mesh.add_attribute("face_albedo", 3, mi.Float(rgb.astype(np.float32).ravel()))
    mesh.add_attribute("face_material", 1, mi.Float(material.astype(np.float32)))
    if "u" in v:
        # Both texture coordinate sets and COLOR_0's alpha, for the alpha test (Cutouts).
        zero = np.zeros(len(p), np.float32)
        mesh.add_attribute("vertex_uv0", 3, mi.Float(
            np.stack([v["u"], v["v"], v["alpha"]], axis=1).ravel()))
        mesh.add_attribute("vertex_uv1", 3, mi.Float(
            np.stack([v["u1"], v["v1"], zero], axis=1).ravel()))
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(p.ravel())
    params["vertex_normals"] = mi.Float(n.ravel())
    params["faces"] = mi.UInt(f.ravel())
    params.update()
    scene = mi.load_dict({"type": "scene", "mesh": mesh})
    dr.sync_thread()
    return scene, mesh


class Cutouts:
    """glTF alpha as envshadow's export describes it (materials.json and alpha_T.f32), tested
    here with Dr.Jit's own texture lookup: a cut-out material's alpha is its base colour
    alpha factor x its base colour texture's alpha (level 0, through the slot's texture
    coordinate set, KHR_texture_transform matrix, wrap mode and magnification filter) x the
    interpolated COLOR_0 alpha. A ray stops at a hit where the surface is there: MASK where
    alpha >= cutoff; BLEND where alpha > the sample's coverage threshold for camera rays, and
    >= 0.5 for shadow rays; OPAQUE always. Rays go on through the rest (spawned past the hit),
    so shadows of cut-out leaves are leaf-shaped in both renderers."""

    WRAPS = {"repeat": dr.WrapMode.Repeat, "clamp": dr.WrapMode.Clamp,
             "mirror": dr.WrapMode.Mirror}

    def __init__(self, export, materials, mesh):
        self.mesh = mesh
        self.cut = []
        for m in materials:
            if not m.get("cut_out", False):
                continue
            tex = m.get("alpha_texture")
            texture = None
            if tex is not None:
                if tex["wrap_s"] != tex["wrap_t"]:
                    sys.exit(f"material {m['name']}: an alpha texture wrapped differently on s "
                             f"and t ({tex['wrap_s']}, {tex['wrap_t']}) is not supported here")
                data = np.fromfile(os.path.join(export, tex["file"]), dtype="<f4")
                data = data.reshape(tex["height"], tex["width"], 1)
                texture = mi.Texture2f(
                    mi.TensorXf(data),
                    filter_mode=dr.FilterMode.Nearest if tex["nearest"] else dr.FilterMode.Linear,
                    wrap_mode=self.WRAPS[tex["wrap_s"]])
            self.cut.append((m, tex, texture))

    def __bool__(self):
        return bool(self.cut)

    def stops(self, si, active, threshold=None):
        """Whether the surface at each hit `si` stops the ray: `threshold` is a camera ray's
        coverage threshold (None for shadow rays)."""
        material = self.mesh.eval_attribute_1("face_material", si, active)
        uv0 = self.mesh.eval_attribute_3("vertex_uv0", si, active)
        stop = mi.Bool(True)
        for m, tex, texture in self.cut:
            here = active & (material == float(m["index"]))
            a = mi.Float(m["base_alpha"]) * uv0.z
            if texture is not None:
                uv = uv0 if tex["tex_coord"] == 0 else self.mesh.eval_attribute_3(
                    "vertex_uv1", si, here)
                u, v = uv.x, uv.y
                t = tex["transform"]
                if t is not None:
                    u, v = t[0] * u + t[1] * v + t[2], t[3] * u + t[4] * v + t[5]
                a = a * texture.eval(mi.Point2f(u, v), active=here)[0]
            if m["alpha_mode"] == "MASK":
                there = a >= m["alpha_cutoff"]
            elif threshold is not None:
                there = a > threshold
            else:
                there = a >= 0.5
            stop = dr.select(here, there, stop)
        return stop


def occluded(scene, cutouts, ray):
    """Whether anything stops `ray`: Mitsuba's ray_test, or with cut-outs its ray_intersect
    repeated past every hit where the surface is cut out."""
    return occluded_cut(scene, cutouts, ray) if cutouts else scene.ray_test(ray)


@dr.syntax
def occluded_cut(scene, cutouts, ray):
    blocked = mi.Bool(False)
    active = mi.Bool(True)
    while active:
        si = scene.ray_intersect(ray, active)
        hit = active & si.is_valid()
        stop = hit & cutouts.stops(si, hit)
        blocked |= stop
        active = hit & ~stop
        ray = si.spawn_ray(ray.d)
    return blocked


def first_hit(scene, cutouts, ray, threshold):
    """The camera ray's hit: the first where the surface is there (cut-outs passed)."""
    si = scene.ray_intersect(ray)
    return first_hit_cut(scene, cutouts, ray, threshold, si) if cutouts else si


@dr.syntax
def first_hit_cut(scene, cutouts, ray, threshold, si):
    going = si.is_valid() & ~cutouts.stops(si, si.is_valid(), threshold)
    while going:
        nxt = scene.ray_intersect(si.spawn_ray(ray.d), going)
        si = dr.select(going, nxt, si)
        going &= si.is_valid() & ~cutouts.stops(si, going & si.is_valid(), threshold)
    return si


def coverage_threshold(px, py, sx, sy, k):
    """envshadow's coverage threshold of a camera sample for BLEND surfaces
    (src/scene/alpha.rs): the pixel's k^2 samples at (r + o)/k^2, o interleaved gradient noise
    over the pixels, in f32 as there."""
    f32 = np.float32
    fr = lambda x: x - np.floor(x)
    o = fr(f32(52.982918) * fr(f32(0.06711056) * px.astype(f32) + f32(0.00583715)
                              * py.astype(f32)))
    n = f32(k * k)
    r = (sy * k + sx).astype(f32)
    return np.minimum((r + o) / n, f32(1.0) - np.finfo(f32).eps / f32(2.0))


def sample_thresholds(meta, spp):
    """Every sample's coverage threshold, in primary.f32's order."""
    h, w = meta["height"], meta["width"]
    k = int(round(spp ** 0.5))
    y, x, j, i = np.meshgrid(np.arange(h), np.arange(w), np.arange(k), np.arange(k),
                             indexing="ij")
    return coverage_threshold(x.ravel(), y.ravel(), i.ravel(), j.ravel(), k)


@dr.syntax
def shade(scene, cutouts, origin, n, albedo, ldir, lenergy, count):
    """Sum over every light of E_j max(0, N.w_j) V_j, in light order."""
    e = mi.Color3f(0.0)
    j = mi.UInt32(0)
    while j < count:
        d = dr.gather(mi.Vector3f, ldir, j)
        c = dr.dot(n, d)
        if c > 0.0:
            blocked = occluded(scene, cutouts, mi.Ray3f(origin, d))
            if ~blocked:
                e += dr.gather(mi.Color3f, lenergy, j) * c
        j += 1
    return albedo * dr.inv_pi * e


def shadow_origin(mesh, si, ng, hit, meta):
    """envshadow's shadow-ray origin (src/offset.rs): the hit point moved along the geometric
    normal `ng` by its error bound, gamma7 * (|p0| + |p1 - p0| + |p2 - p0|) per axis, projected
    on |ng|."""
    face = mesh.face_indices(si.prim_index, hit)
    p0 = mesh.vertex_position(face.x, hit)
    p1 = mesh.vertex_position(face.y, hit)
    p2 = mesh.vertex_position(face.z, hit)
    err = (dr.abs(p0) + dr.abs(p1 - p0) + dr.abs(p2 - p0)) * meta["shadow_offset_gamma"]
    return si.p + ng * dr.dot(dr.abs(ng), err)


def primary_hits(scene, cutouts, meta, dirs, spp):
    """The samples' primary rays as envshadow casts them: (direction, interaction, hit, geometric
    normal, shading normal), both normals turned to the camera, the shading normal replaced by
    the geometric one where it points away from the visible side or is not finite; through
    cut-outs, with envshadow's coverage thresholds for BLEND surfaces."""
    cam = mi.Point3f(*meta["camera_position"])
    d = mi.Vector3f(dirs[:, 0], dirs[:, 1], dirs[:, 2])
    threshold = mi.Float(sample_thresholds(meta, spp)) if cutouts else None
    si = first_hit(scene, cutouts, mi.Ray3f(cam, d), threshold)
    hit = si.is_valid()
    ng = si.n
    ns = si.sh_frame.n
    flip = dr.dot(ng, d) > 0.0
    ng = dr.select(flip, -ng, ng)
    ns = dr.select(flip, -ns, ns)
    ns = dr.select((dr.dot(ns, ng) <= 0.0) | ~dr.all(dr.isfinite(ns)), ng, ns)
    return d, si, hit, ng, ns


def render(scene, mesh, cutouts, meta, dirs, ldir, lenergy, count, spp):
    """Every sample's radiance, then each pixel's plain mean of its `spp` consecutive samples;
    returns (pixel RGB, whether every sample of the pixel hit the scene)."""
    d, si, hit, ng, ns = primary_hits(scene, cutouts, meta, dirs, spp)
    albedo = mesh.eval_attribute_3("face_albedo", si, hit)
    origin = shadow_origin(mesh, si, ng, hit, meta)
    b = shade(scene, cutouts, origin, ns, albedo, ldir, lenergy, count)
    b = dr.select(hit, b, 0.0)
    if spp > 1:
        # A pixel's samples are consecutive: sum each block, in the same kernels.
        b = dr.block_sum(b, spp) / spp
        hit = dr.block_sum(dr.select(hit, mi.UInt32(1), mi.UInt32(0)), spp) == spp
    dr.eval(b, hit)
    # The LLVM backend runs kernels asynchronously: wait for this one before the clock stops.
    dr.sync_thread()
    return b, hit


SURFACE = ["hit", "r", "g", "b", "metallic", "roughness", "occlusion", "er", "eg", "eb",
           "f0r", "f0g", "f0b", "f90", "lambert", "nx", "ny", "nz", "material"]


def gltf_brdf_cos(n, v, l, base, metallic, roughness, f0, f90, lambert, precise=True):
    """The glTF 2.0 BRDF times n.l, as the specification writes it (f32 here, another
    order of operations than envshadow's kernels). `precise`: GGX's denominator
    (n.h)^2 (a^2 - 1) + 1 written as |n x h|^2 + (n.h)^2 a^2, the same quantity for unit n and
    h, without the cancellation of 1 - (n.h)^2 near a sharp lobe's peak (at roughness 0, a =
    0.001, f32's 1 - (n.h)^2 is off by about 10 % of a^2); else the plain formula."""
    nl = dr.dot(n, l)
    nv = dr.maximum(dr.dot(n, v), 1e-4)
    h = dr.normalize(v + l)
    nh = dr.dot(n, h)
    vh = dr.dot(v, h)
    a = dr.maximum(roughness * roughness, 1e-3)
    a2 = a * a
    if precise:
        ggx = dr.squared_norm(dr.cross(n, h)) + nh * nh * a2
    else:
        ggx = nh * nh * (a2 - 1.0) + 1.0
    d = a2 / (dr.pi * dr.square(ggx))
    vis = 0.5 / (nl * dr.sqrt(nv * nv * (1.0 - a2) + a2) + nv * dr.sqrt(nl * nl * (1.0 - a2) + a2))
    w = dr.power(1.0 - vh, 5.0)
    f0max = dr.maximum(dr.maximum(f0.x, f0.y), f0.z)
    fd = f0 + (f90 - f0) * w
    fd_max = f0max + (f90 - f0max) * w
    dielectric = (1.0 - fd_max) * base * dr.inv_pi + fd * d * vis
    metal = (base + (1.0 - base) * w) * d * vis
    f = dielectric * (1.0 - metallic) + metal * metallic
    f = dr.select(lambert, base * dr.inv_pi, f)
    return f * nl


def gltf_brdf_cos_f64(n, v, l, m):
    """The same BRDF times n.l in float64 (numpy): the truth both f32 evaluations are
    measured against. n, v, l: (..., 3) float64; m: the material columns, broadcast."""
    nl = np.sum(n * l, axis=-1)
    nv = np.maximum(np.sum(n * v, axis=-1), 1e-4)
    h = v + l
    h /= np.linalg.norm(h, axis=-1)[..., None]
    nh = np.sum(n * h, axis=-1)
    vh = np.sum(v * h, axis=-1)
    a = np.maximum(m["roughness"] ** 2, 1e-3)
    a2 = a * a
    d = a2 / (np.pi * (nh * nh * (a2 - 1.0) + 1.0) ** 2)
    vis = 0.5 / (nl * np.sqrt(nv * nv * (1.0 - a2) + a2) + nv * np.sqrt(nl * nl * (1.0 - a2) + a2))
    w = ((1.0 - vh) ** 5)[..., None]
    f0, f90, base = m["f0"], m["f90"][..., None], m["base"]
    f0max = f0.max(axis=-1, keepdims=True)
    fd = f0 + (f90 - f0) * w
    fd_max = f0max + (f90 - f0max) * w
    dv = (d * vis)[..., None]
    dielectric = (1.0 - fd_max) * base / np.pi + fd * dv
    metal = (base + (1.0 - base) * w) * dv
    metallic = m["metallic"][..., None]
    f = dielectric * (1.0 - metallic) + metal * metallic
    f = np.where(m["lambert"][..., None], base / np.pi, f)
    return f * nl[..., None]


@dr.syntax
def shade_materials(scene, cutouts, bsdf, si, origin, n, n_ours, v, m, ldir, lenergy, count,
                    visible):
    """Every light of the set, exactly, at every sample: (glTF BRDF sum, the same with the
    plain f32 formula for D, principled sum). Each light above either normal's horizon (the
    one shaded with, and envshadow's exported `n_ours`) is traced, and its visibility written
    to `visible` (sample-major, `count` a sample) for the float64 check."""
    ctx = mi.BSDFContext()
    e_gltf = mi.Color3f(0.0)
    e_plain = mi.Color3f(0.0)
    e_principled = mi.Color3f(0.0)
    sample = dr.arange(mi.UInt32, dr.width(n))
    j = mi.UInt32(0)
    while j < count:
        d = dr.gather(mi.Vector3f, ldir, j)
        c = dr.dot(n, d)
        if (c > 0.0) | (dr.dot(n_ours, d) > 0.0):
            blocked = occluded(scene, cutouts, mi.Ray3f(origin, d))
            dr.scatter(visible, ~blocked, sample * count + j)
            if (c > 0.0) & ~blocked:
                e = dr.gather(mi.Color3f, lenergy, j)
                e_gltf += e * gltf_brdf_cos(n, v, d, m["base"], m["metallic"], m["roughness"],
                                            m["f0"], m["f90"], m["lambert"])
                e_plain += e * gltf_brdf_cos(n, v, d, m["base"], m["metallic"], m["roughness"],
                                             m["f0"], m["f90"], m["lambert"], precise=False)
                f = bsdf.eval(ctx, si, si.to_local(d))
                f = dr.select(m["lambert"], m["base"] * dr.inv_pi * c, f)
                e_principled += e * f
        j += 1
    return e_gltf, e_plain, e_principled


def render_materials(scene, mesh, cutouts, meta, dirs, surf, material_normal_mapped, ldir,
                     lenergy, count, spp):
    """Every sample shaded with the glTF BRDF (precise and plain f32) and with principled;
    returns per-sample arrays for the float64 check and per-pixel images: a dict with
    'gltf', 'plain', 'principled' (pixel RGB), 'compared' (pixels whose every sample hit the
    same material in both renderers), 'material' (the pixel's), 'mismatched' (pixels hit in
    both whose samples met another material in Mitsuba: cut-outs seen differently),
    'samples' (what the float64 check needs)."""
    d, si, hit, ng, ns = primary_hits(scene, cutouts, meta, dirs, spp)
    col = {k: surf[:, i] for i, k in enumerate(SURFACE)}
    mat = col["material"].astype(np.int64)
    mapped = np.array([material_normal_mapped.get(int(k), False) for k in mat]) & (mat >= 0)
    theirs = mi.Vector3f(col["nx"], col["ny"], col["nz"])
    n = dr.select(mi.Bool(mapped), theirs, ns)
    m = {
        "base": mi.Color3f(col["r"], col["g"], col["b"]),
        "metallic": mi.Float(col["metallic"]),
        "roughness": mi.Float(col["roughness"]),
        "f0": mi.Color3f(col["f0r"], col["f0g"], col["f0b"]),
        "f90": mi.Float(col["f90"]),
        "lambert": mi.Bool(col["lambert"] > 0.5),
    }
    # principled, its parameters per sample: each a bitmap texture with one texel per sample
    # (a row per image row, the row's samples in order), looked up nearest at the sample's
    # own texel through si.uv (a uniform spectrum cannot hold one value per lane).
    h, w = meta["height"], meta["width"]
    row = w * spp

    def per_sample(values):
        data = np.ascontiguousarray(values.reshape(h, row, -1).astype(np.float32))
        return {"type": "bitmap", "bitmap": mi.Bitmap(data), "filter_type": "nearest",
                "wrap_mode": "clamp", "raw": True}

    bsdf = mi.load_dict({
        "type": "principled",
        "base_color": per_sample(np.stack([col["r"], col["g"], col["b"]], axis=1)),
        "metallic": per_sample(col["metallic"][:, None]),
        "roughness": per_sample(col["roughness"][:, None]),
    })
    their_material = mesh.eval_attribute_1("face_material", si, hit)
    index = np.arange(h * row)
    si.uv = mi.Point2f(((index % row) + 0.5) / row, ((index // row) + 0.5) / h)
    si.sh_frame = mi.Frame3f(n)
    si.wi = si.to_local(-d)
    origin = shadow_origin(mesh, si, ng, hit, meta)
    visible = dr.zeros(mi.Bool, h * row * int(count[0]))
    g, gp, p = shade_materials(scene, cutouts, bsdf, si, origin, n, theirs, -d, m, ldir,
                               lenergy, count, visible)
    occ = mi.Float(col["occlusion"])
    emission = mi.Color3f(col["er"], col["eg"], col["eb"])
    g = dr.select(hit, g * occ + emission, 0.0)
    gp = dr.select(hit, gp * occ + emission, 0.0)
    p = dr.select(hit, p * occ + emission, 0.0)
    dr.eval(g, gp, p, n, their_material, visible)
    dr.sync_thread()
    ours_hit = col["hit"] > 0.5
    hit_np = np.array(hit, copy=False)
    same_material = np.array(their_material, copy=False).astype(np.int64) == mat
    both = hit_np & ours_hit

    def pixels(x):
        return np.array(x, copy=False).T.astype(np.float64).reshape(h, w, spp, 3).mean(axis=2)

    pmat = mat.reshape(h, w, spp)
    same = np.all(pmat == pmat[..., :1], axis=2)
    both_px = both.reshape(h, w, spp).all(axis=2)
    agree = same_material.reshape(h, w, spp).all(axis=2)
    samples = {
        "col": col,
        "hit": both & same_material,
        "n_ours": np.stack([col["nx"], col["ny"], col["nz"]], axis=1),
        "n_theirs": np.array(n, copy=False).T.copy(),
        "visible": np.array(visible, copy=False).reshape(h * row, -1),
    }
    return {
        "gltf": pixels(g),
        "plain": pixels(gp),
        "principled": pixels(p),
        "compared": both_px & same & agree,
        "mismatched": both_px & same & ~agree,
        "material": pmat[..., 0],
        "samples": samples,
    }


def float64_reference(samples, dirs, ldir, lenergy, normal, meta, spp, chunk=1024):
    """Every sample's radiance in float64: the glTF BRDF over every light Mitsuba found
    visible, with the sample's material from the export, at the shading normal `normal`
    ('ours': envshadow's exported one; 'theirs': the one Mitsuba shaded with), n, v and each l
    normalised in float64. Returns pixel RGB (the plain mean of the samples)."""
    col = samples["col"]
    nrm = samples["n_" + normal].astype(np.float64)
    with np.errstate(invalid="ignore", divide="ignore"):  # the misses' zero normals
        nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    v = -dirs.astype(np.float64)
    v /= np.linalg.norm(v, axis=1)[:, None]
    l = ldir.astype(np.float64)
    l /= np.linalg.norm(l, axis=1)[:, None]
    e = lenergy.astype(np.float64)
    mat = {
        "base": np.stack([col["r"], col["g"], col["b"]], axis=1).astype(np.float64),
        "metallic": col["metallic"].astype(np.float64),
        "roughness": col["roughness"].astype(np.float64),
        "f0": np.stack([col["f0r"], col["f0g"], col["f0b"]], axis=1).astype(np.float64),
        "f90": col["f90"].astype(np.float64),
        "lambert": col["lambert"] > 0.5,
    }
    out = np.zeros((len(nrm), 3))
    todo = np.nonzero(samples["hit"])[0]
    for start in range(0, len(todo), chunk):
        i = todo[start:start + chunk]
        m = {k: (x[i][:, None, :] if x.ndim == 2 else x[i][:, None]) for k, x in mat.items()}
        f = gltf_brdf_cos_f64(nrm[i][:, None, :], v[i][:, None, :], l[None, :, :], m)
        lit = samples["visible"][i] & (np.sum(nrm[i][:, None, :] * l[None], axis=-1) > 0.0)
        out[i] = np.sum(np.where(lit[..., None], f * e[None], 0.0), axis=1)
    emission = np.stack([col["er"], col["eg"], col["eb"]], axis=1).astype(np.float64)
    out = out * col["occlusion"].astype(np.float64)[:, None] + emission
    out[~samples["hit"]] = 0.0
    h, w = meta["height"], meta["width"]
    return out.reshape(h, w, spp, 3).mean(axis=2)


def rel_rmse(img, ref, sel):
    """Relative RMSE of `img` against `ref` over the pixels `sel`, in percent."""
    d = (img - ref)[sel]
    mean = float(ref[sel].mean())
    return 100 * float(np.sqrt(np.mean(d ** 2))) / mean if mean > 0 else float("nan")


def material_table(images, refs, materials):
    """Relative RMSE per material against both references, with the issue's bounds; then the
    float64 check of both glTF BRDF evaluations."""
    sel_of = {}
    for mat in materials:
        sel = refs["compared"] & (refs["material"] == mat["index"])
        if sel.any():
            sel_of[mat["index"]] = sel
    print(f"\nPer material (pixels whose every sample hits it in both renderers; relative RMSE "
          "= RMSE / the reference's mean there; bound: 2 % at roughness >= 0.3, 5 % below; "
          f"{int(refs['mismatched'].sum())} pixels left out where a sample met another "
          "material in Mitsuba than in envshadow):")
    for name, img in images.items():
        print(f"\n`envshadow {name} --glossy-env=false`:\n")
        print("| material | metallic | roughness | pixels | vs glTF BRDF (Dr.Jit) | vs `principled` |")
        print("|---|---:|---:|---:|---:|---:|")
        for mat in materials:
            sel = sel_of.get(mat["index"])
            if sel is None:
                continue
            bound = 2.0 if mat["roughness"] >= 0.3 else 5.0
            cells = []
            for ref in (refs["gltf"], refs["principled"]):
                rel = rel_rmse(img, ref, sel)
                cells.append(f"{rel:.2f} % {'ok' if rel <= bound else 'OVER'}")
            print(f"| {mat['name']} | {mat['metallic']:.2f} | {mat['roughness']:.2f} | "
                  f"{int(sel.sum())} | {cells[0]} | {cells[1]} |")
    print("\nThe glTF BRDF in float64 (numpy; the lights Mitsuba found visible, each sample's "
          "material from the export, n, v, l normalised in float64) at each side's own shading "
          "normal: envshadow's exported one for envshadow, the one Dr.Jit shaded with for Dr.Jit "
          "(Mitsuba's interpolated normal, or envshadow's where a normal map bent it). Relative "
          "RMSE against it; the last column is the float64 value at Mitsuba's normal against "
          "the one at envshadow's (what the two normals alone make differ):")
    for name, img in images.items():
        print(f"\n`envshadow {name} --glossy-env=false`:\n")
        print("| material | roughness | pixels | envshadow vs f64 | Dr.Jit (precise D) vs f64 "
              "| Dr.Jit (plain f32 D) vs f64 | f64: Mitsuba's normal vs envshadow's |")
        print("|---|---:|---:|---:|---:|---:|---:|")
        for mat in materials:
            sel = sel_of.get(mat["index"])
            if sel is None:
                continue
            ours, theirs = refs["f64_ours"], refs["f64_theirs"]
            print(f"| {mat['name']} | {mat['roughness']:.2f} | {int(sel.sum())} | "
                  f"{rel_rmse(img, ours, sel):.2f} % | {rel_rmse(refs['gltf'], theirs, sel):.2f} % "
                  f"| {rel_rmse(refs['plain'], theirs, sel):.2f} % | "
                  f"{rel_rmse(theirs, ours, sel):.2f} % |")


def envshadow_frame(binary, spec, frame, lights, method, threads, out, sample_flags):
    """Renders one frame with envshadow; returns (the run's wall seconds from
    records/runs.csv -- loading the map and scene, sampling the lights, rendering, writing --,
    the frame's thread-seconds from stats.csv, RGB array). `method` is a method name,
    optionally followed by more render flags ("grid-nowarp-uncertainty --flood-to contrary");
    `sample_flags` are the export's `--spp`, `--filter` and `--filter-width`, so envshadow
    traces the exported samples."""
    name, *flags = method.split()
    subprocess.run(
        [binary, "render", spec, "--frames", str(frame), "--lights", str(lights),
         "--method", name, *flags, *sample_flags, "--threads", str(threads), "--out", out,
         "-q", "--no-report"],
        check=True)
    with open(os.path.join(out, "stats.csv")) as f:
        row = list(csv.DictReader(f))[-1]
    with open(os.path.join(out, "records", "runs.csv")) as f:
        run = list(csv.DictReader(f))[-1]
    if int(run["frames_rendered"]) != 1:
        sys.exit(f"{out}: the run rendered {run['frames_rendered']} frames, not 1")
    # Reading an EXR runs on Dr.Jit's thread pool, which waits forever when it has a single
    # thread (seen with set_thread_count(1)): read with two, then restore the timed count.
    dr.set_thread_count(max(threads, 2))
    bmp = mi.Bitmap(os.path.join(out, f"frame_{frame:04d}.exr"))
    names = [field.name for field in bmp.struct_()]
    data = np.array(bmp)
    dr.set_thread_count(threads)
    rgb = np.stack([data[..., names.index(c)] for c in ("R", "G", "B")], axis=-1)
    return float(run["wall_seconds"]), float(row["thread_seconds"]), rgb.astype(np.float64)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("export")
    ap.add_argument("--binary", default="target/release/envshadow")
    ap.add_argument("--spec", required=True)
    ap.add_argument("--frame", type=int, default=0)
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--methods", default="brute,grid-nowarp-uncertainty",
                    help="comma-separated; each a method name, optionally with render flags")
    ap.add_argument("--work", required=True)
    ap.add_argument("--spp", type=int,
                    help="samples per pixel the export must have (default: frame.json's)")
    ap.add_argument("--filter", help="pixel filter the export must have (default: frame.json's)")
    ap.add_argument("--lambert-only", action="store_true",
                    help="ignore surface.f32: the Lambertian comparison of per-face colours")
    args = ap.parse_args()

    meta = json.load(open(os.path.join(args.export, "frame.json")))
    lights = json.load(open(os.path.join(args.export, "lights.json")))["lights"]
    w, h = meta["width"], meta["height"]
    # The export decides the samples; --spp and --filter only check that it is the one meant.
    spp = int(meta.get("spp", 1))
    filt = meta.get("filter")
    if args.spp is not None and args.spp != spp:
        sys.exit(f"{args.export}: exported at {spp} spp, not --spp {args.spp}; export again")
    if args.filter is not None and filt is not None and args.filter != filt:
        sys.exit(f"{args.export}: exported with filter {filt}, not --filter {args.filter}")
    sample_flags = ["--spp", str(spp)]
    if filt is not None:
        sample_flags += ["--filter", filt, "--filter-width", repr(float(meta["filter_width"]))]
    dirs = np.fromfile(os.path.join(args.export, "primary.f32"), dtype="<f4").reshape(-1, 3)
    if len(dirs) != w * h * spp:
        sys.exit(f"{args.export}: primary.f32 holds {len(dirs)} directions, "
                 f"not {w}x{h}x{spp}")
    ldir_np = np.array([l["direction"] for l in lights], dtype=np.float32)
    le_np = np.array([l["energy"] for l in lights], dtype=np.float32)
    count = len(lights)
    pattern = f" ({filt} filter, width {meta['filter_width']})" if filt and spp > 1 else ""
    print(f"mitsuba {mi.__version__} ({mi.variant()}), drjit {dr.__version__}; "
          f"{meta['triangles']} triangles, {count} lights, {w}x{h}, {spp} spp{pattern}, "
          f"frame {meta['frame']}")

    surface_path = os.path.join(args.export, "surface.f32")
    materials_mode = os.path.exists(surface_path) and not args.lambert_only
    if materials_mode:
        nf = int(meta.get("surface_floats", len(SURFACE)))
        surf = np.fromfile(surface_path, dtype="<f4").reshape(-1, nf)
        materials = json.load(open(os.path.join(args.export, "materials.json")))["materials"]
        normal_mapped = {m["index"]: m["normal_mapped"] for m in materials}
        # The exact sum over the lights, which is what the references evaluate.
        sample_flags = sample_flags + ["--glossy-env=false"]
    else:
        # Still read for the cut-outs (an export from before materials has none).
        path = os.path.join(args.export, "materials.json")
        materials = json.load(open(path))["materials"] if os.path.exists(path) else []

    rows = []
    images = {}
    for threads in [int(t) for t in args.threads.split(",")]:
        dr.set_thread_count(threads)
        for rep in range(args.repeat):
            t0 = time.perf_counter()
            scene, mesh = build_scene(args.export)
            cutouts = Cutouts(args.export, materials, mesh)
            t1 = time.perf_counter()
            ldir = mi.Vector3f(ldir_np[:, 0], ldir_np[:, 1], ldir_np[:, 2])
            lenergy = mi.Color3f(le_np[:, 0], le_np[:, 1], le_np[:, 2])
            if materials_mode:
                refs = render_materials(
                    scene, mesh, cutouts, meta, dirs, surf, normal_mapped, ldir, lenergy,
                    mi.UInt32(count), spp)
                b, hit = mi.Color3f(0.0), mi.Bool(False)
            else:
                b, hit = render(scene, mesh, cutouts, meta, dirs, ldir, lenergy,
                                mi.UInt32(count), spp)
            t2 = time.perf_counter()
            # The first render of a run includes compiling the kernel; later ones reuse it.
            rows.append(("mitsuba", threads, rep, t1 - t0, t2 - t1, None))
            if not materials_mode:
                images["mitsuba"] = (
                    np.array(b, copy=False).T.reshape(h, w, 3).astype(np.float64),
                    np.array(hit, copy=False).reshape(h, w))
            for method in args.methods.split(","):
                out = os.path.join(args.work, f"{'_'.join(method.split())}-t{threads}")
                wall, thread_secs, img = envshadow_frame(
                    args.binary, args.spec, meta["frame"], count, method, threads, out,
                    sample_flags)
                rows.append((method, threads, rep, None, wall, thread_secs))
                images[method] = img

    print("\nSeconds: Mitsuba's scene build and render (waiting for the kernels; the first "
          "render compiles them); envshadow's whole run (records/runs.csv: loading the map and "
          "scene, sampling the lights, rendering, writing the frame) and the frame's "
          "thread-seconds (stats.csv: its compute summed over the threads).")
    print("\n| renderer | threads | s/frame (median) | build s | first render s | frame thread-s | × envshadow default |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    default = "grid-nowarp-uncertainty"
    for threads in sorted({r[1] for r in rows}):
        def med(name):
            v = sorted(r[4] + (r[3] or 0.0) for r in rows if r[0] == name and r[1] == threads)
            return v[len(v) // 2] if v else None
        ours = med(default)
        for name in ["mitsuba"] + args.methods.split(","):
            m = med(name)
            if m is None:
                continue
            build = [r[3] for r in rows if r[0] == name and r[1] == threads and r[3] is not None]
            first = [r[4] for r in rows if r[0] == name and r[1] == threads and r[2] == 0]
            label = "Mitsuba 3 (exact, every light)" if name == "mitsuba" else f"envshadow {name}"
            ratio = f"{m / ours:.2f}" if ours else "–"
            bs = f"{sorted(build)[len(build) // 2]:.3f}" if build else "–"
            fs = f"{first[0]:.3f}" if name == "mitsuba" and first else "–"
            ts = sorted(r[5] for r in rows if r[0] == name and r[1] == threads and r[5] is not None)
            tsm = f"{ts[len(ts) // 2]:.3f}" if ts else "–"
            print(f"| {label} | {threads} | {m:.3f} | {bs} | {fs} | {tsm} | {ratio} |")

    if materials_mode:
        ours = {k: v for k, v in images.items() if k != "mitsuba"}
        for normal in ("ours", "theirs"):
            refs["f64_" + normal] = float64_reference(refs["samples"], dirs, ldir_np, le_np,
                                                      normal, meta, spp)
        material_table(ours, refs, materials)
        for key in ("gltf", "plain", "principled", "f64_ours", "f64_theirs"):
            np.save(os.path.join(args.work, f"mitsuba-{key.replace('_', '-')}.npy"),
                    refs[key].astype(np.float32))
        np.save(os.path.join(args.work, "compared.npy"), refs["compared"])
        np.save(os.path.join(args.work, "material.npy"), refs["material"])
        return
    ref, hit = images["mitsuba"]
    print(f"\nImage difference at {spp} spp, the same sample positions in both (a pixel is the "
          f"plain mean of its samples), over the {int(hit.sum())} pixels whose every sample "
          "hits the scene: where a sample misses, envshadow shows the environment and this "
          "integrator returns 0, so such pixels are left out (relative = divided by "
          "Mitsuba's mean pixel value there):")
    print("\n| image | RMSE | relative RMSE | max abs diff | relative max | pixels differing > 1 % |")
    print("|---|---:|---:|---:|---:|---:|")
    mean = ref[hit].mean()
    for name in args.methods.split(","):
        img = images[name]
        d = (img - ref)[hit]
        rmse = float(np.sqrt(np.mean(d ** 2)))
        mx = float(np.abs(d).max())
        lum = np.maximum(ref[hit].mean(axis=1), 1e-6)
        big = int(np.sum(np.abs(d).mean(axis=1) / lum > 0.01))
        print(f"| envshadow {name} vs Mitsuba | {rmse:.5f} | {100 * rmse / mean:.3f} % | "
              f"{mx:.4f} | {100 * mx / mean:.1f} % | {big} |")
    np.save(os.path.join(args.work, "mitsuba.npy"), ref.astype(np.float32))


if __name__ == "__main__":
    main()
