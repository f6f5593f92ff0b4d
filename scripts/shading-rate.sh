#!/usr/bin/env bash
# shading-rate.sh — the image cost of shading once per pixel surface (issue 38): every corpus
# model under every shared map, and the bunny, rendered at both shading rates with the same
# flags, the pixel rate's frame compared with the sample rate's.
#
# usage: scripts/shading-rate.sh [--corpus DIR] [--maps A.hdr,B.hdr,…] [--size 640x480]
#                                [--spp 16] [--work DIR] [-- EXTRA RENDER FLAGS…]
#
# Prints a markdown table, a row per model × map: the relative RMSE of the pixel rate's beauty
# against the sample rate's (RMS difference over the mean, as src/film.rs defines it), the
# largest difference, and the 8-bit preview pixels that differ by more than 2/255
# (scripts/compare-images.py, which needs the PyPI packages OpenEXR, numpy and Pillow). The
# prediction is the same at both rates (visibility is decided per sample), so the difference
# is the shading's alone. $ENVSHADOW_BIN measures another build.
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
cd "$ROOT"

ASSETS="${ENVSHADOW_ASSETS:-$ROOT/../shared/assets}"
CORPUS="${CORPUS:-$ASSETS/corpus}"
MAPS="$ASSETS/grace.hdr,$ASSETS/rooitou_park_1k.hdr,$ASSETS/studio_small_03_1k.hdr"
SIZE=640x480
SPP=16
WORK=target/shading-rate
EXTRA=()
while [ $# -gt 0 ]; do
  case "$1" in
    --corpus) CORPUS="$2"; shift 2 ;;
    --maps) MAPS="$2"; shift 2 ;;
    --size) SIZE="$2"; shift 2 ;;
    --spp) SPP="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --) shift; EXTRA=("$@"); break ;;
    -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
    *) echo "shading-rate.sh: unknown option $1" >&2; exit 2 ;;
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

echo "| scene | map | rel. RMSE | max abs. diff. | 8-bit pixels off by > 2/255 |"
echo "|---|---|---:|---:|---:|"
compare() { # name map scene-args…
  local name="$1" map="$2"; shift 2
  for rate in pixel sample; do
    "$BIN" render "$@" --frames 0 --width "$W" --height "$H" --spp "$SPP" \
      --shading-rate "$rate" --out "$WORK/$name/$rate" --quiet ${EXTRA[@]+"${EXTRA[@]}"}
  done
  local p="$WORK/$name/pixel" s="$WORK/$name/sample" line
  line=$(python3 "$SCRIPT_DIR/compare-images.py" "$p/frame_0000.exr" "$s/frame_0000.exr" \
    "$p/frame_0000.png" "$s/frame_0000.png")
  # rel_rmse=… rmse=… max_abs=… ldr_over_2=N of M
  read -r rel _ max over _ of <<<"$(sed 's/[a-z_0-9]*=//g' <<<"$line")"
  echo "| $name | $map | $(printf '%.4f %%' "$(python3 -c "print($rel*100)")") | $max | $over of $of |"
}
shopt -s nullglob
for model in "$CORPUS"/*.glb "$CORPUS"/*.gltf; do
  for map in ${MAPS//,/ }; do
    m=$(basename "$model"); m="${m%.*}"; e=$(basename "$map"); e="${e%.*}"
    compare "$m-$e" "$e" "$model" --env "$map"
  done
done
compare bunny default anims/bunny-turntable.toml
