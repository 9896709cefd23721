// The error of a value in ulps of the exact one (SLEEF's countULP: ulp(x) =
// 2^(e - p + 1) for 2^e <= |x| < 2^(e+1), p = 53 or 24, never below the ulp
// of the smallest normal), with a floor: values tinier than `floor` (1e-10 of
// the quantity's magnitude: near an interior root, beyond a vanishing edge)
// in ulps of the floor, as mollify's own accuracy suite measures.
#pragma once

#include "reference.hpp"

namespace mollify::verify::detail {

// +inf for a NaN, or an infinity where the exact value is finite in the format.
double ulps(double y, const accuracy::Real& x, double floor, bool single);

}  // namespace mollify::verify::detail
