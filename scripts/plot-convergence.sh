#!/usr/bin/env bash
# Plots CSV columns against frame, one line per method: RMSE by default, or the columns named
# with --column, one panel per column in the same PNG.
# Usage: scripts/plot-convergence.sh OUT.png [--column NAME[,NAME...]]... METHOD=FILE.csv
#          [METHOD=FILE.csv ...]
# Each CSV has a header line naming its columns, among them `frame` and the plotted ones (in
# any order). The rmse panel has a logarithmic axis and skips rows with an empty or
# non-positive rmse; another column's panel skips rows where it is empty and is logarithmic
# when every value is positive (fireflies, p999, rel_mse), linear otherwise (bias, acf_x1).
set -euo pipefail

usage() {
  echo "usage: $0 OUT.png [--column NAME[,NAME...]]... METHOD=FILE.csv [METHOD=FILE.csv ...]" >&2
  [ $# -gt 0 ] && echo "error: $*" >&2
  exit 2
}

columns=()
positional=()
while [ $# -gt 0 ]; do
  case "$1" in
    --column)
      [ $# -ge 2 ] || usage "--column needs a column name"
      list=$2
      shift 2
      ;;
    --column=*)
      list=${1#--column=}
      shift
      ;;
    *)
      positional+=("$1")
      shift
      continue
      ;;
  esac
  IFS=',' read -r -a names <<<"$list"
  [ ${#names[@]} -gt 0 ] || usage "--column needs a column name"
  for name in "${names[@]}"; do
    [[ "$name" =~ ^[A-Za-z0-9_]+$ ]] || usage "'$name' is not a column name (letters, digits, _)"
    case " ${columns[*]-} " in
      *" $name "*) ;;
      *) columns+=("$name") ;;
    esac
  done
done
[ ${#columns[@]} -gt 0 ] || columns=(rmse)
set -- "${positional[@]+"${positional[@]}"}"

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

# Writes "frame value" per row of file $2 for column $1 to $3; exits 3 when a column is missing.
# rmse keeps only positive values (its axis is logarithmic), other columns every non-empty one.
extract() {
  awk -F',' -v file="$2" -v column="$1" '
    function clean(s) { gsub(/\r/, "", s); gsub(/^[ \t"]+|[ \t"]+$/, "", s); return s }
    NR == 1 {
      for (c = 1; c <= NF; c++) {
        name = clean($c)
        if (name == "frame") frame_col = c
        if (name == column) value_col = c
      }
      if (!frame_col || !value_col) {
        printf "error: %s has no %s column in its header\n", file,
               (!frame_col ? "\"frame\"" : "\"" column "\"") > "/dev/stderr"
        exit 3
      }
      next
    }
    {
      frame = clean($frame_col)
      value = clean($value_col)
      if (frame == "" || value == "") next
      if (column == "rmse" && value + 0 <= 0) next
      print frame, value
    }
  ' "$2" >"$3"
}

# The gnuplot commands of one panel: column $1, its data files after it.
panel() {
  local column=$1 plots=() i=0 log=1 data
  shift
  for data in "$@"; do
    awk '$2 + 0 <= 0 { found = 1 } END { exit !found }' "$data" && log=0
    plots+=("$(gnuplot_quote "$data") using 1:2 with lines linewidth 2 title $(gnuplot_quote "${methods[$i]}") noenhanced")
    i=$((i + 1))
  done
  if [ "$column" = rmse ]; then
    echo 'set title "RMSE against the reference"'
    echo 'set ylabel "RMSE"'
  else
    echo "set title $(gnuplot_quote "$column") noenhanced"
    echo "set ylabel $(gnuplot_quote "$column") noenhanced"
  fi
  if [ "$log" -eq 1 ]; then echo 'set logscale y'; else echo 'unset logscale y'; fi
  local plot_list
  plot_list=$(printf '%s, ' "${plots[@]}")
  echo "plot ${plot_list%, }"
}

panels=""
for column in "${columns[@]}"; do
  data_files=()
  for i in "${!files[@]}"; do
    data="$tmp_dir/$column.$i.dat"
    status=0
    extract "$column" "${files[$i]}" "$data" || status=$?
    [ "$status" -eq 0 ] || exit 1
    if [ ! -s "$data" ]; then
      if [ "$column" = rmse ]; then
        echo "error: ${files[$i]} has no rows with an rmse" >&2
      else
        echo "error: ${files[$i]} has no rows with a value of $column" >&2
      fi
      exit 1
    fi
    data_files+=("$data")
  done
  panels+=$(panel "$column" "${data_files[@]}")$'\n'
done

mkdir -p "$(dirname "$out")"
count=${#columns[@]}
height=600 begin="" end=""
if [ "$count" -gt 1 ]; then
  height=$((380 * count)) begin="set multiplot layout $count,1" end="unset multiplot"
fi
gnuplot <<EOF
set terminal pngcairo size 900,$height font "sans,11"
set output $(gnuplot_quote "$out")
$begin
set xlabel "frame"
set format y "%g"
set grid xtics ytics mytics
set key top right
$panels
$end
EOF
echo "plot: $out"
