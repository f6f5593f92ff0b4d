#!/usr/bin/env bash
# reference-mitsuba.sh — envshadow's frames against the true environment light: each corpus
# scene (or SPEC) exported, rendered by Mitsuba 3 with an `envmap` emitter over envshadow's own
# texels (scripts/reference-mitsuba.py: direct light by emitter and BRDF sampling, shadow rays,
# two seeds), and envshadow's default and brute-force frames measured against it.
#
# usage: scripts/reference-mitsuba.sh [SPEC.toml] [--scenes NAME,NAME] [--size WxH] [--spp N]
#                                     [--passes P] [--work DIR] [--render NAME=FLAGS]...
#                                     [--clamp C]
# Defaults: the corpus scenes metal_rough_spheres and golf_ball (../shared/assets/corpus or
# $CORPUS) under studio_small_03_1k.hdr, 320x240, 4 spp, the files' own lights left out
# ([lights] scene_lights = false: the reference sees the map only); 512 passes per seed;
# renders `default=` (the spec's settings) and `brute4096=--method brute --lights 4096`; work
# folder target/reference-mitsuba. The venv and libLLVM as scripts/compare-mitsuba.sh makes
# them ($MITSUBA_VENV, $DRJIT_LIBLLVM_PATH).
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
cd "$ROOT"

SPEC=
SCENES="metal_rough_spheres golf_ball"
SIZE=320x240
SPP=4
PASSES=512
WORK=target/reference-mitsuba
VENV="${MITSUBA_VENV:-target/mitsuba-venv}"
CORPUS="${CORPUS:-$ROOT/../shared/assets/corpus}"
RENDERS=()
EXTRA=()
while [ $# -gt 0 ]; do
  case "$1" in
    --scenes) SCENES="${2//,/ }"; shift 2 ;;
    --size) SIZE="$2"; shift 2 ;;
    --spp) SPP="$2"; shift 2 ;;
    --passes) PASSES="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --render) RENDERS+=(--render "$2"); shift 2 ;;
    --clamp) EXTRA+=(--clamp "$2"); shift 2 ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    -*) echo "reference-mitsuba.sh: unknown option $1" >&2; exit 2 ;;
    *) SPEC="$1"; shift ;;
  esac
done
[ ${#RENDERS[@]} -gt 0 ] || RENDERS=(--render "default=" --render "brute4096=--method brute --lights 4096")

if [ -z "${DRJIT_LIBLLVM_PATH:-}" ]; then
  for f in /usr/lib/*/libLLVM-{21,20,19,18,17,16}.so /usr/lib/llvm-{21,20,19,18,17,16}/lib/libLLVM.so; do
    [ -e "$f" ] && { DRJIT_LIBLLVM_PATH="$f"; break; }
  done
fi
if [ -z "${DRJIT_LIBLLVM_PATH:-}" ]; then
  echo "reference-mitsuba.sh: Mitsuba's LLVM variant needs libLLVM 16 or later: apt-get install libllvm19 (or set DRJIT_LIBLLVM_PATH)" >&2
  exit 2
fi
export DRJIT_LIBLLVM_PATH
if [ ! -x "$VENV/bin/python" ]; then
  python3 -m venv "$VENV"
fi
if ! "$VENV/bin/python" -c "import mitsuba, numpy" 2>/dev/null; then
  "$VENV/bin/pip" install -q mitsuba numpy
fi
cargo build --release -q
mkdir -p "$WORK"
WORK="$(cd "$WORK" && pwd)"

# reference SPEC DIR: export frame 0 of SPEC, render the reference, measure envshadow's frames.
reference() {
  local spec="$1" dir="$2"
  ./target/release/envshadow export "$spec" --frame 0 --out "$dir/export" -q
  "$VENV/bin/python" "$SCRIPT_DIR/reference-mitsuba.py" "$dir/export" --spec "$spec" \
    --passes "$PASSES" --work "$dir" "${RENDERS[@]}" ${EXTRA[@]+"${EXTRA[@]}"}
}

if [ -n "$SPEC" ]; then
  reference "$SPEC" "$WORK/spec"
  exit 0
fi
W="${SIZE%x*}"; H="${SIZE#*x}"
MAP="$ROOT/../shared/assets/studio_small_03_1k.hdr"
[ -f "$MAP" ] || MAP="$ROOT/assets/studio_small_03_1k.hdr"
for name in $SCENES; do
  glb="$CORPUS/$name.glb"
  [ -f "$glb" ] || { echo "reference-mitsuba.sh: $glb is missing" >&2; exit 2; }
  mkdir -p "$WORK/$name"
  cat > "$WORK/$name/spec.toml" <<SPEC
# Written by scripts/reference-mitsuba.sh.
[scene]
file = "$glb"
[environment]
file = "$MAP"
[lights]
scene_lights = false
[motion]
kind = "none"
frames = 1
[render]
width = $W
height = $H
spp = $SPP
[output]
dir = "$WORK/$name/out"
SPEC
  echo "## $name"
  reference "$WORK/$name/spec.toml" "$WORK/$name"
done
