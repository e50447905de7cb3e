#!/usr/bin/env bash
# Side-by-side frame times of two or more restir-render binaries (docs/performance.md): the
# binaries take turns, ROUNDS times, on the same ReSTIR render (Cornell box, about 100k VPLs;
# extra restir-render flags after --), and for each binary the smallest over the rounds of each
# phase's median over frames 2..N is printed (the machine's noise only ever adds time).
# Usage: scripts/compare-builds.sh ROUNDS WIDTH HEIGHT BINARY... [-- RESTIR-RENDER-FLAGS]
set -euo pipefail
rounds=$1 width=$2 height=$3
shift 3
binaries=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do binaries+=("$1"); shift; done
[ $# -gt 0 ] && shift
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
columns=(frame_ms primary_ms tiles_ms candidates_ms temporal_ms spatial_ms shading_ms)
median() { # CSV COLUMN: the median over frames 2..N
  awk -F, -v name="$2" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == name) c = i; next }
    NR > 2 { print $c }' "$1" | sort -n | awk '{ v[NR] = $1 } END {
    printf "%.1f ", NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}
for round in $(seq "$rounds"); do
  for n in "${!binaries[@]}"; do
    "${binaries[$n]}" --scene cornell --gi vpl --vpls 100000 --width "$width" --height "$height" \
      --frames 10 --method restir "$@" --csv "$dir/run.csv" --out "$dir/run.pfm" >/dev/null
    for column in "${columns[@]}"; do median "$dir/run.csv" "$column"; done >>"$dir/$n.txt"
    echo >>"$dir/$n.txt"
  done
done
echo "| binary | frame | primary | tiles | candidates | temporal | spatial | shading |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
for n in "${!binaries[@]}"; do
  printf '| %s | %s |\n' "${binaries[$n]}" "$(awk '{ for (i = 1; i <= NF; ++i) if (NR == 1 || $i < m[i]) m[i] = $i }
    END { for (i = 1; i <= NF; ++i) printf "%s%s", m[i], i < NF ? " | " : "" }' "$dir/$n.txt")"
done
