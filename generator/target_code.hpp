// What the generic source-code targets (c, fortran, python) share: one
// kernel's tables laid out as code, language-neutrally. Every coefficient
// goes into one flat array of constants (writer order: quantity, piece,
// term, coefficient), each term is an expression in the variables of the
// runtime's Precision::fast evaluation (include/mollify/detail/evaluate.hpp):
//   q = r/h, e = (h - r)/h (the distance to the support edge, exact for the
//   last pieces), r and h themselves,
// and the factored form of the tables (table.hpp): Horner's rule in q, q^2
// or q - centre, times q^low, times a power of the distance to the term's
// edge, times S^m, S = sqrt(e (1 + q)), times arcsech q, log q or arcsin q.
// A language supplies its spelling (Syntax) and helper functions with the
// names below; the writers add the piece selection and the scale h^p.
#pragma once

#include "closed_form.hpp"
#include "target.hpp"

#include <mollify/detail/evaluate.hpp>

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace mollify::gen {

struct CodeConstant {
    double value;             // correctly rounded
    std::string exact;        // its exact value, for people
    std::optional<Exact> exact_value;  // where it is a constant q pi^e log p
};

struct CodeTerm {
    const RoundedTerm* term;
    std::size_t first;  // its coefficients: constants [first, first + term->c.size())
};

struct CodePiece {
    double lo, hi;
    std::string note;
    std::vector<CodeTerm> terms;
};

struct CodeQuantity {
    table::QuantityId id;
    std::string name;   // table::quantity_names
    int scale_power;    // f_h(r) = h^p f(r/h) (detail::scale_power)
    std::vector<CodePiece> inside;  // [lo, hi) in q, the last one closed at q = 1
    CodePiece exterior;             // r > h: no terms (0) or the Green's function at r
    // A 2D potential: phi(r/h) + c log h inside, c the constant of this index.
    std::optional<std::size_t> log_h_coefficient;
    // Singular at q = 0: its limit there, +-inf (detail::limit_at_origin, as
    // the runtime), taken where the first piece's terms give NaN (inf - inf
    // or 0 * inf: at q = 0, and where q^low overflows).
    std::optional<double> at_origin{};
    // Singular at q = 0 (detail::singular_piece, as the runtime): below
    // r/h = detail::near_origin_bound the leading order h^p q^low (plain + logarithm
    // log q) (the runtime's detail::near_origin_value), so that neither q^low
    // nor h^p overflows alone; plain and logarithm exact from the first
    // piece's closed form (leading_order), then correctly rounded.
    struct NearOrigin {
        int low;
        CodeConstant plain, logarithm;
    };
    std::optional<NearOrigin> near_origin{};
};

// The leading order at 0 of a closed form singular there, f(q) = q^low
// (plain + logarithm log q) (1 + O(q)), exactly (series.hpp,
// leading_order_at_zero), checked against f at q = detail::near_origin_bound
// at 800 bits; Error where they differ (`what` names the quantity).
CodeQuantity::NearOrigin leading_order(const ClosedForm& first, const std::string& what);

struct CodeKernel {
    std::string spec;
    int dim;
    std::string prefix;  // a C identifier made from the spec: mollify_<identifier(spec, dim)>
    CodeConstant normalisation;
    std::vector<CodeConstant> constants;
    std::vector<CodeQuantity> quantities;  // only those the kernel has
};

CodeKernel code_kernel(const TargetKernel& k);

// A function of a target's own (a writer rounds a Radial it derives with
// rounded_quantity), as a CodeQuantity named `name` (id and scale unused),
// its coefficients appended to `constants`. `rounded` must outlive it.
CodeQuantity code_quantity(const std::string& name, const std::vector<RoundedPiece>& rounded,
                           std::vector<CodeConstant>& constants);

// How a language spells what the term expressions need.
struct Syntax {
    std::function<std::string(std::size_t)> constant;  // constant i of the flat array
    // sum_k c_k v^k, the n coefficients from constant `first` on
    std::function<std::string(std::size_t first, std::size_t n, const std::string& v)> horner;
    std::function<std::string(const std::string& x, int n)> power;  // x^n, n an integer (maybe negative)
    std::function<std::string(double)> literal;                    // a double, exactly
    // Helpers every language defines (same meaning, evaluate.hpp's fast form):
    //   shifted(r, h, c, c_lo) = (r - c h)/h - c_lo
    //   to_edge(r, h, a)       = (a h - r)/h
    //   sqrt_s(q, e)           = sqrt(e (1 + q))
    //   arcsech(q, e), log_q(q, e): evaluate.hpp's basis<>
    //   times_arcsech(x, q, e), times_log(x, q, e): x times them, 0 at q = 0
    //     (for q^low with low > 0: the limit, not 0 * inf)
    //   arcsin(q, e) = atan2(q, sqrt_s(q, e))
    //   at_origin(x, limit) = limit where x is NaN, else x (CodeQuantity::at_origin)
    std::function<std::string(const std::string& name, const std::vector<std::string>& args)> call;
    std::string log;  // natural logarithm, for the Green's function
    std::string infinity;  // +inf
    // The variable q is the radius on support 1 itself (h = 1: the peers' unit
    // functions): shifted is q - c, one rounding, then c_lo, and to_edge a - q,
    // the values fma(-c, 1, q) and fma(a, 1, -q) give, without calling fma (a
    // libm call where the compiler's target has no FMA, e.g. SWIFT's -march=core2).
    bool unit_h = false;
};

// Inner piece p of q: its terms added in order; the first piece of a
// quantity singular at 0 its limit where they give NaN (CodeQuantity::at_origin).
std::string inside_piece(const Syntax& s, const CodeQuantity& q, std::size_t p);
// One term inside the support (variables q, e, r, h).
std::string inside_term(const Syntax& s, const CodeTerm& t);
// One term of the Green's function outside (variable r).
std::string exterior_term(const Syntax& s, const CodeTerm& t);
// A piece: its terms added in order, "0.0" without terms.
std::string piece_sum(const Syntax& s, const CodePiece& p, bool exterior);

// Does `code` use the variable `name` (a whole identifier)?
bool uses(const std::string& code, const std::string& name);
// `code` with its comments (from `open` to `close`, "/*" "*/" in C, "!" "\n" in
// Fortran) blanked, for uses(): a piece's note ("Taylor about 24/145 up to
// (r-c)^39") names variables the code may not use.
std::string without_comments(std::string code, const std::string& open, const std::string& close);

// The quantities' descriptions for comments ("W'/r: grad W = (W'/r) x").
std::string quantity_description(table::QuantityId q);

}  // namespace mollify::gen
