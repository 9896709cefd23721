// Schoenberg's B-splines through the runtime, against an identity they obey
// exactly: the translates of M_n by the integers sum to one (partition of
// unity, Schoenberg 1946; de Boor, "A Practical Guide to Splines", IX (37)),
//   sum_j M_n(x - j) = 1,   sum_j M_n'(x - j) = 0   for every real x.
// mollify's kernels have support 1 and unit mass, so with h = n/2 (M_n's
// support radius in units of the spacing) W_h(r) = M_n(r) in 1D: the
// cubic (n = 4, h = 2), quartic (n = 5, h = 5/2) and quintic spline (n = 6,
// h = 3). The identity involves no number printed anywhere: a wrong
// coefficient, piece boundary or normalisation in the emitted tables breaks
// it. No GMP here: the run-time library and the tables a user links.
#include <mollify/detail/double_double.hpp>
#include <mollify/kernel.hpp>
#include <mollify/static_kernel.hpp>
#include <mollify/tables/classic/cubic_spline_D1.hpp>
#include <mollify/tables/classic/quartic_spline_D1.hpp>
#include <mollify/tables/classic/quintic_spline_D1.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace {

using mollify::Precision;
using mollify::QuantityId;

double ulp(double x) {
    const double a = std::abs(x);
    return std::nextafter(a, std::numeric_limits<double>::infinity()) - a;
}

// sum - target with the sum's own roundings kept (each addition's error by
// two_sum, added up): its error, ~2^-106, is far below the bound below.
struct CompensatedSum {
    double sum = 0, compensation = 0;
    void add(double x) {
        const mollify::detail::DoubleDouble s = mollify::detail::two_sum(sum, x);
        sum = s.hi;
        compensation += s.lo;
    }
    double minus(double target) const { return (sum - target) + compensation; }
};

// f(r, h) is W_h(r) or W_h'(r) of the spline of order n.
using Radial = std::function<double(double, double)>;

// The points x: a grid of 2^-12 on [0, 1), and the hard cases: x at 0 and
// at the knots (the half-integers for odd n), 2^-50 either side of them, and
// within 2^-40 of 0 and 1 (points at the support edge). All multiples of
// 2^-50 in [0, 1), so every x - j (|j| <= 4) is exact.
std::vector<double> points() {
    std::vector<double> x;
    for (int k = 0; k < 4096; ++k) x.push_back(k * 0x1p-12);
    for (double e : {0x1p-50, 0x1p-40, 0x1p-30, 0x1p-20}) x.push_back(e), x.push_back(1 - e), x.push_back(0.5 - e), x.push_back(0.5 + e);
    return x;
}

struct Deviation {
    double worst_ratio = 0;  // largest |sum - exact| / bound over the points
    double at = 0;
};

// Largest |sum_j f(|x - j|) sign^odd - exact| over the points, in units of
// the bound sum_j ulps * ulp(f_j): each term within `ulps` of its exact
// value, the sum exact (CompensatedSum) and every x - j exact.
Deviation deviation(const Radial& f, double h, bool odd, double exact, double ulps) {
    Deviation d;
    const int reach = static_cast<int>(std::ceil(h)) + 1;
    for (const double x : points()) {
        CompensatedSum s;
        double bound = 0;
        for (int j = -reach; j <= reach; ++j) {
            const double t = x - j;
            double v = f(std::abs(t), h);
            if (odd && t < 0) v = -v;
            s.add(v);
            bound += ulps * ulp(v);
        }
        const double dev = std::abs(s.minus(exact));
        const double ratio = bound > 0 ? dev / bound : (dev == 0 ? 0 : std::numeric_limits<double>::infinity());
        if (ratio > d.worst_ratio) d = {ratio, x};
    }
    return d;
}

struct Spline {
    const char* spec;
    double h;  // n/2
};
constexpr Spline splines[] = {{"cubic-spline", 2.0}, {"quartic-spline", 2.5}, {"quintic-spline", 3.0}};

// Precision::accurate's contract is 0.51 ulp a value (README "Runtime accuracy").
TEST(PartitionOfUnity, AccurateValuesSumToOne) {
    for (const Spline& s : splines) {
        const mollify::Kernel k = mollify::kernel(s.spec, 1);
        const Deviation d = deviation([&](double r, double h) { return k.value(r, h); }, s.h, false, 1.0, 0.51);
        EXPECT_LE(d.worst_ratio, 1.0) << s.spec << ": at x = " << d.at;
        const Deviation g = deviation([&](double r, double h) { return k(QuantityId::dr, r, h); }, s.h, true, 0.0, 0.51);
        EXPECT_LE(g.worst_ratio, 1.0) << s.spec << " (derivative): at x = " << g.at;
    }
}

// Precision::fast: within 32 ulps a value (its measured worst is 24.9,
// README "Runtime accuracy").
TEST(PartitionOfUnity, FastValuesSumToOne) {
    for (const Spline& s : splines) {
        const mollify::Kernel k = mollify::kernel(s.spec, 1, Precision::fast);
        const Deviation d = deviation([&](double r, double h) { return k.value(r, h); }, s.h, false, 1.0, 32);
        EXPECT_LE(d.worst_ratio, 1.0) << s.spec << ": at x = " << d.at;
    }
}

// The compile-time form, from the same tables.
template <const mollify::table::Kernel& K>
void expect_static_sum(double h) {
    using W = mollify::StaticKernel<K>;
    const Deviation d = deviation(
        [](double r, double hh) { return W::template radial<QuantityId::value>(r, W::smoothing(hh)); }, h, false, 1.0,
        0.51);
    EXPECT_LE(d.worst_ratio, 1.0) << K.spec << ": at x = " << d.at;
}

TEST(PartitionOfUnity, StaticKernelValuesSumToOne) {
    expect_static_sum<mollify::tables::cubic_spline_D1>(2.0);
    expect_static_sum<mollify::tables::quartic_spline_D1>(2.5);
    expect_static_sum<mollify::tables::quintic_spline_D1>(3.0);
}

// The identity tells the splines apart (the quartic spread to the quintic's
// h misses it by far more than the bound), and it sees a normalisation off
// by 2^-48 of itself (~16-32 ulps of the values) at five times the bound.
// (A spacing off by eps does not show: the sum of the translates of M_n is
// then 1 + O(eps^n) by Poisson summation, M_n's transform sinc^n.)
TEST(PartitionOfUnity, TheIdentityCanFail) {
    const mollify::Kernel quartic = mollify::kernel("quartic-spline", 1);
    EXPECT_GT(deviation([&](double r, double h) { return quartic.value(r, h); }, 3.0, false, 1.0, 0.51).worst_ratio, 1e3);
    const mollify::Kernel quintic = mollify::kernel("quintic-spline", 1);
    const double off = 1 + 0x1p-48;
    EXPECT_GT(deviation([&](double r, double h) { return quintic.value(r, h) * off; }, 3.0, false, 1.0, 0.51).worst_ratio,
              5);
}

}  // namespace
