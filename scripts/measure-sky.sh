#!/usr/bin/env bash
# The environment-light measurements of docs/noise-and-bias.md ("Environment light"): the
# sun-sky scene, direct light only (--gi none), static camera, against a path-traced reference
# of the same scene (REFERENCE_SPP samples per pixel, with the sky's NEE and MIS):
#   RIS with the environment importance-sampled (one light among the lamps, by power) against
#   RIS that finds it only through BSDF-sampled directions (cosine-weighted at diffuse pixels,
#   --env-sampling bsdf --bsdf-candidates B), and ReSTIR against RIS: per-frame MSE (frames
#   2..FRAMES), MSE after FRAMES frames, and frame time (the smallest over TIME_ROUNDS rounds,
#   taking turns, of the median over frames 2..6), so that MSE x time compares at equal time.
# Every MSE printed includes the reference's own noise; the "reference noise" line gives it
# (var(1 spp) / REFERENCE_SPP) so that it can be subtracted.
# Usage: [WIDTH=1280 HEIGHT=720 REFERENCE_SPP=1024 FRAMES=20 B=4 TIME_ROUNDS=3 OUT_DIR=out/sky]
#        scripts/measure-sky.sh
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

width=${WIDTH:-1280}
height=${HEIGHT:-720}
reference_spp=${REFERENCE_SPP:-1024}
frames=${FRAMES:-20}
bsdf=${B:-4}
render=build/render/examples/pathtracer/restir-render
[ -x "$render" ] ||
  bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
dir=${OUT_DIR:-out/sky}
mkdir -p "$dir"
# shellcheck source=scripts/measure-lib.sh
source scripts/measure-lib.sh

scene=(--scene sun-sky --gi none --width "$width" --height "$height")
ref=$(reference "sun-sky-${width}x$height" "$reference_spp" "${scene[@]}")
run "${scene[@]}" --seed 3 --method reference --spp 1 --frames 3 --reference "$ref" \
  --csv "$dir/noise.csv" --out "$dir/time.pfm"
awk -v a="$(stat "$dir/noise.csv" frame_rmse meansq)" -v n="$reference_spp" \
  'BEGIN { printf "reference noise (%s spp): MSE %.3g\n", n, a / (n + 1) }'

names=(ris-importance ris-bsdf restir)
flags=("--method ris" "--method ris --env-sampling bsdf --bsdf-candidates $bsdf" "--method restir")
declare -A ms
for k in 0 1 2; do ms[$k]=1e30; done
for _ in $(seq "${TIME_ROUNDS:-3}"); do
  for k in 0 1 2; do
    # shellcheck disable=SC2086 # the method and its flags
    run "${scene[@]}" --seed 4 ${flags[$k]} --frames 6 --csv "$dir/time.csv" --out "$dir/time.pfm"
    ms[$k]=$(smaller "${ms[$k]}" "$(stat "$dir/time.csv" frame_ms median)")
  done
done
echo "| sun-sky ${width}x$height | frame ms | frame MSE | frame MSE x ms | MSE, $frames frames |"
echo "| --- | --- | --- | --- | --- |"
declare -A frame_mse last_mse
for k in 0 1 2; do
  # shellcheck disable=SC2086
  run "${scene[@]}" --seed 2 ${flags[$k]} --frames "$frames" --reference "$ref" \
    --csv "$dir/${names[$k]}.csv" --out "$dir/${names[$k]}.png" --out "$dir/${names[$k]}.pfm" \
    --exposure "$(exposure "$ref")"
  frame_mse[$k]=$(stat "$dir/${names[$k]}.csv" frame_rmse meansq)
  last_mse[$k]=$(awk -v r="$(stat "$dir/${names[$k]}.csv" rmse last)" 'BEGIN { printf "%.4g", r * r }')
  awk -v n="${names[$k]} (${flags[$k]})" -v t="${ms[$k]}" -v f="${frame_mse[$k]}" -v l="${last_mse[$k]}" \
    'BEGIN { printf "| %s | %s | %s | %.4g | %s |\n", n, t, f, f * t, l }'
done
awk -v f0="${frame_mse[0]}" -v f1="${frame_mse[1]}" -v f2="${frame_mse[2]}" -v t0="${ms[0]}" \
  -v t1="${ms[1]}" -v t2="${ms[2]}" -v l0="${last_mse[0]}" -v l2="${last_mse[2]}" 'BEGIN {
  printf "importance / bsdf-only RIS: frame MSE %.3g, at equal time (MSE x ms) %.3g\n", f0 / f1, f0 * t0 / (f1 * t1)
  printf "ReSTIR / RIS: frame MSE %.3g, at equal time %.3g; after the frames %.3g\n", f2 / f0, f2 * t2 / (f0 * t0), l2 / l0 }'
