// The shapes of the catalogue's polynomial terms for which the run-time
// evaluator compiles a fused loop (src/evaluator.cpp): a loop specialised on
// a shape — Horner length n, edge power, power of q, variable q or q^2, the
// support edge or an interior one, coefficients with or without low parts —
// reads any table's coefficients of that shape. Instantiating only the shapes that
// occur (in W and W'/r, the SPH pair loop's quantities) keeps the compiled
// library small; a kernel with another shape (one made at run time, say)
// takes the evaluator's general loops, with the same bits.
#pragma once

#include "target.hpp"

#include <compare>
#include <set>
#include <string>
#include <vector>

namespace mollify::gen {

struct TermShape {
    bool var_r;         // table::Var::r (else r2)
    bool support_edge;  // edge == 1 (else an interior edge, a combination's radius)
    bool exact;         // every low part c_lo is 0
    int n;              // Horner length
    int edge_power;
    // table::Term::split (Precision::accurate's exact Horner at the split):
    // a combination's shared terms keep its grid (so that the run-time form's
    // loop knows which terms share one, as StaticKernel's does), the other
    // shapes only whether there is one (1 or 0).
    int split;
    // table::Term::low, the power q^low: negative only in a piece that
    // starts above 0 (the cubic spline's W'/r, (1 - q)^2 q^-1 on [1/2, 1)),
    // where the term is bounded.
    int low = 0;
    auto operator<=>(const TermShape&) const = default;
};

// W's and W'/r's shapes of a kernel (D >= 2) whose W and W'/r are both
// whole: the SPH pair loop in one pass (StaticKernel::pairs_unchecked's).
struct WholePair {
    TermShape value, over_r;
    auto operator<=>(const WholePair&) const = default;
};

// The most terms a combination's fused loop takes (src/evaluator.cpp; the
// runtime's src/term_shapes.hpp reads the longest from the list this writes).
inline constexpr std::size_t max_shared_terms = 4;
// The most pieces of a quantity the pieces' fused loop takes (the runtime
// reads the longest from the list, as max_shared_terms).
inline constexpr std::size_t max_pieces = 4;

struct TermShapes {
    std::set<TermShape> terms;  // every fusable term of W and W'/r
    std::set<TermShape> whole;  // those that are a whole quantity: one piece, one term, 0 outside
    std::set<WholePair> whole_pairs;
    // A combination's distinct terms (its innermost piece's, which the
    // outer pieces' terms end), for the fast precision: one pass for all.
    std::set<std::vector<TermShape>> shared;
    // W's and W'/r's shared terms of a combination (D >= 2): the pair loop
    // in one pass, as whole_pairs.
    std::set<std::pair<std::vector<TermShape>, std::vector<TermShape>>> shared_pairs;
    // A quantity of several inner pieces, each one fusable term, 0 outside
    // (the cubic spline's W and W'/r): its pieces' shapes in order; and the
    // kernels (D >= 2) whose W and W'/r are such, at the same breakpoints:
    // the pair loop in one pass, every piece evaluated and one selected, as
    // StaticKernel's.
    std::set<std::vector<TermShape>> pieces;
    std::set<std::pair<std::vector<TermShape>, std::vector<TermShape>>> pieces_pairs;

    void add(const TermShapes& other) {
        terms.insert(other.terms.begin(), other.terms.end());
        whole.insert(other.whole.begin(), other.whole.end());
        whole_pairs.insert(other.whole_pairs.begin(), other.whole_pairs.end());
        shared.insert(other.shared.begin(), other.shared.end());
        shared_pairs.insert(other.shared_pairs.begin(), other.shared_pairs.end());
        pieces.insert(other.pieces.begin(), other.pieces.end());
        pieces_pairs.insert(other.pieces_pairs.begin(), other.pieces_pairs.end());
    }
};

// The fusable terms of one kernel's W and W'/r (Basis::one, no Taylor
// variable, a non-negative edge power, a negative power of q only in a
// piece that starts above 0), added to `out`; its WholePair, its
// combination's shared terms and its pieces where it has them.
void add_term_shapes(const Tables& tables, int dim, TermShapes& out);

// generated/src/term_shapes.def: the shapes as X-macro lines
// MOLLIFY_TERM_SHAPE(var_r, support_edge, exact, n, edge_power, split, low) and
// MOLLIFY_WHOLE_SHAPE(...), MOLLIFY_SHARED_TERMS(...), MOLLIFY_WHOLE_PAIR(...),
// MOLLIFY_SHARED_PAIR(i, j), MOLLIFY_PIECES(...), MOLLIFY_PIECES_PAIR(i, j)
// for the evaluator to instantiate.
std::string term_shapes_source(const std::string& command, const TermShapes& shapes);

}  // namespace mollify::gen
