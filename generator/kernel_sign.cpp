#include "kernel_sign.hpp"

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

}  // namespace

SignFact non_negative(const Radial& f) {
    for (std::size_t i = 0; i < f.pieces.size(); ++i) {
        Laurent p;
        Atom factor;
        if (f.pieces[i].is_zero()) continue;
        if (!f.pieces[i].single_polynomial(&p, &factor) || !p.is_polynomial())
            return {SignVerdict::unknown, std::nullopt,
                    "piece [" + short_string(f.breaks[i]) + ", " + short_string(f.breaks[i + 1]) +
                        "] is not a polynomial (no exact sign proof for its closed form)"};
        // pi^e log(p) > 0 (log of a prime): the sign is p's
        SignFact s = prove(p, f.breaks[i], f.breaks[i + 1], max_bisections);
        if (s.verdict != SignVerdict::proved) return s;
    }
    return {SignVerdict::proved, std::nullopt, ""};
}

}  // namespace mollify::gen
