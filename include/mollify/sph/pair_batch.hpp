// Pairs of particles within the support radius eps of each other, found
// in a cell list's sorted copy and collected in batches for one kernel call
// each (CellList::half_pairs, BarotropicEuler's cell sweep): the batch, and
// the loops that fill it. A home cell's candidates are one contiguous list
// (its own particles first, then the neighbouring cells' as images); each
// home particle tests them eight at a time with AVX-512 where the compiler
// targets it (the indices of those within eps compressed in a register,
// their displacements gathered), four at a time with AVX2 (the indices
// left-packed by a table of the 16 masks), a scalar branch-free loop
// elsewhere: no branch per candidate.
#pragma once

#include <mollify/detail/coloured_allocator.hpp>
#include <mollify/detail/isa.hpp>
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
inline namespace MOLLIFY_ISA {

// Pairs of particles found near each other, by slot in a CellList's sorted
// copy, with their displacements x_a - x_b (structure of arrays, the form
// kernel.pairs takes); y and slot hold a home cell's candidates.
template <int D>
struct PairBatch {
    // Pairs per kernel call: enough to amortise the call, few enough to
    // stay in L1 with the kernel's outputs; and squared distances per block
    // of home particles.
    static constexpr std::size_t capacity = 1024, block = 1024;
    // Each buffer of the hot loops its own colour (detail::ColouredAllocator):
    // append_near reads y and writes close, store_pairs writes d, a and b,
    // the kernel reads d and writes its outputs (BarotropicEuler's scratch,
    // colours from next_colour on). close lies 1-3 colours below y (mod
    // 4 KiB): the loads of y run ahead of the stores to close, at 8 bytes a
    // candidate against 4 a candidate within eps, so they reach a recent
    // store's offset only past ~450 candidates; 2-4 colours above y they met
    // within every home particle's ~250, and the 3D sweep at N ~ 10^4 took
    // ~30 % longer in some processes (stop 68).
    enum : std::size_t { close_colour = 0, y_colour = 1, slot_colour = 4, d_colour = 5, a_colour = 8, b_colour = 9,
                         ends_colour = 10, next_colour = 11 };
    template <class T>
    using Buffer = mollify::detail::ColouredVector<T>;
    template <class T>
    static Buffer<T> buffer(std::size_t colour) {
        return Buffer<T>(mollify::detail::ColouredAllocator<T>(colour));
    }
    template <class T>
    static std::array<Buffer<T>, D> buffers(std::size_t first_colour) {
        std::array<Buffer<T>, D> v;
        for (int c = 0; c < D; ++c) v[static_cast<std::size_t>(c)] = buffer<T>(first_colour + static_cast<std::size_t>(c));
        return v;
    }

    std::array<Buffer<double>, D> d = buffers<double>(d_colour);
    Buffer<std::size_t> a = buffer<std::size_t>(a_colour), b = buffer<std::size_t>(b_colour);
    std::size_t size = 0;
    // The pairs come grouped by a (one home particle after another): group
    // g is [ends[g - 1], ends[g]), with ends[-1] = 0.
    Buffer<std::size_t> ends = buffer<std::size_t>(ends_colour);
    std::size_t groups = 0;
    // a home cell's candidates: positions (images), slots
    std::array<Buffer<double>, D> y = buffers<double>(y_colour);
    Buffer<std::size_t> slot = buffer<std::size_t>(slot_colour);
    Buffer<std::uint32_t> close = buffer<std::uint32_t>(close_colour);  // the candidates within eps of one home particle
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
        ends.resize(n);
    }
    void clear() { size = groups = 0; }
    // Closes the group of the pairs appended since the last one, if any.
    void close_group(std::size_t end) {
        if (end > (groups ? ends[groups - 1] : 0)) ends[groups++] = end;
        size = end;
    }
};

namespace detail {

// to[u] = from[u] + shift and slot[u] = first + u, u < N: a fixed length,
// so straight-line vector code without a loop of its own.
template <std::size_t N>
[[gnu::always_inline]] inline void shifted_chunk(double* __restrict to, const double* __restrict from, double shift) {
    for (std::size_t u = 0; u < N; ++u) to[u] = from[u] + shift;
}
template <std::size_t N>
[[gnu::always_inline]] inline void numbered_chunk(std::size_t* __restrict slot, std::size_t first) {
    for (std::size_t u = 0; u < N; ++u) slot[u] = first + u;
}

// The rows of cells along axis 0 that a home cell meets its neighbours in,
// by their offsets on axes 1 .. D-1 (entry 0 unused): its own row first,
// then those whose last non-zero offset is +1, so that each pair of
// neighbouring cells is met once. A table, not a walk over the 3^(D-1)
// offsets: its branches mispredicted ~10 times per home cell.
constexpr std::size_t half_row_count(int d) {  // 1 + (3^(d-1) - 1)/2
    std::size_t rows = 1;
    for (int k = 1; k < d; ++k) rows *= 3;
    return 1 + (rows - 1) / 2;
}
template <int D>
inline constexpr auto half_rows = [] {
    std::array<std::array<int, D>, half_row_count(D)> rows{};
    std::size_t n = 1;  // rows[0]: all offsets 0
    std::array<int, D> off{};
    for (int k = 1; k < D; ++k) off[static_cast<std::size_t>(k)] = -1;
    for (;;) {
        int last = 0;  // the last non-zero offset
        for (int c = D - 1; c >= 1 && last == 0; --c) last = off[static_cast<std::size_t>(c)];
        if (last > 0) rows[n++] = off;
        int c = 1;
        while (c < D && off[static_cast<std::size_t>(c)] == 1) off[static_cast<std::size_t>(c++)] = -1;
        if (c >= D) break;
        ++off[static_cast<std::size_t>(c)];
    }
    return rows;
}();

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

// Appends the indices j in [lo, hi) with |xa - y_j| <= eps (y padded by 8
// entries) to near from position k, which has room for hi - lo + 8 more;
// returns the new size. Only indices: the displacements of the few within
// eps (~1 in 7 candidates in 3D) are computed afterwards.
template <int D>
[[gnu::always_inline]] inline std::size_t append_near(std::uint32_t* near, std::size_t k, const std::array<double, D>& xa,
                                                      const std::array<const double*, D>& y, std::size_t lo,
                                                      std::size_t hi, double eps2) {
#if defined(__AVX512F__) && defined(__AVX512VL__)
    // Eight candidates a step, the indices of those within eps compressed
    // in a register (the memory form of compress is slow on Zen 4).
    __m512d xv[D];
    for (int c = 0; c < D; ++c) xv[c] = _mm512_set1_pd(xa[static_cast<std::size_t>(c)]);
    const __m512d e2 = _mm512_set1_pd(eps2);
    const auto near_mask = [&](std::size_t s) {
        __m512d dc = _mm512_sub_pd(xv[0], _mm512_loadu_pd(y[0] + s));
        __m512d r2 = _mm512_mul_pd(dc, dc);
        for (int c = 1; c < D; ++c) {
            dc = _mm512_sub_pd(xv[c], _mm512_loadu_pd(y[static_cast<std::size_t>(c)] + s));
            r2 = _mm512_fmadd_pd(dc, dc, r2);
        }
        return _mm512_cmp_pd_mask(r2, e2, _CMP_LE_OQ);
    };
    const auto pack = [&](__mmask8 mask, __m256i at) {
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(near + k), _mm256_maskz_compress_epi32(mask, at));
        k += static_cast<std::size_t>(__builtin_popcount(mask));
    };
    __m256i at = _mm256_add_epi32(_mm256_set1_epi32(static_cast<std::int32_t>(lo)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    const __m256i eight = _mm256_set1_epi32(8);
    std::size_t s = lo;
    for (; s + 8 <= hi; s += 8) {
        pack(near_mask(s), at);
        at = _mm256_add_epi32(at, eight);
    }
    if (s < hi) pack(static_cast<__mmask8>(near_mask(s) & ((1u << (hi - s)) - 1)), at);
#elif defined(__AVX2__)
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

// Stores the pairs (a, close[q]), q < m, from position k of the batch: slots
// and displacements x_a - y_j. With AVX-512 eight at a time by gathers.
template <int D>
[[gnu::always_inline]] inline void store_pairs(PairBatch<D>& b, std::size_t k, const std::uint32_t* close, std::size_t m,
                                               const std::array<double, D>& xa, const std::array<const double*, D>& y,
                                               const std::size_t* slot, std::size_t sa) {
#if defined(__AVX512F__) && defined(__AVX512VL__)
    static_assert(sizeof(std::size_t) == 8);
    __m512d xv[D];
    for (int c = 0; c < D; ++c) xv[c] = _mm512_set1_pd(xa[static_cast<std::size_t>(c)]);
    const __m512i a = _mm512_set1_epi64(static_cast<long long>(sa));
    const auto chunk = [&](std::size_t q) {  // pairs q .. q + 7 (those below m)
        const __mmask8 live = m >= q + 8 ? __mmask8(0xFF) : m > q ? static_cast<__mmask8>((1u << (m - q)) - 1) : __mmask8(0);
        const __m256i j = _mm256_maskz_loadu_epi32(live, close + q);
        for (int c = 0; c < D; ++c) {
            const __m512d yj = _mm512_mask_i32gather_pd(_mm512_setzero_pd(), live, j, y[static_cast<std::size_t>(c)], 8);
            _mm512_mask_storeu_pd(b.d[c].data() + k + q, live, _mm512_sub_pd(xv[c], yj));
        }
        _mm512_mask_storeu_epi64(b.a.data() + k + q, live, a);
        _mm512_mask_storeu_epi64(b.b.data() + k + q, live, _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), live, j, slot, 8));
    };
    // Two chunks whatever m (~15 in 3D at ~30 neighbours), so that the
    // common case takes no data-dependent branch; a loop for the rest.
    chunk(0);
    chunk(8);
    for (std::size_t q = 16; q < m; q += 8) chunk(q);
#else
    for (std::size_t q = 0; q < m; ++q) {
        const std::size_t j = close[q];
        for (int c = 0; c < D; ++c) b.d[c][k + q] = xa[static_cast<std::size_t>(c)] - y[static_cast<std::size_t>(c)][j];
        b.a[k + q] = sa;
        b.b[k + q] = slot[j];
    }
#endif
}

// Appends the pairs (a, j), a0 <= a < a1, a < j < nc, of candidates within
// eps to the batch; returns the new size. Three passes, so that the costly
// one runs in SIMD: the squared distances of the block's rows (vectorised),
// the indices of those within eps compacted branch-free (rows apart, so the
// loads do not wait on the wide stores just made), and the displacements
// of those (~1 in 7 candidates in 3D) stored.
// (clang cannot vectorise the minimum image's nearbyint on a target
// without SSE4.1's rounding.)
MOLLIFY_VECTOR_MISSES_ALLOWED_BEGIN
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
        b.close_group(k);
    }
    return k;
}
MOLLIFY_VECTOR_MISSES_ALLOWED_END

}  // namespace detail

}  // namespace MOLLIFY_ISA
}  // namespace mollify::sph
