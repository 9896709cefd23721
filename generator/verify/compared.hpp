// One sample judged: the arguments, the value given, the exact value and the
// error, with what the diagnosis needs (r/H in mollify's units, the floor of
// tiny values).
#pragma once

#include "setup.hpp"

#include <optional>
#include <vector>

namespace mollify::verify::detail {

struct Compared {
    double r, h, got;
    Real exact;      // in the convention's units
    double exact_d;  // rounded to double
    double q;        // r / H
    double magnitude;  // max |value| over the support at this h
    double floor;    // values below it are measured in its ulps
    double ulps;
};

// Why a failing kernel fails, when the error is systematic; nullopt when it
// passed. `bound` is Options::ulps.
std::optional<Diagnosis> diagnose(const Setup& s, const std::vector<Compared>& points, double bound);

}  // namespace mollify::verify::detail
