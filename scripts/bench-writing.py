#!/usr/bin/env python3
"""bench-writing.py -- does a multi-frame render's wall time follow its thread-seconds divided
by the threads (issue 38, item 3: frames written off the critical path)?

usage: scripts/bench-writing.py [--frames 0-95] [--threads 2] [--repeat 1]
                                [--before BIN] [--after BIN] [--amdahl] [--cores 16]

Renders the default animation (anims/shapes-turntable.toml; --frames limits it) with each
binary in turn, in one run (before, after, before, after, ... with --repeat), each into a fresh
folder with -v, and prints per render:
  wall       the render's own seconds (its summary line: loading, rendering, writing)
  thread-s   its frames' thread-seconds (stats.csv's thread_seconds, summed)
  ideal      thread-s / threads
  ratio      wall / ideal (the acceptance: at most 1.15 on 2 threads)
  report     the report's seconds (made after the render)
  cpu        the process's user + system CPU seconds, all threads (writing included)
  cpu-ratio  the process's seconds (report included) / (cpu / threads): how busy the threads
             were
and, for a binary that prints them (-v), its writing summary: the frames' writing seconds
summed, the share of them while frames rendered, and the writing left after the last frame
rendered.

--amdahl also renders with --after pinned to one core (taskset -c 0, --threads 1) and to two
(taskset -c 0,1, --threads 2) and prints the experimentally determined serial fraction
(Karp-Flatt: e = 2 T2 / T1 - 1 on two cores), the serial seconds per frame it implies
(e T1 / frames), and the Amdahl projection to --cores cores: T = T1 (e + (1 - e) / cores).

--before defaults to $ENVSHADOW_BEFORE, --after to $ENVSHADOW_BIN or this checkout's release
build (built first). Timings depend on the machine and on what else runs on it: name both.
"""

import argparse
import os
import re
import resource
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SPEC = os.path.join(ROOT, "anims", "shapes-turntable.toml")

SUMMARY = re.compile(
    r"(\d+) frames rendered, (\d+) skipped in ([\d.]+) s \(([\d.]+) thread-s on (\d+) threads\)"
)
REPORT = re.compile(r"^report: .* \(([\d.]+) s\)$", re.M)
WRITING = re.compile(
    r"writing: (\d+) frames in ([\d.]+) s summed \(([\d.]+) s each\), (\d+) % of it while "
    r"frames rendered; the last frame written ([\d.]+) s after the last frame rendered"
)


def render(binary, frames, threads, out, pin=None):
    """One render with -v into `out`: what its output says, and its process's CPU seconds."""
    cmd = [binary, "render", SPEC, "--threads", str(threads), "--out", out, "-v"]
    if frames:
        cmd += ["--frames", frames]
    if pin:
        cmd = ["taskset", "-c", pin] + cmd
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True)
    elapsed = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    text = p.stdout + p.stderr
    if p.returncode != 0:
        sys.exit(f"bench-writing.py: {' '.join(cmd)} failed:\n{text[-2000:]}")
    m = SUMMARY.search(text)
    if not m:
        sys.exit(f"bench-writing.py: no summary line from {binary}:\n{text[-2000:]}")
    r = {
        "frames": int(m.group(1)),
        "wall": float(m.group(3)),
        "thread_s": float(m.group(4)),
        "threads": int(m.group(5)),
        "process": elapsed,
        "cpu": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime),
    }
    rep = REPORT.search(text)
    r["report"] = float(rep.group(1)) if rep else float("nan")
    w = WRITING.search(text)
    if w:
        r["writing"] = (float(w.group(2)), float(w.group(3)), int(w.group(4)), float(w.group(5)))
    return r


def row(label, r):
    ideal = r["thread_s"] / r["threads"]
    busy = r["cpu"] / r["threads"]
    line = (
        f"{label:<8} {r['frames']:>6} {r['threads']:>7} {r['wall']:>7.1f} {r['thread_s']:>8.1f} "
        f"{ideal:>6.1f} {r['wall'] / ideal:>6.3f} {r['report']:>7.1f} {r['cpu']:>6.1f} "
        f"{r['process'] / busy:>9.3f}"
    )
    if "writing" in r:
        summed, each, share, tail = r["writing"]
        line += f"   writing {summed:.1f} s summed ({each:.3f} s/frame), {share} % beside rendering, tail {tail:.3f} s"
    return line


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--frames", default="")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--before", default=os.environ.get("ENVSHADOW_BEFORE"))
    ap.add_argument("--after", default=os.environ.get("ENVSHADOW_BIN"))
    ap.add_argument("--amdahl", action="store_true")
    ap.add_argument("--cores", type=int, default=16)
    a = ap.parse_args()
    if not a.after:
        subprocess.run(["cargo", "build", "--release", "-q"], cwd=ROOT, check=True)
        a.after = os.path.join(ROOT, "target", "release", "envshadow")
    bins = [("after", a.after)]
    if a.before:
        bins.insert(0, ("before", a.before))
    print(f"machine: {os.cpu_count()} cores; load average {os.getloadavg()[0]:.2f} at the start")
    print(
        f"{'binary':<8} {'frames':>6} {'threads':>7} {'wall':>7} {'thread-s':>8} {'ideal':>6} "
        f"{'ratio':>6} {'report':>7} {'cpu':>6} {'cpu-ratio':>9}"
    )
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(a.repeat):
            for label, binary in bins:
                out = os.path.join(tmp, f"{label}-{k}")
                print(row(label, render(binary, a.frames, a.threads, out)), flush=True)
        if a.amdahl:
            one = render(a.after, a.frames, 1, os.path.join(tmp, "one"), pin="0")
            two = render(a.after, a.frames, 2, os.path.join(tmp, "two"), pin="0,1")
            print(row("1 core", one), flush=True)
            print(row("2 cores", two), flush=True)
            t1, t2 = one["wall"], two["wall"]
            e = max(0.0, min(1.0, 2 * t2 / t1 - 1))
            n = a.cores
            projected = t1 * (e + (1 - e) / n)
            print(
                f"Amdahl: T1 {t1:.1f} s, T2 {t2:.1f} s (speed-up {t1 / t2:.2f}); serial fraction "
                f"e = 2 T2/T1 - 1 = {e:.4f}, {e * t1 / one['frames']:.4f} serial s per frame of "
                f"{t1 / one['frames']:.3f} s; on {n} cores T = {projected:.1f} s, "
                f"{t2 / projected:.2f}x the 2-core time"
            )


if __name__ == "__main__":
    main()
