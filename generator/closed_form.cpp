#include "closed_form.hpp"

#include "error.hpp"
#include "series.hpp"

#include <map>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string_view>
#include <tuple>
#include <unordered_map>

namespace mollify::gen {

namespace {

const Laurent one_minus_r2 = Laurent(Q(1)) - Laurent::monomial(Q(1), 2);

void add_to(std::map<TermKey, Laurent>& terms, const TermKey& k, const Laurent& p) {
    if (p.is_zero()) return;
    auto [it, inserted] = terms.emplace(k, p);
    if (!inserted) {
        it->second += p;
        if (it->second.is_zero()) terms.erase(it);
    }
}

// p / (1 - r^2) when exact.
std::optional<Laurent> divide_by_one_minus_r2(const Laurent& p) {
    auto a = p.divided_by_linear_power(Q(1), 1);  // (1 - r)
    if (!a) return std::nullopt;
    auto b = a->divided_by_linear_power(Q(-1), 1);  // (-1 - r) = -(1 + r)
    if (!b) return std::nullopt;
    return *b * Q(-1);
}

}  // namespace

ClosedForm::ClosedForm(const Laurent& p) { add_to(terms_, TermKey{}, p); }

ClosedForm::ClosedForm(const Laurent& p, const TermKey& key) {
    add_to(terms_, key, p);
    canonicalise();
}

ClosedForm ClosedForm::constant(const Exact& c) { return ClosedForm(Laurent(Q(1))) * c; }

bool ClosedForm::is_elementary() const {
    for (const auto& [k, p] : terms_)
        if (k.basis != Basis::one && k.basis != Basis::log) return false;
    return true;
}

bool ClosedForm::has_only_basis_one() const {
    for (const auto& [k, p] : terms_)
        if (k.basis != Basis::one) return false;
    return true;
}

bool ClosedForm::single_polynomial(Laurent* p, Atom* factor) const {
    if (terms_.size() > 1) return false;
    if (terms_.empty()) {
        *p = Laurent();
        *factor = Atom{};
        return true;
    }
    const auto& [k, poly] = *terms_.begin();
    if (k.basis != Basis::one) return false;
    *p = poly;
    *factor = k.factor;
    return true;
}

ClosedForm& ClosedForm::operator+=(const ClosedForm& o) {
    for (const auto& [k, p] : o.terms_) add_to(terms_, k, p);
    return *this;
}

ClosedForm& ClosedForm::operator-=(const ClosedForm& o) {
    for (const auto& [k, p] : o.terms_) add_to(terms_, k, p * Q(-1));
    return *this;
}

ClosedForm operator*(const ClosedForm& a, const Exact& c) {
    ClosedForm x;
    for (const auto& [k, p] : a.terms_)
        for (const auto& [atom, q] : c.terms()) {
            if (k.factor.log_of != 1 && atom.log_of != 1) fail("internal: product of two logarithmic constants");
            TermKey nk = k;
            nk.factor = Atom{k.factor.pi_power + atom.pi_power, k.factor.log_of != 1 ? k.factor.log_of : atom.log_of};
            add_to(x.terms_, nk, p * q);
        }
    return x;
}

ClosedForm operator*(const ClosedForm& a, const Laurent& m) {
    ClosedForm x;
    for (const auto& [k, p] : a.terms_) add_to(x.terms_, k, p * m);
    x.canonicalise();
    return x;
}

// Unique form of the S terms, so that equality of closed forms is equality
// of functions: per constant factor, all powers S^j are gathered on the
// lowest one (S^j = (1 - r^2)^((j-i)/2) S^i), then factors (1 - r^2) of the
// coefficient are absorbed while the power is below 1. A form whose value is
// finite at r = 1 thus ends with no negative powers of S (powers are odd).
void ClosedForm::canonicalise() {
    std::map<Atom, std::map<int, Laurent>> by_factor;
    for (auto it = terms_.begin(); it != terms_.end();) {
        if (it->first.basis == Basis::sqrt_power) {
            by_factor[it->first.factor][it->first.s_power] += it->second;
            it = terms_.erase(it);
        } else {
            ++it;
        }
    }
    for (auto& [factor, powers] : by_factor) {
        int j = powers.begin()->first;
        Laurent c;
        for (const auto& [i, p] : powers) {
            Laurent q = p;
            for (int step = j; step < i; step += 2) q = q * one_minus_r2;
            c += q;
        }
        if (c.is_zero()) continue;
        while (j < 1) {
            auto q = divide_by_one_minus_r2(c);
            if (!q) break;
            c = *q;
            j += 2;
        }
        while (j > 1) {  // only when every power was above 1
            c = c * one_minus_r2;
            j -= 2;
        }
        if (j == 0) fail("internal: even power of S in a closed form");
        add_to(terms_, TermKey{Basis::sqrt_power, j, factor}, c);
    }
}

ClosedForm ClosedForm::derivative() const {
    ClosedForm d;
    for (const auto& [k, p] : terms_) {
        add_to(d.terms_, k, p.derivative());
        switch (k.basis) {
            case Basis::one: break;
            case Basis::sqrt_power:  // (S^j)' = -j r S^(j-2)
                add_to(d.terms_, TermKey{Basis::sqrt_power, k.s_power - 2, k.factor},
                       p * Laurent::monomial(Q(-k.s_power), 1));
                break;
            case Basis::arcsech:  // L' = -1/(r S)
                add_to(d.terms_, TermKey{Basis::sqrt_power, -1, k.factor}, p * Laurent::monomial(Q(-1), -1));
                break;
            case Basis::log:  // (log r)' = 1/r
                add_to(d.terms_, TermKey{Basis::one, 0, k.factor}, p * Laurent::monomial(Q(1), -1));
                break;
            case Basis::arcsin:  // A' = 1/S
                add_to(d.terms_, TermKey{Basis::sqrt_power, -1, k.factor}, p);
                break;
        }
    }
    d.canonicalise();
    return d;
}

namespace {

const TermKey key_one{Basis::one, 0, Atom{}};
const TermKey key_S{Basis::sqrt_power, 1, Atom{}};
const TermKey key_L{Basis::arcsech, 0, Atom{}};
const TermKey key_A{Basis::arcsin, 0, Atom{}};
const TermKey key_log{Basis::log, 0, Atom{}};

ClosedForm mono(const Q& c, int n, const TermKey& k) { return ClosedForm(Laurent::monomial(c, n), k); }

ClosedForm integrate_monomial(Basis b, int s_power, int n);

// K_n = int r^n / S: r^(n-1) S = (n-1) K_(n-2) - n K_n (differentiate r^(n-1) S).
ClosedForm inverse_sqrt_integral(int n) {
    switch (n) {
        case 0: return mono(Q(1), 0, key_A);
        case 1: return mono(Q(-1), 0, key_S);
        case -1: return mono(Q(-1), 0, key_L);  // (-L)' = 1/(r S)
        case -2: return mono(Q(-1), -1, key_S);  // (-S/r)' = 1/(r^2 S)
    }
    if (n > 1) return (inverse_sqrt_integral(n - 2) * Q(n - 1) - mono(Q(1), n - 1, key_S)) * ratio(1, n);
    const int m = n + 2;  // n <= -3: K_n = (r^(m-1) S + m K_m) / (m - 1)
    return (mono(Q(1), m - 1, key_S) + inverse_sqrt_integral(m) * Q(m)) * ratio(1, m - 1);
}

// I_n = int r^n S: r^(n-1) S^3 = (n-1) I_(n-2) - (n+2) I_n.
ClosedForm sqrt_integral(int n) {
    const Laurent one_minus_r2 = Laurent(Q(1)) - Laurent::monomial(Q(1), 2);
    auto r_S3 = [&](int p) { return ClosedForm(Laurent::monomial(Q(1), p) * one_minus_r2, key_S); };
    switch (n) {
        case 0: return (mono(Q(1), 1, key_S) + mono(Q(1), 0, key_A)) * ratio(1, 2);
        case 1: return r_S3(0) * ratio(-1, 3);
        case -1: return mono(Q(1), 0, key_S) - mono(Q(1), 0, key_L);  // (S - L)' = S/r
        case -2: return mono(Q(-1), -1, key_S) - mono(Q(1), 0, key_A);
    }
    if (n > 1) return (sqrt_integral(n - 2) * Q(n - 1) - r_S3(n - 1)) * ratio(1, n + 2);
    const int m = n + 2;  // n <= -3: I_n = (r^(m-1) S^3 + (m+2) I_m) / (m - 1)
    return (r_S3(m - 1) + sqrt_integral(m) * Q(m + 2)) * ratio(1, m - 1);
}

// int r^n basis(r) dr.
ClosedForm integrate_monomial(Basis b, int s_power, int n) {
    switch (b) {
        case Basis::one:
            return n == -1 ? mono(Q(1), 0, key_log) : mono(ratio(1, n + 1), n + 1, key_one);
        case Basis::log:  // r^(n+1) log r/(n+1) - r^(n+1)/(n+1)^2
            if (n == -1) fail("the antiderivative of log(r)/r is outside mollify's closed forms");
            return mono(ratio(1, n + 1), n + 1, key_log) - mono(Q(1, (n + 1) * (n + 1)), n + 1, key_one);
        case Basis::sqrt_power:
            if (s_power == 1) return sqrt_integral(n);
            if (s_power == -1) return inverse_sqrt_integral(n);
            fail("internal: antiderivative of S^" + std::to_string(s_power));
        case Basis::arcsech:  // by parts: r^(n+1) L/(n+1) + K_n/(n+1)
            if (n == -1) fail("the antiderivative of arcsech(r)/r is outside mollify's closed forms");
            return mono(ratio(1, n + 1), n + 1, key_L) + inverse_sqrt_integral(n) * ratio(1, n + 1);
        case Basis::arcsin:  // by parts: r^(n+1) A/(n+1) - K_(n+1)/(n+1)
            if (n == -1) fail("the antiderivative of arcsin(r)/r is outside mollify's closed forms");
            return mono(ratio(1, n + 1), n + 1, key_A) - inverse_sqrt_integral(n + 1) * ratio(1, n + 1);
    }
    fail("internal: unknown basis");
}

}  // namespace

ClosedForm ClosedForm::antiderivative() const {
    ClosedForm f;
    for (const auto& [k, p] : terms_)
        for (int n = p.low(); n <= p.high(); ++n) {
            const Q c = p.coefficient(n);
            if (c == 0) continue;
            const ClosedForm F = integrate_monomial(k.basis, k.s_power, n) * c;
            f += F * Exact::of(k.factor);
        }
    f.canonicalise();
    return f;
}

ClosedForm ClosedForm::scaled_argument(const Q& s) const {
    ClosedForm x;
    for (const auto& [k, p] : terms_) {
        if (k.basis != Basis::one) fail("internal: rescaling a non-polynomial closed form");
        add_to(x.terms_, k, p.scaled_argument(s));
    }
    return x;
}

Exact ClosedForm::at(const Q& r) const {
    Exact v;
    for (const auto& [k, p] : terms_) {
        const Exact factor = Exact::of(k.factor);
        switch (k.basis) {
            case Basis::one: v += factor * p(r); break;
            case Basis::log:
                if (r == 0) fail("internal: log r at r = 0");
                v += factor * Exact::log_of(r) * p(r);
                break;
            default: fail("internal: exact value of a non-elementary closed form");
        }
    }
    return v;
}

PointValues::PointValues(const Real& r, unsigned bits) : digits10_(bits * 30103 / 100000 + 2), r_(r, digits10_) {}

// Every value is computed in raw MPFR into a number of the point's
// precision: Boost's expressions and functions may give their result the
// thread's default precision, which they leave at whatever they last used
// (from 121 to 1330 bits here): values below the precision asked for, and
// the run's table (below) filled at a precision that depended on the thread
// and the run.
Real PointValues::fresh() const { return Real(0, digits10_); }

// S = sqrt(1 - r^2) on first use (where every basis value comes from the
// run's table, never).
const Real& PointValues::S() {
    if (!s_) {
        mpfr_ptr s = s_.emplace(fresh()).backend().data();
        mpfr_sqr(s, r_.backend().data(), MPFR_RNDN);
        mpfr_ui_sub(s, 1, s, MPFR_RNDN);
        mpfr_sqrt(s, s, MPFR_RNDN);
    }
    return *s_;
}

namespace {

Real rounded_real(const Q& x, unsigned digits10) {
    Real r(0, digits10);
    mpfr_set_q(r.backend().data(), x.backend().data(), MPFR_RNDN);
    return r;
}

// Basis function values at rational points, r -> (basis, power of S) ->
// value at one precision, shared by the threads for the whole run: the
// pieces of a kernel's quantities in its three dimensions lie on a few common
// grids, and MPFR's log, asin and powers at 200 bits there were a seventh of
// `emit`. Map nodes do not move (nor do an unordered map's), so a returned
// reference stays valid.

// A rational point's hash, from its numerator's and denominator's limbs:
// the points are looked up by hash, not by the ~15 rational comparisons
// (cross-multiplied) of an ordered map's search.
struct PointKeyHash {
    std::size_t operator()(const std::pair<unsigned, Q>& key) const {
        mpq_srcptr q = key.second.backend().data();
        auto limbs = [](mpz_srcptr z) {
            return std::hash<std::string_view>{}(std::string_view(reinterpret_cast<const char*>(mpz_limbs_read(z)),
                                                                  sizeof(mp_limb_t) * mpz_size(z)));
        };
        return limbs(mpq_numref(q)) ^ (limbs(mpq_denref(q)) * 0x9e3779b97f4a7c15ULL + key.first +
                                       static_cast<std::size_t>(mpq_sgn(q) + 1));
    }
};
}  // namespace

struct PointValues::Shared {
    std::map<std::pair<Basis, int>, Real> values;
};

namespace {

// Looked up far more often than filled (every sample point of every piece
// asks it): lookups share the lock, so that two threads reading it do not
// wait on each other (an exclusive mutex here put the threads to sleep
// ~2,000 times per `emit`).
class BasisTable {
public:
    using Point = PointValues::Shared;
    Point& point(const Q& r, unsigned digits10) {
        std::pair<unsigned, Q> key{digits10, r};
        {
            std::shared_lock lock(mutex_);
            auto it = points_.find(key);
            if (it != points_.end()) return it->second;
        }
        std::unique_lock lock(mutex_);
        return points_.try_emplace(std::move(key)).first->second;
    }
    template <class Compute>
    const Real& get(Point& p, std::pair<Basis, int> key, Compute compute) {
        {
            std::shared_lock lock(mutex_);
            auto it = p.values.find(key);
            if (it != p.values.end()) return it->second;
        }
        Real v = compute();
        std::unique_lock lock(mutex_);
        return p.values.try_emplace(key, std::move(v)).first->second;
    }

private:
    std::shared_mutex mutex_;
    std::unordered_map<std::pair<unsigned, Q>, Point, PointKeyHash> points_;
};

BasisTable& basis_table() {
    static auto& table = *new BasisTable;  // never destroyed, as once_per_run's results
    return table;
}

}  // namespace

PointValues::PointValues(const Q& r, unsigned bits) : PointValues(rounded_real(r, bits * 30103 / 100000 + 2), bits) {
    shared_ = &basis_table().point(r, digits10_);
}

const Real& PointValues::power_of_r(int n) {
    if (n == 1) return r_;  // pow(r, 1) = r exactly
    auto it = r_powers_.find(n);
    if (it == r_powers_.end()) {
        it = r_powers_.emplace(n, fresh()).first;
        mpfr_pow_si(it->second.backend().data(), r_.backend().data(), n, MPFR_RNDN);
    }
    return it->second;
}

// pi^e and log p do not depend on r (exact.hpp, at the point's precision).
const Real& PointValues::pi_power(int e) { return pi_power_at(e, static_cast<unsigned>(mpfr_get_prec(r_.backend().data()))); }

const Real& PointValues::log_of(int p) { return log_at(p, static_cast<unsigned>(mpfr_get_prec(r_.backend().data()))); }

const Real& PointValues::basis(Basis b, int s_power) {
    const std::pair key{b, b == Basis::sqrt_power ? s_power : 0};
    auto it = bases_.find(key);
    if (it != bases_.end()) return it->second;
    auto compute = [&] {
        Real v = fresh();
        mpfr_ptr x = v.backend().data();
        mpfr_srcptr r = r_.backend().data();
        switch (b) {
            case Basis::one: mpfr_set_ui(x, 1, MPFR_RNDN); break;
            case Basis::sqrt_power: mpfr_pow_si(x, S().backend().data(), s_power, MPFR_RNDN); break;
            case Basis::arcsech:  // log((1 + S) / r)
                mpfr_add_ui(x, S().backend().data(), 1, MPFR_RNDN);
                mpfr_div(x, x, r, MPFR_RNDN);
                mpfr_log(x, x, MPFR_RNDN);
                break;
            case Basis::log: mpfr_log(x, r, MPFR_RNDN); break;
            case Basis::arcsin: mpfr_asin(x, r, MPFR_RNDN); break;
        }
        return v;
    };
    if (shared_ && b != Basis::one) {
        for (const auto& [k, v] : seen_)
            if (k == key) return *v;
        const Real& v = basis_table().get(*shared_, key, compute);
        seen_.emplace_back(key, &v);
        return v;
    }
    return bases_.emplace(key, compute()).first->second;
}

std::pair<Real, Real> ClosedForm::evaluate(const Real& r, unsigned bits) const {
    PointValues at(r, bits);
    return evaluate(at);
}

// Each monomial c r^n times its term's factor and basis, multiplied in that
// order; the magnitude is the sum of the monomials' sizes.
std::pair<Real, Real> ClosedForm::evaluate(PointValues& at) const {
    const unsigned digits10 = at.digits10();
    Real sum(0, digits10), magnitude(0, digits10);
    for (const auto& [k, p] : terms_) {
        for (int n = p.low(); n <= p.high(); ++n) {
            const Q c = p.coefficient(n);
            if (c == 0) continue;
            Real t(0, digits10);
            mpfr_set_q(t.backend().data(), c.backend().data(), MPFR_RNDN);
            if (k.factor.pi_power != 0) t *= at.pi_power(k.factor.pi_power);
            if (k.factor.log_of != 1) t *= at.log_of(k.factor.log_of);
            if (n != 0) t *= at.power_of_r(n);
            if (k.basis != Basis::one) t *= at.basis(k.basis, k.s_power);
            sum += t;
            magnitude += boost::multiprecision::abs(t);
        }
    }
    return {sum, magnitude};
}

PreparedForm::PreparedForm(const ClosedForm& f, unsigned bits) : digits10_(bits * 30103 / 100000 + 2) {
    for (const auto& [k, p] : f.terms()) {
        Term t{k, p.low(), {}};
        for (int n = p.low(); n <= p.high(); ++n) {
            t.c.emplace_back(0, digits10_);
            mpfr_set_q(t.c.back().backend().data(), p.coefficient(n).backend().data(), MPFR_RNDN);
        }
        terms_.push_back(std::move(t));
    }
}

Real PreparedForm::value(PointValues& at) const {
    if (at.digits10() != digits10_) fail("internal: a prepared closed form evaluated at another precision");
    Real sum(0, digits10_), h(0, digits10_);
    mpfr_ptr s = sum.backend().data(), x = h.backend().data();
    mpfr_srcptr r = at.power_of_r(1).backend().data();
    for (const Term& t : terms_) {
        mpfr_set(x, t.c.back().backend().data(), MPFR_RNDN);
        for (std::size_t i = t.c.size() - 1; i-- > 0;) mpfr_fma(x, x, r, t.c[i].backend().data(), MPFR_RNDN);
        if (t.low != 0) mpfr_mul(x, x, at.power_of_r(t.low).backend().data(), MPFR_RNDN);
        if (t.key.factor.pi_power != 0) mpfr_mul(x, x, at.pi_power(t.key.factor.pi_power).backend().data(), MPFR_RNDN);
        if (t.key.factor.log_of != 1) mpfr_mul(x, x, at.log_of(t.key.factor.log_of).backend().data(), MPFR_RNDN);
        if (t.key.basis != Basis::one) mpfr_mul(x, x, at.basis(t.key.basis, t.key.s_power).backend().data(), MPFR_RNDN);
        mpfr_add(s, s, x, MPFR_RNDN);
    }
    return sum;
}

std::string ClosedForm::to_string_at(const Q& r) const {
    if (is_elementary()) return at(r).to_string();
    std::string s;
    const std::string one_minus = short_string(Q(1) - r * r);
    const std::string rr = is_integer(r) ? short_string(r) : "(" + short_string(r) + ")";
    for (const auto& [k, p] : terms_) {
        const Q v = p(r);
        if (v == 0) continue;
        if (!s.empty()) s += " + ";
        s += short_string(v);
        if (k.factor.pi_power != 0) s += " * pi^" + std::to_string(k.factor.pi_power);
        if (k.factor.log_of != 1) s += " * log(" + std::to_string(k.factor.log_of) + ")";
        switch (k.basis) {
            case Basis::one: break;
            case Basis::sqrt_power:
                s += " * sqrt(" + one_minus + ")" + (k.s_power == 1 ? "" : "^" + std::to_string(k.s_power));
                break;
            case Basis::arcsech: s += " * log((1 + sqrt(" + one_minus + ")) / " + rr + ")"; break;
            case Basis::log: s += " * log(" + rr + ")"; break;
            case Basis::arcsin: s += " * arcsin(" + short_string(r) + ")"; break;
        }
    }
    return s.empty() ? "0" : s;
}

Exact value_at(const ClosedForm& f, const Q& r) {
    if (r == 0) return limit_at_zero(f);
    if (f.is_elementary()) return f.at(r);
    if (r == 1) {
        Exact v;
        for (const auto& [k, p] : f.terms()) {
            const Exact factor = Exact::of(k.factor);
            switch (k.basis) {
                case Basis::one: v += factor * p(Q(1)); break;
                case Basis::sqrt_power:
                    if (k.s_power < 0) fail("closed form is singular at r = 1 (S^" + std::to_string(k.s_power) + ")");
                    break;  // S(1) = 0
                case Basis::arcsech: case Basis::log: break;  // both vanish at 1
                case Basis::arcsin: v += factor * Exact::pi_power(Q(1, 2), 1) * p(Q(1)); break;
            }
        }
        return v;
    }
    fail("value of a sqrt/arcsech/arcsin closed form at r = " + short_string(r) + " is irrational");
}

std::pair<Exact, ClosedForm> normalised(const ClosedForm& f) {
    if (f.is_zero()) fail("internal: the normalised form of 0");
    const auto& [key, p] = *f.terms().begin();
    const Exact c = Exact::pi_power(p.coefficient(p.low()), key.factor.pi_power);
    return {c, f * c.inverse()};
}

}  // namespace mollify::gen
