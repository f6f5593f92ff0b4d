#!/usr/bin/env bash
# environment-savings.sh — how much of the spatial method's tracing --temporal keeps while the
# environment turns around a still model (`[motion] kind = "environment"`): the bunny
# (anims/bunny-environment.toml) and every model of the corpus, each rendered with --temporal
# --validate and again without --temporal, the same frames.
#
# Usage: scripts/environment-savings.sh OUT [render flags…]
#   e.g. scripts/environment-savings.sh out/envturn --frames 0..8
# Environment: ENVSHADOW (the binary; default target/release/envshadow), CORPUS (default
# ../shared/assets/corpus), MAP (the HDR map for the corpus, default the bunny spec's
# rooitou_park_1k.hdr beside the corpus). The corpus specs (OUT/specs/) frame each model with
# the default camera, 200 lights, 640×480, 3° per frame. Extra flags go to every render.
# Prints one row per model: frames predicted from their predecessor, % of their queries traced
# without and with --temporal, the ratio (the share of the spatial rays traced), the same ratio
# over all frames (key frames included), the wrong pairs % of the first (spatial) key frame and
# the largest over the predicted frames. A model the renderer refuses is noted and skipped.
# Renders already in OUT are reused (delete OUT to measure again).
set -euo pipefail
if [[ $# -lt 1 ]]; then
    sed -n '2,18p' "$0" >&2
    exit 2
fi
OUT="$1"; shift
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="${ENVSHADOW:-$ROOT/target/release/envshadow}"
CORPUS="${CORPUS:-$ROOT/../shared/assets/corpus}"
MAP="${MAP:-$CORPUS/../rooitou_park_1k.hdr}"
[[ -x "$BIN" ]] || { echo "environment-savings: $BIN not found (cargo build --release, or set ENVSHADOW)" >&2; exit 1; }
[[ -d "$CORPUS" ]] || { echo "environment-savings: no corpus at $CORPUS (set CORPUS)" >&2; exit 1; }
mkdir -p "$OUT/specs"
specs=("$ROOT/anims/bunny-environment.toml")
for glb in "$CORPUS"/*.glb; do
    name="$(basename "$glb" .glb)"
    cat > "$OUT/specs/$name.toml" <<EOF
name = "$name-environment"
[scene]
file = "$(realpath "$glb")"
[environment]
file = "$(realpath "$MAP")"
[lights]
count = 200
[motion]
kind = "environment"
frames = 120
degrees_per_frame = 3.0
[render]
width = 640
height = 480
[output]
dir = "$OUT/$name"
EOF
    specs+=("$OUT/specs/$name.toml")
done
printf '%-28s %6s %10s %10s %8s %9s %8s %8s\n' model frames spatial% temporal% share share_all key_err% max_err%
for spec in "${specs[@]}"; do
    name="$(basename "$spec" .toml)"
    if [[ ! -f "$OUT/$name/stats.csv" || ! -f "$OUT/$name-spatial/stats.csv" ]]; then
        if ! "$BIN" render "$spec" --out "$OUT/$name" --temporal --validate --no-report -q "$@" 2> "$OUT/$name.err"; then
            echo "$name: refused ($(head -c 200 "$OUT/$name.err")), skipped"
            continue
        fi
        "$BIN" render "$spec" --out "$OUT/$name-spatial" --no-report -q "$@"
    fi
    # Columns of stats.csv by name: rays_traced, queries, error_percent, temporal_pixels.
    paste -d, "$OUT/$name/stats.csv" "$OUT/$name-spatial/stats.csv" | awk -F, -v name="$name" '
        NR == 1 { n = NF / 2; for (i = 1; i <= n; i++) col[$i] = i; next }
        {
            rt = $col["rays_traced"]; rs = $(n + col["rays_traced"]); q = $col["queries"]
            all_t += rt; all_s += rs
            if ($col["temporal_pixels"] > 0) { t += rt; s += rs; qs += q; frames++ }
            e = $col["error_percent"]
            if ($col["temporal_pixels"] > 0) { if (e > maxe) maxe = e } else if (key == "") key = e
        }
        END {
            printf "%-28s %6d %10.2f %10.2f %7.1f%% %8.1f%% %8.4f %8.4f\n", name, frames,
                100 * s / qs, 100 * t / qs, 100 * t / s, 100 * all_t / all_s, key, maxe
        }'
done
