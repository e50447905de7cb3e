#!/usr/bin/env bash
# Plots RMSE against frame, one line per method, on a logarithmic RMSE axis.
# Usage: scripts/plot-convergence.sh OUT.png METHOD=FILE.csv [METHOD=FILE.csv ...]
# Each CSV has a header line naming its columns, among them `frame` and `rmse` (in any order);
# rows with an empty or non-positive rmse are skipped.
set -euo pipefail

usage() {
  echo "usage: $0 OUT.png METHOD=FILE.csv [METHOD=FILE.csv ...]" >&2
  [ $# -gt 0 ] && echo "error: $*" >&2
  exit 2
}

[ $# -ge 2 ] || usage "need an output file and at least one METHOD=FILE.csv"
out=$1
shift
case "$out" in
  *.png) ;;
  *) usage "the output '$out' must end in .png" ;;
esac

methods=()
files=()
for arg in "$@"; do
  case "$arg" in
    ?*=?*) ;;
    *) usage "'$arg' is not METHOD=FILE.csv" ;;
  esac
  method=${arg%%=*}
  file=${arg#*=}
  [ -f "$file" ] || usage "no such file: $file"
  [ -r "$file" ] || usage "cannot read $file"
  methods+=("$method")
  files+=("$file")
done

script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
command -v gnuplot >/dev/null || bash "$script_dir/install-deps.sh" gnuplot-nox

tmp_dir=$(mktemp -d)
trap 'rm -rf "$tmp_dir"' EXIT

# A string for gnuplot inside single quotes, where a quote is written twice.
gnuplot_quote() {
  local s=${1//\'/\'\'}
  printf "'%s'" "$s"
}

plots=()
for i in "${!files[@]}"; do
  data="$tmp_dir/$i.dat"
  # Prints "frame rmse" per row; exits 3 when a column is missing.
  status=0
  awk -F',' -v file="${files[$i]}" '
    function clean(s) { gsub(/\r/, "", s); gsub(/^[ \t"]+|[ \t"]+$/, "", s); return s }
    NR == 1 {
      for (c = 1; c <= NF; c++) {
        name = clean($c)
        if (name == "frame") frame_col = c
        if (name == "rmse") rmse_col = c
      }
      if (!frame_col || !rmse_col) {
        printf "error: %s has no %s column in its header\n", file,
               (!frame_col ? "\"frame\"" : "\"rmse\"") > "/dev/stderr"
        exit 3
      }
      next
    }
    {
      frame = clean($frame_col)
      rmse = clean($rmse_col)
      if (frame == "" || rmse == "") next
      if (rmse + 0 <= 0) next
      print frame, rmse
    }
  ' "${files[$i]}" >"$data" || status=$?
  [ "$status" -eq 0 ] || exit 1
  [ -s "$data" ] || { echo "error: ${files[$i]} has no rows with an rmse" >&2; exit 1; }
  plots+=("$(gnuplot_quote "$data") using 1:2 with lines linewidth 2 title $(gnuplot_quote "${methods[$i]}") noenhanced")
done

mkdir -p "$(dirname "$out")"
plot_list=$(printf '%s, ' "${plots[@]}")
gnuplot <<EOF
set terminal pngcairo size 900,600 font "sans,11"
set output $(gnuplot_quote "$out")
set title "RMSE against the reference"
set xlabel "frame"
set ylabel "RMSE"
set logscale y
set format y "%g"
set grid xtics ytics mytics
set key top right
plot ${plot_list%, }
EOF
echo "plot: $out"
