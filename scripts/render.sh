#!/usr/bin/env bash
# Builds the Embree example renderer (Release) and renders the default scene: the Cornell box
# with ReSTIR and VPL global illumination, written to out/cornell.png. Extra arguments go to
# restir-render (see build/render/examples/pathtracer/restir-render --help).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/install-deps.sh cmake make g++ libglm-dev libstb-dev libembree-dev libtbb-dev \
  libtinyobjloader-dev libopenexr-dev libcli11-dev

cmake -S . -B build/render -DCMAKE_BUILD_TYPE=Release -DRESTIR_BUILD_TESTS=OFF \
  -DRESTIR_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build/render --target restir-render -j "$(nproc)"
build/render/examples/pathtracer/restir-render --scene cornell --method restir --gi vpl \
  --frames 16 --out out/cornell.png "$@"
# The image written: the last --out given, out/cornell.png when none is.
out=out/cornell.png
while [ $# -gt 0 ]; do
  case $1 in
  --out) [ $# -gt 1 ] && out=$2 ;;
  --out=*) out=${1#--out=} ;;
  esac
  shift
done
case $out in /*) ;; *) out=$PWD/$out ;; esac
echo "image: $out"
