"""Renders an `envshadow export` frame with Mitsuba 3 (LLVM variant) exactly as envshadow's
`brute` method does, times it against envshadow on the same frame at the same samples per
pixel in the same run, and compares the images. Run through scripts/compare-mitsuba.sh,
which makes the venv and export.

Materials (exports with surface.f32, from envshadow's glTF metallic-roughness materials):
every light at every sample is shaded twice, by Mitsuba 3's own `principled` BSDF
(`bsdf.eval`, its parameters per sample: base colour, metallic, roughness as envshadow's
textures gave them) and by the glTF 2.0 BRDF written here in Dr.Jit from the specification's
formulas (h normalised, D and Vis apart) -- an independent implementation of what envshadow
computes. Mitsuba intersects the primary and shadow rays itself; the shading normal is
Mitsuba's interpolated one, or envshadow's where a normal map bent it. Occlusion scales and
emission adds as in envshadow. envshadow renders with --glossy-env=false, the exact sum over
the lights, which is what both references evaluate. Relative RMSE is reported per material,
over the pixels whose every sample hits that material in both renderers. `principled` is the
Disney model, not glTF's: its diffuse lobe has retro-reflection and no (1 - F) weight, its
Fresnel is the exact dielectric one and its Smith term separable, so it differs from glTF's
BRDF by the models' own difference; the glTF column checks envshadow's implementation.

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
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii").strip()
            header.append(line)
            if line == "end_header":
                break
        nv = int(next(l for l in header if l.startswith("element vertex")).split()[2])
        nf = int(next(l for l in header if l.startswith("element face")).split()[2])
        verts = np.frombuffer(f.read(nv * 24), dtype="<f4").reshape(nv, 6)
        face_t = np.dtype([("n", "u1"), ("i", "<i4", 3), ("rgb", "<f4", 3)])
        faces = np.frombuffer(f.read(nf * face_t.itemsize), dtype=face_t)
    if not np.all(faces["n"] == 3):
        sys.exit(f"{path}: only triangles are expected")
    return verts[:, :3], verts[:, 3:], faces["i"].astype(np.uint32), faces["rgb"]


def build_scene(export):
    p, n, f, rgb = read_ply(os.path.join(export, "scene.ply"))
    mesh = mi.Mesh("scene", len(p), len(f), has_vertex_normals=True)
    mesh.add_attribute("face_albedo", 3, mi.Float(rgb.ravel()))
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(p.ravel())
    params["vertex_normals"] = mi.Float(n.ravel())
    params["faces"] = mi.UInt(f.ravel())
    params.update()
    scene = mi.load_dict({"type": "scene", "mesh": mesh})
    dr.sync_thread()
    return scene, mesh


@dr.syntax
def shade(scene, origin, n, albedo, ldir, lenergy, count):
    """Sum over every light of E_j max(0, N.w_j) V_j, in light order."""
    e = mi.Color3f(0.0)
    j = mi.UInt32(0)
    while j < count:
        d = dr.gather(mi.Vector3f, ldir, j)
        c = dr.dot(n, d)
        if c > 0.0:
            blocked = scene.ray_test(mi.Ray3f(origin, d))
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


def primary_hits(scene, meta, dirs):
    """The samples' primary rays as envshadow casts them: (direction, interaction, hit, geometric
    normal, shading normal), both normals turned to the camera, the shading normal replaced by
    the geometric one where it points away from the visible side or is not finite."""
    cam = mi.Point3f(*meta["camera_position"])
    d = mi.Vector3f(dirs[:, 0], dirs[:, 1], dirs[:, 2])
    si = scene.ray_intersect(mi.Ray3f(cam, d))
    hit = si.is_valid()
    ng = si.n
    ns = si.sh_frame.n
    flip = dr.dot(ng, d) > 0.0
    ng = dr.select(flip, -ng, ng)
    ns = dr.select(flip, -ns, ns)
    ns = dr.select((dr.dot(ns, ng) <= 0.0) | ~dr.all(dr.isfinite(ns)), ng, ns)
    return d, si, hit, ng, ns


def render(scene, mesh, meta, dirs, ldir, lenergy, count, spp):
    """Every sample's radiance, then each pixel's plain mean of its `spp` consecutive samples;
    returns (pixel RGB, whether every sample of the pixel hit the scene)."""
    d, si, hit, ng, ns = primary_hits(scene, meta, dirs)
    albedo = mesh.eval_attribute_3("face_albedo", si, hit)
    origin = shadow_origin(mesh, si, ng, hit, meta)
    b = shade(scene, origin, ns, albedo, ldir, lenergy, count)
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


def gltf_brdf_cos(n, v, l, base, metallic, roughness, f0, f90, lambert):
    """The glTF 2.0 BRDF times n.l, as the specification writes it (f32 here, another
    order of operations than envshadow's kernels)."""
    nl = dr.dot(n, l)
    nv = dr.maximum(dr.dot(n, v), 1e-4)
    h = dr.normalize(v + l)
    nh = dr.dot(n, h)
    vh = dr.dot(v, h)
    a = dr.maximum(roughness * roughness, 1e-3)
    a2 = a * a
    d = a2 / (dr.pi * dr.square(nh * nh * (a2 - 1.0) + 1.0))
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


@dr.syntax
def shade_materials(scene, bsdf, si, origin, n, v, m, ldir, lenergy, count):
    """Every light of the set, exactly, at every sample: (glTF BRDF sum, principled sum)."""
    ctx = mi.BSDFContext()
    e_gltf = mi.Color3f(0.0)
    e_principled = mi.Color3f(0.0)
    j = mi.UInt32(0)
    while j < count:
        d = dr.gather(mi.Vector3f, ldir, j)
        c = dr.dot(n, d)
        if c > 0.0:
            blocked = scene.ray_test(mi.Ray3f(origin, d))
            if ~blocked:
                e = dr.gather(mi.Color3f, lenergy, j)
                e_gltf += e * gltf_brdf_cos(n, v, d, m["base"], m["metallic"], m["roughness"],
                                            m["f0"], m["f90"], m["lambert"])
                f = bsdf.eval(ctx, si, si.to_local(d))
                f = dr.select(m["lambert"], m["base"] * dr.inv_pi * c, f)
                e_principled += e * f
        j += 1
    return e_gltf, e_principled


def render_materials(scene, mesh, meta, dirs, surf, material_normal_mapped, ldir, lenergy, count,
                     spp):
    """Every sample shaded both ways; returns per-pixel (gltf RGB, principled RGB, pixel
    compared, pixel material)."""
    d, si, hit, ng, ns = primary_hits(scene, meta, dirs)
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
    index = np.arange(h * row)
    si.uv = mi.Point2f(((index % row) + 0.5) / row, ((index // row) + 0.5) / h)
    si.sh_frame = mi.Frame3f(n)
    si.wi = si.to_local(-d)
    origin = shadow_origin(mesh, si, ng, hit, meta)
    g, p = shade_materials(scene, bsdf, si, origin, n, -d, m, ldir, lenergy, count)
    occ = mi.Float(col["occlusion"])
    emission = mi.Color3f(col["er"], col["eg"], col["eb"])
    g = dr.select(hit, g * occ + emission, 0.0)
    p = dr.select(hit, p * occ + emission, 0.0)
    dr.eval(g, p)
    dr.sync_thread()
    g = np.array(g, copy=False).T.astype(np.float64)
    p = np.array(p, copy=False).T.astype(np.float64)
    ours_hit = col["hit"] > 0.5
    both = np.array(hit, copy=False) & ours_hit
    h, w = meta["height"], meta["width"]
    g = g.reshape(h, w, spp, 3).mean(axis=2)
    p = p.reshape(h, w, spp, 3).mean(axis=2)
    mat = mat.reshape(h, w, spp)
    same = np.all(mat == mat[..., :1], axis=2)
    compared = both.reshape(h, w, spp).all(axis=2) & same
    return g, p, compared, mat[..., 0]


def material_table(images, default_method, ref_g, ref_p, compared, pixel_material, materials):
    """Relative RMSE per material against both references, with the issue's bounds."""
    print("\nPer material (pixels whose every sample hits it in both renderers; relative RMSE "
          "= RMSE / the reference's mean there; bound: 2 % at roughness >= 0.3, 5 % below):")
    for name, img in images.items():
        print(f"\n`envshadow {name} --glossy-env=false`:\n")
        print("| material | metallic | roughness | pixels | vs glTF BRDF (Dr.Jit) | vs `principled` |")
        print("|---|---:|---:|---:|---:|---:|")
        for mat in materials:
            sel = compared & (pixel_material == mat["index"])
            npx = int(sel.sum())
            if npx == 0:
                continue
            cells = []
            for ref in (ref_g, ref_p):
                d = (img - ref)[sel]
                rmse = float(np.sqrt(np.mean(d ** 2)))
                mean = float(ref[sel].mean())
                rel = 100 * rmse / mean if mean > 0 else float("nan")
                bound = 2.0 if mat["roughness"] >= 0.3 else 5.0
                cells.append(f"{rel:.2f} % {'ok' if rel <= bound else 'OVER'}")
            print(f"| {mat['name']} | {mat['metallic']:.2f} | {mat['roughness']:.2f} | {npx} | "
                  f"{cells[0]} | {cells[1]} |")


def envshadow_frame(binary, spec, frame, lights, method, threads, out, sample_flags):
    """Renders one frame with envshadow; returns (seconds from stats.csv, RGB array).
    `method` is a method name, optionally followed by more render flags
    ("grid-nowarp-uncertainty --flood-to contrary"); `sample_flags` are the export's
    `--spp`, `--filter` and `--filter-width`, so envshadow traces the exported samples."""
    name, *flags = method.split()
    subprocess.run(
        [binary, "render", spec, "--frames", str(frame), "--lights", str(lights),
         "--method", name, *flags, *sample_flags, "--threads", str(threads), "--out", out,
         "-q", "--no-report"],
        check=True)
    with open(os.path.join(out, "stats.csv")) as f:
        row = list(csv.DictReader(f))[-1]
    # Reading an EXR runs on Dr.Jit's thread pool, which waits forever when it has a single
    # thread (seen with set_thread_count(1)): read with two, then restore the timed count.
    dr.set_thread_count(max(threads, 2))
    bmp = mi.Bitmap(os.path.join(out, f"frame_{frame:04d}.exr"))
    names = [field.name for field in bmp.struct_()]
    data = np.array(bmp)
    dr.set_thread_count(threads)
    rgb = np.stack([data[..., names.index(c)] for c in ("R", "G", "B")], axis=-1)
    return float(row["seconds"]), rgb.astype(np.float64)


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

    rows = []
    images = {}
    for threads in [int(t) for t in args.threads.split(",")]:
        dr.set_thread_count(threads)
        for rep in range(args.repeat):
            t0 = time.perf_counter()
            scene, mesh = build_scene(args.export)
            t1 = time.perf_counter()
            ldir = mi.Vector3f(ldir_np[:, 0], ldir_np[:, 1], ldir_np[:, 2])
            lenergy = mi.Color3f(le_np[:, 0], le_np[:, 1], le_np[:, 2])
            if materials_mode:
                ref_g, ref_p, compared, pixel_material = render_materials(
                    scene, mesh, meta, dirs, surf, normal_mapped, ldir, lenergy, mi.UInt32(count),
                    spp)
                b, hit = mi.Color3f(0.0), mi.Bool(False)
            else:
                b, hit = render(scene, mesh, meta, dirs, ldir, lenergy, mi.UInt32(count), spp)
            t2 = time.perf_counter()
            # The first render of a run includes compiling the kernel; later ones reuse it.
            rows.append(("mitsuba", threads, rep, t1 - t0, t2 - t1))
            if not materials_mode:
                images["mitsuba"] = (
                    np.array(b, copy=False).T.reshape(h, w, 3).astype(np.float64),
                    np.array(hit, copy=False).reshape(h, w))
            for method in args.methods.split(","):
                out = os.path.join(args.work, f"{'_'.join(method.split())}-t{threads}")
                secs, img = envshadow_frame(args.binary, args.spec, meta["frame"], count,
                                            method, threads, out, sample_flags)
                rows.append((method, threads, rep, None, secs))
                images[method] = img

    print("\n| renderer | threads | s/frame (median) | build s | first render s | × envshadow default |")
    print("|---|---:|---:|---:|---:|---:|")
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
            print(f"| {label} | {threads} | {m:.3f} | {bs} | {fs} | {ratio} |")

    if materials_mode:
        ours = {k: v for k, v in images.items() if k != "mitsuba"}
        material_table(ours, "grid-nowarp-uncertainty", ref_g, ref_p, compared, pixel_material,
                       materials)
        np.save(os.path.join(args.work, "mitsuba-gltf.npy"), ref_g.astype(np.float32))
        np.save(os.path.join(args.work, "mitsuba-principled.npy"), ref_p.astype(np.float32))
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
