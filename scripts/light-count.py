"""The default light count by measurement (issue 42, item 4): for each scene, the converged
reference of the true environment light (scripts/reference-mitsuba.py) made once per samples
per pixel, then envshadow's default method at each light count, its relative RMSE against the
reference beside its seconds per frame, and the Monte Carlo efficiency 1 / (error^2 x seconds).

    python3 scripts/light-count.py [--scenes bunny,lion_statue@grace,...] [--counts 50,100,...]
                                   [--spp 1,4] [--size 320x240] [--passes 512] [--work DIR]

Needs a python3 with mitsuba and numpy (scripts/reference-mitsuba.sh makes a venv) and a built
target/release/envshadow. A scene is a corpus model's name (or `bunny`: assets/bunny_on_plane.glb
under anims/bunny-turntable.toml's camera), optionally @MAP, a map's file stem in the shared
assets (studio_small_03_1k, rooitou_park_1k, grace); the files' own lights are left out, so the
reference and envshadow see the map alone. The seconds are `envshadow bench`'s (the median of
--repeat renders of the frame, the scene, BVH and prefiltered map loaded before timing; one
bench run sweeps every count, so the counts are timed side by side); the image is a separate
`envshadow render` of the same frame at the same count (its wall time, loading included, is
shown too). A reference is cached in the work folder (reference-P<passes>.npz) and reused.

The efficiency's error is the measured one less the reference's own noise (in quadrature).
Efficiency is reported per scene relative to its best count (1.00), so scenes weigh alike in
the median over scenes that picks the overall winner.
"""

import argparse
import csv
import importlib.util
import json
import os
import re
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
_spec = importlib.util.spec_from_file_location("reference_mitsuba",
                                               os.path.join(HERE, "reference-mitsuba.py"))
rm = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(rm)

DEFAULT_SCENES = ("bunny,lion_statue,metal_rough_spheres,objects_on_circuit_board@rooitou_park_1k,"
                  "toy_plane@rooitou_park_1k,palm_tree@rooitou_park_1k")
# anims/bunny-turntable.toml's camera: the bunny, not the whole plane, fills the frame.
BUNNY_CAMERA = """[camera]
target = [0.0, 0.075, 0.0]
distance = 0.45
elevation = 25.0
azimuth = 20.0
vfov = 40.0
"""


def shared_assets():
    for d in (os.environ.get("ASSETS", ""), os.path.join(ROOT, "..", "shared", "assets"),
              os.path.join(ROOT, "assets")):
        if d and os.path.isdir(os.path.join(d, "corpus")):
            return os.path.abspath(d)
    sys.exit("light-count.py: no assets folder with corpus/ (set ASSETS)")


def write_spec(path, model, env, width, height, extra="", motion=None):
    """A spec for one still frame (or `motion`, a [motion] table's body) of `model` under the
    map `env`, the file's own lights left out; `extra` adds tables (a camera)."""
    motion = motion or 'kind = "none"\nframes = 1'
    with open(path, "w") as f:
        f.write(f"""# Written by scripts/{os.path.basename(sys.argv[0])}.
[scene]
file = "{model}"
[environment]
file = "{env}"
[lights]
scene_lights = false
{extra}[motion]
{motion}
[render]
width = {width}
height = {height}
[output]
dir = "{os.path.join(os.path.dirname(path), 'out')}"
""")


def scene_spec(name, assets, work, width, height, motion=None):
    """(spec path, label) for a scene argument NAME[@MAP]; `motion` as write_spec's."""
    model_name, _, map_name = name.partition("@")
    map_name = map_name or "studio_small_03_1k"
    env = os.path.join(assets, map_name + ".hdr")
    if model_name == "bunny":
        model, extra = os.path.join(assets, "bunny_on_plane.glb"), BUNNY_CAMERA
    else:
        model, extra = os.path.join(assets, "corpus", model_name + ".glb"), ""
    for f in (model, env):
        if not os.path.isfile(f):
            sys.exit(f"light-count.py: {f} is missing")
    d = os.path.join(work, name.replace("@", "-"))
    os.makedirs(d, exist_ok=True)
    spec = os.path.join(d, "spec.toml")
    write_spec(spec, model, env, width, height, extra, motion)
    return spec, f"{model_name}, {map_name}"


def default_method(binary):
    """The method `envshadow methods` marks as the default."""
    out = subprocess.run([binary, "methods"], check=True, capture_output=True, text=True).stdout
    m = re.search(r"^(\S+) \(default\):", out, re.M)
    if not m:
        sys.exit("light-count.py: `envshadow methods` names no default")
    return m.group(1)


def export(binary, spec, frame, spp, out):
    subprocess.run([binary, "export", spec, "--frame", str(frame), "--spp",
                    str(spp), "--out", out, "-q"], check=True)
    meta = json.load(open(os.path.join(out, "frame.json")))
    materials = json.load(open(os.path.join(out, "materials.json")))["materials"]
    return meta, materials


def cached_reference(export_dir, meta, materials, passes, seeds, cache):
    """rm.converged's reference, halves and compared pixels, from `cache` when there."""
    if os.path.isfile(cache):
        z = np.load(cache)
        return {"reference": z["reference"], "halves": list(z["halves"]),
                "compared": z["compared"], "seconds": list(z["seconds"])}
    _, worst = rm.envmap_emitter(export_dir, meta)
    # A turned map's lookups differ by f32 rounding of the turned directions near the map's
    # sharp edges (1.1e-3 on the studio map turned 2 deg); a wrong convention by 3.7 or more.
    if worst > 1e-2:
        sys.exit(f"{export_dir}: the emitter does not show envshadow's map ({worst:.1e})")
    conv = rm.converged(export_dir, meta, materials, passes, seeds)
    np.savez(cache, reference=conv["reference"], halves=np.stack(conv["halves"]),
             compared=conv["compared"], seconds=np.array(conv["seconds"]))
    return conv


def bench_seconds(binary, spec, counts, spp, method, repeat, threads, frame=0):
    """envshadow bench's seconds per frame for each light count, one run."""
    cmd = [binary, "bench", "--scene", spec, "--lights",
           ",".join(map(str, counts)), "--method", method, "--threads", str(threads), "--spp",
           str(spp), "--repeat", str(repeat), "--frame", str(frame), "--no-split", "--csv", "-q"]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    rows = list(csv.DictReader(out.splitlines()))
    return {int(r["lights"]): float(r["seconds"]) for r in rows}


def efficiency(err, noise, seconds):
    """1 / (error^2 x seconds), the error's square less the reference's own noise's (the
    measured mean square is the true one plus the reference's variance)."""
    true2 = max((err / 100) ** 2 - (noise / 100) ** 2, 0.25 * (err / 100) ** 2)
    return 1.0 / (true2 * seconds)


def measure_scene(args, name, assets, method):
    spec, label = scene_spec(name, assets, args.work, args.width, args.height)
    d = os.path.dirname(spec)
    rows = []
    for spp in args.spp:
        ex = os.path.join(d, f"export-spp{spp}")
        meta, materials = export(args.binary, spec, 0, spp, ex)
        conv = cached_reference(ex, meta, materials, args.passes, args.seeds,
                                os.path.join(d, f"reference-spp{spp}-P{args.passes}.npz"))
        ref, sel = conv["reference"], conv["compared"]
        noise = rm.reference_noise(conv["halves"], ref, sel)
        seconds = bench_seconds(args.binary, spec, args.counts, spp, method, args.repeat,
                                args.threads)
        for n in args.counts:
            out = os.path.join(d, f"render-spp{spp}-n{n}")
            img, wall = rm.render_ours(args.binary, spec, 0, f"--lights {n}", out,
                                       ["--spp", str(spp)])
            err = rm.cm.rel_rmse(img, ref, sel)
            rows.append({"scene": label, "spp": spp, "lights": n, "rel_rmse": err,
                         "noise": noise, "seconds": seconds[n], "render_wall": wall,
                         "efficiency": efficiency(err, noise, seconds[n])})
            print(f"{label}, {spp} spp, {n} lights: {err:.2f} % in {seconds[n]:.3f} s",
                  file=sys.stderr)
    return rows


def report(rows, counts):
    for spp in sorted({r["spp"] for r in rows}):
        sub = [r for r in rows if r["spp"] == spp]
        scenes = list(dict.fromkeys(r["scene"] for r in sub))
        print(f"\n### {spp} spp: relative RMSE against the reference / bench seconds per "
              f"frame / efficiency relative to the scene's best\n")
        print("| scene | ref. noise | " + " | ".join(f"{n} lights" for n in counts)
              + " | best |")
        print("|---|---:|" + "---:|" * len(counts) + "---:|")
        norm = {n: [] for n in counts}
        winners = []
        for s in scenes:
            by = {r["lights"]: r for r in sub if r["scene"] == s}
            best = max(counts, key=lambda n: by[n]["efficiency"])
            winners.append(best)
            cells = []
            for n in counts:
                e = by[n]["efficiency"] / by[best]["efficiency"]
                norm[n].append(e)
                cells.append(f"{by[n]['rel_rmse']:.2f} % / {by[n]['seconds']:.2f} s / {e:.2f}")
            print(f"| {s} | {by[counts[0]]['noise']:.2f} % | " + " | ".join(cells)
                  + f" | {best} |")
        med = {n: float(np.median(norm[n])) for n in counts}
        print("| median efficiency | | " + " | ".join(f"{med[n]:.2f}" for n in counts)
              + f" | {max(counts, key=lambda n: med[n])} |")
        print(f"\n{spp} spp: per-scene winners {winners}, their median "
              f"{float(np.median(winners)):g}; the count with the best median efficiency: "
              f"{max(counts, key=lambda n: med[n])}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", default=DEFAULT_SCENES)
    ap.add_argument("--counts", default="50,100,200,400,800,1600")
    ap.add_argument("--spp", default="1,4")
    ap.add_argument("--size", default="320x240")
    ap.add_argument("--passes", type=int, default=512, help="reference passes per seed")
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--repeat", type=int, default=3, help="bench renders per count")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--binary", default=os.path.join(ROOT, "target", "release", "envshadow"))
    ap.add_argument("--work", default=os.path.join(ROOT, "target", "light-count"))
    args = ap.parse_args()
    args.counts = [int(n) for n in args.counts.split(",")]
    args.spp = [int(n) for n in args.spp.split(",")]
    args.seeds = [int(n) for n in args.seeds.split(",")]
    args.width, args.height = (int(v) for v in args.size.split("x"))
    args.binary = os.path.abspath(args.binary)
    args.work = os.path.abspath(args.work)
    os.makedirs(args.work, exist_ok=True)
    assets = shared_assets()
    method = default_method(args.binary)
    print(f"mitsuba {rm.mi.__version__}; envshadow {args.binary}, method {method}; "
          f"{args.width}x{args.height}; reference {args.passes} passes x seeds {args.seeds}")
    rows = []
    for name in args.scenes.split(","):
        rows += measure_scene(args, name, assets, method)
        with open(os.path.join(args.work, "light-count.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    report(rows, args.counts)


if __name__ == "__main__":
    main()
