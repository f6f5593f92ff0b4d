#!/usr/bin/env bash
# fetch-assets.sh — fill envshadow's assets/ folder with the test assets.
# Run with --help for details.  Provenance of every file: SOURCES.md (shared folder).
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
REPO_ROOT="$(cd "$SCRIPT_DIR/.." && pwd)"
CONVERTER="$SCRIPT_DIR/ply_to_glb.py"

DEST="$REPO_ROOT/assets"
SOURCE_DEFAULT="$REPO_ROOT/../shared/assets"
SOURCE=""
SOURCE_GIVEN=0
MODE="auto"          # auto | copy | download
VERIFY=1

# ---------------------------------------------------------------------------
# Manifest: name | sha256 | origin.  Origins are pinned commits; "generated:"
# entries are built locally from an already fetched PLY with ply_to_glb.py.
# Hashes were computed from the shared assets folder (see SOURCES.md).
# ---------------------------------------------------------------------------
R_BUNNY="https://raw.githubusercontent.com/ksnabb/stan_bun/3f304b79052f2023f22ef8e5d15b7e571665ac16/bunny/reconstruction"
R_DREI="https://raw.githubusercontent.com/pmndrs/drei-assets/456060a26bbeb8fdf79326f224b6d99b8bcce736/hdri"
R_PROBU="https://raw.githubusercontent.com/kayru/Probulator/ad916bda84a6383ec34a69eaf2f3444bfef6026d/Data/Probes"
R_EXR="https://raw.githubusercontent.com/AcademySoftwareFoundation/openexr-images/e38ffb0790f62f05a6f083a6fa4cac150b3b7452"

# Order matters: PLYs come before the .glb files generated from them.
MANIFEST=(
  "bun_zipper.ply|e5bfa06a738e5c59e4c147c6edc17df99e09735daa3432391e841fba825a2a33|$R_BUNNY/bun_zipper.ply"
  "bun_zipper_res2.ply|8faa052bb08cf1625eec97b6508baceee11eec9cf28f83f6a9d4547ab15d7761|$R_BUNNY/bun_zipper_res2.ply"
  "bun_zipper_res3.ply|d628625d14fbe5deecb123536b515405c522984d43488cc24f91980eb75edadc|$R_BUNNY/bun_zipper_res3.ply"
  "bun_zipper_res4.ply|2ca4b1c9206eb2768f10eeb06f30d2dcf576c21f69243335660c896605d1f0ab|$R_BUNNY/bun_zipper_res4.ply"
  "bun_zipper_README.txt|91cd6c3a1b21008ccc4169ff2bde4732243ccb4b68ab99e10c09fdd7a6496eac|$R_BUNNY/README"
  "bunny.glb|51a69885e6d3657945fc2f36884333d08cf362b1b469ea59d3c39b1717beea21|generated:bun_zipper.ply"
  "bunny_on_plane.glb|eb798718c5127ded760b006ddd28d46c51a1cce2ec5ca96dceca8664648affd1|generated:bun_zipper.ply --ground"
  "bunny_res4.glb|240efa7cab11d7378be546290842958b5135f7b747f9320ddac7395e43451cc1|generated:bun_zipper_res4.ply"
  "studio_small_03_1k.hdr|29267a4aa8c10de26cae758e4e3c4daadde88673798666ad657724bab7224a35|$R_DREI/studio_small_03_1k.hdr"
  "rooitou_park_1k.hdr|af15cb5ca49de469e2ee74fcb6622cb32b36e3f9ee95504fc762d9c3d62c5163|$R_DREI/rooitou_park_1k.hdr"
  "grace.hdr|14abacf9522a7a1731b9d6396898059430a3bef6bac0a14f6acbce5cbb9c73cd|$R_PROBU/grace.hdr"
  "KernerEnvLatLong.exr|ce51d01973fbbe5388b335c83cc1dba3d0d8127207985f3d02501a05ba32af6d|$R_EXR/MultiResolution/KernerEnvLatLong.exr"
  "OrientationLatLong.exr|89d355540e7fa5e849daa6e979d6dbff813c42dd6e9195e187a81fc09d869158|$R_EXR/MultiResolution/OrientationLatLong.exr"
  "LICENSE-openexr-images.txt|e09f669c94b61172cd355c36b8737721df12eb4e4fa570600ac1955c9686327f|$R_EXR/LICENSE"
)
# Copied as documentation when present in the source folder (not hash-checked,
# not downloadable: it only exists in the shared folder).
DOC_FILES=(SOURCES.md)

# The benchmark corpus (corpus/, see corpus/SOURCES.md): ten glTF scenes built by
# corpus/build_corpus.py from files of two public repositories, with their sources,
# licences and the build script. Copied (hash-checked) in copy mode; not downloadable:
# the .glb files are derived, and rebuilding them needs the source repositories and
# Python's trimesh (corpus/SOURCES.md says how).
CORPUS=(
  "ATTRIBUTION.txt|42623c020e318a9160036eb73783794de8526496a8f104ee59858feccc2bcca4"
  "LICENSE-bevy-MIT.txt|508a77d2e7b51d98adeed32648ad124b7b30241a8e70b2e72c99f92d8e5874d1"
  "SOURCES.md|09a3326033a82ef1c9661119743dc1b92a66c8ce823c18549a8010e78045546e"
  "alpha_mask_panels.glb|06565e2255df9a8b8c13de85e3da4ce7a85f29fd4bb8cf90d41a924a1db17e7c"
  "build_corpus.py|a00ae6c7fb9a7450f32ee45cdec835c91aecde9a128c9dcea6855a7a010adc81"
  "golf_ball.glb|c1d9002a245947ac01d660380327cd3765654f08a0c4520bd4cb165494354a40"
  "lion_statue.glb|6bb1a3d5edc2966d15c11ca8d4dcfc230f3a1323312503c29a77c57f29ed4764"
  "metal_rough_spheres.glb|63d1171c71c1e82bec8f04a2dc832e38a4a8ac3f2842df72363eae84b4de7eb3"
  "objects_on_circuit_board.glb|f1d6ff05ce69201b2a8cb5e03d9cdcc94f1100bc560e7462be59e00b8c0bb496"
  "palm_tree.glb|39c2110fdea29e68fc40e9d3672b754d0140d646ab5dc3e822401af57637015e"
  "sheen_chair_scene.glb|333609686ee793ba8be33f6a4edcc1c52a1dc0579edc1c6d804ac94b6b6b8ba5"
  "skull.glb|50b835117fe0233cacd2f1964ce406adaba6c8118bf989acdf2c6d33a34925da"
  "spot.glb|35c6cdecf4d01ad878ea4b6959c8212281ad9a4ff037b094c77a29a26dac169d"
  "toy_plane.glb|623899606144b8c6fb8fee14c652df713c925c76a34deb302b764059083dad37"
)

usage() {
  cat <<EOF
Usage: scripts/fetch-assets.sh [--dest DIR] [--source DIR] [--download] [--no-verify] [--help]

Fills envshadow's test-asset folder (default: <repo>/assets, which is git-ignored)
with the Stanford bunny meshes, the bunny glTF scenes and the HDR/EXR environment
maps described in SOURCES.md.

Two modes:

  copy      If the shared folder exists -- <repo>/../shared/assets by default, or the
            folder given with --source -- the files are copied from it with cp,
            keeping their names.  Files already in the destination with identical
            content are skipped; differing ones are replaced.  SOURCES.md is copied
            too, and corpus/ (the benchmark scenes) when the source has it.  A .glb
            missing from the source folder is generated from the PLY.

  download  Otherwise (or with --download) every file is fetched from its public
            origin with 'curl -fL --retry 3', from raw.githubusercontent.com at a
            pinned commit:
              ksnabb/stan_bun@3f304b7            bunny/reconstruction/{bun_zipper*.ply,README}
              pmndrs/drei-assets@456060a         hdri/{studio_small_03_1k,rooitou_park_1k}.hdr
              kayru/Probulator@ad916bd           Data/Probes/grace.hdr
              AcademySoftwareFoundation/openexr-images@e38ffb0
                                                 MultiResolution/{Kerner,Orientation}LatLong.exr,
                                                 LICENSE (saved as LICENSE-openexr-images.txt)
            The .glb files are not downloadable: they are generated from the
            downloaded PLY files with scripts/ply_to_glb.py (Python 3, standard
            library only):
              bunny.glb           <- bun_zipper.ply
              bunny_on_plane.glb  <- bun_zipper.ply --ground
              bunny_res4.glb      <- bun_zipper_res4.ply
            The conversion is byte-reproducible, so generated files are checked
            against the same SHA-256 as the shared copies.  SOURCES.md is not
            downloadable and is skipped in this mode, and so is corpus/ (the
            benchmark scenes): its .glb files are built from two public
            repositories by corpus/build_corpus.py (see corpus/SOURCES.md).

Every file (downloaded, generated or copied) is checked against a SHA-256 embedded
in this script; a file that is already present and matches is left alone.  Files
are written under a temporary name in the destination and renamed into place, so an
interrupted run never leaves a partial file behind.  On any failure the script stops
with a non-zero exit status and a message naming the file.

Options:
  --dest DIR     destination folder (default: $REPO_ROOT/assets)
  --source DIR   shared folder to copy from (default: <repo>/../shared/assets);
                 it is an error if a folder given here does not exist
  --download     download from the public origins even if a shared folder exists
  --no-verify    copy mode only: do not check SHA-256 of copied files
  -h, --help     show this help

Licences (a reminder is printed after every run):
  * Stanford bunny (bun_zipper*.ply, README, and the derived .glb files): Stanford
    3D Scanning Repository terms -- free for research, may be redistributed at no
    charge, credit the Stanford University Computer Graphics Laboratory; commercial
    use needs Stanford's permission.
  * studio_small_03_1k.hdr, rooitou_park_1k.hdr: Poly Haven, CC0 1.0.
  * grace.hdr: Paul Debevec / USC ICT light probe -- free for research use with
    credit; no commercial use.
  * KernerEnvLatLong.exr, OrientationLatLong.exr: (c) 2004 Industrial Light & Magic,
    BSD-3-Clause-style licence; LICENSE-openexr-images.txt must stay beside them.
EOF
}

die() { echo "fetch-assets: error: $*" >&2; exit 1; }

while [[ $# -gt 0 ]]; do
  case "$1" in
    --dest)      [[ $# -ge 2 ]] || die "--dest needs a directory"; DEST="$2"; shift 2 ;;
    --dest=*)    DEST="${1#--dest=}"; shift ;;
    --source)    [[ $# -ge 2 ]] || die "--source needs a directory"; SOURCE="$2"; SOURCE_GIVEN=1; shift 2 ;;
    --source=*)  SOURCE="${1#--source=}"; SOURCE_GIVEN=1; shift ;;
    --download)  MODE="download"; shift ;;
    --no-verify) VERIFY=0; shift ;;
    -h|--help)   usage; exit 0 ;;
    *)           die "unknown argument '$1' (see --help)" ;;
  esac
done

if [[ $SOURCE_GIVEN -eq 1 ]]; then
  [[ -d "$SOURCE" ]] || die "--source folder '$SOURCE' does not exist"
else
  SOURCE="$SOURCE_DEFAULT"
fi
if [[ "$MODE" == "auto" ]]; then
  if [[ -d "$SOURCE" ]]; then MODE="copy"; else MODE="download"; fi
fi

if command -v sha256sum >/dev/null 2>&1; then
  sha256() { sha256sum "$1" | cut -d' ' -f1; }
elif command -v shasum >/dev/null 2>&1; then
  sha256() { shasum -a 256 "$1" | cut -d' ' -f1; }
else
  die "neither sha256sum nor shasum is available"
fi

mkdir -p "$DEST" || die "cannot create destination folder '$DEST'"
DEST="$(cd "$DEST" && pwd)"

# Temporary files live in DEST (same filesystem, so mv is an atomic rename).
TMPFILES=()
cleanup() {
  local f
  for f in "${TMPFILES[@]+"${TMPFILES[@]}"}"; do rm -f -- "$f"; done
}
trap cleanup EXIT
trap 'echo "fetch-assets: interrupted" >&2; exit 130' INT TERM

new_tmp() {  # new_tmp NAME -> sets $tmp to a fresh temp path for NAME in DEST
  # (not via $(...): the subshell would lose the TMPFILES registration; a NAME in a
  # subfolder gets its temp file in DEST itself, the same filesystem)
  tmp="$DEST/.${1//\//_}.tmp.$$"
  rm -f -- "$tmp"
  TMPFILES+=("$tmp")
}

check_hash() {  # check_hash FILE_ON_DISK NAME EXPECTED
  local got
  got="$(sha256 "$1")" || die "$2: cannot compute SHA-256"
  [[ "$got" == "$3" ]] || die "$2: SHA-256 mismatch (expected $3, got $got)"
}

n_done=0; n_skip=0

generate_glb() {  # generate_glb NAME EXPECTED_SHA "PLY [FLAGS]"
  local name="$1" want="$2" spec="$3" ply flags tmp
  ply="${spec%% *}"; flags=""
  [[ "$spec" == *" "* ]] && flags="${spec#* }"
  [[ -f "$DEST/$ply" ]] || die "$name: needs $ply in $DEST, which is missing"
  command -v python3 >/dev/null 2>&1 || die "$name: python3 is needed to run $CONVERTER"
  [[ -f "$CONVERTER" ]] || die "$name: converter $CONVERTER not found"
  new_tmp "$name"
  # shellcheck disable=SC2086
  python3 "$CONVERTER" "$DEST/$ply" "$tmp" $flags --quiet \
    || die "$name: conversion from $ply failed"
  check_hash "$tmp" "$name (generated from $ply)" "$want"
  mv -f -- "$tmp" "$DEST/$name" || die "$name: cannot rename into $DEST"
  echo "generated  $name  <- ply_to_glb.py $ply${flags:+ $flags}  (sha256 ok, byte-identical)"
  n_done=$((n_done + 1))
}

copy_file() {  # copy_file NAME: SOURCE/NAME to DEST/NAME, unless an identical copy is there
  local name="$1" src="$SOURCE/$1" action="copied    " tmp
  if [[ -f "$DEST/$name" ]] && cmp -s -- "$src" "$DEST/$name"; then
    echo "skipped    $name  (identical copy already present)"; n_skip=$((n_skip + 1))
    return
  fi
  [[ -e "$DEST/$name" ]] && action="replaced  "
  new_tmp "$name"
  cp -- "$src" "$tmp" || die "$name: copy from $SOURCE failed"
  chmod u+w -- "$tmp" 2>/dev/null || true
  cmp -s -- "$src" "$tmp" || die "$name: copy differs from source (disk full?)"
  mv -f -- "$tmp" "$DEST/$name" || die "$name: cannot rename into $DEST"
  echo "$action $name"
  n_done=$((n_done + 1))
}

if [[ "$MODE" == "copy" ]]; then
  SOURCE="$(cd "$SOURCE" && pwd)"
  echo "fetch-assets: copying from $SOURCE to $DEST"
  for entry in "${MANIFEST[@]}"; do
    IFS='|' read -r name want origin <<<"$entry"
    src="$SOURCE/$name"
    if [[ ! -f "$src" ]]; then
      if [[ "$origin" == generated:* ]]; then
        if [[ -f "$DEST/$name" && "$(sha256 "$DEST/$name")" == "$want" ]]; then
          echo "skipped    $name  (not in source; present and sha256 ok)"; n_skip=$((n_skip + 1))
        else
          generate_glb "$name" "$want" "${origin#generated:}"
        fi
        continue
      fi
      die "$name: missing from source folder $SOURCE"
    fi
    if [[ $VERIFY -eq 1 ]]; then check_hash "$src" "$name (in $SOURCE)" "$want"; fi
    copy_file "$name"
  done
  for name in "${DOC_FILES[@]}"; do
    [[ -f "$SOURCE/$name" ]] || { echo "note       $name not in source folder, not copied"; continue; }
    copy_file "$name"
  done
  if [[ -d "$SOURCE/corpus" ]]; then
    mkdir -p "$DEST/corpus" || die "cannot create $DEST/corpus"
    for entry in "${CORPUS[@]}"; do
      IFS='|' read -r file want <<<"$entry"
      name="corpus/$file"; src="$SOURCE/$name"
      [[ -f "$src" ]] || die "$name: missing from source folder $SOURCE"
      if [[ $VERIFY -eq 1 ]]; then check_hash "$src" "$name (in $SOURCE)" "$want"; fi
      copy_file "$name"
    done
  else
    echo "note       corpus/ not in source folder, not copied"
  fi
else
  if [[ -d "$SOURCE" ]]; then
    echo "fetch-assets: --download given; ignoring shared folder $SOURCE"
  else
    echo "fetch-assets: shared folder $SOURCE not found"
  fi
  echo "fetch-assets: downloading from pinned public origins into $DEST"
  command -v curl >/dev/null 2>&1 || die "curl is needed to download the assets"
  for entry in "${MANIFEST[@]}"; do
    IFS='|' read -r name want origin <<<"$entry"
    if [[ -f "$DEST/$name" && "$(sha256 "$DEST/$name")" == "$want" ]]; then
      echo "skipped    $name  (present, sha256 ok)"; n_skip=$((n_skip + 1))
      continue
    fi
    if [[ "$origin" == generated:* ]]; then
      generate_glb "$name" "$want" "${origin#generated:}"
      continue
    fi
    new_tmp "$name"
    echo "download   $name  <- $origin"
    curl -fL --retry 3 --silent --show-error -o "$tmp" -- "$origin" \
      || die "$name: download failed from $origin"
    check_hash "$tmp" "$name (downloaded from $origin)" "$want"
    mv -f -- "$tmp" "$DEST/$name" || die "$name: cannot rename into $DEST"
    echo "           $name  sha256 ok"
    n_done=$((n_done + 1))
  done
  echo "note       SOURCES.md (provenance notes) exists only in the shared folder; not downloaded"
  echo "note       corpus/ (the benchmark scenes) is not downloadable: its .glb files are built by"
  echo "           corpus/build_corpus.py from two public repositories (corpus/SOURCES.md); copy it"
  echo "           from a shared folder with --source DIR"
fi

echo "fetch-assets: done: $n_done written, $n_skip already up to date, in $DEST"
cat <<'EOF'

Licence reminder -- these assets are NOT covered by envshadow's own licence:
  * Stanford bunny (bun_zipper*.ply, bun_zipper_README.txt, bunny*.glb derived from it):
    Stanford 3D Scanning Repository terms. Free for research and may be redistributed
    at no charge; credit "Stanford Bunny, courtesy of the Stanford University Computer
    Graphics Laboratory". Commercial use or use in a product for sale needs Stanford's
    permission.
  * studio_small_03_1k.hdr, rooitou_park_1k.hdr: Poly Haven, CC0 1.0 (public domain).
  * grace.hdr: Grace Cathedral light probe, Paul Debevec / USC ICT. Free for research
    use with credit to Paul Debevec and USC ICT; do not use commercially.
  * KernerEnvLatLong.exr, OrientationLatLong.exr: (c) 2004 Industrial Light & Magic,
    BSD-3-Clause-style licence. Keep LICENSE-openexr-images.txt next to them when
    redistributing.
EOF
