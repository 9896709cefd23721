// The exact mollified sum over a contiguous range of sources at one target:
// sum_j q_j phi_delta_j(|x - x_j|) and its field, the inner loop of direct
// summation and of the treecode's near field. Sources are copied once into
// SourceArrays (the treecode reorders them); the loop runs in blocks: the
// radii of a block and the Green's function for all its pairs (vectorised),
// one batch call of the kernel per quantity (potential, phi'/r) for the
// pairs within a support, then the weighted sums (vectorised reductions).
//
// The treecode's near field uses two variants (add_green, add_within, at
// the end): the Green's function for the pairs beyond their support over
// sources gathered from several cells, and the exact kernel only for the
// pairs within a support.
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

#if defined(MOLLIFY_LANES)
// The Green's passes a register's worth of sources at a time (detail/lanes.hpp),
// over the blocks j0 = 0, N, ... of the first nv = n - n % N sources
// (N = register_doubles; returns nv, the rest left to the scalar loop):
// use(j0, dx, dy, dz, r2, inv), d = xt - x_j, r2 = |d|^2 as the scalar loop
// forms it, inv = 1/sqrt(r2), returns the target's {q/r, q/r^3} per lane,
// whose sums (q/r and q d/r^3) are added to p_sum and e0, e1, e2. Each
// block's square root and division are issued a block ahead of their use:
// out of order, the processor did not reach the next block's by itself
// (the rest of a block is ~40 instructions), and on AMD Zen 1 a block's
// square root and division hold the divider for ~25 cycles. There
// add_green_mutual went 6.6 -> 4.4 ns per pair (2400 sources, a test
// program) and the 3D treecode at N = 10^5, theta 0.7, p = 13 | 19 2.2 ->
// 1.7 | 3.2 -> 2.6 s; two blocks ahead was slower in the treecode (2.7 s at
// p = 19: four more live registers of AVX2's 16). A block's d is formed
// again for use (three loads and subtractions, on pipes the divider leaves
// idle) rather than carried from its r^2, for the same registers. How: the
// square root and division, or on Intel's AVX-512 cores 1/sqrt refined
// from its estimate (detail::inverse_sqrt_lanes, fastest_inverse_sqrt),
// which needs no look-ahead: a plain loop, d carried from r^2 to its use
// (three subtractions and loads fewer: 0.95-1.03 -> 0.77-0.92 ns per pair of the
// mutual pass, 244 targets against 6588 sources, alternating runs on the
// Intel Xeon of stop 60; the division's path unchanged, 1.34-1.42 ns).
template <mollify::detail::InverseSqrt How, class Use>
MOLLIFY_INLINE std::size_t green_blocks(const double* x, const double* y, const double* z, std::size_t n,
                                        const std::array<double, 3>& xt, double& p_sum, double& e0, double& e1,
                                        double& e2, Use&& use) {
    using namespace mollify::detail;
    constexpr std::size_t N = register_doubles;
    const std::size_t nv = n - n % N;
    const Lanes tx = Lanes{} + xt[0], ty = Lanes{} + xt[1], tz = Lanes{} + xt[2];
    auto d_at = [&](std::size_t j0) {
        return std::array<Lanes, 3>{tx - load_lanes(x + j0), ty - load_lanes(y + j0), tz - load_lanes(z + j0)};
    };
    auto r2_of = [](const std::array<Lanes, 3>& d) {
        return mul_add_lanes(d[2], d[2], mul_add_lanes(d[1], d[1], d[0] * d[0]));
    };
    Lanes vp{}, v0{}, v1{}, v2{};
    auto add = [&](std::size_t j0, const std::array<Lanes, 3>& d, Lanes r2, Lanes inv) {
        const auto [w, g] = use(j0, d[0], d[1], d[2], r2, inv);
        vp += w;
        v0 += g * d[0];
        v1 += g * d[1];
        v2 += g * d[2];
    };
    if constexpr (How == InverseSqrt::refine) {  // no divider to wait for: d carried, not formed again
        for (std::size_t j0 = 0; j0 < nv; j0 += N) {
            const std::array<Lanes, 3> d = d_at(j0);
            const Lanes r2 = r2_of(d);
            add(j0, d, r2, inverse_sqrt_lanes<How>(r2));
        }
    } else {
        Lanes r2_a{}, inv_a{};  // the next block's
        if (nv > 0) {
            r2_a = r2_of(d_at(0));
            inv_a = inverse_sqrt_lanes<How>(r2_a);
        }
        for (std::size_t j0 = 0; j0 < nv; j0 += N) {
            const Lanes r2 = r2_a, inv = inv_a;
            if (j0 + N < nv) {
                r2_a = r2_of(d_at(j0 + N));
                inv_a = inverse_sqrt_lanes<How>(r2_a);
            }
            add(j0, d_at(j0), r2, inv);
        }
    }
    p_sum += sum_lanes(vp);
    e0 += sum_lanes(v0);
    e1 += sum_lanes(v1);
    e2 += sum_lanes(v2);
    return nv;
}
#endif

// The treecode's near field in two parts, which together are add_exact
// over the same sources (each pair in exactly one part: r^2 >= delta_j^2
// in the first, r^2 < delta_j^2 in the second).
//
// add_green: the pairs beyond their support, where phi_delta IS the
// Green's function (3D), over n sources gathered into plain arrays
// (coordinates x, y, z, charges q, squared smoothing lengths d2): one
// vectorised pass, 1/r from one square root and one division (or refined
// from VRSQRT14PD's estimate: `how`, green_blocks), no kernel.
MOLLIFY_NOINLINE void add_green(const double* x, const double* y, const double* z, const double* q, const double* d2,
                      std::size_t n, const std::array<double, 3>& xt, double& phi, std::array<double, 3>& e,
                      [[maybe_unused]] InverseSqrt how = fastest_inverse_sqrt()) {
    constexpr double k = 0.25 * std::numbers::inv_pi;
    double p_sum = 0, e0 = 0, e1 = 0, e2 = 0;
    std::size_t j = 0;
#if defined(MOLLIFY_LANES)
    using mollify::detail::Lanes;
    auto use = [&](std::size_t j0, Lanes, Lanes, Lanes, Lanes r2, Lanes inv) {
        using namespace mollify::detail;
        const Lanes to_t = keep_lanes(r2 >= load_lanes(d2 + j0), inv);  // 1/r, or 0 within the support
        const Lanes w = load_lanes(q + j0) * to_t;                       // q/r
        return std::array<Lanes, 2>{w, w * to_t * to_t};                 // q/r, q/r^3
    };
    j = how == InverseSqrt::refine ? green_blocks<InverseSqrt::refine>(x, y, z, n, xt, p_sum, e0, e1, e2, use)
                                   : green_blocks<InverseSqrt::divide>(x, y, z, n, xt, p_sum, e0, e1, e2, use);
#else
    MOLLIFY_SIMD_REDUCTION(p_sum, e0, e1, e2)
#endif
    for (; j < n; ++j) {
        const double dx = xt[0] - x[j], dy = xt[1] - y[j], dz = xt[2] - z[j];
        const double r2 = mollify::detail::mul_add(dz, dz, mollify::detail::mul_add(dy, dy, dx * dx));
        const double inv = r2 >= d2[j] ? 1 / std::sqrt(r2) : 0.0;  // 1/r, or 0 within the support
        const double w = q[j] * inv, g = w * inv * inv;               // q/r, q/r^3
        p_sum += w;
        e0 += g * dx;
        e1 += g * dy;
        e2 += g * dz;
    }
    // phi = -k q/r, E = -grad phi = -k q (x - x_j)/r^3.
    phi -= k * p_sum;
    e[0] -= k * e0;
    e[1] -= k * e1;
    e[2] -= k * e2;
}

// add_green for a target that is itself a source (charge qt, squared
// smoothing length d2t) and n sources that feel it back: each pair's 1/r
// serves both directions (Newton's third law; masks r^2 >= d2[j] for the
// target, r^2 >= d2t for the source). The sources' sums of q/r and
// q (x_j - x_t)/r^3 are added to w[j], g0[j], g1[j], g2[j] (to be scaled by
// -1/(4 pi) like the target's).
//
// Both kept out of line: inlined into the treecode's descend, GCC left
// the loop scalar (3x the time).
MOLLIFY_NOINLINE void add_green_mutual(const double* x, const double* y, const double* z, const double* q, const double* d2,
                             std::size_t n, const std::array<double, 3>& xt, double qt, double d2t, double& phi,
                             std::array<double, 3>& e, double* w, double* g0, double* g1, double* g2,
                             [[maybe_unused]] InverseSqrt how = fastest_inverse_sqrt()) {
    constexpr double k = 0.25 * std::numbers::inv_pi;
    double p_sum = 0, e0 = 0, e1 = 0, e2 = 0;
    std::size_t j = 0;
#if defined(MOLLIFY_LANES)
    using mollify::detail::Lanes;
    const Lanes vq = Lanes{} + qt, vd2 = Lanes{} + d2t;
    auto use = [&](std::size_t j0, Lanes dx, Lanes dy, Lanes dz, Lanes r2, Lanes inv) {
        using namespace mollify::detail;
        const Lanes to_t = keep_lanes(r2 >= load_lanes(d2 + j0), inv), to_j = keep_lanes(r2 >= vd2, inv);
        const Lanes wt = load_lanes(q + j0) * to_t;
        const Lanes wj = vq * to_j, gj = wj * to_j * to_j;
        const Lanes gt = wt * to_t * to_t;
        store_lanes(w + j0, load_lanes(w + j0) + wj);
        store_lanes(g0 + j0, load_lanes(g0 + j0) - gj * dx);
        store_lanes(g1 + j0, load_lanes(g1 + j0) - gj * dy);
        store_lanes(g2 + j0, load_lanes(g2 + j0) - gj * dz);
        return std::array<Lanes, 2>{wt, gt};
    };
    j = how == InverseSqrt::refine ? green_blocks<InverseSqrt::refine>(x, y, z, n, xt, p_sum, e0, e1, e2, use)
                                   : green_blocks<InverseSqrt::divide>(x, y, z, n, xt, p_sum, e0, e1, e2, use);
#else
    MOLLIFY_SIMD_REDUCTION(p_sum, e0, e1, e2)
#endif
    for (; j < n; ++j) {
        const double dx = xt[0] - x[j], dy = xt[1] - y[j], dz = xt[2] - z[j];
        const double r2 = mollify::detail::mul_add(dz, dz, mollify::detail::mul_add(dy, dy, dx * dx));
        const double inv = 1 / std::sqrt(r2);
        const double to_t = r2 >= d2[j] ? inv : 0.0, to_j = r2 >= d2t ? inv : 0.0;
        const double wt = q[j] * to_t, gt = wt * to_t * to_t;
        const double wj = qt * to_j, gj = wj * to_j * to_j;
        p_sum += wt;
        e0 += gt * dx;
        e1 += gt * dy;
        e2 += gt * dz;
        w[j] += wj;
        g0[j] -= gj * dx;
        g1[j] -= gj * dy;
        g2[j] -= gj * dz;
    }
    phi -= k * p_sum;
    e[0] -= k * e0;
    e[1] -= k * e1;
    e[2] -= k * e2;
}

// The sources b0 + j, j < n, within their support at xt (r^2 < delta_j^2,
// r^2 exactly as add_green forms it: the two tests must split the pairs):
// their j in near[0, m) and r^2 in near_r2[0, m), in order; returns m.
// With AVX-512 eight at a time, the lanes within compressed into place
// (VCOMPRESSPD): the scalar loop's compaction, a compare, a flag and a store
// per source, was ~40 % of the treecode's within-support search, which
// reads every source of a cell for its ~16 pairs (an Intel Xeon, N = 10^6).
template <int D>
MOLLIFY_INLINE std::size_t near_sources(const SourceArrays<D>& s, const std::array<double, D>& xt, std::size_t b0,
                                        std::size_t n, unsigned* near, double* near_r2) {
    const double* delta = s.delta.data() + b0;
    const double *x = s.x[0].data() + b0, *y = s.x[1].data() + b0, *z = s.x[D - 1].data() + b0;
    auto r2_of = [&](std::size_t j) {
        const double dx = xt[0] - x[j], dy = xt[1] - y[j];
        const double r2 = mollify::detail::mul_add(dy, dy, dx * dx);
        if constexpr (D == 3) {
            const double dz = xt[2] - z[j];
            return mollify::detail::mul_add(dz, dz, r2);
        }
        return r2;
    };
    std::size_t m = 0, j = 0;
#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(MOLLIFY_LANES)
    using namespace mollify::detail;
    static_assert(register_doubles == 8);
    const Lanes tx = Lanes{} + xt[0], ty = Lanes{} + xt[1];
    const __m256i step = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    for (; j + 8 <= n; j += 8) {
        const Lanes dx = tx - load_lanes(x + j), dy = ty - load_lanes(y + j);
        Lanes r2 = mul_add_lanes(dy, dy, dx * dx);
        if constexpr (D == 3) {
            const Lanes dz = (Lanes{} + xt[2]) - load_lanes(z + j);
            r2 = mul_add_lanes(dz, dz, r2);
        }
        const Lanes d = load_lanes(delta + j);
        const __mmask8 within = _mm512_cmp_pd_mask(r2, d * d, _CMP_LT_OQ);
        _mm512_mask_compressstoreu_pd(near_r2 + m, within, r2);
        _mm256_mask_compressstoreu_epi32(near + m, within, _mm256_add_epi32(step, _mm256_set1_epi32(static_cast<int>(j))));
        m += static_cast<std::size_t>(std::popcount(static_cast<unsigned>(within)));
    }
#endif
    for (; j < n; ++j) {  // branch-free compaction
        const double r2 = r2_of(j);
        near[m] = static_cast<unsigned>(j);
        near_r2[m] = r2;
        m += r2 < delta[j] * delta[j] ? 1 : 0;
    }
    return m;
}

// The pairs of sources [begin, end) within their support (r^2 < delta_j^2)
// at the target xt, with the exact mollified kernel: pair(j, pot, g) for
// each, pot = phi_delta_j(r) and g = phi_delta_j'(r)/r (add_within,
// add_within_mutual).
template <int D, RadialKernel K, class Pair>
void within_pairs(const K& kernel, const SourceArrays<D>& s, const std::array<double, D>& xt, std::size_t begin,
                  std::size_t end, Pair&& pair) {
    alignas(64) double near_r2[block], near_r[block], near_pot[block], near_g[block];
    unsigned near[block + 1];
    for (std::size_t b0 = begin; b0 < end; b0 += block) {
        const std::size_t n = std::min(block, end - b0);
        const double* delta = s.delta.data() + b0;
        const std::size_t m = near_sources<D>(s, xt, b0, n, near, near_r2);
        if (m == 0) continue;
        for (std::size_t i = 0; i < m; ++i)
            near_r[i] = s.global ? std::sqrt(near_r2[i]) : std::sqrt(near_r2[i]) / delta[near[i]];
        batch<QuantityId::potential>(kernel, near_r, near_pot, m, s.smoothing);
        batch<QuantityId::dpotential_over_r>(kernel, near_r, near_g, m, s.smoothing);
        for (std::size_t i = 0; i < m; ++i) {
            const std::size_t j = b0 + near[i];
            double pot = near_pot[i], g = near_g[i];
            if (!s.global) {
                pot = pot * s.phi_scale[j] + s.phi_shift[j];
                g *= s.grad_scale[j];
            }
            pair(j, pot, g);
        }
    }
}

// add_within: the pairs of sources [begin, end) within their support, with
// the exact mollified kernel (as add_exact).
template <int D, RadialKernel K>
void add_within(const K& kernel, const SourceArrays<D>& s, const std::array<double, D>& xt, std::size_t begin,
                std::size_t end, double& phi, std::array<double, D>& e) {
    within_pairs<D>(kernel, s, xt, begin, end, [&](std::size_t j, double pot, double g) {
        phi += s.q[j] * pot;
        for (int k = 0; k < D; ++k) e[k] -= s.q[j] * g * (xt[k] - s.x[k][j]);
    });
}

// add_within for a target that is itself source t of a global delta, where
// phi_delta(r) is the same from either end: each pair's kernel values serve
// both directions (Newton's third law), source j's share added to
// phi_j[j - offset] and e_j[k][j - offset].
template <int D, RadialKernel K>
void add_within_mutual(const K& kernel, const SourceArrays<D>& s, std::size_t t, std::size_t begin, std::size_t end,
                       double& phi, std::array<double, D>& e, double* phi_j, const std::array<double*, D>& e_j,
                       std::size_t offset) {
    std::array<double, D> xt;
    for (int k = 0; k < D; ++k) xt[k] = s.x[k][t];
    const double qt = s.q[t];
    within_pairs<D>(kernel, s, xt, begin, end, [&](std::size_t j, double pot, double g) {
        phi += s.q[j] * pot;
        phi_j[j - offset] += qt * pot;
        for (int k = 0; k < D; ++k) {
            const double d = xt[k] - s.x[k][j];
            e[k] -= s.q[j] * g * d;
            e_j[k][j - offset] += qt * g * d;
        }
    });
}

}  // namespace detail
}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson
