#include "target_code.hpp"

#include "error.hpp"
#include "rounding.hpp"
#include "series.hpp"

#include <mollify/detail/evaluate.hpp>
#include <mollify/smoothing.hpp>

#include <cctype>
#include <cmath>

namespace mollify::gen {

namespace {

CodePiece code_piece(const RoundedPiece& p, std::vector<CodeConstant>& constants) {
    CodePiece out{p.lo, p.hi, p.note, {}};
    for (const RoundedTerm& t : p.terms) {
        out.terms.push_back({&t, constants.size()});
        for (std::size_t k = 0; k < t.c.size(); ++k)
            constants.push_back({t.c[k], t.exact[k], k < t.exact_value.size() ? t.exact_value[k] : std::nullopt});
    }
    return out;
}

// The coefficient of log r in a 2D potential's Green's function (evaluate.hpp's log_coefficient).
std::optional<std::size_t> log_coefficient(const CodePiece& exterior) {
    for (const CodeTerm& t : exterior.terms)
        if (t.term->basis == table::Basis::log) return t.first;
    return std::nullopt;
}

std::string times(const std::string& a, const std::string& b) { return a + " * " + b; }

// The rounded terms as the runtime's tables hold them (what its tests read).
std::vector<table::Term> table_terms(const RoundedPiece& p) {
    std::vector<table::Term> terms;
    for (const RoundedTerm& t : p.terms)
        terms.push_back({.basis = t.basis, .s_power = t.s_power, .var = t.var, .edge = t.edge,
                         .edge_power = t.edge_power, .low = t.low, .c = t.c.data(), .n = static_cast<int>(t.c.size())});
    return terms;
}

// The limit at q = 0 of a quantity singular there, by the runtime's rule
// (detail::limit_at_origin) on the same rounded terms: +-inf, or nullopt
// where it is not singular or the rule cannot tell (NaN).
std::optional<double> at_origin(const RoundedPiece& first) {
    const std::vector<table::Term> terms = table_terms(first);
    const double limit = detail::limit_at_origin({first.lo, first.hi, terms.data(), static_cast<int>(terms.size())});
    if (std::isnan(limit)) return std::nullopt;
    return limit;
}

// The runtime's test (detail::singular_piece) on the same rounded terms.
bool singular(const RoundedPiece& first) {
    const std::vector<table::Term> terms = table_terms(first);
    return detail::singular_piece({first.lo, first.hi, terms.data(), static_cast<int>(terms.size())});
}

CodeConstant code_constant(const Exact& x) { return {round_to_double(x), x.to_string(), x}; }

}  // namespace

CodeQuantity::NearOrigin leading_order(const ClosedForm& first, const std::string& what) {
    const LeadingOrder o = leading_order_at_zero(first);
    // f(q0) against q0^low (plain + logarithm log q0) at the bound q0 = 2^-150:
    // the terms beyond are O(q0) of it; 800 bits, since the closed forms' own
    // singular terms may cancel (S/q - 1/q) by up to q0^-3 there.
    constexpr unsigned bits = 800;
    const unsigned digits = bits * 30103 / 100000 + 2;
    const Real q0(detail::near_origin_bound, digits);
    const Real f = first.evaluate(q0, bits).first;
    Real lead = o.plain.evaluate(bits).first;
    if (!o.logarithm.is_zero()) lead += o.logarithm.evaluate(bits).first * boost::multiprecision::log(q0);
    lead *= boost::multiprecision::pow(q0, o.low);
    if (!(boost::multiprecision::abs(f - lead) <= boost::multiprecision::ldexp(boost::multiprecision::abs(lead), -90)))
        fail("internal: " + what + ": the leading order at 0 is not the closed form's value at r/h = 2^-150");
    return {o.low, code_constant(o.plain), code_constant(o.logarithm)};
}

CodeKernel code_kernel(const TargetKernel& k) {
    const ExactKernel& kernel = k.facts.kernel;
    const double norm = round_to_double(kernel.normalisation);
    CodeKernel out{k.facts.spec, kernel.dim, "mollify_" + k.facts.id, {norm, kernel.normalisation.to_string(), kernel.normalisation}, {}, {}};
    for (int i = 0; i < table::quantity_count; ++i) {
        const auto& rounded = k.tables[static_cast<std::size_t>(i)];
        if (!rounded) continue;
        if (rounded->empty()) fail("internal: quantity " + std::string(table::quantity_names[i]) + " without pieces");
        const auto id = static_cast<table::QuantityId>(i);
        CodeQuantity q{id, table::quantity_names[i], detail::scale_power(id, kernel.dim), {}, {}, std::nullopt};
        for (std::size_t p = 0; p + 1 < rounded->size(); ++p) q.inside.push_back(code_piece((*rounded)[p], out.constants));
        q.exterior = code_piece(rounded->back(), out.constants);
        q.at_origin = at_origin(rounded->front());
        if (singular(rounded->front())) {
            const Radial* exact = quantity_of(k.facts, i);
            if (!exact) fail("internal: quantity " + q.name + " without its closed form");
            if (id == table::QuantityId::potential && kernel.dim == 2)  // (its + c log h is not in the leading order)
                fail("internal: a 2D potential singular at 0 (" + k.facts.spec + ")");
            q.near_origin = leading_order(exact->pieces.front(), k.facts.spec + " D" + std::to_string(kernel.dim) + " " + q.name);
        }
        if (id == table::QuantityId::potential && kernel.dim == 2) {
            q.log_h_coefficient = log_coefficient(q.exterior);
            if (!q.log_h_coefficient) fail("internal: a 2D potential without log r outside (" + k.facts.spec + ")");
        }
        out.quantities.push_back(std::move(q));
    }
    return out;
}

CodeQuantity code_quantity(const std::string& name, const std::vector<RoundedPiece>& rounded,
                           std::vector<CodeConstant>& constants) {
    if (rounded.empty()) fail("internal: " + name + " without pieces");
    CodeQuantity q{table::QuantityId::value, name, 0, {}, {}, std::nullopt};
    for (std::size_t p = 0; p + 1 < rounded.size(); ++p) q.inside.push_back(code_piece(rounded[p], constants));
    q.exterior = code_piece(rounded.back(), constants);
    return q;
}

std::string inside_term(const Syntax& s, const CodeTerm& ct) {
    const RoundedTerm& t = *ct.term;
    std::string v;
    switch (t.var) {
        case table::Var::r: v = "q"; break;
        case table::Var::r2: v = "q * q"; break;
        case table::Var::shifted:
            if (!s.unit_h)
                v = s.call("shifted", {"r", "h", s.literal(t.centre), s.literal(t.centre_lo)});
            else if (t.centre_lo == 0)
                v = "(q - " + s.literal(t.centre) + ")";
            else  // x - c_lo as x + (-c_lo): the same rounding, no "- -"
                v = "((q - " + s.literal(t.centre) + ") " + (t.centre_lo < 0 ? "+ " : "- ") + s.literal(std::fabs(t.centre_lo)) + ")";
            break;
    }
    std::string x = s.horner(ct.first, t.c.size(), v);
    if (t.low != 0) x = times(x, s.power("q", t.low));
    if (t.edge_power != 0) {
        std::string d = t.edge == 1.0 ? std::string("e")
                        : s.unit_h    ? "(" + s.literal(t.edge) + " - q)"
                                      : s.call("to_edge", {"r", "h", s.literal(t.edge)});
        if (t.var == table::Var::r2) d = "(" + d + " * (" + s.literal(t.edge) + " + q))";
        x = times(x, s.power(d, t.edge_power));
    }
    if (t.basis == table::Basis::sqrt_power) x = times(x, s.power(s.call("sqrt_s", {"q", "e"}), t.s_power));
    switch (t.basis) {
        case table::Basis::one:
        case table::Basis::sqrt_power: return x;
        case table::Basis::arcsech:
            return t.low > 0 ? s.call("times_arcsech", {x, "q", "e"}) : times(x, s.call("arcsech", {"q", "e"}));
        case table::Basis::log: return t.low > 0 ? s.call("times_log", {x, "q", "e"}) : times(x, s.call("log_q", {"q", "e"}));
        case table::Basis::arcsin: return times(x, s.call("arcsin", {"q", "e"}));
    }
    fail("internal: unknown basis");
}

std::string exterior_term(const Syntax& s, const CodeTerm& ct) {
    const RoundedTerm& t = *ct.term;
    if (t.edge_power != 0 || t.var == table::Var::shifted || (t.basis != table::Basis::one && t.basis != table::Basis::log))
        fail("internal: the exterior of a potential is a Green's function in r");
    std::string x = s.horner(ct.first, t.c.size(), t.var == table::Var::r ? std::string("r") : std::string("r * r"));
    if (t.low != 0) x = times(x, s.power("r", t.low));
    if (t.basis == table::Basis::log) x = times(x, s.log + "(r)");
    return x;
}

std::string inside_piece(const Syntax& s, const CodeQuantity& q, std::size_t p) {
    const std::string sum = piece_sum(s, q.inside[p], false);
    if (p != 0 || !q.at_origin) return sum;
    return s.call("at_origin", {sum, *q.at_origin > 0 ? s.infinity : "-" + s.infinity});
}

std::string piece_sum(const Syntax& s, const CodePiece& p, bool exterior) {
    if (p.terms.empty()) return s.literal(0.0);
    std::string out;
    for (const CodeTerm& t : p.terms) {
        const std::string x = exterior ? exterior_term(s, t) : inside_term(s, t);
        out += out.empty() ? x : "\n        + " + x;
    }
    return out;
}

bool uses(const std::string& code, const std::string& name) {
    auto identifier_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    for (std::size_t i = code.find(name); i != std::string::npos; i = code.find(name, i + 1)) {
        const bool starts = i == 0 || !identifier_char(code[i - 1]);
        const bool ends = i + name.size() == code.size() || !identifier_char(code[i + name.size()]);
        if (starts && ends) return true;
    }
    return false;
}

std::string without_comments(std::string code, const std::string& open, const std::string& close) {
    for (std::size_t i = code.find(open); i != std::string::npos; i = code.find(open, i)) {
        const std::size_t end = code.find(close, i + open.size());
        code.replace(i, (end == std::string::npos ? code.size() : end) - i, " ");
    }
    return code;
}

std::string quantity_description(table::QuantityId q) {
    switch (q) {
        case table::QuantityId::value: return "W";
        case table::QuantityId::dr: return "W' = dW/dr";
        case table::QuantityId::d2r: return "W''";
        case table::QuantityId::laplacian: return "Laplacian W'' + (D-1) W'/r";
        case table::QuantityId::grad_over_r: return "W'/r (grad W = (W'/r) x, finite at r = 0)";
        case table::QuantityId::hess_radial: return "(W'' - W'/r)/r^2 (Hessian = this x x^T + (W'/r) I)";
        case table::QuantityId::potential: return "phi, Delta phi = W, the Green's function outside the support";
        case table::QuantityId::dpotential: return "phi' = dphi/dr";
        case table::QuantityId::dpotential_over_r: return "phi'/r (grad phi = (phi'/r) x)";
        case table::QuantityId::potential_hess_radial: return "(phi'' - phi'/r)/r^2";
    }
    return "?";
}

}  // namespace mollify::gen
