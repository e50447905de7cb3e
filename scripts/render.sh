#!/usr/bin/env bash
# Builds the Embree example renderer (Release) and renders the default scene: the Cornell box
# with ReSTIR and VPL global illumination, written to out/cornell.png, or to each --out given.
# Extra arguments go to restir-render (see build/render/examples/pathtracer/restir-render --help).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/install-deps.sh cmake make g++ libglm-dev libstb-dev libembree-dev libtbb-dev \
  libtinyobjloader-dev libopenexr-dev libcli11-dev

cmake -S . -B build/render -DCMAKE_BUILD_TYPE=Release -DRESTIR_BUILD_TESTS=OFF \
  -DRESTIR_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build/render --target restir-render -j "$(nproc)"
# The image written: the last --out given, out/cornell.png when none is (restir-render writes
# every --out it gets, so the default is passed only when the arguments name none).
out= previous=
for arg in "$@"; do
  case $previous in --out) out=$arg ;; esac
  case $arg in --out=*) out=${arg#--out=} ;; esac
  previous=$arg
done
default_out=()
[ -n "$out" ] || { out=out/cornell.png; default_out=(--out "$out"); }
build/render/examples/pathtracer/restir-render --scene cornell --method restir --gi vpl \
  --frames 16 "${default_out[@]}" "$@"
case $out in /*) ;; *) out=$PWD/$out ;; esac
echo "image: $out"
