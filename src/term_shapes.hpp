// The term shapes the evaluator compiles fused loops for: those of the
// catalogue's W and W'/r, listed by the generator (generated/src/
// term_shapes.def, generator/term_shapes.hpp). A plan records each term's
// index in the list (make_plan); src/evaluator.cpp instantiates one loop per
// entry. Terms of other shapes take the general loops, with the same bits.
// Each reading of the list defines the macro it takes; term_shapes_rest.inc
// defines the others to nothing, term_shapes_end.inc undefines all.
#pragma once

#include <mollify/detail/evaluate.hpp>
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

// Does a whole quantity's loop of this shape take its edge in units of 2^e
// (detail::unit_edge_power's rule, the term's size aside: the plan sends a
// whole quantity whose own rule differs to the blocks)?
constexpr bool unit_edge_shape(const TermShape& s) {
    return s.var_r && s.support_edge && s.low == 0 && s.edge_power >= 1 && s.edge_power <= max_unit_edge_power;
}

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

// The longest list of a listed combination's shared terms or of a
// quantity's pieces (the generator's limits are generator/term_shapes.hpp's
// max_shared_terms and max_pieces; read here from its lists).
inline constexpr std::size_t max_list_length = std::max({
    std::size_t{1},
#define MOLLIFY_SHARED_TERMS(m, ...) std::size_t{m},
#define MOLLIFY_PIECES(m, ...) std::size_t{m},
#include "term_shapes_rest.inc"
#include <src/term_shapes.def>
#include "term_shapes_end.inc"
});

// A list of m shapes in order: a combination's distinct terms
// (QuantityPlan::shared_terms; for the fast precision, exact false), or a
// quantity's pieces of one fused term each, 0 outside
// (QuantityPlan::pieces_fused: the cubic spline's W and W'/r).
struct ShapeList {
    std::size_t m;
    TermShape shapes[max_list_length];
};
inline constexpr ShapeList shared_shapes[] = {
#define MOLLIFY_SHARED_TERMS(m, ...) {m, {__VA_ARGS__}},
#include "term_shapes_rest.inc"
#include <src/term_shapes.def>
#include "term_shapes_end.inc"
    {},  // an end that matches no quantity (m = 0)
};
inline constexpr ShapeList piece_shapes[] = {
#define MOLLIFY_PIECES(m, ...) {m, {__VA_ARGS__}},
#include "term_shapes_rest.inc"
#include <src/term_shapes.def>
#include "term_shapes_end.inc"
    {},  // an end that matches no quantity (m = 0)
};

// A kernel's (W, W'/r) lists (D = 2, 3), indices in one of those: the
// pair loop in one pass. The combinations' shared terms (in shared_shapes)
// and the kernels of pieces at the same breakpoints (in piece_shapes).
struct ListPair {
    std::size_t value, over_r;
};
inline constexpr ListPair shared_pairs[] = {
#define MOLLIFY_SHARED_PAIR(value, over_r) {value, over_r},
#include "term_shapes_rest.inc"
#include <src/term_shapes.def>
#include "term_shapes_end.inc"
    {},  // an end that matches no kernel
};
inline constexpr ListPair pieces_pairs[] = {
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

// Each entry as an object of its own, for the evaluator's loops that take
// a shape by reference as a template argument: C++20 allows a reference to
// an array's element there (a subobject), and GCC takes it, but clang 14
// does not.
template <std::size_t I>
inline constexpr TermShape term_shape = term_shapes[I];
template <std::size_t I>
inline constexpr TermShape whole_shape = whole_shapes[I];
template <std::size_t I>
inline constexpr WholePair whole_pair = whole_pairs[I];
template <std::size_t I>
inline constexpr ShapeList shared_list = shared_shapes[I];
template <std::size_t I>
inline constexpr ShapeList piece_list = piece_shapes[I];

}  // namespace mollify::detail
