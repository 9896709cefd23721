// The plan of a table: the compile-time predicates of detail/evaluate.hpp
// (continues_series, edge_series, has_factor, polynomial_inside,
// singular_at_origin, zero_outside, log_coefficient) computed once from
// the table data.
#include "plan.hpp"
#include "term_shapes.hpp"

#include <mollify/detail/evaluate.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/smoothing.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <span>
#include <string>

namespace mollify::detail {
namespace {

[[noreturn]] void bad_table(const table::Kernel& k, int q, int p, int t, const std::string& why) {
    fail("kernel " + std::string(k.spec) + " in D = " + std::to_string(k.dim) + ": " + quantity_names[q] + ", piece " +
         std::to_string(p) + ", term " + std::to_string(t) + ": " + why);
}

// A term the fused loops can take: Basis::one, no Taylor variable, a
// non-negative edge power, every Horner step compensated, a power of q
// only where bounded on its piece. (bounded: the accurate fused loops'
// last product has no overflow guard, detail::rounded_product_bounded)
bool fusable(const TermPlan& t) {
    return t.basis == table::Basis::one && t.var != table::Var::shifted && t.edge_power >= 0 && t.plain == 0 && t.bounded;
}

// table::bounded_term, or for a negative power of q in a piece [lo, ...)
// with lo > 0 the same bound times lo^low, q^low's largest there (the cubic
// spline's W'/r, (1 - q)^2 q^-1 on [1/2, 1)): the fused loops' unguarded
// last product holds wherever the piece is selected; elsewhere (q below lo,
// q^low up to inf) its value is discarded.
bool bounded_on_piece(const table::Term& t, double lo) {
    if (table::bounded_term(t)) return true;
    if (t.low >= 0 || !(lo > 0)) return false;
    table::Term without = t;
    without.low = 0;
    return table::term_bound(without) * std::pow(lo, t.low) < 0x1p100;
}

// Its shape is s's, low parts aside (variable, edge, length, edge power, power of q).
// A support edge is exactly 1 (edge_lo 0): the fused loops take it as the constant.
bool has_shape(const TermPlan& t, const TermShape& s) {
    const bool support_edge = t.edge == 1.0 && t.edge_lo == 0;
    return s.var_r == (t.var == table::Var::r) && s.support_edge == support_edge && (support_edge || t.edge != 1.0) &&
           s.n == t.n && s.edge_power == t.edge_power && s.low == t.low;
}

// A fusable term not continuing a series, with or without low parts as
// listed (the accurate loops): its index in `shapes`, or -1.
int shape_index(const TermPlan& t, std::span<const TermShape> shapes) {
    if (!fusable(t) || t.continues) return -1;
    for (std::size_t i = 0; i < shapes.size(); ++i)
        if (has_shape(t, shapes[i]) && shapes[i].exact == t.exact && (shapes[i].split > 0) == (t.split > 0))
            return static_cast<int>(i);
    return -1;
}

// The term's shape for Precision::fast's fused loops (add_term_fixed),
// which read no low parts and take a term continuing a series as any
// other (its edge power computed whole): its first index in term_shapes,
// or -1.
int fast_shape_index(const TermPlan& t) {
    if (!fusable(t)) return -1;
    for (std::size_t i = 0; i < term_shape_count; ++i)
        if (has_shape(t, term_shapes[i])) return static_cast<int>(i);
    return -1;
}

TermPlan term_plan(const table::Term& t, const table::Term* previous, double piece_lo) {
    TermPlan p{t.basis, t.s_power, t.var, t.edge, t.edge_lo, t.edge_power, t.low, t.c, {}, t.n, t.centre,
               t.centre_lo, true, false, false, 0};
    p.c_lo.assign(static_cast<std::size_t>(t.n), 0.0);
    for (int k = 0; k < t.n; ++k) {
        p.c_lo[static_cast<std::size_t>(k)] = t.c_lo ? t.c_lo[k] : 0.0;
        p.exact = p.exact && p.c_lo[static_cast<std::size_t>(k)] == 0;
    }
    p.plain = t.plain;
    if (t.split > 0) {
        p.split = t.split;
        p.m.assign(t.m, t.m + t.n);
        p.content = t.content;
        p.content_lo = t.content_lo;
        p.split_c = split_constant(t.split);
    }
    p.bounded = bounded_on_piece(t, piece_lo);
    p.has_factor = t.edge_power != 0 || t.low != 0 || t.basis == table::Basis::sqrt_power;
    p.continues = previous && continues(*previous, t);
    p.step = p.continues ? t.edge_power - previous->edge_power : 0;
    p.shape = shape_index(p, {term_shapes, term_shape_count});
    p.fast_shape = fast_shape_index(p);
    return p;
}

// is_edge_series: more than two terms, each a constant times the previous
// term's factor and one more power of the edge distance.
bool is_edge_series(const table::Piece& piece) {
    if (piece.nterms <= 2) return false;
    for (int t = 0; t < piece.nterms; ++t) {
        const table::Term& term = piece.terms[t];
        if (term.n != 1) return false;
        if (t > 0 && !(continues(piece.terms[t - 1], term) && term.edge_power == piece.terms[t - 1].edge_power + 1))
            return false;
    }
    return true;
}

PiecePlan piece_plan(const table::Kernel& k, int q, int p, bool exterior) {
    const table::Piece& piece = k.quantities[q].pieces[p];
    PiecePlan out{piece.lo, piece.hi, {}, false, {}, {}, true};
    for (int t = 0; t < piece.nterms; ++t) {
        const table::Term& term = piece.terms[t];
        if (term.n < 1) bad_table(k, q, p, t, "a polynomial of " + std::to_string(term.n) + " coefficients");
        if (term.var == table::Var::shifted && term.edge_power != 0)
            bad_table(k, q, p, t, "a Taylor piece with an edge factor");
        if (exterior && (term.edge_power != 0 || term.var == table::Var::shifted ||
                         (term.basis != table::Basis::one && term.basis != table::Basis::log)))
            bad_table(k, q, p, t, "the exterior is not a Green's function in r");
        out.terms.push_back(term_plan(term, t > 0 ? &piece.terms[t - 1] : nullptr, piece.lo));
    }
    out.edge_series = !exterior && is_edge_series(piece);
    if (out.edge_series)
        for (const TermPlan& t : out.terms) {
            out.series_c.push_back(t.c[0]);
            out.series_lo.push_back(t.c_lo[0]);
            out.series_exact = out.series_exact && t.c_lo[0] == 0;
        }
    return out;
}

// The plan's inner pieces as shared_terms_rule (detail/evaluate.hpp) reads
// them, the rule StaticKernel applies to the table.
struct PlanTerms {
    const std::vector<PiecePlan>& inner;
    int pieces() const { return static_cast<int>(inner.size()); }
    double lo(int p) const { return piece(p).lo; }
    int terms(int p) const { return static_cast<int>(piece(p).terms.size()); }
    bool series(int p) const { return piece(p).edge_series; }
    bool continues(int p, int t) const { return term(p, t).continues; }
    bool same(int p, int t, int r, int u) const {
        const TermPlan &a = term(p, t), &b = term(r, u);
        return same_term_fields(a, b) && a.m == b.m && std::equal(a.c, a.c + a.n, b.c) && a.c_lo == b.c_lo;
    }
    const PiecePlan& piece(int p) const { return inner[static_cast<std::size_t>(p)]; }
    const TermPlan& term(int p, int t) const { return piece(p).terms[static_cast<std::size_t>(t)]; }
};

std::vector<QuantityPlan::SharedTerm> shared_terms_of(const std::vector<PiecePlan>& inner) {
    const SharedTermList list = shared_terms_rule(PlanTerms{inner});
    std::vector<QuantityPlan::SharedTerm> out;
    for (int d = 0; d < list.m; ++d)
        out.push_back({static_cast<std::size_t>(list.t[d].piece), static_cast<std::size_t>(list.t[d].term),
                       list.t[d].lo, list.t[d].hi});
    return out;
}

// The index in shared_shapes of the quantity's shared terms' shapes (the
// fast precision's: low parts not read; the grids, table::Term::split, as
// they are), or -1; -1 also where the terms are not a combination's radii in
// order (detail::radii_in_order), which the fused loops assume.
int shared_shapes_index(const QuantityPlan& qp) {
    const std::size_t m = qp.shared_terms.size();
    // the fused loops compare q with each radius only (SharedTerms::reaches)
    if (m == 0 || m > max_list_length || !radii_in_order(qp.shared_terms, qp.shared_terms, m)) return -1;
    for (std::size_t i = 0; i < shared_shapes_count; ++i) {
        const ShapeList& s = shared_shapes[i];
        bool same = s.m == m;
        for (std::size_t j = 0; same && j < m; ++j) {
            const TermPlan& t = qp.inner[qp.shared_terms[j].piece].terms[qp.shared_terms[j].term];
            same = fusable(t) && has_shape(t, s.shapes[j]) && s.shapes[j].split == t.split;
        }
        if (same) return static_cast<int>(i);
    }
    return -1;
}

// The index in piece_shapes of a quantity of several inner pieces, each
// one fusable term of a listed shape (with or without low parts, split or
// not, as the accurate loops read them), 0 outside; or -1.
int piece_shapes_index(const QuantityPlan& qp) {
    const std::size_t m = qp.inner.size();
    if (m < 2 || m > max_list_length || !qp.polynomial_inside || !qp.zero_outside || qp.singular_at_origin) return -1;
    for (const PiecePlan& piece : qp.inner)
        if (piece.terms.size() != 1 || piece.edge_series) return -1;
    for (std::size_t i = 0; i < piece_shapes_count; ++i) {
        const ShapeList& s = piece_shapes[i];
        bool same = s.m == m;
        for (std::size_t p = 0; same && p < m; ++p) {
            const TermPlan& t = qp.inner[p].terms.front();
            same = fusable(t) && !t.continues && has_shape(t, s.shapes[p]) && s.shapes[p].exact == t.exact &&
                   (s.shapes[p].split > 0) == (t.split > 0);
        }
        if (same) return static_cast<int>(i);
    }
    return -1;
}

QuantityPlan quantity_plan(const table::Kernel& k, int q) {
    QuantityPlan out;
    const table::Quantity& quantity = k.quantities[q];
    if (quantity.npieces == 0) return out;
    if (quantity.npieces < 2) fail("kernel " + std::string(k.spec) + ": " + quantity_names[q] + " has no inner piece");
    out.present = true;
    for (int p = 0; p + 1 < quantity.npieces; ++p) out.inner.push_back(piece_plan(k, q, p, false));
    out.exterior = piece_plan(k, q, quantity.npieces - 1, true);
    for (const PiecePlan& piece : out.inner)
        for (const TermPlan& t : piece.terms) out.polynomial_inside = out.polynomial_inside && t.basis == table::Basis::one;
    out.zero_outside = out.exterior.terms.empty();
    out.singular_at_origin = singular_piece(quantity.pieces[0]);
    if (out.singular_at_origin) {
        out.at_origin = limit_at_origin(quantity.pieces[0]);
        out.first = &quantity.pieces[0];
        out.spec = k.spec;
    }
    out.unit_edge = unit_edge_power(quantity);
    if (out.unit_edge > 0) out.inner.front().terms.front().unit_edge = true;
    if (out.inner.size() == 1 && out.inner.front().terms.size() == 1 && !out.inner.front().edge_series && out.zero_outside) {
        out.whole = shape_index(out.inner.front().terms.front(), {whole_shapes, whole_shape_count});
        // A whole loop takes its shape's edge in units of 2^e or not
        // (unit_edge_shape); where the quantity's own rule says otherwise
        // (a term too large for it), the blocks.
        if (out.whole >= 0 && unit_edge_shape(whole_shapes[static_cast<std::size_t>(out.whole)]) != (out.unit_edge > 0))
            out.whole = -1;
    }
    if (out.polynomial_inside && out.zero_outside) out.shared_terms = shared_terms_of(out.inner);
    out.shared_fused = shared_shapes_index(out);
    out.pieces_fused = piece_shapes_index(out);
    // (the shared terms' accurate loops read no unit edge)
    out.shared_accurate = out.shared_fused >= 0 && out.unit_edge == 0;
    for (const QuantityPlan::SharedTerm& m : out.shared_terms) {
        const TermPlan& t = out.inner[m.piece].terms[m.term];
        out.shared_accurate = out.shared_accurate && (t.n == 1 || !t.exact);
    }
    for (const TermPlan& t : out.exterior.terms)
        if (t.basis == table::Basis::log) {
            out.log_coefficient = t.c[0];
            break;
        }
    return out;
}

// The index in whole_pairs of a kernel in D dimensions with W's and W'/r's
// whole shapes (indices in whole_shapes), or -1 (always in 1D, whose pair
// loop is scalar).
int whole_pair_index(int dim, int value, int over_r) {
    if (dim < 2 || value < 0 || over_r < 0) return -1;
    const TermShape& v = whole_shapes[static_cast<std::size_t>(value)];
    const TermShape& g = whole_shapes[static_cast<std::size_t>(over_r)];
    for (std::size_t i = 0; i < whole_pair_count; ++i)
        if (whole_pairs[i].value == v && whole_pairs[i].over_r == g) return static_cast<int>(i);
    return -1;
}

// W's and W'/r's whole terms split q on one grid where both split (the
// generator's with_one_split_grid; a table file may differ): the whole pair
// loop then splits q once for both (whole_pairs_fixed), as StaticKernel's,
// whose two grids are one constant. Two grids take the general loops.
bool one_split_grid(const QuantityPlan& value, const QuantityPlan& over_r) {
    const TermPlan& v = value.inner.front().terms.front();
    const TermPlan& g = over_r.inner.front().terms.front();
    return !(v.split > 0 && g.split > 0) || v.split_c == g.split_c;
}

// Are W's and W'/r's shared terms at the same radii, term for term (edge,
// its low part, and the range's end)? The pair loop then takes each
// distance once for both (AccurateSharedTerms::sum from W's radii), and
// one level per register for both (shared_level from W's).
bool same_radii(const QuantityPlan& value, const QuantityPlan& over_r) {
    if (value.shared_terms.size() != over_r.shared_terms.size()) return false;
    for (std::size_t j = 0; j < value.shared_terms.size(); ++j) {
        const TermPlan& v = value.inner[value.shared_terms[j].piece].terms[value.shared_terms[j].term];
        const TermPlan& g = over_r.inner[over_r.shared_terms[j].piece].terms[over_r.shared_terms[j].term];
        if (v.edge != g.edge || v.edge_lo != g.edge_lo || value.shared_terms[j].hi != over_r.shared_terms[j].hi)
            return false;
    }
    return true;
}

// The index in shared_pairs of a combination in D dimensions with W's and
// W'/r's shared terms (indices in shared_shapes, each listed once) at the
// same radii, or -1.
int shared_pair_index(int dim, const QuantityPlan& value, const QuantityPlan& over_r) {
    if (dim < 2 || value.shared_fused < 0 || over_r.shared_fused < 0 || !same_radii(value, over_r)) return -1;
    for (std::size_t i = 0; i < shared_pair_count; ++i)
        if (shared_pairs[i].value == static_cast<std::size_t>(value.shared_fused) &&
            shared_pairs[i].over_r == static_cast<std::size_t>(over_r.shared_fused))
            return static_cast<int>(i);
    return -1;
}

// The index in pieces_pairs of a kernel in D dimensions whose W and W'/r
// are pieces of fused terms at the same breakpoints, or -1 (always in 1D,
// whose pair loop takes the sign of x).
int pieces_pair_index(int dim, const QuantityPlan& value, const QuantityPlan& over_r) {
    if (dim < 2 || value.pieces_fused < 0 || over_r.pieces_fused < 0 || value.inner.size() != over_r.inner.size())
        return -1;
    for (std::size_t p = 0; p < value.inner.size(); ++p)
        if (value.inner[p].lo != over_r.inner[p].lo) return -1;
    for (std::size_t i = 0; i < pieces_pair_count; ++i)
        if (pieces_pairs[i].value == static_cast<std::size_t>(value.pieces_fused) &&
            pieces_pairs[i].over_r == static_cast<std::size_t>(over_r.pieces_fused))
            return static_cast<int>(i);
    return -1;
}

}  // namespace

std::shared_ptr<const Plan> make_plan(const table::Kernel& k, std::shared_ptr<const table::Kernel> owner) {
    if (k.support != 1.0) fail("kernel " + std::string(k.spec) + " has support " + show(k.support) + ", not 1");
    if (k.dim < 1 || k.dim > 3) fail("kernel " + std::string(k.spec) + " has dimension " + std::to_string(k.dim));
    auto plan = std::make_shared<Plan>();
    plan->table = &k;
    plan->owner = std::move(owner);
    plan->odd = k.parity < 0;
    for (int q = 0; q < table::quantity_count; ++q) plan->quantities[static_cast<std::size_t>(q)] = quantity_plan(k, q);
    const QuantityPlan& value = plan->quantities[static_cast<std::size_t>(table::QuantityId::value)];
    const QuantityPlan& over_r = plan->quantities[static_cast<std::size_t>(table::QuantityId::grad_over_r)];
    plan->whole_pair = whole_pair_index(k.dim, value.whole, over_r.whole);
    if (plan->whole_pair >= 0 && !one_split_grid(value, over_r)) plan->whole_pair = -1;
    plan->shared_pair = shared_pair_index(k.dim, value, over_r);
    plan->pieces_pair = pieces_pair_index(k.dim, value, over_r);
    return plan;
}

}  // namespace mollify::detail
