#!/usr/bin/env bash
# Frame times of restir-render on this machine (docs/performance.md):
#  1. the Cornell box at 1280 x 720 with about 100k VPLs, 32 candidates, temporal reuse and one
#     spatial pass of 5 neighbours (1/M and pairwise MIS), beside uniform sampling and RIS;
#  2. the many-light scene with 1k, 100k and 1M emitters (ReSTIR, pairwise MIS, no GI).
# Medians over frames 2..N (frame 1 has no temporal reuse); CSVs in out/speed/.
# Usage: scripts/measure-speed.sh [FRAMES]   (default 10)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

frames=${1:-10}
bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
render=build/render/examples/pathtracer/restir-render
dir=out/speed
mkdir -p "$dir"

# Median of each timing column over frames 2..N of a CSV, as "total primary candidates ...".
medians() {
  local csv=$1
  for column in frame_ms primary_ms candidates_ms temporal_ms spatial_ms shading_ms; do
    awk -F, -v name="$column" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == name) c = i; next }
      NR > 2 { print $c }' "$csv" | sort -n | awk '{ v[NR] = $1 } END {
      m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2; printf "%.1f ", m }'
  done
}

echo "| run | frame | primary | candidates | temporal | spatial | shading |"
echo "| --- | --- | --- | --- | --- | --- | --- |"
cornell=(--scene cornell --gi vpl --vpls 100000 --width 1280 --height 720 --frames "$frames"
  --candidates 32 --neighbours 5 --spatial-passes 1)
run() { # NAME ARGS...
  local name=$1
  shift
  "$render" "$@" --csv "$dir/$name.csv" --out "$dir/$name.png" >"$dir/$name.log"
  printf '| %s | %s |\n' "$name" "$(medians "$dir/$name.csv" | sed 's/ $//; s/ / | /g')"
}
run cornell-uniform "${cornell[@]}" --method uniform
run cornell-ris "${cornell[@]}" --method ris
run cornell-restir-1overM "${cornell[@]}" --method restir --bias-correction none
run cornell-restir-pairwise "${cornell[@]}" --method restir --bias-correction pairwise
for lights in 1000 100000 1000000; do
  run "many-lights-$lights" --scene many-lights --lights "$lights" --gi none --width 1280 \
    --height 720 --frames "$frames" --method restir
done
grep -h "^scene" "$dir"/*.log
