// Exact sign facts of a kernel on its support, for targets that clamp
// (SWIFT's kernel_deval: W >= 0, dW/du <= 0): is W >= 0 and W' <= 0 on
// [0, 1], proved piece by piece on polynomial pieces by Bernstein
// coefficients (a polynomial whose Bernstein coefficients on [a, b] are all
// >= 0 is >= 0 there; Farouki & Rajan 1987), bisected where they are not
// conclusive, or disproved by an exact rational point where it fails.
// A closed-form piece on the whole support [0, 1] (missing Wendland
// functions: S, arcsech r) is proved from its exact series: at 0 on [0, 5/8]
// (series.hpp, f >= T - B (r/t)^(N+1)) and in S at the edge on [5/8, 1]
// (edge_series.hpp, f >= series - beta |lead|), each lower bound divided by
// its lowest power and enclosed by interval arithmetic in MPFR with outward
// rounding on bisected sub-intervals (r^n, S, log r are monotone there, so
// their ends rounded outward enclose them); such a piece is proved or left
// unknown, never disproved.
#pragma once

#include "radial.hpp"

#include <optional>
#include <string>

namespace mollify::gen {

enum class SignVerdict { proved, disproved, unknown };

struct SignFact {
    SignVerdict verdict = SignVerdict::unknown;
    std::optional<Q> witness;  // disproved: a point where the sign fails (exact)
    std::string reason;        // unknown: why not decided; disproved: the value there
};

// f >= 0 on [0, support] (every piece on its closed interval).
SignFact non_negative(const Radial& f);

}  // namespace mollify::gen
