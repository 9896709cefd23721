#include "series.hpp"

#include "error.hpp"
#include "once_per_run.hpp"
#include "search_choices.hpp"

#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace mollify::gen {

namespace {

int floor_half(int a) { return a >= 0 ? a / 2 : -((1 - a) / 2); }

using Interval = std::pair<Q, Q>;

// A basis function's power series r^off sum_i a_i x^i (x = r^2, the
// log 2 - log r of arcsech apart): the tail after index I is at most
// first x^(I+1) r^off / (1 - rho x) when first = |a_(I+1)| and
// |a_(i+1) / a_i| <= rho for all i > I (geometric majorant).
struct Tail {
    Q first, rho;
    int off;
};

Tail basis_tail(const TermKey& k, int I) {
    switch (k.basis) {
        case Basis::sqrt_power: {  // |a_(i+1)/a_i| = |j/2 - i|/(i+1) <= (|j|/2 + i)/(i+1), monotone in i
            const Q half_j = ratio(std::abs(k.s_power), 2);
            return {abs(binomial(ratio(k.s_power, 2), I + 1)), std::max(Q(1), (half_j + I + 1) / Q(I + 2)), 0};
        }
        case Basis::arcsech:  // a_i = c_i/(2i): ratio (2i+1)/(2i+2) * i/(i+1) < 1
            return {central_binomial_ratio(I + 1) / Q(2 * (I + 1)), Q(1), 0};
        case Basis::arcsin:  // a_i = c_i/(2i+1): ratio (2i+1)^2/((2i+2)(2i+3)) < 1
            return {central_binomial_ratio(I + 1) / Q(2 * I + 3), Q(1), 1};
        default: fail("internal: no tail for an exact basis");
    }
}

// Coefficients of r^n (plain) and r^n log r (logs) of a series.
struct Split {
    std::map<int, Exact> plain, logs;
};

Split split(const ClosedForm& s) {
    Split out;
    for (const auto& [k, p] : s.terms())
        for (int n = p.low(); n <= p.high(); ++n)
            if (p.coefficient(n) != 0) (k.basis == Basis::log ? out.logs : out.plain)[n] += Exact::of(k.factor) * p.coefficient(n);
    for (auto* m : {&out.plain, &out.logs}) std::erase_if(*m, [](const auto& e) { return e.second.is_zero(); });
    return out;
}

// sup over (0, r0] of r^d |log r|, d >= 1: it increases while |log r| > 1/d,
// so it is r0^d |log r0| when d |log r0| >= 1; otherwise at most 1/(e d).
Q sup_power_log(int d, const Q& r0, const Interval& log0) {
    if (log0.first * d >= 1) return pow(r0, d) * log0.second;
    return Q(36788, 100000) / Q(d);  // 1/e < 0.36788
}

// A lower bound of |T(r)| / g(r) on (0, r0], g the leading behaviour r^p or
// r^p |log r|: the leading coefficient minus every other term's supremum
// relative to g (each ratio increases with r, so its supremum is at r0).
Q leading_lower_bound(const Split& t, int p, bool log_lead, const Q& r0, const Interval& log0) {
    Q ell = abs_lower_bound(log_lead ? t.logs.at(p) : t.plain.at(p));
    for (const auto& [n, c] : t.plain)
        if (log_lead || n != p) ell -= abs_upper_bound(c) * (log_lead ? pow(r0, n - p) / log0.first : pow(r0, n - p));
    for (const auto& [n, c] : t.logs)
        if (!log_lead || n != p) ell -= abs_upper_bound(c) * (log_lead ? pow(r0, n - p) : sup_power_log(n - p, r0, log0));
    return ell;
}

int highest_power(const ClosedForm& f) {
    int high = 0;
    for (const auto& [k, p] : f.terms()) high = std::max(high, p.high());
    return high;
}

// Sum of |terms| over |value| of the series at r0, each power's constants
// combined as the emitter rounds them: the condition number of its double
// evaluation (a heuristic for accuracy, not part of the bound).
double condition(const ClosedForm& series, const Q& r0) {
    const Split t = split(series);
    const double r = static_cast<double>(r0), log_r = std::log(r);
    double sum = 0, magnitude = 0;
    for (const auto* s : {&t.plain, &t.logs})
        for (const auto& [n, c] : *s) {
            const double term = static_cast<double>(interval(c).first) * std::pow(r, n) * (s == &t.logs ? log_r : 1);
            sum += term;
            magnitude += std::abs(term);
        }
    return sum == 0 ? 1e300 : magnitude / std::abs(sum);
}

struct Candidate {
    ZeroSeries z;
    double score;  // the series' condition number at the seam r0
};

// series_at_zero(f, order), each order computed once per zero_series (the
// radii 2^-1 .. 2^-8 and the proof ask for the same few orders again).
using SeriesByOrder = std::map<int, ClosedForm>;
const ClosedForm& series_of(const ClosedForm& f, int order, SeriesByOrder& memo) {
    auto it = memo.find(order);
    if (it == memo.end()) it = memo.emplace(order, series_at_zero(f, order)).first;
    return it->second;
}

std::optional<Q> relative_bound(const ClosedForm& f, const ClosedForm& series, int order, int m);

Q zero_series_target() { return Q(1) / pow(Q(2), 60); }

std::optional<Candidate> series_for_radius(const ClosedForm& f, int m, SeriesByOrder& memo) {
    const Q r0 = Q(1) / pow(Q(2), m), target = zero_series_target();
    Real r(0, 70);
    mpfr_set_q(r.backend().data(), r0.backend().data(), MPFR_RNDN);
    const double f0 = static_cast<double>(abs(f.evaluate(r, 400).first));
    if (f0 == 0) return std::nullopt;
    // The cheapest order whose tail is below 2^-62 |f(r0)| (bisection: the
    // bound decreases with the order), then proven.
    const int max_order = 120;
    auto small = [&](int order) {
        const auto B = truncation_bound(f, order, r0);
        return B && static_cast<double>(*B) <= f0 * std::ldexp(1.0, -62);
    };
    int lo = highest_power(f) - 1, order = max_order + 1;  // small(lo) false, small(order) true
    if (small(max_order)) order = max_order;
    while (order - lo > 1) {
        const int mid = (lo + order) / 2;
        (small(mid) ? order : lo) = mid;
    }
    for (int tries = 0; tries < 2 && order <= max_order; ++tries, order += 2) {
        const ClosedForm& s = series_of(f, order, memo);
        const auto rel = relative_bound(f, s, order, m);
        if (!rel || *rel > target) continue;
        // The next piece is a Taylor piece about a centre (centred_series.hpp),
        // not the cancelling closed form: only the series' own condition counts.
        const double score = condition(s, r0);
        return Candidate{ZeroSeries{m, order, s, *rel}, score};
    }
    return std::nullopt;
}

}  // namespace

// Coefficients by their recurrences: binom(j/2, i+1) = binom(j/2, i) (j/2 - i)/(i+1),
// c_(i+1) = c_i (2i+1)/(2i+2).
std::vector<SeriesTerm> basis_series(const TermKey& k, int order) {
    std::vector<SeriesTerm> s;
    Q a = 1;
    switch (k.basis) {
        case Basis::one: s.push_back({0, Exact(Q(1)), false}); break;
        case Basis::log: s.push_back({0, Exact(Q(1)), true}); break;
        case Basis::sqrt_power:  // (1 - x)^(j/2) = sum_i binom(j/2, i) (-x)^i
            for (int i = 0; 2 * i <= order; a *= -(ratio(k.s_power, 2) - i) / Q(i + 1), ++i)
                s.push_back({2 * i, Exact(a), false});
            break;
        case Basis::arcsech:
            s.push_back({0, Exact::log_of(Q(2)), false});
            s.push_back({0, Exact(Q(-1)), true});
            for (int i = 1; 2 * i <= order; ++i) {
                a *= ratio(2 * i - 1, 2 * i);
                s.push_back({2 * i, Exact(-a / Q(2 * i)), false});
            }
            break;
        case Basis::arcsin:
            for (int i = 0; 2 * i + 1 <= order; a *= ratio(2 * i + 1, 2 * i + 2), ++i)
                s.push_back({2 * i + 1, Exact(a / Q(2 * i + 1)), false});
            break;
    }
    return s;
}

ClosedForm series_at_zero(const ClosedForm& f, int order) {
    std::map<TermKey, std::map<int, Q>> acc;  // coefficient of r^n (or r^n log r) per constant
    for (const auto& [k, p] : f.terms()) {
        const Exact factor = Exact::of(k.factor);
        for (const SeriesTerm& t : basis_series(k, order - p.low())) {
            const Exact ft = factor * t.c;
            for (int n = p.low(); n <= p.high() && n + t.power <= order; ++n) {
                const Q c = p.coefficient(n);
                if (c == 0) continue;
                for (const auto& [atom, q] : ft.terms())
                    acc[TermKey{t.log_r ? Basis::log : Basis::one, 0, atom}][n + t.power] += q * c;
            }
        }
    }
    ClosedForm s;
    for (const auto& [key, powers] : acc) {
        Laurent l;
        for (const auto& [n, q] : powers) l += Laurent::monomial(q, n);
        if (!l.is_zero()) s += ClosedForm(l, key);
    }
    return s;
}

LeadingOrder leading_order_at_zero(const ClosedForm& f, int beyond) {
    if (f.is_zero()) fail("the leading order at 0 of a closed form that is 0");
    int lowest = std::numeric_limits<int>::max();
    for (const auto& [k, p] : f.terms()) lowest = std::min(lowest, p.low());
    Split s = split(series_at_zero(f, lowest + beyond));
    int low = std::numeric_limits<int>::max();
    for (auto* m : {&s.plain, &s.logs})
        if (!m->empty()) low = std::min(low, m->begin()->first);
    if (low == std::numeric_limits<int>::max())
        fail("a closed form whose series at 0 vanishes up to r^" + std::to_string(lowest + beyond));
    return {low, s.plain[low], s.logs[low]};
}

Exact limit_at_zero(const ClosedForm& f) {
    const Split s = split(series_at_zero(f, 0));
    if (!s.plain.empty() && s.plain.begin()->first < 0)
        fail("closed form is singular at r = 0 (r^" + std::to_string(s.plain.begin()->first) + " term)");
    if (!s.logs.empty()) fail("closed form is singular at r = 0 (log r term)");
    auto it = s.plain.find(0);
    return it == s.plain.end() ? Exact() : it->second;
}

// Each dropped basis tail of a term c r^n b(r) is at most
// |c| r^(n + 2(I+1) + off) first / (1 - rho r^2) (basis_tail), with
// n + 2(I+1) + off > order: divided by (r/r0)^(order+1) it increases with r,
// so its value at r0 bounds it on (0, r0].
namespace {

// abs_upper_bound(pi^e log p) once per thread (the bisections over the
// order ask for the same few constants hundreds of times).
const Q& factor_bound(const Atom& a) {
    thread_local std::map<Atom, Q> bounds;
    auto it = bounds.find(a);
    if (it == bounds.end()) it = bounds.emplace(a, abs_upper_bound(Exact::of(a))).first;
    return it->second;
}

}  // namespace

std::optional<Q> truncation_bound(const ClosedForm& f, int order, const Q& r0) {
    const Q x0 = r0 * r0;
    Q B = 0;
    for (const auto& [k, p] : f.terms()) {
        if (k.basis == Basis::one || k.basis == Basis::log) continue;  // kept exactly
        const Q& factor = factor_bound(k.factor);
        for (int n = p.low(); n <= p.high(); ++n) {
            const Q c = p.coefficient(n);
            if (c == 0) continue;
            if (n > order) fail("internal: truncation below a power of the closed form");
            const int I = floor_half(order - n - (k.basis == Basis::arcsin ? 1 : 0));
            const Tail t = basis_tail(k, I);
            if (t.rho * x0 >= 1) return std::nullopt;
            B += abs(c) * factor * t.first * pow(r0, n + 2 * (I + 1) + t.off) / (Q(1) - t.rho * x0);
        }
    }
    return B;
}

// |f| >= |T| - |f - T| >= g (ell - beta) on (0, r0] with g(r) = r^p (or
// r^p |log r| when T leads with r^p log r), ell <= |T|/g
// (leading_lower_bound) and beta = B / g(r0) >= |f - T| / g (B (r/r0)^(order+1)
// / g(r) increases with r as order + 1 > p). So |f - T| / |f| <= beta / (ell - beta).
std::optional<Q> relative_truncation_bound(const ClosedForm& f, int order, int m) {
    return relative_bound(f, series_at_zero(f, order), order, m);
}

namespace {

// relative_truncation_bound with T = series_at_zero(f, order) given.
std::optional<Q> relative_bound(const ClosedForm& f, const ClosedForm& series, int order, int m) {
    const Q r0 = Q(1) / pow(Q(2), m);
    const auto B = truncation_bound(f, order, r0);
    if (!B) return std::nullopt;
    const Split t = split(series);
    int p = std::numeric_limits<int>::max();
    for (const auto* s : {&t.plain, &t.logs})
        if (!s->empty()) p = std::min(p, s->begin()->first);
    if (p == std::numeric_limits<int>::max() || p > order) return std::nullopt;
    const bool log_lead = t.logs.count(p) > 0;
    const auto [l2lo, l2hi] = interval(Atom{0, 2});
    const Interval log0{l2lo * m, l2hi * m};  // |log r0| = m log 2
    const Q ell = leading_lower_bound(t, p, log_lead, r0, log0);
    const Q beta = *B / (pow(r0, p) * (log_lead ? log0.first : Q(1)));
    if (ell <= beta) return std::nullopt;
    return beta / (ell - beta);
}

}  // namespace

namespace {

// The seam r0 should be where the series does not cancel: of the provable
// radii the largest whose condition number is within 2 (or 1.25 times the
// best seam's).
std::optional<ZeroSeries> searched_zero_series(const ClosedForm& f) {
    std::vector<Candidate> candidates;
    SeriesByOrder memo;
    for (int m = 1; m <= 8; ++m)
        if (auto c = series_for_radius(f, m, memo)) {
            if (c->score <= 2) return std::move(c->z);  // the largest such r0: done
            candidates.push_back(std::move(*c));
        }
    if (candidates.empty()) return std::nullopt;
    double best = candidates.front().score;
    for (const Candidate& c : candidates) best = std::min(best, c.score);
    for (Candidate& c : candidates)
        if (c.score <= std::max(2.0, 1.25 * best)) return std::move(c.z);
    return std::nullopt;
}

// The series the search chose (search_choices.hpp), its bound proven again;
// nullopt where it does not prove the target.
std::optional<ZeroSeries> chosen_zero_series(const ClosedForm& f, const ZeroChoice& c) {
    ClosedForm s = series_at_zero(f, c.order);
    const auto rel = relative_bound(f, s, c.order, c.m);
    if (!rel || *rel > zero_series_target()) return std::nullopt;
    return ZeroSeries{c.m, c.order, std::move(s), *rel};
}

// As the compiled-in choice says, or searched.
std::optional<ZeroSeries> zero_series_of(const ClosedForm& f) {
    const std::uint64_t key = search_key("zero", f, {});
    if (const ZeroChoice* c = known_choice<ZeroChoice>(key))
        if (auto z = chosen_zero_series(f, *c)) return z;
    auto z = searched_zero_series(f);
    if (z && searching_afresh()) record_choice(key, ZeroChoice{z->m, z->order});
    return z;
}

}  // namespace

// Once per run for g, f = c g (closed_form.hpp's normalised): the series is
// linear in f and its bound relative, so f's is g's times c.
std::optional<ZeroSeries> zero_series(const ClosedForm& f) {
    if (f.is_zero()) return zero_series_of(f);
    const auto [c, g] = normalised(f);
    // (g captured by an init-capture: clang 14 captures no structured binding)
    std::optional<ZeroSeries> z =
        once_per_run<std::optional<ZeroSeries>>(search_key("zero", g, {}), [&g = g] { return zero_series_of(g); });
    if (z) z->series = z->series * c;
    return z;
}

}  // namespace mollify::gen
