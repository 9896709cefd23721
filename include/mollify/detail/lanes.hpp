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

// v where the mask (a lane-wise comparison's: all bits set or none) is set,
// +0 elsewhere.
template <class Mask>
MOLLIFY_INLINE Lanes keep_lanes(Mask m, Lanes v) {
    static_assert(sizeof(Mask) == sizeof(Lanes));
    return std::bit_cast<Lanes>(std::bit_cast<Mask>(v) & m);
}

// The lanes' sum, lane 0 first.
MOLLIFY_INLINE double sum_lanes(Lanes v) {
    double s = v[0];
    for (int l = 1; l < register_doubles; ++l) s += v[l];
    return s;
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::detail
#endif
