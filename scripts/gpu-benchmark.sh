#!/usr/bin/env bash
# Builds benchmarks/cuda/di_pipeline for this machine's GPU and runs it: the ReSTIR DI pipeline
# at 1920x1080 (G-buffer, light tiles, then the library's frame recipe, a kernel per step), each
# pass and step timed with CUDA events (a row per stage) and compared with the same one on the
# CPU. --mis-rays traces the MIS rays in reuse (ReuseVisibility::traced); the default is ray-free
# reuse (assumed).
# Arguments go to the program (--help lists them); NVCC_FLAGS adds compiler flags (for example
# -I/path/to/glm where GLM is not installed).
set -euo pipefail
cd "$(dirname "$0")/.."

nvcc_bin=$(command -v nvcc || true)
[ -z "$nvcc_bin" ] && [ -x /usr/local/cuda/bin/nvcc ] && nvcc_bin=/usr/local/cuda/bin/nvcc
if [ -z "$nvcc_bin" ]; then
  echo "gpu-benchmark: nvcc not found (install the CUDA toolkit)" >&2
  exit 1
fi
if ! nvidia-smi -L >/dev/null 2>&1; then
  echo "gpu-benchmark: no GPU found (nvidia-smi -L failed); build/cuda/di_pipeline --cpu-only runs the CPU passes alone" >&2
  exit 1
fi
mkdir -p build/cuda
# -fmad=false: the GPU rounds as the CPU does, so that their results can be compared bit for bit
# (it did not change the pass times on an H100). -DNDEBUG: a release build, as a renderer ships
# its kernels (assertions cost 7 % of the frame; NVCC_FLAGS=-UNDEBUG keeps them).
# shellcheck disable=SC2086
"$nvcc_bin" -std=c++20 -Iinclude -DNDEBUG ${NVCC_FLAGS:-} -O3 -fmad=false -arch=native \
  -diag-suppress 20012 benchmarks/cuda/di_pipeline.cu -o build/cuda/di_pipeline_native
build/cuda/di_pipeline_native "$@"
