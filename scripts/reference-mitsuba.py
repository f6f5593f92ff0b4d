"""The converged reference: an `envshadow export` frame rendered with the true environment
light -- Mitsuba 3's `envmap` emitter over envshadow's own decoded texels, every sample's direct
light integrated by Monte Carlo with shadow rays (the `direct` integrator's estimator:
emitter sampling and BRDF sampling combined by the power heuristic) -- then envshadow's frames
measured against it: relative RMSE over all pixels, the shadowed pixels, and per material,
beside the reference's own noise. Run it through scripts/reference-mitsuba.sh, which makes
the export and the venv.

What is matched, and how it is checked (docs/materials.md, "The converged reference"):
- the map: env.f32 holds envshadow's decoded texels (intensity applied). Mitsuba's envmap
  reads rows at v = j/(H - 1) (the first and last at the poles), envshadow at texel centres,
  v = (j + 1/2)/H; so Mitsuba gets 2H + 1 rows: envshadow's rows at the odd rows, the mean of
  two neighbours (envshadow's bilinear value there) at the even ones, and the first and last
  rows at the poles (envshadow clamps there). Its columns and its direction convention are
  envshadow's (found so, by the check below), and the emitter is turned about +y by the map's
  rotation plus the frame's turn, in envshadow's sense. Then Mitsuba's bilinear lookup is
  envshadow's. Checked at startup: emitter.eval against envshadow's lookup written here in
  numpy, at 20,000 random directions (the largest relative difference is printed, 6e-4 on the
  studio map, f32 rounding; the run stops above 10^-3; a half-column turn gives 3.7, a turn
  the other way 10^6);
- the camera rays: primary.f32, envshadow's own sample directions, from its camera position;
- the geometry, normals, cut-outs and shadow-ray origins: compare-mitsuba.py's (scene.ply;
  Mitsuba's interpolated normal, envshadow's where a normal map bent it; rays through cut-out
  texels; origins moved along the geometric normal by envshadow's error bound);
- the materials: each sample's base colour, metallic, roughness, f0, f90, occlusion and
  emission as envshadow read them (surface.f32), shaded with the glTF BRDF written in Dr.Jit
  (compare-mitsuba.py's gltf_brdf_cos); occlusion scales the environment's light, emission
  adds;
- a pixel is the plain mean of its samples, over the pixels whose every sample hits the same
  material in both renderers.

The estimator, per sample and pass: one direction from the emitter (Mitsuba's
`sample_direction`, the map's luminance importance) and one from the BRDF (GGX half vectors
with probability p, cosine-weighted with 1 - p; p = 1/2 + metallic/2, 0 for Lambertian), each
weighted by the power heuristic against the other's density, each with a shadow ray; pass k
takes point k of a five-dimensional low-discrepancy sequence (Roberts' R5), shifted per
sample by numpy PCG64 random numbers from the seed given (Cranley-Patterson rotation), so a
reference is reproducible and each seed's estimate unbiased and independent of the other's. Two seeds
give two independent halves: their difference estimates the reference's own noise (printed as
the relative RMSE of the mean of both). The unshadowed light (the same estimate with every
shadow ray passing) marks the shadowed pixels: those whose light the shadows lower by more
than --shadowed (default 5 %).
"""

import argparse
import importlib.util
import json
import os
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
_spec = importlib.util.spec_from_file_location("compare_mitsuba",
                                               os.path.join(HERE, "compare-mitsuba.py"))
cm = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(cm)
mi, dr = cm.mi, cm.dr


def our_lookup(tex, rot_deg, d):
    """envshadow's EnvMap::radiance in numpy (float64): the world direction turned into the
    map's frame, lat-long (u, v) = (1/2 - atan2(x, z)/2pi, 1/2 - asin(y)/pi), bilinear between
    texel centres, wrapping in longitude and clamped at the poles."""
    h, w, _ = tex.shape
    s, c = np.sin(np.radians(rot_deg)), np.cos(np.radians(rot_deg))
    # to_map: rotate_y by (-s, c).
    mx = c * d[:, 0] - s * d[:, 2]
    mz = s * d[:, 0] + c * d[:, 2]
    my = d[:, 1]
    u = 0.5 - np.arctan2(mx, mz) / (2 * np.pi)
    v = 0.5 - np.arcsin(np.clip(my, -1, 1)) / np.pi
    fx, fy = u * w - 0.5, v * h - 0.5
    x0, y0 = np.floor(fx), np.floor(fy)
    tx, ty = (fx - x0)[:, None], (fy - y0)[:, None]
    x0 = x0.astype(np.int64)
    y0 = y0.astype(np.int64)
    xa, xb = x0 % w, (x0 + 1) % w
    ya, yb = np.clip(y0, 0, h - 1), np.clip(y0 + 1, 0, h - 1)
    top = tex[ya, xa] * (1 - tx) + tex[ya, xb] * tx
    bottom = tex[yb, xa] * (1 - tx) + tex[yb, xb] * tx
    return top * (1 - ty) + bottom * ty


def envmap_emitter(export, meta):
    """Mitsuba's envmap emitter showing envshadow's map exactly (see the module comment), and
    the largest relative difference of its lookups from envshadow's at random directions."""
    w, h = meta["env_width"], meta["env_height"]
    tex = np.fromfile(os.path.join(export, "env.f32"), dtype="<f4").reshape(h, w, 3)
    rows = np.empty((2 * h + 1, w, 3), np.float32)
    rows[1::2] = tex
    rows[2:-1:2] = 0.5 * (tex[:-1] + tex[1:])
    rows[0], rows[-1] = tex[0], tex[-1]
    rot = float(meta["env_rotation_deg"])
    emitter = mi.load_dict({
        "type": "envmap",
        "bitmap": mi.Bitmap(rows),
        "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], rot),
    })
    rng = np.random.default_rng(7)
    d = rng.normal(size=(20000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    si = dr.zeros(mi.SurfaceInteraction3f, len(d))
    si.wi = mi.Vector3f(-d[:, 0], -d[:, 1], -d[:, 2])
    theirs = np.array(emitter.eval(si), copy=False).T.astype(np.float64)
    ours = our_lookup(tex.astype(np.float64), rot, d)
    rel = np.abs(theirs - ours) / np.maximum(np.abs(ours), 1e-3 * ours.mean())
    return emitter, float(rel.max())


def ggx_pdf(n, v, l, a2):
    """The density of GGX-sampled reflected directions: D(h) (n.h) / 4 (v.h)."""
    h = dr.normalize(v + l)
    nh = dr.maximum(dr.dot(n, h), 0.0)
    ggx = dr.squared_norm(dr.cross(n, h)) + nh * nh * a2
    d = a2 / (dr.pi * dr.square(ggx))
    return d * nh / (4.0 * dr.maximum(dr.dot(v, h), 1e-8))


def bsdf_pdf(n, v, l, a2, p_spec):
    cos = dr.maximum(dr.dot(n, l), 0.0)
    return p_spec * ggx_pdf(n, v, l, a2) + (1.0 - p_spec) * cos * dr.inv_pi


def sample_bsdf(n, v, a2, p_spec, u0, u1, u2):
    """A direction from the glTF lobe's mixture: GGX half vectors (tan^2 = a^2 u/(1 - u)) with
    probability p_spec, else cosine-weighted."""
    frame = mi.Frame3f(n)
    cos_h = dr.sqrt((1.0 - u1) / (1.0 + (a2 - 1.0) * u1))
    sin_h = dr.sqrt(dr.maximum(1.0 - cos_h * cos_h, 0.0))
    phi = dr.two_pi * u2
    h = frame.to_world(mi.Vector3f(sin_h * dr.cos(phi), sin_h * dr.sin(phi), cos_h))
    spec = 2.0 * dr.dot(v, h) * h - v
    diff = frame.to_world(mi.warp.square_to_cosine_hemisphere(mi.Point2f(u1, u2)))
    return dr.normalize(dr.select(u0 < p_spec, spec, diff))


def env_radiance(emitter, d):
    si = dr.zeros(mi.SurfaceInteraction3f, dr.width(d))
    si.wi = -d
    return emitter.eval(si)


def one_pass(scene, cutouts, emitter, it, origin, n, v, m, a2, p_spec, u):
    """One pass of the estimator over every sample: (shadowed, unshadowed) radiance before
    occlusion and emission."""
    # Emitter sampling.
    ds, weight = emitter.sample_direction(it, mi.Point2f(u[0], u[1]))
    f = cm.gltf_brdf_cos(n, v, ds.d, m["base"], m["metallic"], m["roughness"], m["f0"],
                         m["f90"], m["lambert"])
    pb = bsdf_pdf(n, v, ds.d, a2, p_spec)
    ok = (dr.dot(n, ds.d) > 0.0) & (ds.pdf > 0.0)
    w_e = dr.square(ds.pdf) / (dr.square(ds.pdf) + dr.square(pb))
    c_e = dr.select(ok, weight * f * w_e, 0.0)
    blocked_e = cm.occluded(scene, cutouts, mi.Ray3f(origin, ds.d))
    # BRDF sampling.
    l = sample_bsdf(n, v, a2, p_spec, u[2], u[3], u[4])
    pb = bsdf_pdf(n, v, l, a2, p_spec)
    ds2 = dr.zeros(mi.DirectionSample3f, dr.width(l))
    ds2.d = l
    pe = emitter.pdf_direction(it, ds2)
    f = cm.gltf_brdf_cos(n, v, l, m["base"], m["metallic"], m["roughness"], m["f0"], m["f90"],
                         m["lambert"])
    ok = (dr.dot(n, l) > 0.0) & (pb > 0.0)
    w_b = dr.square(pb) / (dr.square(pb) + dr.square(pe))
    c_b = dr.select(ok, env_radiance(emitter, l) * f * w_b / dr.maximum(pb, 1e-30), 0.0)
    blocked_b = cm.occluded(scene, cutouts, mi.Ray3f(origin, l))
    shadowed = dr.select(blocked_e, 0.0, c_e) + dr.select(blocked_b, 0.0, c_b)
    return shadowed, c_e + c_b


def r_sequence(k, shift):
    """Point `k` of Roberts' R5 sequence (a low-discrepancy sequence in five dimensions, the
    generalised golden ratio), randomly shifted per lane by `shift` (5 x lanes, in [0, 1)):
    every lane an unbiased estimator, independent between seeds, converging faster than
    independent random numbers where the integrand is smooth."""
    phi = 1.0
    for _ in range(50):
        phi = (1.0 + phi) ** (1.0 / 6.0)
    g = np.array([phi ** -(i + 1) for i in range(5)])
    point = np.mod(0.5 + g * (k + 1), 1.0)
    out = np.mod(shift + point[:, None], 1.0)
    # float32 of a value just below 1 may round to 1: keep every coordinate in [0, 1).
    return np.minimum(out, 1.0 - 2.0 ** -24)


def reference(export, meta, materials, passes, seed):
    """The reference at `passes` passes with random numbers from `seed`: per sample
    (radiance, unshadowed radiance), float64, with the samples' hit and material masks."""
    spp = int(meta.get("spp", 1))
    w, h = meta["width"], meta["height"]
    dirs = np.fromfile(os.path.join(export, "primary.f32"), dtype="<f4").reshape(-1, 3)
    nf = int(meta.get("surface_floats", len(cm.SURFACE)))
    surf = np.fromfile(os.path.join(export, "surface.f32"), dtype="<f4").reshape(-1, nf)
    scene, mesh = cm.build_scene(export)
    cutouts = cm.Cutouts(export, materials, mesh)
    emitter, _ = envmap_emitter(export, meta)
    d, si, hit, ng, ns = cm.primary_hits(scene, cutouts, meta, dirs, spp)
    col = {k: surf[:, i] for i, k in enumerate(cm.SURFACE)}
    mat = col["material"].astype(np.int64)
    normal_mapped = {m["index"]: m["normal_mapped"] for m in materials}
    mapped = np.array([normal_mapped.get(int(k), False) for k in mat]) & (mat >= 0)
    n = dr.select(mi.Bool(mapped), mi.Vector3f(col["nx"], col["ny"], col["nz"]), ns)
    m = {
        "base": mi.Color3f(col["r"], col["g"], col["b"]),
        "metallic": mi.Float(col["metallic"]),
        "roughness": mi.Float(col["roughness"]),
        "f0": mi.Color3f(col["f0r"], col["f0g"], col["f0b"]),
        "f90": mi.Float(col["f90"]),
        "lambert": mi.Bool(col["lambert"] > 0.5),
    }
    a = dr.maximum(m["roughness"] * m["roughness"], 1e-3)
    a2 = a * a
    p_spec = dr.select(m["lambert"], 0.0, 0.5 + 0.5 * m["metallic"])
    origin = shadow_origin_of(mesh, si, ng, hit, meta)
    it = dr.zeros(mi.Interaction3f, dr.width(d))
    it.p = origin
    v = -d
    their_material = mesh.eval_attribute_1("face_material", si, hit)
    dr.eval(n, origin, their_material, hit)
    lanes = len(dirs)
    shift = np.random.default_rng(seed).random((5, lanes))
    acc = np.zeros((lanes, 3))
    acc_free = np.zeros((lanes, 3))
    t0 = time.perf_counter()
    for k in range(passes):
        u = [mi.Float(x.astype(np.float32)) for x in r_sequence(k, shift)]
        s, free = one_pass(scene, cutouts, emitter, it, origin, n, v, m, a2, p_spec, u)
        dr.eval(s, free)
        acc += np.array(s, copy=False).T
        acc_free += np.array(free, copy=False).T
    seconds = time.perf_counter() - t0
    occ = col["occlusion"][:, None].astype(np.float64)
    emission = np.stack([col["er"], col["eg"], col["eb"]], axis=1).astype(np.float64)
    ours_hit = col["hit"] > 0.5
    both = np.array(hit, copy=False) & ours_hit
    same = np.array(their_material, copy=False).astype(np.int64) == mat
    radiance = np.where(both[:, None], acc / passes * occ + emission, 0.0)
    free = np.where(both[:, None], acc_free / passes * occ + emission, 0.0)

    def pixels(x):
        return x.reshape(h, w, spp, 3).mean(axis=2)

    pmat = mat.reshape(h, w, spp)
    compared = ((both & same).reshape(h, w, spp).all(axis=2)
                & np.all(pmat == pmat[..., :1], axis=2))
    return pixels(radiance), pixels(free), compared, pmat[..., 0], seconds


def converged(export, meta, materials, passes, seeds):
    """The reference as the mean of one `reference` per seed (independent halves): a dict of
    its pixels ("reference", "unshadowed"), the pixels compared ("compared"), each pixel's
    material, each half's pixels ("halves") and each seed's seconds."""
    runs = [reference(export, meta, materials, passes, seed) for seed in seeds]
    return {
        "reference": sum(r[0] for r in runs) / len(runs),
        "unshadowed": sum(r[1] for r in runs) / len(runs),
        "compared": runs[0][2],
        "material": runs[0][3],
        "halves": [r[0] for r in runs],
        "seconds": [r[4] for r in runs],
    }


def reference_noise(halves, ref, sel):
    """The reference's own relative RMSE over `sel`, in percent, from two independent halves
    (the mean's error is about |a - b| / 2); nan with one half."""
    if len(halves) < 2:
        return float("nan")
    d = (halves[0] - halves[1])[sel] / 2.0
    return 100 * float(np.sqrt(np.mean(d ** 2))) / float(ref[sel].mean())


def shadow_origin_of(mesh, si, ng, hit, meta):
    return cm.shadow_origin(mesh, si, ng, hit, meta)


def read_exr(path):
    bmp = mi.Bitmap(path)
    names = [field.name for field in bmp.struct_()]
    data = np.array(bmp)
    return np.stack([data[..., names.index(c)] for c in ("R", "G", "B")],
                    axis=-1).astype(np.float64)


def render_ours(binary, spec, frame, flags, out, sample_flags):
    """One frame by envshadow with `flags` (and the export's samples); its RGB and wall time."""
    t0 = time.perf_counter()
    subprocess.run([binary, "render", spec, "--frames", str(frame), *sample_flags,
                    *flags.split(), "--out", out, "-q", "--no-report"], check=True)
    seconds = time.perf_counter() - t0
    return read_exr(os.path.join(out, f"frame_{frame:04d}.exr")), seconds


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("export")
    ap.add_argument("--binary", default="target/release/envshadow")
    ap.add_argument("--spec", help="the spec the export came from, to render envshadow's frames")
    ap.add_argument("--render", action="append", default=[],
                    help="NAME=FLAGS: an envshadow frame to measure (repeatable), e.g. "
                         "'default=' or 'brute4096=--method brute --lights 4096'")
    ap.add_argument("--image", action="append", default=[],
                    help="NAME=PATH.exr: an envshadow frame already rendered (repeatable)")
    ap.add_argument("--passes", type=int, default=256,
                    help="estimator passes per seed (two directions each)")
    ap.add_argument("--seeds", default="1,2", help="two seeds: two independent halves")
    ap.add_argument("--shadowed", type=float, default=0.05)
    ap.add_argument("--clamp", type=float,
                    help="also the error with every channel of both images clamped at this "
                         "value (a display's white): a mirror's few pixels that reflect a lamp, "
                         "thousands of times brighter than the rest, decide the plain RMSE")
    ap.add_argument("--work", required=True)
    ap.add_argument("--threads", type=int, default=0)
    args = ap.parse_args()
    if args.threads:
        dr.set_thread_count(args.threads)
    os.makedirs(args.work, exist_ok=True)
    meta = json.load(open(os.path.join(args.export, "frame.json")))
    if "env_width" not in meta:
        sys.exit(f"{args.export}: no env.f32 in this export (from an older envshadow); "
                 "export again")
    materials = json.load(open(os.path.join(args.export, "materials.json")))["materials"]
    _, worst = envmap_emitter(args.export, meta)
    print(f"mitsuba {mi.__version__} ({mi.variant()}); {meta['width']}x{meta['height']}, "
          f"{meta.get('spp', 1)} spp; map {meta['env_width']}x{meta['env_height']} "
          f"({meta.get('env_source', '?')}), rotation {meta['env_rotation_deg']} deg")
    print(f"map convention: Mitsuba's envmap against envshadow's lookup at 20000 random "
          f"directions, largest relative difference {worst:.2e}")
    if worst > 1e-3:
        sys.exit("the emitter does not show envshadow's map: the convention check failed")
    seeds = [int(s) for s in args.seeds.split(",")]
    conv = converged(args.export, meta, materials, args.passes, seeds)
    for seed, secs in zip(seeds, conv["seconds"]):
        print(f"seed {seed}: {args.passes} passes in {secs:.1f} s")
    ref, free, compared = conv["reference"], conv["unshadowed"], conv["compared"]
    material, halves = conv["material"], conv["halves"]
    np.save(os.path.join(args.work, "reference.npy"), ref.astype(np.float32))
    np.save(os.path.join(args.work, "unshadowed.npy"), free.astype(np.float32))
    np.save(os.path.join(args.work, "compared.npy"), compared)
    lum = lambda x: x @ np.array([0.2126, 0.7152, 0.0722])
    shadowed = compared & (lum(ref) < (1.0 - args.shadowed) * lum(free))
    sels = [("all", compared), ("shadowed", shadowed)]
    for mat in materials:
        sel = compared & (material == mat["index"])
        if sel.sum() >= 20:
            sels.append((mat["name"], sel))

    def noise(sel):
        return reference_noise(halves, ref, sel)

    images = {}
    sample_flags = ["--spp", str(meta.get("spp", 1))]
    if meta.get("filter") is not None:
        sample_flags += ["--filter", meta["filter"], "--filter-width",
                         repr(float(meta["filter_width"]))]
    for item in args.render:
        name, _, flags = item.partition("=")
        if not args.spec:
            sys.exit("--render needs --spec")
        out = os.path.join(args.work, "envshadow-" + name)
        images[name], secs = render_ours(args.binary, args.spec, meta["frame"], flags, out,
                                         sample_flags)
        print(f"envshadow {name} ({flags or 'defaults'}): {secs:.2f} s wall")
    for item in args.image:
        name, _, path = item.partition("=")
        images[name] = read_exr(path)
    print(f"\nRelative RMSE against the reference (pixels whose every sample hits the same "
          f"material in both renderers; shadowed: the shadows lower the pixel's light by more "
          f"than {100 * args.shadowed:.0f} %):\n")
    names = list(images)
    if args.clamp is not None:
        print(f"Each cell: plain / clamped at {args.clamp:g}.\n")
    print("| pixels | count | reference noise | " + " | ".join(names) + " |")
    print("|---|---:|---:|" + "---:|" * len(names))

    def cell(img, sel):
        plain = f"{cm.rel_rmse(img, ref, sel):.2f} %"
        if args.clamp is None:
            return plain
        c = args.clamp
        return plain + f" / {cm.rel_rmse(np.minimum(img, c), np.minimum(ref, c), sel):.2f} %"

    for label, sel in sels:
        cells = [cell(images[k], sel) for k in names]
        print(f"| {label} | {int(sel.sum())} | {noise(sel):.2f} % | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
