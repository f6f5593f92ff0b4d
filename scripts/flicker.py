"""Flicker (issue 42, item 5): the frame-to-frame noise of an animation, against the converged
reference's own frame-to-frame change. A still camera over a slowly turning map (`[motion]
kind = "environment"`) or a slow orbit; every frame exported and its converged reference made
(scripts/reference-mitsuba.py, cached); envshadow's default render of the frames; Mitsuba's
own estimator (the reference's, emitter and BRDF sampling with shadow rays) at equal time:
as many passes as fit in envshadow's seconds per frame, with a new seed every frame and with
one seed for all frames.

    python3 scripts/flicker.py [--scene bunny@rooitou_park_1k] [--motion environment|orbit]
                               [--frames 8] [--degrees 2] [--spp 1] [--size 320x240]
                               [--passes 512] [--work DIR]

For each pair of frames k, k + 1 and each method, with D = the frame difference,
flicker = RMS(D_method - D_reference) / mean(reference), over the pixels compared in both
frames (every sample on the same material in both renderers): what the method adds to the
true change from one frame to the next. Reported beside the true change RMS(D_reference) /
mean, the reference's own noise in D (from its two seeds' halves), and each method's mean
relative RMSE per frame. envshadow's seconds are `envshadow bench`'s (median of --repeat
renders of frame 0, loading excluded); Mitsuba's are its passes' own (its scene built before
timing), its seconds per pass calibrated on frame 0 from 4 and 16 passes (a call's fixed cost
not counted: Mitsuba gets at least envshadow's time). Needs a python3 with mitsuba and numpy
and a built target/release/envshadow (as scripts/light-count.py).
"""

import argparse
import importlib.util
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
_spec = importlib.util.spec_from_file_location("light_count",
                                               os.path.join(HERE, "light-count.py"))
lc = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(lc)
rm = lc.rm


def frame_difference(a, b, ref_a, ref_b, sel):
    """RMS over `sel` of (b - a) - (ref_b - ref_a), relative to the references' mean, in %."""
    d = ((b - a) - (ref_b - ref_a))[sel]
    mean = float((0.5 * (ref_a + ref_b))[sel].mean())
    return 100 * float(np.sqrt(np.mean(d ** 2))) / mean


def flicker(images, refs, masks):
    """The mean over frame pairs of frame_difference."""
    return float(np.mean([
        frame_difference(images[k], images[k + 1], refs[k], refs[k + 1],
                         masks[k] & masks[k + 1]) for k in range(len(images) - 1)]))


def mitsuba_frames(exports, passes, seeds):
    """Mitsuba's estimator at `passes` passes on every export, seed `seeds[k]` for frame k:
    the pixels and the mean seconds per frame."""
    images, secs = [], []
    for (ex, meta, materials), seed in zip(exports, seeds):
        img, _, _, _, s = rm.reference(ex, meta, materials, passes, seed)
        images.append(img)
        secs.append(s)
    return images, float(np.mean(secs))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default="bunny@rooitou_park_1k")
    ap.add_argument("--motion", choices=["environment", "orbit"], default="environment")
    ap.add_argument("--frames", type=int, default=8)
    ap.add_argument("--degrees", type=float, default=2.0, help="degrees per frame")
    ap.add_argument("--spp", type=int, default=1)
    ap.add_argument("--size", default="320x240")
    ap.add_argument("--passes", type=int, default=512, help="reference passes per seed")
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--repeat", type=int, default=3, help="bench renders of frame 0")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--binary", default=os.path.join(lc.ROOT, "target", "release", "envshadow"))
    ap.add_argument("--work", default=os.path.join(lc.ROOT, "target", "flicker"))
    args = ap.parse_args()
    width, height = (int(v) for v in args.size.split("x"))
    binary = os.path.abspath(args.binary)
    seeds = [int(n) for n in args.seeds.split(",")]
    work = os.path.join(os.path.abspath(args.work), args.motion)
    os.makedirs(work, exist_ok=True)
    motion = (f'kind = "{args.motion}"\nframes = {args.frames}\n'
              f"degrees_per_frame = {args.degrees}")
    spec, label = lc.scene_spec(args.scene, lc.shared_assets(), work, width, height, motion)
    d = os.path.dirname(spec)
    method = lc.default_method(binary)
    exports, refs, halves, masks = [], [], [], []
    for k in range(args.frames):
        ex = os.path.join(d, f"export-{k:04d}")
        meta, materials = lc.export(binary, spec, k, args.spp, ex)
        conv = lc.cached_reference(ex, meta, materials, args.passes, seeds,
                                   os.path.join(d, f"reference-{k:04d}-P{args.passes}.npz"))
        exports.append((ex, meta, materials))
        refs.append(conv["reference"])
        halves.append(conv["halves"])
        masks.append(conv["compared"])
    lights = exports[0][1]["lights"]
    seconds = lc.bench_seconds(binary, spec, [lights], args.spp, method, args.repeat,
                               args.threads)[lights]
    out = os.path.join(d, "envshadow")
    ours = []
    for k in range(args.frames):
        img, _ = rm.render_ours(binary, spec, k, "", out, ["--spp", str(args.spp)])
        ours.append(img)
    # Seconds per pass on frame 0, from two pass counts: a call's fixed cost (tracing and
    # compiling its kernels) is left out of Mitsuba's budget, in its favour.
    _, t_few = mitsuba_frames(exports[:1], 4, [99])
    _, t_many = mitsuba_frames(exports[:1], 16, [99])
    passes = max(1, round(seconds * 12 / max(t_many - t_few, 1e-6)))
    animated, t_animated = mitsuba_frames(exports, passes, [100 + k for k in range(args.frames)])
    fixed, t_fixed = mitsuba_frames(exports, passes, [100] * args.frames)

    def noise(k):
        # The reference's own noise in D: the two halves' D differ by twice the mean's error.
        a, b = halves[k], halves[k + 1]
        return frame_difference(a[0], b[0], a[1], b[1], masks[k] & masks[k + 1]) / 2

    pairs = range(args.frames - 1)
    # The true change: the reference's D against a method that never changes.
    change = np.mean([frame_difference(refs[k], refs[k], refs[k], refs[k + 1],
                                       masks[k] & masks[k + 1]) for k in pairs])
    ref_noise = np.mean([noise(k) for k in pairs])
    print(f"{label}, {args.motion} {args.degrees} deg/frame, {args.frames} frames, "
          f"{width}x{height}, {args.spp} spp; reference {args.passes} passes x {len(seeds)} "
          f"seeds; true change RMS(D_ref)/mean {change:.2f} %, the reference's noise in D "
          f"{ref_noise:.2f} %\n")
    print("| method | seconds per frame | flicker | rel. RMSE per frame |")
    print("|---|---:|---:|---:|")
    for name, imgs, secs in (
            (f"envshadow {method}, {lights} lights", ours, seconds),
            (f"Mitsuba, {passes} passes, new seed per frame", animated, t_animated),
            (f"Mitsuba, {passes} passes, one seed", fixed, t_fixed)):
        err = np.mean([rm.cm.rel_rmse(imgs[k], refs[k], masks[k]) for k in range(args.frames)])
        print(f"| {name} | {secs:.2f} | {flicker(imgs, refs, masks):.2f} % | {err:.2f} % |")


if __name__ == "__main__":
    main()
