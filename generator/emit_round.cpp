#include "emit_round.hpp"

#include "emit_checks.hpp"
#include "emit_plan.hpp"
#include "rounding.hpp"

#include <algorithm>
#include <cmath>

namespace mollify::gen {

namespace {

// A term's coefficients rounded, with their low parts c - round(c); no low
// parts where every one is 0 (the coefficients are exact).
void set_coefficients(RoundedTerm& t, std::vector<double> c, std::vector<double> c_lo, std::vector<std::string> exact) {
    t.c = std::move(c);
    t.exact = std::move(exact);
    if (!std::all_of(c_lo.begin(), c_lo.end(), [](double x) { return x == 0; })) t.c_lo = std::move(c_lo);
}

// table::Term::plain of a Taylor piece: the most leading Horner steps of
// Precision::accurate that may run in plain double arithmetic. After P
// such steps (the coefficients a_{n-1} .. a_K, K = n - 1 - P, their low
// parts dropped) the sum is off by at most (gamma_{2P} + u) sum_{k >= K}
// |a_k| |v|^(k-K) (Higham, "Accuracy and Stability", 2nd ed., eq. 5.3:
// Horner's rule, here two roundings a step where there is no FMA; u for
// the dropped low parts), which enters f times |v|^K r^low S^s_power <=
// rho^K lo^min(low, 0) (S <= 1, r <= 1): P is the largest with that below
// 2^-66 of the piece's scale, the reference of its truncation bound (2^-60).
// Every quantity is positive, so the bound in long double (64-bit
// significands, a relative error below 2^-57 over these few hundred
// operations) times 1 + 2^-40 is an upper bound of the exact one.
int plain_steps(const CentredPiece& p, const std::vector<double>& a) {
    const int n = static_cast<int>(a.size());
    if (n < 3) return 0;
    using L = long double;
    const L margin = 1 + std::ldexp(L{1}, -40), u = std::ldexp(L{1}, -53);
    const Q reach = std::max(boost::multiprecision::abs(p.lo - p.centre), boost::multiprecision::abs(p.hi - p.centre));
    const L rho = static_cast<L>(reach.convert_to<double>()) * margin;
    const L scale = static_cast<L>(p.scale.convert_to<double>()) / margin;
    const L factor = p.low < 0 ? std::pow(static_cast<L>(p.lo.convert_to<double>()) / margin, static_cast<L>(p.low)) : L{1};
    if (!(rho > 0) || !(scale > 0) || !std::isfinite(factor)) return 0;
    // tail[K] = sum_{k >= K} |a_k| (1 + 2^-52) rho^k (a_k within 2^-53 of its double)
    std::vector<L> tail(static_cast<std::size_t>(n) + 1, L{0});
    for (int k = n - 1; k >= 0; --k)
        tail[static_cast<std::size_t>(k)] =
            tail[static_cast<std::size_t>(k) + 1] + std::abs(static_cast<L>(a[static_cast<std::size_t>(k)])) * (1 + 2 * u) * std::pow(rho, static_cast<L>(k));
    for (int P = n - 2; P >= 1; --P) {
        const L gamma = 2 * P * u / (1 - 2 * P * u);
        const L bound = factor * (gamma + u) * tail[static_cast<std::size_t>(n - 1 - P)] * margin;
        if (bound <= std::ldexp(scale, -66)) return P;
    }
    return 0;
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
    t.plain = plain_steps(p, a);
    return t;
}

}  // namespace

// The bounds below in long double (64-bit significands): every quantity is
// positive and each takes at most a few dozen operations, so the computed
// value is within 2^-57 of the exact one, and times (or over) 1 + 2^-40 an
// upper (lower) bound of it, as in plain_steps.
namespace {
using L = long double;
const L margin = 1 + std::ldexp(L{1}, -40), unit = std::ldexp(L{1}, -53);

L horner_value(const std::vector<L>& m, L x) {
    L sum = 0;
    for (std::size_t k = m.size(); k-- > 0;) sum = sum * x + m[k];
    return sum;
}

L derivative_value(const std::vector<L>& m, L x) {
    L sum = 0;
    for (std::size_t k = m.size(); k-- > 1;) sum = sum * x + static_cast<L>(k) * m[k];
    return sum;
}

// The remainder d = p(q) - p(qa) = sum_k m_k (q^k - qa^k) by the recurrence
// d_k = d_{k+1} q + a_{k+1} (q - qa): every term has the sign of q - qa, so
// its computed value is within gamma_{4n+4} of itself (Higham, "Accuracy
// and Stability", 2nd ed., Lemma 3.1: at most 3 roundings a step without an
// FMA, those of q - qa and of q, which enters up to n - 1 times), and
// |d| <= |q - qa| p'(q + 2^-(s+1)) (p' increases: m_k >= 0). That must stay
// below 2^-62 of p(q) on the piece (p increases too): on 64 parts [a, b] of
// it, the bound at b against p(a). |q - qa| <= 2^-(s+1) + 2 u xa (qa is the
// evaluated q's neighbour on the grid, and q = r/h enters as r (1/h) rounded
// plus its residual, at most ~2 ulp: detail::AccurateRadius).
bool remainder_small(const std::vector<L>& m, L lo, L hi, L xa, int s) {
    const int n = static_cast<int>(m.size());
    const L half_grid = std::ldexp(L{1}, -(s + 1)), step = (hi - lo) / 64;
    const L gamma = (4 * n + 4) * unit / (1 - (4 * n + 4) * unit);
    const L reach = (half_grid + 2 * unit * xa) * margin;
    for (int j = 0; j < 64; ++j) {
        const L a = (lo + j * step) / margin, b = j == 63 ? hi : (lo + (j + 1) * step) * margin;
        const L error = gamma * reach * derivative_value(m, (b + half_grid) * margin) * margin;
        if (error > std::ldexp(horner_value(m, a) / margin, -62)) return false;
    }
    return true;
}

// Is a split of s bits exact and its remainder bounded for the integers m
// on [0, edge] (split_of's two proofs, from the term as rounded)?
bool split_holds(const std::vector<double>& m, double edge, int s) {
    const int n = static_cast<int>(m.size());
    if (n < 2 || !table::split_is_exact(m.data(), n, edge, s)) return false;
    const std::vector<L> ml(m.begin(), m.end());  // integers below 2^53: exact
    const L hi_l = static_cast<L>(edge) * margin;
    return remainder_small(ml, L{0}, hi_l, (hi_l + std::ldexp(L{1}, -s)) * margin, s);
}
}  // namespace

Split split_of(const std::vector<Exact>& c, const Q& lo, const Q& hi) {
    const int n = static_cast<int>(c.size());
    if (n < 2 || lo < 0 || hi <= lo || c[0].is_zero()) return {};
    // One atom pi^e log p for every coefficient: c_k = r_k atom.
    const Atom atom = c[0].terms().begin()->first;
    std::vector<Q> r;
    for (const Exact& x : c) {
        if (x.is_zero()) {
            r.push_back(0);
            continue;
        }
        if (x.terms().size() != 1 || x.terms().begin()->first != atom) return {};
        r.push_back(x.terms().begin()->second);
    }
    // The content g = +-gcd(numerators)/lcm(denominators), its sign that of
    // r_0, so that m_k = r_k/g are coprime integers, m_0 > 0.
    boost::multiprecision::mpz_int num = 0, den = 1;
    for (const Q& x : r)
        if (x != 0) {
            num = boost::multiprecision::gcd(num, boost::multiprecision::numerator(x));
            den = boost::multiprecision::lcm(den, boost::multiprecision::denominator(x));
        }
    Q g = Q(num) / Q(den);
    if (r[0] < 0) g = -g;
    std::vector<Q> m;
    for (const Q& x : r) {
        m.push_back(x / g);
        if (m.back() < 0) return {};  // mixed signs: p may cancel (compensated Horner)
    }
    std::vector<L> ml;
    for (const Q& x : m) {
        if (x >= Q(boost::multiprecision::mpz_int(1) << 53)) return {};
        ml.push_back(static_cast<L>(x.convert_to<double>()));  // an integer below 2^53: exact
    }
    const std::vector<double> md(ml.begin(), ml.end());
    const double edge = hi.convert_to<double>();
    const L lo_l = static_cast<L>(lo.convert_to<double>()) / margin, hi_l = static_cast<L>(edge) * margin;
    for (int s = 26; s >= 1; --s) {
        const L xa = (hi_l + std::ldexp(L{1}, -s)) * margin;
        if (!table::split_is_exact(md.data(), n, edge, s)) continue;
        // The largest exact split; a smaller one only widens q - qa.
        if (!remainder_small(ml, lo_l, hi_l, xa, s)) return {};
        return {s, std::move(m), Exact::of(atom) * g};
    }
    return {};
}

namespace {

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
    // On [0, edge], the term's whole domain (a combination's term w_j psi(q/a_j)
    // is the same in every piece up to a_j): one split for every piece that
    // holds it, so that the run-time form still sees one term (same_term).
    if (t.var == table::Var::r && hi) {
        const Split split = split_of(term.c, Q(0), term.edge ? *term.edge : *hi);
        const double content = split.bits > 0 ? round_to_double(split.content) : 0.0;
        if (split.bits > 0 && table::content_in_range(content)) {
            t.split = split.bits;
            for (const Q& x : split.m) t.m.push_back(x.convert_to<double>());
            t.content = content;
            t.content_lo = low_part(split.content, t.content);
            t.content_exact = split.content.to_string();
        }
    }
    const std::optional<Q> edge = term.edge ? term.edge : hi;
    if (edge) {
        t.edge = round_to_double(*edge);
        t.edge_lo = low_part(*edge, t.edge);
    }
    return t;
}

}  // namespace

std::optional<std::vector<RoundedPiece>> rounded_quantity(const Radial* f, bool potential_like,
                                                          const std::vector<Radial>& parts, ResultPrecision result) {
    if (!f) return std::nullopt;
    const std::vector<EmittedPiece> emitted = plan_quantity(*f, potential_like, parts, result);
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

std::vector<std::optional<std::vector<RoundedPiece>>> with_one_split_grid(
    std::vector<std::optional<std::vector<RoundedPiece>>> tables) {
    // Only the quantities whose every piece is one term: a piece of several
    // (a combination's, Franz (4.17)) may cancel them, and their remainders'
    // errors, each below 2^-62 of its term (remainder_small), then grow by
    // the cancellation, without bound near a root of the sum: such a
    // quantity's terms keep their own grids, the finest their proofs allow,
    // in every piece (the same term in two pieces stays the same term for
    // the run-time form's shared terms). A shared grid 9 bits coarser put
    // combo:m=2,base=wendland:k=3,l=1's dr 79 ulp off near its root.
    const auto one_term_pieces = [](const std::vector<RoundedPiece>& q) {
        return std::all_of(q.begin(), q.end(), [](const RoundedPiece& p) { return p.terms.size() <= 1; });
    };
    int grid = 0;  // the coarsest of those terms' own grids
    for (const auto& q : tables)
        if (q && one_term_pieces(*q))
            for (const RoundedPiece& p : *q)
                for (const RoundedTerm& t : p.terms)
                    if (t.split > 0) grid = grid == 0 ? t.split : std::min(grid, t.split);
    for (auto& q : tables)
        if (q && one_term_pieces(*q))
            for (RoundedPiece& p : *q)
                for (RoundedTerm& t : p.terms)
                    if (t.split > grid && split_holds(t.m, t.edge, grid)) t.split = grid;
    return tables;
}

}  // namespace mollify::gen
