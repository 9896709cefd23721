// Series of the closed forms at r = 0, truncated with a rigorous error bound.
// The missing Wendland closed forms (S P + L Q, with Laurent terms r^-k in
// their derivatives and potentials) cancel as r -> 0; their series there,
//   S^j      = sum_i binom(j/2, i) (-1)^i r^(2i),
//   arcsech r = log 2 - log r - sum_{i>=1} c_i/(2i) r^(2i),
//   arcsin r  = sum_{i>=0} c_i/(2i+1) r^(2i+1),      c_i = (2i)!/(4^i i!^2),
// have rational coefficients (log 2 apart), so the series of every quantity
// is computed exactly; the emitter writes it as the first piece [0, r0).
#pragma once

#include "closed_form.hpp"

#include <optional>
#include <vector>

namespace mollify::gen {

// One term of a basis function's series: c r^power (times log r if log_r).
struct SeriesTerm {
    int power;
    Exact c;
    bool log_r;
};
// The series of a basis function at 0 up to r^order.
std::vector<SeriesTerm> basis_series(const TermKey& k, int order);

// The series of f at r = 0 truncated after r^order: a closed form in the
// bases 1 and log r (terms r^n and r^n log r, n <= order). Negative powers
// cancel exactly where f is finite at 0.
ClosedForm series_at_zero(const ClosedForm& f, int order);

// The leading order of f at r = 0, f(r) = r^low (plain + logarithm log r)
// (1 + o(1)): the lowest power of its series there (singular terms that
// cancel exactly are gone), looked for up to `beyond` powers above the
// lowest power of f's Laurent parts; Error where none is found.
struct LeadingOrder {
    int low = 0;
    Exact plain, logarithm;
};
LeadingOrder leading_order_at_zero(const ClosedForm& f, int beyond = 8);

// A rigorous B with |f(r) - series_at_zero(f, order)(r)| <= B (r/r0)^(order+1)
// for 0 < r <= r0; nullopt when the tail bound does not converge at r0.
// Requires order >= the highest power of r in f.
std::optional<Q> truncation_bound(const ClosedForm& f, int order, const Q& r0);

// Rigorous bound on |f - T| / |f| over (0, r0] for T = series_at_zero(f,
// order), r0 = 2^-m; nullopt when no bound (T may vanish in (0, r0]).
std::optional<Q> relative_truncation_bound(const ClosedForm& f, int order, int m);

// The series piece replacing f on [0, r0).
struct ZeroSeries {
    int m = 0;      // r0 = 2^-m
    int order = 0;  // highest power of r kept
    ClosedForm series;
    Q relative_bound;  // |f - series| <= relative_bound |f| on (0, r0]
};

// The series piece of f: r0 = 2^-m (1 <= m <= 8) with a truncation proven
// below 2^-60 relative (order <= 120), chosen where the series is well
// conditioned (sum of |terms| over |value|, the factor by which double
// evaluation loses accuracy): the largest r0 whose condition number is at
// most 2, or within 1.25 of the best seam's. (The closed form beyond r0 is
// not evaluated: Taylor pieces about centres replace it, centred_series.hpp.)
// nullopt when f has no such series (e.g. it is singular beyond log r).
// The search's compiled-in choice where it fits (search_choices.hpp).
std::optional<ZeroSeries> zero_series(const ClosedForm& f);

}  // namespace mollify::gen
