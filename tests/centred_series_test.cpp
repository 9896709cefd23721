// The Taylor pieces about Pythagorean centres that replace the cancelling
// missing Wendland closed forms between the series at 0 and at the edge
// (generator/centred_series.hpp): the basis coefficients are the textbook
// derivatives, and for every missing Wendland quantity of one kernel per D
// the exact truncated series (coefficients evaluated at 300 bits, before any
// rounding to double) is within its proven tail of the closed form, at the
// ends and inside every piece; the pieces cover the interval in order.
#include "catalogue.hpp"
#include "centred_series.hpp"
#include "emit_checks.hpp"
#include "kernel.hpp"
#include "quantities.hpp"
#include "sanitized.hpp"

#include <gtest/gtest.h>

using namespace mollify::gen;

namespace {

Real real(const Q& q, unsigned bits) {
    Real x(0, bits * 30103 / 100000 + 2);
    mpfr_set_q(x.backend().data(), q.backend().data(), MPFR_RNDN);
    return x;
}

// The coefficient as a number at 300 bits.
Real value(const CentredValue& a, const Q& c) { return a.evaluate(c, 300).first; }

}  // namespace

TEST(CentredSeries, BasisCoefficientsAreTheTextbookDerivatives) {
    const Q c(3, 5);  // S(c) = 4/5
    // arcsin: a_0 = arcsin c, a_1 = 1/S = 5/4, a_2 = c/(2 S^3) = 75/128.
    const auto a = taylor_at_centre(ClosedForm(Laurent(Q(1)), TermKey{Basis::arcsin, 0, Atom{}}), c, 2);
    EXPECT_EQ(a[0].arcsin, Exact(Q(1)));
    EXPECT_TRUE(a[0].one.is_zero());
    EXPECT_EQ(a[1].one, Exact(Q(5, 4)));
    EXPECT_EQ(a[2].one, Exact(Q(75, 128)));
    // S^3: a_1 = -3 c S = -36/25.
    const auto s = taylor_at_centre(ClosedForm(Laurent(Q(1)), TermKey{Basis::sqrt_power, 3, Atom{}}), c, 1);
    EXPECT_EQ(s[0].one, Exact(Q(64, 125)));
    EXPECT_EQ(s[1].one, Exact(Q(-36, 25)));
    // arcsech: a_0 = log((1 + S)/c) = log 3, a_1 = -1/(c S) = -25/12.
    const auto l = taylor_at_centre(ClosedForm(Laurent(Q(1)), TermKey{Basis::arcsech, 0, Atom{}}), c, 1);
    EXPECT_EQ(l[0].arcsech, Exact(Q(1)));
    EXPECT_EQ(l[1].one, Exact(Q(-25, 12)));
    EXPECT_NE(l[0].to_string(c).find("log(3)"), std::string::npos);
    // A centre with irrational S(c) is refused.
    EXPECT_THROW(taylor_at_centre(ClosedForm(Laurent(Q(1))), Q(1, 2), 2), std::exception);
}

TEST(CentredSeries, TruncatedSeriesOfMissingWendlandQuantitiesIsWithinItsProvenTail) {
    int checked = 0;
    for (const CatalogueEntry& e : expand_dimensions(default_specs())) {
        if (e.spec.family != Family::wendland_missing || spec_string(e.spec) != "wendland-missing:k=2,l=2") continue;
        if (mollify::testing::sanitized_build && e.dim != 3) continue;  // the code paths, not every D (sanitized.hpp)
        const ExactKernel k = make_kernel(e.spec, e.dim);
        const Quantities qs = derive_quantities(k);
        for (const std::string& name : quantity_names()) {
            const ClosedForm& f = quantity(k, qs, name).pieces.front();
            const Q lo(1, 8), hi(3, 4);
            const auto pieces = centred_pieces(f, lo, hi);
            ASSERT_FALSE(pieces.empty());
            EXPECT_EQ(pieces.front().lo, lo);
            EXPECT_EQ(pieces.back().hi, hi);
            for (std::size_t i = 0; i < pieces.size(); ++i) {
                const CentredPiece& p = pieces[i];
                if (i > 0) {
                    EXPECT_EQ(p.lo, pieces[i - 1].hi);
                }
                EXPECT_LE(p.tail, p.scale / pow(Q(2), 60)) << name;
                for (int j = 0; j <= 4; ++j) {
                    const Q x = p.lo + (p.hi - p.lo) * ratio(j, 4);
                    const Real r = real(x, 300), v = real(x - p.centre, 300);
                    Real sum = real(Q(0), 300);
                    for (std::size_t n = p.a.size(); n-- > 0;) sum = sum * v + value(p.a[n], p.centre);
                    sum *= pow(r, p.low) * pow(sqrt(1 - r * r), p.s_power);
                    const Real gap = abs(sum - f.evaluate(r, 400).first);
                    // The proven tail, plus 2^-200 of the scale for the 300-bit arithmetic.
                    EXPECT_LE(gap, real(p.tail + p.scale / pow(Q(2), 200), 300))
                        << spec_string(e.spec) << " D" << e.dim << " " << name << " at r = " << short_string(x);
                    ++checked;
                }
            }
        }
    }
    EXPECT_GT(checked, mollify::testing::sanitized_build ? 100 / 3 : 100);  // D = 3 only, or D = 1..3
}

// The emission's own check (emit_checks.hpp) of the Taylor pieces, which
// compares the rounded coefficients' polynomial with the closed form's 200-bit
// samples at 129 points: it passes the emitted pieces, in D = 1 and in
// D = 3 (whose pieces are the D = 1 pieces times the normalisation), and
// fails a piece whose constant coefficient is off by 2^-46 of itself (its
// bound is 2^-50 of max(|f|, |r f'|)) or whose samples are not f's.
TEST(CentredSeries, CheckOfEmittedTaylorPiecesCatchesAWrongCoefficient) {
    const Spec spec = parse_spec("wendland-missing:k=1,l=1");
    int pieces_checked = 0;
    for (const int dim : {1, 3}) {
        const ExactKernel k = make_kernel(spec, dim);
        const Quantities qs = derive_quantities(k);
        const Radial& f = quantity(k, qs, "value");
        std::vector<EmittedPiece> pieces = plan_quantity(f, false, {});
        EXPECT_NO_THROW(check_emitted(f, pieces)) << "D" << dim;
        for (EmittedPiece& p : pieces) {
            if (!p.centred) continue;
            ++pieces_checked;
            std::vector<EmittedPiece> one{p};
            EXPECT_NO_THROW(check_emitted(f, one));
            std::vector<double>& a = one.front().centred->a_double;
            ASSERT_FALSE(a.empty());
            a.front() *= 1 + 0x1p-46;
            EXPECT_THROW(check_emitted(f, one), mollify::Error) << "D" << dim << " piece from " << short_string(p.lo);
            one = {p};
            auto& [value, size] = one.front().centred->samples.at(64);
            value *= 1 + 1e-13;
            EXPECT_THROW(check_emitted(f, one), mollify::Error) << "D" << dim << " piece from " << short_string(p.lo);
        }
    }
    EXPECT_GE(pieces_checked, 4);
}

// A centre without a rational S(c) = sqrt(1 - c^2) is an internal error
// (the catalogue's centres have one): the names of its constants fail, and
// fail again on the next call instead of leaving an empty cache entry
// whose names would print as "" (the cache once kept it).
TEST(CentredSeries, IrrationalCentreFailsEveryTime) {
    const CentredValue zero{};
    const Q c(1, 3);  // 1 - c^2 = 8/9
    EXPECT_THROW((void)zero.to_string(c), mollify::Error);
    EXPECT_THROW((void)zero.to_string(c), mollify::Error);
    EXPECT_EQ(zero.to_string(Q(3, 5)), "0");  // S = 4/5: fine
}
