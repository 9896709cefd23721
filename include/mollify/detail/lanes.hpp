// A register's worth of doubles (detail::register_doubles) as one GCC/Clang
// vector, for the loops written lane-wise by hand rather than left to the
// vectoriser: those that keep many sums in registers (poisson/multipole.hpp's
// M2L and L2P) and those that issue a slow operation ahead of its use
// (poisson/pair_sum.hpp's Green's passes). Each operation is the scalar
// one per lane (the same roundings). Only where MOLLIFY_LANES is defined
// (GCC and Clang); callers keep a plain loop for other compilers.
#pragma once

#include <mollify/detail/isa.hpp>

#include <bit>
#include <cmath>
#include <cstring>

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#include <immintrin.h>
#endif

namespace mollify::detail {
inline namespace MOLLIFY_ISA {

// The two ways of the Green's passes' 1/sqrt (inverse_sqrt_lanes below).
enum class InverseSqrt { divide, refine };

// The way this processor takes 1/sqrt faster, once per process: on Intel's
// AVX-512 cores the divider takes a block's square root and division in
// ~40 cycles, where the refinement's six operations share the two
// multiply-add ports (an Intel Xeon, 2026-12-04: the treecode's mutual
// Green's pass went from 43 % to ~30 % of the time, 10^6 neutral sources
// 7.0 -> 5.3-6.3 s); on AMD's Zen 5 a refinement of two Newton steps was 6 %
// slower in the same pass (stop 42), on Zen 1 (rsqrtps, AVX2) slower too
// (stop 48): AMD keeps the division. Without AVX-512 there is no estimate
// of a double's 1/sqrt to refine.
inline InverseSqrt fastest_inverse_sqrt() {
#if defined(__AVX512F__) && defined(__AVX512DQ__) && defined(__GNUC__)
    static const InverseSqrt how = [] {
        __builtin_cpu_init();
        return __builtin_cpu_is("intel") ? InverseSqrt::refine : InverseSqrt::divide;
    }();
    return how;
#else
    return InverseSqrt::divide;
#endif
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::detail

#if defined(__GNUC__)
#define MOLLIFY_LANES 1

namespace mollify::detail {
inline namespace MOLLIFY_ISA {

typedef double Lanes __attribute__((vector_size(register_doubles * sizeof(double))));

// Unaligned loads and stores (memcpy: no alignment or aliasing assumed).
MOLLIFY_INLINE Lanes load_lanes(const double* p) {
    Lanes v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
MOLLIFY_INLINE void store_lanes(double* p, Lanes v) { std::memcpy(p, &v, sizeof v); }

// Lane-wise square root and a*b + c (one rounding where the unit has FMA,
// as mul_add): by the instruction itself, since GCC's SLP splits a lane loop
// to the tuning's preferred width (two 128-bit square roots on AMD Zen 1).
MOLLIFY_INLINE Lanes sqrt_lanes(Lanes a) {
#if defined(__AVX512F__)
    return _mm512_mask_sqrt_pd(a, 0xff, a);  // _mm512_sqrt_pd's undefined source trips GCC 12's -Wmaybe-uninitialized
#elif defined(__AVX__)
    return _mm256_sqrt_pd(a);
#elif defined(__SSE2__)
    return _mm_sqrt_pd(a);
#else
    Lanes r;
    for (int l = 0; l < register_doubles; ++l) r[l] = std::sqrt(a[l]);
    return r;
#endif
}
MOLLIFY_INLINE Lanes mul_add_lanes(Lanes a, Lanes b, Lanes c) {
#if defined(__AVX512F__)
    return _mm512_fmadd_pd(a, b, c);
#elif defined(__FMA__) && defined(__AVX__)
    return _mm256_fmadd_pd(a, b, c);
#else
    Lanes r;
    for (int l = 0; l < register_doubles; ++l) r[l] = mul_add(a[l], b[l], c[l]);
    return r;
#endif
}

// 1/sqrt(a) lane-wise, two ways (detail::InverseSqrt): by the square root
// and the division, each correctly rounded (within ~1 ulp), and, with
// AVX-512, refined from VRSQRT14PD's estimate y0 (relative error < 2^-14):
// with e = 1 - a y0^2 (|e| < 2^-13, formed by one FMA from t = a y0),
// 1/sqrt(a) = y0 (1 - e)^(-1/2) = y0 (1 + e/2 + 3e^2/8 + 5e^3/16 + ...),
// cut after e^3 (the rest 35 e^4/128 < 2^-53.8 of the value) and summed as
// y0 + (y0 e) P(e): six operations, within ~1.5 ulp (t's rounding moves e
// by 2^-53, y by 2^-54; tests/poisson_green_test.cpp measures 1.27 ulp
// against long double). Lanes where a is 0, subnormal, infinite, negative
// or NaN (the estimate then gives 0 * inf = NaN, or is not defined) take
// the division, the whole block at once (a branch the blocks of a
// treecode never take but at coincident or overflowing points). AVX-512F
// and DQ (VFPCLASSPD), as in x86-64-v4; else the division.
#if defined(__AVX512F__) && defined(__AVX512DQ__)
MOLLIFY_INLINE Lanes refined_inverse_sqrt_lanes(Lanes a) {
    const Lanes y0 = _mm512_maskz_rsqrt14_pd(0xff, a);  // maskz: _mm512_rsqrt14_pd's undefined source trips GCC 12
    const Lanes t = a * y0;
    const Lanes e = mul_add_lanes(-t, y0, Lanes{} + 1.0);
    const Lanes p = mul_add_lanes(mul_add_lanes(Lanes{} + 0.3125, e, Lanes{} + 0.375), e, Lanes{} + 0.5);
    return mul_add_lanes(y0 * e, p, y0);
}

// Is a lane 0, subnormal, infinite, negative or NaN (VFPCLASSPD's classes
// QNaN, +-0, +-inf, subnormal, negative finite, SNaN)?
MOLLIFY_INLINE bool outside_refined_range(Lanes a) { return _mm512_fpclass_pd_mask(a, 0xff) != 0; }
#define MOLLIFY_REFINED_INVERSE_SQRT 1
#endif

template <InverseSqrt How>
MOLLIFY_INLINE Lanes inverse_sqrt_lanes(Lanes a) {
#if defined(MOLLIFY_REFINED_INVERSE_SQRT)
    if constexpr (How == InverseSqrt::refine) {
        if (!outside_refined_range(a)) [[likely]]
            return refined_inverse_sqrt_lanes(a);
    }
#endif
    return 1.0 / sqrt_lanes(a);
}

// Lane-wise a >= b (false where either is NaN) as a mask: AVX-512's mask
// register, else the comparison's vector (all bits set or none per lane);
// keep_lanes(m, v): v where m is set, +0 elsewhere; clear_lanes(m): the
// lanes where m is clear, as bits (lane l at bit l).
#if defined(__AVX512F__)
using LaneMask = __mmask8;
MOLLIFY_INLINE LaneMask at_least_lanes(Lanes a, Lanes b) { return _mm512_cmp_pd_mask(a, b, _CMP_GE_OQ); }
MOLLIFY_INLINE Lanes keep_lanes(LaneMask m, Lanes v) { return _mm512_maskz_mov_pd(m, v); }
MOLLIFY_INLINE unsigned clear_lanes(LaneMask m) { return static_cast<unsigned>(static_cast<LaneMask>(~m)); }
#else
using LaneMask = decltype(Lanes{} >= Lanes{});
MOLLIFY_INLINE LaneMask at_least_lanes(Lanes a, Lanes b) { return a >= b; }
MOLLIFY_INLINE Lanes keep_lanes(LaneMask m, Lanes v) { return std::bit_cast<Lanes>(std::bit_cast<LaneMask>(v) & m); }
MOLLIFY_INLINE unsigned clear_lanes(LaneMask m) {
#if defined(__AVX__)
    return static_cast<unsigned>(~_mm256_movemask_pd(std::bit_cast<__m256d>(m))) & 0xfu;
#else
    unsigned bits = 0;
    for (int l = 0; l < register_doubles; ++l) bits |= m[l] ? 0u : 1u << l;
    return bits;
#endif
}
#endif

// The lanes' sum, lane 0 first.
MOLLIFY_INLINE double sum_lanes(Lanes v) {
    double s = v[0];
    for (int l = 1; l < register_doubles; ++l) s += v[l];
    return s;
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::detail
#endif
