#!/usr/bin/env bash
# Helpers of the measurement scripts (sourced): `run` a render quietly under nice, read a
# column of a render's CSV (`stat`), render a reference once and cache it (`reference`), and
# the PNG exposure it chose (`exposure`), the indirect light's bias over seeds
# (`bias_over_seeds`), and the flags of the three boxes (`box_scene_flags`). The caller sets
# `render` (the restir-render binary) and `dir` (where references and CSVs go).

run() { nice -n 10 "$render" "$@" >/dev/null; }
smaller() { awk -v a="$1" -v b="$2" 'BEGIN { print a < b ? a : b }'; }

# stat CSV COLUMN HOW: mean (frames 2..N), meansq (mean of the squares, frames 2..N), median
# (frames 2..N) or last (frame N).
stat() {
  if [ "$3" = median ]; then
    awk -F, -v name="$2" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == name) c = i; next }
      NR > 2 { print $c }' "$1" | sort -g | awk '{ v[NR] = $1 } END {
      printf "%.4g\n", NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
    return
  fi
  awk -F, -v name="$2" -v how="$3" '
    NR == 1 { for (i = 1; i <= NF; ++i) if ($i == name) c = i; next }
    { last = $c } NR > 2 { n++; s += $c; q += $c * $c }
    END {
      if (how == "last") print last
      else if (how == "mean") printf "%.4g\n", s / n
      else printf "%.4g\n", q / n
    }' "$1"
}

# reference NAME SPP SCENE-FLAGS...: renders (once) and prints the path of a reference image.
reference() {
  local name=$1 spp=$2
  shift 2
  local image="$dir/reference-$name-${spp}spp.pfm"
  [ -f "$image" ] || nice -n 10 "$render" "$@" --seed 1 --method reference --spp "$spp" --frames 1 \
    --out "$image" --out "${image%.pfm}.png" >"${image%.pfm}.log"
  echo "$image"
}

# exposure REFERENCE: the PNG exposure the reference was written with.
exposure() { sed -n 's/.*(exposure \(.*\))$/\1/p' "${1%.pfm}.log" | tail -n 1; }

# bias_over_seeds LABEL REFERENCE FLAGS...: the indirect light's accumulated mean at 80 x 60
# against REFERENCE over seeds 1..$seeds (the caller sets `seeds`), as mean +- standard error.
bias_over_seeds() {
  local label=$1 image=$2
  shift 2
  for seed in $(seq 1 "$seeds"); do
    run "$@" --width 80 --height 60 --indirect-only --seed "$seed" --reference "$image" \
      --csv "$dir/bias.csv" --out "$dir/bias.pfm"
    stat "$dir/bias.csv" bias last
  done | awk -v label="$label" '{ s += $1; q += $1 * $1; n++ } END {
    m = s / n; printf "| %s | %+.2f %% +- %.2f %% |\n", label, 100 * m, 100 * sqrt((q / n - m * m) / (n - 1)) }'
}

# box_scene_flags NAME: restir-render's flags of cornell, cornell-glossy or cornell-obj
# (../shared/scenes/cornell-box.obj, its materials made Lambertian).
box_scene_flags() {
  case "$1" in
    cornell | cornell-glossy) echo "--scene $1" ;;
    cornell-obj) echo "--scene ../shared/scenes/cornell-box.obj --materials diffuse" ;;
    *) echo "unknown scene '$1' (cornell, cornell-glossy, cornell-obj)" >&2; exit 2 ;;
  esac
}
