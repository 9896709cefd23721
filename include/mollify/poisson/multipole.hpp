// Far-field (multipole) expansions of the Green's function about a cell
// centre c, of order p, for sources y_j with |y_j - c| <= rho < |x - c|.
// Beyond the support the mollified potential IS the Green's function
// (include/mollify/static_kernel.hpp), so these are expansions of the exact
// far field, not of an approximation of it.
//
// 3D: the Cartesian Taylor expansion in y about c,
//     1/|x - y| = sum_k a_k(x - c) (y - c)^k,   a_k = (1/k!) D_y^k 1/|x - y| at y = c,
// truncated at |k| <= p. Its degree-n terms are exactly the notes' Legendre
// terms rho^n P_n(cos gamma)/r^(n+1) (notes 001, "multipole expansion":
// P_n(cos theta) = (-1)^n/n! r^(n+1) d^n/dz^n (1/r)), so the truncation error is
// the notes' Legendre/spherical-harmonic one (|P_n| <= 1):
//     |error| <= sum_j |q_j| (rho/r)^(p+1) / (r - rho).
// Cartesian rather than spherical harmonics because one recurrence serves
// every p and the field: the a_k follow from
//     n |R|^2 a_k - (2n - 1) sum_i R_i a_(k-e_i) + (n - 1) sum_i a_(k-2e_i) = 0,  n = |k|
// (Lindsay & Krasny, J. Comput. Phys. 172 (2001), eq. (2.8)), and the field
// from the same a_k one order up, d a_k/dx_i = -(k_i + 1) a_(k+e_i); no
// Legendre functions, no complex arithmetic, no rotation of the moments.
// (C(p+3,3) moments against (p+1)^2: 84 against 49 at p = 6.)
//
// 2D: log|x - y| = Re log(z - w) with complex z, w, and
//     log(z - w) = log(z - c) - sum_(k>=1) ((w - c)/(z - c))^k / k,
// the 2D analogue (the notes' harmonic cos(n theta)/r^n terms); same bound
// with (rho/r)^(p+1)/(1 - rho/r) times |q|.
//
// Scaled for range: moments of (y - c)/rho, coefficients of the unit vector
// (x - c)/|x - c|, the powers (rho/r)^n applied last, so neither tiny nor
// huge coordinates overflow r^-(n+1).
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/lanes.hpp>
#include <mollify/detail/parallel.hpp>
#include <mollify/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstddef>
#include <numbers>
#include <string>
#include <vector>

namespace mollify::poisson {
inline namespace MOLLIFY_ISA {

inline constexpr int max_order = 20;

inline void check_order(int p) {
    if (p < 0 || p > max_order)
        fail("multipole order p = " + std::to_string(p) + " is outside 0.." + std::to_string(max_order));
}

template <int D>
class Multipole;

// 3D Cartesian Taylor expansion of order p.
template <>
class Multipole<3> {
public:
    explicit Multipole(int p) : p_(p) {
        check_order(p);
        // Multi-indices by degree up to p + 1 (the field needs one more).
        for (int n = 0; n <= p + 1; ++n) {
            start_.push_back(static_cast<int>(k_.size()));
            for (int a = n; a >= 0; --a)
                for (int b = n - a; b >= 0; --b) k_.push_back({a, b, n - a - b});
        }
        start_.push_back(static_cast<int>(k_.size()));
        const int total = static_cast<int>(k_.size());
        zero_ = total;  // a slot that holds 0: missing predecessors read it
        for (int i = 0; i < total; ++i) {
            const auto& k = k_[static_cast<std::size_t>(i)];
            Step s{};
            const int n = k[0] + k[1] + k[2];
            s.c1 = n > 0 ? (2.0 * n - 1) / n : 0;
            s.c2 = n > 0 ? (n - 1.0) / n : 0;
            for (int c = 0; c < 3; ++c) {
                auto m = k;
                m[c] -= 1;
                s.minus1[c] = m[c] >= 0 ? index(m) : zero_;
                m[c] -= 1;
                s.minus2[c] = m[c] >= 0 ? index(m) : zero_;
                if (n <= p) {
                    auto u = k;
                    u[c] += 1;
                    s.plus1[c] = index(u);
                }
            }
            steps_.push_back(s);
            degree_.push_back(n);
        }
        for (int a = 0; a <= max_order; ++a) {
            binom_[static_cast<std::size_t>(a)][0] = 1;
            for (int b = 1; b <= a; ++b)
                binom_[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] =
                    binom_[static_cast<std::size_t>(a) - 1][static_cast<std::size_t>(b) - 1] +
                    (b < a ? binom_[static_cast<std::size_t>(a) - 1][static_cast<std::size_t>(b)] : 0.0);
        }
        for (const auto& k : k_) {
            double f = 1;
            for (int c = 0; c < 3; ++c)
                for (int t = 2; t <= k[c]; ++t) f *= t;
            factorial_.push_back(f);
        }
        // Monomials by one multiplication each: u^k = u^(k - e_c) u_c, c the
        // first nonzero component of k.
        parent_.assign(size(), {0, 0});
        for (std::size_t i = 1; i < size(); ++i) {
            auto k = k_[i];
            const int c = k[0] > 0 ? 0 : k[1] > 0 ? 1 : 2;
            --k[static_cast<std::size_t>(c)];
            parent_[i] = {index(k), c};
        }
        harmonic_tables();
    }

    int order() const { return p_; }
    std::size_t size() const { return static_cast<std::size_t>(start_[static_cast<std::size_t>(p_) + 1]); }

    // Adds sum_j q_j ((y_j - c)/rho)^k for |k| <= p to m (size()), n sources
    // (coordinates y[0..2][j], charges q[j]) as SIMD lanes: each monomial q t^k is its parent's
    // (multi-index k - e_c) times t_c, lane sums accumulated per
    // coefficient and added to m once.
    void add_sources(double* m, const std::array<const double*, 3>& y, const double* q, std::size_t n,
                     const std::array<double, 3>& c, double rho, std::vector<double>& work) const {
        constexpr int W = lanes;
        const std::size_t s = size();
        // The monomials of one degree from the previous degree's (graded
        // order: a parent is of degree |k| - 1), two buffers of a degree's
        // (p + 1)(p + 2)/2 that stay in L1, beside the lane sums acc.
        work.assign(s * W + 2 * widest() * W + W, 0.0);
        double* acc = aligned(work.data());
        double* prev = acc + s * W;
        double* cur = prev + widest() * W;
        for (std::size_t j0 = 0; j0 < n; j0 += W) {
            const std::size_t count = std::min<std::size_t>(W, n - j0);
            alignas(64) double t[3][W];
            for (int l = 0; l < W; ++l) {
                const bool on = static_cast<std::size_t>(l) < count;
                for (int d = 0; d < 3; ++d) t[d][l] = on ? (y[d][j0 + static_cast<std::size_t>(l)] - c[d]) / rho : 0.0;
                prev[l] = on ? q[j0 + static_cast<std::size_t>(l)] : 0.0;
                acc[l] += prev[l];
            }
            for (int deg = 1; deg <= p_; ++deg) {
                const DegreeRows rows = rows_of(deg);
                const std::size_t first = rows.first, last = rows.last, below = rows.below;
                for (std::size_t i = first; i < last; ++i) {
                    const double* from = prev + (static_cast<std::size_t>(parent_[i].index) - below) * W;
                    const double* tc = t[parent_[i].c];
                    double* to = cur + (i - first) * W;
                    double* a = acc + i * W;
                    MOLLIFY_SIMD
                    for (int l = 0; l < W; ++l) {
                        to[l] = from[l] * tc[l];
                        a[l] += to[l];
                    }
                }
                std::swap(prev, cur);
            }
        }
        for (std::size_t i = 0; i < s; ++i) {
            double sum = 0;
            for (int l = 0; l < W; ++l) sum += acc[i * W + static_cast<std::size_t>(l)];
            m[i] += sum;
        }
    }

    // Adds the expansion's G = -1/(4 pi r) potential and field E = -grad at
    // x, R = x - c, |R| > rho; `work` holds the a_k (size() of order p + 1, + 1).
    void add_far(const double* m, double rho, int order, const std::array<double, 3>& R, double& phi,
                 std::array<double, 3>& e, std::vector<double>& work) const {
        const double r2 = R[0] * R[0] + R[1] * R[1] + R[2] * R[2];
        const double r = std::sqrt(r2), inv_r = 1 / r;
        const std::array<double, 3> u{R[0] * inv_r, R[1] * inv_r, R[2] * inv_r};
        const int top = order + 1;
        const auto last = static_cast<std::size_t>(start_[static_cast<std::size_t>(top) + 1]);
        work.resize(k_.size() + 1);
        double* a = work.data();
        recurrence(u, a, last);
        const double t = rho * inv_r;
        double tn = 1, p_sum = 0;
        std::array<double, 3> g{};
        for (int n = 0; n <= order; ++n) {
            double pn = 0, g0 = 0, g1 = 0, g2 = 0;
            for (int i = start_[static_cast<std::size_t>(n)]; i < start_[static_cast<std::size_t>(n) + 1]; ++i) {
                const auto& k = k_[static_cast<std::size_t>(i)];
                const Step& s = steps_[static_cast<std::size_t>(i)];
                pn += m[i] * a[i];
                g0 += m[i] * (k[0] + 1) * a[s.plus1[0]];
                g1 += m[i] * (k[1] + 1) * a[s.plus1[1]];
                g2 += m[i] * (k[2] + 1) * a[s.plus1[2]];
            }
            p_sum += tn * pn;
            g[0] += tn * g0;
            g[1] += tn * g1;
            g[2] += tn * g2;
            tn *= t;
        }
        constexpr double k4pi = 0.25 * std::numbers::inv_pi;
        // phi = -(1/4 pi) sum_k M_k a_k; E_i = -(1/4 pi) sum_k M_k (k_i + 1) a_(k+e_i).
        phi -= k4pi * p_sum * inv_r;
        const double f = k4pi * inv_r * inv_r;
        for (int c = 0; c < 3; ++c) e[c] -= f * g[c];
    }

    // Cluster-cluster: the far field of a source cell (moments m, centre
    // c_s, radius rho_s) as a local Taylor expansion about a target cell's
    // centre c_t (radius rho_t), R = c_t - c_s. With F = 1/|x - y|,
    // x = c_t + v, y = c_s + w: F = sum T_n(R) (v - w)^n, T_n = D^n F(R)/n!
    // = (-1)^|n| a_n(R), so
    //     phi(c_t + v) = -(1/4 pi) sum_(|m|<=p) L_m v^m,
    //     L_m = (-1)^|m| sum_(|k|<=p) binom(k + m, k) M_k a_(k+m)(R):
    // the local expansion of degree p of the whole degree-p multipole
    // expansion (derivatives up to degree 2p), as in Greengard & Rokhlin's
    // FMM. Its error is the two expansions' own truncations,
    // ~(rho_s/(|R| - rho_t))^(p+1) + (rho_t/(|R| - rho_s))^(p+1), where the
    // triangle |k| + |m| <= p (Dehnen's Cartesian M2L, (p + 1)^4/6
    // multiply-adds instead of (p + 1)^4) has ((rho_s + rho_t)/|R|)^(p+1):
    // at the opening angle theta = 0.5 with rho_s = rho_t that is 1/3 against
    // 1/2 per order. Measured (treecode_bench's neutral set, N = 10^5, one
    // thread, 2026-11-29): 1e-5 of the field in 0.45-0.5 s against 1.0-1.3 s
    // with the triangle (theta 0.5, p = 13, the best it had); the full
    // translation costs more per pair but pays at wider opening angles
    // (fewer pairs, larger leaves, smaller p).
    //
    // Harmonic reduction. With x_k = M_k/k! and the derivatives
    // T_j = j! a_j = (-1)^|j| D^j (1/|R|) (unit R; the powers of |R| apply
    // per degree), L_m = ((-1)^|m|/m!) sum_k x_k T_(k+m). 1/|R| is harmonic,
    // so T_(j+2e_z) = -T_(j+2e_x) - T_(j+2e_y) for every j (exactly; the
    // trace of a derivative tensor of 1/r vanishes). Hence
    //  (1) the sum over k needs only k_z <= 1: a moment x_k with k_z >= 2
    //      is folded into x_(k-2e_z+2e_x) and x_(k-2e_z+2e_y) with a minus
    //      sign (same degree, so every truncation |k| <= d is kept),
    //      once per source cell (reduce);
    //  (2) the outputs need only m_z <= 1: W_m = sum_k x_k T_(k+m) obeys
    //      W_m = -W_(m-2e_z+2e_x) - W_(m-2e_z+2e_y) for m_z >= 2 (same k
    //      range), and so does any sum of them over source cells, so a
    //      target cell accumulates the reduced W and rebuilds the rest once
    //      (add_expanded);
    //  (3) only T_j with j_z <= 2 are read, and their recurrence (below)
    //      never leaves that set.
    // 2n + 1 of the (n + 1)(n + 2)/2 coefficients of degree n are kept: at
    // degree 10 a translation costs (p + 1)^4 = 14641 multiply-adds instead
    // of C(p + 3, 3)^2 = 81796.

    // (p + 1)^2: the coefficients with k_z <= 1 (2n + 1 of degree n).
    std::size_t reduced_size() const { return count_reduced(p_); }

    // The reduced moments of a cell: x_k = M_k/k! (full moments m, those of
    // degree above order_s taken as 0), folded onto k_z <= 1; work: scratch.
    void reduce(const double* m, int order_s, double* out, std::vector<double>& work) const {
        const std::size_t n = size();
        work.resize(n);
        double* x = work.data();
        for (std::size_t i = 0; i < n; ++i) x[i] = degree_[i] <= order_s ? m[i] / factorial_[i] : 0.0;
        for (const Fold& f : fold_) {  // k_z descending
            x[f.a] -= x[f.i];
            x[f.b] -= x[f.i];
        }
        for (std::size_t r = 0; r < reduced_size(); ++r) out[r] = x[reduced_full_[r]];
    }

    // Source cells translated together (one per SIMD lane) by add_local.
    static constexpr int lanes = 8;

    // One source cell of an M2L batch: reduced moments mr (reduce), scale
    // rho_s, R = c_t - c_s.
    struct Source {
        const double* mr;
        double rho_s;
        std::array<double, 3> R;
    };

    // Adds the reduced local coefficients W_m (-1)^|m| (rho_t/|R|)^|m| / |R|
    // (m_z <= 1, |m| <= degree, |k| <= degree) of up to `lanes` source
    // cells to one target cell's per-lane sums lr (reduced_size() rows of
    // `lanes`, lane l of row m at m lanes + l, aligned with `aligned`);
    // add_expanded adds the lanes and turns the accumulated sum into
    // L_m rho_t^|m|. degree <= p: a pair far enough
    // apart reaches the accuracy of the worst accepted pair at a lower degree
    // (pair_degree); a batch uses the largest degree of its pairs. The cells
    // are SIMD lanes: derivatives, scaled moments and partial sums are stored
    // lane-innermost, so every step is a vector operation on contiguous
    // memory (no gathers) and the lanes' sums are independent chains.
    void add_local(const Source* src, int count, double rho_t, double* lr, std::vector<double>& work,
                   int degree = -1) const {
        constexpr int W = lanes;
        if (degree < 0 || degree > p_) degree = p_;
        const std::size_t nt = static_cast<std::size_t>(t_start_[2 * static_cast<std::size_t>(degree) + 1]);
        const std::size_t nr = count_reduced(degree);
        const std::size_t du = static_cast<std::size_t>(degree) + 1;
        work.resize((t_rows() + reduced_size() + 2 * du) * W + W);
        double* t = aligned(work.data());     // T_j, lane l at t[dense(j) W + l]
        double* x = t + t_rows() * W;         // x_k (rho_s/|R|)^|k|, in runs (run_position_)
        double* ts = x + reduced_size() * W;  // (rho_s/|R|)^d
        double* tt = ts + du * W;             // (-rho_t/|R|)^d / |R|
        alignas(64) double u[3][W], inv_r[W], rs[W];
        for (int l = 0; l < W; ++l) {
            // Empty lanes: a unit vector and no moments.
            const bool on = l < count;
            const std::array<double, 3> R = on ? src[l].R : std::array<double, 3>{1.0, 0.0, 0.0};
            const double r = std::sqrt(R[0] * R[0] + R[1] * R[1] + R[2] * R[2]);
            inv_r[l] = 1 / r;
            for (int c = 0; c < 3; ++c) u[c][l] = R[c] * inv_r[l];
            rs[l] = on ? src[l].rho_s : 0.0;
        }
        for (int l = 0; l < W; ++l) {
            ts[l] = 1;
            tt[l] = l < count ? inv_r[l] : 0.0;
        }
        for (std::size_t d = 1; d < du; ++d)
            for (int l = 0; l < W; ++l) {
                ts[d * W + static_cast<std::size_t>(l)] = ts[(d - 1) * W + static_cast<std::size_t>(l)] * rs[l] * inv_r[l];
                tt[d * W + static_cast<std::size_t>(l)] = -tt[(d - 1) * W + static_cast<std::size_t>(l)] * rho_t * inv_r[l];
            }
        // T_j = j! a_j(u): a_j's recurrence times j! (derivatives).
        for (int l = 0; l < W; ++l) {
            t[static_cast<std::size_t>(t_zero_) * W + static_cast<std::size_t>(l)] = 0;
            t[l] = 1;
        }
        for (std::size_t i = 1; i < nt; ++i) {
            const TStep& st = t_steps_[i];
            double* ti = t + static_cast<std::size_t>(st.row) * W;
            const double *a0 = t + static_cast<std::size_t>(st.minus1[0]) * W,
                         *a1 = t + static_cast<std::size_t>(st.minus1[1]) * W,
                         *a2 = t + static_cast<std::size_t>(st.minus1[2]) * W,
                         *b0 = t + static_cast<std::size_t>(st.minus2[0]) * W,
                         *b1 = t + static_cast<std::size_t>(st.minus2[1]) * W,
                         *b2 = t + static_cast<std::size_t>(st.minus2[2]) * W;
            MOLLIFY_SIMD
            for (int l = 0; l < W; ++l)
                ti[l] = st.c1[0] * u[0][l] * a0[l] + st.c1[1] * u[1][l] * a1[l] + st.c1[2] * u[2][l] * a2[l] -
                        (st.c2[0] * b0[l] + st.c2[1] * b1[l] + st.c2[2] * b2[l]);
        }
        for (std::size_t k = 0; k < nr; ++k) {
            const double* tsk = ts + static_cast<std::size_t>(reduced_degree_[k]) * W;
            double* xk = x + static_cast<std::size_t>(run_position_[k]) * W;
            for (int l = 0; l < W; ++l) xk[l] = l < count ? src[l].mr[k] * tsk[l] : 0.0;
        }
        alignas(64) double acc[8 * W];
        for (const Tile& tile : m2l_tiles_) {
            if (tile.degree > degree) continue;
            const double* tm = t + static_cast<std::size_t>(tile.row) * W;
            const int width = degree - tile.degree < 4 ? 4 : 8;  // outputs left in the tile's row (tile_dot)
            if (width == 8)
                tile_dot<8>(x, tm, m2l_runs_.data(), m2l_runs_.size(), degree, acc);
            else
                tile_dot<4>(x, tm, m2l_runs_.data(), m2l_runs_.size(), degree, acc);
            for (int d = 0; d < width && tile.degree + d <= degree; ++d) {
                double* out = lr + static_cast<std::size_t>(tile.out[d]) * W;
                const double* f = tt + static_cast<std::size_t>(tile.degree + d) * W;
                MOLLIFY_SIMD
                for (int l = 0; l < W; ++l) out[l] += f[l] * acc[d * W + l];
            }
        }
    }

    // The first address at or after q on a multiple of the lanes' width
    // (rows of lanes then never straddle a cache line); callers leave W
    // doubles of room.
    static double* aligned(double* q) {
        constexpr std::uintptr_t a = lanes * sizeof(double);
        const auto v = reinterpret_cast<std::uintptr_t>(q);
        return q + ((a - v % a) % a) / sizeof(double);
    }

    // The M2L's inner loop for one tile of Width (8 or 4) outputs
    // m = m0 + d e_x (d < Width): acc_d = sum_k x_k T_(k + m), lane-wise,
    // over |k| <= degree. T is stored densely (dense(j) linear in j), so
    // T_(k + m0 + d e_x) is row dense(k) + d of t (t at m0's row), and
    // k + e_x reads the rows of k shifted by one: the k are taken in runs
    // along k_x (one run per k_y, k_z; x stored in that order,
    // run_position_), C at a time, so Width + C - 1 T rows feed C Width
    // multiply-adds (and GCC keeps the rows the next step shares in
    // registers), where one k at a time loaded a T row per multiply-add: on
    // AMD Zen 1 at p = 19 that loop took ~2.3 cycles per 256-bit
    // multiply-add (loads, L2), this one ~1.2 (2026-12-02, add_local 333 ->
    // 240 us per call of eight cells, the tiles of four below included).
    // A row's last tile is one of four where at most four outputs are left
    // (add_local): tiles of eight wasted 38 % of the multiply-adds at
    // p = 19 on outputs beyond the degree. GCC/Clang vector extension in
    // the machine's own width (detail::register_doubles), the lanes a
    // register's worth at a time: Width accumulators, C x and a T register
    // fit the 16 registers of AVX2 or SSE2 (eight lanes as one vector there
    // needed 20: GCC spilled them through general registers, the M2L 3.6x
    // slower on AMD Zen 1 at p = 19, bench/results/treecode_bench_zen1.md).
    // Plain loops otherwise.
    static_assert(lanes % mollify::detail::register_doubles == 0);

    // A run of reduced k along k_x: x rows x_row.., T rows t_row.. (k_x = 0
    // first), k_x <= degree - low (low = k_y + k_z).
    struct Run {
        int x_row, t_row, low;
    };

    template <int Width>
    static void tile_dot(const double* x, const double* t, const Run* runs, std::size_t count, int degree,
                         double* acc) {
        constexpr int W = lanes;
#if defined(MOLLIFY_LANES)
        constexpr int N = mollify::detail::register_doubles;
        constexpr int C = 16 / Width;  // k per step: 2 (eight outputs) or 4 (four)
        using V = mollify::detail::Lanes;
        using mollify::detail::load_lanes;
        for (int h = 0; h < W; h += N) {
            V s[Width] = {};  // fully unrolled: accumulator registers
            for (std::size_t r = 0; r < count; ++r) {
                const int len = degree - runs[r].low + 1;
                const double* xr = x + static_cast<std::size_t>(runs[r].x_row) * W + h;
                const double* tr = t + static_cast<std::size_t>(runs[r].t_row) * W + h;
                int a = 0;
                for (; a + C <= len; a += C) {
                    V xa[C];
#pragma GCC unroll 4
                    for (int i = 0; i < C; ++i) xa[i] = load_lanes(xr + (a + i) * W);
#pragma GCC unroll 11
                    for (int j = 0; j < C + Width - 1; ++j) {
                        const V b = load_lanes(tr + (a + j) * W);
#pragma GCC unroll 4
                        for (int i = 0; i < C; ++i)
                            if (j - i >= 0 && j - i < Width) s[j - i] += xa[i] * b;
                    }
                }
                for (; a < len; ++a) {
                    const V xa = load_lanes(xr + a * W);
#pragma GCC unroll 8
                    for (int d = 0; d < Width; ++d) s[d] += xa * load_lanes(tr + (a + d) * W);
                }
            }
#pragma GCC unroll 8
            for (int d = 0; d < Width; ++d) mollify::detail::store_lanes(acc + d * W + h, s[d]);
        }
#else
        for (int d = 0; d < Width; ++d)
            for (int l = 0; l < W; ++l) {
                double s0 = 0;
                for (std::size_t r = 0; r < count; ++r)
                    for (int a = 0; a <= degree - runs[r].low; ++a)
                        s0 += x[static_cast<std::size_t>(runs[r].x_row + a) * W + l] *
                              t[static_cast<std::size_t>(runs[r].t_row + a + d) * W + l];
                acc[d * W + l] = s0;
            }
#endif
    }

    // Adds the full local expansion L_m rho_t^|m| = W_m/m! of the reduced
    // accumulation lr (add_local, per lane) to local (size()): the W_m with m_z >= 2
    // from W_m = -W_(m-2e_z+2e_x) - W_(m-2e_z+2e_y), m_z ascending.
    void add_expanded(const double* lr, double* local, std::vector<double>& work) const {
        const std::size_t n = size();
        work.resize(n);
        double* w = work.data();
        for (std::size_t r = 0; r < reduced_size(); ++r) {
            double sum = 0;
            for (int l = 0; l < lanes; ++l) sum += lr[r * lanes + static_cast<std::size_t>(l)];
            w[reduced_full_[r]] = sum;
        }
        for (auto f = fold_.rbegin(); f != fold_.rend(); ++f) w[f->i] = -(w[f->a] + w[f->b]);
        for (std::size_t i = 0; i < n; ++i) local[i] += w[i] / factorial_[i];
    }

    // The degree at which an accepted pair with convergence ratio c (the
    // larger of rho_s/d_s and rho_t/d_t, d_s the distance from the source
    // centre to the targets, d_t from the target centre to the sources;
    // rho_s/(|R| - rho_t) and rho_t/(|R| - rho_s) for spheres) has the
    // truncation factor c_max^(p+1) of the worst accepted pair, c_max =
    // theta/(2 - theta) (two spheres of radius theta |R|/2: Dehnen's
    // error-controlled order for the M2L's error above): (p + 1) log c_max /
    // log c - 1 rounded up; p where c >= c_max. Measured against the full
    // degree everywhere: ~2x the error in ~0.85x the time; with theta, the
    // most unbalanced sphere pair's ratio, as c_max the degrees fell too far
    // (100x the error).
    int pair_degree(double c, double theta) const {
        const double c_max = theta / (2 - theta);
        if (!(c > 0)) return 0;
        if (!(c < c_max)) return p_;
        const double d = std::ceil((p_ + 1) * std::log(c_max) / std::log(c)) - 1;
        return d < p_ ? static_cast<int>(std::max(d, 0.0)) : p_;
    }

    // Adds a child cell's full moments (add_sources; centre cc, scale rho_c)
    // to its parent's (cp, rho_p): with t_p = s t_c + e, s = rho_c/rho_p,
    // e = (cc - cp)/rho_p, the parent's sum of q t_p^k is the child's of
    // q (s t_c + e)^k, exactly (degree |k| needs only the child's moments
    // of degree <= |k|): the moments scaled by s^|m|, then one axis at a time
    // (shift_moments).
    void add_child_moments(const double* child, double rho_c, const std::array<double, 3>& cc, double* parent,
                           double rho_p, const std::array<double, 3>& cp, std::vector<double>& work) const {
        const std::size_t n = size();
        work.resize(2 * n);
        double *a = work.data(), *b = a + n;
        const auto sn = powers(rho_c / rho_p);
        for (std::size_t i = 0; i < n; ++i) a[i] = sn[static_cast<std::size_t>(degree_[i])] * child[i];
        shift_moments(a, b, 0, (cc[0] - cp[0]) / rho_p);
        shift_moments(b, a, 1, (cc[1] - cp[1]) / rho_p);
        shift_moments(a, b, 2, (cc[2] - cp[2]) / rho_p);
        for (std::size_t i = 0; i < n; ++i) parent[i] += b[i];
    }

    // Moves a local expansion from a parent cell (centre cp, scale rho_p) to
    // a child (cc, rho_c): with u_p = s u_c + d, s = rho_c/rho_p,
    // d = (cc - cp)/rho_p, the polynomial sum_k L_k u_p^k re-expanded about
    // u_p = d one axis at a time (shift_local), then scaled by s^|m|.
    void add_shifted(const double* parent, double rho_p, const std::array<double, 3>& cp, double rho_c,
                     const std::array<double, 3>& cc, double* child, std::vector<double>& work) const {
        const std::size_t n = size();
        work.resize(2 * n);
        double *a = work.data(), *b = a + n;
        shift_local(parent, b, 0, (cc[0] - cp[0]) / rho_p);
        shift_local(b, a, 1, (cc[1] - cp[1]) / rho_p);
        shift_local(a, b, 2, (cc[2] - cp[2]) / rho_p);
        const auto sn = powers(rho_c / rho_p);
        for (std::size_t i = 0; i < n; ++i) child[i] += sn[static_cast<std::size_t>(degree_[i])] * b[i];
    }

    // phi and E = -grad phi at n points x (coordinates x[0..2][i]) from a
    // local expansion about c (radius rho), added to phi[i] and e[0..2][i]:
    // phi = -(1/4 pi) sum L_m u^m, u = (x - c)/rho,
    // E_c = (1/4 pi rho) sum_m L_m m_c u^(m - e_c) = (1/4 pi rho) sum_j (j_c + 1) L_(j+e_c) u^j.
    // The points are SIMD lanes, each monomial one multiplication (add_sources).
    void add_local_at(const double* local, double rho, const std::array<double, 3>& c,
                      const std::array<const double*, 3>& x, std::size_t n, double* phi,
                      const std::array<double*, 3>& e, std::vector<double>& work) const {
        constexpr int W = lanes;
        const std::size_t s = size(), sg = count(p_ - 1 < 0 ? 0 : p_ - 1), ng = p_ > 0 ? sg : 0;
        const std::size_t rows = std::max(s, 2 * widest());  // local_sums: a row per monomial, or two degrees'
        work.resize(rows * W + 3 * s + W);
        double* mono = aligned(work.data());
        double* lg = mono + rows * W;  // (j_c + 1) L_(j+e_c), c = 0, 1, 2
        for (std::size_t j = 0; j < ng; ++j)
            for (int d = 0; d < 3; ++d)
                lg[static_cast<std::size_t>(d) * s + j] =
                    (k_[j][static_cast<std::size_t>(d)] + 1) * local[steps_[j].plus1[static_cast<std::size_t>(d)]];
        constexpr double k4pi = 0.25 * std::numbers::inv_pi;
        for (std::size_t i0 = 0; i0 < n; i0 += W) {
            const std::size_t count = std::min<std::size_t>(W, n - i0);
            alignas(64) double t[3][W], f[W], g[3][W];
            for (int l = 0; l < W; ++l) {
                const bool on = static_cast<std::size_t>(l) < count;
                for (int d = 0; d < 3; ++d) {
                    t[d][l] = on ? (x[d][i0 + static_cast<std::size_t>(l)] - c[d]) / rho : 0.0;
                    g[d][l] = ng > 0 ? lg[static_cast<std::size_t>(d) * s] : 0.0;
                }
                mono[l] = 1;
                f[l] = local[0];
            }
            local_sums(local, lg, s, ng, t, mono, f, g);
            for (std::size_t l = 0; l < count; ++l) {
                phi[i0 + l] -= k4pi * f[l];
                for (int d = 0; d < 3; ++d) e[static_cast<std::size_t>(d)][i0 + l] += k4pi / rho * g[d][l];
            }
        }
    }

private:
    // The monomials of a degree: (p + 1)(p + 2)/2 at degree p.
    std::size_t widest() const { return static_cast<std::size_t>((p_ + 1) * (p_ + 2) / 2); }

    // The monomials of degree deg >= 1, [first, last), and the first of the
    // degree below (their parents' rows in the buffer of that degree).
    struct DegreeRows {
        std::size_t first, last, below;
    };
    DegreeRows rows_of(int deg) const {
        const auto at = [&](int d) { return static_cast<std::size_t>(start_[static_cast<std::size_t>(d)]); };
        return {at(deg), at(deg + 1), at(deg - 1)};
    }

    // The lane sums of add_local_at: f += L_i u^i, g_c += lg_c,i u^i
    // (i < ng = the monomials of degree < p), i >= 1; monomials from their
    // parents (mono row 0 set), with SIMD lanes degree by degree in two
    // buffers of a degree's rows (add_sources).
    void local_sums(const double* local, const double* lg, std::size_t s, std::size_t ng, const double (&t)[3][lanes],
                    double* mono, double (&f)[lanes], double (&g)[3][lanes]) const {
        constexpr int W = lanes;
#if defined(MOLLIFY_LANES)
        // The lanes a register's worth at a time (tile_dot).
        constexpr int N = mollify::detail::register_doubles;
        using V = mollify::detail::Lanes;
        using mollify::detail::load_lanes, mollify::detail::store_lanes;
        for (int h = 0; h < W; h += N) {
            V vf = load_lanes(f + h), v0 = load_lanes(g[0] + h), v1 = load_lanes(g[1] + h), v2 = load_lanes(g[2] + h);
            // mono_i = mono_parent t_c (the monomial one multiplication from its
            // parent's, of the degree below: prev), kept in cur
            double *prev = mono, *cur = mono + widest() * W;
            for (int deg = 1; deg <= p_; ++deg) {
                const DegreeRows rows = rows_of(deg);
                // named, not a structured binding: the lambda below captures them (clang 14 cannot)
                const std::size_t first = rows.first, last = rows.last, below = rows.below;
                auto monomial = [&](std::size_t i) {
                    const V a = load_lanes(prev + (static_cast<std::size_t>(parent_[i].index) - below) * W + h) *
                                load_lanes(t[parent_[i].c] + h);
                    store_lanes(cur + (i - first) * W + h, a);
                    return a;
                };
                if (last <= ng) {
                    for (std::size_t i = first; i < last; ++i) {
                        const V a = monomial(i);
                        vf += local[i] * a;
                        v0 += lg[i] * a;
                        v1 += lg[s + i] * a;
                        v2 += lg[2 * s + i] * a;
                    }
                } else {  // ng = count(p - 1), a degree's start: the degree p, no gradient terms
                    for (std::size_t i = first; i < last; ++i) vf += local[i] * monomial(i);
                }
                std::swap(prev, cur);
            }
            store_lanes(f + h, vf);
            store_lanes(g[0] + h, v0);
            store_lanes(g[1] + h, v1);
            store_lanes(g[2] + h, v2);
        }
#else
        for (std::size_t i = 1; i < s; ++i) {
            const double* from = mono + static_cast<std::size_t>(parent_[i].index) * W;
            for (int l = 0; l < W; ++l) {
                const double a = from[l] * t[parent_[i].c][l];
                mono[i * W + static_cast<std::size_t>(l)] = a;
                f[l] += local[i] * a;
                if (i < ng)
                    for (int d = 0; d < 3; ++d) g[d][l] += lg[static_cast<std::size_t>(d) * s + i] * a;
            }
        }
#endif
    }

    // a_k(u) for |u| = 1 and the first `last` multi-indices (a_k(R) = a_k(u)/|R|^(|k|+1)).
    void recurrence(const std::array<double, 3>& u, double* a, std::size_t last) const {
        a[zero_] = 0;
        a[0] = 1;
        for (std::size_t i = 1; i < last; ++i) {
            const Step& s = steps_[i];
            const double first = u[0] * a[s.minus1[0]] + u[1] * a[s.minus1[1]] + u[2] * a[s.minus1[2]];
            const double second = a[s.minus2[0]] + a[s.minus2[1]] + a[s.minus2[2]];
            a[i] = s.c1 * first - s.c2 * second;
        }
    }

    // The derivatives T_j = j! a_j(u), j_z <= 2 (t_steps_ order), follow
    // a_j's recurrence times j!:
    //     T_j = c1 sum_i j_i u_i T_(j-e_i) - c2 sum_i j_i (j_i - 1) T_(j-2e_i),
    // which reads only j_z, j_z - 1, j_z - 2 (the set is closed).
    // Tables of the harmonic reduction (see add_local).
    void harmonic_tables() {
        // Reduced multi-indices (k_z <= 1) by degree: k_z = 0 with k_x
        // descending, then k_z = 1 likewise; degree n starts at n^2.
        for (int n = 0; n <= p_; ++n) {
            for (int z = 0; z <= std::min(n, 1); ++z)
                for (int a = n - z; a >= 0; --a) {
                    reduced_full_.push_back(index({a, n - z - a, z}));
                    reduced_degree_.push_back(n);
                }
        }
        // Folding order: k_z descending (a folded moment lands on k_z - 2,
        // which is folded later).
        for (int z = p_; z >= 2; --z)
            for (int n = z; n <= p_; ++n)
                for (int a = n - z; a >= 0; --a)
                    fold_.push_back({index({a, n - z - a, z}), index({a + 2, n - z - a, z - 2}),
                                     index({a, n - z - a + 2, z - 2})});
        // Derivatives with j_z <= 2, by degree up to 2p (the M2L's |k| + |m|):
        // j_z = 0, 1, 2, each with j_x descending.
        std::vector<std::array<int, 3>> tk;
        for (int n = 0; n <= 2 * p_; ++n) {
            t_start_.push_back(static_cast<int>(tk.size()));
            for (int z = 0; z <= std::min(n, 2); ++z)
                for (int a = n - z; a >= 0; --a) tk.push_back({a, n - z - a, z});
        }
        t_start_.push_back(static_cast<int>(tk.size()));
        // Dense rows: dense(j) = (j_z X + j_y) X + j_x, X = 2p + 1, linear in
        // j (the M2L tiles' T_(k + m) are row sums); eight rows of room after
        // the last (a tile's unused outputs read there), then a zero row.
        const int X = 2 * p_ + 1;
        auto dense = [X](const std::array<int, 3>& j) { return (j[2] * X + j[1]) * X + j[0]; };
        t_zero_ = 3 * X * X + 8;
        for (const auto& j : tk) {
            const int n = j[0] + j[1] + j[2];
            TStep s{};
            s.row = dense(j);
            for (int c = 0; c < 3; ++c) {
                s.minus1[c] = s.minus2[c] = t_zero_;
                if (n == 0) continue;
                auto m = j;
                if (--m[c] >= 0) {
                    s.minus1[c] = dense(m);
                    s.c1[c] = (2.0 * n - 1) / n * j[c];
                }
                if (--m[c] >= 0) {
                    s.minus2[c] = dense(m);
                    s.c2[c] = (n - 1.0) / n * j[c] * (j[c] - 1);
                }
            }
            t_steps_.push_back(s);
        }
        // M2L: the reduced k in runs, and the outputs in tiles of eight
        // along m_x (m_z <= 1, |m| <= p; a tile's first four alone where
        // the degree leaves no more, add_local).
        auto reduced = [&](const std::array<int, 3>& m) {
            for (std::size_t r = 0; r < reduced_full_.size(); ++r)
                if (k_[static_cast<std::size_t>(reduced_full_[r])] == m) return static_cast<int>(r);
            return -1;
        };
        // Runs along k_x (tile_dot): k_z, then k_y, each run's k_x ascending.
        run_position_.resize(reduced_full_.size());
        int row = 0;
        for (int z = 0; z <= 1; ++z)
            for (int y = 0; y + z <= p_; ++y) {
                m2l_runs_.push_back({row, dense({0, y, z}), y + z});
                for (int a = 0; a + y + z <= p_; ++a)
                    run_position_[static_cast<std::size_t>(reduced({a, y, z}))] = row++;
            }
        for (int z = 0; z <= 1; ++z)
            for (int y = 0; y + z <= p_; ++y)
                for (int x0 = 0; x0 + y + z <= p_; x0 += 8) {
                    Tile tile{dense({x0, y, z}), x0 + y + z, {}};
                    for (int d = 0; d < 8; ++d) tile.out[static_cast<std::size_t>(d)] = reduced({x0 + d, y, z});
                    m2l_tiles_.push_back(tile);
                }
    }

    // Rows of the dense derivative array (add_local's work).
    std::size_t t_rows() const { return static_cast<std::size_t>(t_zero_) + 1; }

    // A change of centre along axis c by e, one factor of the binomial
    // theorem per axis ((s t + e)^k = prod_c (s t_c + e_c)^(k_c)): ~p/4
    // multiply-adds per coefficient, three passes per shift, where the
    // double sum over multi-indices costs O(p^6) per shift.
    // Moments (sums of t^k): out_k = sum_(j <= k_c) binom(k_c, j) e^j in_(k - j e_c).
    void shift_moments(const double* in, double* out, int c, double e) const {
        const auto pw = powers(e);
        const auto axis = static_cast<std::size_t>(c);
        for (std::size_t i = 0; i < size(); ++i) {
            const auto kc = static_cast<std::size_t>(k_[i][axis]);
            double sum = in[i];
            int at = static_cast<int>(i);
            for (std::size_t j = 1; j <= kc; ++j) {
                at = steps_[static_cast<std::size_t>(at)].minus1[axis];
                sum += binom_[kc][j] * pw[j] * in[at];
            }
            out[i] = sum;
        }
    }
    // Local coefficients (of u^k), u -> u + e along c:
    // out_k = sum_(j <= p - |k|) binom(k_c + j, j) e^j in_(k + j e_c).
    void shift_local(const double* in, double* out, int c, double e) const {
        const auto pw = powers(e);
        const auto axis = static_cast<std::size_t>(c);
        for (std::size_t i = 0; i < size(); ++i) {
            const auto kc = static_cast<std::size_t>(k_[i][axis]);
            const auto up = static_cast<std::size_t>(p_ - degree_[i]);
            double sum = in[i];
            int at = static_cast<int>(i);
            for (std::size_t j = 1; j <= up; ++j) {
                at = steps_[static_cast<std::size_t>(at)].plus1[axis];
                sum += binom_[kc + j][j] * pw[j] * in[at];
            }
            out[i] = sum;
        }
    }
    std::array<double, max_order + 1> powers(double x) const {
        std::array<double, max_order + 1> pw{};
        pw[0] = 1;
        for (std::size_t k = 1; k <= static_cast<std::size_t>(p_); ++k) pw[k] = pw[k - 1] * x;
        return pw;
    }

    // The number of multi-indices of degree <= d.
    std::size_t count(int d) const { return static_cast<std::size_t>(start_[static_cast<std::size_t>(d) + 1]); }

    struct Step {
        double c1, c2;
        std::array<int, 3> minus1, minus2, plus1;
    };
    int index(const std::array<int, 3>& k) const {
        const int n = k[0] + k[1] + k[2];
        // Within degree n the order is a descending, then b descending.
        const int a = k[0], b = k[1];
        int offset = 0;
        for (int aa = n; aa > a; --aa) offset += n - aa + 1;
        offset += (n - a) - b;
        return start_[static_cast<std::size_t>(n)] + offset;
    }

    int p_;
    int zero_ = 0;
    std::vector<std::array<int, 3>> k_;
    std::vector<int> start_;
    std::vector<Step> steps_;
    std::vector<int> degree_;
    std::vector<double> factorial_;  // k_0! k_1! k_2! of multi-index i
    std::array<std::array<double, max_order + 1>, max_order + 1> binom_{};  // binom_[a][b] = binom(a, b)
    struct Parent {
        int index, c;  // k - e_c, c
    };
    std::vector<Parent> parent_;
    // The harmonic reduction (add_local).
    static std::size_t count_reduced(int d) { return static_cast<std::size_t>(d + 1) * static_cast<std::size_t>(d + 1); }
    struct Fold {
        int i, a, b;  // k (k_z >= 2), k - 2e_z + 2e_x, k - 2e_z + 2e_y
    };
    struct TStep {
        double c1[3], c2[3];
        int minus1[3], minus2[3];  // dense rows of j - e_c, j - 2 e_c (or the zero row)
        int row;                   // dense(j)
    };
    std::vector<int> reduced_full_, reduced_degree_;
    std::vector<Fold> fold_;
    std::vector<int> t_start_;
    int t_zero_ = 0;
    std::vector<TStep> t_steps_;
    std::vector<Run> m2l_runs_;      // the reduced k in runs along k_x (tile_dot)
    std::vector<int> run_position_;  // each reduced k's row in x (add_local): its run's order
    struct Tile {
        int row, degree;           // dense(m0), |m0|
        std::array<int, 8> out;    // reduced index of m0 + d e_x (-1 beyond degree p)
    };
    std::vector<Tile> m2l_tiles_;
};

// 2D complex expansion of order p: moments M_k = sum q ((w - c)/rho)^k.
template <>
class Multipole<2> {
public:
    explicit Multipole(int p) : p_(p) { check_order(p); }
    int order() const { return p_; }
    std::size_t size() const { return 2 * (static_cast<std::size_t>(p_) + 1); }  // re, im pairs

    void add_source(double* m, const std::array<double, 2>& y, const std::array<double, 2>& c, double rho,
                    double q) const {
        const std::complex<double> t((y[0] - c[0]) / rho, (y[1] - c[1]) / rho);
        std::complex<double> tk(q, 0);
        for (int k = 0; k <= p_; ++k) {
            m[2 * k] += tk.real();
            m[2 * k + 1] += tk.imag();
            tk *= t;
        }
    }

    // G = log(r)/(2 pi): phi = (1/2 pi) Re[M_0 log w - sum_k M_k (rho/w)^k / k],
    // f'(z) = (1/w)[M_0 + sum_k M_k (rho/w)^k], grad Re f = (Re f', -Im f').
    void add_far(const double* m, double rho, int order, const std::array<double, 2>& R, double& phi,
                 std::array<double, 2>& e, std::vector<double>&) const {
        const std::complex<double> w(R[0], R[1]);
        const std::complex<double> u = rho / w;
        std::complex<double> uk = 1, series = 0, deriv(m[0], m[1]);
        for (int k = 1; k <= order; ++k) {
            uk *= u;
            const std::complex<double> term = std::complex<double>(m[2 * k], m[2 * k + 1]) * uk;
            series += term / static_cast<double>(k);
            deriv += term;
        }
        constexpr double inv_2pi = 0.5 * std::numbers::inv_pi;
        const double log_r = std::log(std::abs(w));
        // Re(M_0 log w) = Re M_0 log|w| - Im M_0 arg w; M_0 = sum q is real.
        phi += inv_2pi * (m[0] * log_r - series.real());
        const std::complex<double> fp = deriv / w;
        e[0] -= inv_2pi * fp.real();
        e[1] += inv_2pi * fp.imag();
    }

private:
    int p_;
};

}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson
