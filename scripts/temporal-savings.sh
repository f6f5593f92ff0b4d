#!/usr/bin/env bash
# temporal-savings.sh — render the same frames with and without --temporal and plot the
# percent of shadow queries traced per frame (DIR/savings.png, blue = with, grey = without).
#
# Usage: scripts/temporal-savings.sh SPEC.toml DIR [render flags…]
#   e.g. scripts/temporal-savings.sh anims/bunny-turntable.toml out/orbit --frames 0..17 --validate
# Writes DIR (with --temporal) and DIR-spatial (without), then DIR/savings.png. The curve
# without --temporal is always measured, never estimated. Extra flags go to both renders
# (--validate adds error columns to both stats.csv files).
set -euo pipefail
if [[ $# -lt 2 ]]; then
    sed -n '2,10p' "$0" >&2
    exit 2
fi
SPEC="$1"; DIR="$2"; shift 2
BIN="${ENVSHADOW:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/target/release/envshadow}"
[[ -x "$BIN" ]] || { echo "temporal-savings: $BIN not found (cargo build --release, or set ENVSHADOW)" >&2; exit 1; }
"$BIN" render "$SPEC" --out "$DIR" --temporal --no-report "$@"
"$BIN" render "$SPEC" --out "$DIR-spatial" --no-report "$@"
"$BIN" savings "$DIR" --without "$DIR-spatial"
