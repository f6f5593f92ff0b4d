#!/usr/bin/env bash
# compare-flags.sh — what a setting changes in the image: every corpus model (a model render:
# auto-framing; under each map given, else the built-in sky) and the bunny, each rendered twice
# with the same flags but for A and B, B's frame compared with A's.
#
# usage: scripts/compare-flags.sh --a "FLAGS" --b "FLAGS" [--corpus DIR] [--maps A.hdr,B.hdr,…]
#                                 [--size 640x480] [--spp 4] [--work DIR] [-- EXTRA FLAGS…]
#
# Prints a markdown table, a row per model (× map): the relative RMSE of A's beauty against B's
# (RMS difference over B's mean, src/film.rs's definition), the largest difference, and the
# 8-bit preview pixels that differ by more than 2/255 (scripts/compare-images.py, which needs
# the PyPI packages OpenEXR, numpy and Pillow). $ENVSHADOW_BIN measures another build.
# scripts/shading-rate.sh and scripts/terminator-offset.sh are this script with their flags.
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
cd "$ROOT"

ASSETS="${ENVSHADOW_ASSETS:-$ROOT/../shared/assets}"
CORPUS="${CORPUS:-$ASSETS/corpus}"
MAPS=""
SIZE=640x480
SPP=4
WORK=target/compare-flags
A=""; B=""
EXTRA=()
while [ $# -gt 0 ]; do
  case "$1" in
    --a) A="$2"; shift 2 ;;
    --b) B="$2"; shift 2 ;;
    --corpus) CORPUS="$2"; shift 2 ;;
    --maps) MAPS="$2"; shift 2 ;;
    --size) SIZE="$2"; shift 2 ;;
    --spp) SPP="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --) shift; EXTRA=("$@"); break ;;
    -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
    *) echo "compare-flags.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
if [ -z "$A" ] || [ -z "$B" ]; then
  echo "compare-flags.sh: give both --a FLAGS and --b FLAGS" >&2; exit 2
fi
read -r -a A_FLAGS <<<"$A"
read -r -a B_FLAGS <<<"$B"
if [ -n "${ENVSHADOW_BIN:-}" ]; then
  BIN="$ENVSHADOW_BIN"
else
  cargo build --release -q
  BIN="$ROOT/target/release/envshadow"
fi
W="${SIZE%x*}"; H="${SIZE#*x}"
mkdir -p "$WORK"

if [ -n "$MAPS" ]; then
  echo "| scene | map | rel. RMSE | max abs. diff. | 8-bit pixels off by > 2/255 |"
  echo "|---|---|---:|---:|---:|"
else
  echo "| scene | rel. RMSE | max abs. diff. | 8-bit pixels off by > 2/255 |"
  echo "|---|---:|---:|---:|"
fi
compare() { # name map-column scene-args…
  local name="$1" column="$2"; shift 2
  local a="$WORK/$name/a" b="$WORK/$name/b" line
  "$BIN" render "$@" --frames 0 --width "$W" --height "$H" --spp "$SPP" "${A_FLAGS[@]}" \
    --out "$a" --quiet ${EXTRA[@]+"${EXTRA[@]}"}
  "$BIN" render "$@" --frames 0 --width "$W" --height "$H" --spp "$SPP" "${B_FLAGS[@]}" \
    --out "$b" --quiet ${EXTRA[@]+"${EXTRA[@]}"}
  line=$(python3 "$SCRIPT_DIR/compare-images.py" "$a/frame_0000.exr" "$b/frame_0000.exr" \
    "$a/frame_0000.png" "$b/frame_0000.png")
  # rel_rmse=… rmse=… max_abs=… ldr_over_2=N of M
  read -r rel _ max over _ of <<<"$(sed 's/[a-z_0-9]*=//g' <<<"$line")"
  echo "| $name |$column $(printf '%.4f %%' "$(python3 -c "print($rel*100)")") | $max | $over of $of |"
}
shopt -s nullglob
for model in "$CORPUS"/*.glb "$CORPUS"/*.gltf; do
  m=$(basename "$model"); m="${m%.*}"
  if [ -n "$MAPS" ]; then
    for map in ${MAPS//,/ }; do
      e=$(basename "$map"); e="${e%.*}"
      compare "$m-$e" " $e |" "$model" --env "$map"
    done
  else
    compare "$m" "" "$model"
  fi
done
if [ -n "$MAPS" ]; then
  compare bunny " default |" anims/bunny-turntable.toml
else
  compare bunny "" anims/bunny-turntable.toml
fi
