// Anderson's compact polynomial mollifiers (seed 000): B_M = sigma/omega (1-r^2)^M
// and their high-order forms by the exponent method, eqs. (11)-(12):
// B = sum_{j<K} beta_j (1-r^2)^(M+j) with unit mass and vanishing radial
// moments r^2 .. r^(2K-2).
#pragma once

#include "exact.hpp"
#include "laurent.hpp"

#include <vector>

namespace mollify::gen {

Laurent one_minus_r2_power(int n);  // (1 - r^2)^n

struct ExponentMethod {
    // B = normalisation * sum_j alpha_j (1-r^2)^(M+j), alpha_0 = 1 (Anderson (12)).
    Exact normalisation;
    std::vector<Q> alpha;
};

// order = 2K; order 2 is the plain mollifier.
ExponentMethod exponent_method(int M, int order, int dim);

}  // namespace mollify::gen
