// Belley's estimators (tools/studies/studies/estimate.hpp): exactness where
// his reproducing conditions say so, convergence in h, the binary-searched
// support, compile-time = run-time kernels, bad input.
#include "studies/estimate.hpp"
#include <mollify/dynamic_kernel.hpp>
#include <mollify/static_kernel.hpp>
#include <mollify/tables/classic/box_D1.hpp>
#include <mollify/tables/classic/box_d1_D1.hpp>
#include <mollify/tables/classic/box_d2_D1.hpp>
#include <mollify/tables/classic/poly6_D1.hpp>
#include <mollify/tables/classic/poly6_D2.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/tables/wendland/k_2_D1.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace mollify;
using sph::Estimator;
using sph::Rule;
using sph::Samples;
using Poly6 = StaticKernel<tables::poly6_D1>;
using Box = StaticKernel<tables::box_D1>;
using BoxD1 = StaticKernel<tables::box_d1_D1>;
using BoxD2 = StaticKernel<tables::box_d2_D1>;
using Wendland2 = StaticKernel<tables::wendland_k_2_D1>;

// Belley's setup: n uniform random points sorted in [-2, 2].
std::vector<double> random_points(std::size_t n, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<double> x(n);
    for (double& v : x) v = -2 + 4 * (static_cast<double>(rng() >> 11) * 0x1p-53);
    std::sort(x.begin(), x.end());
    return x;
}

std::vector<double> uniform_points(std::size_t n) {  // n points, spacing 4/(n-1), on [-2, 2]
    std::vector<double> x(n);
    for (std::size_t j = 0; j < n; ++j) x[j] = -2 + 4 * static_cast<double>(j) / static_cast<double>(n - 1);
    return x;
}

template <class F>
std::vector<double> sample(const std::vector<double>& x, F f) {
    std::vector<double> v(x.size());
    for (std::size_t j = 0; j < x.size(); ++j) v[j] = f(x[j]);
    return v;
}

std::string message_of(auto&& call) {
    try {
        call();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

// The kernels are Belley's, in his scaling: k_{h,poly6} = 35/(32 h^7)
// (h^2 - x^2)^3 (his (8)) is mollify's poly6 W_h in 1D. Tolerance 4 ulp:
// both sides are a few correctly rounded operations.
TEST(Belley, Poly6IsBelleysEquation8) {
    for (double h : {0.5, 0.12, 0.01})
        for (double x : {0.0, 0.3 * h, 0.77 * h, h}) {
            const double belley = 35 / (32 * std::pow(h, 7)) * std::pow(h * h - x * x, 3);
            EXPECT_NEAR(Poly6::value(x, h), belley, 4 * 0x1p-52 * std::abs(35 / (32 * h))) << "h = " << h << ", x = " << x;
        }
}

// The delta sums reproduce what Belley's discrete reproducing conditions
// (33), (36), (37) say, on any points (random, not a grid): T_{h,delta} of a
// linear f is f, T'_{h,delta} of a linear f is f', T''_{h,delta} of a linear
// f is 0, and Simpson's Q''_{h,delta} of a quadratic is f'' (f~ = f, and
// Simpson is exact for quadratics). Only rounding remains: the sums have
// ~2h/spacing terms of size |f| ~ 10, each rounded to 1e-16 relative, then
// scaled by h^-q: tolerance 1e-12 * h^-q (a few hundred ulps of the terms).
TEST(Belley, DeltaSumsAreExactForLowDegree) {
    const std::vector<double> x = random_points(1000, 7);
    const Samples s(x);
    const std::vector<double> linear = sample(x, [](double t) { return 2 * t + 5; });
    const std::vector<double> square = sample(x, [](double t) { return t * t - 3 * t + 1; });
    for (double h : {0.5, 0.12, 0.03}) {
        const Estimator t0(Box{}, Rule::trapezoid, 0, s, h);
        const Estimator t1(BoxD1{}, Rule::trapezoid, 1, s, h);
        const Estimator t2(BoxD2{}, Rule::trapezoid, 2, s, h);
        const Estimator q2(BoxD2{}, Rule::simpson, 2, s, h);
        const Estimator q0(Box{}, Rule::simpson, 0, s, h);
        for (std::size_t i = s.first_at_or_after(-1); i < s.count_at_or_before(1); i += 7) {
            const double x0 = x[i];
            EXPECT_NEAR(t0(x0, linear), 2 * x0 + 5, 1e-12) << "h = " << h << ", x0 = " << x0;
            EXPECT_NEAR(t1(x0, linear), 2, 1e-12 / h) << "h = " << h << ", x0 = " << x0;
            EXPECT_NEAR(t2(x0, linear), 0, 1e-12 / (h * h)) << "h = " << h << ", x0 = " << x0;
            EXPECT_NEAR(q2(x0, square), 2, 1e-12 / (h * h)) << "h = " << h << ", x0 = " << x0;
            // Simpson with delta: int f~ of the quadratic x^2 is exact, so f * delta = f(x0) + h^2/3 (Belley (13)).
            EXPECT_NEAR(q0(x0, square), x0 * x0 - 3 * x0 + 1 + h * h / 3, 1e-12) << "h = " << h << ", x0 = " << x0;
        }
        // Also at a point that is not a sample (the split at x0 interpolates).
        EXPECT_NEAR(t1(0.123456, linear), 2, 1e-12 / h);
    }
}

// On a uniform grid away from the boundary the trapezoidal delta sum of a
// linear f is f to rounding (the brief's case), and the smooth-kernel
// trapezoid sum T_{h,6} of a constant is the trapezoidal rule for int k_h,
// whose error on a grid of spacing d is O(d^2 k'') plus the edge kink:
// relative 1e-4 at h/d = 50 (measured 2e-6; the bound is loose on purpose).
TEST(Belley, UniformGrid) {
    const std::vector<double> x = uniform_points(4001);  // spacing 1e-3
    const Samples s(x);
    const std::vector<double> linear = sample(x, [](double t) { return 2 * t + 5; });
    const std::vector<double> one(x.size(), 1.0);
    const Estimator t0(Box{}, Rule::trapezoid, 0, s, 0.05);
    const Estimator p0(Poly6{}, Rule::trapezoid, 0, s, 0.05);
    for (double x0 : {-1.0, -0.2345, 0.0, 0.5, 1.0}) {
        EXPECT_NEAR(t0(x0, linear) / (2 * x0 + 5), 1, 1e-14) << "x0 = " << x0;
        EXPECT_NEAR(p0(x0, one), 1, 1e-4) << "x0 = " << x0;
    }
}

// Convergence in h on a smooth function where the quadrature error is
// negligible (a fine uniform grid): the delta estimates converge as h^2
// (Belley (23), (27), (29)), so halving h divides the error by ~4; we
// assert at least 3 (the constants h^2/6 f'', h^2/12 f''', h^2/16 f'''' are
// leading terms; the next ones are O(h^4)).
TEST(Belley, ConvergenceInH) {
    const std::vector<double> x = uniform_points(40001);  // spacing 1e-4
    const Samples s(x);
    const double pi = std::numbers::pi;
    const std::vector<double> f = sample(x, [&](double t) { return std::sin(pi * t); });
    const double x0 = 0.3;
    double previous[4] = {0, 0, 0, 0};
    for (double h : {0.4, 0.2, 0.1}) {
        const double errors[4] = {
            std::abs(Estimator(Box{}, Rule::trapezoid, 0, s, h)(x0, f) - std::sin(pi * x0)),
            std::abs(Estimator(BoxD1{}, Rule::trapezoid, 1, s, h)(x0, f) - pi * std::cos(pi * x0)),
            std::abs(Estimator(BoxD2{}, Rule::trapezoid, 2, s, h)(x0, f) + pi * pi * std::sin(pi * x0)),
            std::abs(Estimator(BoxD2{}, Rule::simpson, 2, s, h)(x0, f) + pi * pi * std::sin(pi * x0)),
        };
        for (int k = 0; k < 4; ++k) {
            if (previous[k] > 0) {
                EXPECT_GT(previous[k] / errors[k], 3.0) << "estimate " << k << ", h = " << h;
            }
            previous[k] = errors[k];
        }
    }
    // The mean error over the samples in [-1, 1] (Belley's measure) falls too.
    const std::vector<double> xc = uniform_points(4001);
    const Samples sc(xc);
    const std::vector<double> fc = sample(xc, [&](double t) { return std::sin(pi * t); });
    const double coarse = sph::mean_abs_error(Estimator(Box{}, Rule::trapezoid, 0, sc, 0.2), fc, fc, -1, 1);
    const double fine = sph::mean_abs_error(Estimator(Box{}, Rule::trapezoid, 0, sc, 0.1), fc, fc, -1, 1);
    EXPECT_GT(coarse / fine, 3.0);
}

// The classic SPH sum (5.1) with a smooth kernel on a uniform grid: the
// volumes 1/rho_j make sum_j k_h(x0 - x_j)/rho_j = 1 up to the grid's
// quadrature error, so f is reproduced to O(h^2) (the kernel's second
// moment): for sin(pi x), error <= h^2/2 * pi^2 * int u^2 k (= h^2/9 for poly6) * 1.1.
TEST(Belley, ClassicSphConverges) {
    const std::vector<double> x = uniform_points(8001);
    const Samples s(x);
    const double pi = std::numbers::pi;
    const std::vector<double> f = sample(x, [&](double t) { return std::sin(pi * t); });
    for (double h : {0.2, 0.1}) {
        const Estimator c0(Poly6{}, Rule::classic, 0, s, h);
        const double x0 = 0.5;  // |f''| is largest here
        EXPECT_LE(std::abs(c0(x0, f) - 1), 1.1 * h * h / 2 * pi * pi / 9) << "h = " << h;
        const Estimator w0(Wendland2{}, Rule::classic, 0, s, h);
        EXPECT_LE(std::abs(w0(x0, f) - 1), 1.1 * h * h / 2 * pi * pi) << "h = " << h;
    }
}

// The support by binary search is exactly the brute-force set {j : |x0 -
// x_j| <= h} with the rounded differences the kernel sees, also for points
// placed at distance exactly h.
TEST(Belley, BinarySearchSupportEqualsBruteForce) {
    std::vector<double> x = random_points(500, 11);
    x[100] = x[50] + 0.25;  // exact distance h = 0.25 (representable sums kept sorted below)
    std::sort(x.begin(), x.end());
    x.erase(std::unique(x.begin(), x.end()), x.end());
    const Samples s(x);
    std::mt19937_64 rng(3);
    std::vector<double> x0s(x.begin(), x.end());
    for (int k = 0; k < 500; ++k) x0s.push_back(-2.5 + 5 * (static_cast<double>(rng() >> 11) * 0x1p-53));
    for (double h : {1.0, 0.25, 0.03, 1e-4})
        for (double x0 : x0s) {
            std::size_t lo = x.size(), hi = 0;
            for (std::size_t j = 0; j < x.size(); ++j)
                if (std::abs(x0 - x[j]) <= h) {
                    lo = std::min(lo, j);
                    hi = j + 1;
                }
            const auto [first, end] = s.within(x0, h);
            if (lo > hi) {  // none
                EXPECT_EQ(first, end) << "x0 = " << x0 << ", h = " << h;
            } else {
                EXPECT_EQ(first, lo) << "x0 = " << x0 << ", h = " << h;
                EXPECT_EQ(end, hi) << "x0 = " << x0 << ", h = " << h;
            }
        }
}

// The compile-time and the run-time kernel give the same weights, bit for
// bit (the run-time form calls the same batch code).
TEST(Belley, StaticAndDynamicKernelsAgree) {
    mollify::use_isa("generic");  // the instruction set this test is compiled for
    const Kernel dynamic(tables::poly6_D1), dynamic_box(tables::box_d2_D1);
    const std::vector<double> x = random_points(300, 5);
    const Samples s(x);
    const std::vector<double> f = sample(x, [](double t) { return std::exp(t); });
    for (Rule rule : {Rule::classic, Rule::trapezoid, Rule::simpson})
        for (int q = 0; q < 3; ++q) {
            const Estimator a(Poly6{}, rule, q, s, 0.2);
            const Estimator b(dynamic, rule, q, s, 0.2);
            for (double x0 : {-0.5, 0.0, 0.777}) EXPECT_EQ(a(x0, f), b(x0, f)) << sph::rule_name(rule) << " q = " << q;
        }
    const Estimator a(BoxD2{}, Rule::simpson, 2, s, 0.2);
    const Estimator b(dynamic_box, Rule::simpson, 2, s, 0.2);
    EXPECT_EQ(a(0.1, f), b(0.1, f));
}

TEST(Belley, BadInputIsAnErrorNamingTheValue) {
    const std::vector<double> x = random_points(100, 1);
    const Samples s(x);
    const std::vector<double> f(x.size(), 1.0);
    EXPECT_NE(message_of([&] { Estimator(Poly6{}, Rule::classic, 0, s, 0.0); }).find("h = 0"), std::string::npos);
    EXPECT_NE(message_of([&] { Estimator(Poly6{}, Rule::classic, 0, s, -0.5); }).find("h = -0.5"), std::string::npos);
    EXPECT_NE(message_of([&] { Estimator(Poly6{}, Rule::trapezoid, 0, s, NAN); }).find("h = nan"), std::string::npos);

    std::vector<double> unsorted = x;
    std::swap(unsorted[10], unsorted[11]);
    const std::string m = message_of([&] { Samples bad(unsorted); });
    EXPECT_NE(m.find("not strictly increasing"), std::string::npos) << m;
    EXPECT_NE(m.find("x[10] = " + mollify::detail::show(unsorted[10])), std::string::npos) << m;

    std::vector<double> with_nan = x;
    with_nan[4] = NAN;
    EXPECT_NE(message_of([&] { Samples bad(with_nan); }).find("x[4] = nan"), std::string::npos);
    std::vector<double> repeated = x;
    repeated[21] = repeated[20];
    EXPECT_NE(message_of([&] { Samples bad(repeated); }).find("x[20]"), std::string::npos);
    EXPECT_NE(message_of([&] { Samples bad(std::vector<double>{0.0, 1.0}); }).find("got 2"), std::string::npos);

    const Estimator e(Box{}, Rule::trapezoid, 0, s, 0.3);
    std::vector<double> f_nan = f;
    const std::size_t j = s.first_at_or_after(0.0);
    f_nan[j] = NAN;
    EXPECT_NE(message_of([&] { (void)e(x[j], f_nan); }).find("f[" + std::to_string(j) + "] = nan"), std::string::npos);
    EXPECT_NE(message_of([&] { (void)e(NAN, f); }).find("x0 = nan"), std::string::npos);
    EXPECT_NE(message_of([&] { (void)e(0.0, std::vector<double>(5, 1.0)); }).find("5 sample values"), std::string::npos);

    // Kernel and estimate that do not fit: named.
    EXPECT_NE(message_of([&] { Estimator(BoxD1{}, Rule::trapezoid, 2, s, 0.3); }).find("box-d1 estimates derivative 1"),
              std::string::npos);
    EXPECT_NE(message_of([&] { Estimator(Box{}, Rule::classic, 0, s, 0.3); }).find("box"), std::string::npos);
    EXPECT_NE(message_of([&] { Estimator(Poly6{}, Rule::trapezoid, 3, s, 0.3); }).find("derivative order 3"),
              std::string::npos);
    EXPECT_NE(message_of([&] { Estimator(StaticKernel<tables::poly6_D2>{}, Rule::trapezoid, 0, s, 0.3); }).find("D = 2"),
              std::string::npos);
    EXPECT_NE(message_of([&] { (void)sph::rule("midpoint"); }).find("'midpoint'"), std::string::npos);
}

}  // namespace
