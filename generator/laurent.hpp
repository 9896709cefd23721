// Laurent polynomials in r over the rationals: sum_{n=low}^{high} c_n r^n.
// The common currency of the exact pipeline; every kernel piece, moment
// and potential is built from these.
#pragma once

#include "number.hpp"

#include <optional>
#include <vector>

namespace mollify::gen {

class Laurent {
public:
    Laurent() = default;
    Laurent(const Q& constant);  // NOLINT: a constant is a Laurent polynomial
    static Laurent monomial(const Q& c, int power);
    // (a + b r)^n, the building block of factored kernels.
    static Laurent binomial_power(const Q& a, const Q& b, int n);

    bool is_zero() const { return c_.empty(); }
    int low() const { return low_; }
    int high() const { return low_ + static_cast<int>(c_.size()) - 1; }
    Q coefficient(int power) const;
    bool is_polynomial() const { return is_zero() || low_ >= 0; }
    bool is_even() const;  // only even powers of r

    Laurent& operator+=(const Laurent& o);
    Laurent& operator-=(const Laurent& o);
    Laurent& operator*=(const Q& s);
    friend Laurent operator+(Laurent a, const Laurent& b) { return a += b; }
    friend Laurent operator-(Laurent a, const Laurent& b) { return a -= b; }
    friend Laurent operator-(Laurent a) { return a *= Q(-1); }
    friend Laurent operator*(Laurent a, const Q& s) { return a *= s; }
    friend Laurent operator*(const Q& s, Laurent a) { return a *= s; }
    friend Laurent operator*(const Laurent& a, const Laurent& b);
    friend bool operator==(const Laurent& a, const Laurent& b) { return a.low_ == b.low_ && a.c_ == b.c_; }

    Laurent shifted(int k) const;       // times r^k
    Laurent& times_r_minus(const Q& a);  // *= (r - a), in place (Horner's rule in r - a)
    Laurent derivative() const;          // d/dr
    // Antiderivative without the r^{-1} term; `log_coefficient` receives the
    // coefficient of log r (the antiderivative of c r^{-1}).
    Laurent antiderivative(Q* log_coefficient) const;
    Laurent scaled_argument(const Q& s) const;  // p(s r)
    Q operator()(const Q& r) const;

    // Quotient by (a - r)^n if it divides exactly.
    std::optional<Laurent> divided_by_linear_power(const Q& a, int n) const;
    // Largest n such that (a - r)^n divides this (0 if not); -1 for zero.
    int multiplicity_of_root(const Q& a) const;
    // Re-expressed in t = a - r (polynomials only): coefficients of t^k.
    std::vector<Q> taylor_at(const Q& a) const;
    // p(r) = q(r^2) for even p: coefficients of q.
    Laurent even_part_in_square() const;

private:
    void trim();
    int low_ = 0;
    std::vector<Q> c_;  // c_[i] multiplies r^(low_ + i)
};

}  // namespace mollify::gen
