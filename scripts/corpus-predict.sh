#!/usr/bin/env bash
# corpus-predict.sh — what a prediction rule traces and gets wrong on every corpus model under
# every shared map (BENCHMARKS.md, "Issue 23: prediction and frame cost").
#
# usage: scripts/corpus-predict.sh [--label NAME] [--lights 400] [--size 640x480] [--frame 1]
#                                  [--threads 2] [--work DIR] [--bin PATH] [-- RENDER FLAGS…]
#
# Every .glb in ../shared/assets/corpus (or $CORPUS) × grace, rooitou_park_1k and
# studio_small_03_1k, each as its own turntable (the bunny spec with the model auto-framed and
# the map swapped), one frame at one sample per pixel rendered with --validate and the extra
# render flags. "% traced" is stats.csv's rays_traced ÷ queries: the rays for the frame's own
# pixels, the ~10 % that tiles trace for their halos left out (percent_traced and
# bench-corpus.sh count them). % traced and wrong pairs are deterministic (the same bits on a busy machine),
# so rules are compared on them; seconds are not printed. A model that does not load is a row
# saying so. The last line: median and largest % traced and wrong pairs over the rows.
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
cd "$ROOT"

LABEL=run
LIGHTS=400
SIZE=640x480
FRAME=1
THREADS=2
WORK=target/corpus-predict
BIN="$ROOT/target/release/envshadow"
CORPUS="${CORPUS:-$ROOT/../shared/assets/corpus}"
MAPS="${MAPS:-grace rooitou_park_1k studio_small_03_1k}"
while [ $# -gt 0 ]; do
  case "$1" in
    --label) LABEL="$2"; shift 2 ;;
    --lights) LIGHTS="$2"; shift 2 ;;
    --size) SIZE="$2"; shift 2 ;;
    --frame) FRAME="$2"; shift 2 ;;
    --threads) THREADS="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --bin) BIN="$2"; shift 2 ;;
    -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
    --) shift; break ;;
    *) echo "corpus-predict.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
EXTRA=("$@")
W="${SIZE%x*}"; H="${SIZE#*x}"
ASSETS="$(cd "$CORPUS/.." && pwd)"
mkdir -p "$WORK/$LABEL"
ROWS="$WORK/$LABEL/rows.txt"
: > "$ROWS"

echo "| model | map | % traced | wrong pairs % | rel. RMSE % | every + unsure + flooded % (fixes) |"
echo "|---|---|---:|---:|---:|---|"
for glb in "$CORPUS"/*.glb; do
  name="$(basename "$glb" .glb)"
  for map in $MAPS; do
    spec="$WORK/$LABEL/$name-$map.toml"
    # The bunny turntable with this model, the camera framing it, and this map.
    sed -e "s|^file = \"../assets/bunny_on_plane.glb\"|file = \"$glb\"|" \
        -e "s|^file = \"../assets/studio_small_03_1k.hdr\"|file = \"$ASSETS/$map.hdr\"|" \
        -e '/^target = /d' -e '/^distance = /d' -e "s|^name = .*|name = \"$name\"|" \
        anims/bunny-turntable.toml > "$spec"
    out="$WORK/$LABEL/$name-$map"
    rm -rf "$out"
    if ! err="$("$BIN" render "$spec" --width "$W" --height "$H" --frames "$FRAME" \
        --lights "$LIGHTS" --threads "$THREADS" --validate --out "$out" --no-report -q \
        "${EXTRA[@]}" 2>&1)"; then
      echo "| $name | $map | does not load: $(echo "$err" | head -c 120) | | | |"
      continue
    fi
    python3 - "$out/stats.csv" "$name" "$map" >> "$ROWS" <<'EOF'
import csv, sys
r = list(csv.DictReader(open(sys.argv[1])))[0]
q = int(r["queries"])
wrong = int(r["wrong_visible"]) + int(r["wrong_blocked"])
pc = lambda k: 100 * int(r[k]) / q
print(sys.argv[2], sys.argv[3], pc("rays_traced"), 100 * wrong / q, 100 * float(r["rel_rmse"]),
      pc("rays_every_light"), pc("rays_unsure"), pc("rays_flooded"), r["flood_fixes"])
EOF
    tail -n 1 "$ROWS" | awk '{printf "| %s | %s | %.2f | %.4f | %.3f | %.2f + %.2f + %.2f (%s) |\n", $1, $2, $3, $4, $5, $6, $7, $8, $9}'
  done
done
python3 - "$ROWS" "$LABEL" <<'EOF'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1]) if l.strip()]
t = [float(r[2]) for r in rows]; w = [float(r[3]) for r in rows]
print(f"{sys.argv[2]}: {len(rows)} frames, traced median {statistics.median(t):.2f} % "
      f"(max {max(t):.2f} %), wrong pairs median {statistics.median(w):.4f} % "
      f"(max {max(w):.4f} %), frames above 0.05 %: {sum(x > 0.05 for x in w)}")
EOF
