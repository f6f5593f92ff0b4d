#!/usr/bin/env bash
# terminator-offset.sh — what the shadow-terminator offset changes on models that do not need
# it (issue 40): every corpus model (a model render: the built-in sky, auto-framing) and the
# bunny, rendered with `--terminator-offset=true` and `=false`, the same other flags
# (scripts/compare-flags.sh).
#
# usage: scripts/terminator-offset.sh [compare-flags.sh options: --corpus, --size, --spp,
#                                      --work, -- EXTRA RENDER FLAGS…]
set -euo pipefail
exec "$(dirname "$0")/compare-flags.sh" --a "--terminator-offset=true" \
  --b "--terminator-offset=false" --spp 4 --work target/terminator-offset "$@"
