#!/usr/bin/env bash
# Bias of plain RIS and of each reuse weighting (docs/noise-and-bias.md): RIS, ReSTIR with 1/M,
# 1/Z, the balance heuristic and pairwise MIS, each with and without the MIS shadow rays, on the
# built-in Cornell box with VPLs, the many-light scene and ../shared/scenes/cornell-box.obj with
# VPLs, against references of the same integrand (the same VPL set, `--method reference`).
#
# Every noisy input is measured from independent renders: REFERENCES reference renders (pixel
# seeds 1, 2, ...) and RUNS renders of FRAMES frames per row (pixel seeds 101, 102, ...), all
# with one scene layout and one VPL set (--scene-seed 1, --vpl-seed 1). The bias is
# (mean of the rows' image means) / (mean of the references' image means) - 1, and its standard
# error sqrt(SE_runs^2 + SE_reference^2), each SE the spread of the image means over the
# independent renders / sqrt(count) (relative to the reference's mean). The frames of one
# render are not used for errors: temporal reuse correlates them. Work files: out/bias/.
#
# Usage: scripts/measure-bias.sh [WIDTH HEIGHT REFERENCE_SPP FRAMES]
#          [--references N] [--runs N] [--scenes LIST] [--rows LIST]
# Defaults: 320 180 1024 20, 4 references, 4 runs, every scene and row. LIST is
# comma-separated: scenes cornell, many-lights, obj; rows ris, none, and WEIGHTS-RAYS with
# WEIGHTS one of one-over-z, balance-heuristic, pairwise and RAYS true or false (for example
# `--scenes many-lights --rows ris,pairwise-true`).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

usage() {
  sed -n '2,21p' "$0" | sed 's/^# \{0,1\}//' >&2
  [ $# -gt 0 ] && echo "error: $*" >&2
  exit 2
}
positional=() references=4 runs=4 scenes=cornell,many-lights,obj
rows=ris,none,one-over-z-true,one-over-z-false,balance-heuristic-true,balance-heuristic-false
rows+=,pairwise-true,pairwise-false
while [ $# -gt 0 ]; do
  case "$1" in
    --references) references=${2:?}; shift 2 ;;
    --runs) runs=${2:?}; shift 2 ;;
    --scenes) scenes=${2:?}; shift 2 ;;
    --rows) rows=${2:?}; shift 2 ;;
    -h|--help) usage ;;
    -*) usage "unknown argument '$1'" ;;
    *) positional+=("$1"); shift ;;
  esac
done
[ ${#positional[@]} -le 4 ] || usage "at most four numbers: WIDTH HEIGHT REFERENCE_SPP FRAMES"
width=${positional[0]:-320}
height=${positional[1]:-180}
reference_spp=${positional[2]:-1024}
frames=${positional[3]:-20}
for n in "$width" "$height" "$reference_spp" "$frames" "$references" "$runs"; do
  [[ "$n" =~ ^[1-9][0-9]*$ ]] || usage "'$n' is not a positive whole number"
done
if [ "$references" -lt 2 ] || [ "$runs" -lt 2 ]; then
  usage "standard errors need 2 or more renders"
fi
obj=../shared/scenes/cornell-box.obj

bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
cmake --build build/render --target restir-compare -j "$(nproc)" >/dev/null
render=build/render/examples/pathtracer/restir-render
compare=build/render/examples/pathtracer/restir-compare
dir=out/bias
mkdir -p "$dir"

# Mean, and standard error of the mean, of the numbers on stdin (one a line).
mean_and_error() {
  awk '{ n++; s += $1; ss += $1 * $1 }
    END { m = s / n; printf "%.9g %.9g\n", m, sqrt((ss - n * m * m) / (n - 1) / n) }'
}

# The flags of one row: RIS, or ReSTIR with the row's weights and MIS rays.
row_flags() { # ROW
  case $1 in
  ris) echo "--method ris" ;;
  none) echo "--method restir --bias-correction none" ;;
  one-over-z-* | balance-heuristic-* | pairwise-*)
    echo "--method restir --bias-correction ${1%-*} --mis-rays ${1##*-}" ;;
  *) usage "unknown row '$1'" ;;
  esac
}

for row in ${rows//,/ }; do row_flags "$row" >/dev/null; done

echo "| scene | row | bias, $frames frames (SE) | SE of the $runs runs | SE of the $references references |"
echo "| --- | --- | --- | --- | --- |"
for scene in ${scenes//,/ }; do
  case $scene in
  cornell) args=(--scene cornell --gi vpl) ;;
  many-lights) args=(--scene many-lights --lights 1000 --gi none --source power --candidates 32) ;;
  obj)
    [ -f "$obj" ] || { echo "error: $obj not found" >&2; exit 1; }
    args=(--scene "$obj" --materials diffuse --gi vpl) ;; # Lambertian, as in docs/
  *) usage "unknown scene '$scene'" ;;
  esac
  args+=(--width "$width" --height "$height" --scene-seed 1 --vpl-seed 1)
  # The references' means relative to the first one's (restir-compare's `bias`).
  : >"$dir/$scene-references.txt"
  for ((k = 1; k <= references; ++k)); do
    reference=$dir/$scene-reference-$k.exr
    "$render" "${args[@]}" --seed "$k" --method reference --spp "$reference_spp" --frames 1 \
      --out "$reference" >/dev/null
    "$compare" "$reference" --reference "$dir/$scene-reference-1.exr" |
      awk '$1 == "bias" { print $2 }' >>"$dir/$scene-references.txt"
  done
  read -r reference_mean reference_error < <(mean_and_error <"$dir/$scene-references.txt")
  for row in ${rows//,/ }; do
    read -ra flags <<<"$(row_flags "$row")"
    name=$scene-$row
    : >"$dir/$name.txt"
    for ((j = 1; j <= runs; ++j)); do
      "$render" "${args[@]}" --seed $((100 + j)) "${flags[@]}" --frames "$frames" \
        --out "$dir/$name-$j.exr" >/dev/null
      # The accumulated image's mean relative to the first reference's.
      "$compare" "$dir/$name-$j.exr" --reference "$dir/$scene-reference-1.exr" |
        awk '$1 == "bias" { print $2 }' >>"$dir/$name.txt"
    done
    read -r run_mean run_error < <(mean_and_error <"$dir/$name.txt")
    awk -v scene="$scene" -v row="$row" -v m="$run_mean" -v se="$run_error" \
      -v rm="$reference_mean" -v rse="$reference_error" 'BEGIN {
        bias = (1 + m) / (1 + rm) - 1; run_se = se / (1 + rm); ref_se = rse / (1 + rm)
        printf "| %s | %s | %+.2f %% (%.2f) | %.2f | %.2f |\n", scene, row, 100 * bias,
          100 * sqrt(run_se * run_se + ref_se * ref_se), 100 * run_se, 100 * ref_se }'
  done
done
