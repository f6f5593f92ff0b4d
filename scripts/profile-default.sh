#!/usr/bin/env bash
# profile-default.sh — where the default method's frame goes, by `perf record` (issue 36).
#
# usage: scripts/profile-default.sh [--spp 1,4] [--lights 400] [--size 640x480]
#                                   [--env MAP] [--method NAME] MODEL…
#
# For each model and samples per pixel: one process rendering frame 0 of the model's
# auto-framed turntable three times with the method on one thread (`envshadow bench --no-split
# --repeat 3`), sampled by `perf record -e cpu-clock` (software clock: works where hardware
# counters do not). Prints, per run, the share of samples in each part of the frame:
#   traversal   the shadow-ray kernels (packets, leaves, the single-ray and blocker walks)
#   shading     primary rays, surfaces, materials, textures, the light sum, background
#   prediction  the method's bookkeeping: the driver's passes, voting, the prediction,
#               the correcting queue and flooding, packing rays, bit rows
#   setup       loading, lights, BVH build, the glossy prefilter (built once per run), and
#               everything outside the worker threads
#   other       worker-thread samples in none of the above (memset/memcpy, the kernel)
# then the ten hottest symbols. Needs `perf` (Debian: linux-perf); $ENVSHADOW_BIN measures
# another build.
set -euo pipefail
SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
cd "$ROOT"
SPP=1,4
LIGHTS=400
SIZE=640x480
ENV_MAP=""
METHOD=grid-nowarp-uncertainty
MODELS=()
while [ $# -gt 0 ]; do
  case "$1" in
    --spp) SPP="$2"; shift 2 ;;
    --lights) LIGHTS="$2"; shift 2 ;;
    --size) SIZE="$2"; shift 2 ;;
    --env) ENV_MAP="$2"; shift 2 ;;
    --method) METHOD="$2"; shift 2 ;;
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    -*) echo "profile-default.sh: unknown option $1" >&2; exit 2 ;;
    *) MODELS+=("$1"); shift ;;
  esac
done
[ ${#MODELS[@]} -gt 0 ] || { echo "profile-default.sh: name at least one model" >&2; exit 2; }
command -v perf >/dev/null || { echo "profile-default.sh: perf not found (apt-get install linux-perf)" >&2; exit 2; }
if [ -n "${ENVSHADOW_BIN:-}" ]; then
  BIN="$ENVSHADOW_BIN"
else
  cargo build --release -q
  BIN="$ROOT/target/release/envshadow"
fi
W="${SIZE%x*}"; H="${SIZE#*x}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
ENV_ARGS=()
[ -n "$ENV_MAP" ] && ENV_ARGS=(--env "$ENV_MAP")
for model in "${MODELS[@]}"; do
  for spp in ${SPP//,/ }; do
    perf record -q -e cpu-clock -F 2000 -o "$TMP/perf.data" -- "$BIN" bench --scene "$model" \
      ${ENV_ARGS[@]+"${ENV_ARGS[@]}"} --lights "$LIGHTS" --width "$W" --height "$H" --spp "$spp" \
      --method "$METHOD" --threads 1 --repeat 3 --no-split --quiet > /dev/null 2>&1
    perf report -i "$TMP/perf.data" --no-children --sort comm,sym --stdio 2>/dev/null \
      > "$TMP/report.txt"
    python3 - "$TMP/report.txt" "$(basename "$model") at $spp spp" <<'PY'
import re, sys
path, title = sys.argv[1], sys.argv[2]
parts = {
    "traversal": ["accel::avx2::occluded_packet", "accel::leaf::", "occluded_unrecorded",
                  "blocker_distance", "Accel::occluded"],
    "shading": ["shade::", "radiance", "closest", "intersect", "material", "texture",
                "Texture", "envmap", "EnvMap", "surface", "shading_normal", "brdf", "glossy",
                "catcher", "background", "Scene::", "alpha", "AlphaTest", "above_horizon",
                "floorf", "powf", "expf", "libm::", "film", "Film"],
    "prediction": ["driver::", "predict::", "trace_packet", "trace_all", "buffers::",
                   "bits::", "lattice::", "Lattice", "Blockers", "history", "context::FrameContext::trace"],
}
share = {k: 0.0 for k in ["traversal", "shading", "prediction", "setup", "other"]}
top = []
for line in open(path):
    m = re.match(r"\s+([\d.]+)%\s+(\S+)\s+\[\.\]\s+(.*)", line) or \
        re.match(r"\s+([\d.]+)%\s+(\S+)\s+\[k\]\s+(.*)", line)
    if not m:
        continue
    pct, comm, sym = float(m.group(1)), m.group(2), m.group(3).strip()
    top.append((pct, sym))
    if not comm.startswith("envshadow-work") or "glossy::" in sym or "flatten::" in sym:
        share["setup"] += pct
        continue
    for k, keys in parts.items():
        if any(key in sym for key in keys):
            share[k] += pct
            break
    else:
        share["other"] += pct
print(f"### {title}")
print()
print("| " + " | ".join(share) + " |")
print("|" + "---:|" * len(share))
print("| " + " | ".join(f"{v:.1f} %" for v in share.values()) + " |")
print()
for pct, sym in top[:10]:
    print(f"- {pct:.1f} % `{sym[:110]}`")
print()
PY
  done
done
