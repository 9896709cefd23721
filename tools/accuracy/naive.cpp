// The naive forms' coefficients, from the generator's exact closed forms:
// per piece, the exact polynomial in v = q^2 (even or odd pieces, as the
// emitter chooses) or v = q, each coefficient correctly rounded once; for
// the pow form the largest power of (edge - v) dividing it is taken out
// exactly, as a textbook writes (1 - q)^n p(q).
#include "naive.hpp"

#include "kernel.hpp"
#include "rounding.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <utility>

namespace mollify::accuracy {

const char* form_name(Form f) {
    switch (f) {
        case Form::mollify: return "mollify";
        case Form::expanded: return "expanded";
        case Form::pow: return "pow";
    }
    return "?";
}

int NaivePolynomial::max_expanded() const {
    std::size_t n = 0;
    for (const auto& p : pieces) n = std::max(n, p.expanded.size());
    return static_cast<int>(n);
}

int NaivePolynomial::max_cofactor() const {
    std::size_t n = 0;
    for (const auto& p : pieces) n = std::max(n, p.cofactor.size());
    return static_cast<int>(n);
}

namespace {

using gen::Atom;
using gen::ClosedForm;
using gen::Exact;
using gen::Laurent;
using gen::Q;

// A piece's polynomial split by its constant factor pi^e (a kernel in 2D or
// 3D is q pi^e p(r); combinations keep one factor too, but nothing forces it).
using Parts = std::vector<std::pair<Atom, Laurent>>;

// Sum over the parts of factor * coefficient of v^i, correctly rounded.
std::vector<double> rounded(const Parts& parts, int low, int high) {
    std::vector<double> c;
    for (int i = low; i <= high; ++i) {
        Exact x;
        for (const auto& [atom, p] : parts) x += Exact::of(atom) * p.coefficient(i);
        c.push_back(gen::round_to_double(x));
    }
    return c;
}

std::pair<int, int> degree_range(const Parts& parts) {
    int low = std::numeric_limits<int>::max(), high = std::numeric_limits<int>::min();
    for (const auto& part : parts) {
        if (part.second.is_zero()) continue;
        low = std::min(low, part.second.low());
        high = std::max(high, part.second.high());
    }
    if (low > high) return {0, 0};  // the zero polynomial
    return {low, high};
}

// One piece [lo, hi) of a polynomial closed form, in both naive forms.
NaivePieceData naive_piece(const ClosedForm& f, const Q& lo, const Q& hi) {
    Parts parts;
    for (const auto& [key, p] : f.terms()) parts.emplace_back(key.factor, p);
    // v = q^2 when every part is even (or odd: then q v^k), as the emitter does.
    bool even = true, odd = true;
    for (const auto& part : parts) {
        even = even && part.second.is_even();
        odd = odd && part.second.shifted(-1).is_even();
    }
    NaivePieceData d;
    d.lo = gen::round_to_double(lo);
    d.hi = gen::round_to_double(hi);
    d.square = even || odd;
    const bool shift = odd && !even;
    if (d.square)
        for (auto& part : parts) part.second = part.second.shifted(shift ? -1 : 0).even_part_in_square();
    // Expanded: q^low' sum_k c_k v^k with the lowest power pulled out only
    // when negative (Laurent pieces); a polynomial keeps its zero low
    // coefficients, as a hand-written Horner form does.
    auto [low, high] = degree_range(parts);
    low = std::min(low, 0);
    d.low = (d.square ? 2 * low : low) + (shift ? 1 : 0);
    d.expanded = rounded(parts, low, high);
    // Pow form: (edge - v)^n cofactor(v), n the multiplicity of the root.
    const Q edge = d.square ? hi * hi : hi;
    d.edge = gen::round_to_double(edge);
    int n = std::numeric_limits<int>::max();
    for (const auto& part : parts)
        if (!part.second.is_zero()) n = std::min(n, part.second.multiplicity_of_root(edge));
    if (n == std::numeric_limits<int>::max()) n = 0;
    d.edge_power = n;
    if (n > 0) {
        Parts cof = parts;
        for (auto& part : cof)
            if (!part.second.is_zero()) part.second = *part.second.divided_by_linear_power(edge, n);
        auto [clow, chigh] = degree_range(cof);
        clow = std::min(clow, 0);
        if (clow != low) fail("naive pow form: the cofactor's lowest power moved");  // (edge - v)^n has a constant term
        d.cofactor = rounded(cof, clow, chigh);
    }
    return d;
}

gen::Radial radial_quantity(const gen::ExactKernel& k, QuantityId q) {
    if (q == QuantityId::value) return k.W;
    if (q == QuantityId::grad_over_r) return k.W.derivative().times(Laurent::monomial(Q(1), -1));
    fail(std::string("naive forms exist for value and grad_over_r only, not ") + quantity_names[static_cast<int>(q)]);
}

}  // namespace

NaivePolynomial naive_polynomial(const std::string& spec, int dim, QuantityId q) {
    const gen::ExactKernel k = gen::make_kernel(parse_spec(spec), dim);
    const gen::Radial f = radial_quantity(k, q);
    NaivePolynomial out;
    out.scale_power = detail::scale_power(q, dim);
    for (std::size_t i = 0; i < f.pieces.size(); ++i) {
        if (!f.pieces[i].has_only_basis_one()) {
            out.pieces.clear();
            out.why_not = spec + " is not a polynomial (sqrt/arcsech terms): no expanded form";
            return out;
        }
        out.pieces.push_back(naive_piece(f.pieces[i], f.breaks[i], f.breaks[i + 1]));
    }
    return out;
}

}  // namespace mollify::accuracy
