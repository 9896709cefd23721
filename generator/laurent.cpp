#include "laurent.hpp"

#include "error.hpp"

#include <algorithm>

namespace mollify::gen {

Laurent::Laurent(const Q& constant) {
    if (constant != 0) c_.push_back(constant);
}

Laurent Laurent::monomial(const Q& c, int power) {
    Laurent p;
    if (c != 0) {
        p.low_ = power;
        p.c_.push_back(c);
    }
    return p;
}

Laurent Laurent::binomial_power(const Q& a, const Q& b, int n) {
    // c_k = binom(n, k) a^(n-k) b^k, the powers of a kept from the bottom up
    // and binom(n, k) by its ratio: O(n) products, not a power per
    // coefficient (check_emitted expands an edge factor (1 - r)^n per term).
    std::vector<Q> a_power(static_cast<std::size_t>(n) + 1, Q(1));
    for (std::size_t j = 1; j < a_power.size(); ++j) a_power[j] = a_power[j - 1] * a;
    Laurent p;
    p.c_.resize(static_cast<std::size_t>(n) + 1);
    Z binom = 1;
    Q b_power = 1;
    for (int k = 0; k <= n; ++k) {
        p.c_[static_cast<std::size_t>(k)] = Q(binom) * a_power[static_cast<std::size_t>(n - k)] * b_power;
        binom = binom * (n - k) / (k + 1);
        b_power *= b;
    }
    p.trim();
    return p;
}

Q Laurent::coefficient(int power) const {
    if (is_zero() || power < low_ || power > high()) return 0;
    return c_[static_cast<std::size_t>(power - low_)];
}

bool Laurent::is_even() const {
    for (int n = low_; n <= high(); ++n)
        if ((n % 2 != 0) && coefficient(n) != 0) return false;
    return true;
}

void Laurent::trim() {
    std::size_t first = 0;
    while (first < c_.size() && c_[first] == 0) ++first;
    if (first == c_.size()) {
        c_.clear();
        low_ = 0;
        return;
    }
    std::size_t last = c_.size();
    while (c_[last - 1] == 0) --last;
    c_.erase(c_.begin() + static_cast<long>(last), c_.end());
    c_.erase(c_.begin(), c_.begin() + static_cast<long>(first));
    low_ += static_cast<int>(first);
}

Laurent& Laurent::operator+=(const Laurent& o) {
    if (o.is_zero()) return *this;
    if (is_zero()) return *this = o;
    // In place: widened where o reaches beyond, o's nonzero coefficients
    // added (summing a polynomial monomial by monomial stays linear).
    const int hi = std::max(high(), o.high());
    if (o.low_ < low_) {
        c_.insert(c_.begin(), static_cast<std::size_t>(low_ - o.low_), Q(0));
        low_ = o.low_;
    }
    c_.resize(static_cast<std::size_t>(hi - low_ + 1));
    for (std::size_t i = 0; i < o.c_.size(); ++i)
        if (o.c_[i] != 0) c_[static_cast<std::size_t>(o.low_ - low_) + i] += o.c_[i];
    trim();
    return *this;
}

Laurent& Laurent::operator-=(const Laurent& o) { return *this += o * Q(-1); }

Laurent& Laurent::operator*=(const Q& s) {
    if (s == 0) {
        c_.clear();
        low_ = 0;
        return *this;
    }
    for (auto& c : c_) c *= s;
    return *this;
}

Laurent operator*(const Laurent& a, const Laurent& b) {
    Laurent p;
    if (a.is_zero() || b.is_zero()) return p;
    p.low_ = a.low_ + b.low_;
    p.c_.assign(a.c_.size() + b.c_.size() - 1, Q(0));
    for (std::size_t i = 0; i < a.c_.size(); ++i)
        for (std::size_t j = 0; j < b.c_.size(); ++j) p.c_[i + j] += a.c_[i] * b.c_[j];
    p.trim();
    return p;
}

Laurent& Laurent::times_r_minus(const Q& a) {
    if (is_zero()) return *this;
    // c'_i = c_(i-1) - a c_i over one more coefficient, from the top down.
    c_.push_back(c_.back());
    for (std::size_t i = c_.size() - 2; i > 0; --i) c_[i] = c_[i - 1] - a * c_[i];
    c_[0] *= -a;
    trim();
    return *this;
}

Laurent Laurent::shifted(int k) const {
    Laurent p = *this;
    if (!p.is_zero()) p.low_ += k;
    return p;
}

Laurent Laurent::derivative() const {
    Laurent p;
    for (int n = low_; n <= high() && !is_zero(); ++n) p += monomial(coefficient(n) * n, n - 1);
    return p;
}

Laurent Laurent::antiderivative(Q* log_coefficient) const {
    Laurent p;
    if (log_coefficient) *log_coefficient = 0;
    for (int n = low_; n <= high() && !is_zero(); ++n) {
        const Q c = coefficient(n);
        if (c == 0) continue;
        if (n == -1) {
            if (!log_coefficient) fail("internal: antiderivative of r^-1 needs a log term");
            *log_coefficient = c;
        } else {
            p += monomial(c / Q(n + 1), n + 1);
        }
    }
    return p;
}

Laurent Laurent::scaled_argument(const Q& s) const {
    Laurent p = *this;
    for (int n = low_; n <= high() && !is_zero(); ++n) p.c_[static_cast<std::size_t>(n - low_)] *= pow(s, n);
    p.trim();
    return p;
}

Q Laurent::operator()(const Q& r) const {
    if (is_zero()) return 0;
    if (r == 0) {
        if (low_ < 0) fail("internal: Laurent polynomial with negative powers evaluated at r = 0");
        return coefficient(0);
    }
    // Horner from the top over the integers, then the r^low factor: with
    // r = a/b and D the common denominator of the c_i,
    // D b^d sum_i c_i r^i = sum_i (D c_i) a^i b^(d-i), reduced once (GMP's
    // rationals would take gcds at every step; the same value).
    mpz_srcptr a = mpq_numref(r.backend().data()), b = mpq_denref(r.backend().data());
    Z D = 1, acc, term, b_power = 1;
    for (const Q& c : c_) mpz_lcm(D.backend().data(), D.backend().data(), mpq_denref(c.backend().data()));
    auto scaled = [&](const Q& c, Z& out) {  // D c
        mpz_divexact(out.backend().data(), D.backend().data(), mpq_denref(c.backend().data()));
        mpz_mul(out.backend().data(), out.backend().data(), mpq_numref(c.backend().data()));
    };
    scaled(c_.back(), acc);
    for (std::size_t i = c_.size() - 1; i-- > 0;) {
        mpz_mul(b_power.backend().data(), b_power.backend().data(), b);
        scaled(c_[i], term);
        mpz_mul(acc.backend().data(), acc.backend().data(), a);
        mpz_addmul(acc.backend().data(), term.backend().data(), b_power.backend().data());
    }
    Q value;
    mpz_set(mpq_numref(value.backend().data()), acc.backend().data());
    mpz_mul(mpq_denref(value.backend().data()), D.backend().data(), b_power.backend().data());
    mpq_canonicalize(value.backend().data());
    return low_ == 0 ? value : Q(value * pow(r, low_));
}

namespace {

// One synthetic division of r^low q(r) by (r - a) in place: q becomes the
// quotient (low unchanged, then trimmed at its low end: r^low q(r) keeps its
// value); false where it leaves a remainder (q then holds no use: both
// callers stop there).
bool divide_by_r_minus(std::vector<Q>& q, int& low, const Q& a) {
    if (q.empty()) return true;
    if (low < 0 && a == 0) return false;
    const bool unit = a == 1;  // the edge: no products
    for (std::size_t k = q.size() - 1; k-- > 0;) {
        if (unit) q[k] += q[k + 1];
        else q[k] += a * q[k + 1];
    }
    if (q.front() != 0) return false;
    std::size_t first = 1;
    while (first < q.size() && q[first] == 0) ++first;
    q.erase(q.begin(), q.begin() + static_cast<long>(first));
    low += static_cast<int>(first - 1);
    return true;
}

}  // namespace

// Divided by (r - a) n times, the sign of (a - r)^n once at the end (a
// rational's product by -1 reduces by gcds; its negation does not).
std::optional<Laurent> Laurent::divided_by_linear_power(const Q& a, int n) const {
    Laurent out = *this;
    for (int i = 0; i < n && !out.c_.empty(); ++i)
        if (!divide_by_r_minus(out.c_, out.low_, a)) return std::nullopt;
    if (n % 2 != 0)
        for (Q& c : out.c_) mpq_neg(c.backend().data(), c.backend().data());
    out.trim();
    return out;
}

int Laurent::multiplicity_of_root(const Q& a) const {
    if (is_zero()) return -1;
    std::vector<Q> q = c_;
    int low = low_, n = 0;
    while (!q.empty() && divide_by_r_minus(q, low, a)) ++n;
    return n;
}

std::vector<Q> Laurent::taylor_at(const Q& a) const {
    if (!is_polynomial()) fail("internal: Taylor form of a Laurent polynomial");
    // p(r) = p(a - t): the coefficients of p(a + t) by repeated synthetic
    // division (the Taylor shift, O(d^2)), then t -> -t.
    if (is_zero()) return {};
    const int d = high();
    std::vector<Q> out(static_cast<std::size_t>(d) + 1);
    for (int n = 0; n <= d; ++n) out[static_cast<std::size_t>(n)] = coefficient(n);
    for (int i = 0; i < d; ++i)
        for (int j = d - 1; j >= i; --j) out[static_cast<std::size_t>(j)] += a * out[static_cast<std::size_t>(j) + 1];
    for (std::size_t k = 1; k < out.size(); k += 2) out[k] = -out[k];
    while (!out.empty() && out.back() == 0) out.pop_back();
    return out;
}

Laurent Laurent::even_part_in_square() const {
    if (!is_even()) fail("internal: even_part_in_square of an odd polynomial");
    Laurent q;
    for (int n = low_; n <= high() && !is_zero(); ++n)
        if (n % 2 == 0) q += monomial(coefficient(n), n / 2);
    return q;
}

}  // namespace mollify::gen
