// Double-double numbers x = hi + lo (|lo| <= ulp(hi)/2, about 106 bits) for
// the few places where the runtime must not round: the edge factors
// (1 - q)^n, (1 - q^2)^M and S^m = (1 - q^2)^(m/2) of the factored kernel
// forms, which multiply the relative error of their base by n (up to 14
// for Wendland k = l = 4). Products follow Dekker (1971) and Ogita, Rump &
// Oishi, "Accurate sum and dot product" (SIAM J. Sci. Comput. 26, 2005):
// the rounding error of a*b is itself a double, found by one fused
// multiply-add where the target has one and by Veltkamp's splitting where
// it does not. Only as much is computed as the edge factors need: the low
// parts are carried to first order (the terms lo*lo, ~2^-106, are dropped).
#pragma once

#include <mollify/detail/isa.hpp>

#include <bit>
#include <cmath>

namespace mollify::detail {
inline namespace MOLLIFY_ISA {

struct DoubleDouble {
    double hi, lo;
};

// a + b = s + t exactly, for |a| >= |b| (Dekker's fast two-sum). The
// error as (a - s) + b, not b - (s - a): the same exact operands, one
// rounding, the same value (an error of 0 is +0 where b is -0, which no
// sum of it can tell), but where b is a negation (h - r, a_j - q) the
// compiler folds it into the subtraction instead of flipping b's sign first
// (one operation fewer a point in the accurate pair loops).
inline DoubleDouble fast_two_sum(double a, double b) {
    const double s = a + b;
    return {s, (a - s) + b};
}

// a + b = s + t exactly, for any a, b (Knuth's two-sum).
inline DoubleDouble two_sum(double a, double b) {
    const double s = a + b;
    const double bb = s - a;
    return {s, (a - (s - bb)) + (b - bb)};
}

// a + x for 0 <= x.hi <= |a| (the factors 1 + q and a_j + q).
inline DoubleDouble plus(double a, const DoubleDouble& x) {
    const DoubleDouble s = fast_two_sum(a, x.hi);
    return {s.hi, s.lo + x.lo};
}

// a + b to double-double accuracy (Knuth's two-sum of the high parts, the
// low parts added to its error); left unnormalised, so an overflowed sum
// stays +-inf in hi for rounded().
inline DoubleDouble operator+(const DoubleDouble& a, const DoubleDouble& b) {
    const DoubleDouble s = two_sum(a.hi, b.hi);
    return {s.hi, s.lo + (a.lo + b.lo)};
}

#if !MOLLIFY_HAS_FMA
// Veltkamp's split of a into a 26-bit head and the rest, a = head + (a - head)
// exactly. The product 2^27 a overflows for |a| > 2^996 (the runtime meets
// such numbers: h^-p for tiny h, q^-3 near a cusp), so those are split at
// 2^-40 of their size and scaled back, exactly.
inline double split_head(double a) {
    constexpr double splitter = 134217729.0;  // 2^27 + 1
    const bool big = std::abs(a) > 0x1p995;
    const double down = big ? 0x1p-40 : 1.0, up = big ? 0x1p40 : 1.0;
    const double x = a * down, c = splitter * x;
    return (c - (c - x)) * up;
}
#endif

// a * b = p + e exactly (barring underflow of e, and overflow of p).
inline DoubleDouble two_product(double a, double b) {
    const double p = a * b;
#if MOLLIFY_HAS_FMA
    return {p, std::fma(a, b, -p)};
#else
    // Dekker's exact error of the product from the split factors (without
    // an FMA: a library fma would be a slow call).
    const double a1 = split_head(a), a2 = a - a1;
    const double b1 = split_head(b), b2 = b - b1;
    return {p, ((a1 * b1 - p) + a1 * b2 + a2 * b1) + a2 * b2};
#endif
}

// The cross terms fused into the product's error (two FMAs where the
// target has them, one rounding fewer than a product and a sum). a.lo
// enters last: in a power chain a is the later factor (ipow's x^(2^k), an
// edge factor times its polynomial), so the low part waits on a.lo through
// one FMA, not two (Wendland C4's accurate pairs on Zen 5: with square()
// below, 2.49-2.54 -> 2.32-2.35 time-stamp ticks a point: README, "Double-
// double squares and the order of a product's cross terms").
inline DoubleDouble operator*(const DoubleDouble& a, const DoubleDouble& b) {
    const DoubleDouble p = two_product(a.hi, b.hi);
    return {p.hi, mul_add(a.lo, b.hi, mul_add(a.hi, b.lo, p.lo))};
}

inline DoubleDouble operator*(const DoubleDouble& a, double b) {
    const DoubleDouble p = two_product(a.hi, b);
    return {p.hi, mul_add(a.lo, b, p.lo)};
}

// x^2, its cross terms as one product 2 x.hi x.lo (2 x.hi exact, a sum on
// the adders where x * x takes a second FMA): the low part waits on x.lo
// through one FMA instead of two. Not x * x's bits (one rounding fewer).
inline DoubleDouble square(const DoubleDouble& x) {
    const DoubleDouble p = two_product(x.hi, x.hi);
    return {p.hi, mul_add(x.hi + x.hi, x.lo, p.lo)};
}

// 1/x to double-double accuracy: one Newton step on the exact residual.
inline DoubleDouble reciprocal(const DoubleDouble& x) {
    const double y = 1 / x.hi;
    const DoubleDouble yx = two_product(y, x.hi);
    return {y, ((1 - yx.hi) - yx.lo - y * x.lo) * y};
}

// sqrt(x) to double-double accuracy: one Newton step on the exact residual
// x - s^2 (Karp & Markstein).
// sqrt(0) = 0 exactly (the support edge of S = sqrt(1 - q^2)).
inline DoubleDouble sqrt(const DoubleDouble& x) {
    const double s = std::sqrt(x.hi);
    const DoubleDouble ss = two_product(s, s);
    const double lo = ((x.hi - ss.hi) - ss.lo + x.lo) / (s > 0 ? 2 * s : 1.0);
    return {s, s > 0 ? lo : 0.0};
}

// x^N as x^(2^k) x^(N - 2^k), 2^k <= N < 2^(k+1), the squares x^(2^j)
// by repeated squaring (N > 0; N < 0 through the reciprocal): a kernel's
// W and W'/r, edge powers n and n - 1, then share their squares (x^6 and
// x^5: four products, not five as with (x^3)^2 and (x^2)^2 x). The
// run-time form walks the same tree (src/evaluator.cpp: ipow_rt). Forced
// inline: GCC left ipow<4> a call in the run-time form's fused combination
// loop, which then did not vectorise (8x slower).
template <int N>
MOLLIFY_INLINE DoubleDouble ipow(const DoubleDouble& x) {
    if constexpr (N < 0) {
        return ipow<-N>(reciprocal(x));
    } else if constexpr (N == 0) {
        return {1.0, 0.0};
    } else if constexpr (N == 1) {
        return x;
    } else {
        constexpr int top = static_cast<int>(std::bit_floor(static_cast<unsigned>(N)));
        if constexpr (N == top) {
            return square(ipow<N / 2>(x));
        } else {
            return ipow<top>(x) * ipow<N - top>(x);
        }
    }
}

// hi + lo rounded; where hi overflowed (lo is then inf - inf), hi itself:
// +-inf, never NaN.
inline double rounded(const DoubleDouble& x) {
    // select, not ?: GCC keeps the ternary a branch, and a branch in the
    // body stops a batch loop's vectorisation (measured: W of Wendland C4
    // accurate 15.5 against 3.7 ns per point).
    return select(std::abs(x.hi) <= 0x1.fffffffffffffp+1023, x.hi + x.lo, x.hi);
}

// x * y rounded to double (the last product of an evaluation, by its scale
// h^p), unguarded: with an FMA, x.hi y.hi + (x.lo y.hi + x.hi y.lo) in one
// rounding (x.hi y.lo first: the scale y is known, x.lo arrives last), the
// exact product x.hi y.hi inside it: x y (1 + d) rounded once,
// |d| <= ~2^-103 (rounded(x * y) rounds twice). For callers that know |x| <=
// 2^110 and finite (table::bounded_term: a polynomial term on the support,
// at most 1024 of them) and |y| <= 2^960 (Smoothing's scale_range times a
// split content's 2^60): then the cross terms are below 2^1020 and the FMA
// itself overflows to +-inf of the right sign.
inline double rounded_product_bounded(const DoubleDouble& x, const DoubleDouble& y) {
#if MOLLIFY_HAS_FMA
    return std::fma(x.hi, y.hi, std::fma(x.lo, y.hi, x.hi * y.lo));
#else
    return rounded(x * y);
#endif
}

// The same for any x: where x.hi y.hi overflows, itself (+-inf, as
// rounded(): there the cross terms may overflow too, to either sign). The
// same bits as rounded_product_bounded wherever both apply.
inline double rounded_product(const DoubleDouble& x, const DoubleDouble& y) {
#if MOLLIFY_HAS_FMA
    const double p = x.hi * y.hi;
    return select(std::abs(p) <= 0x1.fffffffffffffp+1023, rounded_product_bounded(x, y), p);
#else
    return rounded(x * y);
#endif
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::detail
