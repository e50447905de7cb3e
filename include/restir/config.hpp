/// @file config.hpp
/// Compile-time configuration: host/device annotation, assertions and version macros.
#pragma once

#define RESTIR_VERSION_MAJOR 0
#define RESTIR_VERSION_MINOR 2
#define RESTIR_VERSION_PATCH 0
/// Single comparable number: major * 10000 + minor * 100 + patch.
#define RESTIR_VERSION                                                                             \
    (RESTIR_VERSION_MAJOR * 10000 + RESTIR_VERSION_MINOR * 100 + RESTIR_VERSION_PATCH)

/// Marks every function that may run on a GPU. Expands to `__host__ __device__` under
/// nvcc (and hipcc), to nothing in a plain C++ compiler.
#if defined(__CUDACC__) || defined(__HIPCC__)
#define RESTIR_HOST_DEVICE __host__ __device__
#define RESTIR_DEVICE_COMPILER 1
#else
#define RESTIR_HOST_DEVICE
#define RESTIR_DEVICE_COMPILER 0
#endif

/// Before a `RESTIR_HOST_DEVICE` template that only calls what it is given (`visit_stage`):
/// under nvcc, the callable decides where it runs (a host lambda that launches kernels, a
/// device one that runs a stage), so the host/device check of the call is left to it.
#if defined(__CUDACC__) && !defined(__HIPCC__)
#define RESTIR_CALLS_ANY_SIDE _Pragma("nv_exec_check_disable")
#else
#define RESTIR_CALLS_ANY_SIDE
#endif

/// Before a loop of a compile-time trip count over a small array: in device code, unrolls it so
/// that the array's indices are constants and it stays in registers (not local memory).
#if defined(__CUDA_ARCH__)
#define RESTIR_UNROLL _Pragma("unroll")
#else
#define RESTIR_UNROLL
#endif

/// Inlines a small function into its callers where the optimiser's own choice measured slower
/// (a call in a loop of independent memory loads serialises them).
#if defined(__CUDACC__)
#define RESTIR_FORCE_INLINE __forceinline__
#elif defined(__GNUC__) || defined(__clang__)
#define RESTIR_FORCE_INLINE inline __attribute__((always_inline))
#else
#define RESTIR_FORCE_INLINE inline
#endif

/// 1 where host code may use `std::experimental::simd` (Parallelism TS 2): libstdc++'s (GCC 11
/// on, or Clang on libstdc++), outside a CUDA or HIP compilation. Such a path computes what the
/// plain loop beside it computes, bit for bit; define RESTIR_STD_SIMD 0 to take the plain loops.
#ifndef RESTIR_STD_SIMD
#include <cstddef> // defines __GLIBCXX__ with libstdc++
#if defined(__GLIBCXX__) && !RESTIR_DEVICE_COMPILER && __has_include(<experimental/simd>)
#define RESTIR_STD_SIMD 1
#else
#define RESTIR_STD_SIMD 0
#endif
#endif

/// Around a header whose loops are marked RESTIR_VECTORIZE: a loop that a build does not
/// vectorise (no optimisation, sanitizers) is only slower, so Clang's -Wpass-failed is off
/// between the two.
#if defined(__clang__)
#define RESTIR_VECTORIZE_REGION_BEGIN                                                              \
    _Pragma("clang diagnostic push") _Pragma("clang diagnostic ignored \"-Wpass-failed\"")
#define RESTIR_VECTORIZE_REGION_END _Pragma("clang diagnostic pop")
#else
#define RESTIR_VECTORIZE_REGION_BEGIN
#define RESTIR_VECTORIZE_REGION_END
#endif

/// Before a short loop whose iterations are independent (the eight lanes of a light BVH
/// group): asks Clang to vectorise it, which its cost model declines for so few iterations;
/// tells GCC the iterations are independent (`ivdep`). Nothing in device code.
#if defined(__clang__) && !defined(__CUDACC__)
#define RESTIR_VECTORIZE _Pragma("clang loop vectorize(enable)")
#elif defined(__GNUC__) && !defined(__CUDACC__)
#define RESTIR_VECTORIZE _Pragma("GCC ivdep")
#else
#define RESTIR_VECTORIZE
#endif

/// Asks for the cache line at `address` ahead of a load that is known early but needed later
/// (host code compiled by GCC or Clang; nothing elsewhere). A function whose only effects are
/// prefetches must be RESTIR_FORCE_INLINE: GCC 12 counts it free of side effects and deletes
/// its calls where it is not inlined first.
#if (defined(__GNUC__) || defined(__clang__)) && !defined(__CUDA_ARCH__)
#define RESTIR_PREFETCH(address) __builtin_prefetch(address)
#else
#define RESTIR_PREFETCH(address) static_cast<void>(address)
#endif

/// 1 where reuse passes keep their inputs as a GPU thread does: streamed, each looked up and
/// evaluated where a merge needs it (registers, no arrays); 0 where host code first gathers the
/// inputs that lend into arrays and evaluates their targets in one loop. Both give the same
/// reservoirs, bit for bit (the test `reuse.streamed_equals_gathered` builds one program each
/// way and compares them). Defaults to 1 in device code and 0 in host code; define it to 1 to
/// run the device form on a host.
#ifndef RESTIR_STREAMED_REUSE
#if defined(__CUDA_ARCH__)
#define RESTIR_STREAMED_REUSE 1
#else
#define RESTIR_STREAMED_REUSE 0
#endif
#endif

/// Debug assertion on internal invariants. Define RESTIR_ASSERT before including any restir
/// header to route it elsewhere; by default it follows `assert` (off under NDEBUG).
#ifndef RESTIR_ASSERT
#include <cassert>
#define RESTIR_ASSERT(condition) assert(condition)
#endif
