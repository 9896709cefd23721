// The treecode's near-field passes on AVX-512 (include/mollify/poisson/pair_sum.hpp,
// detail/lanes.hpp): 1/sqrt refined from VRSQRT14PD's estimate against
// long double, its hard cases (the lanes it leaves to the division), the
// two Green's passes with the refined 1/r against the same passes with the
// division, the pairs they leave to the exact kernel (detail::WithinPairs,
// compressed into place eight at a time) against their definition, and the
// tile of four targets against four single-target passes. Built for
// x86-64-v4 where the host has AVX-512 (tests/CMakeLists.txt:
// poisson_free_v4_test).
#include <mollify/poisson.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#if !defined(__AVX512F__)
#error "poisson_green_test is built for AVX-512 (x86-64-v4)"
#endif

namespace {

namespace md = mollify::detail;
namespace pd = mollify::poisson::detail;
using md::InverseSqrt;
using md::Lanes;

// The lanes' 1/sqrt both ways, lane by lane.
std::array<double, 8> inverse_sqrt(InverseSqrt how, const std::array<double, 8>& a) {
    const Lanes v = md::load_lanes(a.data());
    const Lanes y = how == InverseSqrt::refine ? md::inverse_sqrt_lanes<InverseSqrt::refine>(v)
                                               : md::inverse_sqrt_lanes<InverseSqrt::divide>(v);
    std::array<double, 8> out;
    md::store_lanes(out.data(), y);
    return out;
}

// |y - exact| in ulps of the exact value, exact = 1/sqrt(a) in long double
// (x87: a 64-bit significand, its own error ~2^-63, below 0.001 ulp of a double).
double ulps(double y, double a) {
    const long double exact = 1.0L / std::sqrt(static_cast<long double>(a));
    int e = 0;
    std::frexp(static_cast<double>(exact), &e);
    const long double ulp = std::ldexp(1.0L, e - 53);
    return static_cast<double>(std::abs(static_cast<long double>(y) - exact) / ulp);
}

// Within 2 ulp everywhere the refinement runs (its analysis, lanes.hpp:
// the truncation 35 e^4/128 < 0.27 ulp, t's rounding <= 0.5 ulp, the last
// multiply-add's 0.5 ulp and the small terms' roundings): every binade of
// the normal doubles, random significands, and the significands where an
// estimate is least accurate, 1 and just below 2 and 4 (the estimate's
// table steps at the binade's edges).
TEST(InverseSqrt, RefinedWithinTwoUlpOfEveryBinade) {
    std::mt19937_64 rng(20261204);
    std::uniform_real_distribution<double> significand(1.0, 4.0);
    double worst = 0, worst_at = 0;
    std::size_t count = 0;
    for (int e = -1022; e <= 1021; e += 2) {
        std::array<double, 8> a;
        a[0] = std::ldexp(1.0, e);
        a[1] = std::ldexp(std::nextafter(2.0, 0.0), e);
        a[2] = std::ldexp(std::nextafter(4.0, 0.0), e);
        a[3] = std::ldexp(std::nextafter(1.0, 2.0), e);
        for (int l = 4; l < 8; ++l) a[l] = std::ldexp(significand(rng), e);
        for (int round = 0; round < 25; ++round) {
            const std::array<double, 8> y = inverse_sqrt(InverseSqrt::refine, a);
            for (int l = 0; l < 8; ++l) {
                const double err = ulps(y[l], a[l]);
                ++count;
                if (err > worst) worst = err, worst_at = a[l];
            }
            for (int l = 0; l < 8; ++l) a[l] = std::ldexp(significand(rng), e);
        }
    }
    std::printf("refined 1/sqrt: %zu values, largest error %.3f ulp at %a\n", count, worst, worst_at);
    EXPECT_LE(worst, 2.0) << "at " << worst_at;
    // The estimate alone (2^-14) or a correction of lower order (the e^2
    // term's rest, 5 e^3/16 ~ 2^-40) would be thousands of ulp off.
    EXPECT_GT(count, 200000u);
}

// Where the estimate or its correction does not hold (0: 0 * inf; inf:
// inf * 0; subnormal, negative, NaN), the block is the division's, bit for
// bit, its other lanes included.
TEST(InverseSqrt, HardLanesTakeTheDivision) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double hard[] = {0.0, -0.0, inf, nan, 0x1p-1074, 0x1.ffffffffffffep-1023, -1.0, -inf};  // the least and largest subnormal
    for (const double h : hard) {
        for (int lane = 0; lane < 8; ++lane) {
            std::array<double, 8> a{0.5, 3.0, 1e-300, 1e300, 7.25, 0x1p-1022, 0x1.fffffffffffffp+1023, 2.0};
            a[lane] = h;
            const std::array<double, 8> r = inverse_sqrt(InverseSqrt::refine, a);
            const std::array<double, 8> d = inverse_sqrt(InverseSqrt::divide, a);
            for (int l = 0; l < 8; ++l)
                EXPECT_EQ(std::bit_cast<std::uint64_t>(r[l]), std::bit_cast<std::uint64_t>(d[l]))
                    << "hard value " << h << " in lane " << lane << ", lane " << l;
        }
    }
    // The extremes of the normal range go through the refinement, finite and within 2 ulp.
    const std::array<double, 8> ends{0x1p-1022, 0x1.fffffffffffffp+1023, 0x1p-1021, 0x1p+1022, 1.0, 4.0, 0x1p-1000, 0x1p+1000};
    const std::array<double, 8> y = inverse_sqrt(InverseSqrt::refine, ends);
    for (int l = 0; l < 8; ++l) EXPECT_LE(ulps(y[l], ends[l]), 2.0) << ends[l];
}

// n sources round a target at distances from 1e-3 to 10 (some within the
// squared supports d2 of either end, every 97th coincident with the target:
// a block the division takes; n not a multiple of 8: the scalar tail),
// charges of both signs.
struct Pass {
    std::vector<double> x, y, z, q, d2;
};

Pass sources(std::size_t n, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), log_r(-3.0, 1.0);
    Pass p;
    for (std::size_t j = 0; j < n; ++j) {
        const double r = j % 97 == 0 ? 0.0 : std::pow(10.0, log_r(rng));
        double v[3] = {unit(rng), unit(rng), unit(rng)};
        const double norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        p.x.push_back(0.25 + r * v[0] / norm);
        p.y.push_back(-0.5 + r * v[1] / norm);
        p.z.push_back(2.0 + r * v[2] / norm);
        p.q.push_back(unit(rng));
        p.d2.push_back(j % 3 == 0 ? 0x1p-600 : 1e-4 * (1 + j % 5));  // > 0, as delta^2 always is
    }
    return p;
}

// The pairs a pass leaves out, by the definition: every j with
// !(r^2 >= d2_j) (r^2 formed as the passes form it: d = xt - x_j, FMAs in
// the order x, y, z), in order, with r^2 bit for bit.
void expect_listed(const Pass& p, std::size_t n, const std::array<double, 3>& xt, const std::vector<double>& d2,
                   const pd::WithinPairs& got, const char* what) {
    std::size_t expected = 0;
    for (std::size_t j = 0; j < n; ++j) {
        const double dx = xt[0] - p.x[j], dy = xt[1] - p.y[j], dz = xt[2] - p.z[j];
        const double r2 = std::fma(dz, dz, std::fma(dy, dy, dx * dx));
        if (r2 >= d2[j]) continue;
        ASSERT_LT(expected, got.size) << what << " n " << n << ": pair " << j << " within the support is missing";
        EXPECT_EQ(got.at[expected], j) << what << " n " << n;
        EXPECT_EQ(std::bit_cast<std::uint64_t>(got.r2[expected]), std::bit_cast<std::uint64_t>(r2)) << what << " n " << n;
        ++expected;
    }
    EXPECT_EQ(got.size, expected) << what << " n " << n;
    EXPECT_GT(got.size, 0u) << what << " n " << n;
}

// Room for a pass's list.
struct List {
    std::vector<unsigned> at;
    std::vector<double> r2;
    explicit List(std::size_t n) : at(n), r2(n) {}
    pd::WithinPairs pairs() { return {at.data(), r2.data()}; }
};

// The mutual pass both ways: the target's phi and E and every source's
// sums agree to a few roundings of their terms' magnitudes (each 1/r within
// 2 ulp, 1/r^3 within ~6 ulp: 1e-15 relative per term, against ~2^-14 for
// an unrefined estimate), and nothing is NaN (coincident pairs are masked
// out as with the division); the pairs it leaves to the exact kernel are
// listed by the definition, per direction (per-source d2: within the
// source's support for the target, within the target's d2t for the source)
// and, with one global d2 (to_source null), once for both.
TEST(GreenPass, MutualRefinedAgreesWithDivision) {
    const std::array<double, 3> xt{0.25, -0.5, 2.0};
    for (const bool global : {false, true})
        for (const std::size_t n : {std::size_t{5}, std::size_t{203}, std::size_t{4099}}) {
            Pass p = sources(n, 7 + static_cast<unsigned>(n));
            const double d2t = 2e-4;
            if (global) p.d2.assign(n, d2t);
            struct Out {
                double phi = 0;
                std::array<double, 3> e{};
                std::vector<double> w, g0, g1, g2;
            };
            auto run = [&](InverseSqrt how) {
                Out o;
                o.w.assign(n, 0.0), o.g0.assign(n, 0.0), o.g1.assign(n, 0.0), o.g2.assign(n, 0.0);
                List to_t(n), to_j(n);
                pd::WithinPairs t = to_t.pairs(), j = to_j.pairs();
                pd::add_green_mutual(p.x.data(), p.y.data(), p.z.data(), p.q.data(), p.d2.data(), n, xt, 0.75, d2t,
                                     o.phi, o.e, o.w.data(), o.g0.data(), o.g1.data(), o.g2.data(), t,
                                     global ? nullptr : &j, how);
                expect_listed(p, n, xt, p.d2, t, global ? "both directions" : "to the target");
                if (!global) expect_listed(p, n, xt, std::vector<double>(n, d2t), j, "to the sources");
                return o;
            };
            const Out r = run(InverseSqrt::refine), d = run(InverseSqrt::divide);
            // The magnitudes the sums are made of: sum |q|/r and sum |q|/r^2.
            double mag_phi = 0, mag_e = 0;
            for (std::size_t j = 0; j < n; ++j) {
                const double dx = xt[0] - p.x[j], dy = xt[1] - p.y[j], dz = xt[2] - p.z[j];
                const double r2 = dx * dx + dy * dy + dz * dz;
                if (r2 >= p.d2[j] && r2 > 0) mag_phi += std::abs(p.q[j]) / std::sqrt(r2), mag_e += std::abs(p.q[j]) / r2;
            }
            const double tol = 1e-14;  // ~45 u: 6 ulp per term plus the sums' own roundings, which the two ways share
            EXPECT_TRUE(std::isfinite(r.phi));
            EXPECT_NEAR(r.phi, d.phi, tol * mag_phi) << n;
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.e[c], d.e[c], tol * mag_e) << n << " component " << c;
            for (std::size_t j = 0; j < n; ++j) {
                const double dx = xt[0] - p.x[j], dy = xt[1] - p.y[j], dz = xt[2] - p.z[j];
                const double r2 = dx * dx + dy * dy + dz * dz;
                ASSERT_TRUE(std::isfinite(r.w[j]) && std::isfinite(r.g0[j])) << j;
                EXPECT_NEAR(r.w[j], d.w[j], 6e-16 * std::abs(d.w[j])) << j << " r2 " << r2;
                EXPECT_NEAR(r.g0[j], d.g0[j], 2e-15 * std::abs(d.g0[j])) << j << " r2 " << r2;
                EXPECT_NEAR(r.g2[j], d.g2[j], 2e-15 * std::abs(d.g2[j])) << j << " r2 " << r2;
            }
        }
}

// The one-way pass, and pairs whose r^2 overflows (2^600 apart): 1/r = 0
// from the division's block, as before, not inf * 0; its list of the
// pairs within a support by the definition.
TEST(GreenPass, OneWayRefinedAgreesWithDivision) {
    const std::array<double, 3> xt{0.25, -0.5, 2.0};
    Pass p = sources(1001, 99);
    p.x[17] = 0x1p600;
    const std::size_t n = p.x.size();
    double phi_r = 0, phi_d = 0;
    std::array<double, 3> e_r{}, e_d{};
    List list_r(n), list_d(n);
    pd::WithinPairs within_r = list_r.pairs(), within_d = list_d.pairs();
    pd::add_green(p.x.data(), p.y.data(), p.z.data(), p.q.data(), p.d2.data(), n, xt, phi_r, e_r, within_r,
                  InverseSqrt::refine);
    pd::add_green(p.x.data(), p.y.data(), p.z.data(), p.q.data(), p.d2.data(), n, xt, phi_d, e_d, within_d,
                  InverseSqrt::divide);
    expect_listed(p, n, xt, p.d2, within_r, "refined");
    expect_listed(p, n, xt, p.d2, within_d, "divided");
    ASSERT_TRUE(std::isfinite(phi_r));
    double mag_phi = 0, mag_e = 0;
    for (std::size_t j = 0; j < n; ++j) {
        const double dx = xt[0] - p.x[j], dy = xt[1] - p.y[j], dz = xt[2] - p.z[j];
        const double r2 = dx * dx + dy * dy + dz * dz;
        if (r2 >= p.d2[j] && r2 > 0 && std::isfinite(r2))
            mag_phi += std::abs(p.q[j]) / std::sqrt(r2), mag_e += std::abs(p.q[j]) / r2;
    }
    EXPECT_NEAR(phi_r, phi_d, 1e-14 * mag_phi);
    for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(e_r[c])) << c;
        EXPECT_NEAR(e_r[c], e_d[c], 1e-14 * mag_e) << c;
    }
}

// T targets in one pass (detail::Targets, the treecode's tile) against T
// single-target passes: each target's phi and E, the sources' sums and
// each target's lists (by the definition), per-source and global d2, both
// ways of 1/sqrt. The tile sums a block's source terms over its targets
// before adding them to the sources' sums: the same terms in another
// order, so agreement to the terms' magnitudes (1e-14 as above).
template <int T>
void tile_is_each_targets_pass(bool global, InverseSqrt how) {
    const std::size_t n = 1003;
    Pass p = sources(n, 41);
    // The first target is sources()' centre, the others at sources 1, 2, 3
    // (r = 0: each has pairs within the supports).
    std::array<std::array<double, 3>, 4> xt{{{0.25, -0.5, 2.0}}};
    for (std::size_t t = 1; t < 4; ++t) xt[t] = {p.x[t], p.y[t], p.z[t]};
    const std::array<double, 4> qt{0.75, -0.5, 1.25, 0.125}, d2t{2e-4, 3e-4, 2e-4, 1e-4};
    if (global) p.d2.assign(n, d2t[0]);
    std::vector<double> w(n, 0.0), g0(n, 0.0), g1(n, 0.0), g2(n, 0.0);
    std::vector<double> w1(n, 0.0), g01(n, 0.0), g11(n, 0.0), g21(n, 0.0);
    std::vector<List> to_t, to_j;
    for (int t = 0; t < 2 * T; ++t) to_t.emplace_back(n), to_j.emplace_back(n);
    std::vector<pd::WithinPairs> lt, lj;
    for (int t = 0; t < 2 * T; ++t) lt.push_back(to_t[t].pairs()), lj.push_back(to_j[t].pairs());
    pd::Targets<T> tg;
    for (int t = 0; t < T; ++t) {
        tg.x[t] = xt[t];
        tg.q[t] = qt[t];
        tg.d2[t] = global ? d2t[0] : d2t[t];
        tg.to_target[t] = &lt[t];
        tg.to_source[t] = global ? nullptr : &lj[t];
    }
    pd::add_green_mutual<T>(p.x.data(), p.y.data(), p.z.data(), p.q.data(), p.d2.data(), n, tg, w.data(), g0.data(),
                            g1.data(), g2.data(), how);
    double mag_w = 0, mag_g = 0;
    for (int t = 0; t < T; ++t) {
        double phi = 0;
        std::array<double, 3> e{};
        pd::add_green_mutual(p.x.data(), p.y.data(), p.z.data(), p.q.data(), p.d2.data(), n, xt[t], qt[t], tg.d2[t],
                             phi, e, w1.data(), g01.data(), g11.data(), g21.data(), lt[T + t],
                             global ? nullptr : &lj[T + t], how);
        double mag_phi = 0, mag_e = 0;
        for (std::size_t j = 0; j < n; ++j) {
            const double dx = xt[t][0] - p.x[j], dy = xt[t][1] - p.y[j], dz = xt[t][2] - p.z[j];
            const double r2 = dx * dx + dy * dy + dz * dz;
            if (r2 >= p.d2[j] && r2 > 0) mag_phi += std::abs(p.q[j]) / std::sqrt(r2), mag_e += std::abs(p.q[j]) / r2;
            if (r2 >= tg.d2[t] && r2 > 0) mag_w += std::abs(qt[t]) / std::sqrt(r2), mag_g += std::abs(qt[t]) / r2;
        }
        EXPECT_NEAR(tg.phi[t], phi, 1e-14 * mag_phi) << "target " << t;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(tg.e[t][c], e[c], 1e-14 * mag_e) << "target " << t << " component " << c;
        expect_listed(p, n, xt[t], p.d2, lt[t], "tile, to the target");
        if (!global) expect_listed(p, n, xt[t], std::vector<double>(n, tg.d2[t]), lj[t], "tile, to the sources");
    }
    for (std::size_t j = 0; j < n; ++j) {
        ASSERT_TRUE(std::isfinite(w[j]) && std::isfinite(g0[j])) << j;
        EXPECT_NEAR(w[j], w1[j], 1e-14 * mag_w) << j;
        EXPECT_NEAR(g0[j], g01[j], 1e-14 * mag_g) << j;
        EXPECT_NEAR(g1[j], g11[j], 1e-14 * mag_g) << j;
        EXPECT_NEAR(g2[j], g21[j], 1e-14 * mag_g) << j;
    }
}

TEST(GreenPass, TileIsEachTargetsPass) {
    for (const bool global : {false, true})
        for (const InverseSqrt how : {InverseSqrt::refine, InverseSqrt::divide}) {
            tile_is_each_targets_pass<1>(global, how);
            tile_is_each_targets_pass<4>(global, how);
        }
}

// A pass over n = 0 sources (a leaf's last target in its own leaf's pass)
// adds nothing and lists nothing.
TEST(GreenPass, EmptyPassAddsNothing) {
    const std::array<double, 3> xt{0.25, -0.5, 2.0};
    double phi = 1.5;
    std::array<double, 3> e{1.0, 2.0, 3.0};
    double none = 0;
    unsigned at = 0;
    pd::WithinPairs t{&at, &none}, j{&at, &none};
    pd::add_green(nullptr, nullptr, nullptr, nullptr, nullptr, 0, xt, phi, e, t);
    pd::add_green_mutual(nullptr, nullptr, nullptr, nullptr, nullptr, 0, xt, 1.0, 1.0, phi, e, nullptr, nullptr,
                         nullptr, nullptr, t, &j);
    EXPECT_EQ(phi, 1.5);
    EXPECT_EQ(e, (std::array<double, 3>{1.0, 2.0, 3.0}));
    EXPECT_EQ(t.size + j.size, 0u);
}

}  // namespace
