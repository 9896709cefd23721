// The instruction set the runtime is compiled for, and the two primitives
// whose code depends on it.
//
// Code compiled for different instruction sets (a benchmark built with
// -march=native linked with a generic library) must not be merged by the
// linker as one inline function: the ISA names an inline namespace. Every
// header of hot inline code is in it: the kernels' evaluation (detail/,
// StaticKernel) and the solvers (sph/, poisson/, vortex/: their AVX2 paths
// and whatever the compiler vectorises; tests/isa_units_test). Not in it: the
// compiled library's interface (Kernel, Smoothing, specs) and table.hpp's
// checks and reference evaluation, which are not hot.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#if defined(__AVX512F__)
#define MOLLIFY_ISA isa_avx512
#elif defined(__AVX2__) && defined(__FMA__)
#define MOLLIFY_ISA isa_avx2_fma
#elif defined(__FMA__) || defined(__FP_FAST_FMA)
#define MOLLIFY_ISA isa_fma
#else
#define MOLLIFY_ISA isa_generic
#endif

#if defined(__FMA__) || defined(__FP_FAST_FMA)
#define MOLLIFY_HAS_FMA 1
#else
#define MOLLIFY_HAS_FMA 0
#endif

// The entry points of a kernel evaluation (StaticKernel) are inlined
// always: a batch loop is then straight-line code that vectorises.
//
// Forced inlining buys speed and nothing else; a unit built to check
// values or memory rather than to run fast defines MOLLIFY_NO_FORCED_INLINE
// (the sanitizer build, runtime_forms_test: tests/CMakeLists.txt) and leaves
// the inlining to the compiler, which halves the compile time of the units
// that instantiate many kernels (the x86-64-v3 evaluator under ASan 82 ->
// 50 s CPU, a runtime_forms_test part 27 -> 18 s). For generic x86-64 no
// rounding changes (no FMA: nothing to contract across inlined calls), so
// the bit-for-bit comparisons with the generic library stay exact.
#if defined(__GNUC__) && !defined(MOLLIFY_NO_FORCED_INLINE)
#define MOLLIFY_INLINE [[gnu::always_inline]] inline
#define MOLLIFY_INLINE_LAMBDA __attribute__((always_inline))  // after a lambda's parameters
#else
#define MOLLIFY_INLINE inline
#define MOLLIFY_INLINE_LAMBDA
#endif

// The batch loops are flattened: every call inside them is inlined, however
// large the translation unit. GCC's inliner otherwise stops at its unit
// growth limit in units that instantiate many kernels (the run-time
// registry, the benchmark): the double-double helpers of
// Precision::accurate then stay calls and the loop neither inlines nor
// vectorises (measured 73 against 13 cycles per W + grad W). Flattening
// does not reach a helper GCC has already replaced by an IPA-SRA clone
// (arguments by value); the pieces of Precision::accurate, where that
// happened (combinations: 138 against 11 ns), are MOLLIFY_INLINE instead.
#if defined(__GNUC__) && !defined(MOLLIFY_NO_FORCED_INLINE)
#define MOLLIFY_FLATTEN [[gnu::flatten]]
#define MOLLIFY_NOINLINE [[gnu::noinline]] inline
#else
#define MOLLIFY_FLATTEN
#define MOLLIFY_NOINLINE inline
#endif

// A batch loop of StaticKernel (its entry points over many points). GCC's
// tuning for AMD Zen 1 (-march=native there is znver1; Excavator's is alike)
// prefers 128-bit vectors to 256-bit ones, and these loops then ran 11-24 %
// slower, both precisions (kernel_bench on an EPYC 7001: Wendland C4's
// W + grad W 59 -> 47 us accurate, 36 -> 30 us fast per 4096 points;
// README "Runtime accuracy and speed"). So in an AVX2 unit without AVX-512
// they ask for 256-bit vectors; every other AVX2 tuning of GCC prefers them
// already. GCC's tuning for Intel's AVX-512 server cores prefers 256-bit
// vectors too, where these loops run 17-23 % faster with 512-bit ones
// (kernel_bench, an Intel Xeon of the Sapphire/Granite Rapids line, stop 62:
// Wendland C4's W + grad W 8.97 -> 6.87 us accurate, 4.40 -> 3.64 us fast per
// 4096 points; the run-time form's x86-64-v4 copy, tuned generic, had them
// already), so in an AVX-512 unit they ask for 512-bit vectors. The vector
// width changes no rounding: each lane does the scalar loop's operations
// (the same bits, tests/batch_loops/batches.cpp). Not inlined there: inlined
// into its caller, a loop takes the caller's preference.
#if defined(__GNUC__) && !defined(__clang__) && !defined(MOLLIFY_NO_FORCED_INLINE) && defined(__AVX512F__)
#define MOLLIFY_BATCH_LOOP [[gnu::flatten, gnu::noinline, gnu::target("prefer-vector-width=512")]]
#elif defined(__GNUC__) && !defined(__clang__) && !defined(MOLLIFY_NO_FORCED_INLINE) && defined(__AVX2__)
#define MOLLIFY_BATCH_LOOP [[gnu::flatten, gnu::noinline, gnu::target("prefer-vector-width=256")]]
#elif defined(__clang__) && !defined(MOLLIFY_NO_FORCED_INLINE) && defined(__AVX512F__)
#define MOLLIFY_BATCH_LOOP [[gnu::flatten, gnu::noinline, clang::min_vector_width(512)]]
#define MOLLIFY_VECTOR_LOOP _Pragma("clang loop vectorize_width(8)")
#else
#define MOLLIFY_BATCH_LOOP MOLLIFY_FLATTEN
#endif
// clang's tuning for those cores prefers 256-bit vectors too, and clang has
// no per-function preference: there the batch loops' inner loops ask for 8
// lanes (MOLLIFY_VECTOR_LOOP before them), and their function's
// min_vector_width(512) gives those 512-bit registers. A clang unit built
// -march=native on an Intel AVX-512 host ran StaticKernel's loops 1.2-3.4x
// slower than GCC's before, about as fast after (stop 73, README
// "Compilers"). Elsewhere the loops keep the compiler's choice.
#ifndef MOLLIFY_VECTOR_LOOP
#define MOLLIFY_VECTOR_LOOP
#endif
// Around loops that ask for vectors (MOLLIFY_VECTOR_LOOP, MOLLIFY_SIMD):
// where clang cannot vectorise one as asked it warns (-Wpass-failed), an
// error in a user's unit built -Werror; a missed optimisation, not a defect
// (kernel_bench measures it).
#if defined(__clang__)
#define MOLLIFY_VECTOR_MISSES_ALLOWED_BEGIN \
    _Pragma("clang diagnostic push") _Pragma("clang diagnostic ignored \"-Wpass-failed\"")
#define MOLLIFY_VECTOR_MISSES_ALLOWED_END _Pragma("clang diagnostic pop")
#else
#define MOLLIFY_VECTOR_MISSES_ALLOWED_BEGIN
#define MOLLIFY_VECTOR_MISSES_ALLOWED_END
#endif

namespace mollify::detail {
inline namespace MOLLIFY_ISA {

// Doubles per vector register of the unit's instruction set: loops that
// keep several lanes of sums in registers take this many at a time (a
// wider GCC vector lives in several registers and can overflow the 16 of
// AVX2 or SSE2: poisson/multipole.hpp's tile_dot).
inline constexpr int register_doubles =
#if defined(__AVX512F__)
    8;
#elif defined(__AVX__)
    4;
#else
    2;
#endif

// a*b + c with one rounding where the target has a fused multiply-add;
// without one, std::fma would be a slow library call.
inline double mul_add(double a, double b, double c) {
#if MOLLIFY_HAS_FMA
    return std::fma(a, b, c);
#else
    return a * b + c;
#endif
}

// c ? a : b on the bits, with both sides already computed: GCC will not
// if-convert a ternary whose arms it sank into branches (floating point may
// trap under the default -ftrapping-math), and a branch stops vectorisation.
inline double select(bool c, double a, double b) {
    const std::uint64_t mask = 0 - static_cast<std::uint64_t>(c);
    return std::bit_cast<double>((std::bit_cast<std::uint64_t>(a) & mask) | (std::bit_cast<std::uint64_t>(b) & ~mask));
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::detail
