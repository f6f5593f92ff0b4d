#!/usr/bin/env bash
# terminator-offset.sh — what the shadow-terminator offset changes on models that do not need
# it (issue 40): every corpus model (a model render: the built-in sky, auto-framing) and the
# bunny, rendered with `--terminator-offset=true` and `=false`, the same other flags.
#
# usage: scripts/terminator-offset.sh [--corpus DIR] [--size 640x480] [--spp 4]
#                                     [--work DIR] [-- EXTRA RENDER FLAGS…]
#
# Prints a markdown table, a row per model: the relative RMSE of the frame with the offset
# against the frame without (RMS difference over the mean, src/film.rs's definition), the
# largest difference, and the 8-bit preview pixels that differ by more than 2/255
# (scripts/compare-images.py: the PyPI packages OpenEXR, numpy and Pillow). $ENVSHADOW_BIN
# measures another build.
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
cd "$ROOT"

ASSETS="${ENVSHADOW_ASSETS:-$ROOT/../shared/assets}"
CORPUS="${CORPUS:-$ASSETS/corpus}"
SIZE=640x480
SPP=4
WORK=target/terminator-offset
EXTRA=()
while [ $# -gt 0 ]; do
  case "$1" in
    --corpus) CORPUS="$2"; shift 2 ;;
    --size) SIZE="$2"; shift 2 ;;
    --spp) SPP="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --) shift; EXTRA=("$@"); break ;;
    -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
    *) echo "terminator-offset.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
if [ -n "${ENVSHADOW_BIN:-}" ]; then
  BIN="$ENVSHADOW_BIN"
else
  cargo build --release -q
  BIN="$ROOT/target/release/envshadow"
fi
W="${SIZE%x*}"; H="${SIZE#*x}"
mkdir -p "$WORK"

echo "| scene | rel. RMSE | max abs. diff. | 8-bit pixels off by > 2/255 |"
echo "|---|---:|---:|---:|"
compare() { # name scene-args…
  local name="$1"; shift
  for offset in true false; do
    "$BIN" render "$@" --frames 0 --width "$W" --height "$H" --spp "$SPP" \
      --terminator-offset="$offset" --out "$WORK/$name/$offset" --quiet \
      ${EXTRA[@]+"${EXTRA[@]}"}
  done
  local a="$WORK/$name/true" b="$WORK/$name/false" line
  line=$(python3 "$SCRIPT_DIR/compare-images.py" "$a/frame_0000.exr" "$b/frame_0000.exr" \
    "$a/frame_0000.png" "$b/frame_0000.png")
  # rel_rmse=… rmse=… max_abs=… ldr_over_2=N of M
  read -r rel _ max over _ of <<<"$(sed 's/[a-z_0-9]*=//g' <<<"$line")"
  echo "| $name | $(printf '%.4f %%' "$(python3 -c "print($rel*100)")") | $max | $over of $of |"
}
shopt -s nullglob
for model in "$CORPUS"/*.glb "$CORPUS"/*.gltf; do
  m=$(basename "$model")
  compare "${m%.*}" "$model"
done
compare bunny anims/bunny-turntable.toml
