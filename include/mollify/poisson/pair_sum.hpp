// The exact mollified sum over a contiguous range of sources at one target:
// sum_j q_j phi_delta_j(|x - x_j|) and its field, the inner loop of direct
// summation and of the treecode's near field. Sources are copied once into
// SourceArrays (the treecode reorders them); the loop runs in blocks: the
// radii of a block and the Green's function for all its pairs (vectorised),
// one batch call of the kernel per quantity (potential, phi'/r) for the
// pairs within a support, then the weighted sums (vectorised reductions).
//
// The treecode's near field uses two variants (add_green, within_kernel,
// at the end): the Green's function for the pairs beyond their support over
// sources gathered from several cells, and the exact kernel only for the
// pairs within a support, which the Green's passes list.
//
// Per-source smoothing lengths use the scaling of the runtime
// (include/mollify/smoothing.hpp): f_delta(r) = delta^p f_1(r/delta), with
// p = 2 - D for the potential (plus log(delta)/(2 pi) in 2D) and p = -D for
// phi'/r. A global delta uses Smoothing(delta) directly, so a single source
// gets the runtime's own accuracy.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/lanes.hpp>
#include <mollify/dynamic_kernel.hpp>
#include <mollify/kernel_concept.hpp>
#include <mollify/poisson/sources.hpp>
#include <mollify/smoothing.hpp>
#include <mollify/static_kernel.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <string>
#include <vector>

#if defined(_OPENMP)
#define MOLLIFY_STRINGIFY(...) #__VA_ARGS__
#define MOLLIFY_SIMD_REDUCTION(...) _Pragma(MOLLIFY_STRINGIFY(omp simd reduction(+ : __VA_ARGS__)))
#else
#define MOLLIFY_SIMD_REDUCTION(...)
#endif

MOLLIFY_VECTOR_MISSES_ALLOWED_BEGIN  // its MOLLIFY_SIMD loops (detail/isa.hpp)

namespace mollify::poisson {
inline namespace MOLLIFY_ISA {
namespace detail {

using mollify::detail::fastest_inverse_sqrt;
using mollify::detail::InverseSqrt;

// Either kernel form (mollify::RadialKernel): made for the sources'
// dimension and with a potential, else a mollify::Error naming both.
template <RadialKernel K>
void check_kernel(const K& k, int dim) {
    const std::string spec(k.spec());
    if (k.dim() != dim)
        fail("kernel " + spec + " is made for D = " + std::to_string(k.dim()) + ", the sources live in D = " +
             std::to_string(dim));
    if (!k.has_potential())
        fail("kernel " + spec + " has no potential in D = " + std::to_string(dim) + " (the Poisson solvers need one)");
}

// One batch of f_s(r) for the potential quantities (the radii are checked
// in one cheap pass, as any caller's).
template <QuantityId Q, RadialKernel K>
void batch(const K& k, const double* r, double* out, std::size_t n, const Smoothing& s) {
    k.evaluate(Q, std::span<const double>(r, n), s, std::span<double>(out, n));
}

inline constexpr double inv_2pi = 0.5 * std::numbers::inv_pi;  // the 2D Green's function log(r)/(2 pi)

// The sources as the sums read them: coordinates, charges, and per source
// the factors delta^(2-D), log(delta)/(2 pi) (2D) and delta^-D that turn
// unit-smoothing values at r/delta into delta-smoothed ones (only for
// per-source delta; a global delta evaluates with Smoothing(delta)).
template <int D>
struct SourceArrays {
    std::array<std::vector<double>, D> x;
    std::vector<double> q, delta, phi_scale, phi_shift, grad_scale;
    bool global = true;
    Smoothing smoothing{1.0, D};  // Smoothing(delta) if global, else the unit one

    SourceArrays(const Sources<D>& s, const std::vector<std::size_t>& order) : smoothing(s.delta[0], D) {
        global = s.global_delta();
        if (!global) smoothing = Smoothing(1.0, D);
        const std::size_t n = order.size();
        for (int k = 0; k < D; ++k) x[k].resize(n);
        q.resize(n);
        delta.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t j = order[i];
            for (int k = 0; k < D; ++k) x[k][i] = s.x[k][j];
            q[i] = s.q[j];
            delta[i] = s.delta_of(j);
        }
        if (global) return;
        phi_scale.resize(n);
        phi_shift.resize(n);
        grad_scale.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            phi_scale[i] = std::pow(delta[i], 2 - D);
            phi_shift[i] = D == 2 ? inv_2pi * std::log(delta[i]) : 0.0;
            grad_scale[i] = std::pow(delta[i], -D);
        }
    }
    std::size_t size() const { return q.size(); }
};

inline constexpr std::size_t block = 128;

// Outside the support phi_delta = G and phi_delta'/r = G'(r)/r:
// 3D -1/(4 pi r) and 1/(4 pi r^3), 2D log(r)/(2 pi) and 1/(2 pi r^2)
// (the runtime's exterior pieces, static_kernel.hpp). Every pair of a block
// gets these (a vectorised loop); the few pairs inside a support are then
// overwritten with the kernel's batch values.
template <int D>
inline void green(const double* r, double* pot, double* g, std::size_t n) {
    constexpr double k = D == 3 ? 0.25 * std::numbers::inv_pi : inv_2pi;
    for (std::size_t j = 0; j < n; ++j) {
        const double inv = 1 / r[j];
        if constexpr (D == 3) {
            pot[j] = -k * inv;
            g[j] = k * inv * inv * inv;
        } else {
            pot[j] = k * std::log(r[j]);
            g[j] = k * inv * inv;
        }
    }
}

// Adds sum over sources [begin, end) of q_j phi_j and of -q_j grad phi_j at
// the target xt to phi and E.
template <int D, RadialKernel K>
void add_exact(const K& kernel, const SourceArrays<D>& s, const std::array<double, D>& xt, std::size_t begin,
               std::size_t end, double& phi, std::array<double, D>& e) {
    alignas(64) double d[D][block], r[block], pot[block], g[block], near_r[block], near_pot[block], near_g[block];
    unsigned near[block];
    double p_sum = 0, e0 = 0, e1 = 0, e2 = 0;
    for (std::size_t b0 = begin; b0 < end; b0 += block) {
        const std::size_t n = std::min(block, end - b0);
        for (std::size_t j = 0; j < n; ++j) {
            double r2 = 0;
            for (int k = 0; k < D; ++k) {
                d[k][j] = xt[k] - s.x[k][b0 + j];
                r2 = mollify::detail::mul_add(d[k][j], d[k][j], r2);
            }
            r[j] = std::sqrt(r2);
        }
        green<D>(r, pot, g, n);
        // The pairs within a support: the exact mollified kernel.
        std::size_t m = 0;
        const double* delta = s.delta.data() + b0;
        for (std::size_t j = 0; j < n; ++j)
            if (r[j] < delta[j]) near[m++] = static_cast<unsigned>(j);
        if (m > 0) {
            for (std::size_t i = 0; i < m; ++i) near_r[i] = s.global ? r[near[i]] : r[near[i]] / delta[near[i]];
            batch<QuantityId::potential>(kernel, near_r, near_pot, m, s.smoothing);
            batch<QuantityId::dpotential_over_r>(kernel, near_r, near_g, m, s.smoothing);
            for (std::size_t i = 0; i < m; ++i) {
                const std::size_t j = near[i];
                if (s.global) {
                    pot[j] = near_pot[i];
                    g[j] = near_g[i];
                } else {
                    pot[j] = near_pot[i] * s.phi_scale[b0 + j] + s.phi_shift[b0 + j];
                    g[j] = near_g[i] * s.grad_scale[b0 + j];
                }
            }
        }
        // E = -grad phi = -(phi'/r) (x - x_j) per source.
        const double* q = s.q.data() + b0;
        MOLLIFY_SIMD_REDUCTION(p_sum, e0, e1, e2)
        for (std::size_t j = 0; j < n; ++j) {
            p_sum += q[j] * pot[j];
            const double gj = q[j] * g[j];
            e0 -= gj * d[0][j];
            e1 -= gj * d[1][j];
            if constexpr (D == 3) e2 -= gj * d[D - 1][j];
        }
    }
    phi += p_sum;
    e[0] += e0;
    e[1] += e1;
    if constexpr (D == 3) e[2] += e2;
}

// The treecode's near field in two parts, which together are add_exact
// over the same sources (each pair in exactly one part: r^2 >= delta_j^2
// in the first, its complement in the second).
//
// The second part's pairs, found by the first as it goes: the pairs a
// Green's pass leaves out (not r^2 >= delta^2: within a support), by their
// position in the pass's arrays and with r^2 as the pass formed it, in
// order; at and r2 hold room for every position of the pass. The search
// for them was a second pass over the near cells (the same r^2 of every
// source in the cells within delta_max of the target, ~6 % of the
// treecode); here a block of sources costs a test of the mask the Green's
// function needs anyway, and ~1 block in 25 has a pair to append.
struct WithinPairs {
    unsigned* at;
    double* r2;
    std::size_t size = 0;
    MOLLIFY_INLINE void push(std::size_t j, double r2j) {
        at[size] = static_cast<unsigned>(j);
        r2[size] = r2j;
        ++size;
    }
#if defined(MOLLIFY_LANES)
    // Lanes l of the block at j0 whose bit is set in `bits`.
    MOLLIFY_INLINE void push_lanes(std::size_t j0, unsigned bits, mollify::detail::Lanes r2j) {
#if defined(__AVX512F__) && defined(__AVX512VL__)
        const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        _mm512_mask_compressstoreu_pd(r2 + size, static_cast<__mmask8>(bits), r2j);
        _mm256_mask_compressstoreu_epi32(at + size, static_cast<__mmask8>(bits),
                                         _mm256_add_epi32(lane, _mm256_set1_epi32(static_cast<int>(j0))));
        size += static_cast<std::size_t>(std::popcount(bits));
#else
        for (; bits != 0; bits &= bits - 1) push(j0 + static_cast<std::size_t>(std::countr_zero(bits)), r2j[std::countr_zero(bits)]);
#endif
    }
#endif
};

// The Green's passes: the pairs beyond their support, where phi_delta IS
// the Green's function (3D), over n sources gathered into plain arrays
// (coordinates x, y, z, charges q, squared smoothing lengths d2), for T
// targets at once (Targets: x[t], q[t], d2[t]; their sums phi[t], e[t],
// added to; their lists to_target[t], to_source[t]), no kernel: one
// vectorised pass, 1/r from one square root and one division, or on
// Intel's AVX-512 cores refined from VRSQRT14PD's estimate (`how`,
// detail::inverse_sqrt_lanes). The pairs each leaves out go to the lists.
// Three kinds:
//   one_way        the targets feel the sources (masks r^2 >= d2[j]);
//   mutual         the sources feel the targets back (Newton's third law;
//                  masks r^2 >= d2[j] for a target, r^2 >= d2[t] for the
//                  source): their sums of q/r and q (x_j - x_t)/r^3 added
//                  to w[j], g0[j], g1[j], g2[j] (to be scaled by -1/(4 pi)
//                  like the targets'); pairs within the source's support to
//                  to_target[t], within the target's to to_source[t];
//   mutual_global  mutual with one delta (every d2[j] is d2[t], which alone
//                  is read): one mask for both directions, each pair left
//                  out once, to to_target[t] (2 of ~30 operations a block
//                  fewer).
// T targets share each block's loads of the sources and stores of their
// sums (the single-target pass loads 8 and stores 4 registers a block for
// ~30 operations; Treecode::tile has the times).
enum class GreenPass { one_way, mutual, mutual_global };

template <int T>
struct Targets {
    std::array<std::array<double, 3>, T> x;
    std::array<double, T> q, d2;
    std::array<double, T> phi{};
    std::array<std::array<double, 3>, T> e{};
    std::array<WithinPairs*, T> to_target{}, to_source{};
};

// The blocks of the division's passes issue the next block's square roots
// and divisions ahead of their use: out of order, the processor did not
// reach the next block's by itself (the rest of a block is ~40
// instructions), and on AMD Zen 1 a block's square root and division hold
// the divider for ~25 cycles. There the mutual pass went 6.6 -> 4.4 ns per
// pair (2400 sources, a test program) and the 3D treecode at N = 10^5,
// theta 0.7, p = 13 | 19 2.2 -> 1.7 | 3.2 -> 2.6 s; two blocks ahead was
// slower (2.7 s at p = 19: four more live registers of AVX2's 16). A
// block's d is formed again for use (three loads and subtractions, on
// pipes the divider leaves idle) rather than carried from its r^2, for the
// same registers. The refinement needs no look-ahead: d carried from r^2
// to its use (three subtractions and loads fewer: 0.95-1.03 -> 0.77-0.92 ns
// per pair of the mutual pass, 244 targets against 6588 sources, the Intel
// Xeon of stop 60).
template <int T, GreenPass Kind, InverseSqrt How>
MOLLIFY_INLINE void green_pass(const double* x, const double* y, const double* z, const double* q,
                                          const double* d2, std::size_t n, Targets<T>& tg, double* w, double* g0,
                                          double* g1, double* g2) {
    constexpr double k = 0.25 * std::numbers::inv_pi;
    std::array<double, T> p_sum{}, e0{}, e1{}, e2{};
    std::size_t j = 0;
#if defined(MOLLIFY_LANES)
    {
        using namespace mollify::detail;
        constexpr std::size_t N = register_doubles;
        const std::size_t nv = n - n % N;
        std::array<Lanes, T> vp{}, v0{}, v1{}, v2{};
        // The targets in registers (the passes' stores could alias tg).
        std::array<Lanes, T> tx, ty, tz, tq, td2;
        for (int t = 0; t < T; ++t) {
            tx[t] = Lanes{} + tg.x[t][0];
            ty[t] = Lanes{} + tg.x[t][1];
            tz[t] = Lanes{} + tg.x[t][2];
            tq[t] = Lanes{} + tg.q[t];
            td2[t] = Lanes{} + tg.d2[t];
        }
        const std::array<WithinPairs*, T> to_target = tg.to_target, to_source = tg.to_source;
        // The division's a block ahead, the refinement's in place (above).
        std::array<Lanes, T> r2_next{}, inv_next{};
        auto ahead = [&](std::size_t j0) {
            const Lanes X = load_lanes(x + j0), Y = load_lanes(y + j0), Z = load_lanes(z + j0);
#pragma GCC unroll 8
            for (int t = 0; t < T; ++t) {
                const Lanes dx = tx[t] - X, dy = ty[t] - Y, dz = tz[t] - Z;
                r2_next[t] = mul_add_lanes(dz, dz, mul_add_lanes(dy, dy, dx * dx));
                inv_next[t] = inverse_sqrt_lanes<How>(r2_next[t]);
            }
        };
        if constexpr (How == InverseSqrt::divide)
            if (nv > 0) ahead(0);
        for (std::size_t j0 = 0; j0 < nv; j0 += N) {
            std::array<Lanes, T> r2_now, inv_now;
            if constexpr (How == InverseSqrt::divide) {
                r2_now = r2_next;
                inv_now = inv_next;
                if (j0 + N < nv) ahead(j0 + N);
            }
            const Lanes X = load_lanes(x + j0), Y = load_lanes(y + j0), Z = load_lanes(z + j0), Q = load_lanes(q + j0);
            Lanes ws{}, gs0{}, gs1{}, gs2{};
#pragma GCC unroll 8
            for (int t = 0; t < T; ++t) {
                const Lanes dx = tx[t] - X, dy = ty[t] - Y, dz = tz[t] - Z;
                Lanes r2, inv;
                if constexpr (How == InverseSqrt::divide) {
                    r2 = r2_now[t];
                    inv = inv_now[t];
                } else {
                    r2 = mul_add_lanes(dz, dz, mul_add_lanes(dy, dy, dx * dx));
                    inv = inverse_sqrt_lanes<How>(r2);
                }
                const Lanes vd2 = td2[t];
                Lanes wt, gt, wj{}, gj{};
                if constexpr (Kind == GreenPass::one_way) {
                    const LaneMask beyond = at_least_lanes(r2, load_lanes(d2 + j0));
                    if (const unsigned in = clear_lanes(beyond)) [[unlikely]]
                        to_target[t]->push_lanes(j0, in, r2);
                    const Lanes to = keep_lanes(beyond, inv);  // 1/r, or 0 within the support
                    wt = Q * to;                               // q/r
                    gt = wt * to * to;                         // q/r^3
                } else if constexpr (Kind == GreenPass::mutual_global) {
                    const LaneMask beyond = at_least_lanes(r2, vd2);
                    if (const unsigned in = clear_lanes(beyond)) [[unlikely]]
                        to_target[t]->push_lanes(j0, in, r2);
                    const Lanes to = keep_lanes(beyond, inv), to2 = to * to;
                    wt = Q * to;
                    wj = tq[t] * to;
                    gt = wt * to2;
                    gj = wj * to2;
                } else {
                    const LaneMask beyond_t = at_least_lanes(r2, load_lanes(d2 + j0)), beyond_j = at_least_lanes(r2, vd2);
                    if (const unsigned in = clear_lanes(beyond_t)) [[unlikely]]
                        to_target[t]->push_lanes(j0, in, r2);
                    if (const unsigned in = clear_lanes(beyond_j)) [[unlikely]]
                        to_source[t]->push_lanes(j0, in, r2);
                    const Lanes to_t = keep_lanes(beyond_t, inv), to_j = keep_lanes(beyond_j, inv);
                    wt = Q * to_t;
                    wj = tq[t] * to_j;
                    gt = wt * to_t * to_t;
                    gj = wj * to_j * to_j;
                }
                vp[t] += wt;
                v0[t] = mul_add_lanes(gt, dx, v0[t]);
                v1[t] = mul_add_lanes(gt, dy, v1[t]);
                v2[t] = mul_add_lanes(gt, dz, v2[t]);
                if constexpr (Kind != GreenPass::one_way) {
                    ws += wj;
                    gs0 = mul_add_lanes(gj, dx, gs0);
                    gs1 = mul_add_lanes(gj, dy, gs1);
                    gs2 = mul_add_lanes(gj, dz, gs2);
                }
            }
            if constexpr (Kind != GreenPass::one_way) {
                store_lanes(w + j0, load_lanes(w + j0) + ws);
                store_lanes(g0 + j0, load_lanes(g0 + j0) - gs0);
                store_lanes(g1 + j0, load_lanes(g1 + j0) - gs1);
                store_lanes(g2 + j0, load_lanes(g2 + j0) - gs2);
            }
        }
        for (int t = 0; t < T; ++t) {
            p_sum[t] = sum_lanes(vp[t]);
            e0[t] = sum_lanes(v0[t]);
            e1[t] = sum_lanes(v1[t]);
            e2[t] = sum_lanes(v2[t]);
        }
        j = nv;
    }
#endif
    for (; j < n; ++j)
        for (int t = 0; t < T; ++t) {
            const double dx = tg.x[t][0] - x[j], dy = tg.x[t][1] - y[j], dz = tg.x[t][2] - z[j];
            const double r2 = mollify::detail::mul_add(dz, dz, mollify::detail::mul_add(dy, dy, dx * dx));
            constexpr bool global = Kind == GreenPass::mutual_global, one_way = Kind == GreenPass::one_way;
            const bool beyond_t = r2 >= (global ? tg.d2[t] : d2[j]), beyond_j = !one_way && r2 >= tg.d2[t];
            if (!beyond_t) tg.to_target[t]->push(j, r2);
            if (Kind == GreenPass::mutual && !beyond_j) tg.to_source[t]->push(j, r2);
            if (!beyond_t && !beyond_j) continue;
            const double inv = 1 / std::sqrt(r2);
            const double to_t = beyond_t ? inv : 0.0, to_j = beyond_j ? inv : 0.0;
            const double wt = q[j] * to_t, gt = wt * to_t * to_t;
            p_sum[t] += wt;
            e0[t] += gt * dx;
            e1[t] += gt * dy;
            e2[t] += gt * dz;
            if constexpr (one_way) continue;
            const double wj = tg.q[t] * to_j, gj = wj * to_j * to_j;
            w[j] += wj;
            g0[j] -= gj * dx;
            g1[j] -= gj * dy;
            g2[j] -= gj * dz;
        }
    for (int t = 0; t < T; ++t) {
        tg.phi[t] -= k * p_sum[t];
        tg.e[t][0] -= k * e0[t];
        tg.e[t][1] -= k * e1[t];
        tg.e[t][2] -= k * e2[t];
    }
}

// The pass with 1/sqrt the way `how` says. Its entry points below are kept
// out of line: inlined into the treecode's descend, GCC left the loop
// scalar (3x the time).
template <int T, GreenPass Kind>
MOLLIFY_INLINE void green_pass(const double* x, const double* y, const double* z, const double* q, const double* d2,
                               std::size_t n, Targets<T>& tg, double* w, double* g0, double* g1, double* g2,
                               InverseSqrt how) {
    if (how == InverseSqrt::refine)
        green_pass<T, Kind, InverseSqrt::refine>(x, y, z, q, d2, n, tg, w, g0, g1, g2);
    else
        green_pass<T, Kind, InverseSqrt::divide>(x, y, z, q, d2, n, tg, w, g0, g1, g2);
}

// The mutual pass (add_green_mutual) for T targets.
template <int T>
MOLLIFY_NOINLINE void add_green_mutual(const double* x, const double* y, const double* z, const double* q,
                                       const double* d2, std::size_t n, Targets<T>& tg, double* w, double* g0,
                                       double* g1, double* g2, InverseSqrt how = fastest_inverse_sqrt()) {
    if (tg.to_source[0] == nullptr)
        green_pass<T, GreenPass::mutual_global>(x, y, z, q, d2, n, tg, w, g0, g1, g2, how);
    else
        green_pass<T, GreenPass::mutual>(x, y, z, q, d2, n, tg, w, g0, g1, g2, how);
}

// The one-way pass for one target xt: its pairs within a support to `within`.
MOLLIFY_NOINLINE void add_green(const double* x, const double* y, const double* z, const double* q, const double* d2,
                                std::size_t n, const std::array<double, 3>& xt, double& phi, std::array<double, 3>& e,
                                WithinPairs& within, InverseSqrt how = fastest_inverse_sqrt()) {
    Targets<1> tg;
    tg.x[0] = xt;
    tg.q[0] = 0;
    tg.d2[0] = 0;
    tg.to_target[0] = &within;
    green_pass<1, GreenPass::one_way>(x, y, z, q, d2, n, tg, nullptr, nullptr, nullptr, nullptr, how);
    phi += tg.phi[0];
    for (int c = 0; c < 3; ++c) e[c] += tg.e[0][c];
}

// The mutual pass for one target (charge qt, squared smoothing length
// d2t): to_source null for one global delta.
inline void add_green_mutual(const double* x, const double* y, const double* z, const double* q, const double* d2,
                             std::size_t n, const std::array<double, 3>& xt, double qt, double d2t, double& phi,
                             std::array<double, 3>& e, double* w, double* g0, double* g1, double* g2,
                             WithinPairs& to_target, WithinPairs* to_source,
                             InverseSqrt how = fastest_inverse_sqrt()) {
    Targets<1> tg;
    tg.x[0] = xt;
    tg.q[0] = qt;
    tg.d2[0] = d2t;
    tg.to_target[0] = &to_target;
    tg.to_source[0] = to_source;
    add_green_mutual<1>(x, y, z, q, d2, n, tg, w, g0, g1, g2, how);
    phi += tg.phi[0];
    for (int c = 0; c < 3; ++c) e[c] += tg.e[0][c];
}

// The exact kernel at m pairs within a support (a Green's pass's
// WithinPairs, in batches): pair(k, pot, g) for pair k, pot = phi_delta(r)
// and g = phi_delta'(r)/r at r = sqrt(r2[k]), delta that of source
// smoothed_by[k] (a global delta: the one).
template <int D, RadialKernel K, class Pair>
void within_kernel(const K& kernel, const SourceArrays<D>& s, const double* r2, const std::size_t* smoothed_by,
                   std::size_t m, Pair&& pair) {
    alignas(64) double r[block], pot[block], g[block];
    for (std::size_t k0 = 0; k0 < m; k0 += block) {
        const std::size_t n = std::min(block, m - k0);
        for (std::size_t k = 0; k < n; ++k)
            r[k] = s.global ? std::sqrt(r2[k0 + k]) : std::sqrt(r2[k0 + k]) / s.delta[smoothed_by[k0 + k]];
        batch<QuantityId::potential>(kernel, r, pot, n, s.smoothing);
        batch<QuantityId::dpotential_over_r>(kernel, r, g, n, s.smoothing);
        for (std::size_t k = 0; k < n; ++k) {
            if (s.global) {
                pair(k0 + k, pot[k], g[k]);
            } else {
                const std::size_t j = smoothed_by[k0 + k];
                pair(k0 + k, pot[k] * s.phi_scale[j] + s.phi_shift[j], g[k] * s.grad_scale[j]);
            }
        }
    }
}

}  // namespace detail
}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson

MOLLIFY_VECTOR_MISSES_ALLOWED_END
