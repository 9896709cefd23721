// Printed decimals read exactly: the unit of the last digit, and the
// simplest rational a rounded decimal stands for (8.35655e-3 -> 3/359), for
// `mollify-gen errata --codes` (published code constants are often decimals).
#pragma once

#include "number.hpp"

#include <optional>
#include <string>

namespace mollify::gen {

// The simplest rational in [lo, hi] (0 < lo <= hi): the smallest
// denominator, by continued fractions.
Q simplest_between(const Q& lo, const Q& hi);

// How many places after the point a printed decimal's last digit sits
// ("0.41778" -> 5, "8.35655e-3" -> 8, "2.5E+2" -> -1); nullopt for "p/q" and
// integers.
std::optional<int> decimal_places(const std::string& text);

// The unit of a printed decimal's last digit ("0.41778" -> 1/100000,
// "8.35655e-3" -> 1/100000000); nullopt for "p/q" and integers.
std::optional<Q> decimal_unit(const std::string& text);

// What a decimal `text` (of exact value `value`) of five or more significant
// digits stands for: the simplest rational within half a unit of its last
// digit, when that differs from the decimal; nullopt otherwise (shorter
// decimals such as 0.05 are taken as exact: each has a simpler neighbour).
std::optional<Q> decimal_reading(const std::string& text, const Q& value);

// round(sqrt(square) 10^places) for a rational square >= 0, decided exactly
// (ties away from zero): N with (N - 1/2)^2 <= square 10^(2 places) < (N + 1/2)^2.
Z rounded_sqrt(const Q& square, int places);

// n 10^-places written with `places` decimals ("2121320", 6 -> "2.121320").
std::string decimal_string(const Z& n, int places);

}  // namespace mollify::gen
