#!/usr/bin/env bash
# The reference study's measurement: the Cornell box of ../shared/scenes, 1 sample per pixel,
# direct + VPL light, 20 frames each of uniform light sampling, RIS and ReSTIR, RMSE of the
# accumulated image against a converged reference after every frame; then the errors at equal
# time, a convergence plot and a side-by-side image, in docs/images/. Work files: out/quality/.
# Usage: scripts/measure-quality.sh [WIDTH HEIGHT REFERENCE_SPP]   (default 1280 720 1024)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

width=${1:-1280}
height=${2:-720}
reference_spp=${3:-1024}
scene=../shared/scenes/cornell-box.obj
[ -f "$scene" ] || { echo "error: $scene not found" >&2; exit 1; }

bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
render=build/render/examples/pathtracer/restir-render
dir=out/quality
mkdir -p "$dir" docs/images
# --materials diffuse: the study treats the box as Lambertian (its MTL's Ks/Ns would add a
# specular lobe, docs/renderer.md), and so do the figures in docs/.
common=(--scene "$scene" --materials diffuse --gi vpl --width "$width" --height "$height")

# The reference (seed 1) fixes the PNG exposure of every panel.
"$render" "${common[@]}" --seed 1 --method reference --spp "$reference_spp" --frames 1 \
  --out "$dir/reference.exr" --out "$dir/reference.png" | tee "$dir/reference.log" | tail -n 1
exposure=$(sed -n 's/.*(exposure \(.*\))$/\1/p' "$dir/reference.log" | tail -n 1)

for method in uniform ris restir; do
  "$render" "${common[@]}" --seed 2 --method "$method" --frames 20 \
    --reference "$dir/reference.exr" --csv "$dir/$method.csv" --out "$dir/$method.png" \
    --exposure "$exposure" | grep '^frame 20:'
done

# RMSE after 20 frames, and at equal time: each method's last frame finished within the time
# uniform sampling took for its 20 frames.
awk -F, '
  FNR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; method = FILENAME; sub(/.*\//, "", method);
             sub(/\.csv$/, "", method); next }
  { f = $col["frame"]; rmse[method, f] = $col["rmse"]; elapsed[method, f] = $col["elapsed_ms"];
    last[method] = f }
  END {
    u = rmse["uniform", 20]
    printf "after 20 frames: uniform %.5f, ris %.5f (%.1f%% lower), restir %.5f (%.1f%% lower)\n",
      u, rmse["ris", 20], 100 * (1 - rmse["ris", 20] / u), rmse["restir", 20],
      100 * (1 - rmse["restir", 20] / u)
    budget = elapsed["uniform", last["uniform"]]
    printf "equal time, %.0f ms (uniform, 20 frames):", budget
    split("uniform ris restir", m, " ")
    for (k = 1; k <= 3; ++k) {
      best = ""; frames = 0
      for (f = 1; f <= last[m[k]]; ++f)
        if (elapsed[m[k], f] <= budget) { best = rmse[m[k], f]; frames = f }
      printf " %s %s (%d frames)%s", m[k], best == "" ? "none" : best, frames, k < 3 ? "," : "\n"
    }
  }' "$dir/uniform.csv" "$dir/ris.csv" "$dir/restir.csv" | tee "$dir/summary.txt"

bash scripts/plot-convergence.sh docs/images/convergence.png uniform="$dir/uniform.csv" \
  ris="$dir/ris.csv" restir="$dir/restir.csv"
TILE_WIDTH=640 bash scripts/side-by-side.sh docs/images/side-by-side.jpg "uniform, 20 frames=$dir/uniform.png" \
  "RIS, 20 frames=$dir/ris.png" "ReSTIR, 20 frames=$dir/restir.png" \
  "reference, $reference_spp spp=$dir/reference.png"
echo "wrote docs/images/convergence.png, docs/images/side-by-side.jpg, $dir/summary.txt"
