#!/usr/bin/env bash
# bench-corpus.sh — every corpus model under every shared map: share traced, wrong pairs,
# relative RMSE and seconds of none, brute and the default measured side by side (issue 23).
#
# usage: scripts/bench-corpus.sh [--corpus DIR] [--maps A.hdr,B.hdr,…] [--lights 400]
#                                [--size 640x480] [--spp 1] [--threads 2] [--repeat 3]
#                                [--method grid-nowarp-uncertainty[,OTHER…]] [--work DIR]
#                                [-- EXTRA BENCH FLAGS…]
#
# For each model (every .glb and .gltf in --corpus, default ../shared/assets/corpus or $CORPUS)
# and each map (default grace.hdr, rooitou_park_1k.hdr and studio_small_03_1k.hdr from
# ../shared/assets or $ENVSHADOW_ASSETS) one `envshadow bench --scene MODEL --env MAP --csv`:
# the model auto-framed (Animation::of_model), frame 0, one process, the methods
# interleaved round robin over --repeat renders of the frame and the median time of each kept
# (bench's rule), then each method rendered once more with --validate (untimed: --accuracy).
# A model envshadow cannot load is a row saying why, not a gap in the table.
#
# Prints a markdown table and, last, lines per method:
#   corpus: median A× faster than brute (min B×), traced C–D %, wrong pairs ≤ E %
#   corpus: a traced query costs a median F× (max G×) brute force's ray; the frame is a
#   median H× the frame without shadows (max I×)
# (a traced query's cost: ((method − none) ÷ rays traced) ÷ ((brute − none) ÷ queries)).
# A bench flag swept after `--` (e.g. `-- --pixel-majority=true,false`) is timed interleaved
# with the rest in one process; each of its settings is summarised as a method of its own.
# "% traced" counts every ray a frame traced, tiles' halos included. Keeps the raw CSV in the
# work folder (default target/bench-corpus/corpus.csv). $ENVSHADOW_BIN measures another build.
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
cd "$ROOT"

ASSETS="${ENVSHADOW_ASSETS:-$ROOT/../shared/assets}"
CORPUS="${CORPUS:-$ASSETS/corpus}"
MAPS="$ASSETS/grace.hdr,$ASSETS/rooitou_park_1k.hdr,$ASSETS/studio_small_03_1k.hdr"
LIGHTS=400
SIZE=640x480
SPP=1
THREADS=2
REPEAT=3
METHODS=grid-nowarp-uncertainty
WORK=target/bench-corpus
EXTRA=()
while [ $# -gt 0 ]; do
  case "$1" in
    --corpus) CORPUS="$2"; shift 2 ;;
    --maps) MAPS="$2"; shift 2 ;;
    --lights) LIGHTS="$2"; shift 2 ;;
    --size) SIZE="$2"; shift 2 ;;
    --spp) SPP="$2"; shift 2 ;;
    --threads) THREADS="$2"; shift 2 ;;
    --repeat) REPEAT="$2"; shift 2 ;;
    --method) METHODS="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --) shift; EXTRA=("$@"); break ;;
    -h|--help) sed -n '2,26p' "$0"; exit 0 ;;
    *) echo "bench-corpus.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

# $ENVSHADOW_BIN: measure that binary instead of building this checkout's.
if [ -n "${ENVSHADOW_BIN:-}" ]; then
  BIN="$ENVSHADOW_BIN"
else
  cargo build --release -q
  BIN="$ROOT/target/release/envshadow"
fi
mkdir -p "$WORK"
CSV="$WORK/corpus.csv"
FAILED="$WORK/failed.txt"
: > "$FAILED"
rm -f "$CSV"
W="${SIZE%x*}"; H="${SIZE#*x}"

shopt -s nullglob
models=("$CORPUS"/*.glb "$CORPUS"/*.gltf)
[ ${#models[@]} -gt 0 ] || { echo "bench-corpus.sh: no .glb or .gltf in $CORPUS" >&2; exit 2; }
for model in "${models[@]}"; do
  for map in ${MAPS//,/ }; do
    out="$WORK/run.csv"
    echo "$(basename "$model") under $(basename "$map") …" >&2
    if "$BIN" bench --scene "$model" --env "$map" --lights "$LIGHTS" --width "$W" --height "$H" \
        --spp "$SPP" --threads "$THREADS" --repeat "$REPEAT" --method "none,brute,$METHODS" \
        --no-split --accuracy --csv ${EXTRA[@]+"${EXTRA[@]}"} > "$out" 2> "$WORK/run.err"; then
      if [ -f "$CSV" ]; then tail -n +2 "$out" >> "$CSV"; else cp "$out" "$CSV"; fi
    else
      # The loader's one-line message, without the binary's prefix.
      msg="$(grep -v '^warning' "$WORK/run.err" | tail -n 1)"
      printf '%s\t%s\t%s\n' "$model" "$map" "${msg#error: }" >> "$FAILED"
      # A model that does not load fails under every map alike: one row says so.
      if grep -q -e 'glTF' -e "$(basename "$model")" <<<"$msg"; then break; fi
    fi
  done
done

python3 - "$CSV" "$FAILED" "$METHODS" "$THREADS" <<'EOF'
import csv, os, statistics, sys
path, failed, methods, threads = sys.argv[1], sys.argv[2], sys.argv[3].split(","), sys.argv[4]
rows = list(csv.DictReader(open(path))) if os.path.exists(path) else []
name = lambda p: os.path.splitext(os.path.basename(p))[0]
runs = {}
for r in rows:
    runs.setdefault((name(r["scene"]), name(r["environment"])), {})[r["method"]] = r
# A bench flag swept after `--` (`-- --pixel-majority=true,false`) labels its rows with the
# method and the setting: each label is summarised as a method of its own.
labels = [r["method"] for r in rows if r["method"] not in ("none", "brute")]
methods += [l for l in dict.fromkeys(labels) if l not in methods]
print(f"| model | map | method | % traced | wrong pairs % | rel. RMSE | none s | brute s | method s | brute ÷ method | method ÷ none | traced query ÷ brute ray |")
print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
summary = {m: [] for m in methods}
def per_ray(shadow, traced, brute_shadow, queries):
    if traced <= 0 or queries <= 0 or brute_shadow <= 0:
        return None
    return (shadow / traced) / (brute_shadow / queries)
for (model, env), by in sorted(runs.items()):
    none, brute = by.get("none"), by.get("brute")
    for m in methods:
        r = by.get(m)
        if not (r and none and brute):
            continue
        s, sb, sn = float(r["seconds"]), float(brute["seconds"]), float(none["seconds"])
        pct, wrong, rel = float(r["percent_traced"]), float(r["wrong_percent"]), float(r["rel_rmse"])
        # What the method's shadows cost per ray it traced, over what brute force's cost per
        # ray: ((method − none) ÷ rays traced) ÷ ((brute − none) ÷ queries).
        cost = per_ray(s - sn, int(r["rays_traced"]), sb - sn, int(brute["queries"]))
        summary[m].append((sb / s, pct, wrong, s / sn, cost))
        shown = f"{cost:.2f}×" if cost is not None else "–"
        print(f"| {model} | {env} | {m} | {pct:.2f} | {wrong:.4f} | {rel:.5f} | {sn:.3f} | {sb:.3f} | {s:.3f} | {sb / s:.2f}× | {s / sn:.2f}× | {shown} |")
for line in open(failed):
    model, env, msg = line.rstrip("\n").split("\t", 2)
    # The reason, without the file names the loader's message repeats.
    msg = msg.split("invalid glTF: ", 1)[-1].split(model + ": ")[-1]
    print(f"| {name(model)} | {name(env)} | does not load: {msg[:200]} | | | | | | | | | |")
print()
if rows:
    r0 = rows[0]
    print(f"{r0['width']}×{r0['height']}, {r0['spp']} spp, {r0['lights']} lights, {threads} threads, "
          f"frame {r0['frame']}, median of {r0['repeats']} interleaved renders per method.")
for m in methods:
    v = summary[m]
    if not v:
        print(f"corpus ({m}): no model rendered")
        continue
    ratios = [x[0] for x in v]
    pcts = [x[1] for x in v]
    wrongs = [x[2] for x in v]
    label = "corpus" if len(methods) == 1 else f"corpus ({m})"
    print(f"{m}: {len(v)} model × map runs, median wrong pairs {statistics.median(wrongs):.4f} %, "
          f"median traced {statistics.median(pcts):.1f} %")
    print(f"{label}: median {statistics.median(ratios):.1f}× faster than brute (min {min(ratios):.1f}×), "
          f"traced {min(pcts):.1f}–{max(pcts):.1f} %, wrong pairs ≤ {max(wrongs):.3f} %")
    over_none = [x[3] for x in v]
    costs = [x[4] for x in v if x[4] is not None]
    cost = (f"{statistics.median(costs):.2f}× (max {max(costs):.2f}×)" if costs else "–")
    print(f"{label}: a traced query costs a median {cost} brute force's ray; the frame is a "
          f"median {statistics.median(over_none):.1f}× the frame without shadows "
          f"(max {max(over_none):.1f}×)")
EOF
