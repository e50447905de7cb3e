#!/usr/bin/env bash
# The glossy measurements of docs/noise-and-bias.md ("Glossy surfaces"), direct light only
# (--gi none), static camera, each method against a path-traced reference of the same scene:
#   glossy: cornell-glossy, RIS vs ReSTIR over the glossy pixels (per-frame MSE, MSE after
#           FRAMES frames, flicker), with and without BSDF candidates;
#   bsdf:   scripts/scenes/glossy-floor.obj (a metal floor of roughness 0.05 under a large
#           light), RIS from light candidates alone vs RIS with BSDF candidates by MIS;
#   nee:    RIS and ReSTIR against the renderer's own NEE with BSDF MIS (--method reference
#           --gi none) at equal frame time, and ReSTIR's LONG-frame image against NEE's image
#           of the same total time (many-lights and cornell-glossy);
#   times:  the frame times of those runs again, taking turns, for the equal-time comparisons.
# Every MSE printed includes the reference's own noise; the "reference noise" lines give it
# (measured from the 1 spp NEE error: var(1 spp) / REFERENCE_SPP) so that it can be subtracted.
# References are cached in OUT_DIR (out/glossy/). Renders run under nice, one at a time.
# Usage: [WIDTH=1280 HEIGHT=720 SMALL_WIDTH=640 SMALL_HEIGHT=360 REFERENCE_SPP=2048
#         FRAMES=20 LONG=256 TIME_ROUNDS=3 OUT_DIR=out/glossy]
#        scripts/measure-glossy.sh [glossy] [bsdf] [nee] [times]   (default: all four)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

width=${WIDTH:-1280}
height=${HEIGHT:-720}
small_width=${SMALL_WIDTH:-640}
small_height=${SMALL_HEIGHT:-360}
reference_spp=${REFERENCE_SPP:-2048}
frames=${FRAMES:-20}
long=${LONG:-256}
items=("$@")
[ ${#items[@]} -gt 0 ] || items=(glossy bsdf nee times)

render=build/render/examples/pathtracer/restir-render
[ -x "$render" ] ||
  bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
dir=${OUT_DIR:-out/glossy}
mkdir -p "$dir"

# shellcheck source=scripts/measure-lib.sh
source scripts/measure-lib.sh

# reference_noise REFERENCE SPP SCENE-FLAGS...: the reference's own variance per pixel, over all
# pixels and over the glossy ones: one 1 spp NEE frame has variance v + v / SPP against it.
reference_noise() {
  local image=$1 spp=$2
  shift 2
  run "$@" --seed 3 --method reference --spp 1 --frames 3 --reference "$image" \
    --csv "$dir/noise.csv" --out "$dir/time.pfm"
  local all glossy
  all=$(stat "$dir/noise.csv" frame_rmse meansq)
  glossy=$(stat "$dir/noise.csv" frame_mse_glossy mean)
  awk -v a="$all" -v g="$glossy" -v n="$spp" -v image="$image" 'BEGIN {
    printf "reference noise (%s, %s spp): all %.3g, glossy %.3g\n", image, n, a / (n + 1), g / (n + 1) }'
}

# row LABEL CSV: a table row of the per-frame and accumulated errors of one render.
row() {
  printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "$1" "$(stat "$2" frame_ms median)" \
    "$(stat "$2" frame_rmse meansq)" "$(stat "$2" frame_mse_glossy mean)" \
    "$(stat "$2" frame_mse_glossy last)" "$(stat "$2" mse_glossy last)" \
    "$(stat "$2" rmse last)" "$(stat "$2" flicker mean)" "$(stat "$2" flicker_glossy mean)"
}
header() {
  echo "| $1 | frame ms | frame MSE | frame MSE glossy | frame $2 MSE glossy |" \
    "MSE glossy, $2 frames | RMSE, $2 frames | flicker | flicker glossy |"
  echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
}

glossy() {
  local scene=(--scene cornell-glossy --gi none --width "$width" --height "$height")
  local ref
  ref=$(reference "cornell-glossy-${width}x$height" "$reference_spp" "${scene[@]}")
  reference_noise "$ref" "$reference_spp" "${scene[@]}"
  header "cornell-glossy ${width}x$height" "$frames"
  for bsdf in 0 1 2; do
    for method in ris restir; do
      run "${scene[@]}" --seed 2 --method "$method" --bsdf-candidates "$bsdf" --frames "$frames" \
        --reference "$ref" --csv "$dir/glossy-$method-b$bsdf.csv" --out "$dir/glossy-$method-b$bsdf.png" \
        --out "$dir/glossy-$method-b$bsdf.pfm" --exposure "$(exposure "$ref")"
      row "$method, --bsdf-candidates $bsdf" "$dir/glossy-$method-b$bsdf.csv"
    done
  done
}

bsdf() {
  local scene=(--scene scripts/scenes/glossy-floor.obj --look-from 0 1.5 5 --look-at 0 0 -1 --fov 60
    --gi none --width "$small_width" --height "$small_height")
  local ref
  ref=$(reference "glossy-floor-${small_width}x$small_height" "$reference_spp" "${scene[@]}")
  reference_noise "$ref" "$reference_spp" "${scene[@]}"
  header "glossy floor ${small_width}x$small_height, RIS" 8
  run "${scene[@]}" --seed 2 --method ris --candidates 32 --frames 8 --reference "$ref" \
    --csv "$dir/floor-c32.csv" --out "$dir/floor-c32.png" --exposure "$(exposure "$ref")"
  row "32 light candidates" "$dir/floor-c32.csv"
  for bsdf in 1 2 4; do
    for candidates in 1 2 4 8 16 32; do
      run "${scene[@]}" --seed 2 --method ris --candidates "$candidates" --bsdf-candidates "$bsdf" \
        --frames 8 --reference "$ref" --csv "$dir/floor-b$bsdf-c$candidates.csv" \
        --out "$dir/floor-b$bsdf-c$candidates.png" --exposure "$(exposure "$ref")"
      row "$bsdf BSDF + $candidates light candidates" "$dir/floor-b$bsdf-c$candidates.csv"
    done
  done
}

# nee_against NAME REFERENCE SCENE-FLAGS...: RIS and ReSTIR (FRAMES frames) and NEE at 1, 2, 4
# and 8 spp (equal time: read off at the spp whose frame time matches, `times`), and ReSTIR's
# LONG-frame image against NEE's image of the same total time, from frame times measured taking
# turns just before.
nee_against() {
  local name=$1 ref=$2
  shift 2
  local spp total restir_ms=1e30 nee_ms=1e30
  for _ in 1 2 3; do
    run "$@" --seed 4 --method restir --frames 6 --csv "$dir/time.csv" --out "$dir/time.pfm"
    restir_ms=$(smaller "$restir_ms" "$(stat "$dir/time.csv" frame_ms median)")
    run "$@" --seed 4 --method reference --spp 4 --frames 6 --csv "$dir/time.csv" --out "$dir/time.pfm"
    nee_ms=$(smaller "$nee_ms" "$(stat "$dir/time.csv" frame_ms median)")
  done
  header "$name" "$frames"
  for method in ris restir "reference --spp 1" "reference --spp 2" "reference --spp 4" \
    "reference --spp 8"; do
    # shellcheck disable=SC2086 # the method and its flags
    run "$@" --seed 2 --method $method --frames "$frames" --reference "$ref" \
      --csv "$dir/$name-run.csv" --out "$dir/time.pfm"
    row "${method/reference/NEE}" "$dir/$name-run.csv"
  done
  # NEE's total: LONG ReSTIR frames of restir_ms, NEE's frames of 16 x spp / 4 x nee_ms.
  spp=$(awk -v r="$restir_ms" -v n="$nee_ms" -v f="$long" \
    'BEGIN { k = int(f * r / (n / 4) / 16 + 0.5); print k < 1 ? 1 : k }')
  run "$@" --seed 2 --method restir --frames "$long" --reference "$ref" \
    --csv "$dir/$name-restir-long.csv" --out "$dir/time.pfm"
  total=$(stat "$dir/$name-restir-long.csv" elapsed_ms last)
  run "$@" --seed 2 --method reference --spp "$spp" --frames 16 --reference "$ref" \
    --csv "$dir/$name-nee-long.csv" --out "$dir/time.pfm"
  printf '%s: frame ms restir %s, NEE at 4 spp %s; ' "$name" "$restir_ms" "$nee_ms"
  printf 'restir %s frames: rmse %s in %s ms; ' "$long" \
    "$(stat "$dir/$name-restir-long.csv" rmse last)" "$total"
  printf 'NEE --spp %s --frames 16: rmse %s in %s ms\n' "$spp" \
    "$(stat "$dir/$name-nee-long.csv" rmse last)" "$(stat "$dir/$name-nee-long.csv" elapsed_ms last)"
}

nee() {
  local size=(--width "$small_width" --height "$small_height")
  local scene=(--scene many-lights --lights 1000 --gi none --source power --candidates 32 "${size[@]}")
  local ref
  ref=$(reference "many-lights-${small_width}x$small_height" "$reference_spp" "${scene[@]}")
  reference_noise "$ref" "$reference_spp" "${scene[@]}"
  nee_against "many-lights-${small_width}x$small_height" "$ref" "${scene[@]}"
  scene=(--scene cornell-glossy --gi none "${size[@]}")
  ref=$(reference "cornell-glossy-${small_width}x$small_height" "$reference_spp" "${scene[@]}")
  reference_noise "$ref" "$reference_spp" "${scene[@]}"
  nee_against "cornell-glossy-${small_width}x$small_height" "$ref" "${scene[@]}"
}

# times [ROUNDS]: the frame times of the runs above, taking turns (the machine's load only ever
# adds time): per run, the smallest over ROUNDS rounds of the median over frames 2-6 in ms.
times() {
  local rounds=${TIME_ROUNDS:-3} n
  local glossy=(--scene cornell-glossy --gi none)
  local small=(--width "$small_width" --height "$small_height")
  local floor=(--scene scripts/scenes/glossy-floor.obj --look-from 0 1.5 5 --look-at 0 0 -1 --fov 60
    --gi none "${small[@]}" --method ris)
  local runs=(
    "${glossy[*]} --width $width --height $height --method ris"
    "${glossy[*]} --width $width --height $height --method restir"
    "${glossy[*]} --width $width --height $height --method ris --bsdf-candidates 1"
    "${glossy[*]} --width $width --height $height --method restir --bsdf-candidates 1"
    "${glossy[*]} --width $width --height $height --method ris --bsdf-candidates 2"
    "${glossy[*]} --width $width --height $height --method restir --bsdf-candidates 2"
    "${floor[*]} --candidates 32"
    "${floor[*]} --bsdf-candidates 1 --candidates 1"
    "${floor[*]} --bsdf-candidates 1 --candidates 2"
    "${floor[*]} --bsdf-candidates 2 --candidates 1"
    "${floor[*]} --bsdf-candidates 1 --candidates 4"
    "${floor[*]} --bsdf-candidates 1 --candidates 32"
    "${floor[*]} --bsdf-candidates 4 --candidates 1")
  for scene in "--scene many-lights --lights 1000 --source power --candidates 32" "--scene cornell-glossy"; do
    for method in "ris" "restir" "reference --spp 1" "reference --spp 2" "reference --spp 4" \
      "reference --spp 8"; do
      runs+=("$scene --gi none ${small[*]} --method $method")
    done
  done
  for _ in $(seq "$rounds"); do
    for n in "${!runs[@]}"; do
      # shellcheck disable=SC2086 # each run is a list of flags
      run ${runs[$n]} --frames 6 --csv "$dir/time.csv" --out "$dir/time.pfm"
      stat "$dir/time.csv" frame_ms median >>"$dir/time-$n.txt"
    done
  done
  echo "| run | frame ms |"
  echo "| --- | --- |"
  for n in "${!runs[@]}"; do
    printf '| %s | %s |\n' "${runs[$n]}" "$(sort -g "$dir/time-$n.txt" | head -n 1)"
    rm "$dir/time-$n.txt"
  done
}

for item in "${items[@]}"; do
  case "$item" in
    glossy | bsdf | nee | times) "$item" ;;
    *) echo "usage: $0 [glossy] [bsdf] [nee] [times]" >&2; exit 2 ;;
  esac
done
