#!/usr/bin/env bash
# compare-embree.sh — trace the same shadow rays with envshadow (obvhs) and Embree 3, one and
# two threads, and print rays per second for both (BENCHMARKS.md).
#
# usage: scripts/compare-embree.sh [--scene bunny] [--lights 400] [--methods grid-nowarp-uncertainty]
#                                  [--threads 1,2] [--repeat 3] [--work DIR]
# envshadow renders the frame once, recording every shadow ray its method traced, and writes them
# with the triangles to WORK/rays-LIGHTS-METHOD.bin; benches/embree/embree_occluded.cpp (built
# here with g++ against Debian's libembree-dev, installed with apt-get when missing and run as
# root; not part of the renderer's build) and `envshadow bench --replay` then trace that file,
# alternating, in the same chunks of rays over the same thread counts.
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
cd "$ROOT"

SCENE=bunny
LIGHTS=400
METHODS=grid-nowarp-uncertainty
THREADS=1,2
REPEAT=3
WORK=target/compare-embree
while [ $# -gt 0 ]; do
  case "$1" in
    --scene) SCENE="$2"; shift 2 ;;
    --lights) LIGHTS="$2"; shift 2 ;;
    --methods) METHODS="$2"; shift 2 ;;
    --threads) THREADS="$2"; shift 2 ;;
    --repeat) REPEAT="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    *) echo "compare-embree.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

if [ ! -f /usr/include/embree3/rtcore.h ] || ! command -v g++ >/dev/null; then
  if [ "$(id -u)" = 0 ]; then
    apt-get install -y -qq libembree-dev g++ >/dev/null
  else
    echo "compare-embree.sh: needs Debian's libembree-dev and g++ (apt-get install libembree-dev g++)" >&2
    exit 2
  fi
fi
mkdir -p "$WORK"
g++ -O2 -std=c++17 -o "$WORK/embree_occluded" benches/embree/embree_occluded.cpp -lembree3 -lpthread
cargo build --release -q
./target/release/envshadow bench --scene "$SCENE" --lights "$LIGHTS" --methods "$METHODS" \
  --threads 1 --repeat 1 --dump-rays "$WORK" >/dev/null
for m in ${METHODS//,/ }; do
  f="$WORK/rays-$LIGHTS-$m.bin"
  echo "## $m, $LIGHTS lights ($f)"
  # Alternate the two tracers so both see the same machine load.
  for round in 1 2; do
    echo "### round $round"
    ./target/release/envshadow bench --replay "$f" --threads "$THREADS" --repeat "$REPEAT"
    echo
    "$WORK/embree_occluded" "$f" "$THREADS" "$REPEAT"
    echo
  done
done
