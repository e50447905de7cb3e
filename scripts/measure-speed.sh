#!/usr/bin/env bash
# Frame times of restir-render on this machine (docs/performance.md), side by side in one run:
#  1. the Cornell box at 1280 x 720 with about 100k VPLs, 32 candidates, temporal reuse and one
#     spatial pass of 5 neighbours (the renderer's defaults: pairwise MIS with its shadow rays;
#     also 1/M and ray-free pairwise), beside uniform sampling and RIS;
#  2. the same ReSTIR frame with 1k and with 1M VPLs (light count with the geometry fixed);
#  3. the many-light scene with 1k, 100k and 1M emitters (ReSTIR, no GI).
# Medians over frames 2..N (frame 1 has no temporal reuse), then the ratios the speed goals are
# stated in: ReSTIR frame / uniform frame, candidate phase per candidate and spatial phase per
# pixel, both per core and per pixel that sees a surface. CSVs and logs in out/speed/.
# Usage: scripts/measure-speed.sh [FRAMES]   (default 10)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

frames=${1:-10}
bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
render=build/render/examples/pathtracer/restir-render
dir=out/speed
rm -rf "$dir"
mkdir -p "$dir"
cores=$(nproc)

# Median of each timing column over frames 2..N of a CSV, as "frame primary tiles ...".
columns=(frame_ms primary_ms tiles_ms candidates_ms temporal_ms spatial_ms shading_ms)
medians() {
  local csv=$1
  for column in "${columns[@]}"; do
    awk -F, -v name="$column" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == name) c = i; next }
      NR > 2 { print $c }' "$csv" | sort -n | awk '{ v[NR] = $1 } END {
      m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2; printf "%.1f ", m }'
  done
}
declare -A frame_ms candidates_ms spatial_ms surface_pixels

echo "| run | frame | primary | tiles | candidates | temporal | spatial | shading |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
cornell=(--scene cornell --gi vpl --width 1280 --height 720 --frames "$frames" --candidates 32
  --neighbours 5 --spatial-passes 1)
run() { # NAME ARGS...
  local name=$1
  shift
  "$render" "$@" --csv "$dir/$name.csv" --out "$dir/$name.png" >"$dir/$name.log"
  local m
  m=$(medians "$dir/$name.csv")
  read -r -a values <<<"$m"
  frame_ms[$name]=${values[0]}
  candidates_ms[$name]=${values[3]}
  spatial_ms[$name]=${values[5]}
  surface_pixels[$name]=$(sed -n 's/^pixels with a surface: \([0-9]*\) of.*/\1/p' "$dir/$name.log")
  printf '| %s | %s |\n' "$name" "$(echo "$m" | sed 's/ $//; s/ / | /g')"
}
run cornell-uniform "${cornell[@]}" --vpls 100000 --method uniform
run cornell-ris "${cornell[@]}" --vpls 100000 --method ris
run cornell-restir "${cornell[@]}" --vpls 100000 --method restir
run cornell-restir-1overM "${cornell[@]}" --vpls 100000 --method restir --bias-correction none
run cornell-restir-rayfree "${cornell[@]}" --vpls 100000 --method restir --mis-rays false
run cornell-restir-1k-vpls "${cornell[@]}" --vpls 1000 --method restir
run cornell-restir-1M-vpls "${cornell[@]}" --vpls 1000000 --method restir
for lights in 1000 100000 1000000; do
  run "many-lights-$lights" --scene many-lights --lights "$lights" --gi none --width 1280 \
    --height 720 --frames "$frames" --method restir
done
grep -h "^scene" "$dir"/*.log | sort -u

echo
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }
per() { # MILLISECONDS COUNT -> nanoseconds per item per core
  awk -v ms="$1" -v n="$2" -v cores="$cores" 'BEGIN { printf "%.1f", ms * 1e6 * cores / n }'
}
uniform=${frame_ms[cornell-uniform]}
pixels=${surface_pixels[cornell-restir]}
echo "Cornell box, 1280 x 720, $pixels pixels see a surface, $cores cores:"
for name in cornell-ris cornell-restir cornell-restir-1overM cornell-restir-rayfree; do
  echo "- $name: frame $(ratio "${frame_ms[$name]}" "$uniform") x uniform"
done
restir=${frame_ms[cornell-restir]}
echo "- ReSTIR at the defaults: $restir ms; 3x uniform is $(awk -v u="$uniform" \
  'BEGIN { printf "%.1f", 3 * u }') ms, 2x $(awk -v u="$uniform" 'BEGIN { printf "%.1f", 2 * u }') ms \
($(awk -v r="$restir" -v u="$uniform" 'BEGIN { printf "%.1f", r - 2 * u }') ms over 2x)"
echo "- ReSTIR candidate phase (32 candidates, tiles apart): $(per "${candidates_ms[cornell-restir]}" \
  $((pixels * 32))) ns per candidate per core, visibility ray included"
echo "- ReSTIR spatial phase (k = 5): $(per "${spatial_ms[cornell-restir]}" "$pixels") ns per pixel per core, rays included"
echo "- ReSTIR with 1M VPLs vs 1k VPLs: $(ratio "${frame_ms[cornell-restir-1M-vpls]}" \
  "${frame_ms[cornell-restir-1k-vpls]}") x"
