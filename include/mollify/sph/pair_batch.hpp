// Pairs of particles within the support radius eps of each other, found
// in a cell list's sorted copy and collected in batches for one kernel call
// each (CellList::half_pairs, BarotropicEuler's cell sweep): the batch, and
// the loops that fill it. A home cell's candidates are one contiguous list
// (its own particles first, then the neighbouring cells' as images); each
// home particle tests them four at a time with AVX2 where the compiler
// targets it, the indices of those within eps left-packed by a table of
// the 16 masks (no branch per candidate), a scalar branch-free loop
// elsewhere.
#pragma once

#include <mollify/detail/parallel.hpp>  // MOLLIFY_SIMD
#include <mollify/sph/domain.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace mollify::sph {

// Pairs of particles found near each other, by slot in a CellList's sorted
// copy, with their displacements x_a - x_b (structure of arrays, the form
// kernel.pairs takes); y and slot hold a home cell's candidates.
template <int D>
struct PairBatch {
    // Pairs per kernel call: enough to amortise the call, few enough to
    // stay in L1 with the kernel's outputs; and squared distances per block
    // of home particles.
    static constexpr std::size_t capacity = 1024, block = 1024;
    std::array<std::vector<double>, D> d;
    std::vector<std::size_t> a, b;
    std::size_t size = 0;
    std::array<std::vector<double>, D> y;  // a home cell's candidates: positions (images), slots
    std::vector<std::size_t> slot;
    std::vector<std::uint32_t> close;  // the candidates within eps of one home particle
    // The aliased case (fewer than 3 cells on a periodic side, near_pairs):
    // squared distances per home particle of a block and candidate.
    std::size_t candidates = 0;
    std::vector<double> r2;
    std::vector<std::size_t> near, row_end;

    void reserve(std::size_t n) {
        if (a.size() >= n) return;
        for (auto& c : d) c.resize(n);
        a.resize(n);
        b.resize(n);
    }
};

namespace detail {

// A run of consecutive slots [lo, hi) whose images lie at x + shift.
template <int D>
struct Run {
    std::size_t lo, hi;
    std::array<double, D> shift;
};

#if defined(__AVX2__)
// For each 4-bit mask, the positions of its set bits, in order (the rest 0):
// the lane offsets of the candidates within eps, left-packed.
struct LeftPack {
    alignas(16) std::array<std::array<std::int32_t, 4>, 16> lanes{};
    constexpr LeftPack() {
        for (int m = 0; m < 16; ++m) {
            int t = 0;
            for (int l = 0; l < 4; ++l)
                if (m & (1 << l)) lanes[static_cast<std::size_t>(m)][static_cast<std::size_t>(t++)] = l;
        }
    }
};
inline constexpr LeftPack left_pack{};
#endif

// Appends the indices j in [lo, hi) with |xa - y_j| <= eps (y padded by 4
// entries) to near from position k, which has room for hi - lo + 4 more;
// returns the new size. Only indices: the displacements of the few within
// eps (~1 in 7 candidates in 3D) are computed afterwards.
template <int D>
[[gnu::always_inline]] inline std::size_t append_near(std::uint32_t* near, std::size_t k, const std::array<double, D>& xa,
                                                      const std::array<const double*, D>& y, std::size_t lo,
                                                      std::size_t hi, double eps2) {
#if defined(__AVX2__)
    __m256d xv[D];
    for (int c = 0; c < D; ++c) xv[c] = _mm256_set1_pd(xa[static_cast<std::size_t>(c)]);
    const __m256d e2 = _mm256_set1_pd(eps2);
    // Full vectors, then the last partial one with its lanes past hi masked.
    // The indices: the 4 lanes' base s kept broadcast, advanced by 4.
    const auto near_mask = [&](std::size_t s) {
        __m256d dc = _mm256_sub_pd(xv[0], _mm256_loadu_pd(y[0] + s));
        __m256d r2 = _mm256_mul_pd(dc, dc);
        for (int c = 1; c < D; ++c) {
            dc = _mm256_sub_pd(xv[c], _mm256_loadu_pd(y[static_cast<std::size_t>(c)] + s));
            r2 = _mm256_fmadd_pd(dc, dc, r2);
        }
        return static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(r2, e2, _CMP_LE_OQ)));
    };
    const auto pack = [&](unsigned mask, __m128i at) {
        const __m128i lanes = _mm_load_si128(reinterpret_cast<const __m128i*>(left_pack.lanes[mask].data()));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(near + k), _mm_add_epi32(lanes, at));
        k += static_cast<std::size_t>(__builtin_popcount(mask));
    };
    __m128i at = _mm_set1_epi32(static_cast<std::int32_t>(lo));
    const __m128i four = _mm_set1_epi32(4);
    std::size_t s = lo;
    for (; s + 4 <= hi; s += 4) {
        pack(near_mask(s), at);
        at = _mm_add_epi32(at, four);
    }
    if (s < hi) pack(near_mask(s) & ((1u << (hi - s)) - 1), at);
#else
    for (std::size_t s = lo; s < hi; ++s) {
        double r2 = 0;
        for (int c = 0; c < D; ++c) {
            const double dc = xa[static_cast<std::size_t>(c)] - y[static_cast<std::size_t>(c)][s];
            r2 += dc * dc;
        }
        near[k] = static_cast<std::uint32_t>(s);
        k += r2 <= eps2 ? 1 : 0;
    }
#endif
    return k;
}

// Appends the pairs (a, j), a0 <= a < a1, a < j < nc, of candidates within
// eps to the batch; returns the new size. Three passes, so that the costly
// one runs in SIMD: the squared distances of the block's rows (vectorised),
// the indices of those within eps compacted branch-free (rows apart, so the
// loads do not wait on the wide stores just made), and the displacements
// of those (~1 in 7 candidates in 3D) stored.
template <int D, bool minimum_image>
std::size_t near_pairs(PairBatch<D>& b, std::size_t a0, std::size_t a1, std::size_t nc, double eps,
                       const Domain<D>& domain) {
    const double eps2 = eps * eps;
    std::array<const double*, D> y;
    for (int c = 0; c < D; ++c) y[c] = b.y[c].data();
    double* __restrict r2 = b.r2.data();
    const double L = domain.length(), inverse = domain.is_periodic() ? 1 / domain.length() : 0.0;
    for (std::size_t a = a0; a < a1; ++a) {
        std::array<double, D> xa;
        for (int c = 0; c < D; ++c) xa[c] = y[c][a];
        double* __restrict row = r2 + (a - a0) * nc;
        MOLLIFY_SIMD
        for (std::size_t j = a + 1; j < nc; ++j) {
            double s = 0;
            for (int c = 0; c < D; ++c) {
                double dc = xa[c] - y[c][j];
                if constexpr (minimum_image) dc -= L * std::nearbyint(dc * inverse);
                s += dc * dc;
            }
            row[j] = s;
        }
    }
    std::size_t* __restrict near = b.near.data();
    std::size_t m = 0;
    for (std::size_t a = a0; a < a1; ++a) {
        const double* row = r2 + (a - a0) * nc;
        for (std::size_t j = a + 1; j < nc; ++j) {
            near[m] = j;
            m += row[j] <= eps2 ? 1 : 0;
        }
        b.row_end[a - a0] = m;
    }
    std::size_t k = b.size, q = 0;
    for (std::size_t a = a0; a < a1; ++a) {
        std::array<double, D> xa;
        for (int c = 0; c < D; ++c) xa[c] = y[c][a];
        const std::size_t sa = b.slot[a];
        for (; q < b.row_end[a - a0]; ++q, ++k) {
            const std::size_t j = near[q];
            for (int c = 0; c < D; ++c) {
                double dc = xa[c] - y[c][j];
                if constexpr (minimum_image) dc -= L * std::nearbyint(dc * inverse);
                b.d[c][k] = dc;
            }
            b.a[k] = sa;
            b.b[k] = b.slot[j];
        }
    }
    return k;
}

}  // namespace detail

}  // namespace mollify::sph
