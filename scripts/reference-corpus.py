"""envshadow's default against the converged reference on the whole corpus, beside a path
tracer's estimator at equal time (issue 42's first acceptance item): for the bunny and every
corpus model, with its materials as authored and all Lambertian, at each samples-per-pixel
count:

- the converged reference of the true environment light (scripts/reference-mitsuba.py's
  estimator, two seeds, cached), and its own noise;
- envshadow's default render (its light count, `envshadow bench`'s seconds per frame: the
  median of --repeat renders, loading excluded) and its relative RMSE against the reference;
- Mitsuba's estimator (the reference's: emitter and BRDF sampling with shadow rays) at equal
  time: as many passes as fit in envshadow's seconds, its seconds per pass calibrated from 4
  and 16 passes after a warm-up call (a call's fixed cost not counted, in Mitsuba's favour;
  at least half the 16-pass call's seconds per pass), and its error there;
- envshadow's error also with both images clamped at --clamp (4), as reference-mitsuba.py's
  --clamp: a mirror's plain error is decided by the one or two pixels that reflect a lamp;
- the passes and seconds Mitsuba needs for envshadow's error: its error measured at doubling
  passes (a new seed each) until it is below envshadow's, interpolated between the last two
  counts (log-log); past --ladder-max passes extrapolated as c / sqrt(passes), which its
  unbiased estimator follows once its rare bright samples are averaged (at a few passes they
  are not, so a fit there overestimates the passes needed). Every error is taken less the
  reference's own noise (in quadrature) when passes are worked out.

    python3 scripts/reference-corpus.py [--scenes bunny,lion_statue,...] [--spp 1,16]
        [--materials authored,lambert] [--size 320x240] [--passes 512] [--ladder-max 1024]
        [--work DIR]

A scene is as scripts/light-count.py takes it (NAME[@MAP], the map studio_small_03_1k unless
named; the files' own lights left out). The reference's passes per seed are --passes at 1 spp
and --passes / spp (at least 16) above: every pixel averages as many estimates at every count.
Needs a python3 with mitsuba and numpy and a built target/release/envshadow (as light-count.py).
"""

import argparse
import importlib.util
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
_spec = importlib.util.spec_from_file_location("light_count",
                                               os.path.join(HERE, "light-count.py"))
lc = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(lc)
rm = lc.rm

CORPUS = ("alpha_mask_panels,golf_ball,lion_statue,metal_rough_spheres,objects_on_circuit_board,"
          "palm_tree,sheen_chair_scene,skull,spot,toy_plane")
LAMBERT = "[material]\nlambert = true\n"


def true_error(err, noise):
    """The error less the reference's own noise, in quadrature (at least half the measured:
    a measured error at the noise's level says little more than that)."""
    return max(np.sqrt(max(err ** 2 - noise ** 2, 0.0)), 0.5 * err)


def mitsuba_error(ex, meta, materials, passes, seed, ref, sel):
    img, _, _, _, secs = rm.reference(ex, meta, materials, passes, seed)
    return rm.cm.rel_rmse(img, ref, sel), secs


def passes_for(err, noise, error_at, n0, e0, most):
    """The passes Mitsuba's estimator needs for the error `err`: its error measured at doubling
    passes from n0 (a new seed each) until it is at most `err`, then interpolated between the
    last two counts as c / sqrt(n) (errors less the reference's noise); past `most` passes,
    extrapolated so from the last count. Returns the passes and whether the error was reached
    by measurement (False: extrapolated)."""
    n, e, seed = n0, e0, 101
    prev = None
    while e > err and n < most:
        prev = (n, e)
        n, seed = min(2 * n, most), seed + 1
        e = error_at(n, seed)
    t, t_err = true_error(e, noise), true_error(err, noise)
    if e > err:
        return max(n, int(np.ceil(n * (t / t_err) ** 2))), False
    if prev is None:
        return n, True
    # err lies between prev's error and this one: on the line through both in log-log.
    (n1, e1), tp = prev, true_error(prev[1], noise)
    if tp <= t:
        return n, True
    slope = np.log(t / tp) / np.log(n / n1)
    return max(n1, min(n, int(np.ceil(n1 * (t_err / tp) ** (1 / slope))))), True


def measure(args, name, materials_mode, spp, assets, method):
    extra = LAMBERT if materials_mode == "lambert" else ""
    work = os.path.join(args.work, materials_mode)
    # light-count.py's scene_spec, with the Lambertian override added after the camera.
    spec, label = lc.scene_spec(name, assets, work, args.width, args.height)
    if extra:
        text = open(spec).read().replace("[motion]", extra + "[motion]", 1)
        open(spec, "w").write(text)
    d = os.path.dirname(spec)
    ex = os.path.join(d, f"export-spp{spp}")
    meta, materials = lc.export(args.binary, spec, 0, spp, ex)
    passes = args.passes if spp == 1 else max(16, args.passes // spp)
    conv = lc.cached_reference(ex, meta, materials, passes, args.seeds,
                               os.path.join(d, f"reference-spp{spp}-P{passes}.npz"))
    ref, sel = conv["reference"], conv["compared"]
    noise = rm.reference_noise(conv["halves"], ref, sel)
    lights = meta["lights"]
    seconds = lc.bench_seconds(args.binary, spec, [lights], spp, method, args.repeat,
                               args.threads)[lights]
    img, _ = rm.render_ours(args.binary, spec, 0, "", os.path.join(d, f"render-spp{spp}"),
                            ["--spp", str(spp)])
    err = rm.cm.rel_rmse(img, ref, sel)
    c = args.clamp
    clamped = rm.cm.rel_rmse(np.minimum(img, c), np.minimum(ref, c), sel)
    # The first call compiles the kernels: it warms up, and the next two time the passes.
    mitsuba_error(ex, meta, materials, 2, 99, ref, sel)
    _, t_few = mitsuba_error(ex, meta, materials, 4, 99, ref, sel)
    _, t_many = mitsuba_error(ex, meta, materials, 16, 99, ref, sel)
    per_pass = max((t_many - t_few) / 12, t_many / 32)
    n0 = max(1, round(seconds / per_pass))
    e0, _ = mitsuba_error(ex, meta, materials, n0, 100, ref, sel)
    n_eq, measured = passes_for(err, noise, lambda n, seed: mitsuba_error(
        ex, meta, materials, n, seed, ref, sel)[0], n0, e0, max(16, args.ladder_max // spp))
    row = {"scene": label, "materials": materials_mode, "spp": spp, "lights": lights,
           "noise": noise, "err": err, "clamped": clamped, "seconds": seconds, "n0": n0, "e0": e0,
           "n_eq": n_eq, "t_eq": n_eq * per_pass, "measured": measured,
           "per_pass": per_pass}
    print(json.dumps(row), file=sys.stderr)
    return row


def report(rows):
    print("| scene | materials | spp | ref. noise | envshadow: error (clamped) / s | "
          "Mitsuba at equal "
          "time: passes / error | Mitsuba for equal error: passes / s | "
          "Mitsuba's time ÷ envshadow's |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        how = "" if r["measured"] else " (extrapolated)"
        print(f"| {r['scene']} | {r['materials']} | {r['spp']} | {r['noise']:.2f} % | "
              f"{r['err']:.2f} % ({r['clamped']:.2f} %) / {r['seconds']:.2f} | {r['n0']} / {r['e0']:.2f} % | "
              f"{r['n_eq']} / {r['t_eq']:.1f}{how} | {r['t_eq'] / r['seconds']:.1f}× |")
    for spp in sorted({r["spp"] for r in rows}):
        for mode in sorted({r["materials"] for r in rows}):
            sub = [r for r in rows if r["spp"] == spp and r["materials"] == mode]
            if not sub:
                continue
            errs = [r["err"] for r in sub]
            ratio = [r["t_eq"] / r["seconds"] for r in sub]
            mits = [r["e0"] for r in sub]
            print(f"\n{spp} spp, {mode}: envshadow's error {min(errs):.2f}–{max(errs):.2f} % "
                  f"(median {np.median(errs):.2f} %); Mitsuba at equal time "
                  f"{min(mits):.1f}–{max(mits):.1f} % (median {np.median(mits):.1f} %); "
                  f"Mitsuba needs {min(ratio):.1f}–{max(ratio):.1f}× envshadow's time for "
                  f"its error (median {np.median(ratio):.1f}×) over {len(sub)} scenes")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", default="bunny," + CORPUS)
    ap.add_argument("--spp", default="1,16")
    ap.add_argument("--materials", default="authored,lambert")
    ap.add_argument("--size", default="320x240")
    ap.add_argument("--passes", type=int, default=512, help="reference passes per seed at 1 spp")
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--repeat", type=int, default=3, help="bench renders of the frame")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--clamp", type=float, default=4.0,
                    help="envshadow's error also with both images clamped at this (a mirror's "
                         "plain error is one or two lamp pixels')")
    ap.add_argument("--ladder-max", type=int, default=1024,
                    help="Mitsuba's error measured up to this many passes at 1 spp (/ spp "
                         "above), extrapolated beyond")
    ap.add_argument("--binary", default=os.path.join(lc.ROOT, "target", "release", "envshadow"))
    ap.add_argument("--work", default=os.path.join(lc.ROOT, "target", "reference-corpus"))
    args = ap.parse_args()
    args.width, args.height = (int(v) for v in args.size.split("x"))
    args.seeds = [int(n) for n in args.seeds.split(",")]
    args.binary = os.path.abspath(args.binary)
    args.work = os.path.abspath(args.work)
    assets = lc.shared_assets()
    method = lc.default_method(args.binary)
    rows = []
    for spp in (int(s) for s in args.spp.split(",")):
        for mode in args.materials.split(","):
            if mode not in ("authored", "lambert"):
                sys.exit(f"reference-corpus.py: --materials takes authored and lambert, not {mode}")
            for name in args.scenes.split(","):
                rows.append(measure(args, name, mode, spp, assets, method))
    print(f"\n{args.width}x{args.height}, the default method ({method}); references "
          f"{args.passes} passes per seed at 1 spp, {args.passes} / spp above, seeds {args.seeds}\n")
    report(rows)
    with open(os.path.join(args.work, "rows.json"), "w") as f:
        json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
