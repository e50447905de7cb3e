#!/usr/bin/env bash
# Equal-time efficiency of ReSTIR against RIS (docs/performance.md, "Equal time"): per scene two
# independent references (seeds 1 and 2, REFERENCE_SPP samples a pixel each), then each run for
# FRAMES frames at seed 3. A run's figure is its mean per-frame MSE over frames 2..N (the last
# frame alone against reference 1, frame_rmse^2 in its CSV) less reference 1's own noise (half
# the MSE between the two references), times its mean frame time: the error a frame buys per
# millisecond. Printed per run, with its ratio to the scene's first run (RIS at the defaults).
# The runs take turns ROUNDS times (default 3; the images are the same every round) and each
# keeps its smallest mean frame time: the machine's noise only ever adds time.
# Work files: out/equal-time-WIDTHxHEIGHT/.
# Usage: scripts/measure-equal-time.sh [WIDTH HEIGHT FRAMES REFERENCE_SPP]
#        (default 640 360 16 1024). SCENES="many-lights-100k cornell-100k-vpls" (the default)
#        names the scenes measured, of those listed below; RUNS
#        replaces the runs: "NAME|FLAGS;NAME|FLAGS", the first being the one the others are
#        divided by.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

width=${1:-640} height=${2:-360} frames=${3:-16} reference_spp=${4:-1024}
bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
cmake --build build/render --target restir-compare -j "$(nproc)" >/dev/null
render=build/render/examples/pathtracer/restir-render
compare=build/render/examples/pathtracer/restir-compare
dir=out/equal-time-${width}x${height}
mkdir -p "$dir"

scenes=(
  "many-lights-100k|--scene many-lights --lights 100000 --gi none"
  "cornell-100k-vpls|--scene cornell --gi vpl --vpls 100000 --vpl-seed 7"
  "many-lights-1k|--scene many-lights --lights 1000 --gi none"
  "many-lights-100k-vpls|--scene many-lights --lights 100000 --gi vpl --vpl-seed 7"
  "cornell-obj|--scene ../shared/scenes/cornell-box.obj --materials diffuse --gi vpl --vpls 100000 --vpl-seed 7"
  "cornell-glossy|--scene cornell-glossy --gi none"
  "sun-sky|--scene sun-sky --gi none"
)
IFS=';' read -r -a runs <<<"${RUNS:-ris|--method ris;restir|--method restir}"

# Mean frame_ms, mean and median frame_rmse^2 over frames 2..N of a CSV.
summary() {
  local column='NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }'
  awk -F, "$column"' NR > 2 { t += $c["frame_ms"]; e += $c["frame_rmse"] ^ 2; ++n }
    END { printf "%.2f %.6g ", t / n, e / n }' "$1"
  awk -F, "$column"' NR > 2 { printf "%.9g\n", $c["frame_rmse"] ^ 2 }' "$1" | sort -g |
    awk '{ v[NR] = $1 } END { printf "%.6g", NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}

printf '%-18s %-24s %9s %12s %12s %12s %8s\n' scene run frame_ms frame_mse median_mse \
  mse_x_ms vs_first
for entry in "${scenes[@]}"; do
  name=${entry%%|*}
  [[ " ${SCENES:-many-lights-100k cornell-100k-vpls} " == *" $name "* ]] || continue
  read -r -a args <<<"${entry#*|}"
  common=("${args[@]}" --width "$width" --height "$height")
  for seed in 1 2; do
    reference=$dir/$name-reference-$seed.exr
    [ -f "$reference" ] ||
      "$render" "${common[@]}" --seed "$seed" --method reference --spp "$reference_spp" \
        --frames 1 --out "$reference" >/dev/null
  done
  reference=$dir/$name-reference-1.exr
  reference_rmse=$("$compare" --reference "$dir/$name-reference-2.exr" "$reference" |
    awk '$1 == "rmse" { print $2 }')
  noise=$(awk -v r="$reference_rmse" 'BEGIN { printf "%.9g", r * r / 2 }')
  declare -A best_ms=()
  for ((round = 1; round <= ${ROUNDS:-3}; ++round)); do
    for run in "${runs[@]}"; do
      label=${run%%|*}
      read -r -a flags <<<"${run#*|}"
      csv=$dir/$name-$label.csv
      "$render" "${common[@]}" --seed 3 "${flags[@]}" --frames "$frames" \
        --reference "$reference" --csv "$csv" --out "$dir/$name-$label.exr" >"$dir/$name-$label.log"
      read -r ms _ <<<"$(summary "$csv")"
      best_ms[$label]=$(awk -v a="$ms" -v b="${best_ms[$label]:-}" \
        'BEGIN { printf "%.2f", b == "" || a < b ? a : b }')
    done
  done
  first=
  for run in "${runs[@]}"; do
    label=${run%%|*}
    read -r _ mse median <<<"$(summary "$dir/$name-$label.csv")"
    ms=${best_ms[$label]}
    corrected=$(awk -v e="$mse" -v n="$noise" 'BEGIN { printf "%.6g", e - n }')
    corrected_median=$(awk -v e="$median" -v n="$noise" 'BEGIN { printf "%.6g", e - n }')
    product=$(awk -v e="$corrected" -v t="$ms" 'BEGIN { printf "%.6g", e * t }')
    [ -n "$first" ] || first=$product
    printf '%-18s %-24s %9s %12s %12s %12s %8s\n' "$name" "$label" "$ms" "$corrected" \
      "$corrected_median" "$product" \
      "$(awk -v a="$product" -v b="$first" 'BEGIN { printf "%.3f", a / b }')"
  done
  echo "$name: reference noise (half the MSE between the two references) $noise"
done | tee "$dir/summary.txt"
