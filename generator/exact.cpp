#include "exact.hpp"

#include "error.hpp"

#include <mpfr.h>

#include <algorithm>
#include <map>
#include <tuple>

namespace mollify::gen {

namespace {

void add_term(std::map<Atom, Q>& terms, const Atom& a, const Q& q) {
    if (q == 0) return;
    auto [it, inserted] = terms.emplace(a, q);
    if (!inserted) {
        it->second += q;
        if (it->second == 0) terms.erase(it);
    }
}

// Trial division: breakpoints and radii are small rationals in practice.
std::map<long long, int> factor(Z n) {
    std::map<long long, int> f;
    for (long long p = 2; p <= 1000000 && Z(p) * p <= n; ++p)
        while (n % p == 0) {
            ++f[p];
            n /= p;
        }
    if (n > 1) {
        if (n > Z(std::numeric_limits<long long>::max()))
            fail("logarithm of " + n.str() + ": number too large to factor");
        ++f[n.convert_to<long long>()];
    }
    return f;
}

}  // namespace

Exact::Exact(const Q& q) { add_term(terms_, Atom{}, q); }

Exact Exact::pi_power(const Q& q, int e) {
    Exact x;
    add_term(x.terms_, Atom{e, 1}, q);
    return x;
}

Exact Exact::log_of(const Q& positive) {
    if (positive <= 0) fail("logarithm of non-positive " + short_string(positive));
    Exact x;
    for (auto [p, k] : factor(numerator(positive))) add_term(x.terms_, Atom{0, p}, Q(k));
    for (auto [p, k] : factor(denominator(positive))) add_term(x.terms_, Atom{0, p}, Q(-k));
    return x;
}

Exact Exact::of(const Atom& a) {
    const Exact p = pi_power(Q(1), a.pi_power);
    return a.log_of == 1 ? p : p * log_of(Q(a.log_of));
}

bool Exact::is_rational() const {
    return terms_.empty() || (terms_.size() == 1 && terms_.begin()->first == Atom{});
}

Q Exact::rational() const {
    if (!is_rational()) fail("internal: " + to_string() + " is not rational");
    return terms_.empty() ? Q(0) : terms_.begin()->second;
}

Exact& Exact::operator+=(const Exact& o) {
    for (const auto& [a, q] : o.terms_) add_term(terms_, a, q);
    return *this;
}

Exact& Exact::operator-=(const Exact& o) {
    for (const auto& [a, q] : o.terms_) add_term(terms_, a, -q);
    return *this;
}

Exact operator*(const Exact& a, const Exact& b) {
    Exact x;
    for (const auto& [aa, qa] : a.terms_)
        for (const auto& [ab, qb] : b.terms_) {
            if (aa.log_of != 1 && ab.log_of != 1) fail("internal: product of two logarithms");
            add_term(x.terms_, Atom{aa.pi_power + ab.pi_power, aa.log_of != 1 ? aa.log_of : ab.log_of}, qa * qb);
        }
    return x;
}

Exact operator*(Exact a, const Q& s) {
    if (s == 0) return Exact{};
    for (auto& [atom, q] : a.terms_) q *= s;
    return a;
}

Exact Exact::inverse() const {
    if (terms_.size() != 1 || terms_.begin()->first.log_of != 1)
        fail("internal: cannot invert " + to_string());
    const auto& [a, q] = *terms_.begin();
    return pi_power(Q(1) / q, -a.pi_power);
}

Real pi_at(unsigned bits) {
    Real p;
    p.precision(bits);
    mpfr_const_pi(p.backend().data(), MPFR_RNDN);
    return p;
}

namespace {

// Filled in place: a copied Real may take the thread's default precision.
const Real& atom_factor(bool log, long n, unsigned bits) {
    thread_local std::map<std::tuple<bool, long, unsigned>, Real> cache;
    auto [it, fresh] = cache.try_emplace(std::tuple{log, n, bits});
    if (fresh) {
        mpfr_ptr x = it->second.backend().data();
        mpfr_set_prec(x, bits);
        if (log) {
            mpfr_set_si(x, n, MPFR_RNDN);
            mpfr_log(x, x, MPFR_RNDN);
        } else {
            mpfr_t pi;
            mpfr_init2(pi, bits);
            mpfr_const_pi(pi, MPFR_RNDN);
            mpfr_pow_si(x, pi, n, MPFR_RNDN);
            mpfr_clear(pi);
        }
    }
    return it->second;
}

}  // namespace

const Real& pi_power_at(int e, unsigned bits) { return atom_factor(false, e, bits); }
const Real& log_at(long p, unsigned bits) { return atom_factor(true, p, bits); }

std::pair<Real, Real> Exact::evaluate(unsigned bits) const {
    const unsigned digits10 = bits * 30103 / 100000 + 2;
    Real sum(0, digits10), magnitude(0, digits10);
    // Raw MPFR at bits + 16 for the factors: Boost's expression temporaries
    // may take the thread's default precision, below what Ziv's rounding of
    // a cancelling sum assumes (rounding.hpp).
    Real t(0, digits10);
    mpfr_ptr x = t.backend().data();
    for (const auto& [a, q] : terms_) {
        mpfr_set_q(x, q.backend().data(), MPFR_RNDN);
        if (a.pi_power != 0) mpfr_mul(x, x, pi_power_at(a.pi_power, bits + 16).backend().data(), MPFR_RNDN);
        if (a.log_of != 1) mpfr_mul(x, x, log_at(static_cast<long>(a.log_of), bits + 16).backend().data(), MPFR_RNDN);
        mpfr_add(sum.backend().data(), sum.backend().data(), x, MPFR_RNDN);
        mpfr_abs(x, x, MPFR_RNDN);
        mpfr_add(magnitude.backend().data(), magnitude.backend().data(), x, MPFR_RNDN);
    }
    return {sum, magnitude};
}

std::string Exact::to_string() const {
    if (terms_.empty()) return "0";
    std::string s;
    for (const auto& [a, q] : terms_) {
        if (!s.empty()) s += " + ";
        s += short_string(q);
        if (a.pi_power != 0) s += " * pi^" + std::to_string(a.pi_power);
        if (a.log_of != 1) s += " * log(" + std::to_string(a.log_of) + ")";
    }
    return s;
}

// pi^e log p at 200 bits (MPFR's pi, log and pow_si correctly rounded)
// carries a relative error below (|e| + 3) 2^-200 < 2^-150, the slack added here.
std::pair<Q, Q> interval(const Atom& a) {
    mpfr_t pi, v, l;
    mpfr_inits2(200, pi, v, l, static_cast<mpfr_ptr>(nullptr));
    mpfr_const_pi(pi, MPFR_RNDN);
    mpfr_pow_si(v, pi, a.pi_power, MPFR_RNDN);
    if (a.log_of != 1) {
        mpfr_set_si(l, static_cast<long>(a.log_of), MPFR_RNDN);
        mpfr_log(l, l, MPFR_RNDN);
        mpfr_mul(v, v, l, MPFR_RNDN);
    }
    Q q;
    mpfr_get_q(q.backend().data(), v);
    mpfr_clears(pi, v, l, static_cast<mpfr_ptr>(nullptr));
    const Q slack = abs(q) / pow(Q(2), 150);
    return {q - slack, q + slack};
}

std::pair<Q, Q> interval(const Exact& x) {
    Q lo = 0, hi = 0;
    for (const auto& [atom, q] : x.terms()) {
        const auto [a, b] = interval(atom);
        lo += q > 0 ? q * a : q * b;
        hi += q > 0 ? q * b : q * a;
    }
    return {lo, hi};
}

Q abs_upper_bound(const Exact& x) {
    const auto [lo, hi] = interval(x);
    return std::max(abs(lo), abs(hi));
}

Q abs_lower_bound(const Exact& x) {
    const auto [lo, hi] = interval(x);
    return lo > 0 ? lo : hi < 0 ? -hi : Q(0);
}

}  // namespace mollify::gen
