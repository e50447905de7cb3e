#!/usr/bin/env bash
# The ReSTIR PT comparison of docs/restir-pt.md: the indirect light alone (--indirect-only) of
# path tracing, ReSTIR GI and ReSTIR PT, one path per pixel per frame beside ReSTIR DI, a still
# camera, seed 2, against a path-traced indirect-only reference of REFERENCE_SPP samples:
#   per-frame MSE over the whole image and over the glossy pixels (mean over frames 2..FRAMES
#   of each frame alone), the median frame time, MSE x time relative to ReSTIR GI's and to path
#   tracing's (below 1 is better at equal time), the MSE after FRAMES frames and its bias.
# The reference's own noise, path tracing's per-frame MSE / (REFERENCE_SPP + 1), is printed too.
#   bias:  the indirect light's mean over SEEDS seeds at 80 x 60 (FRAMES frames) against an 8192
#          spp reference, mean +- standard error, ReSTIR PT and path tracing, glossy and diffuse
#          box.
# Usage: [WIDTH=640 HEIGHT=360 REFERENCE_SPP=1024 FRAMES=20 SEEDS=60 OUT_DIR=out/pt]
#        scripts/measure-pt.sh [cornell-glossy] [cornell] [cornell-obj] [bias]  (default: all)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

width=${WIDTH:-640}
height=${HEIGHT:-360}
reference_spp=${REFERENCE_SPP:-1024}
frames=${FRAMES:-20}
seeds=${SEEDS:-60}
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(cornell-glossy cornell cornell-obj bias)

render=build/render/examples/pathtracer/restir-render
[ -x "$render" ] ||
  bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
dir=${OUT_DIR:-out/pt}
mkdir -p "$dir"

# shellcheck source=scripts/measure-lib.sh
source scripts/measure-lib.sh

# table SCENE: the three methods' rows.
table() {
  local name=$1 flags
  read -r -a flags <<<"$(box_scene_flags "$name")"
  local common=("${flags[@]}" --width "$width" --height "$height" --frames "$frames" --seed 2
    --indirect-only)
  local indirect
  indirect=$(reference "$name-indirect" "$reference_spp" "${flags[@]}" --width "$width" \
    --height "$height" --gi path --indirect-only)
  for gi in path restir-gi restir-pt; do
    run "${common[@]}" --gi "$gi" --reference "$indirect" --csv "$dir/$name-$gi.csv" \
      --out "$dir/$name-$gi.pfm" --out-frame "$dir/$name-$gi-frame.pfm"
  done
  echo "## $name, indirect light (${width}x$height, $frames frames, reference $reference_spp spp)"
  echo "| method | frame ms | per-frame MSE | glossy per-frame MSE | MSE x ms / restir-gi's (glossy) | / path's (glossy) | MSE after $frames | bias after $frames |"
  echo "|---|---|---|---|---|---|---|---|"
  local gi
  for gi in path restir-gi restir-pt; do
    local csv=$dir/$name-$gi.csv g=$dir/$name-restir-gi.csv p=$dir/$name-path.csv
    awk -v label="$gi" -v ms="$(stat "$csv" frame_ms median)" \
      -v m="$(stat "$csv" frame_rmse meansq)" -v mg="$(stat "$csv" frame_mse_glossy mean)" \
      -v gms="$(stat "$g" frame_ms median)" -v gm="$(stat "$g" frame_rmse meansq)" \
      -v gmg="$(stat "$g" frame_mse_glossy mean)" \
      -v pms="$(stat "$p" frame_ms median)" -v pm="$(stat "$p" frame_rmse meansq)" \
      -v pmg="$(stat "$p" frame_mse_glossy mean)" \
      -v r="$(stat "$csv" rmse last)" -v b="$(stat "$csv" bias last)" 'BEGIN {
        rg = mg > 0 && gmg > 0 ? sprintf(" (%.3f)", mg * ms / (gmg * gms)) : ""
        rp = mg > 0 && pmg > 0 ? sprintf(" (%.3f)", mg * ms / (pmg * pms)) : ""
        printf "| %s | %.1f | %.4g | %.4g | %.3f%s | %.3f%s | %.4g | %+.2f %% |\n", label, ms, m, mg,
          m * ms / (gm * gms), rg, m * ms / (pm * pms), rp, r * r, 100 * b }'
  done
  awk -v p="$(stat "$dir/$name-path.csv" frame_rmse meansq)" -v n="$reference_spp" \
    'BEGIN { printf "reference noise (path per-frame MSE / %d): %.3g\n\n", n + 1, p / (n + 1) }'
}

bias_study() {
  echo "## the indirect light's mean over $seeds seeds, 80x60, $frames frames"
  echo "| setup | mean against the reference |"
  echo "|---|---|"
  local name image
  for name in cornell-glossy cornell; do
    image=$(reference "$name-80x60-indirect" 8192 --scene "$name" --width 80 --height 60 \
      --gi path --indirect-only)
    for gi in restir-pt path; do
      bias_over_seeds "$name, $gi" "$image" --scene "$name" --gi "$gi" --frames "$frames"
    done
  done
}

for name in "${scenes[@]}"; do
  if [ "$name" = bias ]; then
    bias_study
  else
    table "$name"
  fi
done
