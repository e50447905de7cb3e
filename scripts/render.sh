#!/usr/bin/env bash
# Builds the minimal example (Release) and renders out/minimal.png.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/install-deps.sh cmake make g++ libglm-dev libstb-dev

cmake -S . -B build/render -DCMAKE_BUILD_TYPE=Release -DRESTIR_BUILD_TESTS=OFF \
  -DRESTIR_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build/render --target restir-minimal -j "$(nproc)"
build/render/examples/minimal/restir-minimal out/minimal.png
echo "image: $PWD/out/minimal.png"
