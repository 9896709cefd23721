// Exact real constants of the forms mollify meets: finite sums of
// q * pi^e * log(p) with q rational, e an integer and p a prime (or 1 for no
// logarithm). Normalisations are q * pi^e; 2D potentials of kernels with
// inner breakpoints pick up log(p) terms (e.g. log 2 for the cubic spline).
#pragma once

#include "number.hpp"

#include <boost/multiprecision/mpfr.hpp>

#include <map>
#include <string>
#include <utility>

namespace mollify::gen {

using Real = boost::multiprecision::mpfr_float;  // precision set per use

struct Atom {  // pi^pi_power * log(log_of); log_of == 1 means no logarithm
    int pi_power = 0;
    long long log_of = 1;
    auto operator<=>(const Atom&) const = default;
};

class Exact {
public:
    Exact() = default;
    Exact(const Q& q);  // NOLINT: rationals are exact constants
    static Exact pi_power(const Q& q, int e);
    static Exact log_of(const Q& positive);  // factored into logs of primes
    static Exact of(const Atom& a);          // pi^e log(p)

    bool is_zero() const { return terms_.empty(); }
    bool is_rational() const;
    Q rational() const;  // requires is_rational()
    const std::map<Atom, Q>& terms() const { return terms_; }

    Exact& operator+=(const Exact& o);
    Exact& operator-=(const Exact& o);
    friend Exact operator+(Exact a, const Exact& b) { return a += b; }
    friend Exact operator-(Exact a, const Exact& b) { return a -= b; }
    friend Exact operator-(const Exact& a) { return a * Q(-1); }
    friend Exact operator*(const Exact& a, const Exact& b);
    friend Exact operator*(Exact a, const Q& s);
    friend bool operator==(const Exact& a, const Exact& b) { return a.terms_ == b.terms_; }
    Exact inverse() const;  // only for a single term without logarithm

    // Value and sum of |terms| at `bits` precision (the latter bounds the
    // rounding error of the sum, for correct-rounding decisions).
    std::pair<Real, Real> evaluate(unsigned bits) const;
    // People's form: "3465/512 * pi^-1", "1/2 * pi^-1 * log(2) + -1/4".
    std::string to_string() const;

private:
    std::map<Atom, Q> terms_;
};

Real pi_at(unsigned bits);

// pi^e (pi rounded to `bits`, then the power) and log p, each rounded to
// `bits`, kept per thread: Ziv's rounding evaluates every coefficient, and
// the check samples every point, at the same few precisions (computed per
// term they were a tenth of the rounding's time).
const Real& pi_power_at(int e, unsigned bits);
const Real& log_at(long p, unsigned bits);

// Rigorous rational bounds of an exact constant: lo <= x <= hi (MPFR's pi,
// log and pow_si correctly rounded at 200 bits, widened by 2^-150 relative
// per atom), and of |x|: abs_lower_bound(x) <= |x| <= abs_upper_bound(x).
std::pair<Q, Q> interval(const Atom& a);
std::pair<Q, Q> interval(const Exact& x);
Q abs_upper_bound(const Exact& x);
Q abs_lower_bound(const Exact& x);

}  // namespace mollify::gen
