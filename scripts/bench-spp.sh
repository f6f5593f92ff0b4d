#!/usr/bin/env bash
# bench-spp.sh — samples per pixel, measured side by side in one run (BENCHMARKS.md, issue 21).
#
# usage: scripts/bench-spp.sh [--sizes 640x480,1920x1080] [--spp 1,4,16] [--lights 400]
#                             [--frames 1..16] [--validate-frames 1..4] [--threads 2]
#                             [--work DIR] [SPEC]
#        scripts/bench-spp.sh --corpus [--spp 16] [--sizes 640x480] [--work DIR]
#
# For each size and spp, on SPEC (default anims/bunny-turntable.toml):
#   none, brute and the default timed on the first frame of --frames alone (a run of several
#   frames keeps two in flight, so its per-frame seconds overlap; a turntable's frames cost
#   about the same);
#   % traced of the default and of the default with --temporal over --frames (the frames'
#   rays over their queries); --temporal's seconds are its frames' mean — a chain renders one
#   frame after another, so they do not overlap (keep --frames inside one chain: 1..16 is
#   frames 1–15 after key frame 0);
#   wrong pairs from --validate runs of both over --validate-frames.
# Peak RSS (/usr/bin/time -v) is reported for every default run.
# With --corpus: every .glb in ../shared/assets/corpus (or $CORPUS) as its own turntable (the
# bunny spec's sky and lights, camera framing the model), none, brute and the default on the
# first frame, validated once.
# Prints markdown tables; keeps every render under the work folder (default target/bench-spp).
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
cd "$ROOT"

SPEC=anims/bunny-turntable.toml
SIZES=640x480,1920x1080
SPPS=1,4,16
LIGHTS=400
FRAMES=1..16
VFRAMES=1..4
THREADS=2
WORK=target/bench-spp
CORPUS_MODE=0
CORPUS="${CORPUS:-$ROOT/../shared/assets/corpus}"
while [ $# -gt 0 ]; do
  case "$1" in
    --sizes) SIZES="$2"; shift 2 ;;
    --spp) SPPS="$2"; shift 2 ;;
    --lights) LIGHTS="$2"; shift 2 ;;
    --frames) FRAMES="$2"; shift 2 ;;
    --validate-frames) VFRAMES="$2"; shift 2 ;;
    --threads) THREADS="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --corpus) CORPUS_MODE=1; shift ;;
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    -*) echo "bench-spp.sh: unknown option $1" >&2; exit 2 ;;
    *) SPEC="$1"; shift ;;
  esac
done

cargo build --release -q
BIN="$ROOT/target/release/envshadow"
mkdir -p "$WORK"
[ -x /usr/bin/time ] || { echo "bench-spp.sh: needs /usr/bin/time (apt-get install time)" >&2; exit 2; }

# render OUT FLAGS…: one render, its peak RSS appended to OUT.rss (kB).
render() {
  local out="$1"; shift
  rm -rf "$out"
  /usr/bin/time -f "%M" -o "$out.rss" "$BIN" render "$@" --out "$out" --threads "$THREADS" \
    --lights "$LIGHTS" --no-report -q
}

# summary DIR: "seconds_mean rays queries wrong frames rss_mb" over stats.csv's rows.
summary() {
  python3 - "$1" <<'EOF'
import csv, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(f"{d}/stats.csv")))
secs = sum(float(r["seconds"]) for r in rows) / len(rows)
rays = sum(int(r["rays_traced"]) for r in rows)
q = sum(int(r["queries"]) for r in rows)
wrong = sum(int(r["wrong_visible"] or 0) + int(r["wrong_blocked"] or 0) for r in rows)
rss = int(open(f"{d}.rss").read().split()[-1]) / 1024
print(f"{secs:.3f} {rays} {q} {wrong} {len(rows)} {rss:.0f}")
EOF
}

first_frame() { echo "${FRAMES%%..*}"; }

if [ "$CORPUS_MODE" = 1 ]; then
  SPPS="${SPPS/1,4,16/16}"
  SIZES="${SIZES/640x480,1920x1080/640x480}"
  echo "| model | spp | % traced | wrong pairs % | none s | brute s | default s | brute ÷ default |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|"
  for glb in "$CORPUS"/*.glb; do
    name="$(basename "$glb" .glb)"
    spec="$WORK/$name.toml"
    # The bunny turntable with this model and the camera framing it, the model as it is (no
    # ground added under those that have none, as when these figures were first measured).
    sed -e "s|^file = \"../assets/bunny_on_plane.glb\"|file = \"$glb\"\nground = \"none\"|" \
        -e "s|^file = \"../assets/|file = \"$ROOT/assets/|" \
        -e '/^target = /d' -e '/^distance = /d' -e "s|^name = .*|name = \"$name\"|" \
        "$SPEC" > "$spec"
    for size in ${SIZES//,/ }; do
      w="${size%x*}"; h="${size#*x}"
      for spp in ${SPPS//,/ }; do
        base="$WORK/$name-$w-$spp"
        f="$(first_frame)"
        # A model envshadow cannot load is a row saying why, not the end of the table.
        if ! err="$("$BIN" render "$spec" --width 8 --height 8 --frames "$f" --lights 8 \
            --out "$WORK/probe" --no-report -q 2>&1)"; then
          msg="${err#*invalid glTF: }"
          echo "| $name | $spp | does not load: ${msg:0:160} | | | | | |"
          continue
        fi
        render "$base-none" "$spec" --width "$w" --height "$h" --spp "$spp" --frames "$f" --method none
        render "$base-brute" "$spec" --width "$w" --height "$h" --spp "$spp" --frames "$f" --method brute
        render "$base-default" "$spec" --width "$w" --height "$h" --spp "$spp" --frames "$f"
        render "$base-valid" "$spec" --width "$w" --height "$h" --spp "$spp" --frames "$f" --validate
        read -r sn _ _ _ _ _ <<<"$(summary "$base-none")"
        read -r sb _ _ _ _ _ <<<"$(summary "$base-brute")"
        read -r sd _ _ _ _ _ <<<"$(summary "$base-default")"
        read -r _ rv qv wv _ _ <<<"$(summary "$base-valid")"
        python3 -c "
print(f'| $name | $spp | {100*$rv/$qv:.2f} | {100*$wv/$qv:.4f} | $sn | $sb | $sd | {$sb/$sd:.1f}× |')"
      done
    done
  done
  exit 0
fi

echo "| size | spp | % traced default / temporal | rays ÷ 1 spp default / temporal | wrong pairs % default / temporal | none s | brute s | default s | temporal s | brute ÷ default / temporal | peak RSS MB, default over the frames |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for size in ${SIZES//,/ }; do
  w="${size%x*}"; h="${size#*x}"
  base1=""
  for spp in ${SPPS//,/ }; do
    base="$WORK/$w-$spp"
    f="$(first_frame)"
    common=(--width "$w" --height "$h" --spp "$spp")
    render "$base-none" "$SPEC" "${common[@]}" --frames "$f" --method none
    render "$base-brute" "$SPEC" "${common[@]}" --frames "$f" --method brute
    render "$base-default1" "$SPEC" "${common[@]}" --frames "$f"
    render "$base-default" "$SPEC" "${common[@]}" --frames "$FRAMES"
    render "$base-temporal" "$SPEC" "${common[@]}" --frames "$FRAMES" --temporal
    render "$base-vdefault" "$SPEC" "${common[@]}" --frames "$VFRAMES" --validate
    render "$base-vtemporal" "$SPEC" "${common[@]}" --frames "$VFRAMES" --validate --temporal
    read -r sn _ _ _ _ _ <<<"$(summary "$base-none")"
    read -r sb _ _ _ _ _ <<<"$(summary "$base-brute")"
    read -r sd _ _ _ _ _ <<<"$(summary "$base-default1")"
    read -r _ rd qd _ _ rss <<<"$(summary "$base-default")"
    read -r st rt qt _ nt _ <<<"$(summary "$base-temporal")"
    read -r _ _ qvd wvd _ _ <<<"$(summary "$base-vdefault")"
    read -r _ _ qvt wvt _ _ <<<"$(summary "$base-vtemporal")"
    if [ -z "$base1" ]; then base1="$rd $rt"; fi
    read -r r1d r1t <<<"$base1"
    python3 -c "
print(f'| ${w}×${h} | $spp | {100*$rd/$qd:.2f} / {100*$rt/$qt:.2f} | {$rd/$r1d:.2f} / {$rt/$r1t:.2f} | {100*$wvd/$qvd:.4f} / {100*$wvt/$qvt:.4f} | $sn | $sb | $sd | $st | {$sb/$sd:.1f}× / {$sb/$st:.1f}× | $rss |')"
  done
done
