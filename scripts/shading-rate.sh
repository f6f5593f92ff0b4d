#!/usr/bin/env bash
# shading-rate.sh — the image cost of shading once per pixel surface (issue 38): every corpus
# model under every shared map, and the bunny, rendered at both shading rates with the same
# flags, the pixel rate's frame compared with the sample rate's (scripts/compare-flags.sh).
# The prediction is the same at both rates (visibility is decided per sample), so the
# difference is the shading's alone.
#
# usage: scripts/shading-rate.sh [compare-flags.sh options: --corpus, --maps, --size, --spp,
#                                 --work, -- EXTRA RENDER FLAGS…]
set -euo pipefail
ASSETS="${ENVSHADOW_ASSETS:-$(dirname "$0")/../../shared/assets}"
exec "$(dirname "$0")/compare-flags.sh" --a "--shading-rate pixel" --b "--shading-rate sample" \
  --maps "$ASSETS/grace.hdr,$ASSETS/rooitou_park_1k.hdr,$ASSETS/studio_small_03_1k.hdr" \
  --spp 16 --work target/shading-rate "$@"
