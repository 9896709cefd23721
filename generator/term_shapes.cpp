#include "term_shapes.hpp"

#include <algorithm>
#include <iterator>
#include <optional>

namespace mollify::gen {
namespace {

// piece_lo: where the term's piece starts. A power of q only where it is
// negative and the piece starts above 0, where it is bounded (src/plan.cpp:
// bounded_on_piece): the cubic spline's W'/r; a whole quantity's or a
// combination's shared term (their first piece starts at 0) has none, as
// their loops assume.
bool fusable(const RoundedTerm& t, double piece_lo) {
    return t.basis == table::Basis::one && (t.low == 0 || (t.low < 0 && piece_lo > 0)) && t.var != table::Var::shifted &&
           t.edge_power >= 0 && !t.c.empty();
}

TermShape shape_of(const RoundedTerm& t) {
    const bool exact = std::all_of(t.c_lo.begin(), t.c_lo.end(), [](double lo) { return lo == 0; });
    return {t.var == table::Var::r, t.edge == 1.0, exact, static_cast<int>(t.c.size()), t.edge_power, t.split > 0 ? 1 : 0,
            t.low};
}

// A combination's pieces (QuantityPlan::shared_terms): 0 outside, piece p
// holding the last terms of piece 0, every term fusable. Its shapes
// (piece 0's, in order; `exact` false: the fast precision reads no low
// parts) added to out.shared, and returned.
std::optional<std::vector<TermShape>> add_shared(const std::vector<RoundedPiece>& pieces, TermShapes& out) {
    const std::size_t inner = pieces.size() - 1;
    if (inner < 2 || !pieces.back().terms.empty()) return std::nullopt;
    const std::vector<RoundedTerm>& all = pieces.front().terms;
    if (all.size() < 2 || all.size() > max_shared_terms) return std::nullopt;
    std::vector<TermShape> shapes;
    for (const RoundedTerm& t : all) {
        if (!fusable(t, pieces.front().lo)) return std::nullopt;
        TermShape s = shape_of(t);
        s.exact = false;
        s.split = t.split;
        shapes.push_back(s);
    }
    for (std::size_t p = 1; p < inner; ++p) {
        const std::vector<RoundedTerm>& terms = pieces[p].terms;
        if (terms.empty() || terms.size() >= all.size()) return std::nullopt;
        for (std::size_t t = 0; t < terms.size(); ++t) {
            const std::size_t in_all = all.size() - terms.size() + t;
            if (!fusable(terms[t], pieces[p].lo) || terms[t].c != all[in_all].c || terms[t].edge != all[in_all].edge)
                return std::nullopt;
        }
    }
    out.shared.insert(shapes);
    return shapes;
}

// A quantity of several inner pieces of one fusable term each, 0 outside
// (QuantityPlan::pieces_fused): its pieces' shapes in order, added to
// out.pieces, and returned.
std::optional<std::vector<TermShape>> add_pieces(const std::vector<RoundedPiece>& pieces, TermShapes& out) {
    const std::size_t inner = pieces.size() - 1;
    if (inner < 2 || inner > max_pieces || !pieces.back().terms.empty()) return std::nullopt;
    std::vector<TermShape> shapes;
    for (std::size_t p = 0; p < inner; ++p) {
        if (pieces[p].terms.size() != 1 || !fusable(pieces[p].terms.front(), pieces[p].lo)) return std::nullopt;
        shapes.push_back(shape_of(pieces[p].terms.front()));
    }
    out.pieces.insert(shapes);
    return shapes;
}

// A quantity's one-pass forms: its shape where it is a whole quantity (one
// inner piece of one fusable term, 0 outside), its shared terms' shapes
// where it is a combination's, its pieces' where it is pieces of one term.
struct OnePass {
    std::optional<TermShape> whole;
    std::optional<std::vector<TermShape>> shared, pieces;
    std::vector<double> breaks;  // the inner pieces' lower ends
};

// Adds the quantity's fusable terms to `out`.
OnePass add_quantity(const std::vector<RoundedPiece>& pieces, TermShapes& out) {
    if (pieces.empty()) return {};
    const std::size_t inner = pieces.size() - 1;  // the last piece is the exterior
    OnePass one_pass{std::nullopt, add_shared(pieces, out), add_pieces(pieces, out), {}};
    for (std::size_t p = 0; p < inner; ++p) {
        one_pass.breaks.push_back(pieces[p].lo);
        for (const RoundedTerm& t : pieces[p].terms)
            if (fusable(t, pieces[p].lo)) out.terms.insert(shape_of(t));
    }
    const bool whole = inner == 1 && pieces.front().terms.size() == 1 && pieces.back().terms.empty();
    if (!whole || !fusable(pieces.front().terms.front(), pieces.front().lo)) return one_pass;
    one_pass.whole = shape_of(pieces.front().terms.front());
    out.whole.insert(*one_pass.whole);
    return one_pass;
}

std::string shape_arguments(const TermShape& s) {
    auto b = [](bool x) { return x ? std::string("true") : std::string("false"); };
    return b(s.var_r) + ", " + b(s.support_edge) + ", " + b(s.exact) + ", " + std::to_string(s.n) + ", " +
           std::to_string(s.edge_power) + ", " + std::to_string(s.split) + ", " + std::to_string(s.low);
}

// MACRO(m, {shape}, ...) for a list of m shapes.
std::string list_line(const char* macro, const std::vector<TermShape>& shapes) {
    std::string out = std::string(macro) + "(" + std::to_string(shapes.size());
    for (const TermShape& t : shapes) out += ", {" + shape_arguments(t) + "}";
    return out + ")\n";
}

std::string line(const char* macro, const TermShape& s) { return std::string(macro) + "(" + shape_arguments(s) + ")\n"; }

}  // namespace

void add_term_shapes(const Tables& tables, int dim, TermShapes& out) {
    OnePass one_pass[2];
    for (const table::QuantityId q : {table::QuantityId::value, table::QuantityId::grad_over_r}) {
        const auto& pieces = tables[static_cast<std::size_t>(q)];
        if (pieces) one_pass[q == table::QuantityId::grad_over_r] = add_quantity(*pieces, out);
    }
    // In 1D the pair loop is scalar (the sign of x), as StaticKernel's.
    if (dim < 2) return;
    const OnePass &value = one_pass[0], &over_r = one_pass[1];
    if (value.whole && over_r.whole) out.whole_pairs.insert({*value.whole, *over_r.whole});
    if (value.shared && over_r.shared) out.shared_pairs.insert({*value.shared, *over_r.shared});
    if (value.pieces && over_r.pieces && value.breaks == over_r.breaks)
        out.pieces_pairs.insert({*value.pieces, *over_r.pieces});
}

std::string term_shapes_source(const std::string& command, const TermShapes& shapes) {
    std::string out = banner(command, "//") +
                      "// The shapes of the catalogue's fusable terms of W and W'/r (generator/term_shapes.hpp):\n"
                      "// MOLLIFY_TERM_SHAPE(var_r, support_edge, exact, n, edge_power, split, low) for every such term\n"
                      "// (split: 1 where there is one, 0 where not; low: the power q^low, below 0 only in a piece\n"
                      "// that starts above 0),\n"
                      "// MOLLIFY_WHOLE_SHAPE(...) for those that are a whole quantity (one piece, one term),\n"
                      "// MOLLIFY_WHOLE_PAIR(W's shape..., W'/r's shape...) for the kernels (D >= 2) whose W and W'/r both are.\n"
                      "// MOLLIFY_SHARED_TERMS(m, {shape}...) for a combination's m distinct terms (fast: exact false;\n"
                      "// split: the term's grid, table::Term::split).\n"
                      "// MOLLIFY_SHARED_PAIR(i, j) for the combinations (D >= 2) whose W and W'/r are the i-th and j-th of those.\n"
                      "// MOLLIFY_PIECES(m, {shape}...) for a quantity of m inner pieces of one term each, 0 outside;\n"
                      "// MOLLIFY_PIECES_PAIR(i, j) for the kernels (D >= 2) whose W and W'/r are the i-th and j-th of\n"
                      "// those, at the same breakpoints.\n"
                      "// The includer defines the seven macros.\n\n";
    for (const TermShape& s : shapes.terms) out += line("MOLLIFY_TERM_SHAPE", s);
    out += "\n";
    for (const TermShape& s : shapes.whole) out += line("MOLLIFY_WHOLE_SHAPE", s);
    out += "\n";
    for (const std::vector<TermShape>& terms : shapes.shared) out += list_line("MOLLIFY_SHARED_TERMS", terms);
    out += "\n";
    for (const WholePair& p : shapes.whole_pairs)
        out += "MOLLIFY_WHOLE_PAIR(" + shape_arguments(p.value) + ", " + shape_arguments(p.over_r) + ")\n";
    out += "\n";
    auto index = [](const std::set<std::vector<TermShape>>& list, const std::vector<TermShape>& s) {
        return std::to_string(std::distance(list.begin(), list.find(s)));
    };
    for (const auto& [value, over_r] : shapes.shared_pairs)
        out += "MOLLIFY_SHARED_PAIR(" + index(shapes.shared, value) + ", " + index(shapes.shared, over_r) + ")\n";
    out += "\n";
    for (const std::vector<TermShape>& pieces : shapes.pieces) out += list_line("MOLLIFY_PIECES", pieces);
    out += "\n";
    for (const auto& [value, over_r] : shapes.pieces_pairs)
        out += "MOLLIFY_PIECES_PAIR(" + index(shapes.pieces, value) + ", " + index(shapes.pieces, over_r) + ")\n";
    return out;
}

}  // namespace mollify::gen
