#include "edge_series.hpp"

#include "once_per_run.hpp"
#include "search_choices.hpp"

#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace mollify::gen {

namespace {

// sqrt(x) rounded up (MPFR RNDU), as a rational: an upper bound.
Q sqrt_hi(const Q& x) {
    mpfr_t s;
    mpfr_init2(s, 128);
    mpfr_set_q(s, x.backend().data(), MPFR_RNDU);
    mpfr_sqrt(s, s, MPFR_RNDU);
    Q q;
    mpfr_get_q(q.backend().data(), s);
    mpfr_clear(s);
    return q;
}

// The infinite series of a basis in S, sum_{i >= start} b_i S^(power(i)),
// consecutive powers 2 apart and |b_i| non-increasing (see the header):
// arcsech 1/(2i+1) at S^(2i+1); log r -1/(2i) at S^(2i) from i = 1;
// arcsin (its part beyond pi/2) -c_i/(2i+1) at S^(2i+1).
bool infinite(Basis b) { return b == Basis::arcsech || b == Basis::log || b == Basis::arcsin; }
int start(Basis b) { return b == Basis::log ? 1 : 0; }
int power(Basis b, int i) { return b == Basis::log ? 2 * i : 2 * i + 1; }
Q coefficient(Basis b, int i) {
    switch (b) {
        case Basis::arcsech: return ratio(1, 2 * i + 1);
        case Basis::log: return ratio(-1, 2 * i);
        default: return -central_binomial_ratio(i) / Q(2 * i + 1);
    }
}

int parity(int n) { return n & 1; }

// n0 per parity: the lowest power of r of that parity in f.
std::map<int, int> lowest_powers(const ClosedForm& f) {
    std::map<int, int> n0;
    for (const auto& [k, p] : f.terms())
        for (int n = p.low(); n <= p.high(); ++n)
            if (p.coefficient(n) != 0) {
                auto it = n0.find(parity(n));
                if (it == n0.end()) n0[parity(n)] = n;
                else it->second = std::min(it->second, n);
            }
    return n0;
}

// Calls visit(low, t, b_t, key) for every term c r^n b(r) of f rewritten as
// r^low c (1 - x)^e b = r^low sum_t b_t S^(2t) b, b_t = c binom(e, t) (-1)^t.
template <class Visit>
void for_each_part(const ClosedForm& f, Visit visit) {
    const std::map<int, int> n0 = lowest_powers(f);
    for (const auto& [k, p] : f.terms())
        for (int n = p.low(); n <= p.high(); ++n) {
            const Q c = p.coefficient(n);
            if (c == 0) continue;
            const int low = n0.at(parity(n)), e = (n - low) / 2;
            for (int t = 0; t <= e; ++t) {
                const Q bt = c * Q(binomial(static_cast<unsigned>(e), static_cast<unsigned>(t))) * (t % 2 ? -1 : 1);
                visit(low, t, bt, k);
            }
        }
}

double to_double(const Exact& c) { return static_cast<double>(c.evaluate(80).first); }

}  // namespace

std::optional<std::vector<EdgeTerm>> series_at_edge(const ClosedForm& f, int order) {
    std::map<std::pair<int, int>, Exact> acc;  // (low, s) -> coefficient
    for_each_part(f, [&](int low, int t, const Q& bt, const TermKey& k) {
        const Exact factor = Exact::of(k.factor);
        auto add = [&](int s, const Exact& c) { acc[{low, s}] += c; };
        switch (k.basis) {
            case Basis::one: add(2 * t, factor * bt); break;
            case Basis::sqrt_power: add(2 * t + k.s_power, factor * bt); break;
            case Basis::arcsin: add(2 * t, Exact::pi_power(Q(1, 2), 1) * factor * bt); [[fallthrough]];
            default:
                for (int i = start(k.basis); 2 * t + power(k.basis, i) <= order; ++i)
                    add(2 * t + power(k.basis, i), factor * (bt * coefficient(k.basis, i)));
        }
    });
    std::vector<EdgeTerm> out;
    for (const auto& [key, c] : acc) {
        if (c.is_zero()) continue;
        if (key.second < 0) return std::nullopt;  // f is singular at the edge
        out.push_back({key.first, key.second, c});
    }
    return out;
}

// The dropped tail of one infinite basis series times b_t r^low S^(2t), from
// its first dropped index i* (2t + power(i*) = s* > order), is at most
// |b_t| |factor| |b_i*| r^low S^(s*) sum_l S^(2l) = ... S^(s*) / r^2 (the
// |b_i| do not increase, 1 - S^2 = r^2), and S^(s*) <= S^(order+1)
// S1^(s* - order - 1) for S <= S1 = sqrt(1 - r1^2): so
// |f - T| <= sum_low K_low r^(low - 2) S^(order+1). Divided by the leading
// term |a| r^low_a S^m0 (m0 <= order + 1), sup over [r1, 1] of r^e being 1
// (e >= 0) or r1^e, and of S^(order+1-m0) S1^(order+1-m0).
namespace {

// The leading term: the lowest power of S, the largest |c| among its classes.
std::optional<EdgeTerm> leading(const std::vector<EdgeTerm>& terms) {
    std::optional<EdgeTerm> lead;
    for (const EdgeTerm& t : terms)
        if (!lead || t.s < lead->s || (t.s == lead->s && std::abs(to_double(t.c)) > std::abs(to_double(lead->c))))
            lead = t;
    return lead;
}

std::optional<Q> bound_with_lead(const ClosedForm& f, int order, const Q& r1, const EdgeTerm& lead) {
    if (lead.s > order) return std::nullopt;  // the lead's coefficient must be complete
    const Q s1 = sqrt_hi(Q(1) - r1 * r1);
    std::map<int, Q> K;
    std::map<Atom, Q> factors;
    for_each_part(f, [&](int low, int t, const Q& bt, const TermKey& k) {
        if (!infinite(k.basis)) return;
        int i = start(k.basis);
        while (2 * t + power(k.basis, i) <= order) ++i;
        auto it = factors.find(k.factor);
        if (it == factors.end()) it = factors.emplace(k.factor, abs_upper_bound(Exact::of(k.factor))).first;
        K[low] += abs(bt) * it->second * abs(coefficient(k.basis, i)) * pow(s1, 2 * t + power(k.basis, i) - order - 1);
    });
    const Q a = abs_lower_bound(lead.c);
    if (a == 0) return std::nullopt;
    Q beta = 0;
    for (const auto& [low, k] : K) {
        const int e = low - 2 - lead.low;
        beta += k * (e >= 0 ? Q(1) : pow(r1, e));
    }
    return beta / a * pow(s1, order + 1 - lead.s);
}

}  // namespace

std::optional<Q> edge_truncation_bound(const ClosedForm& f, int order, const Q& r1) {
    const auto terms = series_at_edge(f, order);
    if (!terms) return std::nullopt;
    const auto lead = leading(*terms);
    if (!lead) return std::nullopt;
    return bound_with_lead(f, order, r1, *lead);
}

double edge_condition(const std::vector<EdgeTerm>& terms, double r) {
    const double S = std::sqrt((1 - r) * (1 + r));
    double sum = 0, magnitude = 0;
    for (const EdgeTerm& t : terms) {
        const double x = to_double(t.c) * std::pow(r, t.low) * std::pow(S, t.s);
        sum += x;
        magnitude += std::abs(x);
    }
    return sum == 0 ? 1e300 : magnitude / std::abs(sum);
}

namespace {

Q edge_target() { return Q(1) / pow(Q(2), 60); }

// The cheapest order with a proven bound below 2^-60 (the bound decreases
// with the order: bisection on 2^-62, then proven), or nullopt above
// max_order.
std::optional<std::pair<int, Q>> order_for(const ClosedForm& f, const Q& r1, int max_order, const EdgeTerm& lead) {
    const Q target = edge_target(), aim = Q(1) / pow(Q(2), 62);
    auto small = [&](int order) {
        const auto b = bound_with_lead(f, order, r1, lead);
        return b && *b <= aim;
    };
    if (!small(max_order)) return std::nullopt;
    int lo = 0, hi = max_order;
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        (small(mid) ? hi : lo) = mid;
    }
    const auto b = bound_with_lead(f, hi, r1, lead);
    if (!b || *b > target) return std::nullopt;
    return std::pair{hi, *b};
}

}  // namespace

namespace {

// The first of r0, k/32 (k = 16..31) with a proven truncation below 2^-60
// within max_order powers of S: the closed form cancels from about r = 1/2
// on (sum of |terms| over |value| 1e3 there, 1e7 at 3/4), so the series
// starts as low as its order allows.
std::optional<EdgeSeries> searched_edge_series(const ClosedForm& f, const Q& r0) {
    constexpr int max_order = 120;
    const auto full = series_at_edge(f, max_order);
    if (!full) return std::nullopt;
    const auto lead = leading(*full);
    if (!lead) return std::nullopt;
    std::vector<Q> candidates{r0};
    for (int k = 16; k < 32; ++k)
        if (Q(k, 32) > r0) candidates.push_back(Q(k, 32));
    for (const Q& r1 : candidates)
        if (auto o = order_for(f, r1, max_order, *lead)) {
            auto terms = series_at_edge(f, o->first);
            if (!terms) return std::nullopt;
            return EdgeSeries{r1, o->first, std::move(*terms), o->second};
        }
    return std::nullopt;
}

// The series the search chose (search_choices.hpp), its bound proven again;
// nullopt where it does not prove 2^-60. Its leading term is the full
// series' (the lowest power of S, complete up to the order).
std::optional<EdgeSeries> chosen_edge_series(const ClosedForm& f, const EdgeChoice& c) {
    auto terms = series_at_edge(f, c.order);
    if (!terms) return std::nullopt;
    const auto lead = leading(*terms);
    if (!lead) return std::nullopt;
    const auto b = bound_with_lead(f, c.order, c.r1, *lead);
    if (!b || *b > edge_target()) return std::nullopt;
    return EdgeSeries{c.r1, c.order, std::move(*terms), *b};
}

// As the compiled-in choice says, or searched.
std::optional<EdgeSeries> edge_series_of(const ClosedForm& f, const Q& r0) {
    const std::uint64_t key = search_key("edge", f, {r0});
    if (const EdgeChoice* c = known_choice<EdgeChoice>(key))
        if (auto e = chosen_edge_series(f, *c)) return e;
    auto e = searched_edge_series(f, r0);
    if (e && searching_afresh()) record_choice(key, EdgeChoice{e->r1, e->order});
    return e;
}

}  // namespace

// Once per run for g, f = c g (closed_form.hpp's normalised): the series is
// linear in f and its bound relative, so f's is g's with its terms times c.
std::optional<EdgeSeries> edge_series(const ClosedForm& f, const Q& r0) {
    if (f.is_zero()) return edge_series_of(f, r0);
    const auto [c, g] = normalised(f);
    // (g captured by an init-capture: clang 14 captures no structured binding)
    std::optional<EdgeSeries> e = once_per_run<std::optional<EdgeSeries>>(
        search_key("edge", g, {r0}), [&g = g, &r0] { return edge_series_of(g, r0); });
    if (e)
        for (EdgeTerm& t : e->terms) t.c = t.c * c;
    return e;
}

}  // namespace mollify::gen
