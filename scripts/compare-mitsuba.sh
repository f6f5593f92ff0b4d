#!/usr/bin/env bash
# compare-mitsuba.sh — render one frame with Mitsuba 3 (LLVM variant, every light evaluated
# exactly at every sample) and with envshadow at the same samples per pixel — the very sample
# positions, exported by envshadow — time both in the same run, compare images.
#
# usage: scripts/compare-mitsuba.sh [SPEC.toml] [--frame F] [--lights N] [--threads 1,2]
#                                   [--repeat R] [--work DIR] [--methods LIST]
#                                   [--spp N] [--filter NAME] [--filter-width PX]
#        scripts/compare-mitsuba.sh --materials [--lights N] [--size WxH] [--threads 2]
#                                   [--repeat R] [--work DIR] [--methods LIST] [--spp N]
#                                   [--scenes NAME,NAME]
# Defaults: anims/bunny-turntable.toml, frame 0, 400 lights, threads 1,2, 3 repeats,
# work folder target/compare-mitsuba, methods brute,grid-nowarp-uncertainty (each entry a
# method name, optionally with render flags: "grid-nowarp-uncertainty --flood-to contrary";
# not --spp or --filter, which come from the export), samples per pixel and filter the spec's
# (its [render] spp, filter, filter_width; 1 sample, the pixel centre, when it sets none).
# Only pixels whose every sample hits the scene are compared (envshadow shows the
# environment where a sample misses; the Mitsuba integrator returns 0 there).
# Glossy materials: the export carries each sample's material (surface.f32), and the python
# script shades every light with Mitsuba's `principled` BSDF and with the glTF BRDF written in
# Dr.Jit, reporting relative RMSE per material, then both glTF BRDF evaluations against the
# same BRDF in float64 (docs/materials.md). Cut-outs (alpha MASK/BLEND) are honoured on the
# Mitsuba side from the export (materials.json's alpha, alpha_T.f32, the PLY's texture
# coordinates) with Dr.Jit's texture lookup, for camera and shadow rays.
# --materials: the corpus scenes made for it (metal_rough_spheres, golf_ball,
# alpha_mask_panels, sheen_chair_scene from ../shared/assets/corpus or $CORPUS), each under the
# studio map from a spec written into the work folder (default framing, --size, default
# 320x240), one after the other (--scenes: only those named). The files' own lights
# (KHR_lights_punctual: the sheen chair has one) are left out on both sides ([lights]
# scene_lights = false): the references sum the map's lights only.
# The virtual environment (target/mitsuba-venv, or $MITSUBA_VENV) is made on first use with
# `pip install mitsuba numpy`. Mitsuba's LLVM variant needs a libLLVM shared library, 16 or
# later: Debian's libllvm19 (installed with apt-get when missing and run as root);
# $DRJIT_LIBLLVM_PATH points Dr.Jit at another one.
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
cd "$ROOT"

SPEC=anims/bunny-turntable.toml
FRAME=0
LIGHTS=400
THREADS=1,2
REPEAT=3
METHODS=brute,grid-nowarp-uncertainty
SAMPLE_FLAGS=()   # --spp/--filter/--filter-width as given: for the export and the check
WORK=target/compare-mitsuba
VENV="${MITSUBA_VENV:-target/mitsuba-venv}"
MATERIALS=0
SIZE=320x240
CORPUS="${CORPUS:-$ROOT/../shared/assets/corpus}"
SCENES="metal_rough_spheres golf_ball alpha_mask_panels sheen_chair_scene"
while [ $# -gt 0 ]; do
  case "$1" in
    --materials) MATERIALS=1; shift ;;
    --size) SIZE="$2"; shift 2 ;;
    --scenes) SCENES="${2//,/ }"; shift 2 ;;
    --frame) FRAME="$2"; shift 2 ;;
    --lights) LIGHTS="$2"; shift 2 ;;
    --threads) THREADS="$2"; shift 2 ;;
    --repeat) REPEAT="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --methods) METHODS="$2"; shift 2 ;;
    --spp|--filter|--filter-width) SAMPLE_FLAGS+=("$1" "$2"); shift 2 ;;
    -h|--help) sed -n '2,34p' "$0"; exit 0 ;;
    -*) echo "compare-mitsuba.sh: unknown option $1" >&2; exit 2 ;;
    *) SPEC="$1"; shift ;;
  esac
done

# Dr.Jit 1.5 emits LLVM intrinsics that libLLVM 15 and older cannot select ("Cannot select:
# fminimum"): the newest libLLVM from 16 on, else Debian's libllvm19 is installed.
newest_llvm() {
  for v in 21 20 19 18 17 16; do
    for f in /usr/lib/*/libLLVM-$v.so /usr/lib/*/libLLVM.so.$v* /usr/lib/llvm-$v/lib/libLLVM*.so*; do
      [ -e "$f" ] && { echo "$f"; return 0; }
    done
  done
  return 1
}
if [ -z "${DRJIT_LIBLLVM_PATH:-}" ] && ! newest_llvm >/dev/null; then
  if [ "$(id -u)" = 0 ]; then
    apt-get install -y -qq libllvm19 >/dev/null
  else
    echo "compare-mitsuba.sh: Mitsuba's LLVM variant needs libLLVM 16 or later: apt-get install libllvm19 (or set DRJIT_LIBLLVM_PATH)" >&2
    exit 2
  fi
fi
if [ -z "${DRJIT_LIBLLVM_PATH:-}" ]; then
  DRJIT_LIBLLVM_PATH="$(newest_llvm)"
  export DRJIT_LIBLLVM_PATH
fi
if [ ! -x "$VENV/bin/python" ]; then
  python3 -m venv "$VENV"
fi
if ! "$VENV/bin/python" -c "import mitsuba, numpy" 2>/dev/null; then
  "$VENV/bin/pip" install -q mitsuba numpy
fi

cargo build --release -q
mkdir -p "$WORK"
# Absolute: the specs written into it name files in it, and a spec's paths are relative to
# the spec's own folder.
WORK="$(cd "$WORK" && pwd)"
echo "libLLVM: $DRJIT_LIBLLVM_PATH"

# The python script reads the samples from the export (frame.json) and renders envshadow with
# them; --spp and --filter given here are checked against it. --filter-width is the export's.
CHECK_FLAGS=()
for ((i = 0; i < ${#SAMPLE_FLAGS[@]}; i += 2)); do
  case "${SAMPLE_FLAGS[i]}" in
    --spp|--filter) CHECK_FLAGS+=("${SAMPLE_FLAGS[i]}" "${SAMPLE_FLAGS[i + 1]}") ;;
  esac
done

# compare SPEC WORK: export frame $FRAME of SPEC into WORK/export, then render and compare.
compare() {
  local spec="$1" work="$2"
  mkdir -p "$work"
  ./target/release/envshadow export "$spec" --frame "$FRAME" --lights "$LIGHTS" \
    ${SAMPLE_FLAGS[@]+"${SAMPLE_FLAGS[@]}"} --out "$work/export"
  "$VENV/bin/python" "$SCRIPT_DIR/compare-mitsuba.py" "$work/export" --spec "$spec" \
    --threads "$THREADS" --repeat "$REPEAT" --work "$work" --methods "$METHODS" \
    ${CHECK_FLAGS[@]+"${CHECK_FLAGS[@]}"}
}

if [ "$MATERIALS" = 0 ]; then
  compare "$SPEC" "$WORK"
  exit 0
fi

W="${SIZE%x*}"; H="${SIZE#*x}"
MAP="$ROOT/../shared/assets/studio_small_03_1k.hdr"
[ -f "$MAP" ] || MAP="$ROOT/assets/studio_small_03_1k.hdr"
for name in $SCENES; do
  glb="$CORPUS/$name.glb"
  [ -f "$glb" ] || { echo "compare-mitsuba.sh: $glb is missing" >&2; exit 2; }
  mkdir -p "$WORK/$name"
  cat > "$WORK/$name/spec.toml" <<EOF
# Written by scripts/compare-mitsuba.sh --materials.
[scene]
file = "$glb"
[environment]
file = "$MAP"
[lights]
count = $LIGHTS
scene_lights = false
[motion]
kind = "none"
frames = 1
[render]
width = $W
height = $H
[output]
dir = "$WORK/$name/out"
EOF
  echo "## $name"
  compare "$WORK/$name/spec.toml" "$WORK/$name"
done
