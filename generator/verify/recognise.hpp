// A measured ratio recognised as an exact number: a rational p/q times a
// power of pi, by continued fractions (the convergents are the best rational
// approximations with small denominators), e.g. PySPH's 3D quintic
// normalisation 3/(359 pi) against the exact 1/(120 pi): the ratio 360/359.
#pragma once

#include "../exact.hpp"

#include <optional>
#include <string>

namespace mollify::verify::detail {

// The candidate p/q pi^k (k = 0, -1, 1, -2, 2 in that order; q <= max_denominator)
// nearest x within relative `tolerance`; nullopt if none is. The caller
// checks the candidate against the exact values.
std::optional<gen::Exact> recognise(double x, double tolerance, long max_denominator);

// For people: "360/359", "3/(359 pi)", "2 pi/3", "-1", "1/(120 pi^2)".
std::string pretty(const gen::Exact& c);

}  // namespace mollify::verify::detail
