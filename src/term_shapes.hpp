// The term shapes the evaluator compiles fused loops for: those of the
// catalogue's W and W'/r, listed by the generator (generated/src/
// term_shapes.def, generator/term_shapes.hpp). A plan records each term's
// index in the list (make_plan); src/evaluator.cpp instantiates one loop per
// entry. Terms of other shapes take the general loops, with the same bits.
// Each reading of the list defines the macro it takes; term_shapes_rest.inc
// defines the others to nothing, term_shapes_end.inc undefines all.
#pragma once

#include <mollify/table.hpp>

#include <algorithm>
#include <cstddef>
#include <iterator>

namespace mollify::detail {

struct TermShape {
    bool var_r, support_edge, exact;
    int n, edge_power;
    // table::Term::split in a combination's shared terms (shared_shapes:
    // the run-time form's loop then computes each grid once, as StaticKernel's
    // does), elsewhere 1 where there is one, 0 where not.
    int split;
    // table::Term::low, the power q^low: below 0 only in a piece that starts
    // above 0 (the cubic spline's W'/r), where the term is bounded.
    int low;
    friend constexpr bool operator==(const TermShape&, const TermShape&) = default;
};

inline constexpr TermShape term_shapes[] = {
#define MOLLIFY_TERM_SHAPE(var_r, support_edge, exact, n, edge_power, split, low) \
    {var_r, support_edge, exact, n, edge_power, split, low},
#include "term_shapes_rest.inc"
#include <src/term_shapes.def>
#include "term_shapes_end.inc"
    {},  // an end that matches no term (n = 0), so that an empty list is still an array
};

// The shapes that are a whole quantity (one inner piece of one term, 0
// outside): evaluated in one pass from r.
inline constexpr TermShape whole_shapes[] = {
#define MOLLIFY_WHOLE_SHAPE(var_r, support_edge, exact, n, edge_power, split, low) \
    {var_r, support_edge, exact, n, edge_power, split, low},
#include "term_shapes_rest.inc"
#include <src/term_shapes.def>
#include "term_shapes_end.inc"
    {},  // an end that matches no term (n = 0), so that an empty list is still an array
};

// The kernels' (W, W'/r) where both are whole (D = 2, 3): the pair loop
// (W and grad W at displacements) in one pass.
struct WholePair {
    TermShape value, over_r;
};
inline constexpr WholePair whole_pairs[] = {
#define MOLLIFY_WHOLE_PAIR(var_r, support_edge, exact, n, edge_power, split, low, g_var_r, g_support_edge, g_exact, g_n, \
                           g_edge_power, g_split, g_low)                                                                  \
    {{var_r, support_edge, exact, n, edge_power, split, low},                                                             \
     {g_var_r, g_support_edge, g_exact, g_n, g_edge_power, g_split, g_low}},
#include "term_shapes_rest.inc"
#include <src/term_shapes.def>
#include "term_shapes_end.inc"
    {},  // an end that matches no kernel
};

// The most terms of a listed combination (the generator's limit is
// generator/term_shapes.hpp's max_shared_terms; read here from its list).
inline constexpr std::size_t max_shared_terms = std::max({
    std::size_t{1},
#define MOLLIFY_SHARED_TERMS(m, ...) std::size_t{m},
#include "term_shapes_rest.inc"
#include <src/term_shapes.def>
#include "term_shapes_end.inc"
});

// A combination's m distinct terms (QuantityPlan::shared_terms) in order,
// for the fast precision (exact false): all m in one pass.
struct SharedShapes {
    std::size_t m;
    TermShape terms[max_shared_terms];
};
inline constexpr SharedShapes shared_shapes[] = {
#define MOLLIFY_SHARED_TERMS(m, ...) {m, {__VA_ARGS__}},
#include "term_shapes_rest.inc"
#include <src/term_shapes.def>
#include "term_shapes_end.inc"
    {},  // an end that matches no quantity (m = 0)
};

// The combinations' (W, W'/r) shared terms (D = 2, 3), indices in
// shared_shapes: the pair loop in one pass.
struct SharedPair {
    std::size_t value, over_r;
};
inline constexpr SharedPair shared_pairs[] = {
#define MOLLIFY_SHARED_PAIR(value, over_r) {value, over_r},
#include "term_shapes_rest.inc"
#include <src/term_shapes.def>
#include "term_shapes_end.inc"
    {},  // an end that matches no kernel
};

// The most pieces of a listed quantity of pieces (generator/term_shapes.hpp's
// max_pieces; read here from its list).
inline constexpr std::size_t max_pieces = std::max({
    std::size_t{1},
#define MOLLIFY_PIECES(m, ...) std::size_t{m},
#include "term_shapes_rest.inc"
#include <src/term_shapes.def>
#include "term_shapes_end.inc"
});

// A quantity of m inner pieces of one fused term each, 0 outside
// (QuantityPlan::pieces_fused: the cubic spline's W and W'/r), the
// pieces' shapes in order.
struct PieceShapes {
    std::size_t m;
    TermShape pieces[max_pieces];
};
inline constexpr PieceShapes piece_shapes[] = {
#define MOLLIFY_PIECES(m, ...) {m, {__VA_ARGS__}},
#include "term_shapes_rest.inc"
#include <src/term_shapes.def>
#include "term_shapes_end.inc"
    {},  // an end that matches no quantity (m = 0)
};

// The kernels' (W, W'/r) of such pieces at the same breakpoints (D = 2, 3),
// indices in piece_shapes: the pair loop in one pass.
struct PiecesPair {
    std::size_t value, over_r;
};
inline constexpr PiecesPair pieces_pairs[] = {
#define MOLLIFY_PIECES_PAIR(value, over_r) {value, over_r},
#include "term_shapes_rest.inc"
#include <src/term_shapes.def>
#include "term_shapes_end.inc"
    {},  // an end that matches no kernel
};

inline constexpr std::size_t term_shape_count = std::size(term_shapes) - 1;
inline constexpr std::size_t whole_shape_count = std::size(whole_shapes) - 1;
inline constexpr std::size_t whole_pair_count = std::size(whole_pairs) - 1;
inline constexpr std::size_t shared_shapes_count = std::size(shared_shapes) - 1;
inline constexpr std::size_t shared_pair_count = std::size(shared_pairs) - 1;
inline constexpr std::size_t piece_shapes_count = std::size(piece_shapes) - 1;
inline constexpr std::size_t pieces_pair_count = std::size(pieces_pairs) - 1;

}  // namespace mollify::detail
