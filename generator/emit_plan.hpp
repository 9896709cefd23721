// Planning the emission of one quantity: which pieces and terms, in the
// stable forms (table.hpp): factored at the edges, series where closed
// forms cancel, Taylor pieces about centres, a combination's terms each
// factored at its own radius. Exact throughout; nothing is written here.
#pragma once

#include "centred_series.hpp"
#include "radial.hpp"

#include <optional>
#include <string>
#include <vector>

namespace mollify::gen {

// One emitted term: (edge - v)^edge_power r^low sum_k c_k v^k basis.
struct EmittedTerm {
    Basis basis;
    int s_power;
    bool square;  // v = r^2
    int edge_power;
    int low;      // power of r in front
    std::vector<Exact> c;
    std::optional<Q> edge;  // where edge_power > 0; else the piece's hi is written
    std::optional<Q> centre{};  // v = r - centre (table::Var::shifted): a Taylor polynomial
};

// A piece as emitted: exact bounds, its terms, and a note for the comment.
struct EmittedPiece {
    Q lo;
    std::optional<Q> hi;  // nullopt: the exterior, to infinity
    std::vector<EmittedTerm> terms;
    std::string note;
    bool series = false;  // a truncated series, not the exact piece (bound in the note)
    std::optional<CentredPiece> centred{};  // a Taylor piece about a centre (then `terms` is empty)
};

// What the emitted form's double evaluation must reach: Precision::fast's
// ~32 double ulps of max(|f|, |r f'|) (the runtime and the double-valued
// files), or only a float result (SWIFT's float functions): within 2^-30 of
// that scale, which a piece's own polynomial reaches where Precision::fast
// needs Taylor sub-pieces; fewer pieces and branches, so that a loop around
// the call vectorises (SWIFT's gravity pair loop, stop 90).
enum class ResultPrecision { double_value, float_value };

// The pieces of quantity `f` as emitted, in order, the exterior last.
// `parts`: for a combination W = sum_j w_j psi_{a_j}, the same quantity of
// each term, w_j f_j (else empty). `potential_like`: the potential and its
// derivatives, which do not vanish at the support edge.
std::vector<EmittedPiece> plan_quantity(const Radial& f, bool potential_like, const std::vector<Radial>& parts,
                                        ResultPrecision result = ResultPrecision::double_value);

// The emitted (rounded) Taylor coefficients of a centred piece, and the low
// part of the k-th of them, hi (correctly rounded).
std::vector<double> rounded(const CentredPiece& p);
double centred_low_part(const CentredPiece& p, std::size_t k, double hi);

}  // namespace mollify::gen
