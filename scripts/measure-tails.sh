#!/usr/bin/env bash
# Heavy tails (docs/noise-and-bias.md, "Heavy tails"): per scene, method and restir-render
# binary, over SEEDS (default "3 4 5 6"): the mean frame time, the per-frame MSE over frames 2..N
# (mean and median over the frames and seeds, less the reference's own noise: half the MSE
# between two independent references), their ratio, the last frame's worst-20 share (the share
# of its squared error in its 20 worst pixels, restir-compare's worst20_share, mean over the
# seeds), the MSE of the N-frame image, its bias (the CSV's `bias`: the mean error over the
# image, relative) and the flicker (the CSV's `flicker` over frames 2..N), means over the seeds. References (REFERENCE_SPP
# samples a pixel, seeds 1 and 2) are cached in out/tails-WIDTHxHEIGHT/.
# Usage: scripts/measure-tails.sh [WIDTH HEIGHT FRAMES REFERENCE_SPP] -- BINARY...
#        SCENES (default "many-lights-1k many-lights-100k many-lights-1M") of those below;
#        METHODS (default "ris restir"): restir-render --method values, or NAME:FLAGS with the
#        flags' spaces as commas (restir-temporal:--method,restir,--spatial-passes,0).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

args=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do args+=("$1"); shift; done
[ $# -gt 0 ] && shift
[ $# -gt 0 ] || { echo "usage: $0 [WIDTH HEIGHT FRAMES REFERENCE_SPP] -- BINARY..." >&2; exit 2; }
binaries=("$@")
width=${args[0]:-640} height=${args[1]:-360} frames=${args[2]:-16} reference_spp=${args[3]:-1024}
render=${binaries[0]}
compare=$(dirname "$render")/restir-compare
[ -x "$compare" ] || { echo "error: $compare not built" >&2; exit 1; }
dir=out/tails-${width}x${height}
mkdir -p "$dir"

declare -A scene_flags=(
  [many-lights-1k]="--scene many-lights --lights 1000 --gi none"
  [many-lights-100k]="--scene many-lights --lights 100000 --gi none"
  [many-lights-1M]="--scene many-lights --lights 1000000 --gi none"
  [many-lights-100k-vpls]="--scene many-lights --lights 100000 --gi vpl --vpl-seed 7"
  [cornell-100k-vpls]="--scene cornell --gi vpl --vpls 100000 --vpl-seed 7"
  [cornell-obj]="--scene ../shared/scenes/cornell-box.obj --materials diffuse --gi vpl --vpls 100000 --vpl-seed 7"
  [cornell-glossy]="--scene cornell-glossy --gi none"
  [sun-sky]="--scene sun-sky --gi none"
  [glossy-floor]="--scene scripts/scenes/glossy-floor.obj --look-from 0 1.5 5 --look-at 0 0 -1 --fov 60 --gi none"
  [glossy-floor-vpls]="--scene scripts/scenes/glossy-floor.obj --look-from 0 1.5 5 --look-at 0 0 -1 --fov 60 --gi vpl --vpls 100000 --vpl-seed 7"
)

printf '| scene | method | binary | frame ms | frame MSE mean / median | mean / median | worst-20 share | %s-frame MSE | bias | flicker |\n' "$frames"
echo '| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |'
for scene in ${SCENES:-many-lights-1k many-lights-100k many-lights-1M}; do
  read -r -a flags <<<"${scene_flags[$scene]}"
  common=("${flags[@]}" --width "$width" --height "$height")
  for seed in 1 2; do
    reference=$dir/$scene-reference-$seed.exr
    [ -f "$reference" ] || "$render" "${common[@]}" --seed "$seed" --method reference \
      --spp "$reference_spp" --frames 1 --out "$reference" >/dev/null
  done
  reference=$dir/$scene-reference-1.exr
  noise=$("$compare" --reference "$dir/$scene-reference-2.exr" "$reference" |
    awk '$1 == "rmse" { printf "%.9g", $2 * $2 / 2 }')
  for method in ${METHODS:-ris restir}; do
    name=${method%%:*}
    method_flags=(--method "$method")
    [[ $method == *:* ]] && IFS=',' read -r -a method_flags <<<"${method#*:}"
    for b in "${!binaries[@]}"; do
      stats=$dir/$scene-$name-$b.txt
      : >"$stats"
      for seed in ${SEEDS:-3 4 5 6}; do
        base=$dir/$scene-$name-$b-$seed
        "${binaries[$b]}" "${common[@]}" "${method_flags[@]}" --seed "$seed" --frames "$frames" \
          --reference "$reference" --csv "$base.csv" --out "$base.exr" --out-frame "$base-last.exr" \
          >/dev/null
        share=$("$compare" --reference "$reference" "$base-last.exr" |
          awk '$1 == "worst20_share" { print $2 }')
        # frame ms and frame MSE of frames 2..N, then the image's MSE, the share.
        awk -F, -v share="$share" 'NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
          { last = $c["rmse"]; bias = $c["bias"] }
          NR > 2 { print "frame", $c["frame_ms"], $c["frame_rmse"] ^ 2, $c["flicker"] }
          END { print "image", last ^ 2, share, bias }' "$base.csv" >>"$stats"
      done
      median=$(awk '$1 == "frame" { print $3 }' "$stats" | sort -g |
        awk -v noise="$noise" '{ v[NR] = $1 - noise }
          END { printf "%.9g", NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }')
      awk -v scene="$scene" -v method="$name" -v binary="${binaries[$b]}" -v noise="$noise" \
        -v median="$median" '
        $1 == "frame" { ms += $2; sum += $3 - noise; flicker += $4; ++n }
        $1 == "image" { image += $2; share += $3; bias += $4; ++runs }
        END {
          printf "| %s | %s | %s | %.1f | %.4g / %.4g | %.2f | %.1f %% | %.4g | %+.2f %% | %.4g |\n",
            scene, method, binary, ms / n, sum / n, median, sum / n / median, 100 * share / runs,
            image / runs, 100 * bias / runs, flicker / n
        }' "$stats"
    done
  done
done
