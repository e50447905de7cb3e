#!/usr/bin/env bash
# Bias of each reuse weighting (docs/noise-and-bias.md): ReSTIR with 1/M, 1/Z, the balance
# heuristic and pairwise MIS, each with and without the MIS shadow rays, on the built-in Cornell
# box with VPLs, the many-light scene and ../shared/scenes/cornell-box.obj with VPLs. For each,
# 20 frames against a reference of the same integrand (the same VPL set, `--method reference`),
# and the bias as the relative difference of the image means: after 20 frames (accumulated
# image), and the mean of the single frames' with its standard error over the frames (frames
# are correlated by temporal reuse, so that error is a rough guide). Work files: out/bias/.
# Usage: scripts/measure-bias.sh [WIDTH HEIGHT REFERENCE_SPP FRAMES]   (default 320 180 1024 20)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

width=${1:-320}
height=${2:-180}
reference_spp=${3:-1024}
frames=${4:-20}
obj=../shared/scenes/cornell-box.obj
[ -f "$obj" ] || { echo "error: $obj not found" >&2; exit 1; }

bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
render=build/render/examples/pathtracer/restir-render
dir=out/bias
mkdir -p "$dir"

echo "| scene | weights | MIS rays | bias, $frames frames | per-frame bias (SE) |"
echo "| --- | --- | --- | --- | --- |"
for scene in cornell many-lights obj; do
  case $scene in
  cornell) args=(--scene cornell --gi vpl) ;;
  many-lights) args=(--scene many-lights --lights 1000 --gi none) ;;
  obj) args=(--scene "$obj" --materials diffuse --gi vpl) ;; # Lambertian, as in docs/
  esac
  args+=(--width "$width" --height "$height" --seed 1)
  "$render" "${args[@]}" --method reference --spp "$reference_spp" --frames 1 \
    --out "$dir/$scene-reference.exr" >/dev/null
  for weights in none one-over-z balance-heuristic pairwise; do
    for rays in true false; do
      [ "$weights" = none ] && [ "$rays" = false ] && continue
      name=$scene-$weights-$rays
      "$render" "${args[@]}" --method restir --frames "$frames" --bias-correction "$weights" \
        --mis-rays "$rays" --reference "$dir/$scene-reference.exr" --csv "$dir/$name.csv" \
        --out "$dir/$name.exr" >/dev/null
      awk -F, -v scene="$scene" -v weights="$weights" -v rays="$rays" '
        NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
        { n++; b = $col["frame_bias"]; s += b; ss += b * b; last = $col["bias"] }
        END {
          mean = s / n; se = n > 1 ? sqrt((ss - n * mean * mean) / (n - 1) / n) : 0
          printf "| %s | %s | %s | %+.2f %% | %+.2f %% (%.2f) |\n", scene, weights,
            weights == "none" ? "-" : (rays == "true" ? "yes" : "no"), 100 * last, 100 * mean,
            100 * se }' "$dir/$name.csv"
    done
  done
done
