#!/usr/bin/env bash
# The candidate sources side by side (docs/performance.md, "Candidate sources"): for each scene
# a reference, then RIS and ReSTIR with power, bvh and grid candidates at several candidate
# counts; for each run the mean frame time and the mean and median per-frame MSE (the last
# frame alone against the reference, frame_rmse^2) over frames 2..N, one line each, so that
# runs of equal time can be compared (the median is the steadier where rare bright pixels make
# a few frames' error many times the others'). Work files: out/sources-WIDTHxHEIGHT/.
# Usage: scripts/measure-sources.sh [WIDTH HEIGHT FRAMES REFERENCE_SPP]  (default 640 360 12 1024)
# SCENES="many-lights-100k many-lights-1M" measures those scenes alone; RUNS as below.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

width=${1:-640}
height=${2:-360}
frames=${3:-12}
reference_spp=${4:-1024}

bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
render=build/render/examples/pathtracer/restir-render
dir=out/sources-${width}x${height}
mkdir -p "$dir"

scenes=(
  "many-lights-1k|--scene many-lights --lights 1000 --gi none"
  "many-lights-100k|--scene many-lights --lights 100000 --gi none"
  "many-lights-1M|--scene many-lights --lights 1000000 --gi none"
  "cornell-100k-vpls|--scene cornell --gi vpl --vpls 100000"
  "cornell-box-obj|--scene ../shared/scenes/cornell-box.obj --materials diffuse --gi vpl --vpls 100000"
)
# The OBJ box Lambertian (--materials diffuse), as docs/performance.md measured it.
# SOURCE:CANDIDATES[:GRID_CELLS] runs; RUNS="bvh:1 bvh:4" measures those alone, RUNS="grid:32:8"
# the grid with --grid-cells 8.
read -r -a runs <<<"${RUNS:-power:32 power:128 power:512 bvh:1 bvh:4 grid:32 grid:128}"

summary() { # CSV: mean frame_ms, mean and median frame_rmse^2 over frames 2..N
  local column='NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }'
  awk -F, "$column"' NR > 2 { t += $c["frame_ms"]; e += $c["frame_rmse"] ^ 2; ++n }
    END { printf "%.1f %.4g ", t / n, e / n }' "$1"
  awk -F, "$column"' NR > 2 { printf "%.9g\n", $c["frame_rmse"] ^ 2 }' "$1" | sort -g |
    awk '{ v[NR] = $1 } END { printf "%.4g", NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}

echo "scene method source candidates frame_ms frame_mse frame_mse_median"
for entry in "${scenes[@]}"; do
  name=${entry%%|*}
  [[ -z "${SCENES:-}" || " $SCENES " == *" $name "* ]] || continue
  read -r -a args <<<"${entry#*|}"
  common=("${args[@]}" --width "$width" --height "$height")
  reference=$dir/$name-reference.exr
  [ -f "$reference" ] ||
    "$render" "${common[@]}" --seed 1 --method reference --spp "$reference_spp" --frames 1 \
      --out "$reference" >/dev/null
  for method in ris restir; do
    for run in "${runs[@]}"; do
      IFS=: read -r source candidates cells <<<"$run"
      grid=() label=$source-$candidates
      [ -z "$cells" ] || { grid=(--grid-cells "$cells"); label=$label-cells-$cells; }
      csv=$dir/$name-$method-$label.csv
      "$render" "${common[@]}" --seed 2 --method "$method" --source "$source" \
        --candidates "$candidates" "${grid[@]}" --frames "$frames" --reference "$reference" \
        --csv "$csv" --out "$dir/$name-$method-$label.png" >/dev/null
      echo "$name $method $source $candidates${cells:+ cells $cells} $(summary "$csv")"
    done
  done
done | tee "$dir/summary.txt"
