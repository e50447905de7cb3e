#!/usr/bin/env bash
# Builds and runs every test: g++ and clang++ builds with warnings as errors (tests,
# examples, benchmarks), the test suite again under AddressSanitizer + UBSan (a Debug build,
# so assertions are on; the renderer too), a CUDA check of the headers when nvcc is available,
# and the fuzz targets (clang's libFuzzer): the checked-in corpus replayed, then
# FUZZ_SECONDS (default 30) of exploration per target.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh cmake make g++ clang libglm-dev libgtest-dev libgmock-dev \
  libbenchmark-dev libstb-dev libembree-dev libtbb-dev libtinyobjloader-dev libopenexr-dev \
  libcli11-dev libclang-rt-dev

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
  # The GPU benchmark of the DI pipeline (benchmarks/cuda; scripts/gpu-benchmark.sh runs it).
  "$nvcc_bin" "${nvcc_flags[@]}" -O3 benchmarks/cuda/di_pipeline.cu -o build/cuda/di_pipeline
  # Each header alone, as g++ checks it in CMake (restir_header_check).
  for header in $(cd include && find restir -name '*.hpp' | sort); do
    echo "#include <$header>" >build/cuda/header.cu
    "$nvcc_bin" "${nvcc_flags[@]}" -c build/cuda/header.cu -o build/cuda/header.o ||
      { echo "$header does not compile alone under nvcc"; exit 1; }
  done
  echo "passed: tests/cuda/*.cu and each header alone compile with $("$nvcc_bin" --version | tail -1)"
  # The benchmark's CPU passes alone, small: the program runs and writes its image.
  build/cuda/di_pipeline --cpu-only --width 64 --height 36 --frames 3 --vpls 2000 \
    --image build/cuda/di_pipeline.ppm >build/cuda/di_pipeline_cpu.log 2>&1 ||
    { cat build/cuda/di_pipeline_cpu.log; exit 1; }
  echo "passed: build/cuda/di_pipeline --cpu-only"
  if nvidia-smi -L >/dev/null 2>&1; then
    build/cuda/device_check
    # GPU and CPU passes compared item by item (exit 1 on a difference).
    build/cuda/di_pipeline --width 320 --height 180 --frames 5 --warmup 1 --check-frames 3
  else
    echo "skipped: no GPU to run build/cuda/device_check and build/cuda/di_pipeline (GPU vs CPU results)"
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

echo "== build/fuzz: libFuzzer targets (tests/fuzz)"
if echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, unsigned long) { return 0; }' |
  clang++ -x c++ -fsanitize=fuzzer - -o /dev/null 2>/dev/null; then
  build_and_test fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DRESTIR_FUZZ=ON -DRESTIR_BUILD_TESTS=OFF -DRESTIR_BUILD_EXAMPLES=OFF \
    -DRESTIR_BUILD_BENCHMARKS=OFF
  seconds=${FUZZ_SECONDS:-30}
  for target in obj exr pfm command_line; do
    # New inputs go to a scratch folder; the checked-in corpus stays as it is.
    scratch="build/fuzz/corpus/$target"
    mkdir -p "$scratch"
    log="build/fuzz/fuzz_$target.log"
    if ! "build/fuzz/tests/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout=10 \
      -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix=build/fuzz/ "$scratch" "tests/fuzz/corpus/$target" >"$log" 2>&1; then
      tail -n 40 "$log"
      echo "fuzz_$target found a failure: the input is in build/fuzz (crash-*, timeout-*, oom-*)"
      exit 1
    fi
    echo "fuzz_$target: $(grep -E '^stat::number_of_executed_units' "$log" | awk '{print $2}') runs in ${seconds} s," \
      "coverage $(grep -oE 'cov: [0-9]+' "$log" | tail -1 | awk '{print $2}') edges"
  done
else
  echo "skipped: clang++ cannot build libFuzzer targets here"
fi
