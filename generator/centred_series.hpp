// Taylor pieces of the missing Wendland closed forms in the middle of the
// support, between the series at r = 0 (series.hpp) and the series in S at
// the edge (edge_series.hpp), where S P + arcsech(r) Q (+ arcsin r, log r)
// cancels (up to 1e9 ulp). About a centre c with S(c) = sqrt(1 - c^2)
// rational (c = 2t/(1 + t^2), S(c) = (1 - t^2)/(1 + t^2), t rational: the
// Pythagorean points) every Taylor coefficient of every basis is rational
// but for one constant per basis:
//   S^j(c + v)     = (S(c)^2 - 2cv - v^2)^(j/2)   (rational series),
//   arcsech(c + v) = arcsech c - int (r S)^-1     (arcsech c = log((1+S(c))/c)),
//   arcsin(c + v)  = arcsin c + int S^-1,
//   log(c + v)     = log c + int r^-1,
// so a coefficient is exact as a sum of four Exact numbers times
// 1, arcsech c, arcsin c, log c (CentredValue). The truncation is bounded by
// Cauchy's estimate on a complex disc about c (centred_series.cpp).
#pragma once

#include "closed_form.hpp"

#include <string>
#include <utility>
#include <vector>

namespace mollify::gen {

// x_one + x_arcsech arcsech(c) + x_arcsin arcsin(c) + x_log log(c), exact.
struct CentredValue {
    Exact one, arcsech, arcsin, log;
    // Value and sum of |terms| at `bits` (for Ziv rounding, rounding.hpp).
    std::pair<Real, Real> evaluate(const Q& c, unsigned bits) const;
    std::string to_string(const Q& c) const;
};

// f(r) ~ r^low S^s_power sum_n a_n (r - centre)^n on [lo, hi): the Taylor
// series of r^-low S^-s_power f (low <= 0: f's Laurent terms r^-k, which
// cancel near 0, are gone; s_power >= 0: f's own power of S at the edge,
// so that the series does not cancel where f falls towards the edge).
struct CentredPiece {
    Q lo, hi, centre;
    int low = 0, s_power = 0;
    std::vector<CentredValue> a;
    Q tail;   // rigorous: |f - sum| <= tail on [lo, hi]
    Q scale;  // min over 257 sample points of max(|f|, |r f'|): the bound's reference
    // f's samples behind `scale`, kept for the check of the emitted piece
    // (emit_checks.cpp), which compares with f at every other one of them:
    // the closed form sampled, and at lo + (hi - lo) i/128, i = 0 .. 128,
    // f and max(|f|, |r f'|) in MPFR at 200 bits.
    ClosedForm sampled;
    std::vector<std::pair<Real, Real>> samples;
    // a_k correctly rounded to double (emit_plan.hpp's rounded), once per
    // piece: the check and the writer emit the same doubles; and the low
    // parts a_k - a_double[k], correctly rounded (emit_plan.hpp's
    // centred_low_part), where they were made with them.
    std::vector<double> a_double{};
    std::vector<double> a_lo{};
};

// The Taylor coefficients a_0 .. a_order of f about a Pythagorean centre c.
std::vector<CentredValue> taylor_at_centre(const ClosedForm& f, const Q& c, int order);

// Pieces covering [lo, hi) (0 < lo < hi <= 1, f analytic on (0, 1)), each
// |r - c| <= 0.3 min(c, 1 - c), truncation below 2^-60 of `scale`; as the
// search's compiled-in choices say where they fit (search_choices.hpp).
// Made once per run for f = c g (c = q pi^e, g's first coefficient 1) and
// multiplied by c for every other multiple of g (the choices are g's).
std::vector<CentredPiece> centred_pieces(const ClosedForm& f, const Q& lo, const Q& hi);

}  // namespace mollify::gen
