#!/usr/bin/env bash
# check-fetch-assets.sh — self-test for scripts/ply_to_glb.py and scripts/fetch-assets.sh.
#
#  1. converts the shared PLY files into a temp folder and byte-compares the results
#     with the shared bunny.glb, bunny_on_plane.glb and bunny_res4.glb;
#  2. runs fetch-assets.sh --dest TMP --source SHARED (copy mode), checks every file,
#     then runs it again and checks that everything is skipped;
#  3. runs fetch-assets.sh in download mode offline, with a stand-in 'curl' on PATH
#     that serves the pinned raw.githubusercontent.com URLs from the shared folder
#     (tests URL mapping, hash checks, .glb generation and atomic renames), plus
#     one run with a corrupted download, which must fail, name the file and leave
#     no partial file.
# Usage: scripts/check-fetch-assets.sh [--source DIR]   (default <repo>/../shared/assets)
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
REPO_ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
SHARED="$REPO_ROOT/../shared/assets"
if [[ "${1:-}" == "--source" && -n "${2:-}" ]]; then SHARED="$2"; fi
[[ -d "$SHARED" ]] || { echo "check: shared folder $SHARED not found" >&2; exit 1; }
SHARED="$(cd "$SHARED" && pwd)"

WORK="$(mktemp -d "${TMPDIR:-/tmp}/check-fetch-assets.XXXXXX")"
trap 'rm -rf -- "$WORK"' EXIT
fail=0
bad() { echo "FAIL: $*" >&2; fail=1; }
ok()  { echo "ok:   $*"; }

# --- 1. converter ----------------------------------------------------------
echo "== 1. ply_to_glb.py vs shared .glb files"
mkdir -p "$WORK/conv"
for spec in "bunny.glb bun_zipper.ply" "bunny_on_plane.glb bun_zipper.ply --ground" \
            "bunny_res4.glb bun_zipper_res4.ply"; do
  read -r glb ply flags <<<"$spec"
  # shellcheck disable=SC2086
  if ! python3 "$SCRIPT_DIR/ply_to_glb.py" "$SHARED/$ply" "$WORK/conv/$glb" ${flags:-}; then
    bad "$glb: converter failed"; continue
  fi
  if cmp -s "$WORK/conv/$glb" "$SHARED/$glb"; then
    ok "$glb byte-identical to shared copy ($(wc -c <"$SHARED/$glb") bytes)"
  else
    bad "$glb differs from shared copy: $(cmp "$WORK/conv/$glb" "$SHARED/$glb" 2>&1 | head -1)"
  fi
done

# --- 2. copy mode ----------------------------------------------------------
echo "== 2. fetch-assets.sh --dest TMP --source SHARED (copy mode)"
D="$WORK/copy"
if "$SCRIPT_DIR/fetch-assets.sh" --dest "$D" --source "$SHARED" >"$WORK/copy1.log" 2>&1; then
  sed 's/^/      /' "$WORK/copy1.log" | head -20
  for f in "$SHARED"/*; do
    n="$(basename "$f")"
    if [[ -d "$f" ]]; then
      if diff -rq "$f" "$D/$n" >/dev/null 2>&1; then ok "copied $n/ ($(ls "$f" | wc -l) files)"; else bad "copy mode: $n/ missing or different"; fi
      continue
    fi
    if cmp -s "$f" "$D/$n"; then ok "copied $n"; else bad "copy mode: $n missing or different"; fi
  done
  if ls -A "$D" | grep -q '\.tmp\.'; then bad "copy mode left temp files"; fi
else
  cat "$WORK/copy1.log" >&2; bad "fetch-assets.sh (copy mode) exited non-zero"
fi
if "$SCRIPT_DIR/fetch-assets.sh" --dest "$D" --source "$SHARED" >"$WORK/copy2.log" 2>&1 \
   && grep -q 'done: 0 written' "$WORK/copy2.log"; then
  ok "second copy run skipped every file ($(grep -c '^skipped' "$WORK/copy2.log") skipped)"
else
  cat "$WORK/copy2.log" >&2; bad "second copy run did not skip everything"
fi
if "$SCRIPT_DIR/fetch-assets.sh" --dest "$WORK/x" --source "$WORK/does-not-exist" >/dev/null 2>&1; then
  bad "a non-existent --source was accepted"
else
  ok "non-existent --source rejected"
fi

# --- 3. download mode, offline --------------------------------------------
echo "== 3. fetch-assets.sh --download with a stand-in curl (offline)"
mkdir -p "$WORK/bin"
cat >"$WORK/bin/curl" <<EOF
#!/usr/bin/env bash
# stand-in for curl: serves pinned raw.githubusercontent.com URLs from the shared folder
set -euo pipefail
out=""; url=""
while [[ \$# -gt 0 ]]; do
  case "\$1" in -o) out="\$2"; shift 2 ;; --retry) shift 2 ;; --) url="\$2"; shift 2 ;; -*) shift ;; *) url="\$1"; shift ;; esac
done
case "\$url" in
  https://raw.githubusercontent.com/ksnabb/stan_bun/3f304b79052f2023f22ef8e5d15b7e571665ac16/bunny/reconstruction/README) f=bun_zipper_README.txt ;;
  https://raw.githubusercontent.com/ksnabb/stan_bun/3f304b79052f2023f22ef8e5d15b7e571665ac16/bunny/reconstruction/*.ply) f="\${url##*/}" ;;
  https://raw.githubusercontent.com/pmndrs/drei-assets/456060a26bbeb8fdf79326f224b6d99b8bcce736/hdri/*.hdr) f="\${url##*/}" ;;
  https://raw.githubusercontent.com/kayru/Probulator/ad916bda84a6383ec34a69eaf2f3444bfef6026d/Data/Probes/grace.hdr) f=grace.hdr ;;
  https://raw.githubusercontent.com/AcademySoftwareFoundation/openexr-images/e38ffb0790f62f05a6f083a6fa4cac150b3b7452/MultiResolution/*.exr) f="\${url##*/}" ;;
  https://raw.githubusercontent.com/AcademySoftwareFoundation/openexr-images/e38ffb0790f62f05a6f083a6fa4cac150b3b7452/LICENSE) f=LICENSE-openexr-images.txt ;;
  *) echo "curl: (22) The requested URL returned error: 404 (\$url)" >&2; exit 22 ;;
esac
cat "$SHARED/\$f" >"\$out"
if [[ -n "\${FAKE_CORRUPT:-}" && "\$f" == "\$FAKE_CORRUPT" ]]; then printf 'x' >>"\$out"; fi
EOF
chmod +x "$WORK/bin/curl"
D="$WORK/dl"
if PATH="$WORK/bin:$PATH" "$SCRIPT_DIR/fetch-assets.sh" --download --dest "$D" >"$WORK/dl.log" 2>&1; then
  grep -E '^(generated|download)' "$WORK/dl.log" | sed 's/^/      /'
  for f in "$SHARED"/*; do
    n="$(basename "$f")"
    [[ "$n" == SOURCES.md ]] && continue
    if [[ "$n" == corpus ]]; then
      # Not downloadable (derived files): the script must say so and write none of it.
      if [[ ! -e "$D/corpus" ]] && grep -q 'corpus/ (the benchmark scenes) is not downloadable' "$WORK/dl.log"; then
        ok "download mode: corpus/ not downloadable, said so"
      else
        bad "download mode: corpus/ written, or its absence not explained"
      fi
      continue
    fi
    if cmp -s "$f" "$D/$n"; then ok "download mode: $n"; else bad "download mode: $n missing or different"; fi
  done
  if ls -A "$D" | grep -q '\.tmp\.'; then bad "download mode left temp files"; fi
else
  cat "$WORK/dl.log" >&2; bad "fetch-assets.sh (download mode) exited non-zero"
fi
D="$WORK/dl-corrupt"
if PATH="$WORK/bin:$PATH" FAKE_CORRUPT=grace.hdr \
   "$SCRIPT_DIR/fetch-assets.sh" --download --dest "$D" >"$WORK/bad.log" 2>&1; then
  bad "corrupted download of grace.hdr was accepted"
else
  msg="$(grep 'error' "$WORK/bad.log" | head -1)"
  if [[ "$msg" == *grace.hdr* && ! -e "$D/grace.hdr" ]] && ! ls -A "$D" | grep -q '\.tmp\.'; then
    ok "corrupted download rejected, no partial file: $msg"
  else
    bad "corrupted download: bad message or leftover file: $msg"
  fi
fi

echo
if [[ $fail -eq 0 ]]; then echo "check-fetch-assets: ALL CHECKS PASSED"; else echo "check-fetch-assets: FAILED" >&2; fi
exit $fail
