// The evaluation paths a table takes through the run-time form
// (src/evaluator.cpp) and the compile-time form (detail/evaluate.hpp): one
// string per distinct case (term shape and flags, piece kind, quantity
// kind), from the table data alone. runtime_forms_test compares the two
// forms on a few tables and checks that they take every path any catalogue
// table takes.
#pragma once

#include <mollify/table.hpp>

#include <set>
#include <string>

namespace mollify::testing {

inline const char* sign(int x) { return x < 0 ? "-" : x == 0 ? "0" : "+"; }

inline bool continues(const table::Term& s, const table::Term& t) {
    return s.basis == t.basis && s.s_power == t.s_power && s.var == t.var && s.var != table::Var::shifted &&
           s.edge == t.edge && s.low == t.low && s.edge_power > 0 && t.edge_power > s.edge_power;
}

inline std::string term_feature(const table::Term& t, const table::Term* previous, bool exterior) {
    const bool cont = previous && continues(*previous, t);
    std::string f = exterior ? "exterior " : "term ";
    f += "basis=" + std::to_string(static_cast<int>(t.basis)) + " var=" + std::to_string(static_cast<int>(t.var)) +
         " edge_power=" + sign(t.edge_power) + " low=" + sign(t.low) + " n=" + (t.n == 1 ? "1" : ">1") +
         " edge=" + (t.edge == 1.0 ? "1" : "a") + " lo=" + (t.c_lo ? "y" : "n") + " continues=" +
         (cont ? (t.edge_power - previous->edge_power > 1 ? "step" : "1") : "no") + " split=" + (t.split ? "y" : "n");
    if (t.basis == table::Basis::sqrt_power) f += std::string(" s_power=") + (t.s_power % 2 ? "odd" : "even");
    return f;
}

// Several inner pieces of one polynomial term each, 0 outside (the cubic
// spline's W and W'/r): the run-time form's fused pieces (src/plan.cpp:
// piece_shapes_index).
inline bool pieces_of_one_term(const table::Quantity& quantity) {
    if (quantity.npieces < 3 || quantity.pieces[quantity.npieces - 1].nterms != 0) return false;
    for (int p = 0; p + 1 < quantity.npieces; ++p)
        if (quantity.pieces[p].nterms != 1 || quantity.pieces[p].terms[0].basis != table::Basis::one) return false;
    return true;
}

inline std::set<std::string> features(const table::Kernel& k) {
    std::set<std::string> out;
    out.insert("dim=" + std::to_string(k.dim) + (k.parity < 0 ? " odd" : ""));
    // W and W'/r such pieces at the same breakpoints, D >= 2: the run-time
    // form's one-pass pair loop of pieces (Plan::pieces_pair).
    const table::Quantity &w = k.quantities[0], &over_r = k.quantities[4];
    if (k.dim >= 2 && pieces_of_one_term(w) && pieces_of_one_term(over_r) && w.npieces == over_r.npieces) {
        bool same = true;
        for (int p = 0; p < w.npieces; ++p) same = same && w.pieces[p].lo == over_r.pieces[p].lo;
        if (same) out.insert("pair of pieces dim>=2");
    }
    for (int q = 0; q < table::quantity_count; ++q) {
        const table::Quantity& quantity = k.quantities[q];
        if (quantity.npieces == 0) continue;
        if (pieces_of_one_term(quantity)) out.insert("quantity pieces of one term");
        bool polynomial_inside = true;
        for (int p = 0; p < quantity.npieces; ++p) {
            const table::Piece& piece = quantity.pieces[p];
            const bool exterior = p + 1 == quantity.npieces;
            bool series = piece.nterms > 2 && !exterior;
            for (int t = 0; t < piece.nterms; ++t) {
                const table::Term& term = piece.terms[t];
                const table::Term* previous = t > 0 ? &piece.terms[t - 1] : nullptr;
                out.insert(term_feature(term, previous, exterior));
                // a negative power of q where its piece starts above 0: fusable (src/plan.cpp: bounded_on_piece)
                if (!exterior && term.low < 0 && piece.lo > 0 && term.basis == table::Basis::one)
                    out.insert("term low=- in a piece above 0");
                if (!exterior && term.basis != table::Basis::one) polynomial_inside = false;
                series = series && term.n == 1 &&
                         (!previous || (continues(*previous, term) && term.edge_power == previous->edge_power + 1));
            }
            if (exterior) out.insert("exterior terms=" + std::string(piece.nterms == 0 ? "0" : ">0") + " dim=" +
                                     std::to_string(k.dim) + (q == 6 ? " potential" : ""));
            else out.insert(std::string("piece ") + (series ? "series" : piece.nterms == 1 ? "one term" : piece.nterms == 0 ? "empty" : "terms"));
        }
        out.insert(std::string("quantity ") + (polynomial_inside ? "polynomial" : "branches") +
                   (quantity.npieces > 2 ? " pieces" : " one piece"));
        if (q == 4) {  // grad_over_r: a cusp at 0 takes the pair loop's W'(r) x/r path
            const table::Piece& first = quantity.pieces[0];
            bool cusp = false;
            for (int t = 0; t < first.nterms; ++t) {
                const table::Term& term = first.terms[t];
                cusp = cusp || term.low < 0 ||
                       ((term.basis == table::Basis::log || term.basis == table::Basis::arcsech) && term.low <= 0);
            }
            if (cusp) out.insert("cusp dim=" + std::to_string(k.dim));
        }
    }
    return out;
}

}  // namespace mollify::testing
