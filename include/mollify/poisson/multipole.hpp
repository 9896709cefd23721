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
// Cartesian for the moments, the local expansions, their shifts and the
// particle-cluster sums, because one recurrence serves every p and the
// field: the a_k follow from
//     n |R|^2 a_k - (2n - 1) sum_i R_i a_(k-e_i) + (n - 1) sum_i a_(k-2e_i) = 0,  n = |k|
// (Lindsay & Krasny, J. Comput. Phys. 172 (2001), eq. (2.8)), and the field
// from the same a_k one order up, d a_k/dx_i = -(k_i + 1) a_(k+e_i); each
// monomial of a source or target is one multiplication. Only the
// cluster-cluster translation (M2L, add_local), the step whose cost grows
// fastest in p, passes through real spherical harmonics, where rotating
// the pair's axis onto z makes it O(p^3) instead of O(p^4).
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
#include <memory>
#include <mutex>
#include <numbers>
#include <string>
#include <vector>

MOLLIFY_VECTOR_MISSES_ALLOWED_BEGIN  // its MOLLIFY_SIMD loops (detail/isa.hpp)

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
        for (int a = 0; a <= 2 * max_order; ++a) {  // to binom(2p, p): the M2L's translation
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
    // expansion, as in Greengard & Rokhlin's FMM. Its error is the two
    // expansions' own truncations, ~(rho_s/(|R| - rho_t))^(p+1) +
    // (rho_t/(|R| - rho_s))^(p+1), where the triangle |k| + |m| <= p
    // (Dehnen's Cartesian M2L) has ((rho_s + rho_t)/|R|)^(p+1): at the
    // opening angle theta = 0.5 with rho_s = rho_t that is 1/3 against 1/2
    // per order (measured, treecode_bench's neutral set, N = 10^5, one
    // thread, 2026-11-29: 1e-5 of the field in 0.45-0.5 s against 1.0-1.3 s
    // with the triangle).
    //
    // Harmonic reduction. With x_k = M_k/k! and T_j = j! a_j =
    // (-1)^|j| D^j (1/|R|), L_m = ((-1)^|m|/m!) W_m, W_m = sum_k x_k T_(k+m).
    // 1/|R| is harmonic, so T_(j+2e_z) = -T_(j+2e_x) - T_(j+2e_y): a moment
    // x_k with k_z >= 2 folds into x_(k-2e_z+2e_x) and x_(k-2e_z+2e_y) with
    // a minus sign (reduce), and the W_m with m_z >= 2 follow from those
    // with m_z <= 1 by the same rule (add_expanded): 2n + 1 coefficients of
    // degree n on either side, (p + 1)^2 in all.
    //
    // Spherical harmonics, rotated (the M2L of Greengard & Rokhlin's
    // "new version" of the FMM, 1997, and of Dehnen 2014, sect. 3.3, in real
    // harmonics): the 2n + 1 numbers of degree n are coordinates of a
    // harmonic polynomial, so they are held in the basis of real solid
    // harmonics S_n^(m,c/s) (sh_tables) instead: by Maxwell's rule
    // T_k(y) = (2n - 1)!! pi(y^k)/|y|^(2n+1) (pi the harmonic projection)
    // the far field of degree n is sum_i M_i S_i(y)/|y|^(2n+1) with
    // M_i = (2n - 1)!! <S_i, sum_k x_k y^k> (Fischer's product, in which the
    // S_i are orthonormal), and the local one sum_i L_i S_i(v). Rotating R
    // onto the z axis, R_y(-theta) R_z(-phi) = Q R_z(-theta) Q^T R_z(-phi)
    // (Q = R_x(-pi/2), fixed; Pinchon & Hoggan, J. Phys. A 40 (2007), its
    // y-z exchange), costs per degree two plane rotations of the (c, s)
    // pairs and two products with Q's fixed matrix, block-diagonal in four
    // parity classes ((2n + 1)^2/4 multiply-adds); along z the translation
    // keeps m: L_(j,m) = sum_n M_(n,m) (-1)^(j-m) binom(n + j, j - m)
    // (K_nm/K_jm) / d^(n+j+1), K_nm the coefficient of x^m z^(n-m) in
    // S_n^(m,c) (match the rho^m cos/sin(m phi) terms on the axis, where
    // S_n^m ~ K_nm rho^m z^(n-m)); then the rotations back. ~2 (p + 1)^3
    // multiply-adds a pair (~17,600 at p = 19: Q's four products 10,660,
    // the translation 5,340, the plane rotations ~1,600; the Cartesian M2L
    // this replaced, 2026-12-04, took (p + 1)^4 = 160,000): the same
    // truncation (n, j <= degree), so the same errors.

    // (p + 1)^2: the coefficients of degree <= p, 2n + 1 of degree n.
    std::size_t reduced_size() const { return count_reduced(p_); }

    // The multipole coefficients of a cell in the harmonics' basis:
    // x_k = M_k/k! (full moments m, those of degree above order_s taken as
    // 0), folded onto k_z <= 1, then per degree M_i = (2n - 1)!! sum_k
    // x_k k! S_i[k] (Harmonics::in); work: scratch.
    void reduce(const double* m, int order_s, double* out, std::vector<double>& work) const {
        const std::size_t n = size();
        work.resize(n);
        double* x = work.data();
        for (std::size_t i = 0; i < n; ++i) x[i] = degree_[i] <= order_s ? m[i] / factorial_[i] : 0.0;
        for (const Fold& f : fold_) {  // k_z descending
            x[f.a] -= x[f.i];
            x[f.b] -= x[f.i];
        }
        for (int d = 0; d <= p_; ++d) {
            const auto w = static_cast<std::size_t>(2 * d + 1), first = static_cast<std::size_t>(d * d);
            const double* a = sh_->in.data() + sh_at(d);
            for (std::size_t i = 0; i < w; ++i) {
                double sum = 0;
                for (std::size_t r = 0; r < w; ++r) sum += a[i * w + r] * x[reduced_full_[first + r]];
                out[first + i] = sum;
            }
        }
    }

    // Source cells translated together (one per SIMD lane) by add_local.
    static constexpr int lanes = 8;

    // One source cell of an M2L batch: coefficients mr (reduce), scale
    // rho_s, R = c_t - c_s.
    struct Source {
        const double* mr;
        double rho_s;
        std::array<double, 3> R;
    };

    // Adds the local coefficients L_i rho_t^j (harmonics' basis, degree
    // j <= degree, from the multipole's n <= degree) of up to `lanes`
    // source cells to one target cell's per-lane sums lr (reduced_size()
    // rows of `lanes`, lane l of row i at i lanes + l, aligned with
    // `aligned`); add_expanded adds the lanes and turns the sum into
    // L_m rho_t^|m|. degree <= p: a pair far enough apart reaches the
    // accuracy of the worst accepted pair at a lower degree (pair_degree); a
    // batch uses the largest degree of its pairs. The cells are SIMD lanes,
    // stored lane-innermost: every step is a vector operation on contiguous
    // rows, the rotations' angles differing per lane.
    void add_local(const Source* src, int count, double rho_t, double* lr, std::vector<double>& work,
                   int degree = -1) const {
        constexpr int W = lanes;
        if (degree < 0 || degree > p_) degree = p_;
        const auto du = static_cast<std::size_t>(degree) + 1;
        const std::size_t wide = 2 * du;  // room for a degree's 2n + 1 rows
        work.resize((reduced_size() + 2 * wide) * W + W);
        double* a = aligned(work.data());  // the multipole along z, by columns (Harmonics::column)
        double* u = a + reduced_size() * W;
        double* v = u + wide * W;
        Angles phi, theta;  // cos/sin(m phi), cos/sin(m theta), R = d (sin t cos f, sin t sin f, cos t)
        alignas(64) double ts[max_order + 1][W], tt[max_order + 1][W];
        for (int l = 0; l < W; ++l) {
            // Empty lanes: along z, no moments, no sum.
            const bool on = l < count;
            const std::array<double, 3> R = on ? src[l].R : std::array<double, 3>{0.0, 0.0, 1.0};
            // The angles from R over its largest component: R_x^2 + R_y^2
            // would underflow at |R| ~ 1e-150 (the azimuth of a pair 1e-12
            // off the axis then off by O(1), an error of ~1e-12 in all) and
            // |R|^2 overflow above 1e154.
            const double big = std::max({std::fabs(R[0]), std::fabs(R[1]), std::fabs(R[2])});
            const double x = R[0] / big, y = R[1] / big, z = R[2] / big;
            const double rxy = std::sqrt(x * x + y * y), rn = std::sqrt(rxy * rxy + z * z);
            const double inv_r = 1 / (rn * big);
            phi.c[1][l] = rxy > 0 ? x / rxy : 1.0;
            phi.s[1][l] = rxy > 0 ? y / rxy : 0.0;
            theta.c[1][l] = z / rn;
            theta.s[1][l] = rxy / rn;
            ts[0][l] = on ? 1.0 : 0.0;
            tt[0][l] = on ? inv_r : 0.0;
            const double fs = (on ? src[l].rho_s : 0.0) * inv_r, ft = rho_t * inv_r;
            for (std::size_t d = 1; d < du; ++d) {
                ts[d][l] = ts[d - 1][l] * fs;
                tt[d][l] = tt[d - 1][l] * ft;
            }
        }
        phi.fill(degree);
        theta.fill(degree);
        // Per degree in the blocks' order (Harmonics::place): to z, then into a by columns.
        for (int n = 0; n <= degree; ++n) {
            const auto first = static_cast<std::size_t>(n * n), w = static_cast<std::size_t>(2 * n + 1);
            for (std::size_t i = 0; i < w; ++i) {
                double* to = u + static_cast<std::size_t>(sh_->place[first + i]) * W;
                for (int l = 0; l < W; ++l) to[l] = l < count ? src[l].mr[first + i] * ts[n][l] : 0.0;
            }
            rotate_z(u, n, phi, -1);
            exchange(u, v, n, true);
            rotate_z(v, n, theta, -1);
            exchange(v, u, n, false);
            for (std::size_t i = 0; i < w; ++i) {
                const double* from = u + static_cast<std::size_t>(sh_->place[first + i]) * W;
                double* to = a + (sh_->column[i] + static_cast<std::size_t>(n) - (i + 1) / 2) * W;
                for (int l = 0; l < W; ++l) to[l] = from[l];
            }
        }
        for (int j = 0; j <= degree; ++j) {
            const auto first = static_cast<std::size_t>(j * j), w = static_cast<std::size_t>(2 * j + 1);
            translate_z(a, u, j, degree);
            exchange(u, v, j, true);
            rotate_z(v, j, theta, 1);
            exchange(v, u, j, false);
            rotate_z(u, j, phi, 1);
            double* out = lr + first * W;
            const double* f = tt[j];
            for (std::size_t i = 0; i < w; ++i) {
                const double* from = u + static_cast<std::size_t>(sh_->place[first + i]) * W;
                MOLLIFY_SIMD
                for (int l = 0; l < W; ++l) out[i * W + static_cast<std::size_t>(l)] += f[l] * from[l];
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

    // Adds the full local expansion L_m rho_t^|m| of the per-lane sums lr
    // (add_local) to local (size()): per degree the reduced
    // W_m (-rho_t)^|m| = m! sum_i S_i[m] (L_i rho_t^j) (Harmonics::out; F(R + v) =
    // sum_m ((-1)^|m|/m!) W_m v^m), the W_m with m_z >= 2 from
    // W_m = -W_(m-2e_z+2e_x) - W_(m-2e_z+2e_y), m_z ascending.
    void add_expanded(const double* lr, double* local, std::vector<double>& work) const {
        const std::size_t n = size();
        work.resize(n + reduced_size());
        double* w = work.data();
        double* sum = w + n;
        for (std::size_t r = 0; r < reduced_size(); ++r) {
            double s = 0;
            for (int l = 0; l < lanes; ++l) s += lr[r * lanes + static_cast<std::size_t>(l)];
            sum[r] = s;
        }
        for (int d = 0; d <= p_; ++d) {
            const auto width = static_cast<std::size_t>(2 * d + 1), first = static_cast<std::size_t>(d * d);
            const double* b = sh_->out.data() + sh_at(d);
            for (std::size_t r = 0; r < width; ++r) {
                double s = 0;
                for (std::size_t i = 0; i < width; ++i) s += b[r * width + i] * sum[first + i];
                w[reduced_full_[first + r]] = s;
            }
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
#if defined(MOLLIFY_LANES)
    // A register's worth of the lanes (detail/lanes.hpp): the loops written
    // lane-wise by hand (local_sums, matrix_rows, column_dot) take the
    // lanes N at a time.
    using V = mollify::detail::Lanes;
    static constexpr int N = mollify::detail::register_doubles;
    static V load(const double* p) { return mollify::detail::load_lanes(p); }
    static void store(double* p, V v) { mollify::detail::store_lanes(p, v); }
    static_assert(lanes % N == 0);
#endif

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
        // The lanes a register's worth at a time: four sums and a monomial in registers.
        for (int h = 0; h < W; h += N) {
            V vf = load(f + h), v0 = load(g[0] + h), v1 = load(g[1] + h), v2 = load(g[2] + h);
            // mono_i = mono_parent t_c (the monomial one multiplication from its
            // parent's, of the degree below: prev), kept in cur
            double *prev = mono, *cur = mono + widest() * W;
            for (int deg = 1; deg <= p_; ++deg) {
                const DegreeRows rows = rows_of(deg);
                // named, not a structured binding: the lambda below captures them (clang 14 cannot)
                const std::size_t first = rows.first, last = rows.last, below = rows.below;
                auto monomial = [&](std::size_t i) {
                    const V a = load(prev + (static_cast<std::size_t>(parent_[i].index) - below) * W + h) *
                                load(t[parent_[i].c] + h);
                    store(cur + (i - first) * W + h, a);
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
            store(f + h, vf);
            store(g[0] + h, v0);
            store(g[1] + h, v1);
            store(g[2] + h, v2);
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

    // The harmonics' tables (sh_tables), one per order p, shared by every
    // expansion of that order (harmonics()).
    struct Block {
        int row, size, matrix;  // its first row in the blocks' order, D and then D^T at matrices[matrix]
    };
    struct Harmonics {
        std::vector<std::size_t> matrix_at;  // degree d's (2d + 1)^2 matrices in `in` and `out`
        std::vector<double> in, out;         // reduced moments to M_i, L_i to reduced W (reduce, add_expanded)
        std::vector<std::size_t> translation_at;  // (j, m), j (p + 1) + m: the coefficients of n = m..p
        std::vector<double> translation;
        std::vector<Block> blocks;           // Q's, by degree
        std::vector<std::size_t> blocks_at;  // degree n's from blocks_at[n]
        std::vector<int> place;              // index i of degree n: its row in the blocks' order, place[n^2 + i]
        std::vector<std::size_t> column;     // the multipole along z by columns (add_local)
        std::vector<double> matrices;        // each block's D, then D^T
    };

    // Tables of the harmonic reduction (see add_local).
    void harmonic_tables() {
        // Reduced multi-indices (k_z <= 1) by degree: k_z = 0 with k_x
        // descending, then k_z = 1 likewise; degree n starts at n^2.
        for (int n = 0; n <= p_; ++n) {
            for (int z = 0; z <= std::min(n, 1); ++z)
                for (int a = n - z; a >= 0; --a) reduced_full_.push_back(index({a, n - z - a, z}));
        }
        // Folding order: k_z descending (a folded moment lands on k_z - 2,
        // which is folded later).
        for (int z = p_; z >= 2; --z)
            for (int n = z; n <= p_; ++n)
                for (int a = n - z; a >= 0; --a)
                    fold_.push_back({index({a, n - z - a, z}), index({a + 2, n - z - a, z - 2}),
                                     index({a, n - z - a + 2, z - 2})});
        sh_ = harmonics();
    }

    // The harmonics' tables of this order, built once per process and order
    // (1.1 ms at p = 14, 5 ms at p = 20: a whole treecode at N = 10^4,
    // theta 0.7, took 27 and 40 ms on the Intel host, and time steppers
    // build one per step).
    std::shared_ptr<const Harmonics> harmonics() const {
        static std::mutex lock;
        static std::array<std::shared_ptr<const Harmonics>, max_order + 1> built;
        const std::lock_guard<std::mutex> hold(lock);
        auto& h = built[static_cast<std::size_t>(p_)];
        if (!h) h = std::make_shared<const Harmonics>(sh_tables());
        return h;
    }

    // A harmonic polynomial of degree n: its coefficients in the graded
    // order of k_ (degree n's block), in long double (the tables' sums
    // cancel; they are rounded to double once).
    using Poly = std::vector<long double>;
    static std::size_t monomials(int n) { return static_cast<std::size_t>((n + 1) * (n + 2) / 2); }
    std::size_t in_degree(const std::array<int, 3>& k) const {
        return static_cast<std::size_t>(index(k) - start_[static_cast<std::size_t>(k[0] + k[1] + k[2])]);
    }
    // x_c q, q of degree n.
    Poly times(const Poly& q, int n, int c) const {
        Poly out(monomials(n + 1), 0.0L);
        for (std::size_t i = 0; i < monomials(n); ++i) {
            auto k = k_[static_cast<std::size_t>(start_[static_cast<std::size_t>(n)]) + i];
            ++k[static_cast<std::size_t>(c)];
            out[in_degree(k)] += q[i];
        }
        return out;
    }
    // Fischer's product sum_k k! x_k y_k of two polynomials of degree n
    // (rotation-invariant; harmonic polynomials are orthogonal to |y|^2 q).
    long double fischer(const Poly& x, const Poly& y, int n) const {
        long double s = 0;
        for (std::size_t i = 0; i < monomials(n); ++i)
            s += static_cast<long double>(factorial_[static_cast<std::size_t>(start_[static_cast<std::size_t>(n)]) + i]) * x[i] * y[i];
        return s;
    }

    // The real solid harmonics S_n^(m,c/s) = G_nm(z, |y|^2) Re/Im (x + iy)^m,
    // Legendre's recurrence (n - m) G_n = (2n - 1) z G_(n-1) - (n + m - 1) |y|^2 G_(n-2)
    // (G_mm = 1, G_(m+1)m = (2m + 1) z), each scaled to Fischer norm 1;
    // within degree n, index 0 is m = 0, 2m - 1 the cosine's, 2m the sine's.
    // From them: in (reduced moments to M_i), out (L_i to reduced
    // W), the z translation's coefficients and Q's blocks (add_local).
    Harmonics sh_tables() const {
        Harmonics h;
        const auto P = static_cast<std::size_t>(p_) + 1;
        std::vector<std::vector<Poly>> S(P);
        for (std::size_t n = 0; n < P; ++n) S[n].resize(2 * n + 1);
        Poly re{1.0L}, im{0.0L};  // (x + iy)^m
        for (int m = 0; m <= p_; ++m) {
            if (m > 0) {
                const Poly a = times(re, m - 1, 0), b = times(im, m - 1, 1), c = times(im, m - 1, 0), d = times(re, m - 1, 1);
                Poly r(a.size()), s(a.size());
                for (std::size_t i = 0; i < a.size(); ++i) {
                    r[i] = a[i] - b[i];
                    s[i] = c[i] + d[i];
                }
                re = std::move(r);
                im = std::move(s);
            }
            for (int part = 0; part < (m > 0 ? 2 : 1); ++part) {
                const std::size_t i = m == 0 ? 0 : static_cast<std::size_t>(2 * m - 1 + part);
                S[static_cast<std::size_t>(m)][i] = part == 0 ? re : im;
                for (int n = m + 1; n <= p_; ++n) {
                    Poly g = times(S[static_cast<std::size_t>(n) - 1][i], n - 1, 2);
                    for (auto& x : g) x *= 2 * n - 1;
                    if (n >= m + 2) {
                        const Poly& q = S[static_cast<std::size_t>(n) - 2][i];
                        for (int c = 0; c < 3; ++c) {
                            const Poly r2 = times(times(q, n - 2, c), n - 1, c);
                            for (std::size_t k = 0; k < g.size(); ++k) g[k] -= (n + m - 1) * r2[k];
                        }
                    }
                    for (auto& x : g) x /= n - m;
                    S[static_cast<std::size_t>(n)][i] = std::move(g);
                }
            }
        }
        for (int n = 0; n <= p_; ++n)
            for (auto& s : S[static_cast<std::size_t>(n)]) {
                const long double norm = std::sqrt(fischer(s, s, n));
                for (auto& x : s) x /= norm;
            }
        // Moments in, locals out: per degree (2n + 1)^2, rows i (harmonics)
        // and r (reduced multi-indices) respectively.
        long double odd_factorial = 1;  // (2n - 1)!!
        for (int n = 0; n <= p_; ++n) {
            if (n > 0) odd_factorial *= 2 * n - 1;
            const auto w = static_cast<std::size_t>(2 * n + 1), first = static_cast<std::size_t>(n * n);
            h.matrix_at.push_back(h.in.size());
            h.in.resize(h.in.size() + w * w);
            h.out.resize(h.in.size());
            double* in = h.in.data() + h.matrix_at.back();
            double* out = h.out.data() + h.matrix_at.back();
            for (std::size_t i = 0; i < w; ++i)
                for (std::size_t r = 0; r < w; ++r) {
                    const auto full = static_cast<std::size_t>(reduced_full_[first + r]);
                    const long double s = S[static_cast<std::size_t>(n)][i][full - static_cast<std::size_t>(start_[static_cast<std::size_t>(n)])];
                    in[i * w + r] = static_cast<double>(odd_factorial * factorial_[full] * s);
                    out[r * w + i] = static_cast<double>(factorial_[full] * s);
                }
        }
        // The translation along z: K_nm, the coefficient of x^m z^(n-m) in S_n^(m,c).
        std::vector<long double> K(P * P, 0.0L);
        for (int n = 0; n <= p_; ++n)
            for (int m = 0; m <= n; ++m)
                K[static_cast<std::size_t>(n) * P + static_cast<std::size_t>(m)] =
                    S[static_cast<std::size_t>(n)][m == 0 ? 0 : static_cast<std::size_t>(2 * m - 1)][in_degree({m, 0, n - m})];
        h.translation_at.assign(P * P, 0);
        for (int j = 0; j <= p_; ++j)
            for (int m = 0; m <= j; ++m) {
                h.translation_at[static_cast<std::size_t>(j) * P + static_cast<std::size_t>(m)] = h.translation.size();
                for (int n = m; n <= p_; ++n) {
                    const double b = binom_[static_cast<std::size_t>(n + j)][static_cast<std::size_t>(j - m)];
                    h.translation.push_back(static_cast<double>(((j - m) % 2 ? -b : b) *
                                                                K[static_cast<std::size_t>(n) * P + static_cast<std::size_t>(m)] /
                                                                K[static_cast<std::size_t>(j) * P + static_cast<std::size_t>(m)]));
                }
            }
        // The multipole along z by columns (add_local): index i (m = (i + 1)/2)
        // of degrees n = m..p at column[i] + n - m.
        for (std::size_t i = 0, row = 0; i < 2 * P - 1; ++i) {
            h.column.push_back(row);
            row += P - (i + 1) / 2;
        }
        // Q = R_x(-pi/2) (z to y): D_(i'i) = <S_i', S_i(Q^T y)>, S_i(Q^T y) =
        // S_i(x, -z, y). Q commutes with x -> -x and with R_x(pi), so D keeps
        // their parities: cos(m phi) parts have (-1)^m and (-1)^(n-m), sine
        // parts the opposite of each: four blocks.
        h.blocks_at.push_back(0);
        for (int n = 0; n <= p_; ++n) {
            const auto w = static_cast<std::size_t>(2 * n + 1);
            const auto first = static_cast<std::size_t>(start_[static_cast<std::size_t>(n)]);
            std::vector<Poly> moved(w, Poly(monomials(n), 0.0L));
            for (std::size_t i = 0; i < w; ++i)
                for (std::size_t k = 0; k < monomials(n); ++k) {
                    const auto& e = k_[first + k];
                    moved[i][in_degree({e[0], e[2], e[1]})] = (e[1] % 2 ? -1 : 1) * S[static_cast<std::size_t>(n)][i][k];
                }
            auto parity = [n](std::size_t i) {
                const int m = static_cast<int>((i + 1) / 2), sine = i > 0 && i % 2 == 0;
                return 2 * ((m + sine) % 2) + (n - m + sine) % 2;
            };
            std::vector<int> order;  // the degree's indices by class: each block's rows contiguous
            for (int cls = 0; cls < 4; ++cls) {
                Block b{static_cast<int>(order.size()), 0, static_cast<int>(h.matrices.size())};
                for (std::size_t i = 0; i < w; ++i)
                    if (parity(i) == cls) order.push_back(static_cast<int>(i));
                b.size = static_cast<int>(order.size()) - b.row;
                if (b.size == 0) continue;
                const auto s = static_cast<std::size_t>(b.size);
                h.matrices.resize(h.matrices.size() + 2 * s * s);
                double* d = h.matrices.data() + b.matrix;
                for (std::size_t x = 0; x < s; ++x)
                    for (std::size_t y = 0; y < s; ++y) {
                        const auto ix = static_cast<std::size_t>(order[static_cast<std::size_t>(b.row) + x]);
                        const auto iy = static_cast<std::size_t>(order[static_cast<std::size_t>(b.row) + y]);
                        const double v = static_cast<double>(fischer(S[static_cast<std::size_t>(n)][ix], moved[iy], n));
                        d[x * s + y] = v;          // D
                        d[s * s + y * s + x] = v;  // D^T
                    }
                h.blocks.push_back(b);
            }
            h.place.resize(h.place.size() + w);
            for (std::size_t r = 0; r < w; ++r) h.place[static_cast<std::size_t>(n * n) + static_cast<std::size_t>(order[r])] = static_cast<int>(r);
            h.blocks_at.push_back(h.blocks.size());
        }
        return h;
    }
    // The offset of degree d's (2d + 1)^2 matrix in Harmonics::in and out.
    std::size_t sh_at(int d) const { return sh_->matrix_at[static_cast<std::size_t>(d)]; }

    // cos(m a) and sin(m a) per lane, m <= degree, from row 1 (fill: the
    // complex powers (cos a + i sin a)^m).
    struct Angles {
        alignas(64) double c[max_order + 1][lanes], s[max_order + 1][lanes];
        void fill(int degree) {
            for (int l = 0; l < lanes; ++l) {
                c[0][l] = 1;
                s[0][l] = 0;
            }
            for (int m = 2; m <= degree; ++m)
                for (int l = 0; l < lanes; ++l) {
                    c[m][l] = c[m - 1][l] * c[1][l] - s[m - 1][l] * s[1][l];
                    s[m][l] = s[m - 1][l] * c[1][l] + c[m - 1][l] * s[1][l];
                }
        }
    };

    // The coordinates of degree n (rows of lanes in the blocks' order)
    // rotated about z by sign a (sign = -1: the frame turned by a):
    // (c, s)_m -> (c cos ma - s sin ma, c sin ma + s cos ma).
    void rotate_z(double* x, int n, const Angles& g, int sign) const {
        constexpr int W = lanes;
        const int* at = sh_->place.data() + n * n;
        for (int m = 1; m <= n; ++m) {
            double* c = x + static_cast<std::size_t>(at[2 * m - 1]) * W;
            double* s = x + static_cast<std::size_t>(at[2 * m]) * W;
            MOLLIFY_SIMD
            for (int l = 0; l < W; ++l) {
                const double cm = g.c[m][l], sm = sign * g.s[m][l], p = c[l], q = s[l];
                c[l] = p * cm - q * sm;
                s[l] = p * sm + q * cm;
            }
        }
    }

    // out = D in (transposed: D^T in), degree n: Q's blocks, each on its
    // own contiguous rows.
    void exchange(const double* in, double* out, int n, bool transposed) const {
        for (std::size_t k = sh_->blocks_at[static_cast<std::size_t>(n)]; k < sh_->blocks_at[static_cast<std::size_t>(n) + 1]; ++k) {
            const Block& b = sh_->blocks[k];
            const auto s = static_cast<std::size_t>(b.size), row = static_cast<std::size_t>(b.row) * lanes;
            matrix_rows(sh_->matrices.data() + b.matrix + (transposed ? s * s : 0), s, in + row, out + row);
        }
    }

    // y = d x for an s x s matrix d and s rows of lanes x: four rows of d
    // at a time (four chains of multiply-adds, x loaded once for the four).
    static void matrix_rows(const double* d, std::size_t s, const double* x, double* y) {
        constexpr int W = lanes;
#if defined(MOLLIFY_LANES)
        for (int h = 0; h < W; h += N) {
            std::size_t r = 0;
            for (; r + 4 <= s; r += 4) {
                V a0{}, a1{}, a2{}, a3{};
                for (std::size_t c = 0; c < s; ++c) {
                    const V v = load(x + c * W + h);
                    a0 += d[r * s + c] * v;
                    a1 += d[(r + 1) * s + c] * v;
                    a2 += d[(r + 2) * s + c] * v;
                    a3 += d[(r + 3) * s + c] * v;
                }
                store(y + r * W + h, a0);
                store(y + (r + 1) * W + h, a1);
                store(y + (r + 2) * W + h, a2);
                store(y + (r + 3) * W + h, a3);
            }
            for (; r < s; ++r) {
                V a0{};
                for (std::size_t c = 0; c < s; ++c) a0 += d[r * s + c] * load(x + c * W + h);
                store(y + r * W + h, a0);
            }
        }
#else
        for (std::size_t r = 0; r < s; ++r)
            for (int l = 0; l < W; ++l) {
                double a0 = 0;
                for (std::size_t c = 0; c < s; ++c) a0 += d[r * s + c] * x[c * W + static_cast<std::size_t>(l)];
                y[r * W + static_cast<std::size_t>(l)] = a0;
            }
#endif
    }

    // The local coordinates of degree j (into u, the blocks' order) of the
    // multipole along z (a by columns, degrees n <= degree): m kept, the
    // cosine's and the sine's column with the same coefficients.
    void translate_z(const double* a, double* u, int j, int degree) const {
        constexpr int W = lanes;
        const auto P = static_cast<std::size_t>(p_) + 1;
        const int* at = sh_->place.data() + j * j;
        for (int m = 0; m <= j; ++m) {
            const double* c = sh_->translation.data() + sh_->translation_at[static_cast<std::size_t>(j) * P + static_cast<std::size_t>(m)];
            const auto len = static_cast<std::size_t>(degree - m + 1);
            if (m == 0) {
                column_dot(c, a + sh_->column[0] * W, a + sh_->column[0] * W, len, u + static_cast<std::size_t>(at[0]) * W, nullptr);
            } else {
                const auto i = static_cast<std::size_t>(2 * m - 1);
                column_dot(c, a + sh_->column[i] * W, a + sh_->column[i + 1] * W, len, u + static_cast<std::size_t>(at[i]) * W,
                           u + static_cast<std::size_t>(at[i + 1]) * W);
            }
        }
    }

    // yc = sum_t c_t xc_t and ys likewise (ys null: yc alone), rows of
    // lanes, in two chains each.
    static void column_dot(const double* c, const double* xc, const double* xs, std::size_t len, double* yc, double* ys) {
        constexpr int W = lanes;
#if defined(MOLLIFY_LANES)
        for (int h = 0; h < W; h += N) {
            V c0{}, c1{}, s0{}, s1{};
            std::size_t t = 0;
            for (; t + 2 <= len; t += 2) {
                c0 += c[t] * load(xc + t * W + h);
                c1 += c[t + 1] * load(xc + (t + 1) * W + h);
                if (ys) {
                    s0 += c[t] * load(xs + t * W + h);
                    s1 += c[t + 1] * load(xs + (t + 1) * W + h);
                }
            }
            if (t < len) {
                c0 += c[t] * load(xc + t * W + h);
                if (ys) s0 += c[t] * load(xs + t * W + h);
            }
            store(yc + h, c0 + c1);
            if (ys) store(ys + h, s0 + s1);
        }
#else
        for (int l = 0; l < W; ++l) {
            double sc = 0, ss = 0;
            for (std::size_t t = 0; t < len; ++t) {
                sc += c[t] * xc[t * W + static_cast<std::size_t>(l)];
                ss += c[t] * xs[t * W + static_cast<std::size_t>(l)];
            }
            yc[l] = sc;
            if (ys) ys[l] = ss;
        }
#endif
    }

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
    // binom_[a][b] = binom(a, b), a <= 2 max_order (exact in double: binom(40, 20) < 2^38).
    std::array<std::array<double, 2 * max_order + 1>, 2 * max_order + 1> binom_{};
    struct Parent {
        int index, c;  // k - e_c, c
    };
    std::vector<Parent> parent_;
    // The harmonic reduction (add_local).
    static std::size_t count_reduced(int d) { return static_cast<std::size_t>(d + 1) * static_cast<std::size_t>(d + 1); }
    struct Fold {
        int i, a, b;  // k (k_z >= 2), k - 2e_z + 2e_x, k - 2e_z + 2e_y
    };
    std::vector<int> reduced_full_;
    std::vector<Fold> fold_;
    std::shared_ptr<const Harmonics> sh_;  // harmonics()
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

MOLLIFY_VECTOR_MISSES_ALLOWED_END
