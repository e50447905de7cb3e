#!/usr/bin/env bash
# Fireflies next to lights (docs/noise-and-bias.md, "Light points next to lights"): in the
# many-light scene (or the Cornell box) with direct light only, the share of one RIS frame's total squared error that
# its 20 worst pixels hold, its RMSE and its time, with area and with solid-angle light points,
# per candidate source (light tiles by power and the light BVH, 32 candidates each), averaged over
# SEEDS independent frames. The converged reference (path tracing) is cached in out/worst/.
# Usage: scripts/measure-worst-pixels.sh [WIDTH HEIGHT REFERENCE_SPP SEEDS BUILD SCENE]
#        (default 640 360 4096 8 build/dev many-lights; BUILD must hold restir-render and
#        restir-compare; SCENE many-lights or cornell)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

width=${1:-640}
height=${2:-360}
reference_spp=${3:-4096}
seeds=${4:-8}
build=${5:-build/dev}
scene_name=${6:-many-lights}
render=$build/examples/pathtracer/restir-render
compare=$build/examples/pathtracer/restir-compare
dir=out/worst
mkdir -p "$dir"
case $scene_name in
many-lights) scene=(--scene many-lights --lights 1000) ;;
cornell) scene=(--scene cornell) ;;
*) echo "error: unknown scene '$scene_name'" >&2 && exit 1 ;;
esac
scene+=(--gi none --width "$width" --height "$height")

reference=$dir/reference-$scene_name-${width}x${height}-${reference_spp}spp.exr
if [ ! -f "$reference" ]; then
  # 1024 samples per frame, accumulated over frames.
  nice -n 10 "$render" "${scene[@]}" --method reference --spp 1024 \
    --frames $(((reference_spp + 1023) / 1024)) --seed 12345 --out "$reference" >/dev/null
fi

echo "| source | light points | worst-20 share (SE) | frame RMSE (SE) | frame ms |"
echo "| --- | --- | --- | --- | --- |"
for source in power bvh; do
  for points in area solid-angle; do
    for seed in $(seq 1 "$seeds"); do
      image=$dir/ris-$scene_name-$source-$points-$seed.exr
      csv=$dir/ris-$scene_name-$source-$points-$seed.csv
      nice -n 10 "$render" "${scene[@]}" --method ris --source "$source" --candidates 32 \
        --light-points "$points" \
        --frames 1 --seed "$seed" --out "$image" --csv "$csv" \
        >/dev/null
      "$compare" "$image" --reference "$reference" |
        awk -v ms="$(tail -n 1 "$csv" | cut -d, -f4)" \
          '$1 == "worst20_share" { share = $2 } $1 == "rmse" { rmse = $2 }
           END { print share, rmse, ms }'
    done | awk -v source="$source" -v points="$points" '
      { n++; s += $1; ss += $1 * $1; r += $2; rr += $2 * $2; t += $3 }
      END {
        ms = s / n; mr = r / n
        se_s = n > 1 ? sqrt((ss - n * ms * ms) / (n - 1) / n) : 0
        se_r = n > 1 ? sqrt((rr - n * mr * mr) / (n - 1) / n) : 0
        printf "| %s | %s | %.1f %% (%.1f) | %.4g (%.2g) | %.0f |\n",
          source, points, 100 * ms, 100 * se_s, mr, se_r, t / n
      }'
  done
done
