#!/usr/bin/env bash
# The GI comparison of docs/restir-gi.md: VPL GI (ReSTIR DI over the emitters and VPLs), ReSTIR
# GI and path-traced indirect light (both beside ReSTIR DI), one sample per pixel per frame, a
# still camera, against path-traced references of the same scene and camera:
#   full:     each method's whole image against the reference (--method reference --gi path):
#             median frame time, per-frame MSE (mean over frames 2..FRAMES), MSE after FRAMES
#             frames, and the accumulated image's relative mean difference (bias);
#   indirect: ReSTIR GI and path tracing with --indirect-only against an indirect-only
#             reference: per-frame MSE, and ReSTIR GI's per-frame MSE x frame time over path
#             tracing's (the equal-time ratio; frame times include the direct light's frame).
# The reference's own noise is in every MSE: "reference noise" is path tracing's per-frame
# indirect MSE / (REFERENCE_SPP + 1), the part of each indirect MSE that is the reference's.
# Scenes: cornell (built in), cornell-obj (../shared/scenes/cornell-box.obj, its materials
# diffuse), many-lights (10k emissive quads).
#   bias:     the mean of the indirect light over SEEDS seeds at 80 x 60 against an 8192 spp
#             reference, mean +- standard error: every bias correction in the Cornell box (8
#             frames), the reconnection rule at 1 and 0.5 in the glossy box (8 frames), ReSTIR GI
#             and path tracing with many lights (20 frames). References are cached in OUT_DIR, with each
# method's accumulated image (NAME-METHOD.png) and last frame alone (NAME-METHOD-frame.png).
# Usage: [WIDTH=640 HEIGHT=360 REFERENCE_SPP=1024 FRAMES=20 VPLS=100000 SEEDS=60 OUT_DIR=out/gi]
#        scripts/measure-gi.sh [cornell] [cornell-obj] [many-lights] [bias]   (default: all four)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

width=${WIDTH:-640}
height=${HEIGHT:-360}
reference_spp=${REFERENCE_SPP:-1024}
frames=${FRAMES:-20}
vpls=${VPLS:-100000}
seeds=${SEEDS:-60}
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(cornell cornell-obj many-lights bias)

render=build/render/examples/pathtracer/restir-render
[ -x "$render" ] ||
  bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
dir=${OUT_DIR:-out/gi}
mkdir -p "$dir"

# shellcheck source=scripts/measure-lib.sh
source scripts/measure-lib.sh

scene_flags() {
  case "$1" in
    cornell) echo "--scene cornell" ;;
    cornell-obj) echo "--scene ../shared/scenes/cornell-box.obj --materials diffuse" ;;
    many-lights) echo "--scene many-lights --lights 10000 --source power --candidates 32" ;;
    *) echo "unknown scene '$1' (cornell, cornell-obj, many-lights)" >&2; exit 2 ;;
  esac
}

# row LABEL CSV: median frame time, per-frame MSE, MSE after FRAMES frames, bias.
row() {
  local rmse
  rmse=$(stat "$2" rmse last)
  printf '| %s | %s | %.4g | %.4g | %+.2f %% |\n' "$1" "$(stat "$2" frame_ms median)" \
    "$(stat "$2" frame_rmse meansq)" "$(awk -v r="$rmse" 'BEGIN { print r * r }')" \
    "$(awk -v b="$(stat "$2" bias last)" 'BEGIN { print 100 * b }')"
}

bias_study() {
  echo "## the indirect light's mean over $seeds seeds, 80x60"
  echo "| setup | mean against the reference |"
  echo "|---|---|"
  local name reference_image
  for name in cornell cornell-glossy many-lights; do
    local flags=(--scene "$name")
    [ "$name" = many-lights ] && flags+=(--lights 10000 --source power --candidates 32)
    reference_image=$(reference "$name-80x60-indirect" 8192 "${flags[@]}" --width 80 --height 60 \
      --gi path --indirect-only)
    case "$name" in
      cornell)
        for mode in none one-over-z balance-heuristic pairwise; do
          bias_over_seeds "cornell, restir-gi, $mode, 8 frames" "$reference_image" "${flags[@]}" \
            --gi restir-gi --bias-correction "$mode" --frames 8
        done ;;
      cornell-glossy)
        for rule in 1 0.5; do
          bias_over_seeds "cornell-glossy, restir-gi, --gi-min-roughness $rule, 8 frames" \
            "$reference_image" "${flags[@]}" --gi restir-gi --gi-min-roughness "$rule" --frames 8
        done
        bias_over_seeds "cornell-glossy, path, 8 frames" "$reference_image" "${flags[@]}" \
          --gi path --frames 8 ;;
      many-lights)
        for gi in restir-gi path; do
          bias_over_seeds "many-lights, $gi, 20 frames" "$reference_image" "${flags[@]}" --gi "$gi" \
            --frames 20
        done ;;
    esac
  done
}

for name in "${scenes[@]}"; do
  if [ "$name" = bias ]; then
    bias_study
    continue
  fi
  read -r -a flags <<<"$(scene_flags "$name")"
  common=("${flags[@]}" --width "$width" --height "$height" --frames "$frames" --seed 2)
  full=$(reference "$name-full" "$reference_spp" "${flags[@]}" --width "$width" \
    --height "$height" --gi path)
  indirect=$(reference "$name-indirect" "$reference_spp" "${flags[@]}" --width "$width" \
    --height "$height" --gi path --indirect-only)
  echo "## $name (${width}x$height, $frames frames, references $reference_spp spp)"
  echo "| method | frame ms | per-frame MSE | MSE after $frames | bias after $frames |"
  echo "|---|---|---|---|---|"
  for gi in vpl restir-gi path; do
    run "${common[@]}" --gi "$gi" --vpls "$vpls" --reference "$full" --csv "$dir/$name-$gi.csv" \
      --out "$dir/$name-$gi.png" --out-frame "$dir/$name-$gi-frame.png" \
      --exposure "$(exposure "$full")"
    row "$gi" "$dir/$name-$gi.csv"
  done
  for gi in restir-gi path; do
    run "${common[@]}" --gi "$gi" --indirect-only --reference "$indirect" \
      --csv "$dir/$name-$gi-indirect.csv" --out "$dir/$name-$gi-indirect.png" \
      --exposure "$(exposure "$indirect")"
  done
  gi_csv=$dir/$name-restir-gi-indirect.csv path_csv=$dir/$name-path-indirect.csv
  awk -v g="$(stat "$gi_csv" frame_rmse meansq)" -v gt="$(stat "$gi_csv" frame_ms median)" \
    -v p="$(stat "$path_csv" frame_rmse meansq)" -v pt="$(stat "$path_csv" frame_ms median)" \
    -v gb="$(stat "$gi_csv" bias last)" -v pb="$(stat "$path_csv" bias last)" \
    -v n="$reference_spp" -v f="$frames" 'BEGIN {
      printf "indirect only: per-frame MSE restir-gi %.4g (%.1f ms), path %.4g (%.1f ms); ", g, gt, p, pt
      printf "MSE x time restir-gi / path %.3f; bias after %s frames restir-gi %+.2f %%, ", g * gt / (p * pt), f, 100 * gb
      printf "path %+.2f %%; reference noise %.3g\n", 100 * pb, p / (n + 1) }'
done
