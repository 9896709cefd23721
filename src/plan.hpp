// The plan of a kernel: what detail/evaluate.hpp derives from a table at
// compile time (which terms continue an edge series, which pieces are one
// series, which factors exist, whether every low part is 0), derived once
// at run time when a Kernel is made, so that the evaluator's loops read
// flags and coefficients instead of being instantiated per table.
#pragma once

#include <mollify/table.hpp>

#include <array>
#include <memory>
#include <vector>

namespace mollify::detail {

struct TermPlan {
    table::Basis basis;
    int s_power;
    table::Var var;
    double edge, edge_lo;
    int edge_power;
    int low;
    const double* c;  // the table's coefficients, n of them
    std::vector<double> c_lo;  // their low parts (0 where the table has none)
    int n;
    double centre, centre_lo;
    bool exact;          // every c_lo is 0 (Coefficients::exact)
    bool has_factor;     // an edge power, a power of r or S^m (has_factor)
    bool continues;      // continues the previous term's edge series (continues_series)
    int step;            // edge_power minus the previous term's, where it continues
    int shape = -1;      // its index in term_shapes (a fused loop), or -1
    // The first entry of term_shapes with its fast loop's shape (variable,
    // edge, length, edge power; Precision::fast reads no low parts and
    // fuses continuing terms too), or -1.
    int fast_shape = -1;
    int plain = 0;  // table::Term::plain: its leading plain steps (Precision::accurate)
    // table::Term::split (0: none), its integer coefficients and content,
    // and split_constant(split).
    int split = 0;
    std::vector<double> m{};
    double content = 0, content_lo = 0, split_c = 0;
    bool bounded = false;  // table::bounded_term (fusable needs it)
    // The only term of a unit_edge quantity: its edge distance is m - r 2^-e
    // (detail::unit_distance), its quantity's scale has m^-P.
    bool unit_edge = false;
};

struct PiecePlan {
    double lo, hi;
    std::vector<TermPlan> terms;
    // One series sum_j c_j F w^j (edge_series): its coefficients c_j as in
    // series_coefficients.
    bool edge_series = false;
    std::vector<double> series_c, series_lo;
    bool series_exact = true;
};

struct QuantityPlan {
    bool present = false;  // the table has pieces for it
    std::vector<PiecePlan> inner;  // [0, support]
    PiecePlan exterior;            // (support, inf): nothing, or the Green's function
    bool polynomial_inside = true;  // every inner term has Basis::one: pieces selected branch-free
    bool zero_outside = true;
    bool singular_at_origin = false;
    double at_origin = 0;  // where singular: its limit at q = 0 (detail::limit_at_origin), taken where the terms give NaN
    // Where singular: the table's first piece and the kernel's spec, for its
    // leading order below r/h = 2^-150 (detail::near_origin_value).
    const table::Piece* first = nullptr;
    const char* spec = nullptr;
    double log_coefficient = 0;  // 2D potentials: c of c log r outside
    int whole = -1;  // one fused term, 0 outside: its index in whole_shapes, or -1
    // detail::unit_edge_power: P where the edge factor is taken in units of
    // 2^e (h = m 2^e) and the scale is h^p m^-P (accurate_scale), else 0.
    int unit_edge = 0;
    // Pieces that share terms (a combination of m radii: piece p holds the
    // terms of the radii beyond it, m(m+1)/2 in all, m distinct): each
    // distinct term once, as inner[piece].terms[term], held by the pieces
    // whose q lie in [lo, hi), in an order every piece's terms keep
    // (shared_terms_of). Empty where the pieces share no term or do not
    // nest so.
    struct SharedTerm {
        std::size_t piece, term;
        double lo, hi;
    };
    std::vector<SharedTerm> shared_terms;
    int shared_fused = -1;  // the shared terms' shapes: their index in shared_shapes, or -1
    // ... and Precision::accurate may take them too: no term reads low parts
    // the fast precision's shapes (exact false) would not (n == 1 or inexact).
    bool shared_accurate = false;
    // Several inner pieces of one fused term each, 0 outside (the cubic
    // spline's W and W'/r): their shapes' index in piece_shapes, or -1.
    int pieces_fused = -1;
};

struct Plan {
    const table::Kernel* table;
    std::shared_ptr<const table::Kernel> owner;  // tables loaded at run time; null for the compiled-in ones
    std::array<QuantityPlan, table::quantity_count> quantities;
    bool odd;
    int whole_pair = -1;  // W and W'/r both whole (one split grid where both split): their index in whole_pairs, or -1
    int shared_pair = -1;  // W and W'/r both a combination's shared terms: their index in shared_pairs, or -1
    int pieces_pair = -1;  // W and W'/r both pieces_fused at the same breakpoints: their index in pieces_pairs, or -1
};

// The plan of a table (checked: a term shape the evaluator cannot evaluate
// fails, naming the kernel).
std::shared_ptr<const Plan> make_plan(const table::Kernel& k, std::shared_ptr<const table::Kernel> owner);

}  // namespace mollify::detail
