// Series of the missing Wendland closed forms at the support edge r = 1, in
// powers of S = sqrt(1 - r^2), truncated with a rigorous error bound.
// The closed forms S P + arcsech(r) Q (+ arcsin r, log r in potentials)
// cancel catastrophically away from r = 0 (up to 7e13 ulp near the edge);
// with x = S^2 = 1 - r^2 every basis is a series in S:
//   arcsech r = artanh S = sum_{i>=0} S^(2i+1) / (2i+1)        (S < 1),
//   arcsin r  = pi/2 - arcsin S = pi/2 - sum_{i>=0} c_i S^(2i+1)/(2i+1),
//   log r     = log(1 - x)/2 = -sum_{i>=1} S^(2i) / (2i),
// c_i = (2i)!/(4^i i!^2), and a Laurent polynomial's r^n = r^n0 (1 - x)^((n-n0)/2)
// for n0 the lowest power of n's parity, so f = sum over the (at most two)
// parity classes of r^n0 sum_s a_s S^s with exact coefficients; the emitter
// writes it on [r1, 1] one term per power, c r^n0 (1 - r^2)^k (times S for
// odd s). The negative powers S^-j of derivatives cancel exactly.
#pragma once

#include "closed_form.hpp"

#include <optional>
#include <vector>

namespace mollify::gen {

// One term c r^low S^s of an edge series (s >= 0).
struct EdgeTerm {
    int low;
    int s;
    Exact c;
};

// The series of f at r = 1 with every infinite basis series truncated after
// S^order (the finite parts, S^j (1 - x)^e and pi/2, are kept whole); by
// (low, s). nullopt when a negative power of S survives (f singular at 1).
std::optional<std::vector<EdgeTerm>> series_at_edge(const ClosedForm& f, int order);

// A rigorous beta with |f(r) - series_at_edge(f, order)(r)| <= beta |lead(r)|
// on [r1, 1], lead the term of lowest power of S (largest |c| among those):
// a bound relative to the series' own leading term, hence to its sum of
// |terms|. nullopt without a leading term.
std::optional<Q> edge_truncation_bound(const ClosedForm& f, int order, const Q& r1);

// The series piece replacing f on [r1, 1].
struct EdgeSeries {
    Q r1;
    int order = 0;
    std::vector<EdgeTerm> terms;
    Q relative_bound;  // |f - series| <= relative_bound |leading term| on [r1, 1]
};

// The edge piece of f, the closed form kept on [r0, r1) (r0: where f's
// series at 0 ends): r1 the smallest of r0 and k/32 (k = 16..31) whose
// truncation is proven below 2^-60 with at most 120 powers of S; nullopt
// when f has no edge series. The search's compiled-in choice where it fits
// (search_choices.hpp).
std::optional<EdgeSeries> edge_series(const ClosedForm& f, const Q& r0);

// Sum of |terms| over |value| of an edge series at r (double, a heuristic).
double edge_condition(const std::vector<EdgeTerm>& terms, double r);

}  // namespace mollify::gen
