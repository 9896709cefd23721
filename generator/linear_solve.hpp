// Exact solution of square linear systems over the rationals (Gaussian
// elimination with a non-zero pivot; no rounding, so no pivoting strategy
// is needed for accuracy).
#pragma once

#include "number.hpp"

#include <vector>

namespace mollify::gen {

using Matrix = std::vector<std::vector<Q>>;

// Throws Error when A is singular.
std::vector<Q> solve(Matrix A, std::vector<Q> b);

}  // namespace mollify::gen
