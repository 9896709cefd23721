// Correct rounding of exact values: to double (for emitted hex-float
// literals) and to N significant decimal digits (for `mollify-gen value`).
// Rationals are rounded exactly (MPFR's mpfr_set_q); values with pi or
// logarithms by Ziv's strategy: evaluate with a rigorous error bound and
// raise the precision until both ends of the interval round alike.
#pragma once

#include "closed_form.hpp"

#include <functional>
#include <string>

namespace mollify::gen {

// Value and sum of |terms| at a working precision in bits.
using Evaluator = std::function<std::pair<Real, Real>(unsigned bits)>;

double round_to_double(const Q& q);
double round_to_double(const Exact& x);
double round_to_double(const Evaluator& f);
// The same to float (SWIFT's single-precision constants).
float round_to_float(const Q& q);
float round_to_float(const Evaluator& f);
// The unit in the last place of a double (float) of magnitude |x| (the
// subnormals' below the smallest normal).
double ulp_of_double(double x);
double ulp_of_float(double x);
// a/b for exact constants (pi and logarithms: Phantom's cnormk_drag and
// av_factor of missing Wendland functions): Ziv's loop on the quotient of
// a's and b's rigorous enclosures, the precision raised until both ends
// round alike; Error naming a and b when 2^16 bits do not decide it (an exact
// tie or a value on a rounding boundary) or b's enclosure keeps 0.
double round_quotient_to_double(const Exact& a, const Exact& b);
std::string decimal_quotient(const Exact& a, const Exact& b, int digits);

// The low part of a double-double x = hi + lo, hi = round_to_double(x): the
// rounding error x - hi, itself correctly rounded (0 where x is hi). The
// runtime's Precision::accurate evaluates with both parts (table.hpp).
double low_part(const Q& q, double hi);
double low_part(const Exact& x, double hi);
// For a value that is not exactly a double (a Ziv loop cannot settle an
// exact zero).
double low_part(const Evaluator& f, double hi);
// Both parts of such a value, {round_to_double(f), low_part(f, hi)}: one
// evaluation where it decides both.
std::pair<double, double> round_to_double_double(const Evaluator& f);

// C99 hexadecimal floating literal ("0x1.8p-2"), exact for every double.
std::string hex_literal(double x);
// The same double as a decimal literal with every digit of its exact value
// ("3.75e-01"; up to 767 significant digits), for languages without hex
// floats (C++ before C++17: GADGET-4 builds with -std=c++11). A literal whose
// value is representable converts to exactly that value in every conforming
// compiler (C++ [lex.fcon], C 6.4.4.2), so it is as exact as the hex form.
std::string exact_decimal_literal(double x);

// The most significant digits a decimal gives (every one delivered: ~400,000
// bits for an irrational value, 0.2 s); front ends name their own option.
inline constexpr int max_decimal_digits = 100000;

// N significant digits, scientific notation ("6.77e-01"), correctly rounded
// (round half to even).
std::string decimal(const Q& q, int digits);
std::string decimal(const Exact& x, int digits);
std::string decimal(const Evaluator& f, int digits);

}  // namespace mollify::gen
