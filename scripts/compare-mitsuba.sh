#!/usr/bin/env bash
# compare-mitsuba.sh — render one frame with Mitsuba 3 (LLVM variant, every light evaluated
# exactly at every sample) and with envshadow at the same samples per pixel — the very sample
# positions, exported by envshadow — time both in the same run, compare images.
#
# usage: scripts/compare-mitsuba.sh [SPEC.toml] [--frame F] [--lights N] [--threads 1,2]
#                                   [--repeat R] [--work DIR] [--methods LIST]
#                                   [--spp N] [--filter NAME] [--filter-width PX]
# Defaults: anims/bunny-turntable.toml, frame 0, 400 lights, threads 1,2, 3 repeats,
# work folder target/compare-mitsuba, methods brute,grid-nowarp-uncertainty (each entry a
# method name, optionally with render flags: "grid-nowarp-uncertainty --flood-to contrary";
# not --spp or --filter, which come from the export), samples per pixel and filter the spec's
# (its [render] spp, filter, filter_width; 1 sample, the pixel centre, when it sets none).
# Only pixels whose every sample hits the scene are compared (envshadow shows the
# environment where a sample misses; the Mitsuba integrator returns 0 there).
# The virtual environment (target/mitsuba-venv, or $MITSUBA_VENV) is made on first use with
# `pip install mitsuba numpy`. Mitsuba's LLVM variant needs a libLLVM shared library: Debian's
# libllvm19 (installed with apt-get when missing and run as root); $DRJIT_LIBLLVM_PATH points
# Dr.Jit at another one.
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
while [ $# -gt 0 ]; do
  case "$1" in
    --frame) FRAME="$2"; shift 2 ;;
    --lights) LIGHTS="$2"; shift 2 ;;
    --threads) THREADS="$2"; shift 2 ;;
    --repeat) REPEAT="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --methods) METHODS="$2"; shift 2 ;;
    --spp|--filter|--filter-width) SAMPLE_FLAGS+=("$1" "$2"); shift 2 ;;
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    -*) echo "compare-mitsuba.sh: unknown option $1" >&2; exit 2 ;;
    *) SPEC="$1"; shift ;;
  esac
done

if [ -z "${DRJIT_LIBLLVM_PATH:-}" ] && ! ls /usr/lib/*/libLLVM*.so* >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ]; then
    apt-get install -y -qq libllvm19 >/dev/null
  else
    echo "compare-mitsuba.sh: Mitsuba's LLVM variant needs libLLVM: apt-get install libllvm19 (or set DRJIT_LIBLLVM_PATH)" >&2
    exit 2
  fi
fi
if [ -z "${DRJIT_LIBLLVM_PATH:-}" ]; then
  DRJIT_LIBLLVM_PATH="$(ls /usr/lib/*/libLLVM*.so* 2>/dev/null | sort -V | tail -1)"
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
./target/release/envshadow export "$SPEC" --frame "$FRAME" --lights "$LIGHTS" \
  ${SAMPLE_FLAGS[@]+"${SAMPLE_FLAGS[@]}"} --out "$WORK/export"
# The python script reads the samples from the export (frame.json) and renders envshadow with
# them; --spp and --filter given here are checked against it. --filter-width is the export's.
CHECK_FLAGS=()
for ((i = 0; i < ${#SAMPLE_FLAGS[@]}; i += 2)); do
  case "${SAMPLE_FLAGS[i]}" in
    --spp|--filter) CHECK_FLAGS+=("${SAMPLE_FLAGS[i]}" "${SAMPLE_FLAGS[i + 1]}") ;;
  esac
done
echo "libLLVM: $DRJIT_LIBLLVM_PATH"
"$VENV/bin/python" "$SCRIPT_DIR/compare-mitsuba.py" "$WORK/export" --spec "$SPEC" \
  --threads "$THREADS" --repeat "$REPEAT" --work "$WORK" --methods "$METHODS" \
  ${CHECK_FLAGS[@]+"${CHECK_FLAGS[@]}"}
