#!/usr/bin/env bash
# The table of docs/vpl-unbiased.md: VPL GI (Yuksel's falloff), unbiased VPL GI (--gi
# vpl-unbiased), ReSTIR GI and path-traced indirect light (all three beside ReSTIR DI), one
# sample per pixel per frame, a still camera, whole images (direct and indirect light: the VPLs
# share ReSTIR DI's light set) against a path-traced reference of the same scene and camera:
#   SCENE:  median frame ms, per-frame MSE (mean over frames 2..FRAMES) and that times the frame
#           ms over VPL GI's, the MSE after FRAMES frames, the accumulated image's bias, and the
#           share of the last frame's squared error in its 20 worst pixels;
#   bias:   the accumulated image's mean over SEEDS seeds at 160 x 90 (8 frames) against an 8192
#           spp reference, mean +- standard error, for the whole image and the glossy box's
#           metal block (its front face, pixels 64-77 x 40-75).
#   radius: the partition's radius in the glossy box (per-frame MSE, ms, worst-20 share).
# Scenes: cornell, cornell-glossy, cornell-obj (../shared/scenes/cornell-box.obj, its materials
# made Lambertian: vpl-unbiased holds VPLs on Lambertian surfaces alone). References are cached
# in OUT_DIR with each method's accumulated image and last frame.
# Usage: [WIDTH=640 HEIGHT=360 REFERENCE_SPP=1024 FRAMES=20 SEEDS=60 OUT_DIR=out/vpl]
#        scripts/measure-vpl.sh [cornell] [cornell-glossy] [cornell-obj] [bias] [radius]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

width=${WIDTH:-640}
height=${HEIGHT:-360}
reference_spp=${REFERENCE_SPP:-1024}
frames=${FRAMES:-20}
seeds=${SEEDS:-60}
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(cornell cornell-glossy cornell-obj bias radius)

bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
cmake --build build/render --target restir-compare >/dev/null
render=build/render/examples/pathtracer/restir-render
compare=build/render/examples/pathtracer/restir-compare
dir=${OUT_DIR:-out/vpl}
mkdir -p "$dir"

# shellcheck source=scripts/measure-lib.sh
source scripts/measure-lib.sh

# row LABEL NAME REFERENCE BASELINE-PRODUCT: one method's line from its CSV and last frame.
row() {
  local csv=$dir/$2.csv ms frame_mse worst
  ms=$(stat "$csv" frame_ms median)
  frame_mse=$(stat "$csv" frame_rmse meansq)
  worst=$("$compare" "$dir/$2-frame.pfm" --reference "$3" | awk '$1 == "worst20_share" { print $2 }')
  awk -v label="$1" -v ms="$ms" -v f="$frame_mse" -v base="$4" -v r="$(stat "$csv" rmse last)" \
    -v b="$(stat "$csv" bias last)" -v w="$worst" 'BEGIN {
    printf "| %s | %+.2f %% | %.4g | %.3g | %.4g | %.1f %% | %s |\n", label, 100 * b, f,
      (base > 0 ? f * ms / base : 1), r * r, 100 * w, ms }'
}

scene_table() {
  local name=$1 flags reference_image base=0
  read -r -a flags <<<"$(box_scene_flags "$name")"
  reference_image=$(reference "$name-${width}x$height" "$reference_spp" "${flags[@]}" \
    --width "$width" --height "$height" --gi path)
  echo "## $name, ${width}x$height, $frames frames"
  echo "| method | bias | per-frame MSE | MSE x ms over VPL GI's | $frames-frame MSE | worst-20 share | frame ms |"
  echo "|---|---|---|---|---|---|---|"
  for method in vpl vpl-unbiased vpl-unbiased-reuse restir-gi path; do
    local label gi=$method method_flags=()
    case $method in
      vpl) label="VPL GI" ;;
      vpl-unbiased) label="unbiased VPL GI" ;;
      vpl-unbiased-reuse)
        label="unbiased VPL GI, paths reused" gi=vpl-unbiased method_flags=(--vpl-path-part reuse) ;;
      restir-gi) label="ReSTIR GI" ;;
      path) label="path tracing" ;;
    esac
    run "${flags[@]}" --width "$width" --height "$height" --gi "$gi" "${method_flags[@]}" \
      --frames "$frames" --seed 1 --reference "$reference_image" --csv "$dir/$name-$method.csv" \
      --out "$dir/$name-$method.pfm" --out "$dir/$name-$method.png" \
      --out-frame "$dir/$name-$method-frame.pfm"
    row "$label" "$name-$method" "$reference_image" "$base"
    if [ "$method" = vpl ]; then
      base=$(awk -v f="$(stat "$dir/$name-vpl.csv" frame_rmse meansq)" \
        -v ms="$(stat "$dir/$name-vpl.csv" frame_ms median)" 'BEGIN { print f * ms }')
    fi
  done
}

# bias_of LABEL REFERENCE REGION FLAGS...: the accumulated image's (or a region's) mean against
# REFERENCE over seeds 1..$seeds, 160 x 90, 8 frames.
bias_of() {
  local label=$1 image=$2 region=$3
  shift 3
  local region_flags=()
  [ -n "$region" ] && region_flags=(--region "$region")
  for seed in $(seq 1 "$seeds"); do
    run "$@" --width 160 --height 90 --frames 8 --seed "$seed" --out "$dir/bias.pfm"
    "$compare" "$dir/bias.pfm" --reference "$image" "${region_flags[@]}" |
      awk -v key="${region:+region_}bias" '$1 == key { print $2 }'
  done | awk -v label="$label" '{ s += $1; q += $1 * $1; n++ } END {
    m = s / n; printf "| %s | %+.2f %% +- %.2f %% |\n", label, 100 * m, 100 * sqrt((q / n - m * m) / (n - 1)) }'
}

bias_study() {
  echo "## the mean over $seeds seeds, 160x90, 8 frames"
  echo "| setup | mean against the reference |"
  echo "|---|---|"
  local name flags reference_image
  for name in cornell cornell-glossy cornell-obj; do
    read -r -a flags <<<"$(box_scene_flags "$name")"
    reference_image=$(reference "$name-160x90" 8192 "${flags[@]}" --width 160 --height 90 --gi path)
    for gi in vpl vpl-unbiased "vpl-unbiased --vpl-path-part reuse"; do
      read -r -a gi_flags <<<"$gi"
      bias_of "$name, $gi" "$reference_image" "" "${flags[@]}" --gi "${gi_flags[@]}"
      if [ "$name" = cornell-glossy ]; then
        bias_of "$name, $gi, metal block" "$reference_image" 64,40,77,75 "${flags[@]}" \
          --gi "${gi_flags[@]}"
      fi
    done
  done
}

radius_table() {
  local name reference_image flags
  echo "## the partition's radius, ${width}x$height, $frames frames"
  echo "| scene | radius (of the scene's size) | per-frame MSE | $frames-frame MSE | worst-20 share | frame ms |"
  echo "|---|---|---|---|---|---|"
  for name in cornell cornell-glossy; do
    read -r -a flags <<<"$(box_scene_flags "$name")"
    reference_image=$(reference "$name-${width}x$height" "$reference_spp" "${flags[@]}" \
      --width "$width" --height "$height" --gi path)
    for share in 0.0125 0.025 0.05 0.1 0.2; do
      local csv=$dir/radius-$name-$share.csv worst
      run "${flags[@]}" --width "$width" --height "$height" --gi vpl-unbiased \
        --partition-radius "$share" --frames "$frames" --seed 1 --reference "$reference_image" \
        --csv "$csv" --out "$dir/radius.pfm" --out-frame "$dir/radius-frame.pfm"
      worst=$("$compare" "$dir/radius-frame.pfm" --reference "$reference_image" |
        awk '$1 == "worst20_share" { print $2 }')
      awk -v n="$name" -v s="$share" -v f="$(stat "$csv" frame_rmse meansq)" \
        -v r="$(stat "$csv" rmse last)" -v w="$worst" -v ms="$(stat "$csv" frame_ms median)" \
        'BEGIN { printf "| %s | %s | %.4g | %.4g | %.1f %% | %s |\n", n, s, f, r * r, 100 * w, ms }'
    done
  done
}

for scene in "${scenes[@]}"; do
  case "$scene" in
    bias) bias_study ;;
    radius) radius_table ;;
    *) scene_table "$scene" ;;
  esac
done
