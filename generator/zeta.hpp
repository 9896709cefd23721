// Euler's values of the zeta function at the even integers, exactly:
// zeta(2j) = (-1)^(j+1) B_2j (2 pi)^(2j) / (2 (2j)!), B the Bernoulli
// numbers, so zeta(2j) / pi^(2j) is rational (1/6, 1/90, 1/945, ...). They
// are the Laurent coefficients of the periodic row of point vortices at its
// own vortex, pi z cot(pi z) = 1 - 2 sum_j zeta(2j) z^(2j)
// (vortex/periodic_point_vortex.hpp; write_constants.hpp emits them).
#pragma once

#include "number.hpp"

#include <vector>

namespace mollify::gen {

// B_0 .. B_n (B_1 = -1/2), from sum_{k=0}^{m} binom(m + 1, k) B_k = 0.
std::vector<Q> bernoulli_numbers(int n);

// zeta(2j) / pi^(2j), j >= 1.
Q zeta_even_over_pi_power(int j);

}  // namespace mollify::gen
