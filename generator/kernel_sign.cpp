#include "kernel_sign.hpp"

#include "edge_series.hpp"
#include "series.hpp"

#include <algorithm>
#include <functional>
#include <map>
#include <tuple>
#include <vector>

namespace mollify::gen {

namespace {

constexpr int max_bisections = 24;  // 2^24 sub-intervals at most: a double root inside is left unknown

// p(a + (b - a) t) in powers of t.
std::vector<Q> on_unit_interval(const Laurent& p, const Q& a, const Q& b) {
    Laurent t;
    for (int k = 0; k <= p.high(); ++k) t += Laurent::binomial_power(a, b - a, k) * p.coefficient(k);
    std::vector<Q> c(static_cast<std::size_t>(std::max(p.high(), 0)) + 1);
    for (std::size_t k = 0; k < c.size(); ++k) c[k] = t.coefficient(static_cast<int>(k));
    return c;
}

// The Bernstein coefficients b_i = sum_{j <= i} C(i, j)/C(n, j) a_j are all >= 0.
bool bernstein_non_negative(const std::vector<Q>& a) {
    const unsigned n = static_cast<unsigned>(a.size() - 1);
    for (unsigned i = 0; i <= n; ++i) {
        Q b(0);
        for (unsigned j = 0; j <= i; ++j) b += Q(binomial(i, j)) / Q(binomial(n, j)) * a[j];
        if (b < 0) return false;
    }
    return true;
}

SignFact prove(const Laurent& p, const Q& a, const Q& b, int depth) {
    for (const Q& x : {a, b, Q((a + b) / 2)})
        if (p(x) < 0) return {SignVerdict::disproved, x, short_string(p(x))};
    if (bernstein_non_negative(on_unit_interval(p, a, b))) return {SignVerdict::proved, std::nullopt, ""};
    if (depth == 0)
        return {SignVerdict::unknown, std::nullopt,
                "not decided on [" + short_string(a) + ", " + short_string(b) + "] after " +
                    std::to_string(max_bisections) + " bisections (a root of even multiplicity inside?)"};
    const Q m = (a + b) / 2;
    SignFact left = prove(p, a, m, depth - 1);
    if (left.verdict != SignVerdict::proved) return left;
    return prove(p, m, b, depth - 1);
}

// ---- non-polynomial pieces (missing Wendland closed forms) ----
//
// Interval arithmetic in MPFR with outward (directed) rounding: every
// enclosure contains the exact real set, so a lower end >= 0 is a proof.

constexpr unsigned interval_bits = 160;
constexpr int max_intervals = 4000;  // sub-intervals per side, at most

struct Interval {
    Real lo, hi;
};

Real fresh() { return Real(0, interval_bits * 30103 / 100000 + 2); }

Interval point(const Q& q) {
    Interval x{fresh(), fresh()};
    mpfr_set_q(x.lo.backend().data(), q.backend().data(), MPFR_RNDD);
    mpfr_set_q(x.hi.backend().data(), q.backend().data(), MPFR_RNDU);
    return x;
}

Interval operator+(const Interval& a, const Interval& b) {
    Interval x{fresh(), fresh()};
    mpfr_add(x.lo.backend().data(), a.lo.backend().data(), b.lo.backend().data(), MPFR_RNDD);
    mpfr_add(x.hi.backend().data(), a.hi.backend().data(), b.hi.backend().data(), MPFR_RNDU);
    return x;
}

Interval operator*(const Interval& a, const Interval& b) {
    Interval x{fresh(), fresh()};
    Real p = fresh();
    bool first = true;
    for (const Real* u : {&a.lo, &a.hi})
        for (const Real* v : {&b.lo, &b.hi}) {
            mpfr_mul(p.backend().data(), u->backend().data(), v->backend().data(), MPFR_RNDD);
            if (first || p < x.lo) x.lo = p;
            mpfr_mul(p.backend().data(), u->backend().data(), v->backend().data(), MPFR_RNDU);
            if (first || p > x.hi) x.hi = p;
            first = false;
        }
    return x;
}

// [f(lo), f(hi)] for an increasing f of a non-empty interval, or of a point.
using MpfrUnary = int (*)(mpfr_ptr, mpfr_srcptr, mpfr_rnd_t);
Interval increasing(MpfrUnary f, const Interval& a) {
    Interval x{fresh(), fresh()};
    f(x.lo.backend().data(), a.lo.backend().data(), MPFR_RNDD);
    f(x.hi.backend().data(), a.hi.backend().data(), MPFR_RNDU);
    return x;
}

// pi^e log(p), from MPFR's correctly rounded pi and log in both directions.
Interval enclose(const Atom& atom) {
    Interval pi{fresh(), fresh()};
    mpfr_const_pi(pi.lo.backend().data(), MPFR_RNDD);
    mpfr_const_pi(pi.hi.backend().data(), MPFR_RNDU);
    if (atom.pi_power < 0) {  // 1/pi, outward
        const Interval p = pi;
        mpfr_ui_div(pi.lo.backend().data(), 1, p.hi.backend().data(), MPFR_RNDD);
        mpfr_ui_div(pi.hi.backend().data(), 1, p.lo.backend().data(), MPFR_RNDU);
    }
    Interval x = point(Q(1));
    for (int i = 0; i < std::abs(atom.pi_power); ++i) x = x * pi;
    if (atom.log_of != 1) x = x * increasing(mpfr_log, point(Q(atom.log_of)));
    return x;
}

Interval enclose(const Exact& c) {
    Interval x = point(Q(0));
    for (const auto& [atom, q] : c.terms()) x = x + point(q) * enclose(atom);
    return x;
}

// r^k on [a, b] (0 <= a, and a > 0 for k < 0): monotone, exact at the ends.
Interval power_on(const Q& a, const Q& b, int k) {
    if (k == 0) return point(Q(1));
    const Q pa = pow(a, k), pb = pow(b, k);
    Interval lo = point(pa < pb ? pa : pb), hi = point(pa < pb ? pb : pa);
    return {lo.lo, hi.hi};
}

// log r on [a, b], 0 < a: increasing.
Interval log_on(const Q& a, const Q& b) { return {increasing(mpfr_log, point(a)).lo, increasing(mpfr_log, point(b)).hi}; }

// S = sqrt(1 - r^2) on [a, b] within [0, 1]: decreasing.
Interval s_on(const Q& a, const Q& b) {
    const Interval low = increasing(mpfr_sqrt, point(Q(1) - b * b)), high = increasing(mpfr_sqrt, point(Q(1) - a * a));
    return {low.lo, high.hi};
}

// r^k log r on [a, b] (k >= 1 where a = 0): on [0, b] it is <= 0, and
// decreasing while log r <= -1/k (its derivative r^(k-1) (k log r + 1));
// elsewhere >= min over r > 0 = -1/(k e) > -1/(2k).
Interval power_log_on(const Q& a, const Q& b, int k) {
    if (a > 0) return power_on(a, b, k) * log_on(a, b);
    const Interval lb = log_on(b, b);
    Interval x = point(Q(0));
    if (lb.hi <= point(Q(-1, k)).lo) x.lo = (power_on(b, b, k) * lb).lo;
    else x.lo = point(Q(-1, 2 * k)).lo;
    return x;
}

// Bisect [a, b] until g's enclosure is >= 0 on every part; `budget` counts the parts.
SignFact prove_by_intervals(const std::function<Interval(const Q&, const Q&)>& g, const Q& a, const Q& b, int& budget,
                            const std::string& what) {
    std::vector<std::pair<Q, Q>> todo{{a, b}};
    while (!todo.empty()) {
        const auto [x, y] = todo.back();
        todo.pop_back();
        const Interval e = g(x, y);
        if (e.lo >= 0) continue;
        if (e.hi < 0 || --budget <= 0 || y - x < pow(Q(2), -50))
            return {SignVerdict::unknown, std::nullopt,
                    what + ": not decided on [" + short_string(x) + ", " + short_string(y) + "] (its enclosure [" +
                        e.lo.str(6) + ", " + e.hi.str(6) + "] reaches below 0)"};
        const Q m = (x + y) / 2;
        todo.push_back({m, y});
        todo.push_back({x, m});
    }
    return {SignVerdict::proved, std::nullopt, ""};
}

// The lower bounds below are sums of terms c r^k (log r)^[log] (at 0) or
// c r^low S^k (at the edge). Their enclosure on [a, b] is the tighter of the
// natural one (each term's) and the mean-value form g(m) + g'([a, b]) [a - m,
// b - m], m the midpoint, whose overestimate shrinks with (b - a)^2 (the
// series' terms cancel: the natural enclosure alone needs ~10^5 parts).
struct ZeroTerm {
    int k;
    bool log_r;
    Interval c;
};
struct EdgeTermI {
    int low, k;  // r^low S^k, k >= -1 (S^-1 only in derivatives, off r = 1)
    Interval c;
};

Interval term_on(const ZeroTerm& t, const Q& a, const Q& b) {
    return t.c * (t.log_r ? power_log_on(a, b, t.k) : power_on(a, b, t.k));
}

Interval s_power_on(const Q& a, const Q& b, int k) {
    if (k == 0) return point(Q(1));
    const Interval S = s_on(a, b);
    Interval x{fresh(), fresh()};
    if (k > 0) {
        mpfr_pow_si(x.lo.backend().data(), S.lo.backend().data(), k, MPFR_RNDD);
        mpfr_pow_si(x.hi.backend().data(), S.hi.backend().data(), k, MPFR_RNDU);
    } else {  // S.lo > 0 (b < 1)
        mpfr_pow_si(x.lo.backend().data(), S.hi.backend().data(), k, MPFR_RNDD);
        mpfr_pow_si(x.hi.backend().data(), S.lo.backend().data(), k, MPFR_RNDU);
    }
    return x;
}

Interval term_on(const EdgeTermI& t, const Q& a, const Q& b) { return t.c * power_on(a, b, t.low) * s_power_on(a, b, t.k); }

template <class T>
Interval sum_on(const std::vector<T>& terms, const Q& a, const Q& b) {
    Interval s = point(Q(0));
    for (const T& t : terms) s = s + term_on(t, a, b);
    return s;
}

// d/dr c r^k = c k r^(k-1); d/dr c r^k log r = c k r^(k-1) log r + c r^(k-1).
std::vector<ZeroTerm> derivative(const std::vector<ZeroTerm>& terms) {
    std::vector<ZeroTerm> d;
    for (const ZeroTerm& t : terms) {
        if (t.k > 0) d.push_back({t.k - 1, t.log_r, t.c * point(Q(t.k))});
        if (t.log_r) d.push_back({t.k - 1, false, t.c});
    }
    return d;
}
// d/dr c r^low S^k = c low r^(low-1) S^k - c k r^(low+1) S^(k-2) (S' = -r/S).
std::vector<EdgeTermI> derivative(const std::vector<EdgeTermI>& terms) {
    std::vector<EdgeTermI> d;
    for (const EdgeTermI& t : terms) {
        if (t.low != 0) d.push_back({t.low - 1, t.k, t.c * point(Q(t.low))});
        if (t.k != 0) d.push_back({t.low + 1, t.k - 2, t.c * point(Q(-t.k))});
    }
    return d;
}

// The natural enclosure, narrowed by the mean-value form where g' is
// bounded on [a, b] (`smooth`: not at r = 0 for log r, not at S = 0 for S^-1).
template <class T>
Interval enclosure_on(const std::vector<T>& g, const std::vector<T>& dg, const Q& a, const Q& b, bool smooth) {
    Interval e = sum_on(g, a, b);
    if (!smooth) return e;
    const Q m = (a + b) / 2;
    const Interval mv = sum_on(g, m, m) + sum_on(dg, a, b) * Interval{point(a - m).lo, point(b - m).hi};
    if (mv.lo > e.lo) e.lo = mv.lo;
    if (mv.hi < e.hi) e.hi = mv.hi;
    return e;
}

// f >= 0 on [0, t] from f's series at 0 (series.hpp): f >= T - B (r/t)^(N+1)
// with T = sum c_n r^n (+ d_n r^n log r); both sides over r^n0, n0 T's
// lowest power (a term of T at r^n0 must not have log r: it would decide
// the sign at 0 by itself, and is left unknown).
SignFact near_zero(const ClosedForm& f, const Q& t, int order, int& budget) {
    const auto B = truncation_bound(f, order, t);
    if (!B) return {SignVerdict::unknown, std::nullopt, "no convergent series at 0 on [0, " + short_string(t) + "]"};
    std::map<std::pair<int, bool>, Exact> c;  // (n, times log r) -> coefficient
    const ClosedForm T = series_at_zero(f, order);
    for (const auto& [k, p] : T.terms())
        for (int n = p.low(); n <= p.high(); ++n)
            if (p.coefficient(n) != 0) c[{n, k.basis == Basis::log}] += Exact::of(k.factor) * p.coefficient(n);
    std::erase_if(c, [](const auto& e) { return e.second.is_zero(); });
    if (c.empty()) return {SignVerdict::unknown, std::nullopt, "series at 0 is 0"};
    const int n0 = c.begin()->first.first;
    if (n0 < 0 || c.count({n0, true})) return {SignVerdict::unknown, std::nullopt, "series at 0 leads with r^n log r or r^-n"};
    std::vector<ZeroTerm> g;
    for (const auto& [key, v] : c) g.push_back({key.first - n0, key.second, enclose(v)});
    g.push_back({order + 1 - n0, false, point(-*B / pow(t, order + 1))});
    const std::vector<ZeroTerm> dg = derivative(g);
    return prove_by_intervals([&](const Q& a, const Q& b) { return enclosure_on(g, dg, a, b, a > 0); }, Q(0), t, budget,
                              "series at 0 to r^" + std::to_string(order));
}

// f >= 0 on [t, 1] from f's series in S at the edge (edge_series.hpp):
// f >= sum c r^low S^s - beta |lead|, lead = a r^low' S^s0 the leading term,
// both sides over S^s0.
SignFact near_edge(const ClosedForm& f, const Q& t, int order, int& budget) {
    const auto series = series_at_edge(f, order);
    const auto beta = edge_truncation_bound(f, order, t);
    if (!series || !beta || series->empty())
        return {SignVerdict::unknown, std::nullopt, "no series at the edge on [" + short_string(t) + ", 1]"};
    int s0 = series->front().s;
    for (const EdgeTerm& e : *series) s0 = std::min(s0, e.s);
    // |lead(r)| = |a| r^low S^s0 for one of the terms at S^s0 (edge_series.cpp
    // picks it): bounded by the largest |c| there times r^min(low, 0) (r <= 1)
    Real lead = fresh();
    int lead_low = 0;
    for (const EdgeTerm& e : *series)
        if (e.s == s0) {
            const Interval v = enclose(e.c);
            const Real m = max(abs(v.lo), abs(v.hi));
            if (m > lead) lead = m;
            lead_low = std::min(lead_low, e.low);
        }
    std::vector<EdgeTermI> g;
    for (const EdgeTerm& e : *series) g.push_back({e.low, e.s - s0, enclose(e.c)});
    g.push_back({lead_low, 0, point(-*beta) * Interval{lead, lead}});
    const std::vector<EdgeTermI> dg = derivative(g);
    return prove_by_intervals([&](const Q& a, const Q& b) { return enclosure_on(g, dg, a, b, b < 1); }, t, Q(1), budget,
                              "series at the edge to S^" + std::to_string(order));
}

// A closed form on the whole support [0, 1]: its series at 0 on [0, t] and
// in S on [t, 1], each at rising orders until proved.
SignFact prove_closed_form(const ClosedForm& f) {
    const Q t(9, 16);
    SignFact last;
    for (auto side : {near_zero, near_edge}) {
        for (int order : {60, 120}) {
            int budget = max_intervals;
            last = side(f, t, order, budget);
            if (last.verdict == SignVerdict::proved) break;
        }
        if (last.verdict != SignVerdict::proved) return last;
    }
    return last;
}

}  // namespace

SignFact non_negative(const Radial& f) {
    for (std::size_t i = 0; i < f.pieces.size(); ++i) {
        Laurent p;
        Atom factor;
        if (f.pieces[i].is_zero()) continue;
        const std::string piece = "piece [" + short_string(f.breaks[i]) + ", " + short_string(f.breaks[i + 1]) + "]";
        if (!f.pieces[i].single_polynomial(&p, &factor) || !p.is_polynomial()) {
            if (f.breaks[i] != 0 || f.breaks[i + 1] != 1)
                return {SignVerdict::unknown, std::nullopt,
                        piece + " is not a polynomial and not the whole support [0, 1] (no exact sign proof for it)"};
            SignFact s = prove_closed_form(f.pieces[i]);
            if (s.verdict != SignVerdict::proved) s.reason = piece + ", closed form: " + s.reason;
            if (s.verdict != SignVerdict::proved) return s;
            continue;
        }
        // pi^e log(p) > 0 (log of a prime): the sign is p's
        SignFact s = prove(p, f.breaks[i], f.breaks[i + 1], max_bisections);
        if (s.verdict != SignVerdict::proved) return s;
    }
    return {SignVerdict::proved, std::nullopt, ""};
}

}  // namespace mollify::gen
