#include "term_shapes.hpp"

#include <algorithm>

namespace mollify::gen {
namespace {

bool fusable(const RoundedTerm& t) {
    return t.basis == table::Basis::one && t.low == 0 && t.var != table::Var::shifted && t.edge_power >= 0 && !t.c.empty();
}

TermShape shape_of(const RoundedTerm& t) {
    const bool exact = std::all_of(t.c_lo.begin(), t.c_lo.end(), [](double lo) { return lo == 0; });
    return {t.var == table::Var::r, t.edge == 1.0, exact, static_cast<int>(t.c.size()), t.edge_power};
}

void add_quantity(const std::vector<RoundedPiece>& pieces, TermShapes& out) {
    if (pieces.empty()) return;
    const std::size_t inner = pieces.size() - 1;  // the last piece is the exterior
    for (std::size_t p = 0; p < inner; ++p)
        for (const RoundedTerm& t : pieces[p].terms)
            if (fusable(t)) out.terms.insert(shape_of(t));
    const bool whole = inner == 1 && pieces.front().terms.size() == 1 && pieces.back().terms.empty();
    if (whole && fusable(pieces.front().terms.front())) out.whole.insert(shape_of(pieces.front().terms.front()));
}

std::string line(const char* macro, const TermShape& s) {
    auto b = [](bool x) { return x ? std::string("true") : std::string("false"); };
    return std::string(macro) + "(" + b(s.var_r) + ", " + b(s.support_edge) + ", " + b(s.exact) + ", " +
           std::to_string(s.n) + ", " + std::to_string(s.edge_power) + ")\n";
}

}  // namespace

void add_term_shapes(const Tables& tables, TermShapes& out) {
    for (const table::QuantityId q : {table::QuantityId::value, table::QuantityId::grad_over_r}) {
        const auto& pieces = tables[static_cast<std::size_t>(q)];
        if (pieces) add_quantity(*pieces, out);
    }
}

std::string term_shapes_source(const std::string& command, const TermShapes& shapes) {
    std::string out = banner(command, "//") +
                      "// The shapes of the catalogue's fusable terms of W and W'/r (generator/term_shapes.hpp):\n"
                      "// MOLLIFY_TERM_SHAPE(var_r, support_edge, exact, n, edge_power) for every such term,\n"
                      "// MOLLIFY_WHOLE_SHAPE(...) for those that are a whole quantity (one piece, one term).\n"
                      "// The includer defines both macros.\n\n";
    for (const TermShape& s : shapes.terms) out += line("MOLLIFY_TERM_SHAPE", s);
    out += "\n";
    for (const TermShape& s : shapes.whole) out += line("MOLLIFY_WHOLE_SHAPE", s);
    return out;
}

}  // namespace mollify::gen
