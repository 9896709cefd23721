#include "centred_series.hpp"

#include "edge_series.hpp"
#include "error.hpp"
#include "once_per_run.hpp"
#include "search_choices.hpp"

#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

namespace mollify::gen {

namespace {

using Series = std::vector<Q>;  // coefficients of v^0 .. v^n, v = r - c

// A rational series over one common denominator, its numerators integers:
// a product of two then multiplies and adds integers only and reduces each
// coefficient once (GMP's rationals spend most of their time in the gcds of
// every addition and multiplication; exact either way, the same result).
struct Scaled {
    std::vector<Z> num;
    Z den;
};

Scaled scaled(const Series& s, std::size_t n) {
    Scaled out{{}, Z(1)};
    for (std::size_t i = 0; i < n; ++i)
        mpz_lcm(out.den.backend().data(), out.den.backend().data(), mpq_denref(s[i].backend().data()));
    out.num.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        Z m;
        mpz_divexact(m.backend().data(), out.den.backend().data(), mpq_denref(s[i].backend().data()));
        mpz_mul(m.backend().data(), m.backend().data(), mpq_numref(s[i].backend().data()));
        out.num.push_back(std::move(m));
    }
    return out;
}

// The first n coefficients of x y as integers over x.den y.den, unreduced.
Scaled product(const Scaled& x, const Scaled& y, std::size_t n) {
    Scaled out{std::vector<Z>(n), x.den * y.den};
    for (std::size_t k = 0; k < n; ++k) {
        mpz_ptr sum = out.num[k].backend().data();
        for (std::size_t i = 0; i <= k; ++i)
            if (mpz_sgn(x.num[i].backend().data()) != 0)
                mpz_addmul(sum, x.num[i].backend().data(), y.num[k - i].backend().data());
    }
    return out;
}

// The coefficients of a scaled series as reduced rationals.
Series reduced(const Scaled& s) {
    Series out(s.num.size());
    for (std::size_t k = 0; k < s.num.size(); ++k) {
        mpq_ptr q = out[k].backend().data();
        mpz_set(mpq_numref(q), s.num[k].backend().data());
        mpz_set(mpq_denref(q), s.den.backend().data());
        mpq_canonicalize(q);
    }
    return out;
}

// The first a.size() coefficients of a b (b at least as long as a).
Series product(const Series& a, const Series& b) {
    const std::size_t n = a.size();
    return reduced(product(scaled(a, n), scaled(b, n), n));
}

// acc += x (sign -1: acc -= x), both over their own denominators: over
// their lcm, the numerators rescaled, not reduced.
void accumulate(Scaled& acc, const Scaled& x, int sign) {
    Z lcm, fa, fx;
    mpz_lcm(lcm.backend().data(), acc.den.backend().data(), x.den.backend().data());
    mpz_divexact(fa.backend().data(), lcm.backend().data(), acc.den.backend().data());
    mpz_divexact(fx.backend().data(), lcm.backend().data(), x.den.backend().data());
    if (sign < 0) mpz_neg(fx.backend().data(), fx.backend().data());
    const bool rescale = mpz_cmp_ui(fa.backend().data(), 1) != 0;
    for (std::size_t k = 0; k < acc.num.size(); ++k) {
        mpz_ptr a = acc.num[k].backend().data();
        if (rescale) mpz_mul(a, a, fa.backend().data());
        mpz_addmul(a, x.num[k].backend().data(), fx.backend().data());
    }
    acc.den = std::move(lcm);
}

Series integral(const Series& s) {  // the antiderivative vanishing at v = 0
    Series out(s.size(), Q(0));
    for (std::size_t k = 0; k + 1 < s.size(); ++k) out[k + 1] = s[k] / Q(static_cast<long long>(k + 1));
    return out;
}

// The first n terms of r^k = (c + v)^k = sum_j binom(k, j) c^(k-j) v^j
// (any integer k) about c = p/q, as integers over one denominator, made so
// (no rational arithmetic, no gcd):
// k >= 0: binom(k, j) p^(k-j) q^j over q^k; k = -m < 0: binom(k, j) c^(k-j)
// = (-1)^j binom(m+j-1, j) (q/p)^(m+j), i.e. (-1)^j binom(m+j-1, j) q^(m+j)
// p^(n-1-j) over p^(m+n-1).
Scaled scaled_power_of_r(int k, const Q& c, std::size_t n) {
    const Z p = numerator(c), q = denominator(c);
    Scaled out{std::vector<Z>(n), Z(1)};
    auto power = [](const Z& base, unsigned long e) {
        Z x;
        mpz_pow_ui(x.backend().data(), base.backend().data(), e);
        return x;
    };
    Z binom = 1;
    if (k >= 0) {
        const unsigned long K = static_cast<unsigned long>(k);
        out.den = power(q, K);
        Z q_j = 1;  // q^j
        for (unsigned long j = 0; j < n && j <= K; ++j) {
            out.num[j] = binom * power(p, K - j) * q_j;
            mpz_mul_ui(binom.backend().data(), binom.backend().data(), K - j);  // binom(K, j + 1)
            mpz_divexact_ui(binom.backend().data(), binom.backend().data(), j + 1);
            q_j *= q;
        }
        return out;
    }
    const unsigned long m = static_cast<unsigned long>(-static_cast<long>(k));
    out.den = power(p, m + n - 1);
    Z q_power = power(q, m);  // q^(m+j)
    for (unsigned long j = 0; j < n; ++j) {
        out.num[j] = binom * q_power * power(p, n - 1 - j);
        if (j % 2 == 1) mpz_neg(out.num[j].backend().data(), out.num[j].backend().data());
        mpz_mul_ui(binom.backend().data(), binom.backend().data(), m + j);  // binom(m + j, j + 1)
        mpz_divexact_ui(binom.backend().data(), binom.backend().data(), j + 1);
        q_power *= q;
    }
    return out;
}

// S^j = g^(j/2), g = 1 - r^2 = S(c)^2 - 2c v - v^2, by J.C.P. Miller's
// recurrence for powers of a series: from g h' = (j/2) g' h,
// k g_0 h_k = sum_{i=1}^{min(k,2)} ((j/2 + 1) i - k) g_i h_(k-i).
// Continues `h` (its first terms, if any, already those of S^j) to order.
void extend_power_of_S(Series& h, int j, const Q& c, const Q& s, int order) {
    const Q g[3] = {s * s, Q(-2) * c, Q(-1)};
    const Q alpha = ratio(j, 2);
    if (h.empty()) h.push_back(j >= 0 ? pow(s, j) : Q(1) / pow(s, -j));
    for (int k = static_cast<int>(h.size()); k <= order; ++k) {
        Q sum = 0;
        for (int i = 1; i <= std::min(k, 2); ++i) sum += ((alpha + 1) * Q(i) - Q(k)) * g[i] * h[static_cast<std::size_t>(k - i)];
        h.push_back(sum / (Q(k) * g[0]));
    }
}

// The first order + 1 terms of S^j about c (s = S(c)), kept per thread and
// centre: the pieces of every quantity and dimension of a kernel share their
// centres, and the recurrence's rationals grow with k (their gcds were a
// tenth of a missing Wendland function's emit).
Series power_of_S(int j, const Q& c, const Q& s, int order) {
    thread_local std::map<std::pair<int, Q>, Series> cache;
    Series& h = cache[{j, c}];
    if (static_cast<int>(h.size()) <= order) extend_power_of_S(h, j, c, s, order);
    return Series(h.begin(), h.begin() + order + 1);
}

// sqrt(x) for a rational square, else Error.
Q rational_sqrt(const Q& x) {
    auto root = [](const Z& n) {
        const Z r = sqrt(n);
        if (r * r != n) return Z(-1);
        return r;
    };
    const Z p = root(numerator(x)), q = root(denominator(x));
    if (p < 0 || q < 0) fail("internal: centre with irrational sqrt(1 - c^2): 1 - c^2 = " + short_string(x));
    return Q(p, q);
}

Real real(const Q& q, unsigned bits) {
    Real x(0, bits * 30103 / 100000 + 2);
    mpfr_set_q(x.backend().data(), q.backend().data(), MPFR_RNDN);
    return x;
}

Q rational(const Real& x) {
    Q q;
    mpfr_get_q(q.backend().data(), x.backend().data());
    return q;
}

// arcsech c, arcsin c, log c, each correctly rounded to `bits` (raw MPFR:
// Boost's expression temporaries may take the thread's default precision,
// too low for Ziv's rounding of a cancelling sum, and differing by thread).
struct Constants {
    Real arcsech, arcsin, log;
};
void compute_constants(const Q& c, unsigned bits, Constants& k) {
    const Q s = rational_sqrt(Q(1) - c * c), argument = (1 + s) / c;  // arcsech c = log((1 + S(c))/c)
    for (Real* x : {&k.arcsech, &k.arcsin, &k.log}) mpfr_set_prec(x->backend().data(), bits);
    mpfr_t y;
    mpfr_init2(y, bits + 8);
    mpfr_set_q(y, argument.backend().data(), MPFR_RNDN);
    mpfr_log(k.arcsech.backend().data(), y, MPFR_RNDN);
    mpfr_set_q(y, c.backend().data(), MPFR_RNDN);
    mpfr_asin(k.arcsin.backend().data(), y, MPFR_RNDN);
    mpfr_log(k.log.backend().data(), y, MPFR_RNDN);
    mpfr_clear(y);
}
// Kept per thread for each (c, bits): every coefficient of a piece is
// evaluated about the same centre at the same few precisions (the choice of
// form, Ziv's rounding, the low parts), and MPFR's log and asin of c were a
// tenth of `mollify-gen emit` when computed per coefficient. Filled in place
// (not copied: a copied Real may take the thread's default precision).
const Constants& constants(const Q& c, unsigned bits) {
    thread_local std::map<std::pair<Q, unsigned>, Constants> cache;
    // The last entry asked for first: a piece's coefficients ask for the same
    // one in turn, and the map's search compares rationals by cross products.
    thread_local const std::pair<const std::pair<Q, unsigned>, Constants>* last = nullptr;
    if (last && last->first.second == bits && last->first.first == c) return last->second;
    auto [it, inserted] = cache.try_emplace(std::pair{c, bits});
    if (inserted) {
        try {
            compute_constants(c, bits, it->second);
        } catch (...) {
            cache.erase(it);  // no half-filled entry for the next call
            throw;
        }
    }
    last = &*it;  // once filled
    return it->second;
}

}  // namespace

std::pair<Real, Real> CentredValue::evaluate(const Q& c, unsigned bits) const {
    const Constants& k = constants(c, bits + 16);
    std::pair<Real, Real> out = one.evaluate(bits);
    mpfr_ptr sum = out.first.backend().data(), magnitude = out.second.backend().data();
    mpfr_t t;
    mpfr_init2(t, bits + 16);
    auto add = [&](const Exact& x, const Real& constant) {
        const auto [v, m] = x.evaluate(bits);
        mpfr_mul(t, v.backend().data(), constant.backend().data(), MPFR_RNDN);
        mpfr_add(sum, sum, t, MPFR_RNDN);
        mpfr_mul(t, m.backend().data(), constant.backend().data(), MPFR_RNDN);
        mpfr_abs(t, t, MPFR_RNDN);
        mpfr_add(magnitude, magnitude, t, MPFR_RNDN);
    };
    add(arcsech, k.arcsech);
    add(arcsin, k.arcsin);
    add(log, k.log);
    mpfr_clear(t);
    return out;
}

namespace {

// The constants' names about c, kept per thread: every coefficient of a
// piece names the same three (S(c) by an integer square root each time was
// most of writing the exact values beside the hex floats).
struct ConstantNames {
    std::string arcsech, arcsin, log;
};
const ConstantNames& constant_names(const Q& c) {
    thread_local std::map<Q, ConstantNames> cache;
    thread_local const std::pair<const Q, ConstantNames>* last = nullptr;  // as constants(): the last first
    if (last && last->first == c) return last->second;
    auto [it, fresh] = cache.try_emplace(c);
    if (fresh) {
        try {
            const Q s = rational_sqrt(Q(1) - c * c);  // fails for a centre without a rational S(c)
            it->second = {"log(" + short_string((1 + s) / c) + ")",  // arcsech c = log((1 + S(c))/c)
                          "arcsin(" + short_string(c) + ")", "log(" + short_string(c) + ")"};
        } catch (...) {
            cache.erase(it);  // no empty entry for the next call
            throw;
        }
    }
    last = &*it;  // once filled
    return it->second;
}

}  // namespace

std::string CentredValue::to_string(const Q& c) const {
    const ConstantNames& names = constant_names(c);
    std::string out;
    auto add = [&](const Exact& x, const std::string* constant) {
        if (x.is_zero()) return;
        if (!out.empty()) out += " + ";
        out += constant ? "(" + x.to_string() + ") * " + *constant : x.to_string();
    };
    add(one, nullptr);
    add(arcsech, &names.arcsech);
    add(arcsin, &names.arcsin);
    add(log, &names.log);
    return out.empty() ? "0" : out;
}

std::vector<CentredValue> taylor_at_centre(const ClosedForm& f, const Q& c, int order) {
    const Q s = rational_sqrt(Q(1) - c * c);
    const std::size_t n = static_cast<std::size_t>(order) + 1;
    std::map<int, Series> S;  // S^j, j -> series
    auto S_power = [&](int j) -> const Series& {
        auto it = S.find(j);
        if (it == S.end()) it = S.emplace(j, power_of_S(j, c, s, order)).first;
        return it->second;
    };
    std::map<int, Scaled> powers;  // r^k, k -> series
    auto r_power = [&](int k) -> const Scaled& {
        auto it = powers.find(k);
        if (it == powers.end()) it = powers.emplace(k, scaled_power_of_r(k, c, n)).first;
        return it->second;
    };
    const Series inverse_r = reduced(r_power(-1));
    // The antiderivatives of arcsech', arcsin', log' (once, not per term),
    // and the powers of S, as integers over one denominator.
    std::map<Basis, Scaled> integrals;
    auto integral_of = [&](Basis b) -> const Scaled& {
        auto it = integrals.find(b);
        if (it != integrals.end()) return it->second;
        Series d = b == Basis::arcsech ? product(inverse_r, S_power(-1)) : b == Basis::arcsin ? S_power(-1) : inverse_r;
        return integrals.emplace(b, scaled(integral(d), n)).first->second;
    };
    std::map<int, Scaled> S_scaled;
    auto S_power_scaled = [&](int j) -> const Scaled& {
        auto it = S_scaled.find(j);
        if (it == S_scaled.end()) it = S_scaled.emplace(j, scaled(S_power(j), n)).first;
        return it->second;
    };
    // The series of each slot (1, arcsech c, arcsin c, log c) and constant
    // pi^e log p, summed over the terms as integers over one denominator
    // and reduced once at the end, not reduced (a gcd per coefficient) and
    // added as Exact per term: this function's instructions over the
    // catalogue 4.0e9 -> 3.0e9 (callgrind).
    Exact CentredValue::*const slots[] = {&CentredValue::one, &CentredValue::arcsech, &CentredValue::arcsin,
                                          &CentredValue::log};
    std::map<std::pair<int, Atom>, Scaled> sums;
    auto add = [&](int slot, const Atom& atom, int sign, Scaled x) {
        auto [it, fresh] = sums.try_emplace({slot, atom});
        if (!fresh) return accumulate(it->second, x, sign);
        if (sign < 0)
            for (Z& v : x.num) mpz_neg(v.backend().data(), v.backend().data());
        it->second = std::move(x);
    };
    for (const auto& [key, p] : f.terms()) {
        // P = sum_k p_k r^k over the common denominator of the p_k r^k.
        std::vector<std::pair<Z, const Scaled*>> parts;  // p_k's numerator times den / (its den r^k's den)
        Z den = 1;
        for (int k = p.low(); k <= p.high(); ++k) {
            const Q pk = p.coefficient(k);
            if (pk == 0) continue;
            const Scaled& rk = r_power(k);
            parts.emplace_back(Z(denominator(pk) * rk.den), &rk);
            mpz_lcm(den.backend().data(), den.backend().data(), parts.back().first.backend().data());
        }
        std::size_t i = 0;
        for (int k = p.low(); k <= p.high(); ++k) {
            const Q pk = p.coefficient(k);
            if (pk == 0) continue;
            Z& m = parts[i++].first;
            mpz_divexact(m.backend().data(), den.backend().data(), m.backend().data());
            m *= numerator(pk);
        }
        Scaled P{std::vector<Z>(n), den};
        for (std::size_t j = 0; j < n; ++j)
            for (const auto& [m, rk] : parts)
                mpz_addmul(P.num[j].backend().data(), m.backend().data(), rk->num[j].backend().data());
        const Atom& atom = key.factor;
        switch (key.basis) {
            case Basis::one: add(0, atom, 1, std::move(P)); break;
            case Basis::sqrt_power: add(0, atom, 1, product(P, S_power_scaled(key.s_power), n)); break;
            case Basis::arcsech:  // arcsech' = -1/(r S)
                add(0, atom, -1, product(P, integral_of(Basis::arcsech), n));
                add(1, atom, 1, std::move(P));
                break;
            case Basis::arcsin:  // arcsin' = 1/S
                add(0, atom, 1, product(P, integral_of(Basis::arcsin), n));
                add(2, atom, 1, std::move(P));
                break;
            case Basis::log:  // log' = 1/r
                add(0, atom, 1, product(P, integral_of(Basis::log), n));
                add(3, atom, 1, std::move(P));
                break;
        }
    }
    std::vector<CentredValue> out(n);
    for (const auto& [slot_atom, sum] : sums) {
        const Exact unit = Exact::of(slot_atom.second);
        const Series x = reduced(sum);
        for (std::size_t k = 0; k < n; ++k)
            if (x[k] != 0) out[k].*slots[slot_atom.first] += unit * x[k];
    }
    return out;
}

namespace {

constexpr unsigned bound_bits = 128;

// A rigorous bound M >= |f(z)| on the circle |z - c| = R (0 < R < min(c,
// 1 - c)), term by term (the terms cancel on the real line, not in the
// bound): |z| in [c - R, c + R], Re z > 0, |1 - z^2| <= 1 + |z|^2 and
// >= (1 - c - R)(1 + c - R); arcsech z = log((1 + S)/z) with Re S >= 0 (the
// principal branches are analytic on the disc, which avoids 0 and +-1), so
// |1 + S| >= 1 and |arcsech z| <= max|log|w|| + pi; |log z| <= max|log|z|| +
// pi/2; |arcsin z| = |int_0^z dt/sqrt(1 - t^2)| <= |z| / sqrt(1 - c - R)
// (on the segment |1 - t| >= 1 - Re t, |1 + t| >= 1). MPFR at 128 bits; the
// factor 1.01 covers its rounding.
// f's terms as circle_bound reads them, converted to MPFR once per closed
// form (not at every radius of every piece): |c_k| and the size of the
// constant factor.
struct CircleTerms {
    struct Term {
        TermKey key;
        std::vector<std::pair<int, Real>> abs_c;  // k, |c_k| (c_k != 0)
        Real factor;  // |pi^e log p| + its evaluation's magnitude 2^-100
    };
    std::vector<Term> terms;
    explicit CircleTerms(const ClosedForm& f) {
        for (const auto& [key, p] : f.terms()) {
            Term t{key, {}, Real()};
            for (int k = p.low(); k <= p.high(); ++k)
                if (p.coefficient(k) != 0) t.abs_c.emplace_back(k, boost::multiprecision::abs(real(p.coefficient(k), bound_bits)));
            const auto [factor, magnitude] = Exact::of(key.factor).evaluate(bound_bits);
            t.factor = boost::multiprecision::abs(factor) + magnitude / boost::multiprecision::pow(Real(2), 100);
            terms.push_back(std::move(t));
        }
    }
};

Real circle_bound(const CircleTerms& f, const Q& c, const Real& R) {
    using boost::multiprecision::abs;
    using boost::multiprecision::log;
    using boost::multiprecision::max;
    using boost::multiprecision::pow;
    using boost::multiprecision::sqrt;
    const Real cc = real(c, bound_bits), one = real(Q(1), bound_bits), pi = pi_at(bound_bits);
    const Real zmax = cc + R, zmin = cc - R;
    const Real gmax = one + zmax * zmax, gmin = (one - zmax) * (one + zmin);
    const Real smax = sqrt(gmax);
    const Real arcsech_max = max(abs(log(zmax)), abs(log((one + smax) / zmin))) + pi;
    const Real log_max = max(abs(log(zmax)), abs(log(zmin))) + pi / 2;
    const Real arcsin_max = zmax / sqrt(one - zmax);
    Real M = real(Q(0), bound_bits);
    std::map<int, Real> powers, s_powers;  // zmax^k or zmin^k, and the S^j bound: once per radius
    auto power = [&](int k) -> const Real& {
        auto it = powers.find(k);
        if (it == powers.end()) it = powers.emplace(k, pow(k >= 0 ? zmax : zmin, k)).first;
        return it->second;
    };
    for (const CircleTerms::Term& t : f.terms) {
        Real poly = real(Q(0), bound_bits);
        for (const auto& [k, a] : t.abs_c) poly += a * power(k);
        Real basis = one;
        switch (t.key.basis) {
            case Basis::one: break;
            case Basis::sqrt_power: {
                auto it = s_powers.find(t.key.s_power);
                if (it == s_powers.end())
                    it = s_powers.emplace(t.key.s_power, pow(t.key.s_power > 0 ? gmax : gmin, Real(t.key.s_power) / 2)).first;
                basis = it->second;
                break;
            }
            case Basis::arcsech: basis = arcsech_max; break;
            case Basis::log: basis = log_max; break;
            case Basis::arcsin: basis = arcsin_max; break;
        }
        M += t.factor * poly * basis;
    }
    return M * Real(101) / 100;
}

// f and max(|f(r)|, |r f'(r)|) at r = lo + (hi - lo) i/n, i = 0 .. n, in
// MPFR at 200 bits: the size of f there in the sense of an exact evaluator
// that is handed r with a relative error of half an ulp.
std::vector<std::pair<Real, Real>> sizes(const PreparedForm& pf, const PreparedForm& pdf, const Q& lo, const Q& hi, int n) {
    std::vector<std::pair<Real, Real>> out;
    for (const Q& x : equispaced(lo, hi, n)) {
        PointValues at(x, 200);
        const Real& r = at.power_of_r(1);  // x at 200 bits, as real(x, 200)
        Real v = pf.value(at);
        // max(|v|, |r f'|) in raw MPFR at the forms' precision (Boost's max
        // takes the thread's default precision, which its expressions leave
        // at whatever they last used: the scale differed from run to run).
        Real s = pdf.value(at);
        mpfr_ptr size = s.backend().data();
        mpfr_mul(size, size, r.backend().data(), MPFR_RNDN);
        mpfr_abs(size, size, MPFR_RNDN);
        if (mpfr_cmpabs(v.backend().data(), size) > 0) mpfr_abs(size, v.backend().data(), MPFR_RNDN);
        out.emplace_back(std::move(v), std::move(s));
    }
    return out;
}

// The check of an emitted piece (emit_checks.cpp) compares with f at 129
// points, lo + (hi - lo) i/128: f and max(|f|, |r f'|) there.
constexpr int checked_points = 128;

// min over 257 points of [lo, hi] of max(|f(r)|, |r f'(r)|) (sampled, not
// proven; the truncation is then made 2^-61 of it, a factor 2 of room).
// Every other sample into `samples` (the check's points, emit_checks.cpp).
Q intrinsic_scale(const PreparedForm& pf, const PreparedForm& pdf, const Q& lo, const Q& hi,
                  std::vector<std::pair<Real, Real>>& samples) {
    std::vector<std::pair<Real, Real>> all = sizes(pf, pdf, lo, hi, 2 * checked_points);
    Real m;
    samples.clear();
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (i == 0 || all[i].second < m) m = all[i].second;
        if (i % 2 == 0) samples.push_back(std::move(all[i]));
    }
    return rational(m);
}

// A centre c = 2t/(1 + t^2) in (above, at], S(c) = (1 - t^2)/(1 + t^2):
// t = p/q with the smallest q <= 4096 (small numbers in the coefficients),
// the largest such c. t(c) = (1 - sqrt(1 - c^2))/c increases with c.
Q pythagorean_between(const Q& above, const Q& at) {
    auto t_of = [](const Q& c) {
        const double x = static_cast<double>(c);
        return (1 - std::sqrt(1 - x * x)) / x;
    };
    const double t_lo = t_of(above), t_hi = t_of(at);
    for (long long q = 2; q <= 4096; ++q) {
        std::optional<Q> best;
        for (long long p = static_cast<long long>(std::floor(t_lo * static_cast<double>(q)));
             p <= static_cast<long long>(std::ceil(t_hi * static_cast<double>(q))); ++p) {
            if (p < 1 || p >= q) continue;
            const Q t = ratio(p, q), c = Q(2) * t / (1 + t * t);
            if (c <= at && c > above && (!best || c > *best)) best = c;
        }
        if (best) return *best;
    }
    fail("internal: no Pythagorean centre in (" + short_string(above) + ", " + short_string(at) + "]");
}

constexpr int max_order = 200;

// A truncation order and its proof: the circle of radius tenth/20 min(c,
// 1 - c) about c, and the bound on the tail there.
struct Order {
    int n = max_order + 1;
    Q tail;
    int tenth = 0;
};

// The order with M (d/R)^(n+1) / (1 - d/R) <= target on the circle of radius
// R = tenth/20 min(c, 1 - c), the tail bound with it; nullopt where R is
// within 1.05 d or no order up to max_order proves the target.
// With m > 0 the series is that of f S^-m: M times max |S^-m| on the circle,
// ((1 - c - R)(1 + c - R))^(-m/2).
// `bounds` keeps circle_bound per radius (tenth) for the other m.
std::optional<Order> order_at_radius(const CircleTerms& f, int m, const Q& c, const Q& d, const Q& target, int tenth,
                                     std::map<int, Real>& bounds) {
    const Q R = std::min<Q>(c, Q(1 - c)) * ratio(tenth, 20);
    if (R <= d * Q(21, 20)) return std::nullopt;
    const Real Rr = real(R, bound_bits), cc = real(c, bound_bits);
    auto it = bounds.find(tenth);
    if (it == bounds.end()) it = bounds.emplace(tenth, circle_bound(f, c, Rr)).first;
    const Real M = it->second * boost::multiprecision::pow((1 - cc - Rr) * (1 + cc - Rr), Real(-m) / 2) *
                   Real(101) / 100;
    const Real x = real(d / R, bound_bits), t = real(target, bound_bits);
    // n + 1 >= log(M / ((1 - x) t)) / log(1/x)
    const Real need = boost::multiprecision::log(M / ((1 - x) * t)) / boost::multiprecision::log(1 / x);
    const int n = std::max(1, static_cast<int>(std::ceil(static_cast<double>(need))));
    if (n > max_order) return std::nullopt;  // the caller fails if no radius is left
    const Q tail = rational(M * boost::multiprecision::pow(x, n + 1) / (1 - x)) * Q(101, 100);
    if (tail > target) return std::nullopt;
    return Order{n, tail, tenth};
}

// The best order over the radii tenth/20 min(c, 1 - c), tenth = 5 .. 19: the
// lowest, on the smallest such radius; n > max_order where none proves it.
Order order_for(const CircleTerms& f, int m, const Q& c, const Q& d, const Q& target, std::map<int, Real>& bounds) {
    Order best;
    for (int tenth = 5; tenth <= 19; ++tenth)
        if (const auto o = order_at_radius(f, m, c, d, target, tenth, bounds); o && o->n < best.n) best = *o;
    return best;
}

}  // namespace

namespace {

// The lowest power of S in f's series at the edge (edge_series.hpp): f
// vanishes like S^m there, and the Taylor pieces next to the edge are
// written as S^m times the series of f S^-m, which does not cancel where f
// falls steeply towards the edge. 0 where f has no edge series.
int edge_power_of_S(const ClosedForm& f) {
    const auto terms = series_at_edge(f, 40);
    if (!terms) return 0;
    int m = std::numeric_limits<int>::max();
    for (const EdgeTerm& t : *terms) m = std::min(m, t.s);
    return m == std::numeric_limits<int>::max() ? 0 : m;
}

// The coefficients of a w (the first a.size() of them), w a rational series
// over one denominator (at least a.size() terms): per slot and constant
// pi^e log p, a product of rational series.
std::vector<CentredValue> times_series(const std::vector<CentredValue>& a, const Scaled& w) {
    std::vector<CentredValue> out(a.size());
    for (Exact CentredValue::*slot : {&CentredValue::one, &CentredValue::arcsech, &CentredValue::arcsin, &CentredValue::log}) {
        std::map<Atom, Series> parts;
        for (std::size_t i = 0; i < a.size(); ++i)
            for (const auto& [atom, q] : (a[i].*slot).terms()) {
                Series& s = parts[atom];
                if (s.empty()) s.assign(a.size(), Q(0));
                s[i] = q;
            }
        for (const auto& [atom, s] : parts) {
            const Series y = reduced(product(scaled(s, s.size()), w, s.size()));
            const Exact unit = Exact::of(atom);
            for (std::size_t k = 0; k < y.size(); ++k)
                if (y[k] != 0) out[k].*slot += unit * y[k];
        }
    }
    return out;
}

// The coefficients of a S^-m, from those of a.
std::vector<CentredValue> times_power_of_S(const std::vector<CentredValue>& a, int m, const Q& c) {
    if (m == 0) return a;
    return times_series(a, scaled(power_of_S(-m, c, rational_sqrt(Q(1) - c * c), static_cast<int>(a.size()) - 1), a.size()));
}

// The coefficients of a r^k (k >= 0: (c + v)^k, k + 1 terms).
std::vector<CentredValue> times_power_of_r(const std::vector<CentredValue>& a, int k, const Q& c) {
    if (k == 0) return a;
    return times_series(a, scaled_power_of_r(k, c, a.size()));
}

// The rounding error of a piece's double evaluation, in ulps of f (a
// heuristic to choose its form): Horner's sum |a_n v^n| / |sum a_n v^n|
// (max over 17 points) plus the error of the factors, about an ulp of q per
// power of r and an ulp of S per power of S.
double expected_error(const CentredPiece& p) {
    std::vector<double> a;
    for (const CentredValue& x : p.a) a.push_back(static_cast<double>(x.evaluate(p.centre, 64).first));
    double worst = 0;
    for (int i = 0; i <= 16; ++i) {
        const double v = static_cast<double>(p.lo + (p.hi - p.lo) * ratio(i, 16) - p.centre);
        double sum = 0, magnitude = 0;
        for (std::size_t n = a.size(); n-- > 0;) {
            sum = sum * v + a[n];
            magnitude = magnitude * std::abs(v) + std::abs(a[n]);
        }
        worst = std::max(worst, sum == 0 ? 1e300 : magnitude / std::abs(sum));
    }
    return worst + std::abs(p.low) + p.s_power;
}

// Where the piece from x ends and about what it is centred: each piece
// [x, y] within kappa min(c, 1 - c) of its centre, kappa = 3/10 (the Taylor
// terms then shrink like (kappa/ratio)^n); d, the distance from c to the
// farther end.
struct Span {
    Q c, y, d;
};
Span span_from(const Q& x, const Q& hi) {
    const Q kappa(3, 10);
    const Q ideal = std::min<Q>(Q(x / (1 - kappa)), Q((x + kappa) / (1 + kappa)));
    const Q c = pythagorean_between(Q(x + (ideal - x) / 2), ideal);
    // y: c + kappa min(c, 1 - c) down to a dyadic breakpoint (exact as a
    // double), on a grid of 1/8 of that reach.
    const Q reach = kappa * std::min<Q>(c, Q(1 - c));
    long long grid = 8;
    while (Q(grid) * reach < 8) grid *= 2;
    Q y = Q(static_cast<long long>(std::floor(static_cast<double>((c + reach) * grid))), grid);
    if (y >= hi || hi - y < reach / 4) y = hi;
    return {c, y, std::max<Q>(Q(c - x), Q(y - c))};
}

// What both ways to a piece read of f: r^-K is its most negative power of r;
// f and f' at 200 bits (the samples), the circle bounds' terms of f and
// f r^K (the orders).
struct Prepared {
    explicit Prepared(const ClosedForm& form)
        : f(form), K(most_negative_power(form)), pf(form, 200), pdf(form.derivative(), 200), f_terms(form),
          fK_terms(form * Laurent::monomial(Q(1), K)) {}
    static int most_negative_power(const ClosedForm& f) {
        int K = 0;
        for (const auto& [key, p] : f.terms()) K = std::max(K, -p.low());
        return K;
    }
    const ClosedForm& f;
    int K;
    PreparedForm pf, pdf;
    CircleTerms f_terms, fK_terms;
};

// The piece r^-k S^j T on [x, y] (T the Taylor series of g = r^k S^-j f to
// (r - c)^order) from the first order + 1 coefficients of f S^-j's series
// (`base`): g's is that times r^k, a polynomial (exact: the same coefficients
// as g's own series). |f - r^-k S^j T| <= x^-k |g - T| (S <= 1 on [x, y]).
CentredPiece make_piece(const Span& s, const Q& x, const std::vector<CentredValue>& base, const CentredChoice& choice,
                        const Q& tail) {
    std::vector<CentredValue> b = times_power_of_r(
        std::vector<CentredValue>(base.begin(), base.begin() + choice.order + 1), choice.k, s.c);
    return CentredPiece{x, s.y, s.c, -choice.k, choice.j, std::move(b), tail / pow(x, choice.k), choice.scale, {}, {}};
}

// The piece from x as the search makes it: f = r^-k S^j g, with k = 0 or K
// (without f's negative powers, which cancel near 0) and j = 0 or m (f
// vanishes like S^m at the edge, edge_power_of_S); the variant whose order
// is provable with the smallest expected rounding error.
std::pair<CentredPiece, CentredChoice> searched_piece(const Prepared& p, int m, const Q& x, const Q& hi) {
    const Span s = span_from(x, hi);
    std::vector<std::pair<Real, Real>> samples;
    const Q scale = intrinsic_scale(p.pf, p.pdf, x, s.y, samples);
    if (scale == 0) fail("internal: the quantity and its derivative vanish on [" + short_string(x) + ", " + short_string(s.y) + "]");
    const Q target = scale / pow(Q(2), 61);
    // The variants' orders first; then f's series once, to the highest of
    // them, times S^-m once.
    struct Variant {
        int k, j;
        Order order;
    };
    std::vector<Variant> variants;
    for (const int k : {0, p.K}) {
        if (k == p.K && k == 0 && !variants.empty()) break;
        const CircleTerms& g = k == 0 ? p.f_terms : p.fK_terms;
        std::map<int, Real> bounds;
        const Order plain = order_for(g, 0, s.c, s.d, target * pow(x, k), bounds);
        const Order factored = m > 0 ? order_for(g, m, s.c, s.d, target * pow(x, k), bounds) : plain;
        for (const int j : {0, m}) {
            const Order& order = j == 0 ? plain : factored;
            if (order.n > max_order || (j == m && j == 0 && !variants.empty() && variants.back().k == k)) continue;
            variants.push_back({k, j, order});
        }
    }
    int most = 0;
    for (const Variant& v : variants) most = std::max(most, v.order.n);
    std::optional<std::pair<CentredPiece, CentredChoice>> best;
    double best_error = 0;
    if (!variants.empty()) {
        const std::vector<CentredValue> a = taylor_at_centre(p.f, s.c, most);
        const std::vector<CentredValue> aS = m > 0 ? times_power_of_S(a, m, s.c) : a;
        for (const Variant& v : variants) {
            const CentredChoice choice{v.k, v.j, v.order.n, v.order.tenth, scale};
            CentredPiece piece = make_piece(s, x, v.j == 0 ? a : aS, choice, v.order.tail);
            const double e = expected_error(piece);
            if (!best || e < best_error) {
                best_error = e;
                best.emplace(std::move(piece), choice);
            }
        }
    }
    if (!best) fail("internal: no Taylor order <= " + std::to_string(max_order) + " about " + short_string(s.c));
    best->first.samples = std::move(samples);
    return std::move(*best);
}

// The piece from x as `choice` says, its order proven again (the same bound
// on the same circle as the search's: valid for any power j of S factored
// out); nullopt where the choice does not fit f (then the search decides).
// The scale, min max(|f|, |r f'|) over 257 points, is the search's; the
// check's 129 of them are sampled here.
std::optional<CentredPiece> chosen_piece(const Prepared& p, const Q& x, const Q& hi, const CentredChoice& choice) {
    const Span s = span_from(x, hi);
    if ((choice.k != 0 && choice.k != p.K) || choice.j < 0 || choice.scale <= 0) return std::nullopt;
    const Q target = choice.scale / pow(Q(2), 61) * pow(x, choice.k);
    std::map<int, Real> bounds;
    const auto order = order_at_radius(choice.k == 0 ? p.f_terms : p.fK_terms, choice.j, s.c, s.d, target, choice.tenth, bounds);
    if (!order || order->n != choice.order) return std::nullopt;
    std::vector<std::pair<Real, Real>> samples = sizes(p.pf, p.pdf, x, s.y, checked_points);
    const Real scale = real(choice.scale, 200);
    for (const auto& [value, size] : samples)  // the scale is a minimum of these sizes, at other points too
        if (size < scale) return std::nullopt;
    const std::vector<CentredValue> a = taylor_at_centre(p.f, s.c, choice.order);
    CentredPiece piece = make_piece(s, x, choice.j == 0 ? a : times_power_of_S(a, choice.j, s.c), choice, order->tail);
    piece.samples = std::move(samples);
    return piece;
}

// The pieces from the compiled-in choices; nullopt where they do not fit.
std::optional<std::vector<CentredPiece>> chosen_pieces(const Prepared& p, const Q& lo, const Q& hi,
                                                       const CentredChoices& choices) {
    std::vector<CentredPiece> out;
    for (Q x = lo; x < hi;) {
        if (out.size() == choices.size()) return std::nullopt;
        auto piece = chosen_piece(p, x, hi, choices[out.size()]);
        if (!piece) return std::nullopt;
        x = piece->hi;
        out.push_back(std::move(*piece));
    }
    if (out.size() != choices.size()) return std::nullopt;
    return out;
}

}  // namespace

namespace {

// The pieces of f as the compiled-in choices say, or searched.
std::vector<CentredPiece> pieces_of(const ClosedForm& f, const Q& lo, const Q& hi) {
    const Prepared p(f);
    const std::uint64_t key = search_key("centred", f, {lo, hi});
    std::optional<std::vector<CentredPiece>> out;
    if (const CentredChoices* known = known_choice<CentredChoices>(key)) out = chosen_pieces(p, lo, hi, *known);
    if (!out) {
        out.emplace();
        CentredChoices choices;
        const int m = edge_power_of_S(f);
        for (Q x = lo; x < hi;) {
            auto [piece, choice] = searched_piece(p, m, x, hi);
            x = piece.hi;
            out->push_back(std::move(piece));
            choices.push_back(std::move(choice));
        }
        if (searching_afresh()) record_choice(key, choices);
    }
    for (CentredPiece& piece : *out) piece.sampled = f;
    return std::move(*out);
}

// The pieces of every g met in this run.
const std::vector<CentredPiece>& shared_pieces(const ClosedForm& g, const Q& lo, const Q& hi) {
    return once_per_run<std::vector<CentredPiece>>(search_key("centred", g, {lo, hi}),
                                                   [&] { return pieces_of(g, lo, hi); });
}

// c times g's piece, a piece of f = c g: the coefficients exactly; the
// truncation bound times an upper bound of |c| (still rigorous), the scale
// by the same factor (their ratio, which the tables print, is g's); the
// samples times c at their 200 bits.
CentredPiece multiple(const CentredPiece& p, const Exact& c, const ClosedForm& f) {
    const auto& [atom, q] = *c.terms().begin();
    const Q c_above = abs(q) * interval(atom).second;
    CentredPiece out{p.lo, p.hi, p.centre, p.low, p.s_power, {}, p.tail * c_above, p.scale * c_above, f, {}, {}};
    for (const CentredValue& a : p.a) out.a.push_back({a.one * c, a.arcsech * c, a.arcsin * c, a.log * c});
    const Real c_real = c.evaluate(200).first;
    for (const auto& [value, size] : p.samples) {
        Real v(value), s(size);
        mpfr_mul(v.backend().data(), v.backend().data(), c_real.backend().data(), MPFR_RNDN);
        mpfr_mul(s.backend().data(), s.backend().data(), c_real.backend().data(), MPFR_RNDN);
        mpfr_abs(s.backend().data(), s.backend().data(), MPFR_RNDN);
        out.samples.emplace_back(std::move(v), std::move(s));
    }
    return out;
}

}  // namespace

std::vector<CentredPiece> centred_pieces(const ClosedForm& f, const Q& lo, const Q& hi) {
    const auto [c, g] = normalised(f);
    std::vector<CentredPiece> out;
    for (const CentredPiece& p : shared_pieces(g, lo, hi)) out.push_back(multiple(p, c, f));
    return out;
}

}  // namespace mollify::gen
