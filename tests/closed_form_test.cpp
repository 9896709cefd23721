// The closed forms' calculus: every antiderivative rule differentiates back
// to its integrand exactly, definite integrals agree with independent Wallis
// formulas, and the limits at r = 0 and r = 1 match the series/values of
// the basis functions.
#include "closed_form.hpp"
#include "error.hpp"
#include "radial.hpp"

#include <gtest/gtest.h>

using namespace mollify::gen;

namespace {

ClosedForm monomial(int n, const TermKey& k) { return ClosedForm(Laurent::monomial(Q(1), n), k); }

const TermKey one{Basis::one, 0, Atom{}}, S{Basis::sqrt_power, 1, Atom{}}, S_inv{Basis::sqrt_power, -1, Atom{}},
    L{Basis::arcsech, 0, Atom{}}, A{Basis::arcsin, 0, Atom{}}, LOG{Basis::log, 0, Atom{}};

// int_0^1 r^n S dr = (n-1)/(n+2) * previous (Wallis), I_0 = pi/4, I_1 = 1/3.
Exact wallis_sqrt(int n) {
    if (n == 0) return Exact::pi_power(Q(1, 4), 1);
    if (n == 1) return Exact(Q(1, 3));
    return wallis_sqrt(n - 2) * ratio(n - 1, n + 2);
}
// int_0^1 r^n / S dr = (n-1)/n * previous, K_0 = pi/2, K_1 = 1.
Exact wallis_inverse_sqrt(int n) {
    if (n == 0) return Exact::pi_power(Q(1, 2), 1);
    if (n == 1) return Exact(Q(1));
    return wallis_inverse_sqrt(n - 2) * ratio(n - 1, n);
}

}  // namespace

TEST(ClosedForm, AntiderivativesDifferentiateBack) {
    for (const TermKey& k : {one, S, S_inv, L, A, LOG})
        for (int n = -6; n <= 12; ++n) {
            const bool outside = (n == -1 && (k.basis == Basis::arcsech || k.basis == Basis::arcsin ||
                                               k.basis == Basis::log));
            const ClosedForm f = monomial(n, k);
            if (outside) {
                EXPECT_THROW(f.antiderivative(), Error);
                continue;
            }
            ClosedForm back = f.antiderivative().derivative();
            back.canonicalise();
            ClosedForm want = f;
            want.canonicalise();
            EXPECT_TRUE(back == want) << "basis " << static_cast<int>(k.basis) << " s^" << k.s_power << " n=" << n;
        }
}

TEST(ClosedForm, DefiniteIntegralsMatchWallis) {
    for (int n = 0; n <= 14; ++n) {
        EXPECT_EQ(integral(monomial(n, S), Q(0), Q(1)), wallis_sqrt(n)) << n;
        EXPECT_EQ(integral(monomial(n, S_inv), Q(0), Q(1)), wallis_inverse_sqrt(n)) << n;
        // int_0^1 r^n L = [r^(n+1) L/(n+1)]_0^1 + 1/(n+1) int_0^1 r^n/S, and L(1) = 0.
        EXPECT_EQ(integral(monomial(n, L), Q(0), Q(1)), wallis_inverse_sqrt(n) * ratio(1, n + 1)) << n;
        // int_0^1 r^n arcsin r = pi/(2(n+1)) - 1/(n+1) int_0^1 r^(n+1)/S.
        EXPECT_EQ(integral(monomial(n, A), Q(0), Q(1)),
                  Exact::pi_power(ratio(1, 2 * (n + 1)), 1) - wallis_inverse_sqrt(n + 1) * ratio(1, n + 1))
            << n;
    }
}

TEST(ClosedForm, LimitsAtTheEndpoints) {
    // S/r - 1/r -> 0, arcsin(r)/r -> 1, arcsech(r) + log r -> log 2 at r = 0.
    EXPECT_EQ(value_at(monomial(-1, S) - monomial(-1, one), Q(0)), Exact(Q(0)));
    EXPECT_EQ(value_at(monomial(-1, A), Q(0)), Exact(Q(1)));
    EXPECT_EQ(value_at(monomial(0, L) + monomial(0, LOG), Q(0)), Exact::log_of(Q(2)));
    EXPECT_THROW(value_at(monomial(0, L), Q(0)), Error);      // log(2/r) is singular
    EXPECT_THROW(value_at(monomial(-1, S), Q(0)), Error);     // 1/r
    EXPECT_EQ(value_at(monomial(3, A), Q(1)), Exact::pi_power(Q(1, 2), 1));
    EXPECT_EQ(value_at(monomial(3, S) + monomial(2, L), Q(1)), Exact(Q(0)));
    EXPECT_THROW(value_at(monomial(0, S_inv), Q(1)), Error);  // 1/S blows up at 1
    EXPECT_THROW(value_at(monomial(0, S), Q(1, 2)), Error);   // sqrt(3/4) is irrational
}

TEST(ClosedForm, CanonicalFormsCancelRemovableSingularities) {
    // (1 - r^2) / S = S: the S^-1 term disappears.
    const Laurent u = Laurent(Q(1)) - Laurent::monomial(Q(1), 2);
    const ClosedForm f(u, S_inv);
    EXPECT_TRUE(f == monomial(0, S));
    // S^3 = (1 - r^2) S.
    EXPECT_TRUE(ClosedForm(Laurent(Q(1)), TermKey{Basis::sqrt_power, 3, Atom{}}) == ClosedForm(u, S));
}

// The Laurent algebra's two shortcuts that the emission's check relies on
// (emit_checks.cpp): (a + b r)^n by its binomial coefficients equals n
// products of (a + b r), and times_r_minus(a) equals the product with
// r - a, for polynomials with negative powers and for a = 0.
TEST(Laurent, BinomialPowerAndTimesRMinusAreTheProducts) {
    const Q a(-3, 7), b(5, 2);
    Laurent power(Q(1));
    for (int n = 0; n <= 12; ++n) {
        EXPECT_EQ(Laurent::binomial_power(a, b, n), power) << "n = " << n;
        power = power * Laurent::binomial_power(a, b, 1);
    }
    const Laurent p = Laurent::monomial(Q(2), -2) + Laurent::monomial(Q(-1, 3), 0) + Laurent::monomial(Q(7, 5), 3);
    for (const Q& c : {Q(0), Q(1, 2), Q(-11, 4)}) {
        Laurent q = p;
        q.times_r_minus(c);
        EXPECT_EQ(q, p * Laurent::binomial_power(-c, Q(1), 1)) << "c = " << short_string(c);
    }
    Laurent zero;
    EXPECT_TRUE(zero.times_r_minus(Q(3)).is_zero());
}
