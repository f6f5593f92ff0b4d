#!/usr/bin/env bash
# bench-specular.sh — what glTF materials' specular costs against Lambert-only shading, measured
# side by side in one run (BENCHMARKS.md, issue 24).
#
# usage: scripts/bench-specular.sh [--lights 400] [--size 640x480] [--spp 1] [--threads 2]
#                                  [--repeat 5] [--methods none,default] [--work DIR] [SPEC]
#        scripts/bench-specular.sh --corpus [same options]
#
# Renders frame 1 of SPEC (default anims/bunny-turntable.toml) with each method of --methods
# (`default` = the spec's method) as the file's materials say and with --lambert (every
# material diffuse: the Lambert kernel alone), the two alternating, --repeat times each, and
# prints each one's median seconds (stats.csv) and the ratio. `none` traces no shadow ray:
# its ratio is the shading's own cost; the default method's is what a user waits for.
# With --corpus: every .glb of ../shared/assets/corpus (or $CORPUS) as its own turntable (the
# bunny spec's map and lights, the camera framing the model), as scripts/bench-spp.sh does.
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
cd "$ROOT"

SPEC=anims/bunny-turntable.toml
LIGHTS=400
SIZE=640x480
SPP=1
THREADS=2
REPEAT=5
METHODS=none,default
WORK=target/bench-specular
CORPUS_MODE=0
CORPUS="${CORPUS:-$ROOT/../shared/assets/corpus}"
while [ $# -gt 0 ]; do
  case "$1" in
    --lights) LIGHTS="$2"; shift 2 ;;
    --size) SIZE="$2"; shift 2 ;;
    --spp) SPP="$2"; shift 2 ;;
    --threads) THREADS="$2"; shift 2 ;;
    --repeat) REPEAT="$2"; shift 2 ;;
    --methods) METHODS="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --corpus) CORPUS_MODE=1; shift ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    -*) echo "bench-specular.sh: unknown option $1" >&2; exit 2 ;;
    *) SPEC="$1"; shift ;;
  esac
done

cargo build --release -q
BIN="$ROOT/target/release/envshadow"
mkdir -p "$WORK"
W="${SIZE%x*}"; H="${SIZE#*x}"

# seconds SPEC METHOD OUT FLAGS…: one render of frame 1, its stats.csv seconds.
seconds() {
  local spec="$1" method="$2" out="$3"; shift 3
  local m=()
  [ "$method" = default ] || m=(--method "$method")
  rm -rf "$out"
  "$BIN" render "$spec" --frames 1 --lights "$LIGHTS" --width "$W" --height "$H" --spp "$SPP" \
    --threads "$THREADS" ${m[@]+"${m[@]}"} "$@" --out "$out" --no-report -q
  python3 -c "import csv,sys; print(list(csv.DictReader(open(sys.argv[1])))[-1]['seconds'])" \
    "$out/stats.csv"
}

# row NAME SPEC: both shadings alternating, per method.
row() {
  local name="$1" spec="$2"
  for method in ${METHODS//,/ }; do
    local mat=() lam=()
    for ((r = 0; r < REPEAT; r++)); do
      mat+=("$(seconds "$spec" "$method" "$WORK/$name-$method")")
      lam+=("$(seconds "$spec" "$method" "$WORK/$name-$method-lambert" --lambert)")
    done
    python3 - "$name" "$method" "${mat[*]}" "${lam[*]}" <<'EOF'
import statistics, sys
name, method, mat, lam = sys.argv[1], sys.argv[2], sys.argv[3].split(), sys.argv[4].split()
m = statistics.median(float(x) for x in mat)
l = statistics.median(float(x) for x in lam)
print(f"| {name} | {method} | {l:.3f} | {m:.3f} | {m / l:.2f}× |")
EOF
  done
}

echo "$LIGHTS lights, ${W}×${H}, $SPP spp, $THREADS threads, frame 1, median of $REPEAT alternating renders each"
echo
echo "| scene | method | --lambert s | materials s | materials ÷ --lambert |"
echo "|---|---|---:|---:|---:|"
if [ "$CORPUS_MODE" = 0 ]; then
  row "$(basename "$SPEC" .toml)" "$SPEC"
  exit 0
fi
for glb in "$CORPUS"/*.glb; do
  name="$(basename "$glb" .glb)"
  spec="$WORK/$name.toml"
  sed -e "s|^file = \"../assets/bunny_on_plane.glb\"|file = \"$glb\"|" \
      -e "s|^file = \"../assets/|file = \"$ROOT/assets/|" \
      -e '/^target = /d' -e '/^distance = /d' -e "s|^name = .*|name = \"$name\"|" \
      anims/bunny-turntable.toml > "$spec"
  if ! err="$("$BIN" render "$spec" --width 8 --height 8 --frames 1 --lights 8 \
      --out "$WORK/probe" --no-report -q 2>&1)"; then
    echo "| $name | does not load: ${err:0:160} | | | |"
    continue
  fi
  row "$name" "$spec"
done
