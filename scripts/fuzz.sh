#!/usr/bin/env bash
# Runs the fuzz campaign: every target in fuzz/ for SECONDS each (default 600), one at a time,
# niced, with memory and time limits per input; prints one summary line per target.
#   scripts/fuzz.sh [SECONDS] [TARGET...]
# Needs the nightly toolchain and cargo-fuzz (`cargo install cargo-fuzz`). New corpus entries go
# to fuzz/corpus/TARGET (not committed); crashes to fuzz/artifacts/TARGET.
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-600}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(anim_spec posed_scene gltf draco envmap_exr envmap_hdr lights_json)
cargo +nightly fuzz build
bin=fuzz/target/x86_64-unknown-linux-gnu/release
# The committed seeds are small; make_seeds also writes the large ones (not committed).
[ -e fuzz/seeds/gltf/large-shared-texture.glb ] || "$bin/make_seeds" fuzz/seeds
mkdir -p fuzz/logs
for t in "${targets[@]}"; do
  mkdir -p "fuzz/corpus/$t" "fuzz/artifacts/$t"
  log="fuzz/logs/$t.log"
  # Images and maps blow up memory only past a few tens of kilobytes (a 200 kB PNG decodes to
  # a gigabyte): their targets take inputs up to 4 MB, and have seeds that large (large-*).
  case $t in
    gltf | envmap_exr | envmap_hdr) max_len=4194304 ;;
    *) max_len=65536 ;;
  esac
  # -rss_limit_mb: twice the loaders' memory budget in the targets (fuzz/src/exercise.rs), so
  # an OOM is an input whose estimate fell short; -timeout: an input taking more than 10 s is
  # a hang. One forked worker that carries on after a crash, OOM or hang, so the whole time is
  # spent and every finding is kept.
  nice -n 10 "$bin/$t" "fuzz/corpus/$t" "fuzz/seeds/$t" \
    -artifact_prefix="fuzz/artifacts/$t/" -max_total_time="$secs" \
    -rss_limit_mb=2048 -timeout=10 -max_len="$max_len" \
    -fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 >"$log" 2>&1 || true
  execs=$(grep -o '^#[0-9]*' "$log" | tail -1 | tr -d '#')
  corpus=$(ls "fuzz/corpus/$t" | wc -l)
  crashes=$(ls "fuzz/artifacts/$t" | wc -l)
  echo "$t: ${secs} s, ${execs} executions, corpus ${corpus} files, ${crashes} artifacts"
done
