#!/usr/bin/env bash
# Builds and runs every test: g++ and clang++ builds with warnings as errors (tests,
# examples, benchmarks), the test suite again under AddressSanitizer + UBSan (a Debug build,
# so assertions are on; the renderer too), and a CUDA check of the headers when nvcc is available.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh cmake make g++ clang libglm-dev libgtest-dev libgmock-dev \
  libbenchmark-dev libstb-dev libembree-dev libtbb-dev libtinyobjloader-dev libopenexr-dev \
  libcli11-dev

jobs=$(nproc)

echo "== CUDA: the headers inside a __global__ kernel"
nvcc_bin=$(command -v nvcc || true)
[ -z "$nvcc_bin" ] && [ -x /usr/local/cuda/bin/nvcc ] && nvcc_bin=/usr/local/cuda/bin/nvcc
if [ -n "$nvcc_bin" ]; then
  # 20012: GLM's own defaulted constructors carry __host__ __device__, which nvcc notes.
  nvcc_flags=(-std=c++20 -Iinclude -fmad=false -diag-suppress 20012 -Werror all-warnings)
  mkdir -p build/cuda
  "$nvcc_bin" "${nvcc_flags[@]}" -c tests/cuda/kernel_compile.cu -o build/cuda/kernel_compile.o
  "$nvcc_bin" "${nvcc_flags[@]}" tests/cuda/device_check.cu -o build/cuda/device_check
  echo "passed: tests/cuda/*.cu compile with $("$nvcc_bin" --version | tail -1)"
  if nvidia-smi -L >/dev/null 2>&1; then
    build/cuda/device_check
  else
    echo "skipped: no GPU to run build/cuda/device_check (GPU vs CPU results)"
  fi
else
  echo "skipped: no nvcc"
fi

build_and_test() { # NAME CMAKE-ARGS...
  local dir="build/$1"
  shift
  echo "== $dir"
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
  cmake --build "$dir" -j "$jobs"
  ctest --test-dir "$dir" --output-on-failure -j "$jobs"
}

build_and_test test-clang -DCMAKE_CXX_COMPILER=clang++
build_and_test test-sanitize -DCMAKE_CXX_COMPILER=g++ -DRESTIR_SANITIZE=ON \
  -DCMAKE_BUILD_TYPE=Debug -DRESTIR_BUILD_BENCHMARKS=OFF
build_and_test test-gcc -DCMAKE_CXX_COMPILER=g++
