#include "emit_plan.hpp"

#include "edge_series.hpp"
#include "error.hpp"
#include "rounding.hpp"
#include "search_choices.hpp"
#include "series.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace mollify::gen {

namespace {

// The stable form (table.hpp): per basis, polynomials that are even or odd
// in r are written in v = r^2 (times r if odd), others in v = r; the largest
// power of (edge - v) dividing every coefficient polynomial is factored out
// and the rest kept in monomials of v.
std::vector<EmittedTerm> stable_terms(const ClosedForm& f, const std::optional<Q>& edge) {
    std::map<std::pair<Basis, int>, std::vector<std::pair<Atom, Laurent>>> groups;
    for (const auto& [k, p] : f.terms()) groups[{k.basis, k.s_power}].emplace_back(k.factor, p);
    std::vector<EmittedTerm> out;
    for (auto& [bs, parts] : groups) {
        bool even = true, odd = true;
        for (const auto& part : parts) {
            even = even && part.second.is_even();
            odd = odd && part.second.shifted(-1).is_even();
        }
        const bool square = even || odd;
        for (auto& part : parts)
            if (square) part.second = part.second.shifted(odd && !even ? -1 : 0).even_part_in_square();
        int n = 0;
        if (edge) {
            const Q root = square ? *edge * *edge : *edge;
            n = std::numeric_limits<int>::max();
            for (const auto& part : parts) n = std::min(n, part.second.multiplicity_of_root(root));
            for (auto& part : parts) part.second = *part.second.divided_by_linear_power(root, n);
        }
        int low = std::numeric_limits<int>::max(), high = std::numeric_limits<int>::min();
        for (const auto& part : parts) {
            low = std::min(low, part.second.low());
            high = std::max(high, part.second.high());
        }
        const int r_low = square ? 2 * low + (odd && !even ? 1 : 0) : low;
        EmittedTerm t{bs.first, bs.second, square, n, r_low, {}, n > 0 ? edge : std::nullopt};
        for (int i = low; i <= high; ++i) {
            Exact c;
            for (const auto& [atom, p] : parts) c += Exact::of(atom) * p.coefficient(i);
            t.c.push_back(c);
        }
        out.push_back(std::move(t));
    }
    return out;
}

std::vector<EmittedTerm> concat(std::vector<EmittedTerm> a, const std::vector<EmittedTerm>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

// The terms of a closed form in one basis (`basis`) or in all others.
ClosedForm basis_part(const ClosedForm& f, Basis basis, bool keep) {
    ClosedForm out;
    for (const auto& [k, p] : f.terms())
        if ((k.basis == basis) == keep) out += ClosedForm(p, k);
    return out;
}

// A polynomial piece as its Taylor polynomial at the edge, one term per
// power: sum_k a_k (edge - v)^k with v = r^2 (times r) when the piece is even
// (odd), v = r otherwise. Near the edge the terms decrease like (edge - v)^k,
// so the sum keeps its relative accuracy where the piece vanishes there
// (2D potentials: phi(1) = log(1)/(2 pi) = 0); nullopt for Laurent terms.
std::optional<std::vector<EmittedTerm>> edge_taylor_terms(const ClosedForm& f, const Q& edge) {
    bool even = true, odd = true;
    for (const auto& [k, p] : f.terms()) {
        if (!p.is_polynomial()) return std::nullopt;
        even = even && p.is_even();
        odd = odd && p.shifted(-1).is_even();
    }
    const bool square = even || odd, shift = odd && !even;
    std::map<int, Exact> taylor;  // coefficient of (edge - v)^k
    for (const auto& [k, p] : f.terms()) {
        const Laurent v_poly = square ? p.shifted(shift ? -1 : 0).even_part_in_square() : p;
        const std::vector<Q> t = v_poly.taylor_at(square ? edge * edge : edge);
        for (std::size_t j = 0; j < t.size(); ++j) taylor[static_cast<int>(j)] += Exact::of(k.factor) * t[j];
    }
    std::vector<EmittedTerm> out;
    for (const auto& [j, c] : taylor)
        if (!c.is_zero()) out.push_back({Basis::one, 0, square, j, shift ? 1 : 0, {c}, j > 0 ? std::optional(edge) : std::nullopt});
    return out;
}

// Sum of |terms| over |sum| of emitted terms (bases 1 and log r) at r: the
// factor by which their double evaluation loses accuracy (a heuristic).
double emitted_condition(const std::vector<EmittedTerm>& terms, const Q& r_exact, const Q& edge) {
    const double r = static_cast<double>(r_exact), e = static_cast<double>(edge);
    double sum = 0, magnitude = 0;
    for (const EmittedTerm& t : terms) {
        const double v = t.square ? r * r : r, factor = std::pow(std::abs((t.square ? e * e : e) - v), t.edge_power) *
                                                        std::pow(r, t.low) * (t.basis == Basis::log ? std::log(r) : 1);
        for (std::size_t k = 0; k < t.c.size(); ++k) {
            const double x = round_to_double(t.c[k]) * std::pow(v, static_cast<double>(k)) * factor;
            sum += x;
            magnitude += std::abs(x);
        }
    }
    return sum == 0 ? 1e300 : magnitude / std::abs(sum);
}

// Where the Taylor form at the edge takes over from the plain form on
// [0, edge]: the smallest of edge/8, ..., edge/2 at which it is conditioned
// no worse than the plain form (the Taylor terms grow away from the edge,
// the plain monomials cancel towards it).
Q taylor_split(const std::vector<EmittedTerm>& plain, const std::vector<EmittedTerm>& taylor, const Q& edge) {
    for (int j = 1; j < 4; ++j) {
        const Q at = edge * ratio(j, 8);
        if (emitted_condition(taylor, at, edge) <= std::max(1.5, emitted_condition(plain, at, edge))) return at;
    }
    return edge / 2;
}

// The first piece of a quantity whose closed form cancels near r = 0 (the
// sqrt/arcsech/arcsin forms of missing Wendland functions): its exact series
// there on [0, r0) (series.hpp), the closed form from r0 on.
std::optional<EmittedPiece> zero_series_piece(const ClosedForm& form, const Q& hi) {
    if (form.is_elementary()) return std::nullopt;
    const auto z = zero_series(form);
    if (!z) fail("internal: no convergent series at r = 0 for a sqrt/arcsech/arcsin closed form");
    const Q r0 = Q(1) / pow(Q(2), z->m);
    if (r0 >= hi) fail("internal: series piece beyond its closed form's piece");
    const std::string note = "series at 0 up to r^" + std::to_string(z->order) + ", truncation < " +
                             decimal(z->relative_bound, 2) + " relative (series.hpp)";
    return EmittedPiece{Q(0), r0, stable_terms(z->series, std::nullopt), note, true};
}

// The last piece of a quantity whose closed form cancels towards the support
// edge hi = 1 (the same forms): its exact series in S = sqrt(1 - r^2) there
// on [r1, 1] (edge_series.hpp), c r^low S^s written one term per power as
// c r^low (1 - r^2)^(s/2) (times S for odd s).
std::optional<EmittedPiece> edge_series_piece(const ClosedForm& form, const Q& lo, const Q& hi) {
    if (form.is_elementary() || hi != 1) return std::nullopt;
    const auto e = edge_series(form, lo);
    if (!e) return std::nullopt;
    std::vector<EmittedTerm> terms;
    for (const EdgeTerm& t : e->terms)
        terms.push_back({t.s % 2 ? Basis::sqrt_power : Basis::one, t.s % 2, true, t.s / 2, t.low, {t.c},
                         t.s / 2 > 0 ? std::optional(hi) : std::nullopt});
    const std::string note = "series at the edge in S = sqrt(1-r^2) up to S^" + std::to_string(e->order) +
                             ", truncation < " + decimal(e->relative_bound, 2) +
                             " of its leading term (edge_series.hpp)";
    return EmittedPiece{e->r1, hi, std::move(terms), note, true};
}

// A centred piece's a_k = a_double[k] + a_lo[k], each correctly rounded,
// once: a coefficient with arcsech c, arcsin c or log c in it by one
// evaluation where that decides both (rounding.hpp), else by two loops.
void round_coefficients(CentredPiece& p) {
    for (const CentredValue& a : p.a) {
        const Evaluator value = [&](unsigned bits) { return a.evaluate(p.centre, bits); };
        if (a.arcsech.is_zero() && a.arcsin.is_zero() && a.log.is_zero()) {
            p.a_double.push_back(round_to_double(value));
            p.a_lo.push_back(low_part(a.one, p.a_double.back()));
        } else {
            const auto [hi, lo] = round_to_double_double(value);
            p.a_double.push_back(hi);
            p.a_lo.push_back(lo);
        }
    }
}

// Between the series at 0 and at the edge, the closed forms with S, arcsech
// and arcsin cancel (up to 1e9 ulp): Taylor pieces about Pythagorean
// centres there (centred_series.hpp).
std::vector<EmittedPiece> middle_pieces(const ClosedForm& form, const Q& lo, const Q& hi) {
    if (hi >= 1) fail("internal: a sqrt/arcsech/arcsin closed form without its edge series");
    std::vector<EmittedPiece> out;
    for (CentredPiece& p : centred_pieces(form, lo, hi)) {
        round_coefficients(p);
        const std::string note = (p.low ? "r^" + std::to_string(p.low) + " " : std::string()) +
                                 (p.s_power ? "S^" + std::to_string(p.s_power) + " " : std::string()) +
                                 (p.low || p.s_power ? "times " : "") + "Taylor about " +
                                 short_string(p.centre) + " up to (r-c)^" +
                                 std::to_string(p.a.size() - 1) + ", truncation < " +
                                 decimal(p.tail / p.scale, 2) + " of min max(|f|, |r f'|) (centred_series.hpp)";
        out.push_back({p.lo, p.hi, {}, note, true, std::move(p)});
    }
    return out;
}

// The pieces of one quantity in their stable forms. Potential-like
// quantities (which do not vanish at the edge) are written on the piece next
// to the edge as exterior form + remainder, the remainder vanishing there to
// high order and so factored at the edge; where that piece starts at r = 0,
// whose exterior form is singular, it is split at half its length and its
// inner half keeps the plain form. 2D potentials, whose remainder has a
// log r term, keep their log r terms and write the polynomial part as its
// Taylor polynomial at the edge (edge_taylor_terms) instead. Closed forms
// that cancel near r = 0 start with their series piece (zero_series_piece).
std::vector<EmittedPiece> emitted_pieces(const Radial& f, bool potential_like) {
    std::vector<EmittedPiece> out;
    const std::size_t n = f.pieces.size();
    for (std::size_t i = 0; i < n; ++i) {
        Q lo = f.breaks[i];
        const Q hi = f.breaks[i + 1];
        const ClosedForm& form = f.pieces[i];
        if (i == 0)
            if (auto s = zero_series_piece(form, hi)) {
                lo = *s->hi;
                out.push_back(std::move(*s));
            }
        const ClosedForm remainder = form - f.outside;
        const bool last_potential = potential_like && i + 1 == n && !f.outside.is_zero();
        const bool green = last_potential && remainder.has_only_basis_one();
        const auto taylor = last_potential && !green && form.is_elementary()
                                ? edge_taylor_terms(basis_part(form, Basis::one, true), hi)
                                : std::nullopt;
        if (!green && !taylor) {
            auto edge = edge_series_piece(form, lo, hi);  // [r1, hi] of cancelling closed forms
            const Q upto = edge ? edge->lo : hi;
            if (lo < upto) {
                if (form.is_elementary()) out.push_back({lo, upto, stable_terms(form, hi), ""});
                else
                    for (EmittedPiece& c : middle_pieces(form, lo, upto)) out.push_back(std::move(c));
            }
            if (edge) out.push_back(std::move(*edge));
            continue;
        }
        std::vector<EmittedTerm> outer =
            green ? concat(stable_terms(f.outside, std::nullopt), stable_terms(remainder, hi))
                  : concat(stable_terms(basis_part(form, Basis::one, false), std::nullopt), *taylor);
        Q mid = lo;
        if (lo == 0) {
            mid = green ? hi / 2 : taylor_split(stable_terms(form, hi), outer, hi);
            out.push_back({lo, mid, stable_terms(form, mid), ""});
        }
        out.push_back({mid, hi, std::move(outer), green ? "" : "Taylor polynomial at the edge"});
    }
    out.push_back({f.support(), std::nullopt, stable_terms(f.outside, std::nullopt), ""});
    return out;
}

// The emitted piece of `pieces` (in order, the exterior last) holding r.
const EmittedPiece& piece_at(const std::vector<EmittedPiece>& pieces, const Q& r) {
    for (const EmittedPiece& p : pieces)
        if (!p.hi || r < *p.hi) return p;
    fail("internal: no emitted piece holds r = " + short_string(r));
}

bool same_factor(const EmittedTerm& a, const EmittedTerm& b) {
    return a.basis == b.basis && a.s_power == b.s_power && a.square == b.square && a.edge_power == b.edge_power &&
           a.low == b.low && a.edge == b.edge && a.centre == b.centre;
}

// Terms with the same factor (basis, v, (edge - v)^n, r^low) as one term,
// their polynomials added; terms that cancel to 0 dropped. In the order of
// first appearance, so emission stays deterministic.
std::vector<EmittedTerm> merged(const std::vector<EmittedTerm>& terms) {
    std::vector<EmittedTerm> out;
    for (const EmittedTerm& t : terms) {
        auto it = std::find_if(out.begin(), out.end(), [&](const EmittedTerm& o) { return same_factor(o, t); });
        if (it == out.end()) {
            out.push_back(t);
            continue;
        }
        if (it->c.size() < t.c.size()) it->c.resize(t.c.size());
        for (std::size_t k = 0; k < t.c.size(); ++k) it->c[k] += t.c[k];
    }
    for (EmittedTerm& t : out)
        while (!t.c.empty() && t.c.back().is_zero()) t.c.pop_back();
    std::erase_if(out, [](const EmittedTerm& t) { return t.c.empty(); });
    return out;
}

// The pieces of a quantity of a combination f = sum_j w_j f_j, f_j the
// quantity of psi_{a_j} (Franz (4.17); `parts` holds w_j f_j): on each
// interval between the breakpoints of all parts' emitted pieces, the sum of
// the parts' emitted terms there. A term of w_j psi_{a_j} stays factored at
// its own edge a_j, (a_j - r)^n p_j(r), where expanding the sum at the
// piece's upper breakpoint cancelled (up to 1e8 ulp); potentials add up the
// Green's functions of the parts outside their support (sum_j w_j = 1).
std::vector<EmittedPiece> combination_pieces(const Radial& f, const std::vector<Radial>& parts,
                                             bool potential_like) {
    std::vector<std::vector<EmittedPiece>> emitted;
    std::vector<Q> breaks = f.breaks;
    for (const Radial& part : parts) {
        emitted.push_back(emitted_pieces(part, potential_like));
        for (const EmittedPiece& p : emitted.back())
            if (p.lo < f.support()) breaks.push_back(p.lo);
    }
    std::sort(breaks.begin(), breaks.end());
    breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
    std::vector<EmittedPiece> out;
    for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
        const Q mid = (breaks[i] + breaks[i + 1]) / 2;
        std::vector<EmittedTerm> terms;
        for (const auto& pieces : emitted) terms = concat(std::move(terms), piece_at(pieces, mid).terms);
        out.push_back({breaks[i], breaks[i + 1], merged(terms), "per radius a_j, factored at a_j (Franz (4.17))"});
    }
    out.push_back({f.support(), std::nullopt, stable_terms(f.outside, std::nullopt), ""});
    return out;
}

// A closed form r^low P(r) (basis 1, P a polynomial; low < 0 for a Laurent
// polynomial such as a multipole factor's) as r^low times one Taylor
// polynomial about c: r^low sum_k a_k (r - c)^k, exact (a polynomial's
// Taylor series ends).
std::vector<EmittedTerm> centred_terms(const ClosedForm& form, const Q& c) {
    int low = 0;
    for (const auto& [key, p] : form.terms()) low = std::min(low, p.low());
    std::vector<Exact> a;
    for (const auto& [key, p] : form.terms()) {
        const std::vector<Q> t = p.shifted(-low).taylor_at(c);  // in c - r
        if (a.size() < t.size()) a.resize(t.size());
        for (std::size_t j = 0; j < t.size(); ++j) a[j] += Exact::of(key.factor) * (j % 2 ? -t[j] : t[j]);
    }
    while (!a.empty() && a.back().is_zero()) a.pop_back();
    if (a.empty()) return {};
    return {EmittedTerm{Basis::one, 0, false, 0, low, std::move(a), std::nullopt, c}};
}

bool is_polynomial_form(const ClosedForm& form) {
    if (!form.has_only_basis_one()) return false;
    for (const auto& [key, p] : form.terms())
        if (!p.is_polynomial()) return false;
    return true;
}

// Does the form vanish at an inner breakpoint lo > 0 (a Laurent polynomial,
// basis 1)? Then its Taylor polynomials near lo are centred at lo
// (taylor_centre): the quartic spline's multipole factor E_4 is 0 on
// [0, 1/5) and grows like r - 1/5 beyond, and its own form there, and one
// about a midpoint, cancelled near 1/5 (4e5 float ulps in SWIFT's D_soft_5).
bool vanishes_at(const ClosedForm& form, const Q& lo) {
    return lo > 0 && form.has_only_basis_one() && value_at(form, lo).is_zero();
}

// The sum of |terms| of emitted terms at r, each polynomial's |c_k v^k|
// summed and multiplied by its factor's modulus: the scale of the rounding
// error of their double evaluation.
class Magnitude {
public:
    explicit Magnitude(const std::vector<EmittedTerm>& terms) : terms_(terms) {
        for (const EmittedTerm& t : terms) {
            std::vector<double> c;
            for (const Exact& x : t.c) c.push_back(std::abs(round_to_double(x)));
            c_.push_back(std::move(c));
        }
    }
    double operator()(double r) const {
        double sum = 0;
        for (std::size_t i = 0; i < terms_.size(); ++i) {
            const EmittedTerm& t = terms_[i];
            const double v = std::abs(t.centre ? r - static_cast<double>(*t.centre) : t.square ? r * r : r);
            double poly = 0;
            for (std::size_t k = c_[i].size(); k-- > 0;) poly = poly * v + c_[i][k];
            double factor = std::pow(r, t.low);
            if (t.edge_power > 0) {
                const double e = static_cast<double>(*t.edge);
                factor *= std::pow(std::abs(t.square ? e * e - r * r : e - r), t.edge_power);
            }
            if (t.basis == Basis::log) factor *= std::abs(std::log(r));
            sum += poly * factor;
        }
        return sum;
    }

private:
    const std::vector<EmittedTerm>& terms_;
    std::vector<std::vector<double>> c_;
};

// The worst condition of `terms` for the polynomial `form` on [lo, hi]:
// max over 33 points of sum |terms| / max(|f|, |r f'|), the scale of the
// runtime's intrinsic error (an exact evaluator given r with one ulp of
// relative error misses f by |r f'| ulp).
// `scales` keeps max(|f|, |r f'|) per point: the candidate forms of a
// piece, and its halves, are measured at the same points.
double worst_condition(const Magnitude& magnitude, const ClosedForm& form, const ClosedForm& derivative,
                       const Q& lo, const Q& hi, std::map<Q, double>& scales) {
    double worst = 0;
    for (int i = 0; i <= 32; ++i) {
        const Q r = lo + (hi - lo) * ratio(i, 32);
        if (r == 0) continue;
        const double x = static_cast<double>(r);
        auto [it, inserted] = scales.try_emplace(r, 0.0);
        if (inserted)
            it->second = std::max(std::abs(round_to_double(form.at(r))), x * std::abs(round_to_double(derivative.at(r))));
        const double scale = it->second;
        if (scale == 0) continue;
        worst = std::max(worst, magnitude(x) / scale);
    }
    return worst;
}

// Potentials of high-degree kernels cancel between r = 0 and the edge in
// both of their forms (Wendland k = l = 4 in 3D: sum |terms| ~ 400 |phi| at
// r = 1/2, 938 ulp measured): where an emitted polynomial piece is
// conditioned worse than recentre_condition, its halves, quarters, ...
// (down to 1/64 of it) take the Taylor polynomial about their midpoints,
// whose terms fall off like |r - c|^k.
constexpr double recentre_condition = 2;

// Sub-pieces of `piece` on [lo, hi): its own terms where they are
// conditioned well enough (`own` true), else Taylor polynomials.
struct SubPiece {
    EmittedPiece piece;
    bool own;
};

SubPiece own_sub_piece(const EmittedPiece& piece, const Q& lo, const Q& hi) {
    return {{lo, hi, piece.terms, piece.note}, true};
}

// The centre of a sub-piece's Taylor polynomial: its lower end where the form
// vanishes there (vanishes_at), else its midpoint.
Q taylor_centre(const ClosedForm& form, const Q& lo, const Q& hi) { return vanishes_at(form, lo) ? lo : (lo + hi) / 2; }

// The Taylor polynomial about taylor_centre (centred_terms).
SubPiece taylor_sub_piece(const ClosedForm& form, const Q& lo, const Q& hi) {
    const Q c = taylor_centre(form, lo, hi);
    return {{lo, hi, centred_terms(form, c), "Taylor polynomial about " + short_string(c)}, false};
}

// `keep`: the condition within which the whole piece keeps its own terms
// (recentre_condition, or laurent_recentre_condition below); its halves,
// quarters, ... take recentre_condition.
void recentre(const EmittedPiece& piece, const Magnitude& own, const ClosedForm& form, const ClosedForm& derivative,
              const Q& lo, const Q& hi, int depth, std::vector<SubPiece>& out, std::map<Q, double>& scales,
              double keep = recentre_condition) {
    const double plain = worst_condition(own, form, derivative, lo, hi, scales);
    if (plain <= (depth == 0 ? keep : recentre_condition)) {
        out.push_back(own_sub_piece(piece, lo, hi));
        return;
    }
    SubPiece taylor = taylor_sub_piece(form, lo, hi);
    const double centred = worst_condition(Magnitude(taylor.piece.terms), form, derivative, lo, hi, scales);
    if (centred <= recentre_condition || depth == 6) {
        out.push_back(centred < plain ? std::move(taylor) : own_sub_piece(piece, lo, hi));
        return;
    }
    const Q c = (lo + hi) / 2;
    recentre(piece, own, form, derivative, lo, c, depth + 1, out, scales);
    recentre(piece, own, form, derivative, c, hi, depth + 1, out, scales);
}

// A Laurent polynomial r^low P(r) (centred_terms keeps r^low in front) is
// recentred only where its own terms cancel worse than this: until stop 91
// only polynomials were, and the quintic spline's W'/r and Laplacian on
// [1/3, 2/3) were 43 and 93.5 intrinsic ulps off in the fast form (3D), its
// 2D potential's derivative 50 (accuracy_test's fast bounds found them; own
// terms conditioned 100-315 there, the fast form's error ~0.3-0.5 ulp per
// unit). Milder ones keep their terms, within the fast bound as they are and
// one branch each: the Green's function joined to a potential's edge terms,
// GADGET-4's g-factors of the cubic spline (conditioned 5.7-24.9), which
// recentred at 16 took 4.9 against 1.35 ns a call (a loop over 4,096 random
// u: the sub-pieces' branches).
constexpr double laurent_recentre_condition = 32;

// The condition within which a piece of `form` keeps its own terms whole.
double keep_condition(const EmittedPiece& p, const ClosedForm& form) {
    return is_polynomial_form(form) || vanishes_at(form, p.lo) ? recentre_condition : laurent_recentre_condition;
}

// The sub-pieces recentre chose (search_choices.hpp); nullopt where they do
// not tile the piece. (Nothing to prove again: check_emitted compares every
// emitted piece's terms with its closed form exactly.)
std::optional<std::vector<SubPiece>> chosen_sub_pieces(const EmittedPiece& piece, const ClosedForm& form,
                                                       const RecentreChoices& choices) {
    std::vector<SubPiece> out;
    Q lo = piece.lo;
    for (const RecentreChoice& c : choices) {
        if (c.hi <= lo || c.hi > *piece.hi) return std::nullopt;
        out.push_back(c.own ? own_sub_piece(piece, lo, c.hi) : taylor_sub_piece(form, lo, c.hi));
        lo = c.hi;
    }
    if (lo != *piece.hi) return std::nullopt;
    return out;
}

// The emitted terms as text: with the closed form and the bounds, all
// recentre reads (its search's key).
std::string terms_text(const std::vector<EmittedTerm>& terms) {
    std::string s;
    for (const EmittedTerm& t : terms) {
        s += std::to_string(static_cast<int>(t.basis)) + " " + std::to_string(t.s_power) + " " + std::to_string(t.square) +
             " " + std::to_string(t.edge_power) + " " + std::to_string(t.low) + (t.edge ? " edge " + t.edge->str() : "") +
             (t.centre ? " centre " + t.centre->str() : "") + ":";
        for (const Exact& c : t.c) s += " " + c.to_string();
        s += ";";
    }
    return s;
}

// recentre's sub-pieces of `piece`, from the compiled-in choice where there is one.
std::vector<SubPiece> sub_pieces(const EmittedPiece& piece, const ClosedForm& form) {
    const std::uint64_t key = search_key("recentre " + terms_text(piece.terms), form, {piece.lo, *piece.hi});
    if (const RecentreChoices* known = known_choice<RecentreChoices>(key))
        if (auto sub = chosen_sub_pieces(piece, form, *known)) return std::move(*sub);
    std::vector<SubPiece> sub;
    std::map<Q, double> scales;
    recentre(piece, Magnitude(piece.terms), form, form.derivative(), piece.lo, *piece.hi, 0, sub, scales,
             keep_condition(piece, form));
    if (searching_afresh()) {
        RecentreChoices choices;
        for (const SubPiece& s : sub) choices.push_back({*s.piece.hi, s.own});
        record_choice(key, choices);
    }
    return sub;
}

// Which pieces recentre may split: every piece of a potential; of a kernel's
// quantity only the interior pieces, between two inner breakpoints (the
// quartic and quintic splines' middle pieces, whose expanded polynomials
// cancel: M6's W on [1/3, 2/3) reached 87 ulps in the fast form). A first
// piece keeps its polynomial about 0 (even there: W'(0) = 0 exactly), a last
// one its edge factor.
enum class Recentre { every_piece, interior_pieces };

bool may_recentre(const EmittedPiece& p, const Radial& f, Recentre which) {
    return which == Recentre::every_piece || (p.lo > 0 && p.hi && *p.hi < f.support());
}

std::vector<EmittedPiece> recentred(const Radial& f, std::vector<EmittedPiece> pieces, Recentre which) {
    std::vector<EmittedPiece> out;
    for (EmittedPiece& p : pieces) {
        const ClosedForm* form =
            p.hi && !p.series && !p.centred && may_recentre(p, f, which) ? &f.form_at((p.lo + *p.hi) / 2) : nullptr;
        if (!form || form->is_zero() || !form->has_only_basis_one()) {
            out.push_back(std::move(p));
            continue;
        }
        std::vector<SubPiece> sub = sub_pieces(p, *form);
        for (std::size_t i = 0; i < sub.size(); ++i) {
            if (i > 0 && sub[i].own && sub[i - 1].own) {  // neighbours in the piece's own form: one piece
                out.back().hi = sub[i].piece.hi;
                continue;
            }
            out.push_back(std::move(sub[i].piece));
        }
    }
    return out;
}

// A float result (ResultPrecision::float_value) needs the double evaluation
// within 2^-30 of max(|f|, |r f'|) only, not Precision::fast's ~32 double
// ulps: Horner's rounding, at most ~2n steps of 2^-53 times sum |terms|, is
// below 2^-36 of that scale (n <= 16) where a form is conditioned up to
// 2^12. So a polynomial piece conditioned so keeps its own terms (factored
// at the edge where it vanishes there) instead of Taylor sub-pieces or a
// potential's exterior form plus remainder.
constexpr double float_recentre_condition = 0x1p12;

// `planned` (the double plan of f, which tiles each of f's pieces) with every
// piece of f that is a Laurent polynomial (M4's potential has a 1/r term)
// whose own terms are conditioned within float_recentre_condition as one
// piece of its own terms; not one that vanishes at its lower end, whose
// Taylor polynomial about that end keeps f's relative accuracy there (M5's
// E_4 beyond 1/5: its own terms were 4e5 float ulps off next to it).
std::vector<EmittedPiece> for_float_results(const Radial& f, std::vector<EmittedPiece> planned) {
    std::vector<EmittedPiece> out;
    std::size_t next = 0;  // the first of `planned` not yet taken
    for (std::size_t i = 0; i < f.pieces.size(); ++i) {
        const Q lo = f.breaks[i], hi = f.breaks[i + 1];
        const ClosedForm& form = f.pieces[i];
        std::vector<EmittedPiece> own;
        while (next < planned.size() && planned[next].hi && *planned[next].hi <= hi) own.push_back(std::move(planned[next++]));
        if (own.empty() || own.front().lo != lo || *own.back().hi != hi)
            fail("internal: the plan of a quantity does not tile its piece [" + short_string(lo) + ", " + short_string(hi) + ")");
        std::vector<EmittedTerm> terms = stable_terms(form, hi);
        std::map<Q, double> scales;
        const bool compact = !form.is_zero() && form.has_only_basis_one() && !vanishes_at(form, lo) &&
                             worst_condition(Magnitude(terms), form, form.derivative(), lo, hi, scales) <=
                                 float_recentre_condition;
        if (compact) {
            out.push_back({lo, hi, std::move(terms), ""});
            continue;
        }
        for (EmittedPiece& p : own) out.push_back(std::move(p));
    }
    for (; next < planned.size(); ++next) out.push_back(std::move(planned[next]));  // the exterior
    return out;
}

std::vector<EmittedPiece> double_plan(const Radial& f, bool potential_like, const std::vector<Radial>& parts) {
    std::vector<EmittedPiece> emitted =
        parts.empty() ? emitted_pieces(f, potential_like) : combination_pieces(f, parts, potential_like);
    if (potential_like) return recentred(f, std::move(emitted), Recentre::every_piece);
    if (parts.empty()) return recentred(f, std::move(emitted), Recentre::interior_pieces);
    return emitted;  // moved (a conditional expression would copy every piece, its Taylor coefficients too)
}

}  // namespace

std::vector<EmittedPiece> plan_quantity(const Radial& f, bool potential_like, const std::vector<Radial>& parts,
                                        ResultPrecision result) {
    std::vector<EmittedPiece> planned = double_plan(f, potential_like, parts);
    if (result == ResultPrecision::float_value) return for_float_results(f, std::move(planned));
    return planned;
}

// The emitted (rounded) Taylor coefficients of a centred piece (kept in the
// piece by middle_pieces: Ziv's loop per coefficient, once).
std::vector<double> rounded(const CentredPiece& p) {
    if (p.a_double.size() == p.a.size()) return p.a_double;
    std::vector<double> out;
    for (const CentredValue& a : p.a) out.push_back(round_to_double([&](unsigned bits) { return a.evaluate(p.centre, bits); }));
    return out;
}

// The low part of the emitted Taylor coefficient a_k = hi + lo.
double centred_low_part(const CentredPiece& p, std::size_t k, double hi) {
    if (p.a_lo.size() == p.a.size() && p.a_double[k] == hi) return p.a_lo[k];
    const CentredValue& a = p.a[k];
    if (a.arcsech.is_zero() && a.arcsin.is_zero() && a.log.is_zero()) return low_part(a.one, hi);
    return low_part([&](unsigned bits) { return a.evaluate(p.centre, bits); }, hi);
}

}  // namespace mollify::gen
