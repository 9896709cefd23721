// The treecode's near-field passes on AVX-512 (include/mollify/poisson/pair_sum.hpp,
// detail/lanes.hpp): 1/sqrt refined from VRSQRT14PD's estimate against
// long double, its hard cases (the lanes it leaves to the division), the
// two Green's passes with the refined 1/r against the same passes with the
// division, and the within-support search's compressed compaction against
// its definition. Built for x86-64-v4 where the host has AVX-512
// (tests/CMakeLists.txt: poisson_free_v4_test).
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

// The mutual pass both ways: the target's phi and E and every source's
// sums agree to a few roundings of their terms' magnitudes (each 1/r within
// 2 ulp, 1/r^3 within ~6 ulp: 1e-15 relative per term, against ~2^-14 for
// an unrefined estimate), and nothing is NaN (coincident pairs are masked
// out as with the division).
TEST(GreenPass, MutualRefinedAgreesWithDivision) {
    const std::array<double, 3> xt{0.25, -0.5, 2.0};
    for (const std::size_t n : {std::size_t{5}, std::size_t{203}, std::size_t{4099}}) {
        const Pass p = sources(n, 7 + static_cast<unsigned>(n));
        struct Out {
            double phi = 0;
            std::array<double, 3> e{};
            std::vector<double> w, g0, g1, g2;
        };
        auto run = [&](InverseSqrt how) {
            Out o;
            o.w.assign(n, 0.0), o.g0.assign(n, 0.0), o.g1.assign(n, 0.0), o.g2.assign(n, 0.0);
            pd::add_green_mutual(p.x.data(), p.y.data(), p.z.data(), p.q.data(), p.d2.data(), n, xt, 0.75, 2e-4, o.phi,
                                 o.e, o.w.data(), o.g0.data(), o.g1.data(), o.g2.data(), how);
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
// from the division's block, as before, not inf * 0.
TEST(GreenPass, OneWayRefinedAgreesWithDivision) {
    const std::array<double, 3> xt{0.25, -0.5, 2.0};
    Pass p = sources(1001, 99);
    p.x[17] = 0x1p600;
    double phi_r = 0, phi_d = 0;
    std::array<double, 3> e_r{}, e_d{};
    pd::add_green(p.x.data(), p.y.data(), p.z.data(), p.q.data(), p.d2.data(), p.x.size(), xt, phi_r, e_r,
                  InverseSqrt::refine);
    pd::add_green(p.x.data(), p.y.data(), p.z.data(), p.q.data(), p.d2.data(), p.x.size(), xt, phi_d, e_d,
                  InverseSqrt::divide);
    ASSERT_TRUE(std::isfinite(phi_r));
    double mag_phi = 0, mag_e = 0;
    for (std::size_t j = 0; j < p.x.size(); ++j) {
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

// The within-support search's compaction (detail::near_sources), eight
// sources at a time compressed into place, against the definition: the
// sources with r^2 < delta_j^2, r^2 formed as add_green forms it, in their
// order, with their r^2 bit for bit; in 2D and 3D, at block offsets that
// leave a scalar tail, per-source delta (some pairs exactly at r^2 =
// delta^2: not within) and one global delta.
template <int D>
void near_sources_are_the_definition(bool per_source) {
    std::mt19937_64 rng(31 + D + (per_source ? 1 : 0));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const std::size_t n = 613;
    std::array<std::vector<double>, D> x;
    std::vector<double> q(n, 1.0), delta;
    for (std::size_t j = 0; j < n; ++j) {
        for (int k = 0; k < D; ++k) x[k].push_back(unit(rng));
        if (per_source) delta.push_back(0.05 + 0.2 * unit(rng));
    }
    if (!per_source) delta.push_back(0.15);
    std::array<double, D> xt;
    for (int k = 0; k < D; ++k) xt[k] = 0.5;
    // A source at distance exactly 0.25 (r^2 = 1/16 exactly) with delta 0.25: r^2 = delta^2, not within.
    x[0][100] = 0.75;
    for (int k = 1; k < D; ++k) x[k][100] = 0.5;
    if (per_source) delta[100] = 0.25;
    mollify::Points<D> p;
    for (int k = 0; k < D; ++k) p[k] = x[k];
    std::vector<std::size_t> order(n);
    for (std::size_t j = 0; j < n; ++j) order[j] = j;
    const pd::SourceArrays<D> s(mollify::poisson::Sources<D>{p, q, delta}, order);
    for (const std::size_t b0 : {std::size_t{0}, std::size_t{3}, std::size_t{128}, std::size_t{500}}) {
        const std::size_t count = std::min<std::size_t>(pd::block, n - b0);
        unsigned near[pd::block + 1];
        double near_r2[pd::block];
        const std::size_t m = pd::near_sources<D>(s, xt, b0, count, near, near_r2);
        std::size_t expected = 0;
        for (std::size_t j = 0; j < count; ++j) {
            const std::size_t i = b0 + j;
            const double dx = xt[0] - s.x[0][i], dy = xt[1] - s.x[1][i];
            double r2 = std::fma(dy, dy, dx * dx);
            if constexpr (D == 3) r2 = std::fma(xt[2] - s.x[2][i], xt[2] - s.x[2][i], r2);
            if (!(r2 < s.delta[i] * s.delta[i])) continue;
            ASSERT_LT(expected, m) << "b0 " << b0 << ": source " << j << " within its support is missing";
            EXPECT_EQ(near[expected], j) << "b0 " << b0;
            EXPECT_EQ(std::bit_cast<std::uint64_t>(near_r2[expected]), std::bit_cast<std::uint64_t>(r2)) << "b0 " << b0;
            ++expected;
        }
        EXPECT_EQ(m, expected) << "b0 " << b0;
        EXPECT_GT(m, 0u) << "b0 " << b0;
    }
}

TEST(WithinSupport, NearSourcesAreTheDefinition3D) {
    near_sources_are_the_definition<3>(true);
    near_sources_are_the_definition<3>(false);
}

TEST(WithinSupport, NearSourcesAreTheDefinition2D) {
    near_sources_are_the_definition<2>(true);
    near_sources_are_the_definition<2>(false);
}

}  // namespace
