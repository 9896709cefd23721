// The 3D M2L (Multipole<3>::reduce, add_local, add_expanded: rotated real
// spherical harmonics, multipole.hpp) against its definition, evaluated
// here in long double from the Cartesian Taylor coefficients of 1/|R|:
//     L_m rho_t^|m| = (-1)^|m| sum_(|k|<=d) binom(k + m, k) M_k a_(k+m)(R) rho_t^|m|,  |m| <= d,
// M_k = sum q (y - c_s)^k, a_k(R) = a_k(u)/|R|^(|k|+1) by Lindsay & Krasny's
// recurrence (J. Comput. Phys. 172 (2001), eq. (2.8)). The oracle shares
// nothing with the code under test but the coefficients' order.
#include <mollify/poisson/multipole.hpp>

#include "sanitized.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

namespace {

using mollify::poisson::Multipole;
using Index = std::array<int, 3>;

// The library's order of the coefficients (multipole.hpp, index()): by
// degree, then k_x descending, then k_y descending.
std::vector<Index> graded(int p) {
    std::vector<Index> k;
    for (int n = 0; n <= p; ++n)
        for (int a = n; a >= 0; --a)
            for (int b = n - a; b >= 0; --b) k.push_back({a, b, n - a - b});
    return k;
}

// a_k(u) for a unit vector u, |k| <= top, in a dense cube.
struct Taylor {
    int side;
    std::vector<long double> a;
    long double& at(const Index& k) { return a[(static_cast<std::size_t>(k[0]) * side + k[1]) * side + k[2]]; }

    Taylor(const std::array<long double, 3>& u, int top) : side(top + 1), a(static_cast<std::size_t>(side) * side * side, 0.0L) {
        for (const Index& k : graded(top)) {  // by degree: the recurrence's terms come first
                const int n = k[0] + k[1] + k[2];
                if (n == 0) {
                    at(k) = 1;
                    continue;
                }
                long double first = 0, second = 0;
                for (int c = 0; c < 3; ++c) {
                    Index m = k;
                    if (--m[c] >= 0) first += u[c] * at(m);
                    if (--m[c] >= 0) second += at(m);
                }
                at(k) = ((2.0L * n - 1) * first - (n - 1.0L) * second) / n;
            }
    }
};

// binom(a, b), a <= 40 (Pascal's triangle: exact in long double).
struct Binomials {
    long double c[41][41] = {};
    Binomials() {
        for (int a = 0; a <= 40; ++a) {
            c[a][0] = 1;
            for (int b = 1; b <= a; ++b) c[a][b] = c[a - 1][b - 1] + (b < a ? c[a - 1][b] : 0.0L);
        }
    }
};

struct Cell {
    std::array<double, 3> centre;
    double rho;
};

// n point charges within a cell (scaled: within 1 of its centre): their moments
// sum q ((y - c)/rho)^k (add_sources' definition), in the graded order.
std::vector<double> moments(int p, std::mt19937_64& g, int n) {
    std::uniform_real_distribution<double> U(-1, 1);
    std::vector<long double> m(graded(p).size(), 0.0L);
    for (int j = 0; j < n; ++j) {
        std::array<long double, 3> t;
        for (auto& c : t) c = U(g) / std::sqrt(3.0);
        const long double q = U(g);
        std::size_t i = 0;
        for (const Index& k : graded(p)) m[i++] += q * std::pow(t[0], k[0]) * std::pow(t[1], k[1]) * std::pow(t[2], k[2]);
    }
    return {m.begin(), m.end()};
}

// R = c_t - c_s as the treecode forms it (in double), for both sides.
std::array<double, 3> apart(const Cell& t, const Cell& s) {
    return {t.centre[0] - s.centre[0], t.centre[1] - s.centre[1], t.centre[2] - s.centre[2]};
}

// The worst |library - definition| of each degree over the largest sum of
// absolute terms of that degree (the scale a rounding error is relative to).
std::vector<double> errors(int p, int degree, const std::vector<std::vector<double>>& m, const std::vector<Cell>& src,
                           const Cell& target) {
    const Multipole<3> e(p);
    const auto order = graded(p);
    constexpr int W = Multipole<3>::lanes;
    std::vector<std::vector<double>> reduced(src.size(), std::vector<double>(e.reduced_size()));
    std::vector<double> work;
    for (std::size_t s = 0; s < src.size(); ++s) e.reduce(m[s].data(), p, reduced[s].data(), work);
    std::vector<double> lanes((e.reduced_size() + 1) * W, 0.0);
    double* lr = Multipole<3>::aligned(lanes.data());
    for (std::size_t s0 = 0; s0 < src.size(); s0 += W) {
        std::vector<Multipole<3>::Source> batch;
        for (std::size_t s = s0; s < std::min(src.size(), s0 + W); ++s) batch.push_back({reduced[s].data(), src[s].rho, apart(target, src[s])});
        e.add_local(batch.data(), static_cast<int>(batch.size()), target.rho, lr, work, degree);
    }
    std::vector<double> local(e.size(), 0.0);
    e.add_expanded(lr, local.data(), work);

    static const Binomials binom;
    std::vector<long double> exact(order.size(), 0.0L), scale(order.size(), 0.0L);
    for (std::size_t s = 0; s < src.size(); ++s) {
        const std::array<double, 3> d = apart(target, src[s]);
        const std::array<long double, 3> R{d[0], d[1], d[2]};
        const long double r2 = R[0] * R[0] + R[1] * R[1] + R[2] * R[2];
        const long double r = std::sqrt(r2);
        Taylor a({R[0] / r, R[1] / r, R[2] / r}, 2 * degree);
        std::vector<long double> ps(static_cast<std::size_t>(degree) + 1), pt(ps.size());  // (rho/|R|)^n
        for (std::size_t n = 0; n < ps.size(); ++n) {
            ps[n] = std::pow(src[s].rho / r, static_cast<int>(n));
            pt[n] = std::pow(target.rho / r, static_cast<int>(n));
        }
        for (std::size_t i = 0; i < order.size(); ++i) {
            const Index& mi = order[i];
            const int dm = mi[0] + mi[1] + mi[2];
            if (dm > degree) continue;
            for (std::size_t j = 0; j < order.size(); ++j) {
                const Index& k = order[j];
                const int dk = k[0] + k[1] + k[2];
                if (dk > degree) continue;
                const long double b = binom.c[k[0] + mi[0]][k[0]] * binom.c[k[1] + mi[1]][k[1]] * binom.c[k[2] + mi[2]][k[2]];
                const long double term = (dm % 2 ? -1 : 1) * b * m[s][j] * ps[static_cast<std::size_t>(dk)] *
                                         pt[static_cast<std::size_t>(dm)] * a.at({k[0] + mi[0], k[1] + mi[1], k[2] + mi[2]}) / r;
                exact[i] += term;
                scale[i] += std::fabs(term);
            }
        }
    }
    std::vector<double> worst(static_cast<std::size_t>(p) + 1, 0.0), top(worst.size(), 0.0);
    for (std::size_t i = 0; i < order.size(); ++i) {
        const auto d = static_cast<std::size_t>(order[i][0] + order[i][1] + order[i][2]);
        if (static_cast<int>(d) > degree) {
            EXPECT_EQ(local[i], 0.0) << "a coefficient above the degree " << degree;
            continue;
        }
        worst[d] = std::max(worst[d], static_cast<double>(std::fabs(local[i] - exact[i])));
        top[d] = std::max(top[d], static_cast<double>(scale[i]));
    }
    for (std::size_t d = 0; d < worst.size(); ++d) worst[d] = top[d] > 0 ? worst[d] / top[d] : 0.0;
    return worst;
}

constexpr double u = std::numeric_limits<double>::epsilon() / 2;

// Tolerance: 32 u of the degree's largest sum of absolute terms. Measured
// worst: 2.3 u (p = 20; x86-64 and x86-64-v4 builds): the four products
// with Q's blocks are orthogonal, the translation's sums have up to 21
// terms with binomials to binom(40, 20); a sign or index slip in any step
// shows as O(1), an azimuth taken from an underflowed R_x^2 + R_y^2 as
// ~3000 u (tried).
constexpr double tolerance = 32 * u;

void expect_within(const std::vector<double>& worst, const char* what) {
    for (std::size_t d = 0; d < worst.size(); ++d)
        EXPECT_LE(worst[d], tolerance) << what << ": degree " << d << ", " << worst[d] / u << " u";
    std::printf("[m2l] %s: worst %.1f u\n", what, *std::max_element(worst.begin(), worst.end()) / u);
}

// Source cells around a target cell at the unit distance scale, in the
// directions given (the hard ones: along the axes, where the rotation's
// azimuth is undefined; off the z axis by 1e-12 and by less than the
// square root of the least normal number, where R_x^2 + R_y^2 underflows).
std::vector<Cell> around(const Cell& t, const std::vector<std::array<double, 3>>& dirs, double distance, double rho) {
    std::vector<Cell> s;
    for (const auto& d : dirs) {
        const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        s.push_back({{t.centre[0] - distance * d[0] / n, t.centre[1] - distance * d[1] / n, t.centre[2] - distance * d[2] / n}, rho});
    }
    return s;
}

const std::vector<std::array<double, 3>> hard_directions{
    {0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {1e-12, 0, 1}, {0, -1e-12, -1}, {1e-170, 1e-170, 1}, {1, 1, 1},
    {-0.3, 0.7, -0.2}};

void check(int p, int degree, double scale, const char* what) {
    std::mt19937_64 g(static_cast<unsigned>(1000 * p + degree));
    const Cell target{{0, 0, 0.3 * scale}, 0.25 * scale};  // on the z axis: R_x, R_y as given
    auto dirs = hard_directions;
    std::normal_distribution<double> N;
    // Under -O0 + ASan (CI's second build: the same code paths, not all the
    // workload) the hard directions alone: the long-double reference's sums
    // are the cost there (p = 20 and 17 took 28 s).
    if (!mollify::testing::sanitized_build)
        for (int i = 0; i < 8; ++i) dirs.push_back({N(g), N(g), N(g)});
    const auto src = around(target, dirs, scale, 0.3 * scale);
    std::vector<std::vector<double>> m;
    for (std::size_t i = 0; i < src.size(); ++i) m.push_back(moments(p, g, 5));
    expect_within(errors(p, degree, m, src, target), what);
}

TEST(M2L, MatchesTheDefinitionAtEveryOrder) {
    for (const int p : {0, 1, 2, 5, 9}) check(p, p, 1, "p = 0, 1, 2, 5, 9");
}

TEST(M2L, MatchesTheDefinitionAtHighOrder) {
    check(20, 20, 1, "p = 20");
    if (!mollify::testing::sanitized_build) check(17, 17, 1, "p = 17");  // the same paths as p = 20
}

// A batch below the expansion's order (pair_degree): the coefficients
// above it stay 0, those below are the truncated sum's.
TEST(M2L, MatchesTheDefinitionBelowTheOrder) {
    check(12, 7, 1, "p = 12, degree 7");
    check(20, 3, 1, "p = 20, degree 3");
}

// Tiny and huge cells: the powers (rho/|R|)^n are taken as ratios, so
// |R|^-(n+j+1) = 1e8200 never appears, and the angles from R over its
// largest component (|R|^2 = 1e400 would overflow; at 1e-150 the
// 1e-12-off-axis pair's R_x^2 underflows).
TEST(M2L, TinyAndHugeScales) {
    check(15, 15, 1e-150, "scale 1e-150");
    check(15, 15, 1e-200, "scale 1e-200");
    check(15, 15, 1e200, "scale 1e200");
}

}  // namespace
