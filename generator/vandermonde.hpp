// Weights of high-order combinations Phi = sum_j w_j psi_{a_j},
// psi_a(r) = a^-D psi(r/a): unit mass and vanishing even moments below 2m,
// i.e. sum_j w_j a_j^(2k) = [k = 0] for k = 0..m-1 (Franz (4.19), with
// w_j = lambda_j a_j^d / c_0). Independent of the base kernel and of D.
#pragma once

#include "linear_solve.hpp"

#include <vector>

namespace mollify::gen {

// Franz Prop. 4.24: w_j = prod_{k != j} a_k^2 / (a_k^2 - a_j^2).
std::vector<Q> vandermonde_weights(const std::vector<Q>& radii);
// The same weights by exact elimination on the transposed Vandermonde system.
std::vector<Q> vandermonde_weights_by_solve(const std::vector<Q>& radii);
// Equidistant radii a_j = j/m: w_j = (-1)^(j-1) 2 (m!)^2 / ((m+j)! (m-j)!)
// (Franz, after Lemma 4.25).
std::vector<Q> equidistant_weights(int m);
// The transposed Vandermonde matrix of (4.19): row k holds a_j^(2k).
Matrix moment_matrix(const std::vector<Q>& radii);

}  // namespace mollify::gen
