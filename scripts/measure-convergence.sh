#!/usr/bin/env bash
# How the accumulated image converges against a reference of the same VPL set: RIS, ReSTIR
# with temporal reuse only, and ReSTIR with the renderer's defaults, each for FRAMES frames
# (RIS for six times as many, for the equal-time comparison). Prints, per method, the RMSE
# after FRAMES frames and of the last frame alone, the relative MSE, the firefly measure, the
# largest difference between the error's autocorrelation along x and along y (lags 1-8) and
# the time; then ReSTIR's RMSE against RIS's at equal time. Plots RMSE and the firefly measure
# per frame. Work files: out/convergence/NAME/.
#
# Usage: scripts/measure-convergence.sh [--scene S] [--width W] [--height H]
#          [--reference-spp N] [--frames F] [--name NAME] [-- RESTIR-FLAGS...]
# Defaults: the built-in Cornell box, 256x256, 4096 spp, 20 frames. Flags after `--` go to
# both ReSTIR runs (for example `-- --history-cap 20 --permutation-sampling false`).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

scene=cornell width=256 height=256 reference_spp=4096 frames=20 name=""
usage() {
  sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//' >&2
  [ $# -gt 0 ] && echo "error: $*" >&2
  exit 2
}
while [ $# -gt 0 ]; do
  case "$1" in
    --scene) scene=${2:?}; shift 2 ;;
    --width) width=${2:?}; shift 2 ;;
    --height) height=${2:?}; shift 2 ;;
    --reference-spp) reference_spp=${2:?}; shift 2 ;;
    --frames) frames=${2:?}; shift 2 ;;
    --name) name=${2:?}; shift 2 ;;
    --) shift; break ;;
    -h|--help) usage ;;
    *) usage "unknown argument '$1'" ;;
  esac
done
for n in "$width" "$height" "$reference_spp" "$frames"; do
  [[ "$n" =~ ^[1-9][0-9]*$ ]] || usage "'$n' is not a positive whole number"
done
restir_flags=("$@")
[ -n "$name" ] || name="$(basename "$scene" .obj)-${width}x${height}"

bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
render=build/render/examples/pathtracer/restir-render
dir=out/convergence/$name
mkdir -p "$dir"
# One scene layout and one VPL set (--scene-seed 1, --vpl-seed 1) for all; the reference's
# pixel samples are independent of the methods' (--seed 99 against --seed 2).
common=(--scene "$scene" --gi vpl --width "$width" --height "$height" --scene-seed 1 --vpl-seed 1)
# An OBJ scene renders Lambertian (--materials diffuse), as the documented measurements on
# ../shared/scenes/cornell-box.obj assume; the built-in scenes are what their names say.
[[ "$scene" != *.obj ]] || common+=(--materials diffuse)

reference=$dir/reference-${reference_spp}spp.exr
if [ ! -f "$reference" ]; then
  echo "reference: $reference_spp spp of the VPL reference (--method reference --gi vpl)"
  "$render" "${common[@]}" --seed 99 --method reference --spp "$reference_spp" --frames 1 \
    --out "$reference" --out "$dir/reference.png" | tee "$dir/reference.log" | tail -n 1
fi
# Every PNG with the exposure of the reference's, so that they compare side by side.
exposure=0
[ -f "$dir/reference.log" ] && exposure=$(sed -n 's/.*(exposure \(.*\))$/\1/p' "$dir/reference.log" | tail -n 1)

run() { # NAME FRAMES FLAGS...
  local method=$1 count=$2
  shift 2
  "$render" "${common[@]}" --seed 2 --frames "$count" --reference "$reference" \
    --csv "$dir/$method.csv" --out "$dir/$method.exr" --out "$dir/$method.png" \
    --exposure "${exposure:-0}" "$@" >/dev/null
}
run ris $((6 * frames)) --method ris
run restir-temporal "$frames" --method restir --spatial-passes 0 "${restir_flags[@]}"
run restir "$frames" --method restir "${restir_flags[@]}"

awk -F, -v frames="$frames" '
  FNR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; m = FILENAME; sub(/.*\//, "", m);
             sub(/\.csv$/, "", m); order[++n] = m; next }
  {
    f = $col["frame"]; rmse[m, f] = $col["rmse"]; elapsed[m, f] = $col["elapsed_ms"]; last[m] = f
    if (f == frames) {
      frame_rmse[m] = $col["frame_rmse"]
      acf = 0
      for (l = 1; l <= 8; ++l) {
        d = $col["acf_x" l] - $col["acf_y" l]; if (d < 0) d = -d; if (d > acf) acf = d
      }
      row[m] = sprintf("%-16s %10.6f %12.6f %10.6f %10s %10.5f %10.3f %10.0f", m, $col["rmse"],
                       $col["frame_rmse"], $col["rel_mse"], $col["fireflies"], $col["p999"], acf,
                       $col["elapsed_ms"])
    }
  }
  END {
    printf "%-16s %10s %12s %10s %10s %10s %10s %10s\n", "after " frames " frames", "rmse",
           "frame_rmse", "rel_mse", "fireflies", "p999", "acf x-y", "ms"
    for (k = 1; k <= n; ++k) print row[order[k]]
    # The noise of the reference itself, from the convergence of RIS (independent frames): RMSE^2(F) =
    # s^2 / F + n^2, so n^2 = (4 RMSE^2(4F) - RMSE^2(F)) / 3. Subtracting it estimates each
    # RMSE against the converged answer.
    r4 = rmse["ris", 4 * frames]; r1 = rmse["ris", frames]
    noise2 = (4 * r4 * r4 - r1 * r1) / 3; if (noise2 < 0) noise2 = 0
    printf "reference noise %.6f (RMSE of the reference itself); without it:", sqrt(noise2)
    for (k = 1; k <= n; ++k) {
      x = rmse[order[k], frames]; x = x * x - noise2
      corrected[order[k]] = x > 0 ? sqrt(x) : 0
      printf " %s %.6f%s", order[k], corrected[order[k]], (k < n ? "," : "\n")
    }
    printf "ratios to RIS without it: temporal only %.3f, restir %.3f\n",
           corrected["restir-temporal"] / corrected["ris"], corrected["restir"] / corrected["ris"]
    r = rmse["ris", frames]
    printf "ratios to RIS: temporal only %.3f, restir %.3f; last frame alone: restir %.3f\n",
           rmse["restir-temporal", frames] / r, rmse["restir", frames] / r,
           frame_rmse["restir"] / frame_rmse["ris"]
    budget = elapsed["restir", frames]; best = ""; used = 0
    for (f = 1; f <= last["ris"]; ++f) if (elapsed["ris", f] <= budget) { best = rmse["ris", f]; used = f }
    printf "equal time (%.0f ms, restir %d frames): restir %.6f, ris %s (%d frames)\n", budget,
           frames, rmse["restir", frames], (best == "" ? "none" : best), used
  }' "$dir/ris.csv" "$dir/restir-temporal.csv" "$dir/restir.csv" | tee "$dir/summary.txt"

bash scripts/plot-convergence.sh "$dir/convergence.png" --column rmse --column fireflies \
  ris="$dir/ris.csv" restir-temporal="$dir/restir-temporal.csv" restir="$dir/restir.csv"
echo "wrote $dir/summary.txt and $dir/convergence.png"
