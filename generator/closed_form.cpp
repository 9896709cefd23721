#include "closed_form.hpp"

#include "error.hpp"

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

// S^j with j >= 3 becomes (1 - r^2) S^(j-2); S^j with j < 0 absorbs a factor
// (1 - r^2) of its coefficient when there is one. A form whose derivative of
// order n is finite at r = 1 thus ends with no negative powers of S.
void ClosedForm::canonicalise() {
    bool changed = true;
    while (changed) {
        changed = false;
        for (auto it = terms_.begin(); it != terms_.end(); ++it) {
            const auto [k, p] = *it;
            if (k.basis != Basis::sqrt_power) continue;
            if (k.s_power == 0) {
                terms_.erase(it);
                add_to(terms_, TermKey{Basis::one, 0, k.factor}, p);
                changed = true;
                break;
            }
            if (k.s_power >= 3) {
                terms_.erase(it);
                add_to(terms_, TermKey{Basis::sqrt_power, k.s_power - 2, k.factor}, p * one_minus_r2);
                changed = true;
                break;
            }
            if (k.s_power < 0) {
                if (auto q = divide_by_one_minus_r2(p)) {
                    terms_.erase(it);
                    add_to(terms_, TermKey{Basis::sqrt_power, k.s_power + 2, k.factor}, *q);
                    changed = true;
                    break;
                }
            }
        }
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
        }
    }
    d.canonicalise();
    return d;
}

ClosedForm ClosedForm::antiderivative() const {
    ClosedForm f;
    for (const auto& [k, p] : terms_) {
        if (k.basis == Basis::one) {
            Q log_c;
            add_to(f.terms_, k, p.antiderivative(&log_c));
            if (log_c != 0) add_to(f.terms_, TermKey{Basis::log, 0, k.factor}, Laurent(log_c));
        } else if (k.basis == Basis::log) {
            // int r^n log r = r^(n+1) log r/(n+1) - r^(n+1)/(n+1)^2
            for (int n = p.low(); n <= p.high(); ++n) {
                const Q c = p.coefficient(n);
                if (c == 0) continue;
                if (n == -1) fail("internal: antiderivative of log(r)/r is outside the closed forms");
                add_to(f.terms_, k, Laurent::monomial(c / Q(n + 1), n + 1));
                add_to(f.terms_, TermKey{Basis::one, 0, k.factor},
                       Laurent::monomial(-c / (Q(n + 1) * Q(n + 1)), n + 1));
            }
        } else {
            fail("antiderivative of a non-polynomial closed form (sqrt(1-r^2) or arcsech terms) is not implemented");
        }
    }
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
        const Exact factor = Exact::pi_power(Q(1), k.factor.pi_power) *
                             (k.factor.log_of == 1 ? Exact(Q(1)) : Exact::log_of(Q(k.factor.log_of)));
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

std::pair<Real, Real> ClosedForm::evaluate(const Real& r, unsigned bits) const {
    const unsigned digits10 = bits * 30103 / 100000 + 2;
    Real sum(0, digits10), magnitude(0, digits10);
    const Real pi = pi_at(bits);
    Real rr(r, digits10);
    Real s = boost::multiprecision::sqrt(Real(1, digits10) - rr * rr);
    for (const auto& [k, p] : terms_) {
        for (int n = p.low(); n <= p.high(); ++n) {
            const Q c = p.coefficient(n);
            if (c == 0) continue;
            Real t(0, digits10);
            mpfr_set_q(t.backend().data(), c.backend().data(), MPFR_RNDN);
            if (k.factor.pi_power != 0) t *= boost::multiprecision::pow(pi, k.factor.pi_power);
            if (k.factor.log_of != 1) t *= boost::multiprecision::log(Real(k.factor.log_of, digits10));
            if (n != 0) t *= boost::multiprecision::pow(rr, n);
            switch (k.basis) {
                case Basis::one: break;
                case Basis::sqrt_power: t *= boost::multiprecision::pow(s, k.s_power); break;
                case Basis::arcsech: t *= boost::multiprecision::log((Real(1, digits10) + s) / rr); break;
                case Basis::log: t *= boost::multiprecision::log(rr); break;
            }
            sum += t;
            magnitude += boost::multiprecision::abs(t);
        }
    }
    return {sum, magnitude};
}

std::string ClosedForm::to_string_at(const Q& r) const {
    if (is_elementary()) return at(r).to_string();
    std::string s;
    const std::string one_minus = short_string(Q(1) - r * r);
    for (const auto& [k, p] : terms_) {
        const Q v = p(r);
        if (v == 0) continue;
        if (!s.empty()) s += " + ";
        s += short_string(v);
        if (k.factor.pi_power != 0) s += " * pi^" + std::to_string(k.factor.pi_power);
        if (k.factor.log_of != 1) s += " * log(" + std::to_string(k.factor.log_of) + ")";
        switch (k.basis) {
            case Basis::one: break;
            case Basis::sqrt_power: s += " * sqrt(" + one_minus + ")^" + std::to_string(k.s_power); break;
            case Basis::arcsech:
                s += " * log((1 + sqrt(" + one_minus + ")) / " + short_string(r) + ")";
                break;
            case Basis::log: s += " * log(" + short_string(r) + ")"; break;
        }
    }
    return s.empty() ? "0" : s;
}

}  // namespace mollify::gen
