#include "emit_checks.hpp"

#include "error.hpp"
#include "rounding.hpp"

#include <mollify/detail/double_double.hpp>

#include <boost/multiprecision/mpfr.hpp>

#include <map>

namespace mollify::gen {

namespace {

// p(v) as a Laurent polynomial in r, v = r^2 (square) or v = r.
Laurent in_r(const Laurent& p, bool square) {
    if (!square || p.is_zero()) return p;
    Laurent out;
    for (int k = p.low(); k <= p.high(); ++k) out += Laurent::monomial(p.coefficient(k), 2 * k);
    return out;
}

// An emitted term as an exact closed form (table.hpp):
// (edge - v)^edge_power r^low sum_k c_k v^k basis.
ClosedForm term_form(const EmittedTerm& t) {
    std::map<Atom, Laurent> by_atom;
    if (t.centre) {
        // sum_k c_k (r - centre)^k by Horner's rule in r - centre, per atom.
        for (std::size_t k = t.c.size(); k-- > 0;) {
            for (auto& [atom, p] : by_atom) p.times_r_minus(*t.centre);
            for (const auto& [atom, q] : t.c[k].terms()) by_atom[atom] += Laurent(q);
        }
    } else {
        for (std::size_t k = 0; k < t.c.size(); ++k)
            for (const auto& [atom, q] : t.c[k].terms()) by_atom[atom] += Laurent::monomial(q, static_cast<int>(k));
    }
    Laurent factor(Q(1));
    if (t.edge_power > 0) factor = Laurent::binomial_power(t.square ? *t.edge * *t.edge : *t.edge, Q(-1), t.edge_power);
    ClosedForm out;
    for (const auto& [atom, p] : by_atom)
        out += ClosedForm(in_r(p * factor, t.square).shifted(t.low), TermKey{t.basis, t.s_power, atom});
    return out;
}

// A centred piece against its closed form in MPFR (200 bits) at 129 points:
// the emitted doubles' polynomial (times r^low S^s_power), evaluated
// exactly, is within centred_certificate_bound of max(|f|, |r f'|): the
// truncation, < 2^-61 of it, plus the rounding of the coefficients, ~2^-53
// of the sum of |terms| (measured over the catalogue: <= 0.59 2^-52; the
// bound leaves a factor 6 for the sum of |terms| where f is small).
constexpr double centred_certificate_bound = 0x1p-50;

// The polynomial's working precision: Horner's rule in double-double
// (mollify/detail/double_double.hpp, ~104 bits a step) leaves an error below
// n 2^-103 of the sum of |terms|, itself within a few max(|f|, |r f'|)
// wherever the check passes (the rounding of the coefficients, 2^-53 of it,
// must stay below 2^-50 of that): it cannot move an error across
// centred_certificate_bound. The factors r^low S^s_power and the comparison
// are in MPFR at 36 digits (120 bits). (In MPFR at 36 digits the Horner
// loop was two fifths of the check, at 70 digits a ninth of a missing
// Wendland function's emit.)
constexpr unsigned horner_digits = 36;

// sum_k a_k v^k by Horner's rule, v = v.hi + v.lo.
detail::DoubleDouble horner(const std::vector<double>& a, const detail::DoubleDouble& v) {
    detail::DoubleDouble y{a.back(), 0.0};
    for (std::size_t k = a.size() - 1; k-- > 0;) y = y * v + detail::DoubleDouble{a[k], 0.0};
    return y;
}

void check_centred(const ClosedForm& f, const CentredPiece& p) {
    const std::vector<double> a = rounded(p);
    // f's samples taken when the piece was planned (centred_series.hpp), if
    // of this closed form: the same points, the same 200 bits.
    const bool sampled = p.samples.size() == 129 && p.sampled == f;
    const ClosedForm df = sampled ? ClosedForm() : f.derivative();
    auto real = [](const Q& q) {
        Real x(0, horner_digits);
        mpfr_set_q(x.backend().data(), q.backend().data(), MPFR_RNDN);
        return x;
    };
    // Raw MPFR into numbers made once per piece (Boost's expressions made
    // and freed several numbers per point, at the thread's default precision).
    Real sum(0, horner_digits), v_rest(0, horner_digits), factor(0, horner_digits), S(0, horner_digits);
    Real difference(0, 70);  // 70 digits: sum and the 200-bit sample subtracted without loss that matters
    mpfr_ptr sum_p = sum.backend().data(), factor_p = factor.backend().data(), S_p = S.backend().data(),
             difference_p = difference.backend().data();
    const std::vector<Q> points = equispaced(p.lo, p.hi, 128);
    for (int i = 0; i <= 128; ++i) {
        const Q& x = points[static_cast<std::size_t>(i)];
        const Real r = real(x), v = real(x - p.centre);
        const double v_hi = mpfr_get_d(v.backend().data(), MPFR_RNDN);
        mpfr_sub_d(v_rest.backend().data(), v.backend().data(), v_hi, MPFR_RNDN);
        const detail::DoubleDouble y = horner(a, {v_hi, mpfr_get_d(v_rest.backend().data(), MPFR_RNDN)});
        mpfr_set_d(sum_p, y.hi, MPFR_RNDN);
        mpfr_add_d(sum_p, sum_p, y.lo, MPFR_RNDN);
        if (p.low != 0 || p.s_power != 0) {  // times r^low S^s_power
            mpfr_pow_si(factor_p, r.backend().data(), p.low, MPFR_RNDN);
            mpfr_sqr(S_p, r.backend().data(), MPFR_RNDN);
            mpfr_ui_sub(S_p, 1, S_p, MPFR_RNDN);
            mpfr_sqrt(S_p, S_p, MPFR_RNDN);
            mpfr_pow_si(S_p, S_p, p.s_power, MPFR_RNDN);
            mpfr_mul(factor_p, factor_p, S_p, MPFR_RNDN);
            mpfr_mul(sum_p, sum_p, factor_p, MPFR_RNDN);
        }
        auto sample = [&]() -> std::pair<Real, Real> {
            PointValues at(r, 200);
            Real value = f.evaluate(at).first;
            Real size = boost::multiprecision::max(boost::multiprecision::abs(value),
                                                   boost::multiprecision::abs(r * df.evaluate(at).first));
            return {std::move(value), std::move(size)};
        };
        const std::pair<Real, Real> computed = sampled ? std::pair<Real, Real>{} : sample();
        const auto& [exact, scale] = sampled ? p.samples[static_cast<std::size_t>(i)] : computed;
        mpfr_sub(difference_p, sum_p, exact.backend().data(), MPFR_RNDN);
        mpfr_abs(difference_p, difference_p, MPFR_RNDN);
        mpfr_div(difference_p, difference_p, scale.backend().data(), MPFR_RNDN);
        const double error = mpfr_get_d(difference_p, MPFR_RNDU);
        if (!(error <= centred_certificate_bound))
            fail("internal: the Taylor piece about " + short_string(p.centre) + " misses the closed form at r = " +
                 short_string(x) + " by " + decimal(Q(error), 3) + " of max(|f|, |r f'|)");
    }
}

}  // namespace

// The emission's own certificate: on every piece (but a truncated series)
// the emitted terms sum exactly to the quantity's closed form there; Taylor
// pieces about a centre are checked numerically (check_centred).
void check_emitted(const Radial& f, const std::vector<EmittedPiece>& pieces) {
    for (const EmittedPiece& p : pieces) {
        if (p.centred) check_centred(f.form_at((p.lo + *p.hi) / 2), *p.centred);
        if (p.series) continue;
        ClosedForm sum;
        for (const EmittedTerm& t : p.terms) sum += term_form(t);
        const ClosedForm& want = p.hi ? f.form_at((p.lo + *p.hi) / 2) : f.outside;
        if (!(sum == want))
            fail("internal: the emitted terms on [" + short_string(p.lo) + ", " +
                 (p.hi ? short_string(*p.hi) : std::string("inf")) + ") do not sum to the exact piece");
    }
}

}  // namespace mollify::gen
