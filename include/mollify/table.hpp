// The format of the tables `mollify-gen emit` writes into generated/: the
// contract between the exact generator and the double-precision runtime.
// Every number in a table is a correctly rounded double of an exact value
// (written beside it, in the generated file, as a comment); coefficients
// and edges also carry their rounding error, correctly rounded (c_lo,
// edge_lo: double-double values for Precision::accurate).
//
// A quantity (W, W', ..., the potential) is a list of pieces over r >= 0,
// the last one reaching to infinity (zero, or the Green's function for
// potentials). A piece is a sum of terms; a term is
//     (edge - v)^edge_power * r^low * sum_k c[k] v^k * basis(r),
// with v = r (Var::r) or v = r^2 (Var::r2; then the factor is edge^2 - r^2)
// or v = r - centre (Var::shifted: a Taylor piece about a centre, where the
// closed form of a missing Wendland function cancels or a potential's
// polynomial does; centre = centre + centre_lo exactly enough, the rational
// centre's double and its rounding),
// `edge` the term's own edge: the piece's upper breakpoint for a single
// kernel, the radius a_j of the term w_j psi(r/a_j) it comes from for a
// combination (Franz (4.17); a_j may lie beyond the piece). The factored
// form keeps the evaluation accurate near the edge: expanded powers of r
// lose accuracy there (SWIFT's Wendland C6 loses up to 1e-2 at r = 0.98).
#pragma once

#include <cmath>
#include <limits>

namespace mollify::table {

enum class Basis : unsigned char {
    one,         // 1
    sqrt_power,  // S(r)^s_power, S = sqrt(1 - r^2)
    arcsech,     // log((1 + S(r)) / r)
    log,         // log r
    arcsin,      // arcsin r
};

// Their names in C++ and in catalogue.json.
constexpr const char* basis_name(Basis b) {
    switch (b) {
        case Basis::one: return "one";
        case Basis::sqrt_power: return "sqrt_power";
        case Basis::arcsech: return "arcsech";
        case Basis::log: return "log";
        case Basis::arcsin: return "arcsin";
    }
    return "?";
}

enum class Var : unsigned char { r, r2, shifted };

constexpr const char* var_name(Var v) {
    switch (v) {
        case Var::r: return "r";
        case Var::r2: return "r2";
        case Var::shifted: return "shifted";
    }
    return "?";
}

struct Term {
    Basis basis;
    int s_power;
    Var var;
    double edge;  // the factor is (edge - v)^edge_power; the piece's hi where edge_power = 0
    int edge_power;
    int low;  // power of r in front of the polynomial
    const double* c;
    int n;
    double centre = 0, centre_lo = 0;  // Var::shifted: v = (r - centre) - centre_lo
    // The low parts c[k] + c_lo[k] and edge + edge_lo of the exact values,
    // to ~2^-106 (Precision::accurate); nullptr: c is exact.
    const double* c_lo = nullptr;
    double edge_lo = 0;
    // Precision::accurate: the first `plain` Horner steps (the highest
    // coefficients, from c[n - 1] down to c[n - 1 - plain]) in plain double
    // arithmetic, their low parts unused, the rest compensated. Set by the
    // generator where it proves those steps' rounding below 2^-66 of the
    // piece's scale (a Taylor piece's terms fall geometrically, so only its
    // last steps carry the error); 0: every step compensated.
    int plain = 0;
    // Precision::accurate of a polynomial in q (Var::r) where the generator
    // proves it: c[k] = content * m[k] exactly, the m[k] non-negative
    // integers, and Horner's rule on m exact at qa, q rounded to a multiple
    // of 2^-split (every partial product and sum fits in 53 bits), so that
    // p(q) = content (p_m(qa) + d) with d = p_m(q) - p_m(qa) from a plain
    // recurrence in q - qa, whose error the generator bounds below 2^-62 of
    // p_m on [0, edge], the term's domain (generator/emit_round.cpp:
    // split_of): ~3 operations a step, no two-sum, instead of compensated
    // Horner's ~11.
    // content + content_lo is the double-double of the exact content.
    // 0: compensated Horner.
    int split = 0;
    const double* m = nullptr;
    double content = 0, content_lo = 0;
};

// Term::split's exactness claim: Horner's rule on the n integers m (in
// [0, 2^53)) is exact at every multiple of 2^-split in [0, edge + 2^-split]:
// a_k = a_{k+1} qa + m_k is a multiple of 2^-split(n-1-k), so each partial
// product and sum is a double where its bound times 2^split(n-1-k) is below
// 2^53 (then also without an FMA). The bounds in long double, each step
// times 1 + 2^-40 (every quantity positive: upper bounds). The generator
// proves a split with it (generator/emit_round.cpp: split_of), a table
// file's reader checks one.
inline bool split_is_exact(const double* m, int n, double edge, int split) {
    const long double margin = 1 + 0x1p-40L;
    const long double reach = (static_cast<long double>(edge) * margin + std::ldexp(1.0L, -split)) * margin;
    long double bound = m[n - 1];
    for (int k = n - 2; k >= 0; --k) {
        const long double grid = std::ldexp(1.0L, split * (n - 1 - k));
        const long double product = bound * reach * margin;
        bound = (product + m[k]) * margin;
        if (product * grid >= 0x1p53L || bound * grid >= 0x1p53L) return false;
    }
    return m[n - 1] < 0x1p53;
}

// Term::split's content within 2^+-60: it joins the scale h^p
// (detail::content_in_scale), which Smoothing keeps within 2^+-900, and
// their product, and its low part, must stay normal doubles.
inline bool content_in_range(double content) {
    return std::abs(content) >= 0x1p-60 && std::abs(content) <= 0x1p60;
}

// An upper bound of |x| over the support 0 <= q <= 1 for a polynomial term
// (Basis::one, low >= 0, Var::r or r2), x as the accurate precision has it
// before the last product by the scale: sum |c_k| (or, for a split term,
// sum m_k where larger: its content may join the scale) times
// (|edge| + 1)^edge_power; +inf for any other term (and for non-finite
// coefficients). Below 2^100 (bounded_term), the last product's cross terms
// cannot overflow: detail::rounded_product_bounded.
constexpr double term_bound(const Term& t) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (t.basis != Basis::one || t.low < 0 || t.var == Var::shifted || t.edge_power < 0) return inf;
    double c = 0, m = 0;
    for (int k = 0; k < t.n; ++k) {
        c += t.c[k] < 0 ? -t.c[k] : t.c[k];
        if (t.split > 0) m += t.m[k];
    }
    double b = m > c ? m : c;  // (a NaN c stays NaN)
    for (int k = 0; k < t.edge_power; ++k) b *= (t.edge < 0 ? -t.edge : t.edge) + 1;
    return b == b ? b : inf;
}

constexpr bool bounded_term(const Term& t) { return term_bound(t) < 0x1p100; }

struct Piece {
    double lo, hi;  // [lo, hi), the last inner piece [lo, support]; the exterior (support, inf)
    const Term* terms;
    int nterms;
};

struct Quantity {
    const Piece* pieces;
    int npieces;
};

// Order of Kernel::quantities.
enum class QuantityId : int {
    value,
    dr,
    d2r,
    laplacian,
    grad_over_r,
    hess_radial,
    potential,
    dpotential,
    dpotential_over_r,
    potential_hess_radial,
};
inline constexpr int quantity_count = 10;

// The names of the quantities in QuantityId order (scene files, the
// generator's command line, catalogue.json).
inline constexpr const char* quantity_names[quantity_count] = {
    "value",     "dr",         "d2r",               "laplacian", "grad_over_r", "hess_radial",
    "potential", "dpotential", "dpotential_over_r", "potential_hess_radial"};

// The potential phi (Delta phi = W) and its derivatives: absent where a
// kernel has no potential (Kernel::has_potential), and not vanishing at the
// support edge (the Green's function outside it).
constexpr bool is_potential(QuantityId q) { return q >= QuantityId::potential; }

struct Kernel {
    const char* spec;  // canonical kernel spec, e.g. "wendland:k=2,l=1"
    int dim;
    double support;  // 1: the runtime scales by h
    int smoothness;  // C^s at the breakpoints and the edge; -1 discontinuous
    int order;       // radial moments r^2 .. r^(order-2) vanish
    int parity;      // 1D extension to x < 0: +1 even, -1 odd
    double normalisation;
    const char* normalisation_exact;
    bool has_potential;
    Quantity quantities[quantity_count];
};

inline constexpr double infinity = std::numeric_limits<double>::infinity();

// Reference evaluation of one quantity at r >= 0, straight from the table
// (the optimised runtime lives in <mollify/kernel.hpp>).
inline double evaluate(const Quantity& q, double r) {
    for (int p = 0; p < q.npieces; ++p) {
        const Piece& piece = q.pieces[p];
        // Pieces are [lo, hi); the support is closed, so the last piece
        // before the exterior also takes r = hi.
        const bool exterior = p + 1 == q.npieces, last_inner = p + 2 == q.npieces;
        if (!exterior && !(r < piece.hi || (last_inner && r == piece.hi))) continue;
        double sum = 0;
        for (int t = 0; t < piece.nterms; ++t) {
            const Term& term = piece.terms[t];
            const double v = term.var == Var::r ? r : term.var == Var::r2 ? r * r : (r - term.centre) - term.centre_lo;
            double poly = 0;
            for (int k = term.n; k-- > 0;) poly = poly * v + term.c[k];
            double x = poly;
            if (term.low != 0) x *= std::pow(r, term.low);
            if (term.edge_power != 0) {
                const double edge = term.var == Var::r ? term.edge - r : (term.edge - r) * (term.edge + r);
                x *= std::pow(edge, term.edge_power);
            }
            switch (term.basis) {
                case Basis::one: break;
                case Basis::sqrt_power: x *= std::pow(std::sqrt((1 - r) * (1 + r)), term.s_power); break;
                case Basis::arcsech: x *= std::log((1 + std::sqrt((1 - r) * (1 + r))) / r); break;
                case Basis::log: x *= std::log(r); break;
                case Basis::arcsin: x *= std::asin(r); break;
            }
            sum += x;
        }
        return sum;
    }
    return 0;
}

}  // namespace mollify::table
