#!/usr/bin/env bash
# bench-alpha-lights.sh — alpha cut-outs and the scene file's lights (BENCHMARKS.md, issue 24),
# measured against an older build side by side in one run.
#
# usage: scripts/bench-alpha-lights.sh [--old BIN] [--repeat N] [--lights 400] [--spp 1]
#                                      [--size 640x480] [--threads 2] [--work DIR]
#
# Every .glb of ../shared/assets/corpus (or $CORPUS) and the bunny as their own turntable (the
# bunny spec's map, the camera framing the model), frame 1: the default method and brute force
# rendered by this build (target/release/envshadow) and by --old (a build from before; omitted:
# this build only), alternately, --repeat times each; the median seconds of each, their ratio,
# and this build's % traced and wrong pairs (one --validate run). A model --old cannot load is
# marked so. Models whose file places lights are rendered again with --scene-lights=false.
# Prints a markdown table; keeps every render under the work folder (default
# target/bench-alpha-lights).
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
cd "$ROOT"

OLD=""
REPEAT=3
LIGHTS=400
SPP=1
SIZE=640x480
THREADS=2
WORK=target/bench-alpha-lights
CORPUS="${CORPUS:-$ROOT/../shared/assets/corpus}"
while [ $# -gt 0 ]; do
  case "$1" in
    --old) OLD="$(realpath "$2")"; shift 2 ;;
    --repeat) REPEAT="$2"; shift 2 ;;
    --lights) LIGHTS="$2"; shift 2 ;;
    --spp) SPP="$2"; shift 2 ;;
    --size) SIZE="$2"; shift 2 ;;
    --threads) THREADS="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
    *) echo "bench-alpha-lights.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

cargo build --release -q
NEW="$ROOT/target/release/envshadow"
W="${SIZE%x*}"; H="${SIZE#*x}"
mkdir -p "$WORK"

# seconds BIN OUT FLAGS…: one render of frame 1; prints its seconds (stats.csv), or "-" if it
# fails (a file the build cannot load).
seconds() {
  local bin="$1" out="$2"; shift 2
  rm -rf "$out"
  if "$bin" render "$@" --frames 1 --width "$W" --height "$H" --spp "$SPP" --lights "$LIGHTS" \
      --threads "$THREADS" --out "$out" --no-report -q >/dev/null 2>&1; then
    python3 -c "import csv; print(next(csv.DictReader(open('$out/stats.csv')))['seconds'])"
  else
    echo "-"
  fi
}

# median of its arguments ("-" if any is "-").
median() {
  python3 -c "
import sys
v = sys.argv[1:]
print('-' if '-' in v else f'{sorted(map(float, v))[len(v) // 2]:.3f}')" "$@"
}

# row NAME SPEC [FLAGS…]: one table row.
row() {
  local name="$1" spec="$2"; shift 2
  local base="$WORK/$name"
  local -a nd=() nb=() od=() ob=()
  for _ in $(seq "$REPEAT"); do
    nd+=("$(seconds "$NEW" "$base-new-default" "$spec" "$@")")
    nb+=("$(seconds "$NEW" "$base-new-brute" "$spec" "$@" --method brute)")
    if [ -n "$OLD" ]; then
      od+=("$(seconds "$OLD" "$base-old-default" "$spec" "$@")")
      ob+=("$(seconds "$OLD" "$base-old-brute" "$spec" "$@" --method brute)")
    fi
  done
  rm -rf "$base-valid"
  local err
  if ! err="$("$NEW" render "$spec" "$@" --frames 1 --width "$W" --height "$H" --spp "$SPP" \
      --lights "$LIGHTS" --threads "$THREADS" --out "$base-valid" --validate --no-report -q \
      2>&1 >/dev/null)"; then
    # A model this build cannot load is a row saying why, not the end of the table.
    echo "| $name | does not load: ${err:0:160} | | | | | | | | |"
    return
  fi
  local snd snb sod="-" sob="-"
  snd="$(median "${nd[@]}")"; snb="$(median "${nb[@]}")"
  if [ -n "$OLD" ]; then sod="$(median "${od[@]}")"; sob="$(median "${ob[@]}")"; fi
  python3 - "$base-valid/stats.csv" "$name" "$snd" "$snb" "$sod" "$sob" <<'EOF'
import csv, sys
r = next(csv.DictReader(open(sys.argv[1])))
name, nd, nb, od, ob = sys.argv[2:]
q = int(r["queries"]); rays = int(r["rays_traced"])
wrong = int(r["wrong_visible"] or 0) + int(r["wrong_blocked"] or 0)
ratio = lambda a, b: "-" if "-" in (a, b) else f"{float(a) / float(b):.3f}"
print(f"| {name} | {r['lights']} | {100 * rays / q:.2f} | {100 * wrong / q:.4f} | {od} | {nd} "
      f"| {ratio(nd, od)} | {ob} | {nb} | {ratio(nb, ob)} |")
EOF
}

echo "| model | lights | % traced | wrong pairs % | default s, old | default s, new | new ÷ old | brute s, old | brute s, new | new ÷ old |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
row bunny anims/bunny-turntable.toml
for glb in "$CORPUS"/*.glb; do
  name="$(basename "$glb" .glb)"
  spec="$WORK/$name.toml"
  # The bunny turntable with this model and the camera framing it.
  sed -e "s|^file = \"../assets/bunny_on_plane.glb\"|file = \"$glb\"|" \
      -e "s|^file = \"../assets/|file = \"$ROOT/assets/|" \
      -e '/^target = /d' -e '/^distance = /d' -e "s|^name = .*|name = \"$name\"|" \
      anims/bunny-turntable.toml > "$spec"
  row "$name" "$spec"
  if grep -q KHR_lights_punctual "$glb"; then
    row "$name (--scene-lights=false)" "$spec" --scene-lights=false
  fi
done
