// The runtime's double-double arithmetic (include/mollify/detail/
// double_double.hpp) against exact rationals (GMP): every product, square,
// power and last rounding Precision::accurate is built from, on random and
// hard operands, within the bound its error analysis gives. Built twice
// (tests/CMakeLists.txt): for generic x86-64 (Dekker's products by
// Veltkamp's split) and for x86-64-v3 (FMA).
#include "number.hpp"

#include <mollify/detail/double_double.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

using mollify::detail::DoubleDouble;
using mollify::gen::Q;

namespace {

Q exact(const DoubleDouble& x) { return Q(x.hi) + Q(x.lo); }

// |got - want| / |want| as a double (want != 0).
double relative_error(const Q& got, const Q& want) {
    Q d = (got - want) / want;
    if (d < 0) d = -d;
    return static_cast<double>(d);
}

// A normalised double-double: hi with a full significand, |lo| <= ulp(hi)/2,
// and the hard shapes: hi a power of two (ulp halves below it), hi one ulp
// below one, lo at +-ulp(hi)/2, lo 0.
std::vector<DoubleDouble> operands() {
    std::mt19937_64 rng(20261207);
    std::uniform_real_distribution<double> unit(0.5, 1.0), half(-0.5, 0.5);
    std::uniform_int_distribution<int> exponent(-60, 60);
    std::vector<DoubleDouble> out;
    for (int i = 0; i < 4000; ++i) {
        const double hi = std::ldexp(unit(rng), exponent(rng)) * (i % 3 == 0 ? -1 : 1);
        const double ulp = std::nextafter(std::fabs(hi), INFINITY) - std::fabs(hi);
        double lo = half(rng) * ulp;
        if (i % 7 == 0) lo = 0.5 * ulp;
        if (i % 11 == 0) lo = -0.5 * ulp;
        if (i % 13 == 0) lo = 0;
        out.push_back({hi, lo});
    }
    for (double hi : {1.0, 0.5, 0x1p-30, std::nextafter(1.0, 0.0), 0x1.fffffffffffffp-1, 0x1.0000000000001p0, 0.7}) {
        const double ulp = std::nextafter(hi, INFINITY) - hi;
        for (double lo : {0.0, 0.5 * ulp, -0.25 * ulp, 0.4999 * ulp}) out.push_back({hi, lo});
    }
    return out;
}

// square(x) and x * x: the exact hi^2 (two_product) plus the cross term
// 2 hi lo and the product's error rounded once (twice for x * x), lo^2
// dropped: <= 2^-53 (2^-52 + 2^-53) + 2^-106 < 2^-103.4 of x^2.
TEST(DoubleDouble, SquaresAndProductsAreRightTo2ToTheMinus103) {
    const std::vector<DoubleDouble> xs = operands();
    double worst_square = 0, worst_product = 0;
    for (std::size_t i = 0; i < xs.size(); ++i) {
        const DoubleDouble& x = xs[i];
        const DoubleDouble& y = xs[(i * 7919 + 1) % xs.size()];
        const Q ex = exact(x), ey = exact(y);
        const double es = relative_error(exact(mollify::detail::square(x)), ex * ex);
        const double ep = relative_error(exact(x * y), ex * ey);
        const double exx = relative_error(exact(x * x), ex * ex);
        worst_square = std::max(worst_square, es);
        worst_product = std::max({worst_product, ep, exx});
        ASSERT_LE(es, 0x1p-103) << "square of " << x.hi << " + " << x.lo;
        ASSERT_LE(ep, 0x1p-103) << x.hi << " + " << x.lo << " times " << y.hi << " + " << y.lo;
        ASSERT_LE(exx, 0x1p-103) << x.hi << " + " << x.lo << " squared as a product";
    }
    std::printf("worst relative error: square %.3g (2^%.2f), product %.3g (2^%.2f)\n", worst_square,
                std::log2(worst_square), worst_product, std::log2(worst_product));
    // The bound is not loose: the worst case is within 2^-2 of it (a square
    // that dropped its cross term would be ~2^-53 off and fail above).
    EXPECT_GE(worst_square, 0x1p-107);
}

// ipow<N> by its tree of squares and products: x^(a+b) = x^a x^b adds
// one operation's error to those of its factors, so the relative errors
// add up to N - 1 of them. Each is ~2^-53 (|lo_a/hi_a| + |lo_b/hi_b|) +
// |lo_a lo_b / hi_a hi_b|, and the low parts are never renormalised: a
// square doubles lo/hi and adds ~2^-53, so at N = 16 they reach ~2^-49 of
// their high part and an operation's error ~2^-102 (measured: the worst
// error over N - 1, N <= 16, 2^-101.7 on the FMA build). Bound: 2^-101 an
// operation, still 2^-40 below what Precision::accurate leaves them
// (2^-59.6 for every error before the last rounding).
double worst_power_error = 0;
template <int N>
void check_power(const std::vector<DoubleDouble>& xs) {
    for (const DoubleDouble& x0 : xs) {
        // keep |x|^N inside the doubles (|x| in [1/2, 1) here, its sign kept)
        const DoubleDouble x{std::ldexp(x0.hi, -std::ilogb(x0.hi) - 1), std::ldexp(x0.lo, -std::ilogb(x0.hi) - 1)};
        Q want(1);
        for (int k = 0; k < N; ++k) want *= exact(x);
        const double e = relative_error(exact(mollify::detail::ipow<N>(x)), want);
        worst_power_error = std::max(worst_power_error, e / (N - 1));
        EXPECT_LE(e, (N - 1) * 0x1p-101) << "x^" << N << " at " << x.hi << " + " << x.lo;
    }
}

TEST(DoubleDouble, PowersAreRightToTheirNumberOfProducts) {
    const std::vector<DoubleDouble> xs = operands();
    check_power<2>(xs);
    check_power<3>(xs);
    check_power<4>(xs);
    check_power<5>(xs);
    check_power<6>(xs);
    check_power<7>(xs);
    check_power<8>(xs);
    check_power<11>(xs);
    check_power<14>(xs);
    check_power<16>(xs);
    std::printf("worst relative error of x^N over N - 1: 2^%.2f\n", std::log2(worst_power_error));
}

// x * y rounded once (the last product of an evaluation): within half an
// ulp of the exact x y, but for the cross terms' one rounding and lo lo
// dropped (~2^-103 of x y, 2^-50 of an ulp).
TEST(DoubleDouble, LastProductIsHalfAnUlpOfTheExactProduct) {
    const std::vector<DoubleDouble> xs = operands();
    for (std::size_t i = 0; i < xs.size(); ++i) {
        const DoubleDouble& x = xs[i];
        const DoubleDouble& y = xs[(i * 104729 + 3) % xs.size()];
        const Q want = exact(x) * exact(y);
        const double got = mollify::detail::rounded_product_bounded(x, y);
        const double ulp = std::nextafter(std::fabs(got), INFINITY) - std::fabs(got);
        Q off = (Q(got) - want) / Q(ulp);
        if (off < 0) off = -off;
        ASSERT_LE(static_cast<double>(off), 0.5 + 0x1p-45) << x.hi << " + " << x.lo << " times " << y.hi << " + " << y.lo;
    }
}

}  // namespace
