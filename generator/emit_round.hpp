// The tables of one quantity as the runtime holds them: the planned pieces
// (emit_plan.hpp), checked (emit_checks.hpp), every number rounded to the
// nearest double with its rounding error (table.hpp's Term::c_lo, edge_lo,
// centre_lo) and the exact values kept for the writers' comments. What the
// C++ writer and the data writer both write.
#pragma once

#include "emit_plan.hpp"
#include "radial.hpp"

#include <mollify/table.hpp>

#include <optional>
#include <string>
#include <vector>

namespace mollify::gen {

struct RoundedTerm {
    table::Basis basis;
    int s_power;
    table::Var var;
    double edge, edge_lo;  // the piece's hi (edge_lo 0) where edge_power = 0
    int edge_power;
    int low;
    std::vector<double> c;
    std::vector<double> c_lo;         // empty where every low part is 0 (table::Term::c_lo = nullptr)
    std::vector<std::string> exact;   // c's exact values, for comments
    double centre = 0, centre_lo = 0;  // table::Var::shifted
    // c's exact values where they are constants q pi^e log p (nullopt for a
    // Taylor piece's coefficients): for writers that keep them (--target python).
    std::vector<std::optional<Exact>> exact_value{};
    int plain = 0;  // table::Term::plain
    // table::Term::split, m, content, content_lo (split 0: none)
    int split = 0;
    std::vector<double> m{};
    double content = 0, content_lo = 0;
    std::string content_exact{};
};

// table::Term::split of a polynomial sum_k c_k q^k on the piece [lo, hi]:
// the content and integer coefficients, the split and its proof (0 where
// the term does not qualify).
struct Split {
    int bits = 0;
    std::vector<Q> m;
    Exact content;
};
Split split_of(const std::vector<Exact>& c, const Q& lo, const Q& hi);

struct RoundedPiece {
    double lo, hi;  // hi: table::infinity for the exterior
    std::vector<RoundedTerm> terms;
    std::string note;  // "[lo, hi) exactly, how the piece is written"
};

// nullopt where the quantity is absent (a potential of a kernel without one).
// `parts`: a combination's terms' quantities w_j f_j (else empty).
std::optional<std::vector<RoundedPiece>> rounded_quantity(const Radial* f, bool potential_like,
                                                          const std::vector<Radial>& parts,
                                                          ResultPrecision result = ResultPrecision::double_value);

// One split grid for all of a kernel's split terms in the quantities whose
// pieces are one term each: the coarsest of their own grids, for each term
// where both of split_of's proofs still hold there (else it keeps its own).
// A coarser grid only widens q - qa, and the remainder's error stays below
// 2^-62 of the term, which is the piece. The grid rounding of q, (q + C) - C
// and q - qa, is then the same operations in those terms, and an evaluation
// of several quantities at one q (W and grad W in a pair loop, a potential
// and its derivative) does them once: the compiler merges them (W + grad W
// of Wendland C4: 4 of the accurate precision's 64 operations). A quantity
// with a piece of several terms keeps each term's own grid: they may cancel
// (with_one_split_grid).
std::vector<std::optional<std::vector<RoundedPiece>>> with_one_split_grid(
    std::vector<std::optional<std::vector<RoundedPiece>>> tables);

}  // namespace mollify::gen
