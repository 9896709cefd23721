// The series at r = 0 that replace the missing Wendland closed forms on
// [0, r0) (generator/series.hpp): the basis series match their textbook
// coefficients, and for every missing Wendland quantity of the catalogue the
// truncated series agrees with a high-precision evaluation of the closed
// form, at r0 and inside, within its proven relative bound (< 2^-60), so the
// emitted tables are continuous at r0 to that bound.
#include "catalogue.hpp"
#include "kernel.hpp"
#include "quantities.hpp"
#include "sanitized.hpp"
#include "series.hpp"
#include "zeta.hpp"
#include "edge_series.hpp"

#include <gtest/gtest.h>

using namespace mollify::gen;

namespace {

const TermKey S{Basis::sqrt_power, 1, Atom{}}, S_inv{Basis::sqrt_power, -1, Atom{}}, L{Basis::arcsech, 0, Atom{}},
    A{Basis::arcsin, 0, Atom{}};

Q coefficient(const ClosedForm& f, Basis b, int n) {
    for (const auto& [k, p] : f.terms())
        if (k.basis == b && k.factor == Atom{}) return p.coefficient(n);
    return 0;
}

// |f(r) - T(r)| / |f(r)| at a rational r, with enough bits for the closed
// form's cancellation (r^-k terms: about k log2(1/r) bits).
double relative_gap(const ClosedForm& f, const ClosedForm& T, const Q& r) {
    const unsigned bits = 400 + 8 * static_cast<unsigned>(std::abs(static_cast<double>(std::log2(static_cast<double>(r)))));
    Real rr(0, bits * 30103 / 100000 + 2);
    mpfr_set_q(rr.backend().data(), r.backend().data(), MPFR_RNDN);
    const Real a = f.evaluate(rr, bits).first, b = T.evaluate(rr, bits).first;
    return static_cast<double>(abs(a - b) / abs(a));
}

}  // namespace

TEST(Series, BasisFunctionsHaveTheirTextbookCoefficients) {
    const ClosedForm s = series_at_zero(ClosedForm(Laurent(Q(1)), S), 6);  // 1 - x/2 - x^2/8 - x^3/16
    EXPECT_EQ(coefficient(s, Basis::one, 2), Q(-1, 2));
    EXPECT_EQ(coefficient(s, Basis::one, 4), Q(-1, 8));
    EXPECT_EQ(coefficient(s, Basis::one, 6), Q(-1, 16));
    const ClosedForm si = series_at_zero(ClosedForm(Laurent(Q(1)), S_inv), 4);  // 1 + x/2 + 3x^2/8
    EXPECT_EQ(coefficient(si, Basis::one, 4), Q(3, 8));
    const ClosedForm l = series_at_zero(ClosedForm(Laurent(Q(1)), L), 4);  // log 2 - log r - r^2/4 - 3r^4/32
    EXPECT_EQ(coefficient(l, Basis::log, 0), Q(-1));
    EXPECT_EQ(coefficient(l, Basis::one, 2), Q(-1, 4));
    EXPECT_EQ(coefficient(l, Basis::one, 4), Q(-3, 32));
    EXPECT_EQ(limit_at_zero(ClosedForm(Laurent(Q(1)), L) + ClosedForm(Laurent(Q(1)), TermKey{Basis::log, 0, Atom{}})),
              Exact::log_of(Q(2)));
    const ClosedForm a = series_at_zero(ClosedForm(Laurent(Q(1)), A), 5);  // r + r^3/6 + 3r^5/40
    EXPECT_EQ(coefficient(a, Basis::one, 3), Q(1, 6));
    EXPECT_EQ(coefficient(a, Basis::one, 5), Q(3, 40));
}

TEST(Series, NegativePowersCancelInFiniteQuantities) {
    // (S - 1)/r^2 -> -1/2 at 0: the r^-2 terms cancel exactly.
    const ClosedForm f = ClosedForm(Laurent::monomial(Q(1), -2), S) - ClosedForm(Laurent::monomial(Q(1), -2));
    const ClosedForm s = series_at_zero(f, 4);
    for (const auto& [k, p] : s.terms()) EXPECT_GE(p.low(), 0);
    EXPECT_EQ(limit_at_zero(f), Exact(Q(-1, 2)));
}

// The leading order at 0 (the emitted C, Fortran and Python files' value
// below r/h = 2^-150): arcsech r / r^3 is r^-3 (log 2 - log r); the
// cancelling r^-2 of (S - 1)/r^3 leaves -1/(2 r); arcsin r / r^2 is 1/r; 0
// to the order looked at is an error.
TEST(Series, LeadingOrderAtZero) {
    const LeadingOrder l = leading_order_at_zero(ClosedForm(Laurent::monomial(Q(1), -3), L));
    EXPECT_EQ(l.low, -3);
    EXPECT_EQ(l.plain, Exact::log_of(Q(2)));
    EXPECT_EQ(l.logarithm, Exact(Q(-1)));
    const LeadingOrder c = leading_order_at_zero(ClosedForm(Laurent::monomial(Q(1), -3), S) - ClosedForm(Laurent::monomial(Q(1), -3)));
    EXPECT_EQ(c.low, -1);
    EXPECT_EQ(c.plain, Exact(Q(-1, 2)));
    EXPECT_TRUE(c.logarithm.is_zero());
    const LeadingOrder a = leading_order_at_zero(ClosedForm(Laurent::monomial(Q(1), -2), A));
    EXPECT_EQ(a.low, -1);
    EXPECT_EQ(a.plain, Exact(Q(1)));
    const ClosedForm f = ClosedForm(Laurent::monomial(Q(1), -2), S);
    EXPECT_THROW(leading_order_at_zero(f - f), mollify::Error);
}

// Calls fn(first piece of the quantity, entry, quantity name) for every
// quantity of every missing Wendland kernel of the catalogue, every D.
template <class F>
void for_each_missing_wendland_quantity(F fn) {
    for (const CatalogueEntry& e : expand_dimensions(default_specs())) {
        if (e.spec.family != Family::wendland_missing) continue;
        if (mollify::testing::left_to_optimised_build(spec_string(e.spec))) continue;
        const ExactKernel k = make_kernel(e.spec, e.dim);
        const Quantities q = derive_quantities(k);
        for (const std::string& name : quantity_names()) fn(quantity(k, q, name).pieces.front(), e, name);
    }
}

TEST(Series, TruncatedSeriesOfEveryMissingWendlandQuantityMatchesTheClosedForm) {
    int checked = 0;
    for_each_missing_wendland_quantity([&](const ClosedForm& f, const CatalogueEntry& e, const std::string& name) {
            const auto z = zero_series(f);
            ASSERT_TRUE(z) << spec_string(e.spec) << " D=" << e.dim << " " << name;
            EXPECT_LT(z->relative_bound, Q(1) / pow(Q(2), 60));
            const Q r0 = Q(1) / pow(Q(2), z->m);
            // The proven bound holds at the seam r0 (continuity of the table
            // there) and inside, down to r = 2^-200.
            for (const Q& r : std::vector<Q>{r0, Q(r0 * Q(3, 4)), Q(r0 / 2), Q(r0 / 16), Q(r0 / pow(Q(2), 40)), Q(1) / pow(Q(2), 200)})
                EXPECT_LE(relative_gap(f, z->series, r), static_cast<double>(z->relative_bound) * 1.0001 + 1e-100)
                    << spec_string(e.spec) << " D=" << e.dim << " " << name << " r=" << r;
            ++checked;
    });
    EXPECT_EQ(checked, (mollify::testing::sanitized_build ? 1 : 6) * 3 * 10);  // kernels x D x quantities
}

// The edge series (edge_series.hpp) of every missing Wendland quantity: the
// negative powers of S cancel, the proven bound is below 2^-60, and the
// truncated series agrees with a high-precision evaluation of the closed
// form at r1 (continuity of the table at the seam) and up to the edge,
// within the bound relative to the series' leading term (<= its sum of |terms|).
TEST(Series, EdgeSeriesOfEveryMissingWendlandQuantityMatchesTheClosedForm) {
    Real::default_precision(400);  // digits: the intermediate S, powers and sums
    int checked = 0;
    for_each_missing_wendland_quantity([&](const ClosedForm& f, const CatalogueEntry& e, const std::string& name) {
            const auto z = zero_series(f);
            ASSERT_TRUE(z);
            const auto es = edge_series(f, Q(1) / pow(Q(2), z->m));
            ASSERT_TRUE(es) << spec_string(e.spec) << " D=" << e.dim << " " << name;
            EXPECT_LT(es->relative_bound, Q(1) / pow(Q(2), 60));
            for (const Q& r : std::vector<Q>{es->r1, (es->r1 + 1) / 2, Q(15, 16), Q(999, 1000), 1 - Q(1) / pow(Q(2), 40)}) {
                Real rr(0, 200);
                mpfr_set_q(rr.backend().data(), r.backend().data(), MPFR_RNDN);
                const Real exact = f.evaluate(rr, 1500).first;
                const Real S = sqrt(Real(1 - rr * rr));
                Real series(0), magnitude(0);
                for (const EdgeTerm& t : es->terms) {
                    const Real x = t.c.evaluate(300).first * pow(rr, t.low) * pow(S, t.s);
                    series += x;
                    magnitude += abs(x);
                }
                EXPECT_LE(static_cast<double>(abs(series - exact) / magnitude), static_cast<double>(es->relative_bound) * 1.0001 + 1e-60)
                    << spec_string(e.spec) << " D=" << e.dim << " " << name << " r=" << r;
            }
            ++checked;
    });
    EXPECT_EQ(checked, (mollify::testing::sanitized_build ? 1 : 6) * 3 * 10);  // kernels x D x quantities
}

// Euler's zeta(2j)/pi^(2j) (generator/zeta.hpp), which the runtime's
// periodic row of point vortices sums near its vortex (through
// generated/mollify/constants/cot_series.hpp): the known first values
// exactly, and every j to 12 against MPFR's zeta at 256 bits (an independent
// oracle: its own summation, not Bernoulli numbers), within 2^-240.
TEST(Series, EulerZetaValuesAtTheEvenIntegers) {
    EXPECT_EQ(zeta_even_over_pi_power(1), Q(1, 6));
    EXPECT_EQ(zeta_even_over_pi_power(2), Q(1, 90));
    EXPECT_EQ(zeta_even_over_pi_power(6), Q(691, 638512875));
    const std::vector<Q> b = bernoulli_numbers(12);
    EXPECT_EQ(b[1], Q(-1, 2));
    EXPECT_EQ(b[3], Q(0));
    EXPECT_EQ(b[12], Q(-691, 2730));
    mpfr_t z, pi, q;
    mpfr_inits2(256, z, pi, q, static_cast<mpfr_ptr>(nullptr));
    mpfr_const_pi(pi, MPFR_RNDN);
    for (int j = 1; j <= 12; ++j) {
        mpfr_zeta_ui(z, static_cast<unsigned long>(2 * j), MPFR_RNDN);
        mpfr_set_q(q, zeta_even_over_pi_power(j).backend().data(), MPFR_RNDN);
        mpfr_pow_ui(pi, pi, static_cast<unsigned long>(2 * j), MPFR_RNDN);
        mpfr_mul(q, q, pi, MPFR_RNDN);  // q pi^(2j)
        mpfr_const_pi(pi, MPFR_RNDN);
        mpfr_sub(q, q, z, MPFR_RNDN);
        mpfr_div(q, q, z, MPFR_RNDN);
        EXPECT_LT(std::abs(mpfr_get_d(q, MPFR_RNDN)), 0x1p-240) << "zeta(" << 2 * j << ")";
    }
    mpfr_clears(z, pi, q, static_cast<mpfr_ptr>(nullptr));
    EXPECT_THROW(zeta_even_over_pi_power(0), mollify::Error);
}
