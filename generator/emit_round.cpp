#include "emit_round.hpp"

#include "emit_checks.hpp"
#include "emit_plan.hpp"
#include "rounding.hpp"

#include <algorithm>

namespace mollify::gen {

namespace {

// A term's coefficients rounded, with their low parts c - round(c); no low
// parts where every one is 0 (the coefficients are exact).
void set_coefficients(RoundedTerm& t, std::vector<double> c, std::vector<double> c_lo, std::vector<std::string> exact) {
    t.c = std::move(c);
    t.exact = std::move(exact);
    if (!std::all_of(c_lo.begin(), c_lo.end(), [](double x) { return x == 0; })) t.c_lo = std::move(c_lo);
}

// The one term of a Taylor piece: sum_k a_k v^k, v = r - centre
// (table::Var::shifted), the centre as a double and its rounding error.
RoundedTerm centred_term(const CentredPiece& p, double hi) {
    RoundedTerm t{p.s_power ? table::Basis::sqrt_power : table::Basis::one, p.s_power, table::Var::shifted, hi, 0, 0,
                  p.low, {}, {}, {}};
    const std::vector<double> a = rounded(p);
    std::vector<double> a_lo;
    std::vector<std::string> exact;
    for (std::size_t k = 0; k < a.size(); ++k) {
        a_lo.push_back(centred_low_part(p, k, a[k]));
        exact.push_back(p.a[k].to_string(p.centre));
    }
    t.exact_value.assign(a.size(), std::nullopt);
    set_coefficients(t, a, std::move(a_lo), std::move(exact));
    t.centre = round_to_double(p.centre);
    t.centre_lo = low_part(p.centre, t.centre);
    return t;
}

RoundedTerm rounded_term(const EmittedTerm& term, const std::optional<Q>& hi, double hi_double) {
    std::vector<double> c, c_lo;
    std::vector<std::string> exact;
    for (const Exact& x : term.c) {
        c.push_back(round_to_double(x));
        c_lo.push_back(low_part(x, c.back()));
        exact.push_back(x.to_string());
    }
    RoundedTerm t{term.basis, term.s_power, table::Var::r, hi_double, 0, term.edge_power, term.low, {}, {}, {}};
    set_coefficients(t, std::move(c), std::move(c_lo), std::move(exact));
    t.exact_value.assign(term.c.begin(), term.c.end());
    if (term.centre) {  // a Taylor polynomial of a polynomial piece: basis 1
        t.basis = table::Basis::one;
        t.s_power = 0;
        t.var = table::Var::shifted;
        t.edge_power = 0;
        t.centre = round_to_double(*term.centre);
        t.centre_lo = low_part(*term.centre, t.centre);
        return t;
    }
    t.var = term.square ? table::Var::r2 : table::Var::r;
    const std::optional<Q> edge = term.edge ? term.edge : hi;
    if (edge) {
        t.edge = round_to_double(*edge);
        t.edge_lo = low_part(*edge, t.edge);
    }
    return t;
}

}  // namespace

std::optional<std::vector<RoundedPiece>> rounded_quantity(const Radial* f, bool potential_like,
                                                          const std::vector<Radial>& parts) {
    if (!f) return std::nullopt;
    const std::vector<EmittedPiece> emitted = plan_quantity(*f, potential_like, parts);
    check_emitted(*f, emitted);
    std::vector<RoundedPiece> out;
    for (const auto& [lo, hi, terms, note, series, centred] : emitted) {
        RoundedPiece p{round_to_double(lo), hi ? round_to_double(*hi) : table::infinity, {},
                       "[" + short_string(lo) + ", " + (hi ? short_string(*hi) : std::string("inf")) + ")" +
                           (note.empty() ? "" : ", " + note)};
        if (centred) p.terms.push_back(centred_term(*centred, p.hi));
        for (const EmittedTerm& t : terms) p.terms.push_back(rounded_term(t, hi, p.hi));
        out.push_back(std::move(p));
    }
    return out;
}

}  // namespace mollify::gen
