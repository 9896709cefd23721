// Exact scalars: rationals (GMP through Boost.Multiprecision), parsing of
// user-supplied numbers ("p/q", decimals, exponents) and their canonical
// "p/q" spelling used in every emitted file.
#pragma once

#include <boost/multiprecision/gmp.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace mollify::gen {

using Q = boost::multiprecision::mpq_rational;
using Z = boost::multiprecision::mpz_int;

// Parses "3", "-3/4", "0.125", "1e-3", "2.5E+2". Throws Error naming `what`.
Q parse_rational(std::string_view text, std::string_view what);

// The same, or a finite hex-float ("0x1.8p-2", "-0x1p-1074"): a double's
// exact value, for an argument that is a double (mollify-gen value --r: a
// point where a double kernel was evaluated; "0.32500000000000001", its
// shortest decimal, is another rational). Kernel specs keep parse_rational's
// grammar.
Q parse_rational_or_hex_float(std::string_view text, std::string_view what);

// Always "p/q" (q = 1 included), the catalogue's canonical form.
std::string pq(const Q& q);

// "p/q", or "p" when q = 1: for messages and closed forms meant for people.
std::string short_string(const Q& q);

Q pow(const Q& base, int exponent);
// a/b for machine integers of any sign (mpq_rational's two-argument
// constructor misreads a negative denominator).
inline Q ratio(long long a, long long b) { return Q(a) / Q(b); }
// The n + 1 points lo + (hi - lo) i/n, i = 0 .. n, exactly (the step once,
// then one addition a point).
std::vector<Q> equispaced(const Q& lo, const Q& hi, int n);
Z factorial(unsigned n);
Z binomial(unsigned n, unsigned k);
// Generalised binomial (a choose k) for rational a, k >= 0 (Franz Thm. 4.38).
Q binomial(const Q& a, int k);
// c_k = (2k)! / (4^k k!^2), the coefficients of 1/sqrt(1 - x) = sum c_k x^k
// (the series of arcsin and arcsech at 0 and of S^j at the edge).
Q central_binomial_ratio(int k);

inline bool is_integer(const Q& q) { return denominator(q) == 1; }

}  // namespace mollify::gen
